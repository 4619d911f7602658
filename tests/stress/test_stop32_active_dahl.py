"""Stress rows for stop 32: a modified Dahl law whose loops give energy.

Before stop 32 such a law was accepted without a word and Hill's verdicts
called its orbits stable where they are not (one DOF, ``β = 1``, ``(5, 1)``,
``(5, −1)``: stable above 4.27 rad/s, monodromy multipliers 1.08-1.14).
Each row scales a law's forces and stiffnesses (``a, b, d, e`` by
``scale``; ``β``, in 1/m, kept: the loops' shapes stay, their forces
scale) and checks that the construction warns
exactly when the loop area ``∮ F du`` of the law's own steady loop is
negative at small, middle and large amplitudes (the compiled march, not
the closed form the check uses).

Run with ``python -m pytest -m stress tests/stress/test_stop32_active_dahl.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.laws.dahl import loop_area

pytestmark = pytest.mark.stress

# (beta, upper, lower) at mu = 1; the margin b - e - (a + d)/beta from
# clearly negative to clearly positive
LAWS = [
    (1.0, (5.0, 1.0), (5.0, -1.0)),  # margin -8
    (1.0, (1.0, 0.5), (1.0, -0.5)),  # -1
    (10.0, (4.0, 0.2), (4.0, 0.0)),  # -0.6
    (10.0, (4.0, 0.5), (4.0, 0.0)),  # +0.3
    (3.0, (0.5, 2.0), (0.3, -0.5)),  # +2.23
    (5.0, (6.0, 1.0), (2.0, 0.0)),  # -0.6, unsymmetric
    (5.0, (6.0, 3.0), (2.0, 0.0)),  # +1.4, unsymmetric
]
SCALES = [1e-6, 1.0, 1e4]


@pytest.mark.parametrize("beta, upper, lower", LAWS)
@pytest.mark.parametrize("scale", SCALES)
def test_active_dahl_is_said(beta, upper, lower, scale):
    (a, b), (d, e) = upper, lower
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        law = hf.ModifiedDahl(
            beta=beta,
            upper=(a * scale, b * scale),
            lower=(d * scale, e * scale),
        )
    said = [w for w in caught if issubclass(w.category, hf.AccuracyWarning)]
    areas = [loop_area(law, float(x), 2048) for x in np.array([0.3, 3.0, 30.0]) / beta]
    assert all(x < 0.0 for x in areas) or all(x > 0.0 for x in areas)
    assert bool(said) == (areas[0] < 0.0), areas
