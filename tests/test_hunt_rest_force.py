"""An unforced system whose contact carries a force at rest (stop 32).

``periodic_solution(force=0)`` returned the zero state at once. A contact
whose force at zero displacement is not zero moves the rest state: an
unsymmetric modified Dahl law carries its mid-envelope force
``(b + e) / 2`` at rest, a 2D element its preload ``N0`` on a normal DOF
without a static load. Before stop 32 both returned zero displacement,
``converged=True``, with no warning; the balance is off there by that
force. References: closed forms of the static balance.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf


def _dahl(a=0.5, b=2.0, d=0.3, e=-0.5, k=1.0):
    law = hf.ModifiedDahl(beta=3.0, exponent=1.0, upper=(a, b), lower=(d, e))
    osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=k, contact=law)
    # k x + ((a + d) x + b + e) / 2 = 0: the mid-envelope force at rest
    return osc, -(b + e) / 2.0 / (k + (a + d) / 2.0)


@pytest.mark.parametrize("harmonics", [7, "auto"])
def test_unsymmetric_dahl_at_rest(harmonics):
    osc, mean = _dahl()
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        sol = hf.periodic_solution(osc, 0.0, 1.3, harmonics=harmonics)
    assert sol.converged
    c = np.ravel(sol.coefficients)
    assert c[0] == pytest.approx(mean, rel=1e-9)
    assert np.max(np.abs(c[1:])) < 1e-12
    # the limit of a vanishing forcing (an independent solve, forced)
    small = hf.periodic_solution(osc, 1e-6, 1.3, harmonics=7)
    assert np.ravel(small.coefficients)[0] == pytest.approx(mean, rel=1e-6)


def test_symmetric_laws_still_rest_at_zero():
    osc, mean = _dahl(a=0.0, b=1.0, d=0.0, e=-1.0)
    assert mean == 0.0
    sol = hf.periodic_solution(osc, 0.0, 1.3)
    assert sol.converged and not np.any(sol.coefficients)
    jen = hf.Oscillator(1.0, 0.02, 1.0, contact=hf.Jenkins(3.0, 1.0))
    sol = hf.periodic_solution(jen, 0.0, 1.3)
    assert sol.converged and not np.any(sol.coefficients)
    assert sol.newton_iterations == 0


def test_contact2d_preload_without_static_load():
    kt, kn, ky, n0 = 3e4, 2e4, 1e4, 10.0
    element = hf.Contact2D(kt, kn, friction_coefficient=0.5, preload=n0)
    s = hf.LinearStructure(
        np.eye(2),
        np.diag([1e4, ky]),
        damping=6.0 * np.eye(2),
        dof_names={"x": 0, "y": 1},
        load={"x": 4.0, "y": 12.0},
        contacts=[hf.Contact(element, "x", normal="y")],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        sol = hf.periodic_solution(s, 0.0, 110.0, harmonics=8)
    assert sol.converged
    # docs/laws.md: at rest v = -N0 / (k_y + k_n), u = 0
    c = sol.coefficients
    assert c[1, 0] == pytest.approx(-n0 / (ky + kn), rel=1e-9)
    assert np.max(np.abs(c[0])) < 1e-15
    assert np.max(np.abs(c[1, 1:])) < 1e-15


@pytest.mark.parametrize("condense", [None, False, True])
def test_unsymmetric_dahl_on_a_chain(condense):
    a, b, d, e = 0.5, 2.0, 0.3, -0.5
    law = hf.ModifiedDahl(beta=3.0, exponent=1.0, upper=(a, b), lower=(d, e))
    K = np.array([[2.0, -1.0], [-1.0, 2.0]])
    s = hf.LinearStructure(
        np.eye(2),
        K,
        damping=0.01 * K,
        load=np.array([0.0, 1.0]),
        contacts=[hf.Contact(law, 1)],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        sol = hf.periodic_solution(s, 0.0, 1.3, harmonics=7, condense=condense)
    assert sol.converged
    # K x + e1 ((a + d) x1 + b + e) / 2 = 0
    A = K.copy()
    A[1, 1] += (a + d) / 2.0
    rest = np.linalg.solve(A, [0.0, -(b + e) / 2.0])
    np.testing.assert_allclose(sol.coefficients[:, 0], rest, rtol=1e-9)
    assert np.max(np.abs(sol.coefficients[:, 1:])) < 1e-12
