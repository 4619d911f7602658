"""Dense linear solves for bordered systems, with a status instead of an
exception (``np.linalg.solve`` raises inside Numba on a singular matrix).

:func:`lu_factor` and :func:`lu_solve` keep the factors for further
right-hand sides (the continuation corrector reuses them for the tangent);
:func:`solve_inplace` is the two in one call.

Matrices of order ``LAPACK_MIN_ORDER`` and above are factored by LAPACK's
blocked ``dgetrf`` (through the LAPACK entry point Numba ships in its
helper library, the one behind its own ``np.linalg``; no exception, and the
compiled caller stays cacheable). Below that order the call overhead loses
to the plain loop (measured: at order 18 LAPACK 2.4 µs, the loop 1.7 µs; at
order 32 5.3 against 6.1 µs; at order 780 13 against 68 ms; at order 1780
88 against 1550 ms). Both give the same factors in the same layout
(row-major ``L`` below the diagonal, ``U`` on and above, pivots 0-based).
"""

import numpy as np
from numba import types

from ..._jit import jit

LAPACK_MIN_ORDER = 32
"""Order from which :func:`lu_factor` calls LAPACK's ``dgetrf``."""

# Numba's helper-library entry point for LAPACK ?getrf (the signature of
# numba.np.linalg._LAPACK.numba_xxgetrf, built here without importing SciPy's
# LAPACK at import time: the helper loads it on the first call).
_getrf = types.ExternalFunction(
    "numba_xxgetrf",
    types.intc(
        types.char,  # kind: "d" for float64
        types.intp,  # m
        types.intp,  # n
        types.CPointer(types.float64),  # a (column-major)
        types.intp,  # lda
        types.CPointer(types.int32),  # ipiv (1-based)
    ),
)
_KIND_FLOAT64 = ord("d")


@jit
def lu_factor(A, piv):
    """LU factorisation with partial pivoting, in place.

    Parameters
    ----------
    A : ndarray, shape (m, m)
        In: the matrix. Out: ``L`` (unit diagonal, below) and ``U``.
    piv : ndarray of int64, shape (m,)
        Out: row ``k`` was swapped with row ``piv[k]`` at step ``k``.

    Returns
    -------
    bool
        False if a pivot is zero or not finite.
    """
    m = A.shape[0]
    big_all = 0.0
    for i in range(m):
        for j in range(m):
            a = abs(A[i, j])
            if not a <= big_all:
                big_all = a
    if not np.isfinite(big_all):
        return False
    tiny = 1e-300 + big_all * 1e-15
    if m >= LAPACK_MIN_ORDER:
        return _lapack_lu_factor(A, piv, tiny)
    for k in range(m):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, m):
            a = abs(A[i, k])
            if a > big:
                big = a
                p = i
        piv[k] = p
        if not big > tiny:
            return False
        if p != k:
            for j in range(m):
                A[k, j], A[p, j] = A[p, j], A[k, j]
        inv = 1.0 / A[k, k]
        for i in range(k + 1, m):
            f = A[i, k] * inv
            A[i, k] = f
            if f != 0.0:
                for j in range(k + 1, m):
                    A[i, j] -= f * A[k, j]
    return True


@jit
def _lapack_lu_factor(A, piv, tiny):
    """:func:`lu_factor` by LAPACK ``dgetrf`` (``A`` square and finite, any
    memory layout); a pivot of modulus ``<= tiny`` fails as in the loop."""
    m = A.shape[0]
    # LAPACK reads column-major: store the transpose row-major
    work = np.empty((m, m))
    for i in range(m):
        for j in range(m):
            work[j, i] = A[i, j]
    ipiv = np.empty(m, dtype=np.int32)
    info = _getrf(_KIND_FLOAT64, m, m, work.ctypes, m, ipiv.ctypes)
    if info < 0:
        return False
    for i in range(m):
        for j in range(m):
            A[i, j] = work[j, i]
    for k in range(m):
        piv[k] = ipiv[k] - 1
        if not abs(A[k, k]) > tiny:
            return False
    return True


@jit
def lu_solve(A, piv, b):
    """Solve with the factors of :func:`lu_factor`; ``b`` holds ``x`` on
    return."""
    m = b.size
    for k in range(m):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for i in range(1, m):
        acc = b[i]
        for j in range(i):
            acc -= A[i, j] * b[j]
        b[i] = acc
    for i in range(m - 1, -1, -1):
        acc = b[i]
        for j in range(i + 1, m):
            acc -= A[i, j] * b[j]
        b[i] = acc / A[i, i]


@jit
def solve_inplace(A, b):
    """Solve ``A x = b`` by LU with partial pivoting, overwriting ``A`` and
    ``b`` (``b`` holds ``x`` on return).

    Parameters
    ----------
    A : ndarray, shape (n, n)
        Out: the factors of :func:`lu_factor`.
    b : ndarray, shape (n,)

    Returns
    -------
    bool
        False if a pivot is zero or not finite, or ``x`` is not finite
        (``b`` is then meaningless).
    """
    piv = np.empty(b.size, dtype=np.int64)
    if not lu_factor(A, piv):
        return False
    lu_solve(A, piv, b)
    return np.isfinite(b).all()
