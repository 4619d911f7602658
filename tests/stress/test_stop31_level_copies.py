"""Stress rows for stop 31b: a level made by ``with_harmonics`` from a
problem already estimated gives each point the estimate of a problem built
afresh at that level (before: the original's level, columns and probe:
0.1x to 10x off; ``tests/test_hunt_level_copies.py``).

Rows: the 2D-contact rig loaded normally (its normal DOF watched too) and
the SDOF Jenkins oscillator, copied from ``H = 7`` to each higher rung, at
several Ω. Run with
``python -m pytest -m stress tests/stress/test_stop31_level_copies.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_hunt_contact2d_normal import _rig

import hbmfric as hf
from hbmfric.api import _problem
from hbmfric.continuation.accuracy import watched_truncation_errors

pytestmark = pytest.mark.stress


def _osc():
    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    return hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)


SCENES = {"rig": (_rig, 1.0), "sdof": (_osc, 0.5)}
ROWS = [
    ("rig", w, h) for w in (120.0, 126.0, 128.1, 130.8, 135.0) for h in (11, 21, 45)
] + [("sdof", w, h) for w in (1.2, 1.6, 2.0, 2.6) for h in (11, 21, 45)]


def _point(system, force, omega, h):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        sol = hf.periodic_solution(system, force, omega, harmonics=h)
    return np.concatenate([sol.coefficients.ravel(), [omega]])[None]


@pytest.mark.parametrize(("scene", "omega", "harmonics"), ROWS)
def test_copied_level_estimate_is_a_fresh_one(scene, omega, harmonics):
    make, force = SCENES[scene]
    base = _problem(make(), force, 7, None, None, "auto", None)
    watched_truncation_errors(base, _point(make(), force, omega, 7))
    point = _point(make(), force, omega, harmonics)
    copied = watched_truncation_errors(base.with_harmonics(harmonics), point)
    level = _problem(make(), force, harmonics, None, None, "auto", None)
    fresh = watched_truncation_errors(level, point)
    assert copied[0] == pytest.approx(fresh[0], rel=1e-12, abs=1e-300)
