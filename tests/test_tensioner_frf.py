"""``hf.frf`` on the belt-tensioner rig: the common engine path (defaults,
coverage, DOF names) against an independent time-domain reference."""

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem, can_condense
from hbmfric.continuation import ContinuationOptions
from hbmfric.systems.tensioner_response import (
    branch_tension_range,
    hbm_frf,
    time_domain_frf,
)
from hbmfric.systems.tensioner_shooting import shooting_steady_state, state_at_zero

RIG = hf.BeltTensioner()
BAND_HZ = (5.0, 100.0)
BAND = (2.0 * math.pi * BAND_HZ[0], 2.0 * math.pi * BAND_HZ[1])


@pytest.fixture(scope="module")
def default_branch():
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        warnings.simplefilter("error", hf.AccuracyWarning)
        return hf.frf(RIG, 20.0, BAND)


def test_frf_covers_the_band_at_default_settings(default_branch):
    branch = default_branch
    assert branch.complete and len(branch) > 50
    assert branch.coefficients.shape[1] == 2
    assert branch.info["harmonics"] == "auto"
    # the DOF names of the rig, the pulley (u2) by default
    np.testing.assert_array_equal(branch.amplitude(1, "pulley"), branch.amplitude(1))
    assert not np.array_equal(branch.amplitude(1, "shaker"), branch.amplitude(1))


def test_rig_held_only_by_its_tensioner_is_not_condensed():
    # K of the belt alone is singular (the rig floats without the
    # tensioner): no static receptance, so no condensation
    assert not can_condense(RIG)
    with pytest.raises(ValueError, match="rigid-body mode"):
        CondensedHBMProblem(RIG, 20.0, harmonics=5)


def _reference_at(branch, index, force):
    """Shooting reference at a branch point, started on its branch."""
    start = state_at_zero(
        RIG, branch.harmonic_numbers, branch.coefficients[index], branch.omega[index]
    )
    ref = shooting_steady_state(
        RIG, force, branch.omega[index] / (2.0 * math.pi), start
    )
    assert ref.converged and ref.stable
    return np.array([ref.tension_range, *ref.first_harmonic])


def _hbm_values(branch, index):
    tension = branch_tension_range(RIG, branch)[index]
    return np.array(
        [
            tension,
            branch.amplitude(1, "shaker")[index],
            branch.amplitude(1, "pulley")[index],
        ]
    )


def test_shooting_reference_matches_linear_closed_form():
    """Vanishing loops: the rig is linear with the small-loop stiffness
    ``β (b − e)/2`` at the pulley (the loop dissipation is of relative
    order ``β X`` = 1e-5 at f1 = 1 mN)."""
    f1, fhz = 1e-3, 30.0
    ref = shooting_steady_state(RIG, f1, fhz, transient_periods=0)
    M, C, K = RIG.matrices()
    K = K.copy()
    K[1, 1] += RIG.small_loop_stiffness()
    w = 2.0 * math.pi * fhz
    x = np.linalg.solve(K - w**2 * M + 1j * w * C, RIG.load_vector(f1))
    np.testing.assert_allclose(ref.first_harmonic, np.abs(x), rtol=2e-5)
    np.testing.assert_allclose(ref.mean, RIG.static_solution(), rtol=1e-9)
    dv = 1j * w * (x[0] - x[1])
    tension = abs(RIG.belt_stiffness * (x[0] - x[1]) + RIG.belt_damping * dv)
    assert ref.tension_range == pytest.approx(2.0 * tension, rel=2e-5)


def test_shooting_reference_agrees_with_the_jit_integrator():
    """Two independent time integrations of the rig: the JIT Newmark
    scheme's error falls (at least 3x per halved step) towards the shooting
    orbit."""
    ref = shooting_steady_state(RIG, 20.0, 41.0, transient_periods=10)
    errors = []
    for steps in (512, 1024):
        td = time_domain_frf(
            RIG, 20.0, [41.0], "jit", steps_per_period=steps, tol=1e-10
        )
        assert td.converged.all()
        errors.append(abs(td.tension_range[0] / ref.tension_range - 1.0))
    assert errors[1] < 1e-5 and errors[1] < errors[0] / 3.0


def test_default_branch_matches_the_reference(default_branch):
    """Default ``hf.frf`` within 1e-4 of the shooting reference (tension
    range, first harmonic of both DOFs) where the sampled Dahl AFT at the
    former 16 H samples was 1e-4 off (41 Hz) and near the resonance at one
    third of the stuck one and above both resonances."""
    branch = default_branch
    f = branch.omega / (2.0 * math.pi)
    for target in (13.7, 41.2, 92.0):
        i = int(np.argmin(np.abs(f - target)))
        np.testing.assert_allclose(
            _hbm_values(branch, i), _reference_at(branch, i, 20.0), rtol=1e-4
        )


def _check_tension_frf(curve, force, n, rtol):
    """``n`` points of a :class:`TensionFRF` against the shooting reference."""
    branch = curve.info["branch"]
    nu = curve.info["subharmonic"]
    np.testing.assert_allclose(
        curve.frequency, nu * branch.omega / (2.0 * math.pi), rtol=1e-14
    )
    for i in np.linspace(0, len(branch) - 1, n).astype(int):
        start = state_at_zero(
            RIG, branch.harmonic_numbers, branch.coefficients[i], branch.omega[i]
        )
        ref = shooting_steady_state(RIG, force, curve.frequency[i], start)
        assert ref.converged
        assert curve.tension_range[i] == pytest.approx(ref.tension_range, rel=rtol)


def test_hbm_frf_paper_settings_against_the_reference():
    """``hbm_frf`` (now a layer over ``hf.frf``) with the settings of the
    paper's Fig. 5 before this change (H = 15, max_step 0.03), f1 = 5 N:
    the tension range within 1e-4 of the reference (3.6e-5 measured)."""
    curve = hbm_frf(RIG, 5.0, BAND_HZ, 15, options=ContinuationOptions(max_step=0.03))
    assert curve.method == "hbm" and curve.info["harmonics"] == 15
    assert isinstance(curve.info["branch"], hf.Branch)
    assert curve.info["stop_reason"] == "end of frequency range reached"
    _check_tension_frf(curve, 5.0, 5, 1e-4)


def test_subharmonic_hbm_frf_against_the_reference():
    """ν = 3 (the paper's resonance at one third of the stuck one) through
    the common path: 15 harmonics of Ω, within 2e-4 of the reference
    (1.2e-4 measured, truncation)."""
    curve = hbm_frf(RIG, 20.0, (12.0, 16.0), harmonics=45, subharmonic=3)
    assert curve.method == "hbm/3"
    assert curve.info["branch"].truncation_error is None
    _check_tension_frf(curve, 20.0, 3, 2e-4)
    with pytest.raises(ValueError, match="fixed number of harmonics"):
        hbm_frf(RIG, 20.0, (12.0, 16.0), subharmonic=3)


@pytest.mark.slow
@pytest.mark.parametrize(
    "force",
    [
        2.0,
        5.0,
        20.0,
        50.0,
    ],
)
def test_default_branch_against_the_reference_over_the_band(force):
    """The paper's Fig. 5 amplitudes at default settings: every 4th point of
    the whole branch (>= 20 frequencies over 5-100 Hz, the resonances
    included) within 1e-4 of the reference (``bench/tensioner_reference``
    checks every point)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        warnings.simplefilter("error", hf.AccuracyWarning)
        branch = hf.frf(RIG, force, BAND)
    index = np.arange(0, len(branch), 4)
    assert index.size >= 20
    tension = branch_tension_range(RIG, branch)
    peak = int(np.argmax(tension))
    for i in np.unique(np.append(index, peak)):
        np.testing.assert_allclose(
            _hbm_values(branch, i), _reference_at(branch, i, force), rtol=1e-4
        )


def test_default_branch_near_the_fifth_superharmonic_at_5n():
    """At 5 N the default run traced 5-8.5 Hz at H = 11 (one stretch of
    that level; the level came back at 15 Hz and 32-37 Hz). The estimate
    of the final pass carried the ratio to the free measure across those
    stretches (0.014 from 5 Hz where it is 0.23-0.47 at 8.3-8.5 Hz), read
    1e-5-2e-5 and let the tension range stand 2.5e-4 off the reference.
    Now a ratio is carried only within a stretch: every point over
    7.5-9.5 Hz within 1e-4 of the shooting reference. (Since the run aims
    at 0.7 of the tolerance it traces this stretch at H = 21, with steps
    of about 0.5 Hz: 7e-6 at worst.)"""
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        warnings.simplefilter("error", hf.AccuracyWarning)
        branch = hf.frf(RIG, 5.0, BAND)
    f = branch.omega / (2.0 * math.pi)
    index = np.flatnonzero((f > 7.5) & (f < 9.5))
    assert index.size >= 3
    for i in index:
        np.testing.assert_allclose(
            _hbm_values(branch, i), _reference_at(branch, i, 5.0), rtol=1e-4
        )


def test_warnings_point_at_the_callers_line():
    """The engine's warnings name the user's call, not a line of api.py
    (fixed H and "auto" go through one more helper than before)."""
    with pytest.warns(hf.AccuracyWarning) as record:
        hf.frf(RIG, 20.0, BAND, 7)
    assert {w.filename for w in record} == {__file__}


def test_estimate_bounds_the_tension_error_near_its_antiresonance():
    """Above both resonances the tension's first harmonic nearly vanishes
    (``u1 ≈ u2``; 0.03 N of 2 N forcing near 93 Hz) and its relative
    truncation error grows 30-250 times the pulley's. The estimate of the
    default branch (which watches the tension, free measure included)
    is never below the tension range's true error by more than 2x (the
    criterion of the estimates, issue 18) at every point where that error
    exceeds 1e-5 (measured 0.98-1.8 times it; 0.98 at one point after the
    curve rule's points' budget moved the points); the contact DOF's free
    measure carried a ratio that put the estimate 3 times below the true
    error (6.4e-6 against 2.0e-5 near 90 Hz)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        warnings.simplefilter("error", hf.AccuracyWarning)
        branch = hf.frf(RIG, 2.0, (2.0 * math.pi * 85.0, 2.0 * math.pi * 100.0))
    tension = branch_tension_range(RIG, branch)
    checked = 0
    for i in range(len(branch)):
        true = abs(tension[i] / _reference_at(branch, i, 2.0)[0] - 1.0)
        assert true <= 1e-4
        if true > 1e-5:
            assert branch.truncation_error[i] >= 0.5 * true
            checked += 1
    assert checked >= 2


def test_fresh_estimate_bounds_the_tension_error_at_h7_near_41hz(monkeypatch):
    """At 2 N, H = 7, 40.5-41.5 Hz the tension range's true error rises
    smoothly from 2.6e-5 to 4.4e-5. The calibrated estimate read the change
    of the output's extremes at the nearest of 64 samples, where the change
    (harmonics up to 15) turns by up to 0.7 rad within one spacing: it swung
    between 2e-6 and 1.2e-4 every 4 points (10 times under the true error at
    every fourth point). Read at the extremes' instants it is 1.7-1.9 times
    the true error at every point; calibrated at every point here."""
    from hbmfric.continuation import accuracy

    monkeypatch.setattr(accuracy, "EVERY", 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(RIG, 2.0, (2.0 * math.pi * 40.5, 2.0 * math.pi * 41.5), 7)
    assert len(branch) >= 12
    tension = branch_tension_range(RIG, branch)
    index = np.arange(0, len(branch), max(1, len(branch) // 12))
    for i in index:
        true = abs(tension[i] / _reference_at(branch, i, 2.0)[0] - 1.0)
        assert true > 1e-5  # slipping: an error to bound
        assert true <= branch.truncation_error[i] <= 4.0 * true
