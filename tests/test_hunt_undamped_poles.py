"""An undamped structure solved at its natural pulsations (stop 31 hunt).

The condensed problem eliminates the linear DOFs through the receptance of
the structure without its contacts, which is infinite at an undamped
natural pulsation of that structure. Before: ``hf.periodic_solution`` of the
undamped chain below at Ω = 1 rad/s (its first free natural pulsation,
where a user who types the natural frequency lands) raised a Numba
``ZeroDivisionError`` ("complex division by zero"); 1e-15 and 1e-13 away
it returned ``converged=True`` amplitudes 7e-2 and 2.6e-4 off the closed
form, with no warning; ``hf.frf`` starting there raised the same error.
At a natural pulsation of the stuck structure the condensed linear start
leaked NumPy ``RuntimeWarning``s (divide by zero), and a fixed-``H`` sweep
that found no start there crashed with a ``ValueError`` from ``reshape``.

The reference is closed form: with the contact stuck (a small force) the
structure is linear, ``x = (K + k_t e eᵀ - Ω² M)⁻¹ p``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf

M = np.eye(2)
K = np.array([[2.0, -1.0], [-1.0, 2.0]])  # free pulsations 1 and √3 rad/s
KT = 1.0
FORCE = 1e-3  # the contact stays stuck: k_t |x_1| = 1e-3 << f_s = 1


def _structure(contacts=1):
    laws = [hf.Contact(hf.Jenkins(stiffness=KT, slip_force=1.0), 1)]
    if contacts == 2:
        laws.append(hf.Contact(hf.Jenkins(stiffness=KT, slip_force=1.0), 0))
    return hf.LinearStructure(M, K, contacts=laws, load=[0.0, 1.0])


def _stuck(omega, contacts=1):
    ks = np.diag([0.0, KT]) if contacts == 1 else KT * np.eye(2)
    return np.abs(np.linalg.solve(K + ks - omega**2 * M, [0.0, FORCE]))


@pytest.mark.parametrize("offset", [0.0, 1e-15, 1e-13, 1e-11])
def test_periodic_solution_at_a_free_natural_pulsation(offset):
    omega = 1.0 + offset
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sol = hf.periodic_solution(_structure(), FORCE, omega, harmonics=5)
    assert sol.converged
    ref = _stuck(omega)
    for dof in (0, 1):
        amp = sol.amplitude(harmonic=1, dof=dof)
        assert amp == pytest.approx(ref[dof], rel=1e-9), (offset, dof, amp, ref)


def test_an_explicit_condensation_there_is_refused():
    with pytest.raises(ValueError, match="natural pulsation 1 rad/s"):
        hf.periodic_solution(_structure(), FORCE, 1.0, harmonics=5, condense=True)
    # the third harmonic of Ω = 1/3 lies on the same pole
    with pytest.raises(ValueError, match="harmonic 3"):
        hf.periodic_solution(_structure(), FORCE, 1.0 / 3.0, harmonics=5, condense=True)


def test_frf_from_a_free_natural_pulsation():
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        branch = hf.frf(_structure(), FORCE, (1.0, 1.1), harmonics=5)
    assert branch.complete
    amp = branch.amplitude(harmonic=1, dof=1)
    ref = np.array([_stuck(w)[1] for w in branch.omega])
    assert np.max(np.abs(amp - ref) / ref) < 1e-8


def test_stuck_natural_pulsation_no_numpy_warning():
    """Ω at the first natural pulsation of the stuck structure: the contact
    slips (no stuck solution exists undamped); the condensed solution is
    the full one, and no NumPy RuntimeWarning reaches the user."""
    omega = float(np.sqrt(np.linalg.eigvalsh(K + np.diag([0.0, KT])))[0])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        sol = hf.periodic_solution(_structure(), FORCE, omega, harmonics=5)
    full = hf.periodic_solution(_structure(), FORCE, omega, harmonics=5, condense=False)
    assert sol.converged and full.converged
    for dof in (0, 1):
        assert sol.amplitude(harmonic=1, dof=dof) == pytest.approx(
            full.amplitude(harmonic=1, dof=dof), rel=1e-8
        )


def test_fixed_harmonics_sweep_from_a_stuck_natural_pulsation():
    """The up sweep finds no start at the undamped stuck resonance (a
    singular point); the retrace from the other end covers the range."""
    omega = float(np.sqrt(np.linalg.eigvalsh(K + np.diag([0.0, KT])))[0])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(_structure(), FORCE, (omega, 1.3), harmonics=5)
    assert branch.n_points > 0
    assert branch.coverage[1] == pytest.approx(1.3)
    assert branch.coverage[0] == pytest.approx(omega, rel=1e-6)
