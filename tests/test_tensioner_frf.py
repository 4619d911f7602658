"""``hf.frf`` on the belt-tensioner rig: the common engine path (defaults,
coverage, DOF names) against an independent time-domain reference."""

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem, can_condense
from hbmfric.systems.tensioner_response import branch_tension_range, time_domain_frf
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
