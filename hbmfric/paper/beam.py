"""The beam study of the paper (Sec. 3.2, Figs. 13–15): the clamped steel
beam rubbing at its tip, FRFs against the normal load and the twelve
``Fex/Fn`` configurations.

The scene (docs/paper.md): the paper's beam (0.50 × 0.04 × 0.008 m, 13
elements, 39 DOFs, E = 210 GPa, ρ = 7800 kg/m³), calibrated on the measured
resonances (24 Hz slipping, 87 Hz stuck: tip mass ≈ 77 g, contact stiffness
≈ 1.586e5 N/m), a Jenkins (Masing macroslip) contact on the tip's transverse
DOF. The paper gives neither the forcing point, nor the damping, nor the
friction coefficient; the project's choices, made so that the model shows
the paper's three observations:

* forcing at x = 0.423 m (node 11 of 13), near the rubbing end;
* modal damping ζ = 5 % on every mode (it lumps the clamp and joint
  losses of the rig);
* friction coefficient μ = 1.5 (it lumps the unknown contact geometry).

1. Fig. 13, Fex = 2 N: stuck and linear at Fn = 40 N (peak contact force of
   the stuck linear FRF ≈ 27 N < μ Fn = 60 N); flat near Fn = 1 N; a
   slipping peak at 24 Hz at Fn = 0.5 N. In full slip the friction force
   bounds the resonance when ``π φ_f Fex ≤ 4 μ Fn |φ_tip|`` (energy balance
   on the first slipping mode, ``φ`` its shape at the force and the tip,
   ``φ_f/φ_tip = 0.785`` here): Fex/Fn ≤ 1.62 μ = 2.4, so the peak is gone
   at Fn = 1 N (ratio 2) and present at Fn = 0.5 N (ratio 4).
2. Fig. 14: the FRFs per unit force depend on Fex/Fn only (exactly, for a
   Jenkins law).
3. The mostly stuck curves stay inside the stuck envelope, so the
   criterion (:func:`hbmfric.criterion.choose_contact_model` on Figs. 13
   and 14 together, with the 40 N curve as the stuck reference,
   :func:`beam_criterion_family`) says "macroslip without roughness".
   ζ was chosen for this with Fig. 14 alone read against the 40 N curve:
   its Fex/Fn = 0.5 curve rises above the stuck envelope by 9 % of its
   peak at ζ = 3 % (the contact is 18 times stiffer than the free tip, so
   partial slip softens the beam a lot) and by 4.3 % at ζ = 5 % (criterion
   threshold 6 %); on Figs. 13 and 14 together the mostly stuck curves are
   the Fig. 13 ones (Fex/Fn ≤ 0.4), with no excess at all.
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..api import frf
from ..results import Branch
from ..systems import CantileverBeam
from ..validation import steady_state
from ._figures import pyplot, save_figure
from .sdof import FigureResult

HZ = 2.0 * np.pi


@dataclass
class BeamFamily(FigureResult):
    """A beam figure; ``stuck`` (the Fn = 40 N, Fex = 2 N curve, linear and
    stuck) is the default stuck reference of :meth:`criterion`."""

    stuck: Branch | None = None
    stuck_normal_load: float = 40.0

    def stuck_record(self):
        """The stuck reference as a :class:`hbmfric.criterion.FRFRecord`."""
        from ..criterion import FRFRecord

        if self.stuck is None:
            return None
        return FRFRecord.from_branch(self.stuck, self.stuck_normal_load, dof="tip")

    def criterion(self, **options):
        """The contact-model criterion on this family, with the stuck curve
        as reference unless ``stuck`` is given."""
        if "stuck" not in options and self.stuck is not None:
            options["stuck"] = self.stuck_record()
        return super().criterion(**options)


#: beam scene of the paper reproduction: SI units, frequencies in Hz
PAPER_BEAM_SCENE = {
    "slip_frequency": 24.0,  # Hz, measured (Fn = 0.5 N)
    "stuck_frequency": 87.0,  # Hz, measured (Fn = 40 N)
    "friction_coefficient": 1.5,
    "damping_ratio": 0.05,
    "force": 2.0,  # N, Fex of Fig. 13
    "normal_loads": (40.0, 10.0, 5.0, 3.0, 2.5, 1.0, 0.5),  # N, Fig. 13
    "stuck_normal_load": 40.0,  # N, the stuck reference of the criterion
    "ratios": (0.5, 1.0, 2.0),  # Fex/Fn, Fig. 14
    "ratio_normal_loads": (2.5, 3.0, 5.0, 10.0),  # N, Fig. 14
    "frequency_range": (15.0, 110.0),  # Hz
    "max_step": 0.02,  # continuation step: smooth curves for the figures
    "validation_normal_loads": (5.0, 2.5),  # N, Fig. 15 stand-in (Fex = 2 N)
    "validation_points": 5,  # time-integration points per curve
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
    harmonics: int | str = "auto",
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
    harmonics: int | str = "auto",
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
    stuck_load = p["stuck_normal_load"]
    stuck, _, _ = _run(
        [(p["force"], stuck_load, "stuck reference")],
        harmonics,
        progress,
        "fig14 stuck reference",
        p,
    )
    return BeamFamily(
        "fig14_beam_ratios",
        "Fig. 14 — beam, twelve Fex/Fn configurations",
        labels,
        branches,
        params,
        stuck=stuck[0],
        stuck_normal_load=stuck_load,
    )


def beam_criterion_family(harmonics: int | str = "auto", **overrides):
    """The beam family the criterion reads, as records: Fig. 13 (Fex = 2 N,
    Fn = 40 … 0.5 N: the stuck curve and the mostly stuck ones) together
    with the twelve configurations of Fig. 14 (ratio invariance), and the
    stuck reference (the Fn = 40 N curve) on its own.

    Returns
    -------
    records : list of :class:`hbmfric.criterion.FRFRecord`
    stuck : :class:`hbmfric.criterion.FRFRecord`

    Examples
    --------
    >>> records, stuck = beam_criterion_family()  # doctest: +SKIP
    >>> hf.criterion.choose_contact_model(records, stuck=stuck).verdict
    ... # doctest: +SKIP
    'macroslip without roughness'
    """
    loads = beam_normal_load_family(harmonics, **overrides)
    family = beam_ratio_family(harmonics, **overrides)
    return loads.records() + family.records(), family.stuck_record()


def ratio_collapse(figure: FigureResult, n_grid: int = 400) -> dict[float, float]:
    """Largest spread of the FRFs per unit force within each Fex/Fn group,
    relative to the group's peak, on a common frequency grid (ratio →
    spread), each FRF read off its dense output
    (:meth:`hbmfric.Branch.amplitude_at`, first pass where it folds). Zero
    for a law without roughness, up to the HBM tolerance."""
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
            curves.append(b.amplitude_at(grid, 1, "tip")[:, 0] / force)
        curves = np.array(curves)
        spread = np.nanmax(curves, axis=0) - np.nanmin(curves, axis=0)
        out[ratio] = float(np.nanmax(spread) / np.nanmax(curves))
    return out


@dataclass
class BeamValidation(BeamFamily):
    """Fig. 15 stand-in: HBM curves with time-integration points.

    The paper compares HBM with its measurements; without the measured data
    the independent reference here is the time integration of the same
    39-DOF model (:func:`hbmfric.validation.steady_state`) at slipping
    points of each curve. ``reference`` holds one dict per point: ``curve``
    (index), ``omega`` (rad/s), ``hbm`` and ``time_integration`` (first
    harmonic at the tip, m), ``periods``.
    """

    reference: list = field(default_factory=list)

    def write_csv(self, path: Path, resample: int | None = None) -> Path:
        """The curves (as :meth:`FigureResult.write_csv`, ``resample``
        likewise) and, next to them, ``<stem>_time_integration.csv`` with
        the reference points."""
        path = super().write_csv(path, resample=resample)
        ti_path = Path(path).with_name(Path(path).stem + "_time_integration.csv")
        with open(ti_path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(
                [
                    "curve",
                    "force_N",
                    "normal_load_N",
                    "omega_rad_s",
                    "hbm_amplitude_h1_m",
                    "time_integration_amplitude_h1_m",
                    "relative_difference",
                    "periods",
                ]
            )
            for ref in self.reference:
                par = self.parameters[ref["curve"]]
                w.writerow(
                    [
                        self.labels[ref["curve"]],
                        f"{par['force']:.9g}",
                        f"{par['normal_load']:.9g}",
                        f"{ref['omega']:.12g}",
                        f"{ref['hbm']:.12g}",
                        f"{ref['time_integration']:.12g}",
                        f"{ref['time_integration'] / ref['hbm'] - 1.0:.3e}",
                        ref["periods"],
                    ]
                )
        self.files.append(ti_path)
        return path

    def write_png(self, path: Path) -> Path:
        """HBM curves (lines) and time-integration points (circles)."""
        plt = pyplot()

        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        for i, (label, b, par) in enumerate(
            zip(self.labels, self.branches, self.parameters, strict=True)
        ):
            (line,) = ax.semilogy(
                b.omega / HZ, b.amplitude(1, "tip") / par["force"], label=label
            )
            pts = [r for r in self.reference if r["curve"] == i]
            ax.semilogy(
                [r["omega"] / HZ for r in pts],
                [r["time_integration"] / par["force"] for r in pts],
                "o",
                mfc="none",
                color=line.get_color(),
                label=f"time integration, Fn = {par['normal_load']:g} N",
            )
        ax.set_xlabel("frequency (Hz)")
        ax.set_ylabel("tip first-harmonic amplitude / Fex (m/N)")
        ax.set_title(self.title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        return save_figure(fig, path, self.files)

    def max_difference(self) -> float:
        """Largest relative difference HBM/time integration (first harmonic
        at the tip)."""
        return max(abs(r["time_integration"] / r["hbm"] - 1.0) for r in self.reference)


def beam_validation(
    harmonics: int | str = "auto",
    progress: Callable[[str], None] | None = None,
    **overrides,
) -> BeamValidation:
    """Fig. 15 stand-in: HBM FRFs at Fex = 2 N (stick–slip normal loads)
    checked by time integration at slipping points of each curve."""
    p = {**PAPER_BEAM_SCENE, **overrides}
    configs = [
        (p["force"], fn, f"Fn = {fn:g} N (Fex = {p['force']:g} N)")
        for fn in p["validation_normal_loads"]
    ]
    branches, labels, params = _run(configs, harmonics, progress, "fig15 beam", p)
    cal = paper_calibration(**p)
    reference = []
    for i, (b, par) in enumerate(zip(branches, params, strict=True)):
        a = b.amplitude(harmonic=1, dof="tip")
        slip = p["friction_coefficient"] * par["normal_load"]
        slipping = np.nonzero(a * cal.contact_stiffness > 1.05 * slip)[0]
        if slipping.size == 0:
            continue
        picks = np.unique(
            slipping[
                np.linspace(0, slipping.size - 1, p["validation_points"])
                .round()
                .astype(int)
            ]
        )
        beam = paper_beam(par["normal_load"], cal, **p)
        for j in picks:
            ref = steady_state(
                beam, par["force"], float(b.omega[j]), initial_state="linear", tol=1e-9
            )
            reference.append(
                {
                    "curve": i,
                    "omega": float(b.omega[j]),
                    "hbm": float(a[j]),
                    "time_integration": ref.amplitude(1, dof=beam.contact_dof),
                    "periods": ref.periods,
                }
            )
        if progress is not None:
            diffs = [
                abs(r["time_integration"] / r["hbm"] - 1.0)
                for r in reference
                if r["curve"] == i
            ]
            progress(
                f"fig15 beam Fn={par['normal_load']:g} N: time integration at "
                f"{len(diffs)} slipping points, largest difference to HBM "
                f"{max(diffs):.2e}"
            )
    return BeamValidation(
        "fig15_beam_validation",
        "Fig. 15 — beam, HBM against time integration",
        labels,
        branches,
        params,
        reference=reference,
    )
