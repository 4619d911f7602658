"""Stability of hysteretic contacts on several DOFs: Hill's linearisation
against the time-domain monodromy and time integration.

Hill's method linearises the AFT force along the periodic motion, which
for a hysteretic law is exact only where an exponent crosses zero. On the
paper beam (39 DOFs, Jenkins tip contact, Fn = 5 N, Fex = 2 N) it reads the
slipping resonance unstable (|μ| 2.5-7.3 along 80-93 Hz), while the
monodromy of the time-integration reference finds 0.69-0.94 and time
integration settles on the solution. ``stability()`` therefore uses the
monodromy for a contact with memory on several DOFs (``method="auto"``).
"""

import warnings

import numpy as np
import pytest
from stability_cases import friction_duffing

import hbmfric as hf
from hbmfric.paper.beam import HZ, paper_beam, paper_calibration
from hbmfric.signals import state_at_zero
from hbmfric.validation import monodromy, steady_state


@pytest.fixture(scope="module")
def beam():
    return paper_beam(5.0, paper_calibration())


def test_slipping_beam_is_stable(beam):
    """At 87 Hz the contact slips. Before the automatic choice,
    ``sol.stable`` was Hill's False; time integration started on the
    solution, nudged by 1e-3, settles back on it (first harmonic of the
    tip within 1e-3)."""
    omega = 87.0 * HZ
    sol = hf.periodic_solution(beam, 2.0, omega, harmonics=7)
    assert sol.contact_state == "contact slips during the period"
    assert not sol.stability(method="hill").stable[0]  # Hill's misreading
    stab = sol.stability()
    assert stab.criterion == "monodromy"
    assert sol.stable
    assert 0.5 < np.abs(stab.multipliers[0]).max() < 0.95
    x0, v0 = state_at_zero(sol.harmonic_numbers, sol.coefficients, omega)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.ConvergenceWarning)
        ref = steady_state(
            beam, 2.0, omega, initial_state=(x0 * (1.0 + 1e-3), v0), tol=1e-9
        )
    tip = beam.contact_dof
    a = sol.amplitude(harmonic=1, dof=tip)
    assert abs(ref.amplitude(harmonic=1, dof=tip) - a) < 1e-3 * a


@pytest.mark.slow
def test_branch_stability_uses_the_monodromy(beam):
    """A stretch of the beam's branch through the slipping resonance: every
    point stable by the automatic choice, equal to the monodromy computed
    point by point; Hill reads the slipping points unstable."""
    branch = hf.frf(beam, 2.0, (84.0 * HZ, 90.0 * HZ), harmonics=3)
    stab = branch.stability()
    assert stab.criterion == "monodromy"
    assert stab.stable.all()
    for i in (0, len(branch) // 2, len(branch) - 1):
        td = monodromy(beam, branch.point(i))
        np.testing.assert_allclose(
            np.sort(np.abs(stab.multipliers[i])), np.sort(np.abs(td.multipliers))
        )
    hill = branch.stability(method="hill")
    assert not hill.stable.any()


@pytest.mark.parametrize(("stiffness", "force"), [(3.0, 0.5), (3.0, 2.0), (30.0, 1.0)])
def test_one_dof_jenkins_keeps_hill_and_agrees_with_the_monodromy(stiffness, force):
    """On one DOF the automatic choice is Hill's method, and its verdict
    equals the time-domain monodromy's at every 8th point (measured: all
    351 points of four such branches agree)."""
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=stiffness, slip_force=1.0))
    branch = hf.frf(osc, force, (0.5, 3.0 * np.sqrt(stiffness / 3.0)), harmonics=15)
    stab = branch.stability()
    assert stab.criterion == "imaginary"
    td = branch.stability(method="monodromy")
    assert td.criterion == "monodromy"
    np.testing.assert_array_equal(td.stable[::8], stab.stable[::8])


def test_menq_on_several_dofs_warns():
    """Where the monodromy cannot be formed (Menq's state is a history),
    Hill is used and says its verdict is approximate."""
    law = hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0)
    chain = hf.LinearStructure(
        np.eye(2),
        np.array([[2.0, -1.0], [-1.0, 1.0]]),
        0.02 * np.eye(2),
        load={0: 1.0},
        contact=law,
        contact_dof=1,
    )
    sol = hf.periodic_solution(chain, 0.5, 1.0, harmonics=5)
    with pytest.warns(hf.AccuracyWarning, match="approximate"):
        stab = sol.stability()
    assert stab.criterion == "imaginary"


def test_method_is_checked():
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Cubic(0.1))
    sol = hf.periodic_solution(osc, 0.2, 1.0, harmonics=5)
    with pytest.raises(ValueError, match="method"):
        sol.stability(method="floquet")


@pytest.mark.stress
@pytest.mark.parametrize("normal_load", [1.0, 2.0, 10.0])
def test_stress_beam_verdicts_against_time_integration(normal_load):
    """Stress: the beam at other normal loads; at 4 points of the branch
    (stuck and slipping) the automatic verdict against time integration
    started on the solution nudged by 1e-3: a stable verdict must settle
    back (first harmonic of the tip within 2e-3, or three times the
    point's truncation estimate), an unstable one must
    leave."""
    beam = paper_beam(normal_load, paper_calibration())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(beam, 2.0, (15.0 * HZ, 110.0 * HZ), harmonics=5)
    tip = beam.contact_dof
    for i in np.linspace(0, len(branch) - 1, 6).round().astype(int)[1:-1]:
        sol = branch.point(int(i))
        x0, v0 = state_at_zero(sol.harmonic_numbers, sol.coefficients, sol.omega)
        with warnings.catch_warnings(record=True):
            warnings.simplefilter("always", hf.ConvergenceWarning)
            ref = steady_state(
                beam,
                2.0,
                sol.omega,
                initial_state=(x0 * (1.0 + 1e-3), v0),
                tol=1e-9,
                max_periods=4000,
            )
        a = sol.amplitude(harmonic=1, dof=tip)
        # the reference converges to the exact solution, the point is H = 5's
        allowance = max(2e-3, 3.0 * float(branch.truncation_error[i]))
        settled = ref.converged and abs(ref.amplitude(1, dof=tip) - a) < allowance * a
        assert settled == bool(sol.stable), (normal_load, sol.omega / HZ)


def test_snap_to_folds_moves_a_nearby_change_onto_the_fold():
    from hbmfric.results import _snap_to_folds

    stable = np.array([True] * 10 + [False] * 10)
    _snap_to_folds(stable, np.array([7]))  # change at 10, fold at 7
    np.testing.assert_array_equal(stable, [True] * 7 + [False] * 13)
    stable = np.array([True] * 10 + [False] * 10)
    _snap_to_folds(stable, np.array([13]))  # fold after the change
    np.testing.assert_array_equal(stable, [True] * 13 + [False] * 7)
    stable = np.array([True] * 10 + [False] * 10)
    _snap_to_folds(stable, np.array([40]))  # far: untouched
    np.testing.assert_array_equal(stable, [True] * 10 + [False] * 10)


@pytest.mark.slow
def test_two_dof_friction_duffing_changes_at_the_folds():
    """A Duffing with a Jenkins contact and a light second mass (two DOFs:
    the monodromy decides): its stability changes next to the two folds,
    within the monodromy's error near a fold (at the first fold, and 4
    points, 6e-6 rad/s, past the second, where the computed multipliers
    read 1.0043, 1.0013, 1.0004; 1.0040, 1.0017, 0.9997 at 16 times the
    steps per period).
    Every computed point keeps its own multipliers' verdict (issue 16,
    stop 27: the snap onto the fold no longer overrides them), and every
    point agrees with Hill, exact at folds, except between a fold and the
    change next to it."""
    from hbmfric.results import FOLD_SNAP
    from hbmfric.stability import NEUTRAL_TOLERANCE

    structure = friction_duffing(second_mass=0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(structure, 0.2, (0.5, 2.5), harmonics=15)
    assert branch.folds.size == 2
    stab = branch.stability()
    assert stab.criterion == "monodromy"
    done = np.flatnonzero(stab.computed)
    own = np.abs(stab._multipliers[done]).max(axis=1) <= 1.0 + NEUTRAL_TOLERANCE
    np.testing.assert_array_equal(stab.stable[done], own)
    changes = stab.changes()
    assert changes.size == 2
    between = np.zeros(len(branch), dtype=bool)
    for c, f in zip(changes, branch.folds, strict=True):
        assert abs(int(c) - int(f)) <= FOLD_SNAP
        assert abs(branch.omega[c] - branch.omega[f]) <= 5e-5 * branch.omega[f]
        between[min(c, f) : max(c, f)] = True
    # each change is its fold's (located on the monodromy 4 points past
    # the second fold, it read as a separate "branch point" before the
    # merge of bifurcation._fold_changes_on_monodromy)
    points = branch.special_points()
    assert [p.kind for p in points] == ["fold", "fold"]
    for p in points:
        assert p.stability_omega is not None
        assert abs(p.stability_omega - p.omega) <= 5e-5 * p.omega
    hill = branch.stability(method="hill")
    assert not (hill.stable != stab.stable)[~between].any()
    c0, c1 = changes
    assert not stab.stable[c0:c1].any()
    assert stab.stable[:c0].all() and stab.stable[c1:].all()
