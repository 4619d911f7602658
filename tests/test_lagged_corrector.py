"""The corrector's confirming evaluation with the previous iterate's LU
factors (:func:`hbmfric.kernels.steps.newton.correct_core`, issue 18, stop
29): the point the plain corrector accepts, and a tangent equal to the one
of a fresh factorisation at that point."""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.residuals.pointer import residual_address
from hbmfric.kernels.steps import newton

#: P1 (bench/p1_defaults.py) in gross slip
FORCE = 2.0
HARMONICS = 21
RANGE = (0.5, 3.0)


def _p1():
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


@pytest.fixture(scope="module")
def branch():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        return hf.frf(_p1(), FORCE, RANGE, HARMONICS)


def _scale(branch, n):
    """The continuation's variable scales (:class:`hbmfric.Branch`)."""
    return np.r_[np.full(n, branch.info["amplitude_scale"]), RANGE[1] - RANGE[0]]


def _null_direction(J, scale):
    """Unit null vector of ``J diag(scale)`` (the exact tangent direction in
    scaled variables), by SVD: independent of the corrector's solves."""
    return np.linalg.svd(J * scale)[2][-1]


def _run(problem, y_pred, t_prev, scale, lag):
    n = problem.n_unknowns
    y = y_pred.copy()
    R = np.empty(n)
    J = np.empty((n, n + 1))
    A = np.empty((n + 1, n + 1))
    piv = np.empty(n + 1, dtype=np.int64)
    rows = np.empty(n)
    out = newton.correct_core(
        problem.kernel_problem,
        residual_address(problem.kernel_problem),
        y,
        y_pred,
        t_prev,
        scale,
        1e-10 * FORCE,
        1e-9,
        12,
        R,
        J,
        A,
        piv,
        rows,
        np.bool_(lag),
    )
    return out, y, J, A, piv, rows


@pytest.mark.parametrize("index", [40, 200, 330])
def test_lagged_confirmation_accepts_the_plain_point_with_its_tangent(branch, index):
    problem = HBMProblem(_p1(), FORCE, HARMONICS)
    n = problem.n_unknowns
    scale = _scale(branch, n)
    y0 = np.r_[branch.coefficients[index].reshape(-1), branch.omega[index]]
    t0 = branch.tangents[index] / scale
    t0 /= np.linalg.norm(t0)
    # a short tangent step: the first update is far below LAG_MAX but
    # above tol_step, so a confirming evaluation follows it
    y_pred = y0 + 1e-4 * t0 * scale
    plain, y_plain, J_plain, A_plain, piv_plain, _ = _run(
        problem, y_pred, t0, scale, False
    )
    lagged, y_lag, J_lag, A_lag, piv_lag, rows = _run(problem, y_pred, t0, scale, True)
    assert plain[0] == lagged[0] == newton.CONVERGED
    assert plain[1:3] == lagged[1:3]  # evaluations and effort
    assert not plain[3] and lagged[3]  # the lagged run reused the factors
    np.testing.assert_array_equal(y_lag, y_plain)  # the same point
    R, J, _ = problem.residual(y_lag)
    assert np.max(np.abs(R)) <= 1e-10 * FORCE
    t_plain = np.empty(n + 1)
    assert newton.tangent_from_lu(A_plain, piv_plain, t_plain)
    # the tangent of the reused factors alone, then refined
    t_stale = np.empty(n + 1)
    assert newton.tangent_from_lu(A_lag, piv_lag, t_stale)
    t_lag = np.empty(n + 1)
    assert newton.lagged_tangent(J_lag, scale, t0, A_lag, piv_lag, rows, t_lag)
    exact = _null_direction(J, scale)
    exact *= np.sign(exact @ t_plain)
    assert np.max(np.abs(t_lag - t_plain)) <= 1e-11
    assert np.max(np.abs(t_lag - exact)) <= 1e-9
    assert np.max(np.abs(t_stale - exact)) > 10.0 * np.max(np.abs(t_lag - exact))


def test_branch_tangents_are_the_null_directions_at_the_points(branch):
    """Every tangent of a fixed-H branch (most points confirmed with the
    previous iterate's factors) is the null direction of the Jacobian at
    its point, and every point is within the residual tolerance. Stale
    tangents, not refined, were up to 1.6e-5 rad off here."""
    problem = HBMProblem(_p1(), FORCE, HARMONICS)
    n = problem.n_unknowns
    scale = _scale(branch, n)
    worst_angle = 0.0
    worst_residual = 0.0
    for i in range(len(branch)):
        y = np.r_[branch.coefficients[i].reshape(-1), branch.omega[i]]
        R, J, _ = problem.residual(y)
        worst_residual = max(worst_residual, np.max(np.abs(R)))
        t = branch.tangents[i] / scale
        t /= np.linalg.norm(t)
        c = abs(t @ _null_direction(J, scale))
        worst_angle = max(worst_angle, np.sqrt(max(0.0, 1.0 - min(c, 1.0) ** 2)))
    assert worst_residual <= 1e-10 * FORCE
    # 1.5e-8: what sqrt(1 - c²) resolves
    assert worst_angle <= 1e-7
