"""Issue 15, stop 24: where the lap joint's Newton iteration spends its
time (condensed residual, full residual, LU of the bordered Jacobian) at
H = 15, N = 10/40/100. ``python -m bench.lap_speed [N ...]``.

Timings are the minimum of repeated calls, after a warm-up call."""

from __future__ import annotations

import sys
import time

import numpy as np

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.hbm import HBMProblem

HZ = 2.0 * np.pi


def _best(fn, repeat=5):
    fn()
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return min(out)


def iteration_costs(n_pairs, harmonics=15, receptance="auto", full=True):
    s = hf.lap_joint(n_pairs)
    force = 1e-3 * 36e3
    omega = HZ * 162.0
    c = CondensedHBMProblem(s, force, harmonics, receptance=receptance)
    y = np.append(3.0 * c.linear_response(omega, "free"), omega)
    row = {"n_pairs": n_pairs, "n_dof": s.n_dof, "n_c": c.n_coordinates}
    row["cond_unknowns"] = c.n_unknowns
    row["cond_residual"] = _best(lambda: c.residual(y))
    _, J, _ = c.residual(y)
    A = np.vstack([J, np.ones((1, J.shape[1]))])
    import scipy.linalg as sl

    row["cond_lu"] = _best(lambda: sl.lu_factor(A))
    if full:
        f = HBMProblem(s, force, harmonics)
        X = c.full_coefficients(y[None])[0]
        yf = np.append(X.reshape(-1), omega)
        row["full_unknowns"] = f.n_unknowns
        row["full_residual"] = _best(lambda: f.residual(yf))
        _, Jf, _ = f.residual(yf)
        Af = np.vstack([Jf, np.ones((1, Jf.shape[1]))])
        row["full_lu"] = _best(lambda: sl.lu_factor(Af), repeat=3)
    return row


if __name__ == "__main__":
    import os

    print("load", os.getloadavg())
    for n in [int(a) for a in sys.argv[1:]] or [10, 40]:
        print(iteration_costs(n), flush=True)
