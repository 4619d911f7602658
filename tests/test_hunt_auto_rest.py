"""Truncation estimates of ``harmonics="auto"`` where the watched DOF is at
rest, at three unit scales (stop 30).

The 3-DOF structure of the README with a rigid Coulomb tip (f_s = 2 N,
forced at 1 N) sticks over 5-8 rad/s: the structure is then linear, every
harmonic but the first is zero and the tip moves by round-off (1e-18 m).
Before stop 30 the final pass of the adaptive run
(:meth:`AdaptiveContinuation.settle`) measured the estimate relative to
that round-off: 5.3e3 at the base scale, 1.1e5 at masses, stiffnesses and
forces x 1e4, 2.6e4 at x 1e-6, each with an ``AccuracyWarning`` ("the top
of the harmonic ladder (H=63) cannot meet it") on a linear response whose
fixed-``H`` branch (the rule of stop 29) reads 1e-10. Rescaling masses,
stiffnesses and forces together leaves the displacements and Ω unchanged:
the estimates must not change either.

Reference: the stuck response is linear, so a solve with 63 harmonics at
the branch's Ω gives the same load-DOF amplitude (to round-off) as the
branch's points: the truncation error is zero.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf

SCALES = (1.0, 1e4, 1e-6)


def _structure(scale: float) -> hf.LinearStructure:
    M = np.diag([1.0, 1.0, 0.5]) * scale
    K = 1e3 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    return hf.LinearStructure(
        M,
        K * scale,
        modal_damping=0.01,
        dof_names={"drive": 0, "tip": 2},
        load={"drive": 1.0, "tip": 0.3j},
        contact=hf.Coulomb(slip_force=2.0 * scale),
        contact_dof="tip",
    )


@pytest.mark.parametrize("scale", SCALES, ids=["x1", "x1e4", "x1e-6"])
def test_stuck_rigid_tip_has_no_truncation_error_under_auto(scale):
    system = _structure(scale)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.AccuracyWarning)
        b = hf.frf(system, scale, (5.0, 8.0), "auto")
    assert b.complete
    # the tip is stuck at every point (round-off against a scale of 1e-3 m)
    assert np.all(b.amplitude(1) < 1e-15)
    assert np.all(b.truncation_error < 1e-6), b.truncation_error
    drive = b.amplitude(None, "drive")
    for i in (0, len(b) // 2, len(b) - 1):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            s = hf.periodic_solution(system, scale, b.omega[i], 63)
        assert s.converged
        assert s.amplitude(None, "drive") == pytest.approx(drive[i], rel=1e-9)
