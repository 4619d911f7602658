"""Per-point truncation-error estimates of a branch and the AccuracyWarning
(issue: trust, item 8).

The reference for the actual error of a point is the same point solved at
H = 63 (Newton seeded by the point): the truncation error of the P1
oscillator at H = 63 is below 1e-8, far below the errors measured here.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf


def oscillator():
    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    return hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)


def actual_errors(osc, force, branch, every=1):
    """Relative first-harmonic error of branch points against H = 63."""
    idx = np.arange(0, len(branch), every)
    errors = []
    for i in idx:
        ref = hf.periodic_solution(
            osc, force, branch.omega[i], 63, initial_guess=branch.point(i)
        )
        assert ref.converged
        a = ref.amplitude(harmonic=1)
        errors.append(abs(branch.amplitude(harmonic=1)[i] - a) / a)
    return idx, np.array(errors)


@pytest.mark.parametrize("harmonics, force", [(7, 0.5), (15, 2.0)])
def test_estimate_bounds_the_actual_error(harmonics, force):
    osc = oscillator()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(osc, force, (0.5, 3.0), harmonics)
    estimate = branch.truncation_error
    assert estimate.shape == (len(branch),)
    idx, error = actual_errors(osc, force, branch, every=3)
    # the largest error along the curve is bounded by the largest estimate,
    # and the estimate is not wildly pessimistic
    assert error.max() <= estimate.max()
    assert estimate.max() <= 20 * error.max()
    # pointwise: within a factor of two at (almost) every point that matters
    big = error > 0.1 * error.max()
    assert np.mean(error[big] <= 2.0 * estimate[idx][big]) >= 0.9


def test_stuck_points_have_zero_estimate():
    # F = 0.005: at the stuck resonance (Ω = 2, amplitude F / (c Ω) = 0.125)
    # the spring force 3 * 0.125 stays below the slip force: stuck throughout
    branch = hf.frf(oscillator(), 0.005, (0.5, 3.0), 15)
    assert np.all(branch.truncation_error == 0.0)


def test_fixed_h_above_tolerance_warns_and_auto_does_not():
    osc = oscillator()
    with pytest.warns(hf.AccuracyWarning, match="harmonic_tolerance"):
        hf.frf(osc, 0.5, (0.5, 3.0), 5)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.AccuracyWarning)
        branch = hf.frf(osc, 0.5, (0.5, 3.0))  # default: harmonics="auto"
    assert branch.point_harmonics is not None
    assert branch.truncation_error.max() <= 1e-4
    # and the auto branch meets the tolerance against H = 63
    _, error = actual_errors(osc, 0.5, branch, every=4)
    assert error.max() <= 1e-4


def test_truncation_error_survives_save_and_load(tmp_path):
    branch = hf.frf(oscillator(), 0.5, (0.5, 3.0), 15)
    loaded = hf.Branch.load(branch.save(tmp_path / "b.npz"))
    np.testing.assert_array_equal(loaded.truncation_error, branch.truncation_error)
