"""Compile (or load from the cache) the kernels that typical runs use, once,
on purpose: ``hbmfric warmup``.

The first use of an installed version compiles the Numba kernels, which
takes minutes on a small machine; after that every run loads them from the
cache. Running this after ``pip install`` (or in a container build step)
moves that wait out of the first real run. Each step is a tiny problem that
goes through one path of the engine: every contact law's AFT, the condensed
beam, the adaptive harmonics, Hill's stability, one-frequency solves and
the time-integration reference.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable


def _steps() -> list[tuple[str, Callable[[], object]]]:
    import hbmfric as hf

    def osc(law):
        return hf.Oscillator(1.0, 0.02, 1.0, law)

    jenkins = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    band = (0.5, 3.0)
    return [
        ("Jenkins FRF (auto harmonics)", lambda: hf.frf(osc(jenkins), 0.5, band)),
        ("Jenkins FRF (fixed H)", lambda: hf.frf(osc(jenkins), 0.5, band, 15)),
        (
            "Menq FRF",
            lambda: hf.frf(
                osc(hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0)), 0.5, band
            ),
        ),
        (
            "Iwan FRF",
            lambda: hf.frf(
                osc(hf.Iwan(stiffnesses=(1.0, 2.0), slip_forces=(0.4, 0.6))), 0.5, band
            ),
        ),
        ("Coulomb FRF", lambda: hf.frf(osc(hf.Coulomb(slip_force=0.3)), 1.0, band, 7)),
        ("cubic FRF", lambda: hf.frf(osc(hf.Cubic(0.2)), 0.3, band, 7)),
        (
            "roughness FRF",
            lambda: hf.frf(
                osc(
                    hf.Roughness(
                        hf.Jenkins(
                            stiffness=3.0, friction_coefficient=1.0, normal_load=100.0
                        )
                    )
                ),
                20.0,
                band,
                7,
            ),
        ),
        (
            "beam FRF (condensed)",
            lambda: hf.frf(
                hf.CantileverBeam(contact=hf.Jenkins(stiffness=1.6e5, slip_force=7.5)),
                2.0,
                (2 * 3.14159 * 15.0, 2 * 3.14159 * 110.0),
            ),
        ),
        (
            "Hill stability",
            # a hysteretic branch (AFT Jacobians) and a memoryless one (the
            # tangent stiffness's spectrum): both kernels
            lambda: (
                hf.frf(osc(jenkins), 0.5, band, 5).stability().exponents,
                hf.frf(osc(hf.Cubic(0.2)), 0.3, band, 7).stability().exponents,
            ),
        ),
        ("one frequency", lambda: hf.periodic_solution(osc(jenkins), 0.5, 1.2)),
        (
            "time integration",
            lambda: hf.validation.steady_state(osc(jenkins), 0.5, 1.2),
        ),
        (
            "belt tensioner FRF",
            lambda: hf.frf(
                hf.BeltTensioner(), 20.0, (2 * 3.14159 * 5, 2 * 3.14159 * 30), 7
            ),
        ),
    ]


def warmup(progress: Callable[[str], None] | None = print) -> dict[str, float]:
    """Run one tiny problem through each path of the engine.

    Parameters
    ----------
    progress : callable or None
        Receives one line per step (``print`` by default).

    Returns
    -------
    dict
        Seconds per step (compilation or cache loading included).
    """
    times = {}
    total = time.perf_counter()
    for name, step in _steps():
        t = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            step()
        times[name] = time.perf_counter() - t
        if progress:
            progress(f"warmup: {name}: {times[name]:.2f} s")
    if progress:
        progress(f"warmup: done in {time.perf_counter() - total:.1f} s")
    return times
