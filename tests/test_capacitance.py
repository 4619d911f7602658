"""The harmonic-block preconditioner corrected for the slipping coordinates
(issue 15, stop 30: ``kernels/linalg/capacitance.py``, Woodbury), against
a plain-NumPy reference: the inverse of the harmonic blocks plus the
chosen coordinates' coupling of harmonics (``numpy.linalg.solve``), and of
the bordered matrix; GMRES on it needs one iteration; a slip set larger
than the arrays corrects the largest couplings."""

import numpy as np
import pytest

import hbmfric.condensation as hc
from hbmfric.condensation import solver_arrays
from hbmfric.kernels.linalg import blocks, krylov
from hbmfric.kernels.linalg.capacitance import (
    capacitance_work,
    prepare_capacitance,
)


def _groups(n_coef, first):
    groups = [[0]] if first else []
    return groups + [[c, c + 1] for c in range(first, n_coef - 1, 2)]


def _joint_like(n_dof, n_coef, first, slipping, coupling, seed=0):
    """A matrix with the structure of a condensed HBM Jacobian: dense
    blocks within each harmonic (the linear part and every contact's
    harmonic-diagonal part) plus, for the ``slipping`` coordinates only,
    a dense coupling of that coordinate's coefficients of size
    ``coupling[i]``."""
    rng = np.random.default_rng(seed)
    n = n_dof * n_coef
    A = np.zeros((n, n))
    for cols in _groups(n_coef, first):
        idx = np.array([d * n_coef + c for d in range(n_dof) for c in cols])
        m = idx.size
        A[np.ix_(idx, idx)] = rng.standard_normal((m, m)) + 2.0 * m * np.eye(m)
    for d, size in zip(slipping, coupling, strict=True):
        s = slice(d * n_coef, (d + 1) * n_coef)
        A[s, s] += size * n_dof * rng.standard_normal((n_coef, n_coef))
    return A


def _reference(A, n_dof, n_coef, first, corrected):
    """Plain NumPy: the harmonic blocks of ``A`` plus, for the
    ``corrected`` coordinates, all of their own diagonal block."""
    M = np.zeros_like(A)
    for cols in _groups(n_coef, first):
        idx = np.array([d * n_coef + c for d in range(n_dof) for c in cols])
        M[np.ix_(idx, idx)] = A[np.ix_(idx, idx)]
    for d in corrected:
        s = slice(d * n_coef, (d + 1) * n_coef)
        M[s, s] = A[s, s]
    return M


def _corrected_apply(A, n_dof, n_coef, first, n_slip_max, v):
    m = A.shape[0]
    bl, pv, border, _, work = blocks.block_work(n_dof, n_coef, first, m, 4)
    correction = capacitance_work(n_dof, n_coef, first, n_slip_max)
    assert blocks.factor_blocks(A, n_dof, n_coef, first, bl, pv)
    count = prepare_capacitance(A, n_dof, n_coef, first, bl, pv, correction, work)
    assert blocks.prepare_border(
        A, n_dof, n_coef, first, bl, pv, correction, border, work
    )
    out = v.copy()
    blocks.apply_corrected(
        A, bl, pv, correction, n_dof, n_coef, first, border, out, work
    )
    return count, correction[1][:count].copy(), out


@pytest.mark.parametrize("first", [0, 1])
@pytest.mark.parametrize("bordered", [False, True])
def test_corrected_blocks_invert_the_matrix(first, bordered):
    """Three of seven coordinates slip: the corrected preconditioner is the
    inverse of the (bordered) matrix itself."""
    n_dof, n_coef = 7, 8 + first
    slipping = [1, 4, 6]
    A = _joint_like(n_dof, n_coef, first, slipping, [0.5, 2.0, 0.1], seed=3)
    n = A.shape[0]
    rng = np.random.default_rng(4)
    if bordered:
        B = np.zeros((n + 1, n + 1))
        B[:n, :n] = A
        B[:n, n] = rng.standard_normal(n)
        B[n, :] = rng.standard_normal(n + 1)
        A = B
    v = rng.standard_normal(A.shape[0])
    count, chosen, out = _corrected_apply(A, n_dof, n_coef, first, 5, v)
    assert count == 3 and list(chosen) == slipping
    ref = np.linalg.solve(A, v)
    assert np.max(np.abs(out - ref)) <= 1e-11 * np.max(np.abs(ref))
    # without the correction the blocks alone are far from it
    bl, pv, border, _, work = blocks.block_work(n_dof, n_coef, first, A.shape[0], 4)
    assert blocks.prepare_blocks(A, n_dof, n_coef, first, bl, pv, border, work)
    plain = v.copy()
    blocks.apply_preconditioner(A, bl, pv, n_dof, n_coef, first, border, plain, work)
    assert np.max(np.abs(plain - ref)) > 1e-3 * np.max(np.abs(ref))


def test_more_slipping_than_the_arrays_hold_corrects_the_largest():
    n_dof, n_coef, first = 6, 10, 0
    slipping = [0, 2, 3, 5]
    A = _joint_like(n_dof, n_coef, first, slipping, [0.2, 1.5, 0.05, 0.8], seed=8)
    v = np.random.default_rng(9).standard_normal(A.shape[0])
    count, chosen, out = _corrected_apply(A, n_dof, n_coef, first, 2, v)
    assert count == 2 and list(chosen) == [2, 5]
    M = _reference(A, n_dof, n_coef, first, [2, 5])
    ref = np.linalg.solve(M, v)
    assert np.max(np.abs(out - ref)) <= 1e-11 * np.max(np.abs(ref))


def test_nothing_slips_nothing_is_corrected():
    n_dof, n_coef, first = 5, 7, 1
    A = _joint_like(n_dof, n_coef, first, [], [], seed=2)
    v = np.random.default_rng(1).standard_normal(A.shape[0])
    count, _, out = _corrected_apply(A, n_dof, n_coef, first, 3, v)
    assert count == 0
    ref = np.linalg.solve(A, v)
    assert np.max(np.abs(out - ref)) <= 1e-11 * np.max(np.abs(ref))


def test_block_solve_on_corrected_blocks_needs_one_iteration(monkeypatch):
    """The corrector's solve: GMRES with the corrected blocks converges in
    one iteration (two products with the check) where the plain blocks
    need many; both solutions against NumPy's dense solve."""
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 0)
    n_dof, n_coef = 8, 10
    A = _joint_like(n_dof, n_coef, 0, [0, 7], [1.0, 1.0], seed=5)
    n = A.shape[0]
    rng = np.random.default_rng(6)
    B = np.zeros((n + 1, n + 1))
    B[:n, :n] = A
    B[:n, n] = rng.standard_normal(n)
    B[n, :] = rng.standard_normal(n + 1)
    b = rng.standard_normal(n + 1)
    ref = np.linalg.solve(B, b)
    products = {}
    for slip_max in (0, 4):
        monkeypatch.setattr(hc, "REUSE_SLIP_MAX", slip_max)
        solver = solver_arrays(n, True, n_dof, n_coef, 0)
        x = b.copy()
        assert blocks.block_solve(B, x, solver, n_dof, n_coef, 0, False, 1e-12)
        assert np.max(np.abs(x - ref)) <= 1e-9 * np.max(np.abs(ref))
        state = solver[3]
        assert state[krylov.REUSE_FACTORISATIONS] == 0
        products[slip_max] = state[krylov.REUSE_PRODUCTS]
    assert products[4] <= 2 < products[0]
