"""Stress row for stop 27 (issue 16, the trust hunt's item 4): the
monodromy's verdicts in a cluster of seven folds, at a few points
(``exponents="auto"``) against every point (``exponents="all"``).

Run with ``python -m pytest -m stress tests/stress/test_stop27_fold_cluster.py``
(about 400 s CPU: the monodromy of 1393 points).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from stability_cases import fold_cluster_chain

import hbmfric as hf
from hbmfric.stability import NEUTRAL_TOLERANCE

pytestmark = pytest.mark.stress


def test_fold_cluster_auto_equals_every_point():
    """2-DOF chain, Jenkins to ground at DOF 0, cubic spring at DOF 1,
    F = 0.3, H = 5: the verdicts at a few points (the schedule computes
    every point of a cluster of flips, the snap crosses no computed point)
    equal the monodromy of every point, each verdict its own multipliers'."""
    system = fold_cluster_chain()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, 0.3, (0.3, 2.2), harmonics=5)
        auto = branch.stability()
        stable = auto.stable.copy()
        computed = auto.computed.copy()
        branch._stability = None
        full = branch.stability(exponents="all")
    own = np.abs(full.multipliers).max(axis=1) <= 1.0 + NEUTRAL_TOLERANCE
    np.testing.assert_array_equal(full.stable, own)
    np.testing.assert_array_equal(stable, full.stable)
    assert computed.sum() < len(branch) // 4
