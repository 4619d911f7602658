"""A harmonic level made by ``with_harmonics`` estimates with its own level
(stop 31b hunt).

``HBMProblem.with_harmonics`` makes a level by a shallow copy, and the
truncation estimate kept its levels (columns, weights, probe level) in the
problem's ``__dict__``: a level copied from a problem that had already been
estimated measured its points with the original's level. The auto ``frf``
makes its levels from the ``H = 7`` one, and the final pass estimates that
level before it solves points again at levels the run had not visited.
On the 2-DOF 2D-contact rig loaded normally (``tests/test_hunt_contact2d_normal.py``),
110-140 rad/s, the final estimates read up to 2.0e-3 at ``H = 63`` (the
warning's worst, 128.1 rad/s) where each point's own estimate is at most
1.2e-4, and 1.5e-6 at ``H = 21`` (130.8 rad/s) where its own is 3.4e-4.

References: the estimate of a problem built afresh at the same ``H`` (an
independent build of the level), and the ``H = 63`` solution for the true
error.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_hunt_contact2d_normal import _rig

import hbmfric as hf
from hbmfric.api import _problem
from hbmfric.continuation.accuracy import (
    truncation_errors,
    watched_truncation_errors,
)

TOL = 1e-4


def _level(system, force, h):
    return _problem(system, force, h, None, None, "auto", None)


def _solve(system, force, omega, h):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        sol = hf.periodic_solution(system, force, omega, harmonics=h)
    assert sol.converged
    return sol


def _point(sol):
    return np.concatenate([sol.coefficients.ravel(), [sol.omega]])[None]


def test_copied_level_estimates_the_normal_dof_as_a_fresh_one():
    omega = 130.8
    base = _level(_rig(), 1.0, 7)
    watched_truncation_errors(base, _point(_solve(_rig(), 1.0, omega, 7)))
    sol = _solve(_rig(), 1.0, omega, 21)
    copied = watched_truncation_errors(base.with_harmonics(21), _point(sol))[0]
    fresh = watched_truncation_errors(_level(_rig(), 1.0, 21), _point(sol))[0]
    exact = _solve(_rig(), 1.0, omega, 63).amplitude(harmonic=1, dof="y")
    true = abs(sol.amplitude(harmonic=1, dof="y") / exact - 1.0)
    assert true > TOL  # H = 21 misses the tolerance here ...
    assert copied == pytest.approx(fresh, rel=1e-12)
    assert copied >= true  # ... and the estimate says so (main: 4.6e-5)


def test_copied_level_estimates_the_contact_dof_as_a_fresh_one():
    osc = hf.Oscillator(
        mass=1.0,
        damping=0.02,
        stiffness=1.0,
        contact=hf.Jenkins(stiffness=3.0, slip_force=1.0),
    )
    base = _level(osc, 0.5, 7)
    truncation_errors(base, _point(_solve(osc, 0.5, 2.0, 7)))
    point = _point(_solve(osc, 0.5, 2.0, 21))
    copied = truncation_errors(base.with_harmonics(21), point)[0]
    fresh = truncation_errors(_level(osc, 0.5, 21), point)[0]
    assert fresh > 0.0
    assert copied == pytest.approx(fresh, rel=1e-12)  # main: 3.1e-6 / 2.9e-7


@pytest.mark.slow
def test_auto_branch_final_estimates_are_each_points_own():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = hf.frf(_rig(), 1.0, (110.0, 140.0))
    scale = branch.info["amplitude_scale"]
    worst = 0.0
    for h in np.unique(branch.point_harmonics):
        idx = np.flatnonzero(branch.point_harmonics == h)
        p = _level(_rig(), 1.0, int(h))
        pts = np.concatenate(
            [
                branch.coefficients[idx, :, : p.n_coef].reshape(len(idx), -1),
                branch.omega[idx, None],
            ],
            axis=1,
        )
        own = np.array(
            [
                watched_truncation_errors(p, x[None], amplitude_scale=scale)[0]
                for x in pts
            ]
        )
        worst = max(worst, float(own.max()))
        # every point of the final pass is calibrated or carried under the
        # tolerance; a carried one may read higher than its own, never a
        # calibrated one lower
        got = branch.truncation_error[idx]
        over = own > TOL
        assert np.allclose(got[over], own[over], rtol=1e-9), h
    assert np.max(branch.truncation_error) == pytest.approx(worst, rel=1e-9)
    if worst > TOL:
        assert any(issubclass(w.category, hf.AccuracyWarning) for w in caught)
