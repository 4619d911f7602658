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
def truncation_change(x, problem, n_dof, first, synthesis, y, R, J, A, dX):
    """Relative change of the first-harmonic amplitude and of half the
    peak-to-peak value when a solution gains harmonics.

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
        Largest over the DOFs of the two relative changes, each measured
        against ``max(own value, 1e-3 × largest first harmonic)`` (DOFs that
        barely move do not dominate); inf if the residual or the solve
        fails.
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
    ref = 0.0
    for d in range(n_dof):
        c = d * n_coef + first
        a1 = np.hypot(y[c], y[c + 1])
        if a1 > ref:
            ref = a1
    if not ref > 0.0:
        return np.inf
    floor = 1e-3 * ref
    worst = 0.0
    n_samples = synthesis.shape[0]
    for d in range(n_dof):
        base = d * n_coef
        c = base + first
        a1 = np.hypot(y[c], y[c + 1])
        a1_new = np.hypot(y[c] + dX[c], y[c + 1] + dX[c + 1])
        e = abs(a1_new - a1) / max(a1, floor)
        if e > worst:
            worst = e
        x_max = -np.inf
        x_min = np.inf
        dx_max = 0.0
        dx_min = 0.0
        for s in range(n_samples):
            x = 0.0
            dx = 0.0
            for k in range(n_coef):
                x += synthesis[s, k] * y[base + k]
                dx += synthesis[s, k] * dX[base + k]
            if x > x_max:
                x_max = x
                dx_max = dx
            if x < x_min:
                x_min = x
                dx_min = dx
        hpp = 0.5 * (x_max - x_min)
        e = abs(0.5 * (dx_max - dx_min)) / max(hpp, floor)
        if e > worst:
            worst = e
    if not np.isfinite(worst):
        return np.inf
    return worst
