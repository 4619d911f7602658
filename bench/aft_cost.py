"""Cost of one corrector iteration of P1 split into its parts, timed from
compiled drivers (issue 18, stop 29).

Run: ``python -m bench.aft_cost [--forces 2] [--harmonics 21,31]`` from the
repository root. For each force and highest harmonic, a fixed-H branch of P1
is traced once; then compiled loops call each part on every point of that
branch (20 passes, least CPU time of 7 repeats, per call):

- ``residual``: :func:`hbmfric.kernels.residuals.hbm.hbm_residual` (linear
  part, AFT, Jacobian assembly),
- ``aft``: :func:`hbmfric.kernels.aft.schemes.aft_jenkins_events` alone,
- ``samples``: its samples of ``u`` and ``u'``; ``+ reversals``: the
  samples and the reversal search,
- ``bordered LU``: equilibration of the bordered matrix, its LU
  factorisation and one solve (what the corrector does per iteration; the
  tangent is one more solve).

Timing from Python would measure the call overhead of a dispatcher (a few
µs), not the kernels.

P1: m = 1, c = 0.02, k = 1, Jenkins kt = 3, f_s = 1, Ω 0.5-3 rad/s.
"""

# ruff: noqa: E402  (BLAS threads are set before NumPy is imported)
from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import time
import warnings

import numpy as np
from numba import njit

from hbmfric.kernels.aft import schemes
from hbmfric.kernels.linalg.lu import lu_factor, lu_solve
from hbmfric.kernels.residuals.hbm import hbm_residual
from hbmfric.kernels.steps.newton import equilibrate_rows


@njit
def _aft_loop(params, hn, Xs, inverse, derivative, F, dF, passes):
    s = 0
    for _ in range(passes):
        for p in range(Xs.shape[0]):
            s += schemes.aft_jenkins_events(
                params, hn, Xs[p], inverse, derivative, F, dF
            )
    return s


@njit
def _search_loop(hn, Xs, inverse, derivative, passes, reversals):
    n = inverse.shape[0]
    u = np.empty(n)
    v = np.empty(n)
    X2 = np.empty(Xs.shape[1])
    cap = 4 * hn[-1] + 8
    theta = np.empty(cap)
    value = np.empty(cap)
    stack = np.empty((schemes._MAX_DEPTH + 2, 5))
    s = 0.0
    for _ in range(passes):
        for p in range(Xs.shape[0]):
            schemes._samples_uv(hn, Xs[p], inverse, derivative, u, v)
            s += u[0]
            if reversals:
                b2, b3 = schemes._derivative_bounds(hn, Xs[p], X2)
                s += schemes._find_reversals(
                    hn, Xs[p], X2, inverse, u, v, b2, b3, theta, value, stack
                )
    return s


@njit
def _residual_loop(Ys, problem, R, J, passes):
    s = 0
    for _ in range(passes):
        for p in range(Ys.shape[0]):
            s += hbm_residual(Ys[p], problem, R, J)
    return s


@njit
def _lu_loop(Ys, problem, R, J, scale, passes):
    n = J.shape[0]
    A = np.empty((n + 1, n + 1))
    piv = np.empty(n + 1, np.int64)
    b = np.empty(n + 1)
    s = 0.0
    for p in range(Ys.shape[0]):
        hbm_residual(Ys[p], problem, R, J)
        for _ in range(passes):
            equilibrate_rows(J, scale, A, b)
            for j in range(n + 1):
                A[n, j] = 1.0 / np.sqrt(n + 1.0)
            lu_factor(A, piv)
            lu_solve(A, piv, b)
            s += b[0]
    return s


def _least(f, *args, repeats: int = 7) -> float:
    best = float("inf")
    for _ in range(repeats):
        c = time.process_time()
        f(*args)
        best = min(best, time.process_time() - c)
    return best


def split(force: float, harmonics: int, passes: int = 20) -> dict:
    """Per-call CPU time (µs) of each part on the points of P1's fixed-H
    branch at ``force``."""
    import hbmfric as hf
    from hbmfric.hbm import HBMProblem

    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(osc, force, (0.5, 3.0), harmonics)
    kp = HBMProblem(osc, force, harmonics).kernel_problem
    hn, inverse, derivative = kp.harmonic_numbers, kp.inverse, kp.derivative
    Xs = np.ascontiguousarray(branch.coefficients[:, 0, :])
    Ys = np.ascontiguousarray(np.column_stack([Xs, branch.omega]))
    n_coef = Xs.shape[1]
    F = np.empty(n_coef)
    dF = np.empty((n_coef, n_coef))
    R = np.empty(n_coef)
    J = np.empty((n_coef, n_coef + 1))
    scale = np.ones(n_coef + 1)
    params = np.ascontiguousarray(kp.law_params[0][:2])
    parts = {
        "residual": (_residual_loop, (Ys, kp, R, J)),
        "aft": (_aft_loop, (params, hn, Xs, inverse, derivative, F, dF)),
        "samples": (_search_loop, (hn, Xs, inverse, derivative)),
        "+ reversals": (_search_loop, (hn, Xs, inverse, derivative)),
        "bordered LU": (_lu_loop, (Ys, kp, R, J, scale)),
    }
    row = {"force": force, "H": harmonics, "n_coef": n_coef, "points": len(Xs)}
    for name, (f, args) in parts.items():
        extra = (name == "+ reversals",) if f is _search_loop else ()
        f(*args, 1, *extra)
        row[name] = 1e6 * _least(f, *args, passes, *extra) / (passes * len(Xs))
    # the bordered LU loop also evaluates the residual once per point
    return row


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--forces", default="2")
    p.add_argument("--harmonics", default="21,31")
    args = p.parse_args(argv)
    print(f"load {os.getloadavg()[0]:.1f}")
    head = ("residual", "aft", "samples", "+ reversals", "bordered LU")
    print("| F | H | n_coef | points | " + " | ".join(head) + " |")
    print("|---" * (4 + len(head)) + "|")
    for force in (float(f) for f in args.forces.split(",")):
        for h in (int(x) for x in args.harmonics.split(",")):
            r = split(force, h)
            cells = " | ".join(f"{r[k]:.2f}" for k in head)
            print(f"| {force:g} | {h} | {r['n_coef']} | {r['points']} | {cells} |")
    print(f"load {os.getloadavg()[0]:.1f} (µs per call, CPU, least of 7)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
