"""The single-DOF study of the paper (Sec. 3.1, Figs. 8–11): FRF families
against ``Fex/Fn`` for Masing macroslip and Menq microslip contacts, without
and with roughness, and the contact-model criterion's verdict on each.

Choices the paper leaves open (docs/paper.md): the scene of
:data:`~hbmfric.paper.PAPER_SDOF`; the Menq law has the same stuck stiffness
and gross-slip force as the Jenkins element and microslip starts at half the
gross-slip force (:data:`MENQ_ONSET`); roughness follows the default
Hertz–Mindlin rule below the limit load of 300 N (:data:`ROUGHNESS_LIMIT_LOAD`).
Figs. 8 and 9 are computed at Fex = 1 N and, as the invariance check the
criterion needs, again at Fex = 1000 N (dashed).
"""

from __future__ import annotations

import csv
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..api import frf
from ..laws import Jenkins, Menq, Roughness
from ..results import Branch
from ._figures import pyplot, save_figure
from .scenes import PAPER_SDOF, paper_oscillator

#: Menq law of the paper scene: microslip starts at this fraction of F*
MENQ_ONSET = 0.5
#: normal load above which the asperities are crushed (paper: 300 N), N
ROUGHNESS_LIMIT_LOAD = 300.0
#: the two excitation levels of the roughness study (paper: 1 N and 1000 N)
FORCES = (1.0, 1000.0)


@dataclass
class FigureResult:
    """A computed figure: its curves and where they were written."""

    name: str
    title: str
    labels: list[str]
    branches: list[Branch]
    parameters: list[dict]
    files: list[Path] = field(default_factory=list)

    def records(self):
        """The curves as :class:`hbmfric.criterion.FRFRecord` (first-harmonic
        amplitude)."""
        from ..criterion import FRFRecord

        return [
            FRFRecord.from_branch(b, par["normal_load"])
            for b, par in zip(self.branches, self.parameters, strict=True)
        ]

    def criterion(self, **options):
        """The contact-model criterion on this family
        (:func:`hbmfric.criterion.choose_contact_model`)."""
        from ..criterion import choose_contact_model

        return choose_contact_model(self.records(), **options)

    def write_csv(self, path: Path, resample: int | None = None) -> Path:
        """Long-format CSV: one row per point of every curve.

        Columns: ``curve, force_N, normal_load_N, ratio, omega_rad_s,
        amplitude_h1_m, amplitude_m, amplitude_h1_per_force_m_per_N``.

        ``resample``: None writes the computed points; an integer ``k``
        writes the dense output (:meth:`hbmfric.Branch.resample`) at ``k``
        arc-length samples per interval between points instead, with a
        last column ``computed`` (1 on a computed point, 0 between).

        When every curve's stability has been computed
        (:meth:`stability`), the computed points get a last column
        ``stable`` (1 or 0; with ``resample``, the stability of the nearest
        computed point in arc length).
        """
        if resample is not None:
            from .._validate import positive_int

            resample = positive_int("resample", resample, low=1)
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            header = [
                "curve",
                "force_N",
                "normal_load_N",
                "ratio",
                "omega_rad_s",
                "amplitude_h1_m",
                "amplitude_m",
                "amplitude_h1_per_force_m_per_N",
            ]
            with_stability = all(b._stability is not None for b in self.branches)
            w.writerow(
                header
                + (["computed"] if resample is not None else [])
                + (["stable"] if with_stability else [])
            )
            for label, b, par in zip(
                self.labels, self.branches, self.parameters, strict=True
            ):
                if resample is None:
                    omega, a1, a = b.omega, b.amplitude(harmonic=1), b.amplitude()
                    extra = [[]] * omega.size
                else:
                    dense = b.resample(resample)
                    omega = dense.omega
                    a1, a = dense.amplitude(harmonic=1), dense.amplitude()
                    on_point = np.isin(dense.arclength, b.arclength)
                    extra = [[str(int(k))] for k in on_point]
                if with_stability:
                    stable = np.asarray(b.stable, dtype=int)
                    if resample is not None:
                        s_pts = b.arclength
                        nearest = np.abs(
                            dense.arclength[:, None] - s_pts[None, :]
                        ).argmin(axis=1)
                        stable = stable[nearest]
                    extra = [
                        [*more, str(int(k))]
                        for more, k in zip(extra, stable, strict=True)
                    ]
                for om, x1, x, more in zip(omega, a1, a, extra, strict=True):
                    w.writerow(
                        [
                            label,
                            f"{par['force']:.9g}",
                            f"{par['normal_load']:.9g}",
                            f"{par['ratio']:.9g}",
                            f"{om:.12g}",
                            f"{x1:.12g}",
                            f"{x:.12g}",
                            f"{x1 / par['force']:.12g}",
                            *more,
                        ]
                    )
        self.files.append(Path(path))
        return Path(path)

    def stability(self) -> int:
        """Compute the stability of every curve's points (Hill's method,
        :meth:`hbmfric.Branch.stability`); returns the number of unstable
        points over all curves."""
        return int(sum(np.count_nonzero(~b.stable) for b in self.branches))

    def write_png(self, path: Path) -> Path:
        """Plot the curves (amplitude per unit force against Ω)."""
        plt = pyplot()

        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        ratios = sorted({par["ratio"] for par in self.parameters})
        forces = sorted({par["force"] for par in self.parameters})
        colours = plt.get_cmap("viridis")
        for label, b, par in zip(
            self.labels, self.branches, self.parameters, strict=True
        ):
            i = ratios.index(par["ratio"])
            style = ("-", "--", ":", "-.")[forces.index(par["force"]) % 4]
            ax.semilogy(
                b.omega,
                b.amplitude(harmonic=1) / par["force"],
                style,
                color=colours(i / max(len(ratios) - 1, 1)),
                label=label,
            )
        ax.set_xlabel("Ω (rad/s)")
        ax.set_ylabel("first-harmonic amplitude / Fex (m/N)")
        ax.set_title(self.title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7 if len(self.labels) > 6 else None)
        return save_figure(fig, path, self.files)


def sdof_family(
    name: str,
    title: str,
    law: Callable[[float], object],
    forces=(1.0,),
    ratios=PAPER_SDOF["ratios"],
    harmonics: int | str = "auto",
    progress: Callable[[str], None] | None = None,
    tag: str = "",
    check_forces=(),
    cache: dict | None = None,
) -> FigureResult:
    """FRFs of the paper oscillator for every ``(Fex, Fex/Fn)``.

    Parameters
    ----------
    name, title : str
        File stem and plot title.
    law : callable
        ``law(normal_load) -> ContactLaw`` at a normal load in N.
    forces : sequence of float
        Excitation amplitudes Fex, N.
    ratios : sequence of float
        Values of Fex/Fn.
    harmonics : int or "auto"
        Highest harmonic.
    progress : callable, optional
        Receives one line per computed curve, starting with ``tag``.
    tag : str
    check_forces : sequence of float
        Further excitation levels, N, computed after ``forces`` (their
        progress lines start with the figure number and ``check``).
    cache : dict, optional
        Branches already computed, keyed by the contact law's kernel code
        and parameters, the force and the harmonics: a contact whose
        roughness has no effect (normal load above the limit) is the plain
        law, and is not computed twice.
    """
    branches, labels, params = [], [], []
    forces, n_main = tuple(forces) + tuple(check_forces), len(forces)
    check_tag = (tag.split() or [""])[0] + " check"
    for k, force in enumerate(forces):
        for ratio in ratios:
            normal_load = force / ratio
            contact = law(normal_load)
            key = (contact.code, contact.params.tobytes(), force, harmonics)
            reused = cache is not None and key in cache
            if reused:
                b = cache[key]
            else:
                osc = paper_oscillator(normal_load).with_contact(contact)
                b = frf(osc, force, PAPER_SDOF["omega"], harmonics)
                if cache is not None:
                    cache[key] = b
            branches.append(b)
            label = f"Fex/Fn = {ratio:g}"
            if len(forces) > 1:
                label += f", Fex = {force:g} N"
            labels.append(label)
            params.append({"force": force, "normal_load": normal_load, "ratio": ratio})
            if progress is not None:
                a1 = b.amplitude(harmonic=1)
                peak = int(np.argmax(a1))
                head = tag if k < n_main else check_tag
                progress(
                    f"{head} Fex={force:g} N Fex/Fn={ratio:g}: {len(b)} points, "
                    f"{b.elapsed * 1e3:.1f} ms, peak {a1[peak] / force:.4g} m/N "
                    f"at {b.omega[peak]:.2f} rad/s, stop: {b.stop_reason}"
                    + (" (same contact as an earlier curve: reused)" if reused else "")
                )
    return FigureResult(name, title, labels, branches, params)


def jenkins_law(normal_load: float) -> Jenkins:
    """Masing macroslip contact of the paper scene at ``normal_load`` (N)."""
    return Jenkins(
        stiffness=PAPER_SDOF["tangential_stiffness"],
        friction_coefficient=PAPER_SDOF["friction_coefficient"],
        normal_load=normal_load,
    )


def menq_law(normal_load: float) -> Menq:
    """Menq microslip contact of the paper scene at ``normal_load`` (N): the
    Jenkins element's stuck stiffness and gross-slip force, microslip from
    ``MENQ_ONSET`` of it."""
    return Menq.from_stiffness(
        PAPER_SDOF["tangential_stiffness"],
        microslip_onset=MENQ_ONSET,
        friction_coefficient=PAPER_SDOF["friction_coefficient"],
        normal_load=normal_load,
    )


def rough_jenkins_law(normal_load: float) -> Roughness:
    """Masing contact with roughness (stiffness drops below 300 N)."""
    return Roughness(jenkins_law(normal_load), ROUGHNESS_LIMIT_LOAD)


def rough_menq_law(normal_load: float) -> Roughness:
    """Menq contact with roughness (shear layer softer below 300 N)."""
    return Roughness(menq_law(normal_load), ROUGHNESS_LIMIT_LOAD)


#: the paper's SDOF figures: file stem, title, contact law, progress tag
_FIGURES = {
    8: ("fig08_masing", "Fig. 8 — Masing macroslip, SDOF", jenkins_law, "fig8 Masing"),
    9: ("fig09_menq", "Fig. 9 — Menq microslip, SDOF", menq_law, "fig9 Menq"),
    10: (
        "fig10_masing_roughness",
        "Fig. 10 — Masing macroslip with roughness, SDOF",
        rough_jenkins_law,
        "fig10 Masing+roughness",
    ),
    11: (
        "fig11_menq_roughness",
        "Fig. 11 — Menq microslip with roughness, SDOF",
        rough_menq_law,
        "fig11 Menq+roughness",
    ),
}


def _paper_figure(
    number: int, forces, ratios, harmonics, progress, check_forces, cache
) -> FigureResult:
    """:func:`sdof_family` for Fig. ``number`` of :data:`_FIGURES`."""
    name, title, law, tag = _FIGURES[number]
    return sdof_family(
        name, title, law, forces, ratios, harmonics, progress, tag, check_forces, cache
    )


def masing_family(
    force: float = 1.0,
    ratios=PAPER_SDOF["ratios"],
    harmonics: int | str = "auto",
    progress: Callable[[str], None] | None = None,
    check_force: float | None = None,
    cache: dict | None = None,
) -> FigureResult:
    """Fig. 8: Masing (Jenkins) macroslip FRFs for several ``Fex/Fn``.

    Parameters
    ----------
    force : float
        Excitation amplitude Fex, N (the normalised FRFs depend on Fex/Fn
        only).
    ratios : sequence of float
        Values of Fex/Fn.
    harmonics : int or "auto"
        Highest harmonic.
    progress : callable, optional
        Receives one line per computed curve.
    check_force : float, optional
        A second excitation level, N, computed at the same ratios (the
        ratio-invariance check of the criterion); none by default.
    cache : dict, optional
        Shared between figures, see :func:`sdof_family`.
    """
    checks = () if check_force is None else (check_force,)
    return _paper_figure(8, (force,), ratios, harmonics, progress, checks, cache)


def menq_family(
    force: float = 1.0,
    ratios=PAPER_SDOF["ratios"],
    harmonics: int | str = "auto",
    progress: Callable[[str], None] | None = None,
    check_force: float | None = None,
    cache: dict | None = None,
) -> FigureResult:
    """Fig. 9: Menq microslip FRFs for several ``Fex/Fn`` (arguments as in
    :func:`masing_family`)."""
    checks = () if check_force is None else (check_force,)
    return _paper_figure(9, (force,), ratios, harmonics, progress, checks, cache)


def rough_masing_family(
    forces=FORCES,
    ratios=PAPER_SDOF["ratios"],
    harmonics: int | str = "auto",
    progress: Callable[[str], None] | None = None,
    cache: dict | None = None,
) -> FigureResult:
    """Fig. 10: Masing macroslip with roughness at Fex = 1 N and 1000 N
    (``cache`` as in :func:`sdof_family`)."""
    return _paper_figure(10, forces, ratios, harmonics, progress, (), cache)


def rough_menq_family(
    forces=FORCES,
    ratios=PAPER_SDOF["ratios"],
    harmonics: int | str = "auto",
    progress: Callable[[str], None] | None = None,
    cache: dict | None = None,
) -> FigureResult:
    """Fig. 11: Menq microslip with roughness at Fex = 1 N and 1000 N
    (``cache`` as in :func:`sdof_family`)."""
    return _paper_figure(11, forces, ratios, harmonics, progress, (), cache)


def sdof_figures(
    harmonics: int | str = "auto", progress: Callable[[str], None] | None = None
) -> list[FigureResult]:
    """Figs. 8–11 of the paper; Figs. 8 and 9 with the Fex = 1000 N check.
    Curves whose contact is the same (roughness without effect above the
    limit load) are computed once."""
    return list(iter_sdof_figures(harmonics, progress))


def iter_sdof_figures(
    harmonics: int | str = "auto", progress: Callable[[str], None] | None = None
) -> Iterator[FigureResult]:
    """:func:`sdof_figures` one figure at a time, each yielded as soon as it
    is computed (so that a caller can write it before the next one starts)."""
    big, cache = FORCES[-1], {}
    kw = {"harmonics": harmonics, "progress": progress, "cache": cache}
    yield masing_family(check_force=big, **kw)
    yield menq_family(check_force=big, **kw)
    yield rough_masing_family(**kw)
    yield rough_menq_family(**kw)
