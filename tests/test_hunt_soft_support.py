"""Several contacts condensed on a structure held by a soft spring, with a
static load (hunt35, stop 34).

A chain grounded by a spring ``s`` times its others (a user's weak spring
against rigid-body modes) and carrying a static load: the static
receptance of the contact coordinates is nearly singular, the static load
drives the soft mode (its linear response ``p`` about ``1/s`` times the
contact motion), and the condensed residual ``D (q - p) + f`` rounds at
about ``eps κ(G₀) |D| |p|`` (2.5e-4 N at ``s = 1e-7``, 2.5 N at ``1e-9``
against loads of 1 N). The corrector accepts a residual at its rounding
level as converged: on main ``periodic_solution`` returned coefficients
off by 4e-4 (``s = 1e-7``) to 4.8 (``1e-9``) relative, the full HBM
residual of the recovered solution 0.1-4.9 times the load, and no warning
beyond the truncation estimate's. Fixed by moving the contacts'
stiffnesses into the structure (:func:`hbmfric.condensation.coordinate_shift`,
``soft=True``) when the static rounding level exceeds
:data:`hbmfric.condensation.STATIC_ROUNDING` of the load.

References, independent of the condensed residual: the full (uncondensed)
HBM solve from its own guesses, and the full HBM residual evaluated at
every DOF recovered from the condensed solution.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem, static_rounding
from hbmfric.hbm import HBMProblem

N_DOF = 6
ELEMENT = hf.Contact2D(
    tangential_stiffness=1.0,
    normal_stiffness=2.0,
    friction_coefficient=0.3,
    preload=0.05,
)


def _chain(soft: float, contacts, static: bool = True):
    """A 6-DOF chain (unequal masses and springs), DOF 0 grounded by a
    spring ``soft``, Rayleigh damping, a harmonic load on three DOFs and a
    static one on DOF 4."""
    m = 1.0 + 0.1 * np.arange(N_DOF)
    k = 1.0 + 0.3 * np.cos(np.arange(N_DOF))
    k[0] = soft
    K = np.zeros((N_DOF, N_DOF))
    for i in range(N_DOF):
        K[i, i] += k[i]
        if i + 1 < N_DOF:
            K[i, i] += k[i + 1]
            K[i, i + 1] = K[i + 1, i] = -k[i + 1]
    return hf.LinearStructure(
        np.diag(m),
        K,
        rayleigh=(0.01, 0.02),
        contacts=contacts,
        load={N_DOF - 1: 1.0, 4: 0.5, 2: 0.3 - 0.2j},
        static_load={4: 0.01} if static else None,
    )


def _element(soft, static=True):
    return _chain(soft, [hf.Contact(ELEMENT, 2, normal=4)], static)


def _two_jenkins(soft):
    return _chain(
        soft,
        [
            hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.04), 2),
            hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.05), 4),
        ],
    )


@pytest.mark.parametrize(
    ("soft", "static"), [(1e-7, True), (1e-9, True), (1e-9, False)]
)
def test_element_on_a_soft_support_matches_the_full_solve(soft, static):
    """Condensed by default: every DOF against the full solve to 1e-9 of
    the largest coefficient and the recovered solution's full residual
    below 1e-9 of the load at three pulsations (main: 2.3e-5 to 4.8
    relative, residual up to 4.9 times the load; without the static load,
    where the preload's mean force alone drives the soft mode, 1.6e-8)."""
    s = _element(soft, static)
    full = HBMProblem(s, 0.1, harmonics=7, symmetry=False)
    load = np.max(np.abs(full.load))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        for omega in (0.3, 0.8, 1.5):
            a = hf.periodic_solution(s, 0.1, omega, harmonics=7)
            b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
            assert a.converged and b.converged
            scale = np.max(np.abs(b.coefficients))
            err = np.max(np.abs(a.coefficients - b.coefficients)) / scale
            assert err < 1e-9, (omega, err)
            R, _, state = full.residual(np.append(a.coefficients.reshape(-1), omega))
            assert state >= 0
            assert np.max(np.abs(R)) < 1e-9 * load, omega


def test_soft_support_is_shifted_and_rounds_finely():
    """The problem moves the element's stiffnesses into the structure
    (:attr:`CondensedHBMProblem.shift`) and its static rounding level
    drops from 2.5 N to below 1e-12 N; a stiffly held chain keeps
    ``shift = 0``."""
    s = _element(1e-9)
    p = CondensedHBMProblem(s, 0.1, harmonics=5)
    np.testing.assert_array_equal(p.shift, [1.0, 2.0])
    static = p.load.reshape(p.n_dof, p.n_coef)[:, 0]
    K = s.matrices()[2]
    assert static_rounding(p._contacts, K, static) > 0.1
    assert static_rounding(p._contacts, K, static, p.shift) < 1e-12
    stiff = CondensedHBMProblem(_element(1.0), 0.1, harmonics=5)
    assert not np.any(stiff.shift)


def test_two_jenkins_on_a_soft_support():
    """Two Jenkins contacts to ground, ``s = 1e-7``, at 1.5 rad/s: main
    1.5e-3 off the full solve (quietly); now within 1e-9."""
    s = _two_jenkins(1e-7)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        a = hf.periodic_solution(s, 0.1, 1.5, harmonics=7)
        b = hf.periodic_solution(s, 0.1, 1.5, harmonics=7, condense=False)
    assert a.converged and b.converged
    scale = np.max(np.abs(b.coefficients))
    assert np.max(np.abs(a.coefficients - b.coefficients)) < 1e-9 * scale
