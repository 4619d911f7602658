"""The single-DOF study of the paper (Sec. 3.1): FRF families against
``Fex/Fn``."""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..api import frf
from ..results import Branch
from .scenes import PAPER_SDOF, paper_oscillator


@dataclass
class FigureResult:
    """A computed figure: its curves and where they were written."""

    name: str
    title: str
    labels: list[str]
    branches: list[Branch]
    parameters: list[dict]
    files: list[Path] = field(default_factory=list)

    def write_csv(self, path: Path) -> Path:
        """Long-format CSV: one row per point of every curve.

        Columns: ``curve, force_N, normal_load_N, ratio, omega_rad_s,
        amplitude_h1_m, amplitude_m, amplitude_h1_per_force_m_per_N``.
        """
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(
                [
                    "curve",
                    "force_N",
                    "normal_load_N",
                    "ratio",
                    "omega_rad_s",
                    "amplitude_h1_m",
                    "amplitude_m",
                    "amplitude_h1_per_force_m_per_N",
                ]
            )
            for label, b, par in zip(
                self.labels, self.branches, self.parameters, strict=True
            ):
                a1 = b.amplitude(harmonic=1)
                a = b.amplitude()
                for om, x1, x in zip(b.omega, a1, a, strict=True):
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
                        ]
                    )
        self.files.append(Path(path))
        return Path(path)

    def write_png(self, path: Path) -> Path:
        """Plot the curves (amplitude per unit force against Ω)."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.4, 4.4))
        for label, b, par in zip(
            self.labels, self.branches, self.parameters, strict=True
        ):
            ax.semilogy(b.omega, b.amplitude(harmonic=1) / par["force"], label=label)
        ax.set_xlabel("Ω (rad/s)")
        ax.set_ylabel("first-harmonic amplitude / Fex (m/N)")
        ax.set_title(self.title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(path, dpi=120)
        plt.close(fig)
        self.files.append(Path(path))
        return Path(path)


def masing_family(
    force: float = 1.0,
    ratios=PAPER_SDOF["ratios"],
    harmonics: int = 15,
    progress: Callable[[str], None] | None = None,
) -> FigureResult:
    """Fig. 8: Masing (Jenkins) macroslip FRFs for several ``Fex/Fn``.

    Parameters
    ----------
    force : float
        Excitation amplitude Fex, N (the normalised FRFs depend on Fex/Fn
        only).
    ratios : sequence of float
        Values of Fex/Fn.
    harmonics : int
        Highest harmonic.
    progress : callable, optional
        Receives one line per computed curve.
    """
    branches, labels, params = [], [], []
    for ratio in ratios:
        normal_load = force / ratio
        osc = paper_oscillator(normal_load)
        b = frf(osc, force, PAPER_SDOF["omega"], harmonics)
        branches.append(b)
        labels.append(f"Fex/Fn = {ratio:g}")
        params.append({"force": force, "normal_load": normal_load, "ratio": ratio})
        if progress is not None:
            peak = int(np.argmax(b.amplitude(harmonic=1)))
            progress(
                f"fig8 Masing Fex/Fn={ratio:g}: {len(b)} points, "
                f"{b.elapsed * 1e3:.1f} ms, peak {b.amplitude(harmonic=1)[peak]:.4g} m "
                f"at {b.omega[peak]:.2f} rad/s, stop: {b.stop_reason}"
            )
    return FigureResult(
        "fig08_masing",
        "Fig. 8 — Masing macroslip, SDOF",
        labels,
        branches,
        params,
    )
