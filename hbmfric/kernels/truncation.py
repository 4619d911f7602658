"""Truncation-error estimate of a harmonic-balance solution: the first-order
change of the response when more harmonics are admitted.

Used by the adaptive-harmonics continuation
(:mod:`hbmfric.continuation.adaptive`).
"""

import numpy as np

from .._jit import jit
from .linalg import solve_inplace
from .residual import residual


@jit
def truncation_change(x, problem, n_dof, dof, first, synthesis, y, R, J, A, dX):
    """Relative change of the first-harmonic amplitude and of half the
    peak-to-peak value of one DOF when a solution gains harmonics.

    ``x`` is a solution of a smaller basis; zero-padded into the basis of
    ``problem`` (whose harmonics extend those of ``x``), one Newton step at
    fixed Ω in that basis gives the change ``dX`` to first order. The
    change of an extreme of ``x(t)`` is ``dx`` at the instant of the
    extreme (located on the samples of ``synthesis``).

    Parameters
    ----------
    x : ndarray, shape (n_dof * n_coef_small + 1,)
        ``[X, Ω]`` in the smaller basis.
    problem : tuple or CondensedProblem
        Kernel problem of the larger basis
        (:func:`hbmfric.kernels.residual.residual`).
    n_dof : int
        DOFs among the unknowns (``n = n_dof * n_coef``).
    dof : int
        The DOF measured (the contact DOF: the higher harmonics are made
        there and filtered by the linear structure elsewhere).
    first : int
        Column of the first-harmonic cosine coefficient within a DOF.
    synthesis : ndarray, shape (n_samples, n_coef)
        Basis functions at ``n_samples`` instants of the period.
    y, R, J, A, dX : ndarray
        Work arrays, shapes (n + 1,), (n,), (n, n + 1), (n, n), (n,); ``y``
        holds the padded point on return.

    Returns
    -------
    float
        The larger of the two relative changes (0 for a DOF at rest); inf
        if the residual or the solve fails.
    """
    n = y.size - 1
    n_coef = n // n_dof
    n_small = (x.size - 1) // n_dof
    for d in range(n_dof):
        for k in range(n_coef):
            y[d * n_coef + k] = x[d * n_small + k] if k < n_small else 0.0
    y[n] = x[x.size - 1]
    status = residual(y, problem, R, J)
    if status < 0:
        return np.inf
    for i in range(n):
        dX[i] = -R[i]
        for j in range(n):
            A[i, j] = J[i, j]
    if not solve_inplace(A, dX):
        return np.inf
    base = dof * n_coef
    c = base + first
    a1 = np.hypot(y[c], y[c + 1])
    if a1 == 0.0:
        return 0.0
    a1_new = np.hypot(y[c] + dX[c], y[c + 1] + dX[c + 1])
    worst = abs(a1_new - a1) / a1
    x_max = -np.inf
    x_min = np.inf
    dx_max = 0.0
    dx_min = 0.0
    for s in range(synthesis.shape[0]):
        xs = 0.0
        dxs = 0.0
        for k in range(n_coef):
            xs += synthesis[s, k] * y[base + k]
            dxs += synthesis[s, k] * dX[base + k]
        if xs > x_max:
            x_max = xs
            dx_max = dxs
        if xs < x_min:
            x_min = xs
            dx_min = dxs
    hpp = 0.5 * (x_max - x_min)
    e = abs(0.5 * (dx_max - dx_min)) / hpp
    if e > worst:
        worst = e
    if not np.isfinite(worst):
        return np.inf
    return worst


@jit
def truncation_changes(
    points, rows, problem, n_dof, dof, first, synthesis, y, R, J, A, dX, out
):
    """:func:`truncation_change` of several points of one branch in one
    call (one dispatch instead of one per point).

    Parameters
    ----------
    points : ndarray, shape (n_points, n_dof * n_coef_small + 1)
        ``[X, Ω]`` per point in the smaller basis.
    rows : ndarray of int64, shape (n_rows,)
        The points to evaluate.
    problem, n_dof, dof, first, synthesis, y, R, J, A, dX
        As in :func:`truncation_change`.
    out : ndarray, shape (n_rows,)
        The change of each point of ``rows`` on return.
    """
    for q in range(rows.size):
        out[q] = truncation_change(
            points[rows[q]], problem, n_dof, dof, first, synthesis, y, R, J, A, dX
        )
