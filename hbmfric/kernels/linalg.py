"""Dense linear solves for small bordered systems, with a status instead of
an exception (``np.linalg.solve`` raises inside Numba on a singular matrix)."""

import numpy as np

from .._jit import jit


@jit
def solve_inplace(A, b):
    """Solve ``A x = b`` by LU with partial pivoting, overwriting ``A`` and
    ``b`` (``b`` holds ``x`` on return).

    Parameters
    ----------
    A : ndarray, shape (n, n)
    b : ndarray, shape (n,)

    Returns
    -------
    bool
        False if a pivot is zero or not finite (``b`` is then meaningless).
    """
    n = b.size
    scale = 0.0
    for i in range(n):
        for j in range(n):
            a = abs(A[i, j])
            if a > scale:
                scale = a
    tiny = 1e-300 + scale * 1e-15
    for k in range(n):
        p = k
        big = abs(A[k, k])
        for i in range(k + 1, n):
            a = abs(A[i, k])
            if a > big:
                big = a
                p = i
        if not big > tiny:
            return False
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            b[k], b[p] = b[p], b[k]
        inv = 1.0 / A[k, k]
        for i in range(k + 1, n):
            f = A[i, k] * inv
            if f != 0.0:
                A[i, k] = f
                for j in range(k + 1, n):
                    A[i, j] -= f * A[k, j]
                b[i] -= f * b[k]
    for i in range(n - 1, -1, -1):
        acc = b[i]
        for j in range(i + 1, n):
            acc -= A[i, j] * b[j]
        b[i] = acc / A[i, i]
    return np.isfinite(b).all()
