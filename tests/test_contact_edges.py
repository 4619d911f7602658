"""Edge inputs of several contacts and of the 2D element in the engine:
zero forcing and a contact open at rest (a gap). Each answer is checked
against a closed form or an independent time integration.

(The 2D element's pass budget cannot run out inside the engine: one
period maps the slider by a clamp, so two passes always repeat it;
``tests/test_contact2d.py::test_pass_budget_status`` checks the status
with a budget of one pass and over random motions.)"""

import warnings

import numpy as np
from test_contact2d import OSC, OSC_ELEMENT, _first_harmonic, _integrate, _TwoDofRig

import hbmfric as hf

RANGE = (40.0, 250.0)


def _chain(n_dof: int = 4) -> hf.LinearStructure:
    """Unit masses and springs, clamped at one end, a Jenkins contact to
    ground at the first mass and one between the last two."""
    K = 2.0 * np.eye(n_dof) - np.eye(n_dof, k=1) - np.eye(n_dof, k=-1)
    K[-1, -1] = 1.0
    law = hf.Jenkins(stiffness=1.0, slip_force=0.05)
    return hf.LinearStructure(
        np.eye(n_dof),
        K,
        modal_damping=0.02,
        load={n_dof - 1: 1.0},
        contacts=[hf.Contact(law, 0), hf.Contact(law, n_dof - 2, n_dof - 1)],
    )


def _quiet(call, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        return call(*args, **kwargs)


def test_several_contacts_at_zero_forcing_rest_exactly():
    """No forcing, no static load: the response is zero, exactly, over the
    whole range, without a warning (and a fixed-Ω solve gives zero)."""
    s = _chain()
    branch = _quiet(hf.frf, s, 0.0, (0.02, 0.6), harmonics=5)
    assert branch.complete
    assert np.all(branch.coefficients == 0.0)
    sol = _quiet(hf.periodic_solution, s, 0.0, 0.3, harmonics=5)
    assert sol.converged and np.all(sol.coefficients == 0.0)


def test_contact2d_at_zero_forcing_rests_at_the_preload():
    """The static load holds the preloaded element at ``v = 0``: without
    forcing nothing moves (harmonic 0 included), exactly."""
    rig = _TwoDofRig(OSC_ELEMENT)
    branch = _quiet(hf.frf, rig, 0.0, RANGE, harmonics=8)
    assert branch.complete
    assert np.all(branch.coefficients == 0.0)
    sol = _quiet(hf.periodic_solution, rig, 0.0, 100.0, harmonics=8)
    assert sol.converged and np.all(sol.coefficients == 0.0)


#: the element with a negative preload: an initial gap; the rig's static
#: load (= preload) then pulls the normal DOF further away, to
#: ``y0 = N0 / ky``, a gap of ``-N0 (1/ky + 1/kn)`` in ``v``
GAP_ELEMENT = OSC_ELEMENT.with_preload(-2.0)


def test_contact2d_open_at_rest_is_the_free_structure_while_open():
    """Forcing too small to close the gap: the response is that of the two
    oscillators without contact (closed form), to the corrector's tolerance
    (measured 2e-9), along the
    whole branch."""
    rig = _TwoDofRig(GAP_ELEMENT)
    force = 0.01
    branch = hf.frf(rig, force, RANGE, harmonics=4)
    assert branch.complete
    o = OSC
    w = branch.omega
    x1 = force * o["fx"] / np.abs(o["k"] - o["m"] * w**2 + 1j * o["c"] * w)
    y1 = force * o["py"] / np.abs(o["ky"] - o["my"] * w**2 + 1j * o["cy"] * w)
    np.testing.assert_allclose(branch.amplitude(1, 0), x1, rtol=1e-8)
    np.testing.assert_allclose(branch.amplitude(1, 1), y1, rtol=1e-8)
    # the mean: the static load alone on the normal spring
    np.testing.assert_allclose(
        branch.coefficients[:, 1, 0], GAP_ELEMENT.preload / o["ky"], rtol=1e-12
    )
    # and it never closes: N0 + kn y stays negative
    assert np.max(GAP_ELEMENT.preload / o["ky"] + y1) * 2e4 + GAP_ELEMENT.preload < 0


def test_contact2d_open_at_rest_closing_against_time_integration():
    """Forcing that closes the gap at some frequencies (the contact opens,
    closes, sticks and slips within a period) and not at others: first
    harmonics of both DOFs within 5e-4 of the time integration (measured
    7e-5 at most)."""
    rig = _TwoDofRig(GAP_ELEMENT)
    force = 0.3
    osc = np.array([OSC[k] for k in ("m", "k", "c", "my", "ky", "cy", "fx", "py")])
    osc[6:] *= force
    steps = 8192
    closed = []
    for omega in (60.0, 100.0, 180.0):
        sol = hf.periodic_solution(rig, force, omega, harmonics=24, n_time=1024)
        assert sol.converged
        n_periods = int(np.ceil(40.0 * omega / (2 * np.pi)))
        rec = _integrate(GAP_ELEMENT.params, osc, omega, steps, n_periods)
        closed.append(bool(np.max(rec[1]) * 2e4 + GAP_ELEMENT.preload > 0))
        for dof in range(2):
            ref = np.hypot(*_first_harmonic(rec[dof, steps:]))
            amp = sol.amplitude(harmonic=1, dof=dof)
            assert abs(amp - ref) <= 5e-4 * ref, (omega, dof, amp, ref)
    assert closed == [True, True, False]
