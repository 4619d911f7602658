"""The rest floor of the truncation estimates (stop 30): under
``harmonics="auto"`` where the watched DOF is at rest, at three unit
scales, and not applied to an output that weighs several DOFs.

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


def _tension_measures(harmonics, X, omega, rig):
    """First-harmonic amplitude and half the peak-to-peak value of the belt
    tension ``k (u1 - u2) + c (u1' - u2')`` (minus ``T0``), sampled on 4096
    instants (plain NumPy, independent of the estimator's measures)."""
    k, c = rig.belt_stiffness, rig.belt_damping
    t = np.linspace(0.0, 2.0 * np.pi, 4096, endpoint=False)
    d = X[0] - X[1]
    T = np.zeros_like(t)
    j, a1 = 0, None
    for h in harmonics:
        if h == 0:
            j += 1
            continue
        a, b = d[j], d[j + 1]
        j += 2
        T += k * (a * np.cos(h * t) + b * np.sin(h * t))
        T += c * h * omega * (b * np.cos(h * t) - a * np.sin(h * t))
        if h == 1:
            a1 = np.hypot(k * a + c * omega * b, k * b - c * omega * a)
    return a1, 0.5 * (T.max() - T.min())


def test_belt_tension_estimate_is_not_floored_by_the_displacement_scale():
    """The belt tensioner watches the tension ``k (u1 - u2)``, which is
    small above both resonances where the two DOFs move together. The rest
    floor of stop 29 (``CURVE_REST`` times the displacement scale times the
    summed weights: 0.136 N in the auto run) exceeded the tension there
    (0.02 N at 91 Hz) and cut the estimate: at H = 3, 93.2 Hz, 2.9e-5
    against a change to H = 31 of 4.8e-4 (16 times low), and the auto run
    left its point at 91.1 Hz at H = 3, 1.7e-4 off the shooting reference.
    Reference: a solve with 31 harmonics at the point's Ω; an estimate is
    at least half of its change."""
    rig = hf.BeltTensioner()
    hz = 2.0 * np.pi
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        b = hf.frf(rig, 2.0, (hz * 5.0, hz * 100.0), 3)
    f = b.omega / hz
    rows = np.flatnonzero((f > 89.0) & (f < 94.0))
    assert rows.size >= 4
    checked = 0
    for i in rows[:: max(1, rows.size // 5)]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            s = hf.periodic_solution(rig, 2.0, b.omega[i], 31, initial_guess=b.point(i))
        if not s.converged:
            continue
        ours = _tension_measures(b.harmonic_numbers, b.coefficients[i], b.omega[i], rig)
        ref = _tension_measures(s.harmonic_numbers, s.coefficients, b.omega[i], rig)
        change = max(abs(x - r) / r for x, r in zip(ours, ref, strict=True))
        checked += 1
        assert b.truncation_error[i] >= 0.5 * change, (
            f[i],
            b.truncation_error[i],
            change,
        )
    assert checked >= 3
