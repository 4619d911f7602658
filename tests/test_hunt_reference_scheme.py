"""The time-integration reference's own error (stop 34 hunt).

``hf.validation.steady_state`` integrates with the trapezoidal rule at a
fixed ``steps_per_period`` (2048). Two quiet failures of the reference:

* ``check_halving=True`` reported the change under step halving relative
  to the largest amplitude of all DOFs: on a 3-DOF chain whose contact DOF
  moves ten times less than the forced one it read 7.1e-5 where the
  contact DOF's amplitude (what ``amplitude(1)`` reads by default) was
  9.5e-4 off the exact event-driven solution.
* The scheme's periodic response to ``cos Ωt`` is the linear one at
  ``Ω̃ = (2/h) tan(Ωh/2)``: on the flank of a stuck resonance with 0.1 %
  damping the first harmonic was 3.9e-4 off the closed form, the phase
  7.8e-4 rad off at the peak, ``converged=True`` and no warning.

References: the closed-form linear response (a stuck Jenkins contact is a
spring) and :func:`hf.validation.exact_periodic_solution` (closed-form
phases, shooting to 1e-13).
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import hbmfric as hf


def _chain(kt=100.0, zeta=0.01, contacts=None):
    n = 3
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    if contacts is None:
        return hf.LinearStructure(
            np.eye(n),
            K,
            modal_damping=zeta,
            load={0: 1.0},
            contact=hf.Jenkins(kt, 1.0),
            contact_dof=2,
        )
    return hf.LinearStructure(
        np.eye(n), K, modal_damping=zeta, load={0: 1.0}, contacts=contacts
    )


def test_halving_estimate_bounds_the_error_of_the_contact_dof():
    chain = _chain()
    exact = hf.validation.exact_periodic_solution(chain, 3.0, 0.3)
    assert exact.residual < 1e-10
    ref = hf.validation.steady_state(chain, 3.0, 0.3, check_halving=True)
    assert ref.converged
    error = abs(ref.amplitude(1) / exact.amplitude(1) - 1.0)
    assert error > 5e-4  # the default step is that far off here (9.5e-4)
    # second order: the error is about 4/3 of the change under halving
    # (measured 0.96e-3 against 9.5e-4); main read 7.1e-5
    assert 0.5 * error < 4.0 / 3.0 * ref.error_estimate < 2.0 * error


def _stuck_oscillator(zeta):
    # m 1, k 1, a Jenkins contact of kt 3 that the force never slips: the
    # linear oscillator of stiffness 4, ω0 = 2 rad/s
    return hf.Oscillator(1.0, 4.0 * zeta, 1.0, contact=hf.Jenkins(3.0, 1.0))


def _closed_form(zeta, force, omega):
    return force / (4.0 - omega**2 + 1j * 4.0 * zeta * omega)


@pytest.mark.parametrize("omega", [1.998, 2.0])
def test_a_lightly_damped_stuck_resonance_warns(omega):
    zeta, force = 1e-3, 1e-4
    with pytest.warns(hf.AccuracyWarning, match="steps_per_period >=") as record:
        ref = hf.validation.steady_state(
            _stuck_oscillator(zeta), force, omega, initial_state="linear"
        )
    assert ref.converged
    assert np.max(np.abs(ref.contact_force)) < 0.1  # stuck throughout
    exact = _closed_form(zeta, force, omega)
    coefficient = ref.coefficients[0, 1] - 1j * ref.coefficients[0, 2]
    error = abs(coefficient - exact) / abs(exact)
    assert error > 3e-4  # 3.9e-4 on the flank, 7.8e-4 (phase) on the peak
    assert 0.5 * error < ref.scheme_error < 2.0 * error
    # the step it names brings the error below the tolerance
    message = str(record[0].message)
    finer = int(re.search(r"steps_per_period >= (\d+)", message).group(1))
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        ref2 = hf.validation.steady_state(
            _stuck_oscillator(zeta),
            force,
            omega,
            initial_state="linear",
            steps_per_period=finer,
        )
    coefficient = ref2.coefficients[0, 1] - 1j * ref2.coefficients[0, 2]
    assert abs(coefficient - exact) / abs(exact) < 1e-4


def test_one_percent_damping_passes_without_a_warning():
    zeta, force, omega = 1e-2, 1e-3, 1.98
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        ref = hf.validation.steady_state(
            _stuck_oscillator(zeta), force, omega, initial_state="linear"
        )
    exact = _closed_form(zeta, force, omega)
    coefficient = ref.coefficients[0, 1] - 1j * ref.coefficients[0, 2]
    error = abs(coefficient - exact) / abs(exact)
    assert error < ref.scheme_error < 1e-4


def test_several_contacts_stuck_warns_with_the_linear_error():
    # a ground and a relative Jenkins contact, both stuck at this force: the
    # chain with two extra springs (the several-contacts integrator)
    law = hf.Jenkins(2.0, 1.0)
    chain = _chain(
        zeta=1e-3, contacts=[hf.Contact(law, 2), hf.Contact(law, 0, other=1)]
    )
    M, C, K = chain.matrices()
    K = K.copy()
    K[2, 2] += 2.0
    K[np.ix_([0, 1], [0, 1])] += 2.0 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    w = np.sqrt(np.linalg.eigvalsh(K))  # M = I
    omega = w[0] * (1.0 + 1e-3)
    force = 1e-4
    with pytest.warns(hf.AccuracyWarning, match="trapezoidal"):
        ref = hf.validation.steady_state(chain, force, omega, initial_state="linear")
    exact = np.linalg.solve(
        K - omega**2 * M + 1j * omega * C, force * chain.load_vector(1.0)
    )
    coefficient = ref.coefficients[:, 1] - 1j * ref.coefficients[:, 2]
    error = np.max(np.abs(coefficient - exact) / np.abs(exact))
    assert error > 1e-4
    assert 0.5 * error < ref.scheme_error < 2.0 * error


def test_a_slipping_contact_at_the_stuck_resonance_does_not_warn():
    # 0.01 % damping, forced on the stuck resonance: the contact slips and
    # its friction damps the motion; the stuck structure's scheme error
    # (7.8e-3) does not apply: the result is 1.2e-6 off the exact solution
    osc = hf.Oscillator(1.0, 4e-4, 1.0, contact=hf.Jenkins(3.0, 1.0))
    exact = hf.validation.exact_periodic_solution(osc, 0.5, 2.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        ref = hf.validation.steady_state(osc, 0.5, 2.0)
    assert np.isnan(ref.scheme_error)
    assert ref.amplitude(1) == pytest.approx(exact.amplitude(1), rel=1e-5)
