"""Kernels of Hill's stability (:mod:`hbmfric.stability`): the HBM
Jacobians of many solutions in one compiled loop, and the signs of the
determinants of diagonal blocks of them.

The sign of ``det Δ0`` (``Δ0`` the HBM Jacobian, Hill's pencil at λ = 0)
is ``sign(det Δ2) (-1)^m`` with ``m`` the number of positive real
eigenvalues of the pencil (``det Δ0 = det Δ2 Π(-λ_j)``, complex pairs
contributing ``|λ_j|² > 0``): it changes exactly where an odd number of
real exponents crosses zero.
"""

import numpy as np

from .._jit import jit
from .hbm import hbm_residual
from .linalg import lu_factor


@jit
def hill_jacobians(points, problem, jac, status):
    """``∂R/∂X`` of the HBM residual at many solutions.

    Parameters
    ----------
    points : ndarray, shape (n_points, n + 1)
        Unknowns ``[X, Ω]`` of each solution (``n = n_dof * n_coef``,
        coefficients in m, Ω in rad/s).
    problem : tuple
        Kernel problem of :func:`hbmfric.kernels.hbm.hbm_residual`.
    jac : ndarray, shape (n_points, n, n)
        Output: the Jacobians (the Ω column left out), N/m.
    status : ndarray of int64, shape (n_points,)
        Output: contact-state code of each AFT (negative on failure).
    """
    n = jac.shape[1]
    R = np.empty(n)
    J = np.empty((n, n + 1))
    for i in range(points.shape[0]):
        status[i] = hbm_residual(points[i], problem, R, J)
        for r in range(n):
            for c in range(n):
                jac[i, r, c] = J[r, c]


@jit
def block_determinant_signs(jac, blocks, sizes, signs):
    """Signs of the determinants of diagonal blocks of many matrices.

    Parameters
    ----------
    jac : ndarray, shape (n_points, n, n)
    blocks : ndarray of int64, shape (n_blocks, m_max)
        Row (and column) indices of each block, the first ``sizes[b]`` of
        row ``b`` used.
    sizes : ndarray of int64, shape (n_blocks,)
    signs : ndarray of int64, shape (n_points, n_blocks)
        Output: ``+1`` or ``-1``, ``0`` for a (numerically) singular or
        non-finite block.
    """
    for b in range(blocks.shape[0]):
        m = sizes[b]
        W = np.empty((m, m))
        p = np.empty(m, dtype=np.int64)
        for i in range(jac.shape[0]):
            for r in range(m):
                for c in range(m):
                    W[r, c] = jac[i, blocks[b, r], blocks[b, c]]
            if not lu_factor(W, p):
                signs[i, b] = 0
                continue
            s = 1
            for k in range(m):
                if p[k] != k:
                    s = -s
                if W[k, k] < 0.0:
                    s = -s
            signs[i, b] = s


@jit
def largest_entry(jac, rows, cols):
    """Largest ``|jac[i, r, c]|`` over all matrices ``i``, ``r`` in
    ``rows``, ``c`` in ``cols`` (int64 index arrays); inf if any of them
    is not finite."""
    big = 0.0
    for i in range(jac.shape[0]):
        for r in rows:
            for c in cols:
                a = abs(jac[i, r, c])
                if not a <= big:
                    big = a if a == a else np.inf
    return big
