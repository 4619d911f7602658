"""Dense LU kernels against NumPy's LAPACK solve, and their failure codes."""

import numpy as np
import pytest

from hbmfric.kernels.linalg import lu_factor, lu_solve, solve_inplace


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
