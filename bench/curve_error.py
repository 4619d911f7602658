"""The curve between the points (issue 18): error of the straight lines
between a branch's returned points against exact references, point counts
and warm branch times, with the curve rule on (``curve_tolerance=1e-4``,
the default) and off (``None``: the step control before issue 18).

Run: ``python -m bench.curve_error [--repeats 30] [--cases p1,beam,menq,iwan]``
from the repository root. References: exact event-driven solutions
(:func:`hbmfric.validation.exact_branch`) at 100 evenly spaced pulsations
plus the chord midpoints of the branch measured (Jenkins SDOF P1 and the
paper beam), time integration at >= 40 pulsations (Menq, Iwan). Times:
the least of ``repeats`` warm runs, settings interleaved.
"""

from __future__ import annotations

import argparse
import time
import warnings

import hbmfric as hf
from hbmfric.validation import branch_curve_error, curve_references, reference_omegas

P1 = dict(mass=1.0, damping=0.02, stiffness=1.0)
SETTINGS = {"off": None, "on": 1e-4}


def p1(force: float):
    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    return hf.Oscillator(contact=law, **P1), force, (0.5, 3.0)


def beam(normal_load: float):
    from hbmfric.paper.beam import HZ, paper_beam, paper_calibration

    return paper_beam(normal_load, paper_calibration()), 2.0, (15.0 * HZ, 110.0 * HZ)


def menq(force: float = 0.5):
    law = hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0, microslip_onset=0.2)
    return hf.Oscillator(contact=law, **P1), force, (0.5, 3.0)


def iwan(force: float = 0.5):
    law = hf.Iwan(stiffnesses=[1.0, 1.0, 1.0], slip_forces=[0.2, 0.5, 0.8])
    return hf.Oscillator(contact=law, **P1), force, (0.5, 3.0)


def measure(system, force, omega, repeats, method="exact", n_ref=100):
    rows = {}
    branches = {}
    times = {k: [] for k in SETTINGS}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        for k, tol in SETTINGS.items():
            branches[k] = hf.frf(system, force, omega, curve_tolerance=tol)
        for _ in range(repeats):
            for k, tol in SETTINGS.items():
                t = time.perf_counter()
                hf.frf(system, force, omega, curve_tolerance=tol)
                times[k].append(time.perf_counter() - t)
    for k, b in branches.items():
        if k == "off" and method == "integrate":
            w = reference_omegas(omega, n_ref)  # enough to show the error
        else:
            w = reference_omegas(omega, n_ref, b)
        w, a = curve_references(system, force, w, method=method)
        e = branch_curve_error(b, w, a)
        rows[k] = dict(
            points=len(b),
            rejected=b.n_rejected,
            curve_error=e.max,
            worst_omega=e.worst_omega,
            estimate=b.curve_error,
            time_ms=1e3 * min(times[k]),
        )
    return rows


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=30)
    ap.add_argument("--cases", default="p1")
    args = ap.parse_args()
    cases = []
    for name in args.cases.split(","):
        if name == "p1":
            cases += [(f"P1 F={f:g}", p1(f), "exact") for f in (0.1, 0.5, 2.0)]
        elif name == "beam":
            cases += [(f"beam Fn={f:g} N", beam(f), "exact") for f in (5.0, 1.0, 0.5)]
        elif name == "menq":
            cases.append(("Menq F=0.5", menq(), "integrate"))
        elif name == "iwan":
            cases.append(("Iwan F=0.5", iwan(), "integrate"))
    for label, case, method in cases:
        n_ref = 100 if method == "exact" else 40
        rows = measure(*case, args.repeats, method=method, n_ref=n_ref)
        for k, r in rows.items():
            print(
                f"{label} curve {k:3s}: {r['points']:4d} points "
                f"({r['rejected']} rejected), curve error {r['curve_error']:.2e} "
                f"at {r['worst_omega']:.4g} (estimate {r['estimate']:.2e}), "
                f"{r['time_ms']:.2f} ms",
                flush=True,
            )


if __name__ == "__main__":
    main()
