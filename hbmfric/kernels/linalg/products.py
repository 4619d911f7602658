"""Dense complex matrix products as plain loops.

Kernels call these instead of ``np.dot``: inside Numba ``np.dot`` is BLAS
(SciPy's OpenBLAS), which multiplies with several threads from a modest
size, and on busy cores those threads wait for each other. On the 2-core
project machine under load an 84 × 356 by 356 × 84 complex product took
56 ms with the default threads against 0.44 ms with one; a loop never
waits. Cost of :func:`matmul`: ``O(m k n)``, the innermost loop running
over contiguous memory.
"""

import numpy as np

from ..._jit import jit


@jit
def matmul(A, B, out):
    """``out = A @ B``.

    Parameters
    ----------
    A : ndarray of complex128, shape (m, k)
    B : ndarray of complex128, shape (k, n)
    out : ndarray of complex128, shape (m, n)
        Overwritten; must not share memory with ``A`` or ``B``.
    """
    m, k = A.shape
    n = B.shape[1]
    for i in range(m):
        for j in range(n):
            out[i, j] = 0.0j
        for r in range(k):
            f = A[i, r]
            if f != 0.0:
                for j in range(n):
                    out[i, j] += f * B[r, j]


@jit
def symmetric_matmul(A, B, out):
    """``out = A @ B`` for a product known to be symmetric (``A diag(c)
    Aᵀ``-like, complex symmetric: ``L diag(c) R`` of a receptance): the
    upper triangle as :func:`matmul` computes it (the same sums in the same
    order), mirrored into the lower one; half the work.

    Parameters
    ----------
    A : ndarray of complex128, shape (m, k)
    B : ndarray of complex128, shape (k, m)
    out : ndarray of complex128, shape (m, m)
        Overwritten; must not share memory with ``A`` or ``B``.
    """
    m, k = A.shape
    for i in range(m):
        for j in range(i, m):
            out[i, j] = 0.0j
        for r in range(k):
            f = A[i, r]
            if f != 0.0:
                for j in range(i, m):
                    out[i, j] += f * B[r, j]
        for j in range(i):
            out[i, j] = out[j, i]


@jit
def matvec(A, x):
    """``A @ x`` as a new array.

    Parameters
    ----------
    A : ndarray of complex128, shape (m, k)
    x : ndarray of complex128, shape (k,)

    Returns
    -------
    ndarray of complex128, shape (m,)
    """
    m, k = A.shape
    out = np.empty(m, dtype=np.complex128)
    for i in range(m):
        s = 0.0j
        for r in range(k):
            s += A[i, r] * x[r]
        out[i] = s
    return out
