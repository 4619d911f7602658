"""Accuracy of the engine's defaults against exact references.

Run: ``python -m bench.exact_reference [--out bench/results] [--scenes a,b]``
from the repository root. For every scene (the paper's SDOF Jenkins cases
and the paper beam with a Jenkins tip at Fn = 5, 1, 0.5 N) and every setting
(``hf.frf`` defaults, i.e. ``harmonics="auto"``; H = 15, the former
default; H = 31; and a scan of fixed H for the smallest one within 1e-4):

* the whole FRF branch over the scene's range is traced by ``hf.frf`` and
  timed (least of ``REPEATS`` warm runs);
* for the three headline settings, every point of the whole branch is also
  compared with the exact reference at its own pulsation
  (:func:`hbmfric.validation.branch_errors`, ``whole_*`` columns), and the
  branch's own per-point estimate ``Branch.truncation_error`` with the
  true error there (the larger of the two relative errors; points with a
  true error above 1e-7): largest estimate, largest true error, points
  where the estimate is below the true error, worst ratio true/estimate;
* at ``N_CHECK`` pulsations spread evenly over ``±WINDOW`` around the
  resonance peak (of the H = 15 branch), the HBM solution of the same
  discretisation is solved from the nearest branch point and compared with
  the exact event-driven periodic solution
  (:func:`hbmfric.validation.exact_branch`): relative error of the
  first-harmonic amplitude at the contact DOF (the headline figure), of half
  the peak-to-peak displacement there, and, for the beam, of the
  first-harmonic amplitude at the forced DOF.

Writes ``exact_reference.csv`` (one row per scene, setting and pulsation)
and ``exact_reference_summary.csv`` (one row per scene and setting: maxima
over the pulsations, run time).
"""

# ruff: noqa: E402  (BLAS threads are set before NumPy is imported)
from __future__ import annotations

import os

# the exact reference does many small dense products: threaded BLAS only
# adds overhead (6x slower on the shared 2-core machine)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import csv
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import hbmfric as hf
from hbmfric.paper.beam import HZ, paper_beam, paper_calibration
from hbmfric.paper.scenes import PAPER_SDOF, paper_oscillator
from hbmfric.validation import branch_errors, exact_branch

#: pulsations checked per scene, and the half-width of their window
#: relative to the resonance peak
N_CHECK = 30
WINDOW = 0.2
REPEATS = 3
TARGET = 1e-4
#: fixed H scanned for the smallest one meeting TARGET (increasing)
SCAN = (3, 5, 7, 9, 11, 13, 15, 19, 23, 27, 31, 41, 51, 63)


@dataclass(frozen=True)
class Scene:
    name: str
    system: object
    force: float
    omega: tuple[float, float]
    extra_dof: str | None = None  # second DOF whose error is reported


def scenes() -> list[Scene]:
    out = []
    for ratio in PAPER_SDOF["ratios"]:
        out.append(
            Scene(
                f"sdof Fex/Fn={ratio:g}",
                paper_oscillator(1.0 / ratio),
                1.0,
                PAPER_SDOF["omega"],
            )
        )
    cal = paper_calibration()
    for fn in (5.0, 1.0, 0.5):
        out.append(
            Scene(
                f"beam Fn={fn:g} N",
                paper_beam(fn, cal),
                2.0,
                (15.0 * HZ, 110.0 * HZ),
                "force",
            )
        )
    return out


def _time_frf(scene: Scene, harmonics):
    branch = hf.frf(scene.system, scene.force, scene.omega, harmonics)
    best = math.inf
    for _ in range(REPEATS):
        t = time.perf_counter()
        hf.frf(scene.system, scene.force, scene.omega, harmonics)
        best = min(best, time.perf_counter() - t)
    return branch, best


def _solve_like(scene: Scene, branch, harmonics, omega: float):
    i = int(np.argmin(np.abs(branch.omega - omega)))
    h = int(branch.harmonics_at(i)) if harmonics == "auto" else harmonics
    return hf.periodic_solution(
        scene.system, scene.force, omega, h, initial_guess=branch.point(i)
    )


def check_omegas(scene: Scene, branch) -> np.ndarray:
    """``N_CHECK`` pulsations over ``±WINDOW`` around the branch's peak."""
    a = branch.amplitude(harmonic=1)
    peak = float(branch.omega[int(np.argmax(a))])
    lo = max(scene.omega[0], (1.0 - WINDOW) * peak)
    hi = min(scene.omega[1], (1.0 + WINDOW) * peak)
    return np.linspace(lo, hi, N_CHECK)


def evaluate(
    scene: Scene, harmonics, label: str, omegas, refs, rows, whole: bool = False
) -> dict:
    branch, elapsed = _time_frf(scene, harmonics)
    e1, epp, ex = [], [], []
    for w, ref in zip(omegas, refs, strict=True):
        sol = _solve_like(scene, branch, harmonics, float(w))
        a1, r1 = sol.amplitude(harmonic=1), ref.amplitude(harmonic=1)
        pp, rpp = sol.amplitude(), ref.amplitude()
        row = {
            "scene": scene.name,
            "setting": label,
            "omega_rad_s": f"{w:.12g}",
            "harmonics": sol.harmonic_numbers.max(),
            "converged": sol.converged,
            "exact_kind": ref.kind,
            "exact_residual": f"{ref.residual:.3g}",
            "exact_h1_m": f"{r1:.15g}",
            "hbm_h1_m": f"{a1:.15g}",
            "error_h1": f"{abs(a1 - r1) / r1:.4g}",
            "exact_hpp_m": f"{rpp:.15g}",
            "hbm_hpp_m": f"{pp:.15g}",
            "error_hpp": f"{abs(pp - rpp) / rpp:.4g}",
        }
        e1.append(abs(a1 - r1) / r1 if sol.converged else math.inf)
        epp.append(abs(pp - rpp) / rpp if sol.converged else math.inf)
        if scene.extra_dof is not None:
            d = scene.extra_dof
            b1 = sol.amplitude(harmonic=1, dof=d)
            q1 = ref.amplitude(harmonic=1, dof=d)
            row[f"error_h1_{d}"] = f"{abs(b1 - q1) / q1:.4g}"
            ex.append(abs(b1 - q1) / q1)
        rows.append(row)
    worst = int(np.argmax(e1))
    extra = {}
    if whole:
        # every point of the whole branch against its own exact reference
        err = branch_errors(branch, scene.system, on_failure="raise")
        i = int(np.argmax(err.error_h1))
        extra = {
            "whole_error_h1": float(err.error_h1[i]),
            "whole_omega_worst": float(err.omega[i]),
            "whole_error_hpp": float(np.max(err.error_hpp)),
            "whole_reference_time_s": err.elapsed,
        }
        if getattr(branch, "truncation_error", None) is not None:
            # the branch's own per-point estimate against the true error
            true = np.maximum(err.error_h1, err.error_hpp)
            est = np.asarray(branch.truncation_error)[err.index]
            big = true > 1e-7
            ratio = true[big] / np.maximum(est[big], 1e-300)
            # the bound kept: the estimate at least the true error wherever
            # that is within 3 times of the branch's largest
            near = true >= np.max(true) / 3.0
            near_ratio = true[near] / np.maximum(est[near], 1e-300)
            extra.update(
                estimate_max=float(np.max(est)),
                true_max=float(np.max(true)),
                underestimated=f"{int(np.sum(ratio > 1.0))}/{int(np.sum(big))}",
                worst_true_over_estimate=float(np.max(ratio)) if big.any() else 0.0,
                worst_true_over_estimate_near_max=(
                    float(np.max(near_ratio)) if np.max(true) > 1e-7 else 0.0
                ),
            )
    return {
        "scene": scene.name,
        "setting": label,
        "time_s": elapsed,
        "points": len(branch),
        "stop": branch.stop_reason,
        "levels": _levels(branch),
        "error_h1": max(e1),
        "omega_worst": float(omegas[worst]),
        "error_hpp": max(epp),
        "error_h1_extra": max(ex) if ex else math.nan,
        **extra,
    }


def _levels(branch) -> str:
    """``"H:count ..."`` of an adaptive branch, else empty."""
    if branch.point_harmonics is None:
        return ""
    levels, counts = np.unique(branch.point_harmonics, return_counts=True)
    return " ".join(f"{h}:{c}" for h, c in zip(levels, counts, strict=True))


def run(out: Path, names=None) -> list[dict]:
    out.mkdir(parents=True, exist_ok=True)
    rows, summary = [], []
    for scene in scenes():
        if names and scene.name not in names:
            continue
        first, _ = _time_frf(scene, 15)
        omegas = check_omegas(scene, first)
        t = time.perf_counter()
        refs = exact_branch(scene.system, scene.force, omegas, on_failure="raise")
        t_ref = time.perf_counter() - t
        worst_res = max(r.residual for r in refs)
        print(
            f"{scene.name}: exact reference at {len(refs)} pulsations "
            f"{omegas[0]:.4g}-{omegas[-1]:.4g} rad/s in {t_ref:.2f} s, "
            f"kinds {sorted({r.kind for r in refs})}, max residual {worst_res:.2g}",
            flush=True,
        )
        settings = [("auto", "default (auto)"), (15, "H=15"), (31, "H=31")]
        for h, label in settings:
            s = evaluate(scene, h, label, omegas, refs, rows, whole=True)
            s["reference_time_s"] = t_ref
            summary.append(s)
            print(_line(s), flush=True)
        for h in SCAN:
            s = evaluate(scene, h, f"scan H={h}", omegas, refs, rows)
            s["reference_time_s"] = t_ref
            summary.append(s)
            print(_line(s), flush=True)
            if s["error_h1"] <= TARGET:
                break
    _write(rows, out / "exact_reference.csv")
    _write(summary, out / "exact_reference_summary.csv")
    return summary


def _line(s: dict) -> str:
    whole = (
        f"; whole branch h1 {s['whole_error_h1']:.3g} (at "
        f"{s['whole_omega_worst']:.5g} rad/s), hpp {s['whole_error_hpp']:.3g}"
        if "whole_error_h1" in s
        else ""
    )
    if "estimate_max" in s:
        whole += (
            f"; estimate max {s['estimate_max']:.3g} vs true {s['true_max']:.3g}, "
            f"under {s['underestimated']}, worst true/est "
            f"{s['worst_true_over_estimate']:.3g}, within 3x of the largest "
            f"{s['worst_true_over_estimate_near_max']:.3g}"
        )
    return (
        f"  {s['setting']:>16}: err h1 {s['error_h1']:.3g} (at "
        f"{s['omega_worst']:.5g} rad/s), hpp {s['error_hpp']:.3g}, extra "
        f"{s['error_h1_extra']:.3g}; frf {s['time_s'] * 1e3:.1f} ms, "
        f"{s['points']} points {s['levels']}{whole}"
    )


def _write(rows: list[dict], path: Path) -> None:
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, keys)
        w.writeheader()
        for r in rows:
            w.writerow(
                {k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()}
            )


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("bench/results"))
    p.add_argument("--scenes", default="", help="comma-separated scene names")
    a = p.parse_args(argv)
    names = [s.strip() for s in a.scenes.split(",") if s.strip()]
    run(a.out, names)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
