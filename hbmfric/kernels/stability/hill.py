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

from ..._jit import jit
from ..linalg.lu import lu_factor
from ..residuals.hbm import hbm_residual


@jit
def hill_jacobians(points, problem, jac, status, blocks, sizes, signs):
    """``∂R/∂X`` of the HBM residual at many solutions, and optionally the
    signs of the determinants of diagonal blocks of each (computed while
    the Jacobian is fresh in the cache).

    Parameters
    ----------
    points : ndarray, shape (n_points, n + 1)
        Unknowns ``[X, Ω]`` of each solution (``n = n_dof * n_coef``,
        coefficients in m, Ω in rad/s).
    problem : tuple
        Kernel problem of :func:`hbmfric.kernels.residuals.hbm.hbm_residual`.
    jac : ndarray, shape (n_points, n, n)
        Output: the Jacobians (the Ω column left out), N/m.
    status : ndarray of int64, shape (n_points,)
        Output: contact-state code of each AFT (negative on failure).
    blocks : ndarray of int64, shape (n_blocks, m_max)
        Row (and column) indices of each block (``n_blocks = 0``: no
        signs), the first ``sizes[b]`` of row ``b`` used.
    sizes : ndarray of int64, shape (n_blocks,)
    signs : ndarray of int64, shape (n_points, n_blocks)
        Output: as :func:`block_determinant_signs`.
    """
    n = jac.shape[1]
    R = np.empty(n)
    J = np.empty((n, n + 1))
    for i in range(points.shape[0]):
        status[i] = hbm_residual(points[i], problem, R, J)
        for r in range(n):
            for c in range(n):
                jac[i, r, c] = J[r, c]
        for b in range(blocks.shape[0]):
            signs[i, b] = _sign_of_det(J, blocks[b, : sizes[b]])


@jit
def _sign_of_det(J, block):
    """Sign of ``det J[block][:, block]`` (0: singular or not finite)."""
    m = block.size
    W = np.empty((m, m))
    p = np.empty(m, dtype=np.int64)
    for r in range(m):
        for c in range(m):
            W[r, c] = J[block[r], block[c]]
    if not lu_factor(W, p):
        return 0
    s = 1
    for k in range(m):
        if p[k] != k:
            s = -s
        if W[k, k] < 0.0:
            s = -s
    return s


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
    for i in range(jac.shape[0]):
        for b in range(blocks.shape[0]):
            signs[i, b] = _sign_of_det(jac[i], blocks[b, : sizes[b]])


@jit
def split_extremes(jac, odd, even):
    """Largest ``|jac[i, r, c]|`` coupling the index sets ``odd`` and
    ``even`` (either way), and the largest entry of all, over all
    matrices ``i``; inf where an entry is not finite."""
    coupling = 0.0
    largest = 0.0
    for i in range(jac.shape[0]):
        for r in range(jac.shape[1]):
            for c in range(jac.shape[2]):
                a = abs(jac[i, r, c])
                if not a <= largest:
                    largest = a if a == a else np.inf
        for r in odd:
            for c in even:
                a = max(abs(jac[i, r, c]), abs(jac[i, c, r]))
                if not a <= coupling:
                    coupling = a if a == a else np.inf
    return coupling, largest
