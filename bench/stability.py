"""Cost of Hill's stability against the branch's own trace (issue 16).

P1 (m = 1, c = 0.02, k = 1, Jenkins kt = 3, f_s = 1), F = 0.5, Ω in
(0.5, 3), H = 15 fixed: the warm trace time (``Branch.elapsed``) against
the time of ``Branch.stability()`` on the same branch, minimum of
``--repeat`` interleaved runs; then the Duffing case of
``tests/test_stability.py``: how close the stability changes lie to the
folds.

    python -m bench.stability [--repeat 10]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import hbmfric as hf


def p1_ratio(repeat: int) -> dict:
    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    osc = hf.Oscillator(1.0, 0.02, 1.0, law)
    hf.frf(osc, 0.5, (0.5, 3.0), harmonics=15).stability()  # warm
    trace, hill = [], []
    for _ in range(repeat):
        branch = hf.frf(osc, 0.5, (0.5, 3.0), harmonics=15)
        trace.append(branch.elapsed)
        t = time.perf_counter()
        branch.stability()
        hill.append(time.perf_counter() - t)
    return {
        "points": len(branch),
        "trace_ms": 1e3 * min(trace),
        "stability_ms": 1e3 * min(hill),
        "ratio": min(hill) / min(trace),
        "all_stable": bool(branch.stable.all()),
    }


def duffing_folds() -> list[tuple[float, float, float]]:
    osc = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    b = hf.frf(osc, 0.2, (0.5, 2.0), harmonics=9)
    s = b.stability()
    out = []
    for i in b.folds:
        t0, t1 = b.tangents[i - 1, -1], b.tangents[i, -1]
        w0, w1 = b.omega[i - 1], b.omega[i]
        fold = w0 + (w1 - w0) * t0 / (t0 - t1)
        r0, r1 = s.max_real[i - 1], s.max_real[i]
        change = w0 + (w1 - w0) * r0 / (r0 - r1)
        out.append((fold, change - fold, abs(w1 - w0)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=10)
    args = parser.parse_args()
    r = p1_ratio(args.repeat)
    print(
        f"P1 F=0.5 H=15: {r['points']} points, trace {r['trace_ms']:.1f} ms, "
        f"stability {r['stability_ms']:.1f} ms, ratio {r['ratio']:.2f} "
        f"(all stable: {r['all_stable']})"
    )
    for fold, gap, spacing in duffing_folds():
        print(
            f"Duffing fold at Ω = {fold:.9f}: stability change {gap:+.1e} rad/s "
            f"away (point spacing {spacing:.1e})"
        )
    print("np", np.__version__)


if __name__ == "__main__":
    main()
