"""Issue 15, stop 24: the lap joint's speed at H = 15.

``python -m bench.lap_speed costs [N ...]``: where one Newton iteration
spends its time (condensed: receptance part of the residual, AFT of the
contacts, LU of the bordered Jacobian by :func:`hbmfric.kernels.linalg.
lu_factor`, one GMRES product of the kept-factor solve, the nonzero
share of the Jacobian, and one solve by GMRES on the harmonic blocks with
its preconditioner's cost and iterations, stop 26; the residual with the
high poles summed as a series planned for 185 Hz and how many poles stay
summed term by term, stop 27; full: residual, LU), at
three times the free linear response
at 162 Hz, Fex = 36 N. Minimum of repeated calls after a warm-up call.

``python -m bench.lap_speed branch N [condense ...]``: one branch
(``hf.frf``, H = 15, ``max_step = 0.05``) over the figure's 125-185 Hz at
Fex/P = 1e-3 (36 N; the first bending resonance goes from stuck, 167 Hz,
into microslip, peak at 162 Hz, and back), per setting of ``condense``
(``state``, ``direct``, ``false``; ``state-plain``: condensed, a fresh LU
of the Jacobian at every Newton iteration and a dense LU in the truncation
estimate, the solvers before stop 25; ``state-factors``: the corrector
preconditioned by kept LU factors, stop 25),
interleaved, warm (N = 10: after one untimed run of each; larger N: the
first run is timed after a short warm-up branch over 160-161 Hz). Wall
and CPU seconds (the CPU time of the process depends less on the load),
and the counters of the corrector's iterative solves (stop 30).

One BLAS thread (as the other bench scripts: threaded OpenBLAS on the
shared 2 cores makes small products 100 times slower under load).
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
from hbmfric.hbm import HBMProblem  # noqa: E402
from hbmfric.kernels.linalg import krylov  # noqa: E402
from hbmfric.kernels.linalg.blocks import (  # noqa: E402
    block_work,
    gmres_blocks,
    prepare_blocks,
)
from hbmfric.kernels.linalg.krylov import sparse_matvec, sparse_rows  # noqa: E402
from hbmfric.kernels.linalg.lu import lu_factor, lu_solve  # noqa: E402
from hbmfric.kernels.residuals.condensed import condensed_contact_forces  # noqa: E402

HZ = 2.0 * np.pi
FORCE = 36.0  # N: Fex/P = 1e-3 of the 36 kN preload
BAND = (125.0, 185.0)  # Hz


def _best(fn, repeat=5):
    fn()
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return min(out)


def _lu_time(J, repeat=5):
    A0 = np.vstack([J, np.ones((1, J.shape[1]))])
    piv = np.empty(A0.shape[0], dtype=np.int64)

    def run():
        A = A0.copy()
        lu_factor(A, piv)

    copy = _best(lambda: A0.copy(), repeat)
    return _best(run, repeat) - copy


def _product_times(J, repeat=5):
    """One GMRES product of the kept-factor solve (stop 25): the bordered
    matrix's nonzeros gathered once per solve (``sparse_rows``), then per
    product a triangular solve with kept factors and a sparse product."""
    A = np.vstack([J, np.ones((1, J.shape[1]))])
    F = A.copy()
    piv = np.empty(A.shape[0], dtype=np.int64)
    lu_factor(F, piv)
    x = np.ones(A.shape[0])
    out = np.empty(A.shape[0])
    rows = sparse_rows(A)
    return {
        "cond_sparse_rows_ms": 1e3 * _best(lambda: sparse_rows(A), repeat),
        "cond_product_ms": 1e3
        * _best(
            lambda: (lu_solve(F, piv, x), sparse_matvec(*rows, x, out)),
            repeat,
        ),
    }


def _block_times(J, n_c, n_coef, repeat=5):
    """One corrector solve by GMRES on the harmonic blocks (stop 26): the
    preconditioner built (one LU of order ``2 n_c`` per harmonic), then
    the whole solve of the bordered system, and its iteration count."""
    A = np.vstack([J, np.ones((1, J.shape[1]))])
    m = A.shape[0]
    arrays = block_work(n_c, n_coef, 0, m, 60)
    blocks, pivots, border, _, work = arrays
    b = np.ones(m)
    x = np.empty(m)
    status, iterations = gmres_blocks(A, b, x, n_c, n_coef, 0, 1e-10, arrays)
    return {
        "blocks_prepare_ms": 1e3
        * _best(
            lambda: prepare_blocks(A, n_c, n_coef, 0, blocks, pivots, border, work),
            repeat,
        ),
        "blocks_solve_ms": 1e3
        * _best(lambda: gmres_blocks(A, b, x, n_c, n_coef, 0, 1e-10, arrays), repeat),
        "blocks_iterations": iterations if status == 0 else -1,
    }


def iteration_costs(n_pairs, harmonics=15, full=True):
    s = hf.lap_joint(n_pairs)
    omega = HZ * 162.0
    row = {"n_pairs": n_pairs, "n_dof": s.n_dof}
    problems = {}
    for rec in ("state", "direct"):
        t = time.perf_counter()
        c = problems[rec] = CondensedHBMProblem(s, FORCE, harmonics, receptance=rec)
        row[f"{rec}_setup_s"] = time.perf_counter() - t
        y = np.append(3.0 * c.linear_response(omega, "free"), omega)
        row["n_c"] = c.n_coordinates
        row["cond_unknowns"] = c.n_unknowns
        row[f"{rec}_residual_ms"] = 1e3 * _best(lambda c=c, y=y: c.residual(y))
    # stop 27: the high poles summed once as a series (planned for the
    # figure's band, as hf.frf does)
    planned = problems["state"].with_harmonics(harmonics)
    planned.plan_band(HZ * BAND[1])
    kp = planned.kernel_problem
    row["series_low_poles"] = int(kp.state_low.size)
    row["series_poles"] = int(kp.state_poles.size)
    row["series_residual_ms"] = 1e3 * _best(lambda: planned.residual(y))
    F = np.empty((1, c.n_unknowns))
    row["aft_ms"] = 1e3 * _best(
        lambda: condensed_contact_forces(y[None], c.kernel_problem, F)
    )
    # every contact in gross slip: 30 times the amplitude
    y30 = np.append(30.0 * y[:-1], y[-1])
    row["aft_slip_ms"] = 1e3 * _best(
        lambda: condensed_contact_forces(y30[None], c.kernel_problem, F)
    )
    row["direct_residual_slip_ms"] = 1e3 * _best(lambda: c.residual(y30))
    st = problems["state"]
    row["state_residual_slip_ms"] = 1e3 * _best(lambda: st.residual(y30))
    _, J, _ = c.residual(y)
    row["cond_lu_ms"] = 1e3 * _lu_time(J)
    row["cond_nonzero_share"] = float(np.count_nonzero(J)) / J.size
    row.update(_product_times(J))
    row.update(_block_times(J, c.n_coordinates, c.n_coef))
    if full:
        f = HBMProblem(s, FORCE, harmonics)
        X = c.full_coefficients(y[None])[0]
        yf = np.append(X.reshape(-1), omega)
        row["full_unknowns"] = f.n_unknowns
        row["full_residual_ms"] = 1e3 * _best(lambda: f.residual(yf))
        _, Jf, _ = f.residual(yf)
        row["full_lu_ms"] = 1e3 * _lu_time(Jf, repeat=3)
    return row


def branch(n_pairs, condense, harmonics=15, band=BAND):
    """One branch; ``condense`` is a value of ``hf.frf``'s option, with the
    suffix ``-plain`` a condensed problem that factors its Jacobian at every
    Newton iteration and its truncation probe by a dense LU (the iterative
    solves of stops 25 and 26 off), with ``-factors`` one whose corrector
    is preconditioned by kept LU factors (stop 25) instead of the harmonic
    blocks (stop 26); suffixes combine: ``-keep``, the harmonic blocks
    kept over matrices while GMRES needs at most 3 more products (stop 27;
    the default keeps them while it needs at most 1 more since stop 29);
    ``-exact``, every pole of
    the complex modes summed at every harmonic, no series of the high poles
    (before stop 27)."""
    s = hf.lap_joint(n_pairs)
    setting, *suffixes = condense.split("-")
    kw = {"condense": False} if setting == "false" else {"condense": setting}
    omega = (HZ * band[0], HZ * band[1])
    threshold = hc.REUSE_MIN_UNKNOWNS
    preconditioner = hc.REUSE_PRECONDITIONER
    keep = hc.REUSE_KEEP_BLOCKS
    margin = hc.SERIES_MARGIN
    if "plain" in suffixes:
        hc.REUSE_MIN_UNKNOWNS = 2**62
    if "factors" in suffixes:
        hc.REUSE_PRECONDITIONER = "factors"
    if "keep" in suffixes:
        hc.REUSE_KEEP_BLOCKS = 3
    if "exact" in suffixes:
        hc.SERIES_MARGIN = np.inf  # no series planned: every pole summed
    made = []  # the solver arrays of the branch's problems: their counters
    solver_arrays = hc.solver_arrays

    def keep_arrays(*args, **kwargs):
        arrays = solver_arrays(*args, **kwargs)
        made.append(arrays)
        return arrays

    hc.solver_arrays = keep_arrays
    t = time.perf_counter()
    cpu = time.process_time()
    try:
        b = hf.frf(s, FORCE, omega, harmonics, max_step=0.05, **kw)
    finally:
        hc.solver_arrays = solver_arrays
        hc.REUSE_MIN_UNKNOWNS = threshold
        hc.REUSE_PRECONDITIONER = preconditioner
        hc.REUSE_KEEP_BLOCKS = keep
        hc.SERIES_MARGIN = margin
    elapsed = time.perf_counter() - t
    cpu = time.process_time() - cpu
    a = b.amplitude(harmonic=1, dof="drive")
    i = int(np.argmax(a))
    errors = b.curve_errors
    return {
        "n_pairs": n_pairs,
        "condense": condense,
        "seconds": round(elapsed, 2),
        "cpu_seconds": round(cpu, 2),
        "points": len(b.omega),
        "complete": b.complete,
        "peak_m_per_N": a[i] / FORCE,
        "peak_Hz": b.omega[i] / HZ,
        "curve_error_max": float(np.max(errors)) if errors is not None else None,
        "load": os.getloadavg()[0],
        **_solver_counts(made),
    }


def _solver_counts(made):
    """Counters of the corrector's iterative solves summed over the
    branch's problems (stop 30): GMRES solves and products, harmonic-block
    builds and their corrections for the slipping coordinates, dense
    fallbacks."""
    states = [a[3] for a in made if a[0].shape[0] > 0]
    names = {
        "solves": krylov.REUSE_SOLVES,
        "products": krylov.REUSE_PRODUCTS,
        "block_builds": krylov.REUSE_BLOCK_BUILDS,
        "corrections": krylov.REUSE_CAPACITANCE_BUILDS,
        "fallbacks": krylov.REUSE_FALLBACKS,
    }
    return {k: int(sum(st[i] for st in states)) for k, i in names.items()}


if __name__ == "__main__":
    import warnings

    warnings.simplefilter("ignore")
    print("load", os.getloadavg(), flush=True)
    mode, *args = sys.argv[1:] or ["costs"]
    if mode == "costs":
        for n in [int(a) for a in args] or [10, 40, 100]:
            print(iteration_costs(n, full=n <= 100), flush=True)
    else:
        n = int(args[0])
        settings = args[1:] or ["state", "false"]
        for setting in settings:  # warm-up (compilation, modes cache)
            branch(n, setting, band=BAND if n <= 10 else (160.0, 161.0))
        for _ in range(2 if n <= 10 else 1):
            for setting in settings:
                print(branch(n, setting), flush=True)
