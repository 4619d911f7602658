"""The beam study of the paper (Sec. 3.2, Figs. 13–15): the clamped steel
beam rubbing at its tip, FRFs against the normal load and the twelve
``Fex/Fn`` configurations.

The scene (SPEC §2, §6): the paper's beam (0.50 × 0.04 × 0.008 m, 13
elements, 39 DOFs, E = 210 GPa, ρ = 7800 kg/m³), calibrated on the measured
resonances (24 Hz slipping, 87 Hz stuck: tip mass ≈ 77 g, contact stiffness
≈ 1.586e5 N/m), a Jenkins (Masing macroslip) contact on the tip's transverse
DOF. The paper gives neither the forcing point, nor the damping, nor the
friction coefficient; the project's choices:

* forcing at x = 0.423 m (node 11 of 13), near the rubbing end;
* modal damping ζ = 3 % on every mode;
* friction coefficient μ = 1.5 (it lumps the unknown contact geometry).

Why these: with Fex = 2 N, the stuck resonance must stay stuck at Fn = 40 N
(peak contact force of the stuck linear FRF ≈ 46 N < μ Fn = 60 N) and the
peak must vanish near Fn = 1 N. In full slip the friction force bounds the
resonance when ``π φ_f Fex ≤ 4 μ Fn |φ_tip|`` (energy balance on the first
slipping mode, ``φ`` its shape at the force and the tip; ``φ_f/φ_tip =
0.785`` here): Fex/Fn ≤ 1.62 μ = 2.4 → flat at Fn = 1 N (ratio 2), a
slipping peak at 24 Hz at Fn = 0.5 N (ratio 4).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..api import frf
from ..systems import CantileverBeam
from .sdof import FigureResult

HZ = 2.0 * np.pi

#: beam scene of the paper reproduction: SI units, frequencies in Hz
PAPER_BEAM_SCENE = {
    "slip_frequency": 24.0,  # Hz, measured (Fn = 0.5 N)
    "stuck_frequency": 87.0,  # Hz, measured (Fn = 40 N)
    "friction_coefficient": 1.5,
    "damping_ratio": 0.03,
    "force": 2.0,  # N, Fex of Fig. 13
    "normal_loads": (40.0, 10.0, 5.0, 3.0, 2.5, 1.0, 0.5),  # N, Fig. 13
    "ratios": (0.5, 1.0, 2.0),  # Fex/Fn, Fig. 14
    "ratio_normal_loads": (2.5, 3.0, 5.0, 10.0),  # N, Fig. 14
    "frequency_range": (15.0, 110.0),  # Hz
    "max_step": 0.02,  # continuation step: smooth curves for the figures
}


def paper_calibration(**overrides):
    """The calibrated paper beam (no contact law), see
    :meth:`CantileverBeam.calibrate`."""
    p = {**PAPER_BEAM_SCENE, **overrides}
    return CantileverBeam.calibrate(
        p["slip_frequency"], p["stuck_frequency"], damping_ratio=p["damping_ratio"]
    )


def paper_beam(normal_load: float, calibration=None, **overrides) -> CantileverBeam:
    """The paper beam with its Jenkins tip contact at ``normal_load`` (N)."""
    p = {**PAPER_BEAM_SCENE, **overrides}
    cal = calibration or paper_calibration(**overrides)
    law = cal.contact(normal_load, p["friction_coefficient"])
    return cal.beam.with_contact(law)


def _omega_range(p) -> tuple[float, float]:
    lo, hi = p["frequency_range"]
    return HZ * lo, HZ * hi


def _run(configs, harmonics, progress, tag, p):
    cal = paper_calibration(**p)
    branches, labels, params = [], [], []
    for force, normal_load, label in configs:
        beam = paper_beam(normal_load, cal, **p)
        b = frf(beam, force, _omega_range(p), harmonics, max_step=p["max_step"])
        branches.append(b)
        labels.append(label)
        params.append(
            {"force": force, "normal_load": normal_load, "ratio": force / normal_load}
        )
        if progress is not None:
            a = b.amplitude(harmonic=1, dof="tip")
            peak = int(np.argmax(a))
            progress(
                f"{tag} Fex={force:g} N Fn={normal_load:g} N: {len(b)} points, "
                f"{b.elapsed * 1e3:.1f} ms, tip peak {a[peak]:.4g} m at "
                f"{b.omega[peak] / HZ:.2f} Hz, stop: {b.stop_reason}"
            )
    return branches, labels, params


def beam_normal_load_family(
    harmonics: int = 15,
    progress: Callable[[str], None] | None = None,
    **overrides,
) -> FigureResult:
    """Fig. 13: tip FRFs at Fex = 2 N for Fn = 40 … 0.5 N.

    Stuck and linear at 40 N (peak at the stuck 87 Hz), flat near 1 N,
    slipping and linear-looking at 0.5 N (peak at 24 Hz).
    """
    p = {**PAPER_BEAM_SCENE, **overrides}
    configs = [
        (p["force"], fn, f"Fn = {fn:g} N (Fex = {p['force']:g} N)")
        for fn in p["normal_loads"]
    ]
    branches, labels, params = _run(configs, harmonics, progress, "fig13 beam", p)
    return FigureResult(
        "fig13_beam_normal_load",
        "Fig. 13 — beam, tip FRFs against the normal load",
        labels,
        branches,
        params,
    )


def beam_ratio_family(
    harmonics: int = 15,
    progress: Callable[[str], None] | None = None,
    **overrides,
) -> FigureResult:
    """Fig. 14: the twelve configurations Fex/Fn = 0.5, 1, 2 × Fn = 2.5, 3,
    5, 10 N. With a Jenkins law the FRFs per unit force depend on Fex/Fn
    only (macroslip without roughness), so they collapse in three groups."""
    p = {**PAPER_BEAM_SCENE, **overrides}
    configs = [
        (ratio * fn, fn, f"Fex/Fn = {ratio:g}, Fn = {fn:g} N")
        for ratio in p["ratios"]
        for fn in p["ratio_normal_loads"]
    ]
    branches, labels, params = _run(configs, harmonics, progress, "fig14 beam", p)
    return FigureResult(
        "fig14_beam_ratios",
        "Fig. 14 — beam, twelve Fex/Fn configurations",
        labels,
        branches,
        params,
    )


def family_records(figure: FigureResult, dof: str = "tip") -> list[dict]:
    """The curves of a figure as records for the contact-model criterion.

    Returns
    -------
    list of dict
        One per curve: ``force`` (N), ``normal_load`` (N), ``omega``
        (ndarray, rad/s, path order) and ``amplitude`` (ndarray, first
        harmonic at ``dof``, m).
    """
    return [
        {
            "force": par["force"],
            "normal_load": par["normal_load"],
            "omega": b.omega.copy(),
            "amplitude": b.amplitude(harmonic=1, dof=dof),
        }
        for b, par in zip(figure.branches, figure.parameters, strict=True)
    ]


def ratio_collapse(figure: FigureResult, n_grid: int = 400) -> dict[float, float]:
    """Largest spread of the FRFs per unit force within each Fex/Fn group,
    relative to the group's peak, on a common frequency grid (ratio →
    spread). Zero for a law without roughness, up to the HBM tolerance."""
    groups: dict[float, list] = {}
    for b, par in zip(figure.branches, figure.parameters, strict=True):
        groups.setdefault(round(par["ratio"], 12), []).append((b, par["force"]))
    out = {}
    for ratio, members in groups.items():
        lo = max(float(np.min(b.omega)) for b, _ in members)
        hi = min(float(np.max(b.omega)) for b, _ in members)
        grid = np.linspace(lo, hi, n_grid)
        curves = []
        for b, force in members:
            order = np.argsort(b.omega)
            curves.append(
                np.interp(grid, b.omega[order], b.amplitude(1, "tip")[order] / force)
            )
        curves = np.array(curves)
        out[ratio] = float(np.max(np.ptp(curves, axis=0)) / np.max(curves))
    return out
