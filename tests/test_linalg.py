"""Dense LU kernels against NumPy's LAPACK solve, and their failure codes."""

import numpy as np
import pytest

from hbmfric.kernels.linalg.lu import lu_factor, lu_solve, solve_inplace


@pytest.mark.parametrize("n", [1, 2, 5, 17])
def test_lu_kernels_match_lapack(n):
    rng = np.random.default_rng(n)
    A = rng.standard_normal((n, n)) + n * np.eye(n)[::-1]  # pivoting needed
    rhs = rng.standard_normal((3, n))
    expected = np.linalg.solve(A, rhs.T).T
    factors = A.copy()
    piv = np.empty(n, dtype=np.int64)
    assert lu_factor(factors, piv)
    for b, x in zip(rhs, expected, strict=True):
        got = b.copy()
        lu_solve(factors, piv, got)
        np.testing.assert_allclose(got, x, rtol=1e-12, atol=1e-12)
        once = b.copy()
        assert solve_inplace(A.copy(), once)
        np.testing.assert_array_equal(once, got)


@pytest.mark.parametrize(
    "bad",
    [
        np.array([[1.0, 2.0], [2.0, 4.0]]),  # singular
        np.array([[np.inf, 0.0], [0.0, 1.0]]),
        np.array([[np.nan, 0.0], [0.0, 1.0]]),
    ],
)
def test_singular_or_non_finite_pivots_fail(bad):
    assert not lu_factor(bad.copy(), np.empty(2, dtype=np.int64))
    assert not solve_inplace(bad.copy(), np.ones(2))


def test_non_finite_entry_off_the_pivots_fails_the_solve():
    # the factorisation only checks pivots; the solution carries the NaN
    bad = np.array([[1.0, np.nan], [0.0, 1.0]])
    assert not solve_inplace(bad, np.ones(2))


def test_first_harmonic_response_against_complex_solve():
    """The real 2n-system of ``kernels.linalg.linear_response`` against NumPy's complex
    solve of ``(K - Ω² M + iΩ C) x = p_c - i p_s``; a singular dynamic
    stiffness (undamped, at a natural frequency) gives zeros and is
    counted."""
    from hbmfric.kernels.linalg.linear_response import first_harmonic_response

    rng = np.random.default_rng(3)
    n = 4
    a = rng.normal(size=(n, n))
    M = a @ a.T + n * np.eye(n)
    b = rng.normal(size=(n, n))
    K = b @ b.T + n * np.eye(n)
    C = 0.03 * K + 0.01 * M
    p_cos, p_sin = rng.normal(size=n), rng.normal(size=n)
    omegas = np.array([0.1, 0.7, 1.3, 2.9])
    out = np.empty((omegas.size, 2, n))
    assert first_harmonic_response(omegas, M, C, K, p_cos, p_sin, out) == 0
    for q, w in enumerate(omegas):
        x = np.linalg.solve(K - w**2 * M + 1j * w * C, p_cos - 1j * p_sin)
        np.testing.assert_allclose(out[q, 0], x.real, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(out[q, 1], -x.imag, rtol=1e-12, atol=1e-14)
    # undamped at a natural frequency: exactly singular, zeros, counted
    out2 = np.ones((2, 2, 2))
    count = first_harmonic_response(
        np.array([1.0, 0.5]),
        np.eye(2),
        np.zeros((2, 2)),
        np.diag([1.0, 4.0]),
        np.ones(2),
        np.zeros(2),
        out2,
    )
    assert count == 1
    np.testing.assert_array_equal(out2[0], 0.0)
    np.testing.assert_allclose(out2[1, 0], [1 / 0.75, 1 / 3.75], rtol=1e-14)


@pytest.mark.parametrize("n", [31, 120])
def test_lu_of_a_strided_view_against_numpy(n):
    """A strided view of a larger buffer against NumPy; the buffer outside
    the view untouched; the factors reproduce ``P A = L U``."""
    rng = np.random.default_rng(n)
    A = rng.standard_normal((n, n)) + 0.1 * np.eye(n)[::-1]
    b = rng.standard_normal(n)
    expected = np.linalg.solve(A, b)
    big = np.zeros((n + 3, 2 * n))
    view = big[1 : n + 1, ::2]
    view[:] = A
    piv = np.empty(n, dtype=np.int64)
    assert lu_factor(view, piv)
    got = b.copy()
    lu_solve(view, piv, got)
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-9)
    assert np.all(big[0] == 0.0) and np.all(big[:, 1::2] == 0.0)
    # the factors reproduce P A = L U with the 0-based swap convention
    L = np.tril(view, -1) + np.eye(n)
    U = np.triu(view)
    PA = A.copy()
    for k in range(n):
        PA[[k, piv[k]]] = PA[[piv[k], k]]
    np.testing.assert_allclose(L @ U, PA, atol=1e-10 * np.abs(A).max())


def test_singular_matrix_of_larger_order_fails():
    n = 40
    A = np.ones((n, n))
    assert not lu_factor(A.copy(), np.empty(n, dtype=np.int64))
    assert not solve_inplace(A.copy(), np.ones(n))


def test_complex_products_against_numpy():
    """The loop products the condensed kernels use instead of BLAS."""
    from hbmfric.kernels.linalg.products import matmul, matvec

    rng = np.random.default_rng(7)
    A = rng.normal(size=(5, 9)) + 1j * rng.normal(size=(5, 9))
    B = rng.normal(size=(9, 4)) + 1j * rng.normal(size=(9, 4))
    A[2, 3] = 0.0  # the zero-skip path
    x = rng.normal(size=9) + 1j * rng.normal(size=9)
    out = np.full((5, 4), np.nan + 0j)
    matmul(A, B, out)
    np.testing.assert_allclose(out, A @ B, rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(matvec(A, x), A @ x, rtol=1e-14, atol=1e-14)
