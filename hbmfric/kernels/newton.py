"""Newton kernels for continuation: the bordered corrector and the tangent.

Both work on ``y = [X, Ω]`` in physical units; ``scale`` (same shape as
``y``) defines the scaled variables ``y / scale`` in which arc length,
tangents and step norms are measured, so that Ω and the amplitudes weigh
alike.
"""

import numpy as np

from .._jit import jit
from .linalg import solve_inplace
from .residual import residual

CONVERGED = 0
MAX_ITERATIONS = 1
SINGULAR = 2
NOT_FINITE = 3
AFT_FAILED = 4

MESSAGES = {
    CONVERGED: "converged",
    MAX_ITERATIONS: "Newton iteration limit reached",
    SINGULAR: "singular Jacobian",
    NOT_FINITE: "non-finite residual or update",
    AFT_FAILED: "AFT evaluation failed",
}


@jit
def _norm_inf(a):
    m = 0.0
    for x in a:
        ax = abs(x)
        if not ax <= m:  # also catches NaN
            m = ax
    return m


@jit
def correct(
    problem, y, y_pred, constraint, scale, tol_residual, tol_step, max_iter, R, J, A
):
    """Solve ``R(y) = 0`` together with ``constraint · (y - y_pred) / scale = 0``.

    With ``constraint`` the unit tangent this is the pseudo-arclength
    corrector (orthogonal to the tangent through the predictor ``y_pred``);
    with ``constraint = e_Ω`` it is Newton's method at fixed Ω.

    Contact laws make ``R`` piecewise smooth (the Jacobian jumps where the
    contact starts to slip), so full Newton steps can cycle across such a
    seam; each step is therefore backtracked until ``max |R|`` decreases.
    The constraint is linear and stays satisfied along the step.

    Parameters
    ----------
    problem : tuple
        HBM problem, see :func:`hbmfric.kernels.hbm.hbm_residual`.
    y : ndarray, shape (n + 1,)
        In: start point. Out: the last iterate (the solution on success).
    y_pred : ndarray, shape (n + 1,)
        Point the constraint hyperplane passes through.
    constraint : ndarray, shape (n + 1,)
        Normal of the constraint hyperplane, in scaled variables.
    scale : ndarray, shape (n + 1,)
        Variable scales.
    tol_residual : float
        Convergence threshold on ``max |R|``, N.
    tol_step : float
        Convergence threshold on the scaled Newton update.
    max_iter : int
        Limit on Newton iterations.
    R, J, A : ndarray
        Work arrays: shapes (n,), (n, n + 1), (n + 1, n + 1). On success
        ``J`` holds the Jacobian at the solution.

    Returns
    -------
    status : int
        ``CONVERGED`` or a failure code (see ``MESSAGES``).
    evaluations : int
        Number of residual-and-Jacobian evaluations.
    """
    n = R.size
    b = np.empty(n + 1)
    y_try = np.empty(n + 1)
    aft = residual(y, problem, R, J)
    evaluations = 1
    if aft < 0:
        return AFT_FAILED, evaluations
    res = _norm_inf(R)
    step = np.inf
    for _ in range(max_iter):
        if not np.isfinite(res):
            return NOT_FINITE, evaluations
        if res <= tol_residual and step <= tol_step:
            return CONVERGED, evaluations
        g = 0.0
        for i in range(n + 1):
            g += constraint[i] * (y[i] - y_pred[i]) / scale[i]
        for i in range(n):
            for j in range(n + 1):
                A[i, j] = J[i, j]
            b[i] = -R[i]
        for j in range(n + 1):
            A[n, j] = constraint[j] / scale[j]
        b[n] = -g
        if not solve_inplace(A, b):
            return SINGULAR, evaluations
        full = 0.0
        for i in range(n + 1):
            s = abs(b[i] / scale[i])
            if not s <= full:
                full = s
        if not np.isfinite(full):
            return SINGULAR, evaluations
        lam = 1.0
        for _ls in range(10):
            for i in range(n + 1):
                y_try[i] = y[i] + lam * b[i]
            aft = residual(y_try, problem, R, J)
            evaluations += 1
            res_try = _norm_inf(R) if aft >= 0 else np.inf
            if res_try <= tol_residual or res_try < (1.0 - 1e-4 * lam) * res:
                break
            lam *= 0.5
        if aft < 0:
            return AFT_FAILED, evaluations
        for i in range(n + 1):
            y[i] = y_try[i]
        res = res_try
        step = lam * full
    if res <= tol_residual and step <= tol_step:
        return CONVERGED, evaluations
    return MAX_ITERATIONS, evaluations


@jit
def tangent(J, previous, scale, A):
    """Unit tangent of the solution curve in scaled variables.

    Solves ``[J diag(scale); previousᵀ] t = [0; 1]`` and normalises, so that
    the new tangent keeps the direction of ``previous``.

    Parameters
    ----------
    J : ndarray, shape (n, n + 1)
        Jacobian at the point, physical units.
    previous : ndarray, shape (n + 1,)
        Previous unit tangent (scaled variables).
    scale : ndarray, shape (n + 1,)
        Variable scales.
    A : ndarray, shape (n + 1, n + 1)
        Work array.

    Returns
    -------
    ndarray, shape (n + 1,)
        The unit tangent; all NaN if the bordered matrix is singular.
    """
    n = J.shape[0]
    b = np.zeros(n + 1)
    for i in range(n):
        for j in range(n + 1):
            A[i, j] = J[i, j] * scale[j]
    for j in range(n + 1):
        A[n, j] = previous[j]
    b[n] = 1.0
    if not solve_inplace(A, b):
        b[:] = np.nan
        return b
    norm = np.sqrt(np.sum(b * b))
    return b / norm
