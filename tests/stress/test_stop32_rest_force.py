"""Stress rows for stop 32: unforced systems whose contact carries a force
at zero displacement.

``periodic_solution(force=0)`` returned the zero state at once, converged,
with no warning, where the static balance is off by that force: an
unsymmetric modified Dahl law (mid-envelope force ``(b + e) / 2`` at rest,
the oscillator at rest at ``-(b + e) / (2 k + a + d)``) and a 2D element's
preload without a static load (the normal DOF at ``-N0 / (k_y + k_n)``).
References: those closed forms.

Run with ``python -m pytest -m stress tests/stress/test_stop32_rest_force.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf

pytestmark = pytest.mark.stress

ENVELOPES = [
    ((0.5, 2.0), (0.3, -0.5)),
    ((0.0, 1.0), (0.0, 0.2)),
    ((2.0, -0.2), (1.0, -3.0)),
]
SCALES = [1.0, 1e4, 1e-6]


@pytest.mark.parametrize("upper, lower", ENVELOPES)
@pytest.mark.parametrize("scale", SCALES)
@pytest.mark.parametrize("harmonics", [7, "auto"])
def test_unforced_dahl_rests_where_the_balance_holds(upper, lower, scale, harmonics):
    (a, b), (d, e) = upper, lower
    # forces and stiffnesses scaled alike: the rest displacement does not move
    law = hf.ModifiedDahl(
        beta=3.0,
        exponent=1.0,
        upper=(a * scale, b * scale),
        lower=(d * scale, e * scale),
    )
    k = 1.0 * scale
    osc = hf.Oscillator(mass=scale, damping=0.02 * scale, stiffness=k, contact=law)
    rest = -(b + e) * scale / (2.0 * k + (a + d) * scale)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        sol = hf.periodic_solution(osc, 0.0, 1.3, harmonics=harmonics)
    assert sol.converged
    c = np.ravel(sol.coefficients)
    assert c[0] == pytest.approx(rest, rel=1e-9, abs=1e-15)
    assert np.max(np.abs(c[1:])) <= 1e-12 * max(abs(rest), 1.0)


@pytest.mark.parametrize("preload", [10.0, 1e-3, 5e4])
@pytest.mark.parametrize("scale", [1.0, 1e3])
def test_unforced_2d_element_rests_on_its_preload(preload, scale):
    kt, kn, ky = 3e4 * scale, 2e4 * scale, 1e4 * scale
    element = hf.Contact2D(kt, kn, friction_coefficient=0.5, preload=preload)
    s = hf.LinearStructure(
        np.eye(2),
        np.diag([1e4 * scale, ky]),
        damping=6.0 * np.eye(2),
        dof_names={"x": 0, "y": 1},
        load={"x": 4.0, "y": 12.0},
        contacts=[hf.Contact(element, "x", normal="y")],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        sol = hf.periodic_solution(s, 0.0, 110.0, harmonics=8)
    assert sol.converged
    c = sol.coefficients
    v = -preload / (ky + kn)
    assert c[1, 0] == pytest.approx(v, rel=1e-9)
    assert np.max(np.abs(c[0])) <= 1e-12 * abs(v)
    assert np.max(np.abs(c[1, 1:])) <= 1e-12 * abs(v)
