"""The time-integration reference names and defaults its DOFs like the HBM
results: ``ref.amplitude(harmonic=1)`` and ``sol.amplitude(harmonic=1)``
measure the same DOF (the contact DOF of the built-in systems), and names
such as ``"tip"`` work on both."""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.validation import steady_state

# the beam with a contact that never slips at this load: linear, so that the
# time integration starts on its steady state (initial_state="linear")
BEAM = hf.CantileverBeam(contact=hf.Jenkins(stiffness=1e4, slip_force=1e6))
OMEGA = 2.0 * np.pi * 30.0


@pytest.fixture(scope="module")
def reference():
    return steady_state(
        BEAM, 1.0, OMEGA, harmonics=3, steps_per_period=256, initial_state="linear"
    )


def test_default_dof_is_the_contact_dof(reference):
    c = BEAM.contact_dof
    assert c != 0
    assert reference.dof_names == BEAM.dof_names
    a = [reference.amplitude(harmonic=1, dof=d) for d in range(BEAM.n_dof)]
    assert a[c] > 0 and a[c] != a[0]
    assert reference.amplitude(harmonic=1) == a[c]
    assert reference.amplitude(harmonic=1, dof="tip") == a[c]
    assert reference.amplitude(harmonic=1, dof="contact") == a[c]
    force_dof = BEAM.dof_names["force"]
    assert reference.amplitude(harmonic=1, dof="force") == a[force_dof]
    assert reference.amplitude() == reference.amplitude(dof=c)
    _, x = reference.time_response(reference.steps_per_period)
    np.testing.assert_allclose(x, reference.samples[c], atol=1e-12 * np.abs(x).max())
    with pytest.raises(ValueError, match="dof name"):
        reference.amplitude(dof="root")


def test_hbm_and_time_integration_defaults_agree(reference):
    """The README pattern: both defaults are the same DOF, so the stuck
    (linear) amplitudes agree to the time step's error."""
    assert reference.converged
    sol = hf.periodic_solution(BEAM, 1.0, OMEGA, harmonics=3)
    assert sol.converged
    a_ref, a_hbm = reference.amplitude(harmonic=1), sol.amplitude(harmonic=1)
    # Newmark's period error at 256 steps per period: (Ωh)²/12 ≈ 5e-5
    assert abs(a_ref / a_hbm - 1.0) < 1e-3
    assert sol.amplitude(harmonic=1, dof="tip") == a_hbm
