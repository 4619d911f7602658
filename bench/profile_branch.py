"""Per-point cost split of the continuation loop (cProfile + kernel replay).

Run: ``python -m bench.profile_branch`` (from the repository root).

Method: the SDOF Jenkins branch (m = 1, c = 0.02, k = 1, kt = 3, f_s = 1,
F = 0.5, Ω 0.5 → 3, H = 15) is traced ``repeats`` times; every compiled
kernel of the Newton and arc-length modules that Python calls is wrapped by
a timer (about 0.1 µs per call), which gives the compiled share; the rest
of the wall time of the same run is Python (since the branch is one
compiled ``arclength.trace`` call, that is the set-up: problem, scales,
first point, Branch) (``cProfile`` inflates Python time several-fold:
it finds the hot spots but cannot measure the split). The
compiled share is split by replaying the branch's own points: the mean cost
of one AFT call and of one residual-and-Jacobian assembly over the points,
times the number of evaluations the branch counted; what remains of the
compiled time is the linear solves and corrector bookkeeping.
"""

from __future__ import annotations

import time

import numpy as np

import hbmfric as hf
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.aft.schemes import aft_jenkins_events
from hbmfric.kernels.residuals.hbm import hbm_residual
from hbmfric.kernels.steps import arclength as _arclength
from hbmfric.kernels.steps import newton as _newton

OSC = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def _min_time(fn, *args, reps=200):
    best = np.inf
    for _ in range(5):
        t = time.perf_counter()
        for _ in range(reps):
            fn(*args)
        best = min(best, (time.perf_counter() - t) / reps)
    return best


def _kernel_time(force, harmonics, repeats):
    """Wall time and time inside the Newton-module kernels of the fastest of
    ``repeats`` runs, timed by wrapping each dispatcher the continuation
    calls."""
    spent = [0.0]
    originals = {}
    for module in (_newton, _arclength):
        for name in dir(module):
            obj = getattr(module, name)
            if hasattr(obj, "signatures"):
                originals[module, name] = obj

                def timed(*args, _f=obj):
                    t = time.perf_counter()
                    out = _f(*args)
                    spent[0] += time.perf_counter() - t
                    return out

                setattr(module, name, timed)
    try:
        best = (np.inf, np.inf)
        for _ in range(repeats):
            spent[0] = 0.0
            t = time.perf_counter()
            hf.frf(OSC, force, (0.5, 3.0), harmonics)
            wall = time.perf_counter() - t
            if wall < best[0]:
                best = (wall, spent[0])
    finally:
        for (module, name), obj in originals.items():
            setattr(module, name, obj)
    return best


def split(force: float = 0.5, harmonics: int = 15, repeats: int = 20) -> dict:
    """Cost split of one branch, seconds per branch and per point."""
    branch = hf.frf(OSC, force, (0.5, 3.0), harmonics)  # warm up
    walls = []
    for _ in range(repeats):
        t = time.perf_counter()
        branch = hf.frf(OSC, force, (0.5, 3.0), harmonics)
        walls.append(time.perf_counter() - t)
    wall_wrapped, kernel = _kernel_time(force, harmonics, repeats)
    # replay the branch's points through the kernels
    problem = HBMProblem(OSC, force, harmonics)
    hn, _, _, _, _, _, _, rows, _, inverse, _, derivative = problem.kernel_problem
    params = rows[0]
    n = problem.n_unknowns
    R = np.empty(n)
    J = np.empty((n, n + 1))
    F = np.empty(problem.n_coef)
    dF = np.empty((problem.n_coef, problem.n_coef))
    t_aft = []
    t_res = []
    for X, w in zip(branch.coefficients[:, 0], branch.omega, strict=True):
        y = np.concatenate((X, [w]))
        t_aft.append(
            _min_time(
                aft_jenkins_events, params, hn, X, inverse, derivative, F, dF, reps=20
            )
        )
        t_res.append(_min_time(hbm_residual, y, problem.kernel_problem, R, J, reps=20))
    evals = branch.newton_iterations
    aft = evals * float(np.mean(t_aft))
    assembly = evals * (float(np.mean(t_res)) - float(np.mean(t_aft)))
    wall = float(np.min(walls))
    out = {
        "points": len(branch),
        "evaluations": evals,
        "steps_rejected": branch.n_rejected,
        "wall_min_ms": 1e3 * wall,
        "wall_median_ms": 1e3 * float(np.median(walls)),
        "aft_ms": 1e3 * aft,
        "assembly_ms": 1e3 * assembly,
        "solve_and_corrector_ms": 1e3 * (kernel - aft - assembly),
        "python_ms": 1e3 * (wall_wrapped - kernel),
        "aft_us_per_call": 1e6 * float(np.mean(t_aft)),
    }
    return out


def main() -> None:
    out = split()
    for k, v in out.items():
        print(f"{k:>24}: {v:.4g}" if isinstance(v, float) else f"{k:>24}: {v}")
    pts = out["points"]
    print(
        "per point (µs): AFT {:.1f}, assembly {:.1f}, solves+corrector {:.1f}, "
        "Python {:.1f}".format(
            *(
                1e3 * out[k] / pts
                for k in (
                    "aft_ms",
                    "assembly_ms",
                    "solve_and_corrector_ms",
                    "python_ms",
                )
            )
        )
    )


if __name__ == "__main__":
    main()
