"""A point at the onset of slip that ``harmonics="auto"`` must solve again
with more harmonics (found by trying the library as a new user would).

On a three-DOF chain with a Jenkins contact between DOFs 1 and 2 the
adaptive run reached the onset of slip at H = 5 and asked for H = 31 there;
Newton from the H = 5 solution needed 37 iterations at that non-smooth
point, more than the budget, so the point was kept at H = 5 with an
estimated truncation error of 0.031 and a warning that blamed the top of the
harmonic ladder. The point is now solved again with the first point's
iteration budget.
"""

import warnings

import numpy as np

import hbmfric as hf
from hbmfric.errors import AccuracyWarning
from hbmfric.validation import steady_state


def _chain() -> hf.LinearStructure:
    mass = np.eye(3)
    stiffness = np.array(
        [[2000.0, -1000.0, 0.0], [-1000.0, 2000.0, -1000.0], [0.0, -1000.0, 1000.0]]
    )
    law = hf.Jenkins(stiffness=2000.0, slip_force=1.0)
    return hf.LinearStructure(
        mass,
        stiffness,
        modal_damping=0.01,
        load={0: 1.0},
        contacts=[hf.Contact(law, 1, other=2)],
    )


def test_onset_point_is_solved_again_higher():
    system = _chain()
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)
        branch = hf.frf(system, 5.0, (8.0, 25.0))
    assert np.max(branch.truncation_error) <= 1e-4
    # the onset of slip: the first point above H = 3 (the stuck stretch is
    # linear, solved at the lowest rung)
    onset = int(np.argmax(branch.point_harmonics > 3))
    omega = float(branch.omega[onset])
    assert 10.5 < omega < 11.5
    reference = steady_state(system, 5.0, omega)
    for dof in range(3):
        got = branch.amplitude(harmonic=1, dof=dof)[onset]
        want = reference.amplitude(harmonic=1, dof=dof)
        assert abs(got - want) <= 1e-4 * want, (dof, got, want)
