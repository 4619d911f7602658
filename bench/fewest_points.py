"""The fewest points any straight-line drawing of P1 needs (issue 18).

Run: ``python -m bench.fewest_points [--forces 0.1,0.5,2] [--grid 4000]
[--tolerances 1e-4,8e-5,5e-5]`` from the repository root.

The exact first-harmonic amplitude of P1 (m = 1, c = 0.02, k = 1, Jenkins
kt = 3, f_s = 1, Ω 0.5-3 rad/s) on ``grid`` evenly spaced pulsations
(:func:`hbmfric.validation.curve.curve_references`, event-driven exact
periodic solutions), then the fewest grid points whose polyline stays
within each relative tolerance of the exact curve at every grid pulsation:
from each point the chord is taken as far as it stays within (greedy
furthest reach, the fewest for an interval cover). With exact points the
whole tolerance is the chord's; a branch whose points carry a truncation
error has less. The count is a floor on the points of any method that
draws straight lines between computed points, and with it on the run time
(points times the cost of the evaluations one point needs).
"""

# ruff: noqa: E402  (BLAS threads are set before NumPy is imported)
from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse

import numpy as np


def fewest_points(omega: np.ndarray, amplitude: np.ndarray, tolerance: float) -> int:
    """Fewest points of ``omega`` (sorted, with their ``amplitude``) whose
    polyline is within ``tolerance`` (relative) of ``amplitude`` at every
    pulsation of ``omega``; the first and last are always kept."""
    n = omega.size
    i, count = 0, 1
    while i < n - 1:
        j = i + 1
        while j + 1 < n:
            k = j + 1
            seg = slice(i, k + 1)
            slope = (amplitude[k] - amplitude[i]) / (omega[k] - omega[i])
            line = amplitude[i] + (omega[seg] - omega[i]) * slope
            if np.max(np.abs(line - amplitude[seg]) / amplitude[seg]) > tolerance:
                break
            j = k
        i = j
        count += 1
    return count


def main() -> None:
    import hbmfric as hf
    from hbmfric.validation.curve import curve_references

    ap = argparse.ArgumentParser()
    ap.add_argument("--forces", default="0.1,0.5,2")
    ap.add_argument("--grid", type=int, default=4000)
    ap.add_argument("--tolerances", default="1e-4,8e-5,5e-5")
    args = ap.parse_args()
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    tolerances = [float(t) for t in args.tolerances.split(",")]
    print("| F | " + " | ".join(f"fewest at {t:g}" for t in tolerances) + " |")
    print("|---" * (len(tolerances) + 1) + "|")
    for force in (float(f) for f in args.forces.split(",")):
        grid = np.linspace(0.5, 3.0, args.grid)
        w, a = curve_references(osc, force, grid, method="exact")
        counts = [fewest_points(w, a, t) for t in tolerances]
        print(f"| {force:g} | " + " | ".join(str(c) for c in counts) + " |")


if __name__ == "__main__":
    main()
