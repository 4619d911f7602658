"""What sets the lap joint's steps through microslip (issue 15, stop 28).

On a problem condensed onto several contact coordinates the continuation
predicts along the parabola through the previous point. With the tangent's
straight line the corrector needed three residual evaluations at any step
longer than a few 1e-4 through microslip, and the Newton target held the
steps there at a tenth of the chord error the curve rule allows (587
points at N = 10 over 125-185 Hz, 258 of them within 161-167 Hz, their
median chord error 7e-6 against the tolerance 1e-4). These tests check
that the curve rule sets the steps there and that the drawn curve and the
peak stay those of a branch traced at a tenth of the tolerance.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.continuation.options import ContinuationOptions
from hbmfric.continuation.palc import Continuation
from hbmfric.kernels.steps import arclength

HZ = 2.0 * np.pi
FORCE = 36.0  # N: Fex/P = 1e-3 of the bolt's 36 kN
BAND = (HZ * 158.0, HZ * 170.0)  # through the stick-slip transition
H = 15


def _branch(curve_tolerance):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        return hf.frf(
            hf.lap_joint(10),
            FORCE,
            BAND,
            H,
            max_step=0.05,
            curve_tolerance=curve_tolerance,
        )


@pytest.fixture(scope="module")
def branches():
    return _branch(1e-4), _branch(1e-5)


def _first_harmonic(coefficients, harmonic_numbers, dof):
    k = list(harmonic_numbers).index(1)
    col = sum(1 if j == 0 else 2 for j in harmonic_numbers[:k])
    return np.hypot(coefficients[:, dof, col], coefficients[:, dof, col + 1])


def _dense(branch, per_interval=64):
    d = branch.resample(per_interval=per_interval)
    dof = branch.dof_names.get("contact", 0)
    a = _first_harmonic(d.coefficients, d.harmonic_numbers, dof)
    ok = np.isfinite(d.omega) & np.isfinite(a)
    return d.omega[ok], a[ok]


def _peak(omega, amplitude):
    """Top of the parabola through the highest sample and its neighbours."""
    j = int(np.argmax(amplitude))
    x = omega[j - 1 : j + 2] - omega[j]
    c = np.polyfit(x, amplitude[j - 1 : j + 2], 2)
    top = -c[1] / (2.0 * c[0])
    return np.polyval(c, top), omega[j] + top


def test_several_contacts_predict_along_the_parabola():
    """Condensed onto several contacts the predictor bends with the
    branch; onto one contact (the paper beam's case) it stays the
    tangent's."""
    s = hf.lap_joint(2)
    many = CondensedHBMProblem(s, FORCE, 3)
    assert many.n_coordinates > 1
    cont = Continuation(many, BAND, 1, ContinuationOptions())
    assert cont._settings[arclength.PREDICTOR] == 1.0
    off = Continuation(many, BAND, 1, ContinuationOptions(curve_tolerance=None))
    assert off._settings[arclength.PREDICTOR] == 0.0


def test_the_curve_rule_sets_the_steps_through_microslip(branches):
    """Through microslip (161-167 Hz) the chords use the curve budget: the
    median estimated chord error is at least a fifth of the tolerance (the
    rule sizes the steps for 0.8 of it; the Newton target held it at 7e-6
    before), none exceeds it, and the corrector takes under 2.8 residual
    evaluations per point (2.99 with the tangent's predictor)."""
    branch, _ = branches
    assert branch.complete
    errors = branch.curve_errors
    inside = (branch.omega[:-1] > HZ * 161.0) & (branch.omega[1:] < HZ * 167.0)
    assert inside.sum() > 10
    assert np.median(errors[inside]) >= 2e-5
    assert np.max(errors) <= 1e-4
    assert branch.newton_iterations / len(branch) < 2.8


def test_drawn_curve_and_peak_match_a_ten_times_tighter_branch(branches):
    """The straight lines between the points (the drawn curve of the contact
    DOF) stay within 1.5 times the curve tolerance of the dense output of a
    branch traced at a tenth of it (the estimate is a cubic's, good to
    about its square), and the peak of the dense output within 1e-6
    (amplitude and frequency) of that branch's."""
    branch, fine = branches
    w_ref, a_ref = _dense(fine)
    dof = branch.dof_names.get("contact", 0)
    w = branch.omega
    a = _first_harmonic(branch.coefficients, branch.harmonic_numbers, dof)
    assert np.all(np.diff(w) > 0.0)  # no fold in this band
    inside = (w_ref >= w[0]) & (w_ref <= w[-1])
    drawn = np.interp(w_ref[inside], w, a)
    error = np.max(np.abs(drawn - a_ref[inside]) / a_ref[inside])
    assert error <= 1.5e-4
    peak, where = _peak(*_dense(branch))
    peak_ref, where_ref = _peak(w_ref, a_ref)
    assert abs(peak / peak_ref - 1.0) <= 1e-6
    assert abs(where / where_ref - 1.0) <= 1e-6


def _solve_tightly(problem, y, y_pred, constraint, scale, iterations=8):
    """Plain Newton in NumPy (dense solve) on ``R(y) = 0`` with
    ``constraint · (y - y_pred) / scale = 0``, to the rounding level."""
    y = y.copy()
    for _ in range(iterations):
        R, J, aft = problem.residual(y)
        assert aft >= 0
        g = np.dot(constraint, (y - y_pred) / scale)
        A = np.vstack([J * scale, constraint])
        y += np.linalg.solve(A, -np.append(R, g)) * scale
    return y


@pytest.mark.parametrize("size", [3e-6, 1e-5])
def test_the_corrector_applies_a_contracting_last_update(size):
    """Stop 29: on a condensed problem solved by GMRES the corrector ends
    by applying an update whose error, estimated from the contraction of
    the last two, is far below ``tol_step`` (Newton is quadratic here: from
    a predictor 3e-6 to 1e-5 off the branch in scaled variables the second
    update is about 1e-8, which the plain test would check with a third
    evaluation). The point returned after two evaluations is within
    ``tol_step`` of the solution of the same bordered system found by plain
    Newton in NumPy, and its residual, evaluated there, within the
    tolerance."""
    problem = CondensedHBMProblem(hf.lap_joint(10), FORCE, H)
    options = ContinuationOptions()
    cont = Continuation(problem, BAND, 1, options)
    n = problem.n_unknowns
    omega = HZ * 164.0  # microslip
    e_omega = np.zeros(n + 1)
    e_omega[n] = 1.0
    for guess in problem.initial_guesses(omega):
        y0, status, _ = cont.solve_at(omega, guess[:n], 40)
        if status == 0:
            break
    else:
        pytest.fail("no solution at 164 Hz")
    # a predictor `size` off the branch (across the tangent: the
    # corrector's hyperplane passes through the solution)
    _, J, _ = problem.residual(y0)
    tangent = np.linalg.solve(
        np.vstack([J * cont.scale, e_omega]), np.append(np.zeros(n), 1.0)
    )
    tangent /= np.linalg.norm(tangent)
    rng = np.random.default_rng(29)
    off = rng.standard_normal(n + 1)
    off -= np.dot(off, tangent) * tangent
    off *= size / np.max(np.abs(off))
    y_pred = y0 + off * cont.scale
    y = y_pred.copy()
    status, evaluations = cont._correct(y, y_pred, tangent)
    assert status == 0
    assert evaluations == 2  # 3 before stop 29
    exact = _solve_tightly(problem, y, y_pred, tangent, cont.scale)
    assert np.max(np.abs(y - exact) / cont.scale) <= options.tol_step
    R, J, _ = problem.residual(y)
    floor = 8.0 * np.finfo(float).eps * np.max(np.abs(J) @ np.abs(y))
    tol = max(cont.tol_residual, floor, problem.kernel_problem.rounding[0])
    assert np.max(np.abs(R)) <= tol


def test_every_point_of_the_branch_solves_its_equations():
    """Stop 29: with the last update applied unevaluated, every point the
    continuation returns through microslip (N = 10, 158-170 Hz, most of
    them ended so) still has its residual, evaluated there, within the
    corrector's tolerance, and plain Newton in NumPy across the branch (on
    the hyperplane through the point orthogonal to its tangent) moves it by
    less than ``tol_step`` in scaled variables."""
    problem = CondensedHBMProblem(hf.lap_joint(10), FORCE, H)
    options = ContinuationOptions(max_step=0.05)
    cont = Continuation(problem, BAND, 1, options)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        state, _ = cont.run()
    points = np.array(state.points)
    assert len(points) > 100
    assert state.n_newton / len(points) < 2.4  # 2.6 before stop 29
    tangents = np.array(state.tangents) / cont.scale
    worst_residual = worst_move = 0.0
    for y, t in zip(points, tangents, strict=True):
        R, J, _ = problem.residual(y)
        floor = 8.0 * np.finfo(float).eps * np.max(np.abs(J) @ np.abs(y))
        tol = max(cont.tol_residual, floor, problem.kernel_problem.rounding[0])
        worst_residual = max(worst_residual, np.max(np.abs(R)) / tol)
        exact = _solve_tightly(problem, y, y, t / np.linalg.norm(t), cont.scale, 3)
        worst_move = max(worst_move, np.max(np.abs(exact - y) / cont.scale))
    assert worst_residual <= 1.0
    assert worst_move <= options.tol_step
