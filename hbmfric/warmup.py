"""Compile (or load from the cache) the kernels that typical runs use, once,
on purpose: ``hbmfric warmup``.

The first use of an installed version compiles the Numba kernels, which
takes minutes on a small machine; after that every run loads them from the
cache. Running this after ``pip install`` (or in a container build step)
moves that wait out of the first real run. Each step is a tiny problem that
goes through one path of the engine: every contact law's AFT, the condensed
beam, the adaptive harmonics, Hill's stability, one-frequency solves and
the time-integration reference.

With ``jobs=2`` (``hbmfric warmup --jobs 2``) the steps run in two worker
processes that fill the same cache (:func:`lanes`): on two cores the wait
is about that of the longer lane instead of both. Numba writes each cached
kernel atomically (a file written aside, then renamed), so two processes
never read a half-written kernel; a kernel both compile is written twice,
the same code.
"""

from __future__ import annotations

import glob
import multiprocessing
import os
import time
import warnings
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed

#: the steps of the condensed continuation kernels, which no other step
#: uses: the one-contact condensed beam and the several-contact lap joint
#: (their compilation on an empty cache, on a quiet 2-core machine: about
#: 42 s and 108 s of the 320 s CPU of a whole warm-up; the other steps share
#: the full continuation kernels, the first of them, the Jenkins FRF, about
#: 71 s, the rigid Coulomb contact's about 62 s, the rest 1-12 s each)
CONDENSED_STEPS = ("beam FRF (condensed)", "lap joint FRF (10 pairs)")

#: the first of :data:`CONDENSED_STEPS` (kept for callers of earlier
#: versions)
CONDENSED_STEP = CONDENSED_STEPS[0]


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
        ("lap joint FRF (10 pairs)", lambda: _lap_joint(10)),
        (
            "belt tensioner FRF",
            lambda: hf.frf(
                hf.BeltTensioner(), 20.0, (2 * 3.14159 * 5, 2 * 3.14159 * 30), 7
            ),
        ),
    ]


def lanes(names: list[str], jobs: int) -> list[list[str]]:
    """The steps of each worker process: the :data:`CONDENSED_STEPS` make
    the second lane, in their order; the other steps, which share the full
    continuation kernels, are dealt in their order to the other lanes, each
    to the first of those with the fewest steps (with two lanes: all to the
    first). The two halves are close in compile time (about 150 s and
    170 s of CPU on an empty cache), and no kernel is compiled by both
    processes at once.

    Parameters
    ----------
    names : list of str
        Step names in their order.
    jobs : int
        Number of lanes, >= 1.

    Returns
    -------
    list of list of str
        ``jobs`` lanes (some empty if there are fewer steps); every step in
        exactly one.
    """
    if jobs == 1:
        return [list(names)]
    out: list[list[str]] = [[] for _ in range(jobs)]
    out[1] = [name for name in names if name in CONDENSED_STEPS]
    others = [lane for i, lane in enumerate(out) if i != 1]
    for name in names:
        if name not in CONDENSED_STEPS:
            min(others, key=len).append(name)  # the first of the shortest
    return out


def _run_steps(
    names: list[str], progress: Callable[[str], None] | None = None
) -> list[tuple[str, float]]:
    """Run the named steps in this process; (name, seconds) of each."""
    steps = dict(_steps())
    times = []
    for name in names:
        t = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            steps[name]()
        times.append((name, time.perf_counter() - t))
        if progress:
            progress(f"warmup: {name}: {times[-1][1]:.2f} s")
    return times


def warmup(
    progress: Callable[[str], None] | None = print, jobs: int = 1
) -> dict[str, float]:
    """Run one tiny problem through each path of the engine.

    Parameters
    ----------
    progress : callable or None
        Receives one line per step (``print`` by default).
    jobs : int
        Worker processes (default 1: every step in this process); with
        more, the steps are split into :func:`lanes` run by that many
        fresh processes at once (``spawn``), each filling the same cache.

    Returns
    -------
    dict
        Seconds per step (compilation or cache loading included; wall time
        in its worker).

    Raises
    ------
    ValueError
        If ``jobs`` is not a positive integer.
    """
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise ValueError(f"jobs must be a positive integer, got {jobs!r}")
    total = time.perf_counter()
    names = [name for name, _ in _steps()]
    if jobs == 1:
        times = dict(_run_steps(names, progress))
    else:
        times = {}
        context = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
            futures = [
                pool.submit(_run_steps, lane) for lane in lanes(names, jobs) if lane
            ]
            for future in as_completed(futures):
                for name, seconds in future.result():
                    times[name] = seconds
                    if progress:
                        progress(f"warmup: {name}: {seconds:.2f} s")
    if progress:
        progress(f"warmup: done in {time.perf_counter() - total:.1f} s")
    return times


def first_run(cache_dir: str | None = None) -> bool:
    """Is this the first run of the installed version: does its kernel cache
    hold no continuation kernel yet?

    Parameters
    ----------
    cache_dir : str, optional
        The version's cache directory (default
        :data:`hbmfric._jit.CACHE_DIR`).

    Returns
    -------
    bool
        True if ``cache_dir`` holds no cache index of
        :func:`hbmfric.kernels.steps.arclength.trace`; False also without a
        cache (a second process's compilation would then be lost).
    """
    if cache_dir is None:
        # absolute import: this module holds no kernel, and a relative
        # import of _jit would make it one of the sources whose hash keys
        # the cache (hbmfric._jit.kernel_sources)
        from hbmfric import _jit

        cache_dir = _jit.CACHE_DIR
    if cache_dir is None:
        return False
    pattern = os.path.join(cache_dir, "kernels", "steps", "arclength.trace-*.nbi")
    return not glob.glob(pattern)


def _paper_beam() -> None:
    """One FRF of the paper beam as the paper computes them (Fn = 5 N,
    condensed, ``harmonics="auto"``): it compiles the beam's kernels."""
    import hbmfric as hf
    from hbmfric.paper.beam import PAPER_BEAM_SCENE, _omega_range, paper_beam

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        hf.frf(
            paper_beam(5.0),
            2.0,
            _omega_range(PAPER_BEAM_SCENE),
            "auto",
            max_step=PAPER_BEAM_SCENE["max_step"],
        )


def _tensioner_residual() -> None:
    """Compile the residual of the belt tensioner's problem type (Dahl,
    Fig. 5: the problem ``hbm_frf`` builds with :func:`hbmfric.frf`'s
    defaults), which the main process would otherwise compile after the
    beam figures."""
    from hbmfric.api import _problem
    from hbmfric.kernels.residuals.pointer import residual_address
    from hbmfric.systems.tensioner import BeltTensioner

    tensioner = _problem(BeltTensioner(), 5.0, 7, None, None, "auto", None)
    residual_address(tensioner.kernel_problem)


def _lap_joint(n_pairs: int) -> None:
    """One FRF of the extra lap-joint figure set (its first preload, a
    microslip ratio) with ``n_pairs`` contact pairs: it compiles the
    several-contact condensed kernels, which no paper figure before it
    uses (the kernels do not depend on ``n_pairs``)."""
    from hbmfric.paper.lap_joint import LAP_JOINT_SCENE, lap_joint_family

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lap_joint_family(
            n_pairs,
            ratios=(1e-3,),
            check_ratios=(),
            bolt_preloads=LAP_JOINT_SCENE["bolt_preloads"][:1],
        )


class PaperHelper:
    """Kernels compiled in a second process while this one computes the
    figures before them (a first run on a machine of two cores or more):
    the longest compilation the paper's figures wait for goes to the
    helper, the rest this process compiles as it goes.

    With the extra lap joint (``lap_joint_pairs`` > 0) the helper compiles
    the lap joint's kernels (the several-contact condensed path, ≈ 110 s of
    compiling, which no paper figure shares) and then the belt tensioner's
    residual, while this process computes the SDOF and beam figures;
    without it, the paper beam's kernels (condensed, sharing nothing with
    the SDOF figures' full ones) and then the tensioner's residual.
    :meth:`wait` before the beam figures and :meth:`wait_lap_joint` before
    the lap joint's: they then load those kernels from the cache. Nothing
    else changes: the helper computes no result the paper uses (cold
    whole paper, bench/README.md "stop 30").
    """

    def __init__(self, lap_joint_pairs: int = 0) -> None:
        context = multiprocessing.get_context("spawn")
        self._pool = ProcessPoolExecutor(max_workers=1, mp_context=context)
        self._future = self._lap = None
        # the helper starts with this environment: it prints no compile
        # notice of its own (this process prints the one line)
        quiet = os.environ.get("HBMFRIC_QUIET")
        os.environ["HBMFRIC_QUIET"] = "1"
        try:
            if lap_joint_pairs:
                self._lap = self._pool.submit(_lap_joint, lap_joint_pairs)
            else:
                self._future = self._pool.submit(_paper_beam)
            # not waited for: the main process needs it after the beam
            # figures only (a failure leaves this process to compile it)
            self._later = self._pool.submit(_tensioner_residual)
        finally:
            if quiet is None:
                del os.environ["HBMFRIC_QUIET"]
            else:
                os.environ["HBMFRIC_QUIET"] = quiet

    @classmethod
    def start(
        cls,
        progress: Callable[[str], None] | None = print,
        lap_joint_pairs: int = 0,
    ) -> PaperHelper | None:
        """A helper if this is a :func:`first_run` on two cores or more
        (one line to ``progress`` says so), else None. With
        ``lap_joint_pairs`` > 0 it also compiles the extra lap joint's
        kernels, after the tensioner's residual (not waited for: the main
        process reaches the lap joint last)."""
        if (os.cpu_count() or 1) < 2 or not first_run():
            return None
        if progress:
            first = "lap joint's" if lap_joint_pairs else "beam's"
            progress(
                f"hbmfric paper: first run of this version: the {first} and the "
                "tensioner's kernels compile in a second process while the "
                "figures before them run (once)"
            )
        return cls(lap_joint_pairs)

    def wait(self, progress: Callable[[str], None] | None = print) -> None:
        """Wait for the beam's kernels if this helper compiles them (no lap
        joint asked for); a failure of the helper is reported in one line
        and otherwise ignored (this process then compiles what it needs).
        The tensioner's residual (and the lap joint's kernels) go on
        compiling in the helper meanwhile; Python waits for them at exit."""
        try:
            if self._future is not None:
                self._future.result()
        except Exception as exc:  # the helper only fills the cache
            if progress:
                progress(f"hbmfric paper: the compiling helper failed ({exc})")
        finally:
            self._pool.shutdown(wait=False)

    def wait_lap_joint(self, progress: Callable[[str], None] | None = print) -> None:
        """Wait for the lap joint's kernels (if this helper compiles them)
        before the extra lap-joint figures: compiling them here as well
        would double the work on two cores (a cold paper: 130 s for the
        first lap-joint FRF against 110 s without a helper's, bench/README
        "stop 30"). A failure is reported in one line and otherwise ignored
        (this process then compiles them)."""
        if self._lap is None:
            return
        try:
            self._lap.result()
        except Exception as exc:  # the helper only fills the cache
            if progress:
                progress(f"hbmfric paper: the compiling helper failed ({exc})")
