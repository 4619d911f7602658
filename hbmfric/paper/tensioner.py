"""The belt-tensioner part of the paper (Sec. 2): the identified hysteresis
loop (Fig. 3) and the belt-tension FRF family (Fig. 5).

The paper's measured loop is not available, so Fig. 3 is reproduced on a
loop *synthesised* from the rig's default tensioner law (exact exponential
branches), with 1.5 % force noise, 0.5 % displacement noise, a mean offset
and 4.3 cycles; the identification must recover the law it came from. Fig. 5
is computed on :class:`~hbmfric.BeltTensioner` with that identified law, by
HBM continuation (lines) and by the JIT time integrator at a few frequencies
(markers), as the paper did with Gear's method.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..continuation import ContinuationOptions
from ..identify import DahlIdentification, modified_dahl
from ..systems.tensioner import BeltTensioner, default_tensioner
from ..systems.tensioner_response import TensionFRF, hbm_frf, time_domain_frf
from ._figures import pyplot, save_figure

#: forcing amplitudes f1 of the Fig. 5 family, N
FORCES = (2.0, 5.0, 20.0, 50.0)
#: frequency band, Hz
BAND = (5.0, 100.0)


def synthetic_loop(
    law=None,
    cycles: float = 4.3,
    samples_per_cycle: int = 800,
    mean: float = 2.0e-3,
    amplitude: float = 4.0e-3,
    force_noise: float = 0.015,
    u_noise: float = 0.005,
    seed: int = 2008,
) -> tuple[np.ndarray, np.ndarray]:
    """A noisy 'measured' loop of a μ = 1 modified Dahl law under a
    displacement ``mean + amplitude cos(2π t)``; noise standard deviations
    are fractions of the ranges. Returns ``(u, force)``."""
    law = law or default_tensioner()
    beta, _, a, b, d, e = law.params
    t = np.arange(int(cycles * samples_per_cycle)) / samples_per_cycle
    u = mean + amplitude * np.cos(2.0 * np.pi * t + 0.7)
    f = np.empty_like(u)
    f[0] = 0.5 * ((a + d) * u[0] + b + e)
    for i in range(1, u.size):
        du = u[i] - u[i - 1]
        if du > 0:
            g = f[i - 1] - a * u[i - 1] - b + a / beta
            f[i] = a * u[i] + b - a / beta + g * math.exp(-beta * du)
        else:
            g = f[i - 1] - d * u[i - 1] - e - d / beta
            f[i] = d * u[i] + e + d / beta + g * math.exp(beta * du)
    rng = np.random.default_rng(seed)
    return (
        u + u_noise * np.ptp(u) * rng.standard_normal(u.size),
        f + force_noise * np.ptp(f) * rng.standard_normal(u.size),
    )


@dataclass
class LoopFigure:
    """Fig. 3 analogue: measured and identified loops."""

    identification: DahlIdentification
    true_law: object
    name: str = "fig03_tensioner_loop"
    files: list[Path] = field(default_factory=list)

    def write_csv(self, path: Path) -> Path:
        """Columns ``u_m, force_measured_N, force_model_N``; the identified
        parameters in a leading comment block."""
        r = self.identification
        with open(path, "w", newline="") as fh:
            fh.write(
                f"# identified: a={r.upper[0]:.6g} b={r.upper[1]:.6g} "
                f"d={r.lower[0]:.6g} e={r.lower[1]:.6g} beta={r.beta:.6g} "
                f"mu={r.exponent:.4g}; rms residual {r.residual_rms:.4g} N\n"
            )
            p = self.true_law.params
            fh.write(
                f"# synthesised from: a={p[2]:.6g} b={p[3]:.6g} d={p[4]:.6g} "
                f"e={p[5]:.6g} beta={p[0]:.6g} mu={p[1]:.4g}\n"
            )
            w = csv.writer(fh)
            w.writerow(["u_m", "force_measured_N", "force_model_N"])
            for row in zip(r.u, r.force, r.model, strict=True):
                w.writerow([f"{v:.10g}" for v in row])
        self.files.append(Path(path))
        return Path(path)

    def write_png(self, path: Path) -> Path:
        pyplot()  # off-screen backend before the identification draws
        return save_figure(self.identification.plot().figure, path, self.files)


@dataclass
class TensionFigure:
    """Fig. 5 analogue: tension variation against frequency, HBM lines and
    time-domain markers for several forcing amplitudes."""

    rig: BeltTensioner
    hbm: list[TensionFRF]
    time_domain: list[TensionFRF]
    name: str = "fig05_tensioner_frf"
    files: list[Path] = field(default_factory=list)

    def write_csv(self, path: Path) -> Path:
        """Long format: ``method, force_N, frequency_Hz, tension_range_N,
        converged``."""
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(
                ["method", "force_N", "frequency_Hz", "tension_range_N", "converged"]
            )
            for curve in [*self.hbm, *self.time_domain]:
                for fr, tr, ok in zip(
                    curve.frequency, curve.tension_range, curve.converged, strict=True
                ):
                    w.writerow(
                        [
                            curve.method,
                            f"{curve.force:g}",
                            f"{fr:.10g}",
                            f"{tr:.10g}",
                            int(ok),
                        ]
                    )
        self.files.append(Path(path))
        return Path(path)

    def write_png(self, path: Path) -> Path:
        plt = pyplot()

        fig, ax = plt.subplots(figsize=(6.8, 4.6))
        for i, (h, t) in enumerate(zip(self.hbm, self.time_domain, strict=True)):
            color = f"C{i}"
            ax.semilogy(
                h.frequency,
                h.tension_range,
                "-",
                color=color,
                label=f"HBM, f1 = {h.force:g} N",
            )
            ax.semilogy(
                t.frequency, t.tension_range, "o", ms=3, color=color, mfc="none"
            )
        stuck = self.rig.resonances()[0]
        for x, text in ((stuck, "stuck"), (stuck / 3.0, "stuck / 3")):
            ax.axvline(x, color="0.6", lw=0.8, ls=":")
            ax.text(x, ax.get_ylim()[1], text, fontsize=7, ha="center", va="bottom")
        ax.set_xlabel("forcing frequency (Hz)")
        ax.set_ylabel("|max T − min T| (N)")
        ax.set_title(
            "Fig. 5 — belt tension variation (lines HBM, circles time domain)",
            fontsize=9,
        )
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        return save_figure(fig, path, self.files)


def tensioner_loop(progress: Callable[[str], None] | None = None) -> LoopFigure:
    """Fig. 3: identify the tensioner law from a synthesised noisy loop."""
    true_law = default_tensioner()
    u, force = synthetic_loop(true_law)
    r = modified_dahl(u, force)
    if progress is not None:
        p = true_law.params
        progress(
            f"fig3 loop identification: a={r.upper[0]:.5g} ({p[2]:.5g}), "
            f"b={r.upper[1]:.5g} ({p[3]:.5g}), d={r.lower[0]:.5g} ({p[4]:.5g}), "
            f"e={r.lower[1]:.5g} ({p[5]:.5g}), beta={r.beta:.5g} ({p[0]:.5g}); "
            f"rms residual {100 * r.residual_relative:.2f} % of the force range"
        )
    return LoopFigure(r, true_law)


def tensioner_frf(
    law=None,
    forces=FORCES,
    harmonics: int | str = "auto",
    n_time_domain: int = 16,
    progress: Callable[[str], None] | None = None,
) -> TensionFigure:
    """Fig. 5: tension FRF family, HBM continuation and JIT time integration.

    Parameters
    ----------
    law : ModifiedDahl, optional
        Tensioner law (default: the rig's default law).
    forces : sequence of float
        Forcing amplitudes f1, N.
    harmonics : int or "auto"
        HBM harmonics; ``"auto"`` (the engine's default) keeps the tension
        range within 1e-4 of the shooting reference over the band
        (``bench/README.md``, "Belt tensioner against the shooting
        reference"); H = 15, the former setting, is up to 2.5e-3 off at
        f1 = 50 N below 15 Hz.
    n_time_domain : int
        Time-domain frequencies per curve (log-spaced over the band).
    """
    rig = BeltTensioner() if law is None else BeltTensioner(tensioner=law)
    options = ContinuationOptions(max_step=0.03)
    targets = np.geomspace(BAND[0], BAND[1], n_time_domain)
    hbm, td = [], []
    for f1 in forces:
        h = hbm_frf(rig, f1, BAND, harmonics, options=options)
        # time domain at HBM points nearest to log-spaced targets: exact pairs
        pick = np.unique([int(np.argmin(np.abs(h.frequency - f))) for f in targets])
        t = time_domain_frf(rig, f1, h.frequency[pick], "jit", steps_per_period=512)
        hbm.append(h)
        td.append(t)
        if progress is not None:
            err = np.max(np.abs(h.tension_range[pick] / t.tension_range - 1.0))
            progress(
                f"fig5 tension f1={f1:g} N: HBM {h.frequency.size} points "
                f"{h.elapsed:.2f} s ({h.info['stop_reason']}); time domain "
                f"{pick.size} frequencies {t.elapsed:.2f} s, "
                f"{t.work['periods']} periods; max |HBM/TD - 1| {err:.2%}"
            )
    return TensionFigure(rig, hbm, td)
