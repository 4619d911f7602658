"""The time-integration reference with several contacts and the 2D element
(``hf.validation.steady_state`` through
:mod:`hbmfric.validation.multi_integrator`), against an explicit time
march written in the tests, against its own single-contact path, and
against the harmonic balance."""

import numpy as np
import pytest
from test_contact2d import OSC, OSC_ELEMENT, _first_harmonic, _integrate

import hbmfric as hf
from hbmfric.systems.protocol import check_system
from hbmfric.validation.problems import SeveralContacts


def _rig(element):
    o = OSC
    return hf.LinearStructure(
        np.diag([o["m"], o["my"]]),
        np.diag([o["k"], o["ky"]]),
        np.diag([o["c"], o["cy"]]),
        load={"x": o["fx"], "y": o["py"]},
        static_load={"y": element.preload},
        contacts=[hf.Contact(element, "x", normal="y")],
        dof_names={"x": 0, "y": 1},
    )


@pytest.mark.parametrize(
    "element, omega",
    [
        (OSC_ELEMENT, 50.0),  # stuck
        (OSC_ELEMENT, 150.0),  # slips and separates
        (OSC_ELEMENT.with_preload(-2.0), 100.0),  # open at rest, closes
    ],
)
def test_2d_element_against_an_explicit_march(element, omega):
    """The implicit Newmark reference with the 2D element against the
    velocity-Verlet march of ``tests/test_contact2d.py`` (re-closure located
    between steps there, at the step here): first harmonics of both DOFs
    within 1e-4 at 4096 steps per period (measured 1e-8 to 2e-5 at 8192)."""
    rig = _rig(element)
    ref = hf.validation.steady_state(
        rig, 1.0, omega, steps_per_period=4096, tol=1e-9, initial_state="linear"
    )
    assert ref.converged, ref.message
    osc = np.array([OSC[k] for k in ("m", "k", "c", "my", "ky", "cy", "fx", "py")])
    steps = 8192
    march = _integrate(
        element.params, osc, omega, steps, int(np.ceil(40 * omega / (2 * np.pi)))
    )
    for dof in range(2):
        expected = np.hypot(*_first_harmonic(march[dof, steps:]))
        assert ref.amplitude(1, dof) == pytest.approx(expected, rel=1e-4)


def _chain():
    """Three masses, a Jenkins contact to ground on the first and a Menq
    contact between the second and third."""
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    return hf.LinearStructure(
        np.eye(3),
        K,
        modal_damping=0.02,
        load={2: 1.0},
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.2), 0),
            hf.Contact(hf.Menq.from_stiffness(stiffness=2.0, slip_force=0.1), 1, 2),
        ],
    )


def test_several_contacts_against_the_harmonic_balance():
    """A chain with a contact to ground and a relative Menq contact: the
    reference and ``hf.periodic_solution`` (H = 31) agree on every DOF's
    first harmonic within 1e-4 (truncation and time step) at a stuck, a
    slipping and a resonant pulsation."""
    s = _chain()
    for omega in (0.2, 0.45, 0.9):
        ref = hf.validation.steady_state(
            s, 0.5, omega, steps_per_period=2048, tol=1e-10, initial_state="linear"
        )
        assert ref.converged, ref.message
        sol = hf.periodic_solution(s, 0.5, omega, harmonics=31)
        assert sol.converged
        for dof in range(3):
            a = sol.amplitude(harmonic=1, dof=dof)
            assert ref.amplitude(1, dof) == pytest.approx(a, rel=1e-4), (omega, dof)


def test_multi_path_equals_the_single_contact_path():
    """One Jenkins contact to ground, integrated by both kernels (the same
    scheme, different code): the same steady state to 1e-10."""
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    single = hf.validation.steady_state(osc, 0.5, 1.6, steps_per_period=512)
    problem = SeveralContacts.build(check_system(osc), np.array([0.5 + 0.0j]))
    x, v = problem.initial_state(None, 1.6, 512)
    f = problem.initial_law_state(x)
    run = problem.integrate(1.6, 512, 1e-10, 20000, x, v, f)
    assert run.converged
    np.testing.assert_allclose(run.samples, single.samples, rtol=0, atol=1e-10)


def test_rigid_coulomb_among_several_is_refused():
    s = hf.LinearStructure(
        np.eye(2),
        np.eye(2),
        modal_damping=0.02,
        load={1: 1.0},
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.2), 0),
            hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.2), 0, 1),
        ],
    )
    assert hf.validation.steady_state(s, 0.1, 0.5).converged
    with pytest.raises(ValueError, match="Coulomb"):
        hf.validation.steady_state(
            hf.LinearStructure(
                np.eye(2),
                np.eye(2),
                modal_damping=0.02,
                load={1: 1.0},
                contacts=[
                    hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.2), 1),
                    hf.Contact(hf.Coulomb(slip_force=0.2), 0),
                ],
            ),
            0.1,
            0.5,
        )


def test_zero_forcing_rests_exactly():
    """No forcing: the chain with several contacts and the preloaded 2D rig
    rest, exactly (no static load on the chain; the rig's static load is
    held by the preload at v = 0)."""
    for system in (_chain(), _rig(OSC_ELEMENT)):
        ref = hf.validation.steady_state(system, 0.0, 0.5, steps_per_period=64)
        assert ref.converged and ref.status == 0
        assert np.all(ref.samples == 0.0)
