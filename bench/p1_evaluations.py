"""Where P1's residual evaluations go at default settings (issue 18,
stop 31).

Run: ``python -m bench.p1_evaluations [--forces 0.5,2]`` from the
repository root. The branch is traced as ``hf.frf`` traces it, with the
compiled stretch (:func:`hbmfric.kernels.steps.arclength.trace`) replaced
by the same loop in Python over the same compiled step
(:func:`~hbmfric.kernels.steps.arclength.advance`) and watch
(:func:`~hbmfric.kernels.steps.arclength.stays`), so that every step's
outcome and evaluations are seen; the branch is the same (points and
evaluation count as ``hf.frf``'s, checked). The solves made from Python
(first point, points solved again at a new level, the boundary point) are
logged by their caller (the final pass's, ``settle``, which solves a
point one level up where its estimate fails, are not in the branch's
``newton_iterations``).

The floor is two evaluations per accepted step: the corrector evaluates
at the predictor, solves one Newton update, and must evaluate at the
updated point to test the residual and the next update there (and to have
the Jacobian for the tangent). Printed: accepted steps by evaluations and
by level, rejected steps, the Python solves, and the excess over that
floor. Not a timing script.
"""

# ruff: noqa: E402  (BLAS threads are set before NumPy is imported)
from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import collections
import inspect
import warnings

from hbmfric.continuation import palc
from hbmfric.kernels.steps import arclength as al

P1_RANGE = (0.5, 3.0)


class _Log:
    """Steps ``(H, outcome, evaluations, first)`` (``first``: the first
    step of a compiled stretch, i.e. after a level change or a decision in
    Python) and Python solves ``(H, caller, evaluations)`` of one branch."""

    def __init__(self) -> None:
        self.steps: list[tuple[int, int, int, bool]] = []
        self.solves: list[tuple[int, str, int]] = []
        self.level = 0


def _traced(log: _Log):
    """A Python copy of :func:`hbmfric.kernels.steps.arclength.trace` that
    logs every step into ``log`` (the same calls in the same order)."""

    def trace(
        problem, residual_at, y, tangent, step, scale, settings, max_attempts,
        watch, points, tangents, flags, estimates, R, J, A, piv, y_pred, y_new,
        t_new, history, calibration,
    ):  # fmt: skip
        n_acc = n_rej = ev = attempts = 0
        while True:
            if n_acc == points.shape[0]:
                return al.BUFFER_FULL, n_acc, n_rej, ev, step
            if attempts == max_attempts:
                return al.BUDGET_SPENT, n_acc, n_rej, ev, step
            attempts += 1
            outcome, step, spent = al.advance(
                problem, residual_at, y, tangent, step, scale, settings,
                R, J, A, piv, y_pred, y_new, t_new, history,
            )  # fmt: skip
            ev += spent
            log.steps.append((log.level, int(outcome), int(spent), attempts == 1))
            if outcome == al.LEFT_RANGE:
                return al.RANGE_LEFT, n_acc, n_rej, ev, step
            if outcome == al.REJECTED or outcome == al.STEP_TOO_SMALL:
                n_rej += 1
                if outcome == al.STEP_TOO_SMALL:
                    return al.STEP_BELOW_MIN, n_acc, n_rej, ev, step
                continue
            points[n_acc] = y
            tangents[n_acc] = tangent * scale
            flags[n_acc] = outcome
            n_acc += 1
            if watch[al.WATCH_ACTIVE] != 0.0:
                if not al.stays(y, watch, calibration):
                    return al.WATCH_STOP, n_acc, n_rej, ev, step
                if watch[al.W_AGE] == 0.0:
                    estimates[n_acc - 1] = watch[al.W_LAST]
                if settings[al.CURVE_POINT] >= 0.0:
                    settings[al.CURVE_POINT] = watch[al.W_LAST]

    return trace


def breakdown(force: float) -> dict:
    """Trace P1 at ``force`` (defaults) with the logging loop; returns the
    counts (see the module doc)."""
    import hbmfric as hf

    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        plain = hf.frf(osc, force, P1_RANGE)
    log = _Log()
    cont = palc.Continuation
    saved = (palc._arclength.trace, cont._trace, cont.solve_at)

    def _trace(self, *args, **kwargs):
        log.level = int(self.problem.harmonic_numbers[-1])
        return saved[1](self, *args, **kwargs)

    def solve_at(self, *args, **kwargs):
        out = saved[2](self, *args, **kwargs)
        caller = inspect.stack()[1].function
        log.solves.append((int(self.problem.harmonic_numbers[-1]), caller, int(out[2])))
        return out

    palc._arclength.trace = _traced(log)
    palc.Continuation._trace = _trace
    palc.Continuation.solve_at = solve_at
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            b = hf.frf(osc, force, P1_RANGE)
    finally:
        palc._arclength.trace, palc.Continuation._trace = saved[:2]
        palc.Continuation.solve_at = saved[2]
    same = len(b) == len(plain) and b.newton_iterations == plain.newton_iterations
    rejected = (al.REJECTED, al.STEP_TOO_SMALL)
    acc = [s for s in log.steps if s[1] not in rejected and s[1] != al.LEFT_RANGE]
    rej = [s for s in log.steps if s[1] in rejected]
    left = [s for s in log.steps if s[1] == al.LEFT_RANGE]
    by_level = collections.defaultdict(collections.Counter)
    for h, _, e, _ in acc:
        by_level[h][e] += 1
    first = collections.Counter(s[2] for s in acc if s[3])
    first_rejected = sum(1 for s in rej if s[3])
    solves = collections.defaultdict(lambda: [0, 0])
    for _, caller, e in log.solves:
        solves[caller][0] += 1
        solves[caller][1] += e
    return {
        "force": force,
        "same_branch": same,
        "points": len(b),
        "evaluations": int(b.newton_iterations),
        "accepted": len(acc),
        "accepted_evaluations": sum(s[2] for s in acc),
        "accepted_histogram": dict(
            sorted(collections.Counter(s[2] for s in acc).items())
        ),
        "by_level": {h: dict(sorted(c.items())) for h, c in sorted(by_level.items())},
        "first_of_stretch": dict(sorted(first.items())),
        "stretches": sum(1 for s in log.steps if s[3]),
        "rejected": len(rej),
        "rejected_first": first_rejected,
        "rejected_evaluations": sum(s[2] for s in rej),
        "left_range_evaluations": sum(s[2] for s in left),
        "python_solves": {k: tuple(v) for k, v in solves.items()},
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--forces", default="0.1,0.5,2")
    args = p.parse_args()
    for f in (float(x) for x in args.forces.split(",")):
        r = breakdown(f)
        floor = 2 * r["accepted"]
        print(
            f"F = {f:g}: {r['points']} points, {r['evaluations']} evaluations "
            f"(same branch as hf.frf: {r['same_branch']}); floor 2 per accepted "
            f"step: {floor}, excess {r['evaluations'] - floor}"
        )
        print(
            f"  accepted {r['accepted']}: {r['accepted_evaluations']} evaluations, "
            f"by evaluations per step {r['accepted_histogram']}"
        )
        print(
            f"  {r['stretches']} compiled stretches (a level change or a "
            f"decision in Python before each): first steps accepted at once, "
            f"by evaluations {r['first_of_stretch']}; rejected "
            f"{r['rejected_first']}"
        )
        for h, c in r["by_level"].items():
            print(f"    H = {h}: {c}")
        print(
            f"  rejected {r['rejected']} ({r['rejected_first']} the first step of "
            f"a stretch): {r['rejected_evaluations']} evaluations; "
            f"the step out of the range: {r['left_range_evaluations']}"
        )
        print(f"  Python solves (calls, evaluations): {r['python_solves']}")
        counted = (
            r["accepted_evaluations"]
            + r["rejected_evaluations"]
            + r["left_range_evaluations"]
            + sum(v[1] for k, v in r["python_solves"].items() if k != "settle")
        )
        print(
            f"  logged, the final pass's solves (settle) left out: {counted} "
            f"(the branch's count: {r['evaluations']}; settle's are not in it)"
        )


if __name__ == "__main__":
    main()
