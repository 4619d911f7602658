"""The corrector's bordered matrix built on the Jacobian's pattern (issue
15, stop 31: ``kernels/linalg/pattern.py``): the places it visits hold
every nonzero of the lap joint's Jacobian; its row scales, rounding floor
and nonzeros (CSR) are those of the dense passes it replaces
(``kernels/steps/newton.py: equilibrate_rows, rounding_floor``,
``kernels/linalg/krylov.py: sparse_rows``) bit for bit, on real lap-joint
Jacobians with no, some and every contact slipping; the block solver on
those nonzeros solves the bordered system (against NumPy) whatever the
dense matrix holds off the pattern, also through its dense fallback."""

import math

import numpy as np
import pytest

import hbmfric as hf
import hbmfric.condensation as hc
from hbmfric.condensation import CondensedHBMProblem, solver_arrays
from hbmfric.kernels.linalg import blocks, krylov
from hbmfric.kernels.linalg.pattern import (
    append_last_row,
    equilibrate_pattern,
    pattern_nonzeros,
    pattern_size,
    pattern_term_sum,
    scatter_pattern,
)
from hbmfric.kernels.steps.newton import (
    ROUNDING_EPS,
    equilibrate_rows,
    rounding_floor,
)

HZ = 2.0 * math.pi


def _pattern_mask(n_dof, n_coef, first):
    """The pattern written out from its definition, in NumPy: harmonic
    groups across coordinates, each coordinate's own block, the last
    column; shape (n, n + 1)."""
    n = n_dof * n_coef
    group = np.array(
        [0 if (first and c == 0) else first + (c - first) // 2 for c in range(n_coef)]
    )
    coord = np.repeat(np.arange(n_dof), n_coef)
    g = np.tile(group, n_dof)
    mask = np.zeros((n, n + 1), dtype=bool)
    mask[:, :n] = (g[:, None] == g[None, :]) | (coord[:, None] == coord[None, :])
    mask[:, n] = True
    return mask


def _lap_jacobians():
    """Jacobians of the lap joint (N = 10, H = 15) at 162 Hz at 0.1, 3 and
    30 times the free linear response: every contact stuck, some and
    every one slipping (the slipping coordinates' blocks full)."""
    s = hf.lap_joint(10)
    c = CondensedHBMProblem(s, 36.0, 15, receptance="state")
    w = HZ * 162.0
    free = c.linear_response(w, "free")
    out = []
    for factor in (0.1, 3.0, 30.0):
        y = np.append(factor * free, w)
        _, J, _ = c.residual(y)
        out.append((y, J))
    return c, out


@pytest.fixture(scope="module")
def lap():
    return _lap_jacobians()


def _off_harmonic_coordinates(J, n_dof, n_coef):
    """Coordinates whose own block couples harmonics (slipping); H odd:
    the groups are the coefficient pairs."""
    n = n_dof * n_coef
    group = np.tile(np.arange(n_coef) // 2, n_dof)
    same = group[:, None] == group[None, :]
    off = (J[:, :n] != 0.0) & ~same
    return sorted({i // n_coef for i in np.nonzero(off.any(axis=1))[0]})


def test_the_lap_joints_jacobian_is_zero_off_the_pattern(lap):
    c, points = lap
    n_dof, n_coef = c.n_coordinates, c.n_coef
    mask = _pattern_mask(n_dof, n_coef, 0)
    slipping = []
    for _, J in points:
        assert J.shape == mask.shape
        assert np.all(J[~mask] == 0.0)
        slipping.append(len(_off_harmonic_coordinates(J, n_dof, n_coef)))
    # stuck, partly and wholly slipping
    assert slipping[0] == 0 and 0 < slipping[1] < slipping[2]
    # the room is the count of places plus the last row
    assert pattern_size(n_dof, n_coef, 0) == mask.sum() + mask.shape[1]


def test_pattern_rows_equal_the_dense_passes_bit_for_bit(lap):
    c, points = lap
    n_dof, n_coef = c.n_coordinates, c.n_coef
    n = n_dof * n_coef
    m = n + 1
    mask = _pattern_mask(n_dof, n_coef, 0)
    rng = np.random.default_rng(3)
    for y, J in points:
        scale = np.abs(y) * rng.uniform(0.5, 2.0, m) + 1e-9
        # the dense path of the corrector
        A = np.zeros((m, m))
        rows = np.empty(m)
        equilibrate_rows(J, scale, A, rows)
        A[n, :] = rng.standard_normal(m)
        A[n, 5] = 0.0
        starts, columns, values = krylov.sparse_rows(A)
        # on the pattern, into a matrix of NaN
        B = np.full((m, m), np.nan)
        B[n, :] = A[n, :]
        rows_p = np.full(m, np.nan)
        room = pattern_size(n_dof, n_coef, 0)
        st = np.zeros(m + 1, dtype=np.int64)
        co = np.zeros(room, dtype=np.int64)
        va = np.zeros(room)
        equilibrate_pattern(J, scale, B, rows_p, n_dof, n_coef, 0, st, co, va)
        append_last_row(B, st, co, va)
        assert np.array_equal(rows_p[:n], rows[:n])
        assert np.array_equal(st, starts)
        nnz = st[-1]
        assert np.array_equal(co[:nnz], columns)
        assert np.array_equal(va[:nnz], values)
        # only the last column (the border) is written at once
        assert np.array_equal(B[:n, n], A[:n, n])
        assert np.isnan(B[:n, :n]).all()
        # the other places of the pattern from the nonzeros, when the block
        # solver factors: the dense matrix's entries, zeros included
        scatter_pattern(B, n_dof, n_coef, 0, st, co, va)
        assert np.array_equal(B[:n][mask], A[:n][mask])
        assert np.isnan(B[:n][~mask]).all()  # nothing written off them
        floor = ROUNDING_EPS * 2.220446049250313e-16
        assert floor * pattern_term_sum(J, y, n_dof, n_coef, 0) == rounding_floor(J, y)
        assert rounding_floor(J, y) > 0.0


def test_pattern_with_a_constant_term_matches_a_dense_gather():
    """``first = 1`` (a constant term: group 0 of width 1) on a matrix of
    the harmonic-balance structure written out in NumPy."""
    n_dof, n_coef, first = 4, 7, 1
    n = n_dof * n_coef
    m = n + 1
    mask = _pattern_mask(n_dof, n_coef, first)
    rng = np.random.default_rng(7)
    J = np.where(mask, rng.standard_normal(mask.shape), 0.0)
    J[3, 5] = 0.0  # a zero inside the pattern is left out of the nonzeros
    scale = rng.uniform(0.1, 10.0, m)
    y = rng.standard_normal(m)
    A = np.zeros((m, m))
    rows = np.empty(m)
    equilibrate_rows(J, scale, A, rows)
    A[n, :] = 1.0
    starts, columns, values = krylov.sparse_rows(A)
    B = np.full((m, m), np.nan)
    B[n, :] = 1.0
    rows_p = np.empty(m)
    room = pattern_size(n_dof, n_coef, first)
    assert room == mask.sum() + m
    st = np.zeros(m + 1, dtype=np.int64)
    co = np.zeros(room, dtype=np.int64)
    va = np.zeros(room)
    equilibrate_pattern(J, scale, B, rows_p, n_dof, n_coef, first, st, co, va)
    append_last_row(B, st, co, va)
    assert np.array_equal(rows_p[:n], rows[:n])
    assert np.array_equal(st, starts)
    assert np.array_equal(co[: st[-1]], columns)
    assert np.array_equal(va[: st[-1]], values)
    floor = ROUNDING_EPS * 2.220446049250313e-16
    assert floor * pattern_term_sum(J, y, n_dof, n_coef, first) == rounding_floor(J, y)


def _built(J, scale, constraint, solver, n_dof, n_coef):
    """The bordered matrix built on the pattern into a matrix of NaN, its
    nonzeros in the solver's arrays; and the same matrix dense."""
    n = J.shape[0]
    m = n + 1
    B = np.full((m, m), np.nan)
    rows = np.empty(m)
    st, co, va = solver[9]
    equilibrate_pattern(J, scale, B, rows, n_dof, n_coef, 0, st, co, va)
    B[n, :] = constraint
    append_last_row(B, st, co, va)
    A = np.zeros((m, m))
    equilibrate_rows(J, scale, A, rows)
    A[n, :] = constraint
    return B, A


def test_block_solve_on_built_nonzeros_ignores_the_rest_of_the_matrix(lap, monkeypatch):
    """The solve of the corrector and of the tangent after it on the
    nonzeros built on the pattern, the dense matrix NaN off it: against
    ``numpy.linalg.solve`` of the dense bordered matrix; and through the
    dense fallback (a two-vector Krylov basis, blocks not corrected)."""
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 0)
    c, points = lap
    n_dof, n_coef = c.n_coordinates, c.n_coef
    n = n_dof * n_coef
    m = n + 1
    rng = np.random.default_rng(11)
    e = np.zeros(m)
    e[-1] = 1.0
    for y, J in points[1:]:
        scale = np.abs(y) + 1e-9
        constraint = rng.standard_normal(m)
        constraint /= np.linalg.norm(constraint)
        b = rng.standard_normal(m)
        for k_max, slip_max in ((None, hc.REUSE_SLIP_MAX), (2, 0)):
            monkeypatch.setattr(hc, "REUSE_SLIP_MAX", slip_max)
            solver = solver_arrays(n, True, n_dof, n_coef, 0)
            if k_max is not None:
                V = np.zeros((k_max + 1, m))
                solver = (*solver[:2], V, *solver[3:])
            B, A = _built(J, scale, constraint, solver, n_dof, n_coef)
            x = b.copy()
            assert blocks.block_solve(B, x, solver, n_dof, n_coef, 0, False, -1.0, True)
            ref = np.linalg.solve(A, b)
            assert np.allclose(x, ref, rtol=0, atol=1e-8 * np.abs(ref).max())
            t = e.copy()
            assert blocks.block_solve(B, t, solver, n_dof, n_coef, 0, True)
            ref = np.linalg.solve(A, e)
            assert np.allclose(t, ref, rtol=0, atol=1e-8 * np.abs(ref).max())
            state = solver[3]
            assert state[krylov.REUSE_NONZEROS] == 1.0
            if k_max is not None:
                assert state[krylov.REUSE_FALLBACKS] == 1
                assert state[krylov.REUSE_FACTORISATIONS] == 1
            elif J is points[1][1]:
                # some contacts slip: solved on the blocks factored from
                # B's places of the pattern, written from the nonzeros (NaN
                # before), no dense factorisation (every contact slipping,
                # the next point, needs more than the Krylov basis, as on
                # main)
                assert state[krylov.REUSE_BLOCK_BUILDS] == 1
                assert state[krylov.REUSE_FALLBACKS] == 0
                assert state[krylov.REUSE_FACTORISATIONS] == 0


def test_block_solve_gathers_the_nonzeros_of_a_new_matrix(lap, monkeypatch):
    """A solve not told that the kept nonzeros are built (a new matrix,
    ``again`` false) gathers those of ``A`` itself, also for the tangent
    after it: the kept nonzeros of an earlier matrix are never used for
    another (GMRES would solve the earlier system)."""
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 0)
    c, points = lap
    n_dof, n_coef = c.n_coordinates, c.n_coef
    n = n_dof * n_coef
    m = n + 1
    rng = np.random.default_rng(13)
    solver = solver_arrays(n, True, n_dof, n_coef, 0)
    (y1, J1), (y2, J2) = points[1], points[2]
    constraint = rng.standard_normal(m)
    B1, _ = _built(J1, np.abs(y1) + 1e-9, constraint, solver, n_dof, n_coef)
    x = rng.standard_normal(m)
    assert blocks.block_solve(B1, x, solver, n_dof, n_coef, 0, False, -1.0, True)
    # another matrix, dense, its nonzeros not built
    A2 = np.zeros((m, m))
    equilibrate_rows(J2, np.abs(y2) + 1e-9, A2, np.empty(m))
    A2[n, :] = constraint
    b = rng.standard_normal(m)
    for again in (False, True):
        x = b.copy()
        assert blocks.block_solve(A2, x, solver, n_dof, n_coef, 0, again)
        ref = np.linalg.solve(A2, b)
        assert np.allclose(x, ref, rtol=0, atol=1e-8 * np.abs(ref).max())
        assert solver[3][krylov.REUSE_NONZEROS] == 0.0


def test_probe_nonzeros_and_solve_read_the_jacobian_on_its_pattern(lap):
    """Stop 32: the truncation probe's system ``J[:, :n] x = b`` solved
    from the Jacobian itself, no square copy (``pattern_nonzeros``,
    ``gmres_pattern``): the nonzeros are ``sparse_rows`` of the copy bit
    for bit, and GMRES takes the same steps as ``gmres_blocks`` on the
    copy (the same solution bit for bit, the same products) and solves
    the system against ``numpy.linalg.solve``; the last column of ``J``
    (``dR/dΩ``) is never read (NaN there)."""
    c, points = lap
    n_dof, n_coef = c.n_coordinates, c.n_coef
    n = n_dof * n_coef
    rng = np.random.default_rng(17)
    for _, J in points:
        Jn = J.copy()
        Jn[:, n] = np.nan
        square = np.ascontiguousarray(J[:, :n])
        starts, columns, values = krylov.sparse_rows(square)
        room = pattern_size(n_dof, n_coef, 0) - 2 * n - 1
        st = np.zeros(n + 1, dtype=np.int64)
        co = np.zeros(room, dtype=np.int64)
        va = np.zeros(room)
        pattern_nonzeros(Jn, n_dof, n_coef, 0, st, co, va)
        assert np.array_equal(st, starts)
        assert np.array_equal(co[: st[-1]], columns)
        assert np.array_equal(va[: st[-1]], values)
        b = rng.standard_normal(n)
        x1 = np.empty(n)
        x2 = np.empty(n)
        arrays = blocks.block_work(n_dof, n_coef, 0, n, 60)
        s1, k1 = blocks.gmres_blocks(square, b, x1, n_dof, n_coef, 0, 1e-10, arrays)
        arrays = blocks.block_work(n_dof, n_coef, 0, n, 60)
        s2, k2 = blocks.gmres_pattern(Jn, b, x2, n_dof, n_coef, 0, 1e-10, arrays)
        assert s1 == s2 == krylov.GMRES_CONVERGED and k1 == k2
        assert np.array_equal(x1, x2)
        ref = np.linalg.solve(square, b)
        assert np.allclose(x2, ref, rtol=0, atol=1e-8 * np.abs(ref).max())


def test_probe_nonzeros_with_a_constant_term():
    """``pattern_nonzeros`` with ``first = 1`` on a matrix of the pattern
    written out in NumPy, a zero inside the pattern left out: the nonzeros
    of the leading square part, as NumPy lists them row by row."""
    n_dof, n_coef, first = 4, 7, 1
    n = n_dof * n_coef
    mask = _pattern_mask(n_dof, n_coef, first)
    rng = np.random.default_rng(19)
    J = np.where(mask, rng.standard_normal(mask.shape), 0.0)
    J[3, 5] = 0.0
    room = pattern_size(n_dof, n_coef, first) - 2 * n - 1
    assert room == mask[:, :n].sum()
    st = np.zeros(n + 1, dtype=np.int64)
    co = np.zeros(room, dtype=np.int64)
    va = np.zeros(room)
    pattern_nonzeros(J, n_dof, n_coef, first, st, co, va)
    rows, cols = np.nonzero(J[:, :n])  # row-major: row by row, columns ascending
    assert st[-1] == rows.size
    assert np.array_equal(np.diff(st), np.bincount(rows, minlength=n))
    assert np.array_equal(co[: st[-1]], cols)
    assert np.array_equal(va[: st[-1]], J[rows, cols])


def test_block_tangent_against_numpy(lap):
    """Stop 32: the tangent outside the trace on the harmonic blocks
    (``newton.block_tangent``, its own arrays): the unit solution of
    ``[J diag(scale); previousᵀ] t = [0; 1]`` from ``numpy.linalg.solve``,
    with none, some and every contact slipping, corrected or not for the
    slipping coordinates; the dense ``tangent`` it falls back to against
    the same reference."""
    from hbmfric.kernels.steps.newton import block_tangent, tangent

    c, points = lap
    n_dof, n_coef = c.n_coordinates, c.n_coef
    n = n_dof * n_coef
    m = n + 1
    rng = np.random.default_rng(23)
    for y, J in points:
        scale = np.abs(y) + 1e-9
        previous = rng.standard_normal(m)
        previous /= np.linalg.norm(previous)
        M = J * scale[None, :]
        M = M / np.abs(M).max(axis=1)[:, None]
        ref = np.linalg.solve(np.vstack([M, previous]), np.eye(m)[-1])
        ref /= np.linalg.norm(ref)
        for n_slip, k_max in ((12, 40), (0, 60)):
            A = np.full((m, m), np.nan)
            out = np.full(m, np.nan)
            ok = block_tangent(
                J, previous, scale, A, n_dof, n_coef, 0, n_slip, k_max, 1e-10, out
            )
            assert ok
            assert np.allclose(out, ref, rtol=0, atol=1e-8)
            assert abs(np.linalg.norm(out) - 1.0) < 1e-14
        A = np.empty((m, m))
        assert np.allclose(tangent(J, previous, scale, A), ref, rtol=0, atol=1e-8)
