"""Accuracy of ``hf.frf`` at default settings on the belt-tensioner rig
against an independent time-domain reference.

Run: ``python -m bench.tensioner_reference [--out bench/results]
[--forces 2,5,20,50] [--every 1]`` from the repository root (about
10 minutes on the shared 2-core machine).

Reference: the period-T steady state of the equations of motion by shooting
(:func:`hbmfric.systems.tensioner_shooting.shooting_steady_state`: DOP853
at ``rtol = 1e-11`` with every reversal of the pulley located, Newton on
``y(T) = y(0)`` with the variational monodromy, converged to 1e-9 of each
state's range). Quantities: the tension range ``max T − min T`` and the
first-harmonic amplitude of ``u1`` (shaker) and ``u2`` (pulley); error =
relative error, the largest of the three is the headline.

For every forcing amplitude of the paper's Fig. 5 (f1 = 2, 5, 20, 50 N) over
5–100 Hz:

* ``default``: ``hf.frf(rig, f1, band)`` (``harmonics="auto"``), timed
  (least of ``REPEATS`` warm runs); every ``--every``-th point of the whole
  branch against the reference at its own frequency (``whole_*``);
* ``grid``: ``N_GRID`` log-spaced frequencies plus the peak of the tension
  range and one third of the stuck resonance, reference there, compared
  with (a) the default branch interpolated (cubic spline in frequency
  between its points, ``interp_*``; also for a branch with
  ``max_step=FINE_STEP``, the paper figure's step) and (b) the HBM solution at that
  frequency for the default and for fixed ``H`` in ``SCAN`` (solved from
  the nearest branch point), from which the smallest fixed ``H`` within
  1e-4 at every grid frequency is found and its whole branch timed.

Writes ``tensioner_reference.csv`` (one row per force, setting and
frequency) and ``tensioner_reference_summary.csv`` (one row per force and
setting).
"""

# ruff: noqa: E402  (BLAS threads are set before NumPy is imported)
from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import csv
import math
import time
import warnings
from pathlib import Path

import numpy as np

import hbmfric as hf
from hbmfric.results import Branch
from hbmfric.systems.tensioner_response import branch_tension_range
from hbmfric.systems.tensioner_shooting import shooting_steady_state, state_at_zero

FORCES = (2.0, 5.0, 20.0, 50.0)
BAND_HZ = (5.0, 100.0)
N_GRID = 22
REPEATS = 3
TARGET = 1e-4
SCAN = (7, 11, 15, 21, 31, 45, 63)
#: ``max_step`` of the finer branch whose interpolation is also measured
FINE_STEP = 0.03
RIG = hf.BeltTensioner()


def _band() -> tuple[float, float]:
    return 2.0 * math.pi * BAND_HZ[0], 2.0 * math.pi * BAND_HZ[1]


def _frf(force: float, harmonics, repeats: int = REPEATS):
    """The branch and its least wall time over ``repeats`` warm runs, s."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(RIG, force, _band(), harmonics)
        best = math.inf
        for _ in range(repeats):
            t = time.perf_counter()
            hf.frf(RIG, force, _band(), harmonics)
            best = min(best, time.perf_counter() - t)
    return branch, best


def quantities(branch: Branch) -> np.ndarray:
    """Tension range (N) and first-harmonic amplitudes of ``u1``, ``u2`` (m)
    of every point, shape (n, 3)."""
    return np.column_stack(
        [
            branch_tension_range(RIG, branch),
            branch.amplitude(1, "shaker"),
            branch.amplitude(1, "pulley"),
        ]
    )


def reference(force: float, frequency: float, start_from=None):
    """Shooting reference at ``frequency`` (Hz), started from the HBM point
    ``start_from = (harmonic_numbers, coefficients, omega)`` (its values
    are not used, only its branch)."""
    initial = None if start_from is None else state_at_zero(RIG, *start_from)
    ref = shooting_steady_state(RIG, force, frequency, initial)
    if not ref.converged:
        ref = shooting_steady_state(RIG, force, frequency, transient_periods=200)
    values = np.array([ref.tension_range, *ref.first_harmonic])
    return ref, values


def _single(branch: Branch, index: int) -> Branch:
    return Branch(
        omega=branch.omega[index : index + 1],
        coefficients=branch.coefficients[index : index + 1],
        harmonic_numbers=branch.harmonic_numbers,
        force=branch.force,
        folds=np.zeros(0, dtype=np.int64),
        stop_reason="",
        n_steps=0,
        n_rejected=0,
        newton_iterations=0,
        elapsed=0.0,
        info={},
        dof_names=RIG.dof_names,
    )


def _solve_like(force, branch, harmonics, omega):
    i = int(np.argmin(np.abs(branch.omega - omega)))
    h = int(branch.harmonics_at(i)) if harmonics == "auto" else harmonics
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        sol = hf.periodic_solution(RIG, force, omega, h, initial_guess=branch.point(i))
    b = Branch(
        omega=np.array([omega]),
        coefficients=sol.coefficients[None],
        harmonic_numbers=sol.harmonic_numbers,
        force=force,
        folds=np.zeros(0, dtype=np.int64),
        stop_reason="",
        n_steps=0,
        n_rejected=0,
        newton_iterations=0,
        elapsed=0.0,
        info={},
        dof_names=RIG.dof_names,
    )
    return quantities(b)[0], sol.converged


def _levels(branch: Branch) -> str:
    if branch.point_harmonics is None:
        return ""
    h, n = np.unique(branch.point_harmonics, return_counts=True)
    return " ".join(f"{a}:{b}" for a, b in zip(h, n, strict=True))


def grid(branch: Branch, values: np.ndarray) -> np.ndarray:
    """``N_GRID`` log-spaced frequencies (Hz), the tension peak and one
    third of the stuck resonance, sorted."""
    f = branch.omega / (2.0 * math.pi)
    peak = float(f[int(np.argmax(values[:, 0]))])
    extra = [peak, RIG.resonances()[0] / 3.0]
    return np.unique(np.concatenate([np.geomspace(*BAND_HZ, N_GRID), extra]))


def _interpolate(branch: Branch, values: np.ndarray, freqs: np.ndarray):
    from scipy.interpolate import CubicSpline

    f = branch.omega / (2.0 * math.pi)
    if len(branch.folds) or np.any(np.diff(f) <= 0.0):
        return None  # a folded branch has no single value per frequency
    return CubicSpline(f, values, axis=0)(freqs)


def _relative(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(a - b) / np.abs(b)


def run(out: Path, forces=FORCES, every: int = 1) -> list[dict]:
    rows, summary = [], []
    for force in forces:
        t0 = time.perf_counter()
        branch, elapsed = _frf(force, "auto")
        values = quantities(branch)
        # whole branch: every `every`-th point against its own reference
        whole = []
        stable = 0
        for i in range(0, len(branch), every):
            ref, rv = reference(
                force,
                branch.omega[i] / (2.0 * math.pi),
                (branch.harmonic_numbers, branch.coefficients[i], branch.omega[i]),
            )
            stable += ref.stable
            err = _relative(values[i], rv)
            whole.append(err)
            rows.append(
                {
                    "force_N": force,
                    "setting": "default (whole branch)",
                    "frequency_Hz": f"{branch.omega[i] / (2 * math.pi):.10g}",
                    "H": branch.harmonics_at(i),
                    "ref_tension_range_N": f"{rv[0]:.12g}",
                    "ref_h1_shaker_m": f"{rv[1]:.12g}",
                    "ref_h1_pulley_m": f"{rv[2]:.12g}",
                    "error_tension": f"{err[0]:.4g}",
                    "error_h1_shaker": f"{err[1]:.4g}",
                    "error_h1_pulley": f"{err[2]:.4g}",
                    "estimate": f"{branch.truncation_error[i]:.3g}",
                    "ref_residual": f"{ref.residual:.3g}",
                    "ref_stable": int(ref.stable),
                }
            )
        whole = np.array(whole)
        # the grid: reference once, then every setting at those frequencies
        freqs = grid(branch, values)
        refs = []
        for fr in freqs:
            j = int(np.argmin(np.abs(branch.omega - 2 * math.pi * fr)))
            refs.append(
                reference(
                    force,
                    fr,
                    (branch.harmonic_numbers, branch.coefficients[j], branch.omega[j]),
                )[1]
            )
        refs = np.array(refs)
        interp = _interpolate(branch, values, freqs)
        interp_err = None if interp is None else _relative(interp, refs)
        if interp_err is not None:
            for fr, e in zip(freqs, interp_err, strict=True):
                rows.append(
                    {
                        "force_N": force,
                        "setting": "default interpolated",
                        "frequency_Hz": f"{fr:.10g}",
                        "error_tension": f"{e[0]:.4g}",
                        "error_h1_shaker": f"{e[1]:.4g}",
                        "error_h1_pulley": f"{e[2]:.4g}",
                    }
                )
        # the same with a finer continuation step (the paper figure's)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.AccuracyWarning)
            fine = hf.frf(RIG, force, _band(), max_step=FINE_STEP)
        fine_interp = _interpolate(fine, quantities(fine), freqs)
        fine_err = None if fine_interp is None else _relative(fine_interp, refs)
        grid_err = {}
        for setting in ("auto", *SCAN):
            b = branch if setting == "auto" else _frf(force, setting, 0)[0]
            errs = []
            for fr, rv in zip(freqs, refs, strict=True):
                v, ok = _solve_like(force, b, setting, 2.0 * math.pi * fr)
                e = _relative(v, rv) if ok else np.full(3, math.inf)
                errs.append(e)
                rows.append(
                    {
                        "force_N": force,
                        "setting": f"grid H={setting}",
                        "frequency_Hz": f"{fr:.10g}",
                        "error_tension": f"{e[0]:.4g}",
                        "error_h1_shaker": f"{e[1]:.4g}",
                        "error_h1_pulley": f"{e[2]:.4g}",
                    }
                )
            grid_err[setting] = np.array(errs)
        meeting = [h for h in SCAN if np.max(grid_err[h]) <= TARGET]
        best_h = meeting[0] if meeting else None
        best_time = _frf(force, best_h)[1] if best_h else math.nan
        h15, t15 = _frf(force, 15)
        s = {
            "force_N": force,
            "points": len(branch),
            "checked": whole.shape[0],
            "stable": stable,
            "time_s": elapsed,
            "levels": _levels(branch),
            "whole_error": float(np.max(whole)),
            "whole_error_tension": float(np.max(whole[:, 0])),
            "whole_error_h1": float(np.max(whole[:, 1:])),
            "whole_worst_Hz": float(
                branch.omega[every * int(np.argmax(np.max(whole, axis=1)))]
                / (2 * math.pi)
            ),
            "grid_points": freqs.size,
            "grid_error": float(np.max(grid_err["auto"])),
            "interp_error": math.nan if interp_err is None else float(interp_err.max()),
            "fine_points": len(fine),
            "fine_interp_error": (
                math.nan if fine_err is None else float(fine_err.max())
            ),
            "h15_grid_error": float(np.max(grid_err[15])),
            "h15_time_s": t15,
            "best_fixed_H": best_h,
            "best_fixed_time_s": best_time,
            "scan": " ".join(f"{h}:{np.max(grid_err[h]):.2g}" for h in SCAN),
            "wall_s": time.perf_counter() - t0,
        }
        summary.append(s)
        print(_line(s), flush=True)
    out.mkdir(parents=True, exist_ok=True)
    _write(rows, out / "tensioner_reference.csv")
    _write(summary, out / "tensioner_reference_summary.csv")
    return summary


def _line(s: dict) -> str:
    return (
        f"f1 = {s['force_N']:g} N: default {s['time_s'] * 1e3:.0f} ms, "
        f"{s['points']} points ({s['levels']}), whole-branch error "
        f"{s['whole_error']:.2g} (tension {s['whole_error_tension']:.2g}, h1 "
        f"{s['whole_error_h1']:.2g}; worst at {s['whole_worst_Hz']:.4g} Hz; "
        f"{s['checked']} checked, {s['stable']} stable); grid of "
        f"{s['grid_points']}: {s['grid_error']:.2g}, interpolated "
        f"{s['interp_error']:.2g} (max_step {FINE_STEP}: {s['fine_points']} "
        f"points, {s['fine_interp_error']:.2g}); H = 15: {s['h15_grid_error']:.2g}, "
        f"{s['h15_time_s'] * 1e3:.0f} ms; smallest fixed H within 1e-4: "
        f"{s['best_fixed_H']} ({s['best_fixed_time_s'] * 1e3:.0f} ms); scan "
        f"{s['scan']}; {s['wall_s']:.0f} s"
    )


def _write(rows: list[dict], path: Path) -> None:
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("bench/results"))
    p.add_argument("--forces", default=",".join(f"{f:g}" for f in FORCES))
    p.add_argument("--every", type=int, default=1)
    a = p.parse_args(argv)
    run(a.out, [float(f) for f in a.forces.split(",")], a.every)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
