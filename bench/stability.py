"""Cost of Hill's stability against the branch's own trace (issue 16).

P1 (m = 1, c = 0.02, k = 1, Jenkins kt = 3, f_s = 1), F = 0.5, Ω in
(0.5, 3), H = 15 fixed: the warm trace time (``Branch.elapsed``) against
the time of ``Branch.stability()`` (``exponents="auto"``: eigenvalues at a
few points) and of ``Branch.stability(exponents="all")`` on the same
branch, minimum of ``--repeat`` interleaved runs; the same for the
hardening Duffing of ``tests/test_stability.py`` (H = 9) and for P1's
oscillator with a Menq contact (H = 15); then the Duffing case: how close
the stability changes lie to the folds; with ``--beam`` the paper beam
(several DOFs: eigenvalues at every point), F_n = 5 N.

    python -m bench.stability [--repeat 10] [--beam] [--chain auto|all]

``--chain``: the three-DOF chain with a Jenkins contact between DOFs 1 and
2 (the monodromy's branch), ``Branch.stability()`` alone (``auto``) or also
at every point (``all``, minutes).
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
    return _ratio(lambda: hf.frf(osc, 0.5, (0.5, 3.0), harmonics=15), repeat)


def duffing_ratio(repeat: int) -> dict:
    """The hardening Duffing of ``tests/test_stability.py`` (two folds, an
    unstable middle stretch; memoryless: no anchors)."""
    osc = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    hf.frf(osc, 0.2, (0.5, 2.0), harmonics=9).stability()  # warm
    return _ratio(lambda: hf.frf(osc, 0.2, (0.5, 2.0), harmonics=9), repeat)


def menq_ratio(repeat: int) -> dict:
    """P1's oscillator with a Menq contact of the same stiffness and slip
    force, H = 15 (hysteretic: anchors)."""
    law = hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0)
    osc = hf.Oscillator(1.0, 0.02, 1.0, law)
    hf.frf(osc, 0.5, (0.5, 3.0), harmonics=15).stability()  # warm
    return _ratio(lambda: hf.frf(osc, 0.5, (0.5, 3.0), harmonics=15), repeat)


def beam_ratio(repeat: int) -> dict:
    import warnings

    from hbmfric.paper.beam import HZ, paper_beam, paper_calibration

    system = paper_beam(5.0, paper_calibration())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        return _ratio(lambda: hf.frf(system, 2.0, (15.0 * HZ, 110.0 * HZ)), repeat)


def chain_monodromy(every_point: bool) -> dict:
    """The user's three-DOF chain (Jenkins between DOFs 1 and 2, F = 5,
    8-25 rad/s, adaptive H): ``Branch.stability()`` by the monodromy at a
    few points, and with ``every_point`` at every point (minutes)."""
    k = np.array(
        [[2000.0, -1000.0, 0.0], [-1000.0, 2000.0, -1000.0], [0.0, -1000.0, 1000.0]]
    )
    system = hf.LinearStructure(
        np.eye(3),
        k,
        modal_damping=0.01,
        load={0: 1.0},
        contacts=[hf.Contact(hf.Jenkins(stiffness=2000.0, slip_force=1.0), 1, other=2)],
    )
    branch = hf.frf(system, 5.0, (8.0, 25.0))
    t = time.perf_counter()
    stab = branch.stability()
    out = {
        "points": len(branch),
        "trace_s": branch.elapsed,
        "auto_s": time.perf_counter() - t,
        "computed": int(stab.computed.sum()),
        "unstable": int(np.count_nonzero(~stab.stable)),
    }
    if every_point:
        branch._stability = None
        t = time.perf_counter()
        full = branch.stability(exponents="all")
        out["all_s"] = time.perf_counter() - t
        out["equal"] = bool(np.array_equal(full.stable, stab.stable))
    return out


def _ratio(trace_branch, repeat: int) -> dict:
    trace, hill, full = [], [], []
    for _ in range(repeat):
        branch = trace_branch()
        trace.append(branch.elapsed)
        t = time.perf_counter()
        stab = branch.stability()
        hill.append(time.perf_counter() - t)
        computed = int(stab.computed.sum())
        branch._stability = None
        t = time.perf_counter()
        ref = branch.stability(exponents="all")
        full.append(time.perf_counter() - t)
        assert (ref.stable == stab.stable).all()
    return {
        "points": len(branch),
        "trace_ms": 1e3 * min(trace),
        "stability_ms": 1e3 * min(hill),
        "ratio": min(hill) / min(trace),
        "all_ms": 1e3 * min(full),
        "all_ratio": min(full) / min(trace),
        "computed": computed,
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
    parser.add_argument("--beam", action="store_true")
    parser.add_argument(
        "--chain",
        choices=("auto", "all"),
        help="the three-DOF Jenkins chain by the monodromy (all: also every point)",
    )
    args = parser.parse_args()
    if args.chain:
        r = chain_monodromy(args.chain == "all")
        print(
            f"chain: {r['points']} points, trace {r['trace_s']:.2f} s, monodromy "
            f"at {r['computed']} points {r['auto_s']:.2f} s, unstable "
            f"{r['unstable']}"
            + (
                f"; every point {r['all_s']:.1f} s, verdicts equal: {r['equal']}"
                if "all_s" in r
                else ""
            )
        )
        return
    cases = [
        ("P1 F=0.5 H=15", p1_ratio),
        ("Duffing F=0.2 H=9", duffing_ratio),
        ("Menq SDOF F=0.5 H=15", menq_ratio),
    ]
    if args.beam:
        cases.append(("beam Fn=5", beam_ratio))
    for name, run in cases:
        r = run(args.repeat)
        print(
            f"{name}: {r['points']} points, trace {r['trace_ms']:.1f} ms, "
            f"stability {r['stability_ms']:.1f} ms (eigenvalues at "
            f"{r['computed']} points), ratio {r['ratio']:.2f}; "
            f'exponents="all" {r["all_ms"]:.1f} ms, ratio {r["all_ratio"]:.2f} '
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
