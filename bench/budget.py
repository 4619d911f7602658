"""Points' error in the curve rule (issue 18): warm branch times (median of
``repeats``), point counts and, with ``--errors``, the curve error against
exact event-driven references (100 pulsations plus every chord midpoint).

Run: ``python -m bench.budget [--repeats 5] [--cases p1,beam] [--errors]``.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

import hbmfric as hf
from hbmfric.validation import branch_curve_error, curve_references, reference_omegas

from .curve_error import beam, p1


def run(case, repeats: int, errors: bool) -> dict:
    system, force, omega = case
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        b = hf.frf(system, force, omega)
        times = []
        for _ in range(repeats):
            t = time.perf_counter()
            hf.frf(system, force, omega)
            times.append(time.perf_counter() - t)
    row = dict(
        points=len(b),
        rejected=b.n_rejected,
        estimate=b.curve_error,
        time_ms=1e3 * statistics.median(times),
    )
    if errors:
        w, a = curve_references(system, force, reference_omegas(omega, 100, b))
        e = branch_curve_error(b, w, a)
        row.update(curve_error=e.max, worst_omega=e.worst_omega)
    return row


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--cases", default="p1,beam")
    ap.add_argument("--errors", action="store_true")
    args = ap.parse_args()
    cases = []
    if "p1" in args.cases:
        cases += [(f"P1 F={f}", p1(f)) for f in (0.1, 0.5, 2.0)]
    if "beam" in args.cases:
        cases += [(f"beam Fn={f}", beam(f)) for f in (5.0, 1.0, 0.5)]
    for name, case in cases:
        row = run(case, args.repeats, args.errors)
        print(name, " ".join(f"{k}={v:.4g}" for k, v in row.items()), flush=True)


if __name__ == "__main__":
    main()
