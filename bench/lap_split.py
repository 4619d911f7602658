"""Issue 15, stop 31: unit costs of one Newton iteration of the lap joint's
corrector at N pairs (H = 15), to multiply with a branch's counters.

``python -m bench.lap_split N``: CPU ms (least of repeats) of the residual
kernel (and of zeroing its dense Jacobian alone), the passes of the
corrector over the dense bordered matrix (row equilibration,
``rounding_floor``, the nonzero gather; and stop 31's same passes on the
Jacobian's pattern, :mod:`hbmfric.kernels.linalg.pattern`), a GMRES
product on the harmonic blocks (sparse product + preconditioner), a
block factorisation with its correction, at 162 Hz, 3 times the free
linear response (some contacts slip) and 30 times (all slip).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import hbmfric as hf  # noqa: E402
import hbmfric.condensation as hc  # noqa: E402
from hbmfric.condensation import CondensedHBMProblem  # noqa: E402
from hbmfric.kernels.linalg.blocks import (  # noqa: E402
    _prepare_corrected,
    apply_corrected,
)
from hbmfric.kernels.linalg.krylov import sparse_matvec, sparse_rows  # noqa: E402
from hbmfric.kernels.linalg.pattern import (  # noqa: E402
    append_last_row,
    equilibrate_pattern,
    pattern_size,
    pattern_term_sum,
)
from hbmfric.kernels.residuals.condensed import condensed_residual  # noqa: E402
from hbmfric.kernels.steps.newton import equilibrate_rows, rounding_floor  # noqa: E402

HZ = 2.0 * np.pi


def _best(fn, repeat=7, inner=3):
    fn()
    out = []
    for _ in range(repeat):
        t = time.process_time()
        for _ in range(inner):
            fn()
        out.append((time.process_time() - t) / inner)
    return 1e3 * min(out)


def unit_costs(n_pairs, harmonics=15, factor=3.0):
    s = hf.lap_joint(n_pairs)
    c = CondensedHBMProblem(s, 36.0, harmonics, receptance="state")
    c = c.with_harmonics(harmonics)
    c.plan_band(HZ * 185.0)
    kp = c.kernel_problem
    omega = HZ * 162.0
    y = np.append(factor * c.linear_response(omega, "free"), omega)
    n = c.n_unknowns
    m = n + 1
    R = np.empty(n)
    J = np.empty((n, m))
    row = {"n_pairs": n_pairs, "factor": factor, "n_c": c.n_coordinates, "m": m}
    row["residual_ms"] = _best(lambda: condensed_residual(y, kp, R, J))
    row["nonzero_share"] = float(np.count_nonzero(J)) / J.size
    J0 = J.copy()
    row["zero_J_ms"] = _best(lambda: J.fill(0.0))
    J[:] = J0
    scale = np.abs(y) + 1e-9
    A = np.empty((m, m))
    rows = np.empty(m)
    row["equilibrate_ms"] = _best(lambda: equilibrate_rows(J, scale, A, rows))
    A[n, :] = 1.0 / np.sqrt(m)
    row["rounding_floor_ms"] = _best(lambda: rounding_floor(J, y))
    row["gather_ms"] = _best(lambda: sparse_rows(A))
    st, co, va = sparse_rows(A)
    # stop 31: the same rows, floor and nonzeros on the Jacobian's pattern
    n_c, n_coef = c.n_coordinates, c.n_coef
    room = pattern_size(n_c, n_coef, 0)
    ps = np.zeros(m + 1, dtype=np.int64)
    pc = np.zeros(room, dtype=np.int64)
    pv = np.zeros(room)
    B = A.copy()

    def pattern_rows():
        equilibrate_pattern(J, scale, B, rows, n_c, n_coef, 0, ps, pc, pv)
        append_last_row(B, ps, pc, pv)

    row["pattern_rows_and_nonzeros_ms"] = _best(pattern_rows)
    row["pattern_term_sum_ms"] = _best(
        lambda: pattern_term_sum(J, y, n_c, n_coef, 0), inner=10
    )
    row["pattern_equal"] = bool(
        np.array_equal(ps, st)
        and np.array_equal(pc[: st[-1]], co)
        and np.array_equal(pv[: st[-1]], va)
    )
    x = np.ones(m)
    out = np.empty(m)
    row["matvec_ms"] = _best(lambda: sparse_matvec(st, co, va, x, out), inner=20)
    solver = hc.solver_arrays(n, True, c.n_coordinates, c.n_coef, 0)
    _, _, _, state, blocks, pivots, border, work, correction = solver[:9]
    row["block_build_ms"] = _best(
        lambda: _prepare_corrected(A, c.n_coordinates, c.n_coef, 0, solver)
    )
    row["slipping_corrected"] = int(correction[0][0])
    u = np.ones(m)
    row["precondition_ms"] = _best(
        lambda: apply_corrected(
            A, blocks, pivots, correction, c.n_coordinates, c.n_coef, 0, border, u, work
        ),
        inner=20,
    )
    row["load"] = os.getloadavg()[0]
    return row


if __name__ == "__main__":
    import warnings

    warnings.simplefilter("ignore")
    for a in sys.argv[1:] or ["40"]:
        for factor in (3.0, 30.0):
            print(unit_costs(int(a), factor=factor), flush=True)
