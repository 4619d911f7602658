"""Dense linear solves for bordered systems, with a status instead of an
exception (``np.linalg.solve`` raises inside Numba on a singular matrix).

:func:`lu_factor` and :func:`lu_solve` keep the factors for further
right-hand sides (the continuation corrector reuses them for the tangent);
:func:`solve_inplace` is the two in one call.

Why not LAPACK: ``dgetrf`` through Numba's LAPACK entry point (SciPy's
OpenBLAS) was tried and removed. From order 100 OpenBLAS factors with
several threads, and on a machine whose cores are busy (other processes,
a parallel study) its threads wait for each other: on the 2-core project
machine at load 9, order 261 took a median of 938 ms against 0.6 ms with
one thread (min 0.9 ms), 0.8–0.9 s spikes from order 176. The plain loop
below costs about 5 GFlop/s (order 780 in 68 ms on a quiet machine) and
never waits.
"""

import numpy as np

from ..._jit import jit


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
