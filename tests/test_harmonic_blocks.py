"""GMRES preconditioned by the harmonic blocks of a harmonic-balance
Jacobian (issue 15, stop 26: ``kernels/linalg/blocks.py``), used by the
corrector of large condensed problems (``kernels/steps/newton.py:
bordered_solve``) and by the probe solve of their truncation estimate
(``kernels/steps/truncation.py: probe_solve``). Checked against NumPy's
dense solve, against the dense path on the lap joint, and for loud
failure; the residual's symmetric product and Gauss-Jordan inverse against
NumPy."""

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
import hbmfric.condensation as hc
from hbmfric.condensation import CondensedHBMProblem, solver_arrays
from hbmfric.continuation.accuracy import truncation_errors
from hbmfric.kernels.linalg import blocks, krylov
from hbmfric.kernels.linalg.products import symmetric_matmul
from hbmfric.kernels.residuals.condensed import _invert, _rounding_level

HZ = 2.0 * math.pi


def _harmonic_matrix(n_dof, n_coef, first, coupling, seed=0):
    """A matrix with the structure of a harmonic-balance Jacobian: dense
    blocks within each harmonic (a stiff, well-conditioned linear part),
    plus per DOF a dense coupling of its coefficients of relative size
    ``coupling`` (the contacts)."""
    rng = np.random.default_rng(seed)
    n = n_dof * n_coef
    A = np.zeros((n, n))
    groups = [[0]] if first else []
    groups += [[c, c + 1] for c in range(first, n_coef - 1, 2)]
    for cols in groups:
        idx = np.array([d * n_coef + c for d in range(n_dof) for c in cols])
        m = idx.size
        A[np.ix_(idx, idx)] = rng.standard_normal((m, m)) + 2.0 * m * np.eye(m)
    for d in range(n_dof):
        s = slice(d * n_coef, (d + 1) * n_coef)
        A[s, s] += coupling * n_dof * rng.standard_normal((n_coef, n_coef))
    return A


def _block_part(A, n_dof, n_coef, first):
    P = np.zeros_like(A)
    groups = [[0]] if first else []
    groups += [[c, c + 1] for c in range(first, n_coef - 1, 2)]
    for cols in groups:
        idx = np.array([d * n_coef + c for d in range(n_dof) for c in cols])
        P[np.ix_(idx, idx)] = A[np.ix_(idx, idx)]
    return P


@pytest.mark.parametrize("first", [0, 1])
@pytest.mark.parametrize("bordered", [False, True])
def test_gmres_with_harmonic_blocks_matches_numpy(first, bordered):
    n_dof, n_coef = 6, 8 + first
    A = _harmonic_matrix(n_dof, n_coef, first, 0.3)
    n = A.shape[0]
    rng = np.random.default_rng(1)
    if bordered:
        B = np.zeros((n + 1, n + 1))
        B[:n, :n] = A
        B[:n, n] = rng.standard_normal(n)
        B[n, :] = rng.standard_normal(n + 1)
        A = B
    m = A.shape[0]
    b = rng.standard_normal(m)
    x = np.empty(m)
    arrays = blocks.block_work(n_dof, n_coef, first, m, 60)
    status, iterations = blocks.gmres_blocks(
        A, b, x, n_dof, n_coef, first, 1e-12, arrays
    )
    assert status == krylov.GMRES_CONVERGED
    assert 1 <= iterations < 60
    ref = np.linalg.solve(A, b)
    assert np.max(np.abs(x - ref)) <= 1e-10 * np.max(np.abs(ref))


@pytest.mark.parametrize("first", [0, 1])
def test_harmonic_blocks_invert_the_block_part(first):
    """The preconditioner is the exact inverse of the harmonic blocks (and,
    bordered, of the blocks with the last row and column)."""
    n_dof, n_coef = 5, 6 + first
    A = _harmonic_matrix(n_dof, n_coef, first, 0.5, seed=3)
    n = A.shape[0]
    P = _block_part(A, n_dof, n_coef, first)
    bl, pv, border, _, work = blocks.block_work(n_dof, n_coef, first, n, 4)
    assert blocks.prepare_blocks(A, n_dof, n_coef, first, bl, pv, border, work)
    v = np.random.default_rng(2).standard_normal(n)
    out = v.copy()
    blocks.apply_preconditioner(A, bl, pv, n_dof, n_coef, first, border, out, work)
    assert np.allclose(out, np.linalg.solve(P, v), rtol=0, atol=1e-12)
    rng = np.random.default_rng(4)
    B = np.zeros((n + 1, n + 1))
    B[:n, :n] = A
    B[:n, n] = rng.standard_normal(n)
    B[n, :] = rng.standard_normal(n + 1)
    M = B.copy()
    M[:n, :n] = P
    bl, pv, border, _, work = blocks.block_work(n_dof, n_coef, first, n + 1, 4)
    assert blocks.prepare_blocks(B, n_dof, n_coef, first, bl, pv, border, work)
    v = rng.standard_normal(n + 1)
    out = v.copy()
    blocks.apply_preconditioner(B, bl, pv, n_dof, n_coef, first, border, out, work)
    assert np.allclose(out, np.linalg.solve(M, v), rtol=0, atol=1e-12)


def test_gmres_with_harmonic_blocks_reports_what_it_cannot_do():
    n_dof, n_coef = 4, 6
    A = _harmonic_matrix(n_dof, n_coef, 0, 0.3)
    n = A.shape[0]
    x = np.empty(n)
    b = np.ones(n)
    # a non-finite right-hand side
    bad = b.copy()
    bad[3] = np.nan
    arrays = blocks.block_work(n_dof, n_coef, 0, n, 30)
    status, _ = blocks.gmres_blocks(A, bad, x, n_dof, n_coef, 0, 1e-10, arrays)
    assert status == krylov.GMRES_NOT_FINITE
    # a singular harmonic block: no preconditioner, no iteration
    S = A.copy()
    S[:, 0] = 0.0
    S[0, :] = 0.0
    status, k = blocks.gmres_blocks(S, b, x, n_dof, n_coef, 0, 1e-10, arrays)
    assert status == krylov.GMRES_NOT_CONVERGED and k == 0
    # too few iterations for a strong coupling of the harmonics
    C = _harmonic_matrix(n_dof, n_coef, 0, 3.0)
    short = blocks.block_work(n_dof, n_coef, 0, n, 2)
    status, k = blocks.gmres_blocks(C, b, x, n_dof, n_coef, 0, 1e-12, short)
    assert status == krylov.GMRES_NOT_CONVERGED and k <= 2
    # a NaN inside the matrix
    N = A.copy()
    N[2, 7] = np.nan
    status, _ = blocks.gmres_blocks(N, b, x, n_dof, n_coef, 0, 1e-10, arrays)
    assert status != krylov.GMRES_CONVERGED


def _solver(n_dof, n_coef, k_max=None):
    """Work arrays of the corrector's block solve for a bordered system."""
    n = n_dof * n_coef
    arrays = solver_arrays(n, True, n_dof, n_coef, 0)
    if k_max is not None:
        arrays = (*arrays[:2], np.zeros((k_max + 1, n + 1)), *arrays[3:])
    return arrays


def _bordered(n_dof, n_coef, coupling, seed=0):
    A = _harmonic_matrix(n_dof, n_coef, 0, coupling, seed)
    n = A.shape[0]
    rng = np.random.default_rng(seed + 10)
    B = np.zeros((n + 1, n + 1))
    B[:n, :n] = A
    B[:n, n] = rng.standard_normal(n)
    B[n, :] = rng.standard_normal(n + 1)
    return B


def test_block_solve_falls_back_to_a_dense_lu_and_keeps_it_for_the_tangent(
    monkeypatch,
):
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 0)
    n_dof, n_coef = 6, 10
    solver = _solver(n_dof, n_coef)
    state = solver[3]
    assert state[krylov.REUSE_MODE] == krylov.REUSE_MODE_BLOCKS
    A = _bordered(n_dof, n_coef, 0.3)
    m = A.shape[0]
    b = np.random.default_rng(5).standard_normal(m)
    x = b.copy()
    assert blocks.block_solve(A, x, solver, n_dof, n_coef, 0, False)
    assert np.allclose(A @ x, b, rtol=0, atol=1e-9 * np.abs(b).max())
    assert state[krylov.REUSE_SOLVES] == 1 and state[krylov.REUSE_FACTORISATIONS] == 0
    assert state[krylov.REUSE_PREPARED] == blocks.PREPARED_BLOCKS
    # again with the same matrix (the tangent): the prepared blocks serve
    e = np.zeros(m)
    e[-1] = 1.0
    t = e.copy()
    assert blocks.block_solve(A, t, solver, n_dof, n_coef, 0, True)
    assert np.allclose(t, np.linalg.solve(A, e), rtol=0, atol=1e-9)
    # a strong coupling and a two-vector basis: GMRES fails, a dense LU
    # solves, counted, and serves the tangent after it (the blocks not
    # corrected for the coupling, which would make GMRES exact)
    monkeypatch.setattr(hc, "REUSE_SLIP_MAX", 0)
    short = _solver(n_dof, n_coef, k_max=2)
    C = _bordered(n_dof, n_coef, 4.0, seed=1)
    x = b.copy()
    assert blocks.block_solve(C, x, short, n_dof, n_coef, 0, False)
    assert np.allclose(x, np.linalg.solve(C, b), rtol=0, atol=1e-9)
    st = short[3]
    assert st[krylov.REUSE_FALLBACKS] == 1 and st[krylov.REUSE_FACTORISATIONS] == 1
    assert st[krylov.REUSE_PREPARED] == blocks.PREPARED_DENSE
    t = e.copy()
    assert blocks.block_solve(C, t, short, n_dof, n_coef, 0, True)
    assert st[krylov.REUSE_FACTORISATIONS] == 1  # no new factorisation
    assert np.allclose(t, np.linalg.solve(C, e), rtol=0, atol=1e-9)
    # a singular matrix is reported
    S = A.copy()
    S[:, 3] = 0.0
    S[3, :] = 0.0
    x = b.copy()
    assert not blocks.block_solve(S, x, solver, n_dof, n_coef, 0, False)


def test_block_solve_keeps_blocks_for_nearby_matrices(monkeypatch):
    """Stop 27: the blocks factored for one matrix precondition the next
    ones (a Newton iteration, the next point) while GMRES needs at most
    ``REUSE_KEEP_BLOCKS`` products more; every solution against NumPy's
    dense solve; a matrix far from the kept blocks gets its own (once
    GMRES on the kept ones fails, before any dense LU)."""
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 0)
    monkeypatch.setattr(hc, "REUSE_KEEP_BLOCKS", 3)
    n_dof, n_coef = 6, 10
    solver = _solver(n_dof, n_coef)
    state = solver[3]
    A = _bordered(n_dof, n_coef, 0.05)
    m = A.shape[0]
    rng = np.random.default_rng(11)
    b = rng.standard_normal(m)
    for _ in range(6):
        # a small change of every entry and of the border, as between
        # Newton iterations
        Ai = A + 1e-4 * rng.standard_normal(A.shape) * np.abs(A).max()
        x = b.copy()
        assert blocks.block_solve(Ai, x, solver, n_dof, n_coef, 0, False)
        assert np.allclose(x, np.linalg.solve(Ai, b), rtol=0, atol=1e-8)
    assert state[krylov.REUSE_SOLVES] == 6
    assert state[krylov.REUSE_BLOCK_BUILDS] < 6
    assert state[krylov.REUSE_FACTORISATIONS] == 0
    # a different matrix: kept blocks useless within the Krylov basis,
    # its own blocks solve it, no dense LU
    short = _solver(n_dof, n_coef, k_max=8)
    st = short[3]
    x = b.copy()
    assert blocks.block_solve(A, x, short, n_dof, n_coef, 0, False)
    builds = st[krylov.REUSE_BLOCK_BUILDS]
    C = _bordered(n_dof, n_coef, 0.05, seed=4)
    x = b.copy()
    assert blocks.block_solve(C, x, short, n_dof, n_coef, 0, False)
    assert np.allclose(x, np.linalg.solve(C, b), rtol=0, atol=1e-8)
    assert st[krylov.REUSE_BLOCK_BUILDS] == builds + 1
    assert st[krylov.REUSE_FACTORISATIONS] == 0
    # keeping switched off: the blocks of every matrix
    monkeypatch.setattr(hc, "REUSE_KEEP_BLOCKS", -1)
    every = _solver(n_dof, n_coef)
    for _ in range(3):
        x = b.copy()
        assert blocks.block_solve(A, x, every, n_dof, n_coef, 0, False)
    assert every[3][krylov.REUSE_BLOCK_BUILDS] == 3


def test_symmetric_product_and_inverse_match_numpy():
    rng = np.random.default_rng(7)
    n_c, n_s = 9, 23
    L = rng.standard_normal((n_c, n_s)) + 1j * rng.standard_normal((n_c, n_s))
    c = rng.standard_normal(n_s) + 1j * rng.standard_normal(n_s)
    scaled = np.ascontiguousarray(L * c)
    G = np.empty((n_c, n_c), dtype=complex)
    symmetric_matmul(scaled, np.ascontiguousarray(L.T), G)
    ref = (L * c) @ L.T
    assert np.allclose(G, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    assert np.array_equal(G, G.T)
    # Gauss-Jordan with pivoting (a zero leading entry forces a swap)
    G[0, 0] = 0.0
    D = np.empty_like(G)
    work = np.empty_like(G)
    assert _invert(G, D, work)
    assert np.allclose(D @ G, np.eye(n_c), rtol=0, atol=1e-10)
    assert np.allclose(D, np.linalg.inv(G), rtol=0, atol=1e-10 * np.abs(D).max())
    singular = G.copy()
    singular[:, 2] = 0.0
    assert not _invert(singular, D, work)


@pytest.mark.parametrize("order", [1, 2, 7, 34, 84])
def test_inverse_of_order_up_to_84_matches_numpy(order):
    """The split-form Gauss-Jordan inverse against ``numpy.linalg.inv``
    (LAPACK's LU) at the lap joint's orders (34 coordinates at N = 40, 84
    at N = 100), on complex symmetric matrices of receptance size (1e-7
    m/N, rows scaled over 4 decades) with zero diagonal entries that force
    pivot swaps, and on an unsymmetric one: within ``100 n eps κ`` of the
    reference, ``D G`` the identity within ``100 n eps κ``."""
    rng = np.random.default_rng(order)
    eps = np.finfo(float).eps
    A = rng.standard_normal((order, order)) + 1j * rng.standard_normal((order, order))
    symmetric = 1e-7 * (A + A.T + order * np.eye(order))
    s = np.logspace(0, 2, order)
    symmetric = s[:, None] * symmetric * s[None, :]
    unsymmetric = 1e-7 * (A + 0.5 * order * np.eye(order))
    if order > 1:
        symmetric[np.arange(0, order, 3), np.arange(0, order, 3)] = 0.0
        unsymmetric[0, 0] = 0.0
    for G in (symmetric, unsymmetric):
        ref = np.linalg.inv(G)
        kappa = np.linalg.cond(G, np.inf)
        D = np.empty_like(G)
        work = np.empty_like(G)
        assert _invert(G, D, work)
        bound = 100 * order * eps * kappa
        assert np.abs(D - ref).max() <= bound * np.abs(ref).max()
        DG = D @ G
        assert np.abs(DG - np.eye(order)).max() <= bound


def _gauss_jordan_one_pivot(G):
    """Plain-NumPy Gauss-Jordan inverse in the kernel's split form, one
    pivot at a time (the kernel before stop 34), the same operations on
    every entry: pivot by ``|Re| + |Im|``, the scaled pivot row, each
    other row with a nonzero factor minus the factor times it."""
    m = G.shape[0]
    re = G.real.copy()
    im = G.imag.copy()
    piv = np.empty(m, dtype=int)
    for k in range(m):
        size = np.abs(re[k:, k]) + np.abs(im[k:, k])
        p = k + int(np.argmax(size))  # the first of the largest
        piv[k] = p
        re[[k, p]] = re[[p, k]]
        im[[k, p]] = im[[p, k]]
        inv = 1.0 / complex(re[k, k], im[k, k])
        re[k, k], im[k, k] = 1.0, 0.0
        a, b = re[k].copy(), im[k].copy()
        re[k] = a * inv.real - b * inv.imag
        im[k] = a * inv.imag + b * inv.real
        for i in range(m):
            f_re, f_im = re[i, k], im[i, k]
            if i == k or (f_re == 0.0 and f_im == 0.0):
                continue
            re[i, k] = im[i, k] = 0.0
            re[i] -= f_re * re[k] - f_im * im[k]
            im[i] -= f_re * im[k] + f_im * re[k]
    D = re + 1j * im
    for k in range(m - 1, -1, -1):
        D[:, [k, piv[k]]] = D[:, [piv[k], k]]
    return D


@pytest.mark.parametrize("order", [1, 2, 3, 7, 34, 84, 85])
def test_inverse_two_pivots_at_a_time_is_one_at_a_time_bit_for_bit(order):
    """Stop 34: the kernel takes its pivots two at a time; its inverse is
    that of one pivot at a time (plain NumPy, the same operations) bit for
    bit: complex symmetric with zero diagonal entries (swaps), and a block
    diagonal one whose zero factors take every branch of the two-pivot
    update (both, the first only, the second only, neither)."""
    rng = np.random.default_rng(order + 40)
    A = rng.standard_normal((order, order)) + 1j * rng.standard_normal((order, order))
    symmetric = 1e-7 * (A + A.T)
    symmetric[np.arange(0, order, 3), np.arange(0, order, 3)] = 0.0
    blocky = A.copy()
    blocky[(np.arange(order)[:, None] // 3) != (np.arange(order)[None, :] // 3)] = 0
    blocky[np.arange(0, order, 2), np.arange(0, order, 2)] = 0.0
    blocky[np.arange(1, order, 4), np.arange(0, order - 1, 4)] = 2.0  # below
    for G in (symmetric, blocky):
        if np.linalg.matrix_rank(G) < order:
            continue
        D = np.empty_like(G)
        work = np.empty_like(G)
        assert _invert(G, D, work)
        assert np.array_equal(D, _gauss_jordan_one_pivot(G))


def test_inverse_of_a_permutation_and_loud_failures():
    """Every pivot a swap: the inverse of a (complex-scaled) permutation is
    its exact transpose; a NaN, an inf, a zero row or two equal rows give
    False."""
    order = 9
    perm = np.random.default_rng(3).permutation(order)
    G = np.zeros((order, order), dtype=complex)
    G[np.arange(order), perm] = 2.0 + 2.0j  # inverse 0.25 - 0.25j, exact
    D = np.empty_like(G)
    work = np.empty_like(G)
    assert _invert(G, D, work)
    assert np.array_equal(D, (G.T != 0) * (0.25 - 0.25j))
    rng = np.random.default_rng(4)
    base = rng.standard_normal((order, order)) + 1j * rng.standard_normal(
        (order, order)
    )
    for bad in (np.nan, np.inf):
        G = base.copy()
        G[4, 6] = bad
        assert not _invert(G, D, work)
    G = base.copy()
    G[5, :] = 0.0
    assert not _invert(G, D, work)
    G = base.copy()
    G[7, :] = G[2, :]
    assert not _invert(G, D, work)


@pytest.mark.parametrize("size", [1.0, 1e-7, 1e200, 1e-170])
def test_rounding_level_matches_numpy(size):
    """The residual's rounding level ``eps max(‖G‖∞, g_scale) ‖D‖∞ max_a
    Σ_b |D_ab| |e_b|`` against NumPy's moduli, at receptance size and at
    sizes whose squares overflow (1e200 in ``G``; 1e-170 in ``G``, 1e170
    in ``D``), where the kernel takes the moduli again by ``hypot``; with
    ``g_scale`` below and above ``‖G‖∞``."""
    rng = np.random.default_rng(11)
    m = 12
    G = size * (rng.standard_normal((m, m)) + 1j * rng.standard_normal((m, m)))
    D = np.linalg.inv(G)
    e = size * (rng.standard_normal(m) + 1j * rng.standard_normal(m))
    g_norm = np.abs(G).sum(axis=1).max()
    d_norm = np.abs(D).sum(axis=1).max()
    worst = (np.abs(D) @ np.abs(e)).max()
    eps = np.finfo(float).eps
    for g_scale in (0.0, 3.0 * g_norm):
        ref = eps * max(g_norm, g_scale) * d_norm * worst
        level = _rounding_level(G, D, e, g_scale)
        assert np.isfinite(level)
        assert abs(level - ref) <= 1e-13 * ref


@pytest.fixture(scope="module")
def microslip_points():
    """Condensed points of the lap joint (N = 10, H = 15) through the onset
    of microslip, from a short branch."""
    joint = hf.lap_joint(10)
    captured = {}
    import hbmfric.api as api

    original = api.watched_truncation_errors

    def keep(problem, points, *args, **kwargs):
        captured["points"] = points.copy()
        return original(problem, points, *args, **kwargs)

    api.watched_truncation_errors = keep
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.AccuracyWarning)
            hf.frf(joint, 36.0, (HZ * 160.0, HZ * 164.0), 15, max_step=0.05)
    finally:
        api.watched_truncation_errors = original
    return joint, captured["points"]


def test_truncation_estimate_by_harmonic_blocks_matches_the_dense_solve(
    microslip_points, monkeypatch
):
    """The probe solve of the truncation estimate by GMRES on the harmonic
    blocks gives the estimates of the dense LU (to 1e-7 relative), and it
    is the path taken (its counters), at every calibrated point."""
    joint, points = microslip_points
    out = {}
    for label, threshold in (("dense", 10**9), ("blocks", 0)):
        monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", threshold)
        p = CondensedHBMProblem(joint, 36.0, 15)
        out[label] = truncation_errors(p, points, 1e-4)
        probe = p._accuracy_cache["watched"][1].problem.kernel_problem
        out[label + "_state"] = probe.solver[3].copy()
    dense, fast = out["dense"], out["blocks"]
    assert np.count_nonzero(dense) >= 3
    assert np.all(np.isfinite(fast))
    assert np.allclose(fast, dense, rtol=1e-7, atol=0)
    state = out["blocks_state"]
    assert state[krylov.REUSE_SOLVES] >= 3
    assert state[krylov.REUSE_FALLBACKS] == 0
    assert state[krylov.REUSE_FACTORISATIONS] == 0
    assert out["dense_state"][krylov.REUSE_SOLVES] == 0


def test_truncation_probe_failure_falls_back_to_the_dense_solve(
    microslip_points, monkeypatch
):
    """A probe GMRES that cannot converge (tolerance 0) falls back to the
    dense LU at every calibrated point (counted): the same estimates."""
    joint, points = microslip_points
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 10**9)
    dense = truncation_errors(CondensedHBMProblem(joint, 36.0, 15), points, 1e-4)
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 0)
    p = CondensedHBMProblem(joint, 36.0, 15)
    truncation_errors(p, points[:1], 1e-4)  # builds the probe level
    state = p._accuracy_cache["watched"][1].problem.kernel_problem.solver[3]
    state[krylov.REUSE_TOL] = 0.0
    before = state.copy()
    errors = truncation_errors(p, points, 1e-4)
    calibrated = (
        state[krylov.REUSE_FACTORISATIONS] - before[krylov.REUSE_FACTORISATIONS]
    )
    assert calibrated >= 3
    assert state[krylov.REUSE_FALLBACKS] - before[krylov.REUSE_FALLBACKS] == calibrated
    assert state[krylov.REUSE_SOLVES] == before[krylov.REUSE_SOLVES]
    assert np.allclose(errors, dense, rtol=1e-12, atol=0)


def test_block_solve_to_a_looser_tolerance(monkeypatch):
    """Stop 28: the corrector's Newton updates are solved to
    ``newton.NEWTON_KRYLOV_TOL`` (1e-6 relative residual, the tangent to
    ``REUSE_TOL``): the residual of the solution recomputed with NumPy
    meets the asked tolerance, in fewer GMRES products than at 1e-10."""
    from hbmfric.kernels.steps import newton

    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 0)
    # the plain blocks: corrected for the coupling, GMRES would be exact
    # at either tolerance (tests/test_capacitance.py)
    monkeypatch.setattr(hc, "REUSE_SLIP_MAX", 0)
    assert newton.NEWTON_KRYLOV_TOL == 1e-6
    n_dof, n_coef = 6, 10
    A = _bordered(n_dof, n_coef, 0.5, seed=3)
    b = np.random.default_rng(7).standard_normal(A.shape[0])
    products = {}
    for tol in (1e-10, 1e-6):
        solver = _solver(n_dof, n_coef)
        x = b.copy()
        assert blocks.block_solve(A, x, solver, n_dof, n_coef, 0, False, tol)
        assert np.linalg.norm(A @ x - b) <= tol * np.linalg.norm(b)
        products[tol] = solver[3][krylov.REUSE_PRODUCTS]
    assert products[1e-6] < products[1e-10]
    # the default is the state's tolerance (REUSE_TOL = 1e-10)
    solver = _solver(n_dof, n_coef)
    x = b.copy()
    assert blocks.block_solve(A, x, solver, n_dof, n_coef, 0, False)
    assert solver[3][krylov.REUSE_PRODUCTS] == products[1e-10]
