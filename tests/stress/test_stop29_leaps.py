"""Stress rows for stop 29: a rigid Coulomb run's leap over a seam
(``Continuation._leap``) is a traced stretch of the branch only where its
chord is near the curve tolerance.

The paper beam with a rigid Coulomb tip at f_s = 1 N, swept down from
110 Hz, stalls at 62.32 Hz and its retrace up from 55 Hz at 62.07 Hz; in
stop 28 the retrace leapt from 62.07 to 67.34 Hz in one chord whose curve
estimate was 27 (relative), and the branch called itself complete. A leap
whose estimate exceeds ``LEAP_CURVE_FACTOR`` times the tolerance is now
refused and the skipped range reported as a gap.

Run with ``python -m pytest -m stress tests/stress/test_stop29_leaps.py``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.continuation.palc import LEAP_CURVE_FACTOR

pytestmark = pytest.mark.stress

HZ = 2.0 * math.pi


@pytest.fixture(scope="module")
def beam():
    return hf.CantileverBeam.calibrate().beam


@pytest.mark.parametrize(
    "slip_force, sweep",
    [(1.0, "down"), (1.0, "up"), (2.0, "down")],
    ids=["fs=1 down", "fs=1 up", "fs=2 down"],
)
def test_no_long_chord_far_above_the_tolerance_counts_as_covered(
    beam, slip_force, sweep
):
    """Every chord longer than 1 % of its Ω between points where the tip
    moves keeps
    its curve estimate within ``LEAP_CURVE_FACTOR`` times the tolerance;
    what a branch does not trace it reports as a gap (CoverageWarning)."""
    system = beam.with_contact(hf.Coulomb(slip_force=slip_force))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        b = hf.frf(system, 2.0, (HZ * 55.0, HZ * 110.0), 15, sweep=sweep)
    tol = b.info.get("curve_tolerance") or 1e-4
    errors = b.curve_errors
    w = b.omega
    # chords between points where the tip moves (a stuck rigid tip is at
    # rest: amplitudes of 1e-20 m, at 1e-9 m just short of sticking, where
    # the relative measure is not what a plot shows)
    a = b.amplitude(1)
    moving = np.minimum(a[:-1], a[1:]) > 1e-3 * a.max()
    long = moving & (np.abs(np.diff(w)) > 1e-2 * np.minimum(w[:-1], w[1:]))
    if "curve rule" not in " ".join(str(x.message) for x in caught):
        # the rule's own branch (not the rerun without it)
        assert np.all(errors[long] <= LEAP_CURVE_FACTOR * tol), (
            w[:-1][long][errors[long] > LEAP_CURVE_FACTOR * tol] / HZ
        )
    if not b.complete:
        assert any(issubclass(x.category, hf.CoverageWarning) for x in caught)
