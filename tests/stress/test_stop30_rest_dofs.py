"""Stress rows for the stop-30 trust hunt (branch hunt30).

* The rest floor under ``harmonics="auto"``: the README's 3-DOF structure
  with a rigid Coulomb tip, stuck over 5-8 rad/s, at masses, stiffnesses
  and forces x 1, 1e4, 1e-6 and two slip forces: no ``AccuracyWarning``
  and estimates below 1e-6 (were 5.3e3, 1.1e5, 2.6e4 with a warning); just
  short of sticking (35.9-36.0 rad/s) the largest estimate at most 100
  times its change to twice the harmonics (was 2.7e6 against 5.7e-3).
* No floor for an output that weighs several DOFs: the belt tensioner's
  tension at H = 3 and 5, 86-95 Hz, estimates at least half the change to
  H = 31 (were 16 times low at H = 3).
* Straight lines of a DOF the step control does not watch: the paper beam
  with a Jenkins tip at Fn = 1 N (auto) and 5 N (H = 13), load DOF
  ``"force"``: ``Branch.curve_errors_of`` within a factor 1.5 of the
  distance of the lines from fixed-frequency solves, and a polyline plot
  warns where it exceeds ``curve_tolerance``.

Run with ``python -m pytest -m stress tests/stress/test_stop30_rest_dofs.py``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from test_hunt_auto_rest import _tension_measures

import hbmfric as hf
from hbmfric.paper.beam import HZ, paper_beam, paper_calibration
from hbmfric.results import CURVE_REST

pytestmark = pytest.mark.stress

FRACTIONS = (0.21132486540518713, 0.5, 0.7886751345948129)


def _structure(scale: float, slip_force: float) -> hf.LinearStructure:
    M = np.diag([1.0, 1.0, 0.5]) * scale
    K = 1e3 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    return hf.LinearStructure(
        M,
        K * scale,
        modal_damping=0.01,
        dof_names={"drive": 0, "tip": 2},
        load={"drive": 1.0, "tip": 0.3j},
        contact=hf.Coulomb(slip_force=slip_force * scale),
        contact_dof="tip",
    )


@pytest.mark.parametrize("slip_force", [2.0, 5.0])
@pytest.mark.parametrize("scale", [1.0, 1e4, 1e-6])
def test_stuck_rigid_tip_auto_at_every_scale(scale, slip_force):
    system = _structure(scale, slip_force)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.AccuracyWarning)
        b = hf.frf(system, scale, (5.0, 8.0), "auto")
    assert np.all(b.amplitude(1) < 1e-15)
    assert np.all(b.truncation_error < 1e-6), b.truncation_error


@pytest.mark.parametrize("scale", [1.0, 1e4, 1e-6])
def test_rigid_tip_short_of_sticking_auto(scale):
    system = _structure(scale, 2.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        b = hf.frf(system, scale, (35.9, 36.0), "auto")
    te = b.truncation_error
    a, half = b.amplitude(1), b.amplitude()
    rest = CURVE_REST * b.info["amplitude_scale"]
    checked = 0
    for i in np.argsort(te)[::-1][:3]:
        h = 2 * int(b.point_harmonics[i]) + 1
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            s = hf.periodic_solution(
                system, scale, b.omega[i], h, initial_guess=b.point(i)
            )
        if not s.converged:
            continue
        checked += 1
        change = max(
            abs(s.amplitude(1) - a[i]) / max(a[i], rest),
            abs(s.amplitude() - half[i]) / max(half[i], rest),
        )
        assert te[i] <= 100.0 * change + 1e-3, (b.omega[i], te[i], change)
    assert checked >= 1


@pytest.mark.parametrize("harmonics", [3, 5])
def test_tension_estimate_not_floored(harmonics):
    rig = hf.BeltTensioner()
    hz = 2.0 * math.pi
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        b = hf.frf(rig, 2.0, (hz * 5.0, hz * 100.0), harmonics)
    f = b.omega / hz
    for i in np.flatnonzero((f > 86.0) & (f < 95.0))[::2]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            s = hf.periodic_solution(rig, 2.0, b.omega[i], 31, initial_guess=b.point(i))
        if not s.converged:
            continue
        ours = _tension_measures(b.harmonic_numbers, b.coefficients[i], b.omega[i], rig)
        ref = _tension_measures(s.harmonic_numbers, s.coefficients, b.omega[i], rig)
        change = max(abs(x - r) / r for x, r in zip(ours, ref, strict=True))
        if change < 1e-7:
            continue  # below what H = 31 resolves against the estimate
        assert b.truncation_error[i] >= 0.5 * change, (f[i], b.truncation_error[i])


@pytest.mark.parametrize("normal_load, harmonics", [(1.0, "auto"), (5.0, 13)])
def test_load_dof_lines_estimated_and_warned(normal_load, harmonics):
    system = paper_beam(normal_load, paper_calibration())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        b = hf.frf(system, 2.0, (15.0 * HZ, 110.0 * HZ), harmonics)
    est = b.curve_errors_of("force")
    a = b.amplitude(1, "force")
    rest = CURVE_REST * b.info["amplitude_scale"]
    for i in np.argsort(est)[::-1][:3]:
        ref = max(min(a[i], a[i + 1]), rest)
        line = 0.0
        for tau in FRACTIONS:
            w = b.omega[i] + tau * (b.omega[i + 1] - b.omega[i])
            h = harmonics if harmonics != "auto" else int(b.point_harmonics[i])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", hf.HbmfricWarning)
                s = hf.periodic_solution(
                    system, 2.0, w, h, initial_guess=b.point(i if tau < 0.5 else i + 1)
                )
            assert s.converged
            line = max(
                line,
                abs(a[i] + tau * (a[i + 1] - a[i]) - s.amplitude(1, "force")) / ref,
            )
        assert line / 1.5 - 1e-6 <= est[i] <= 1.5 * line + 1e-6, (
            b.omega[i] / HZ,
            est[i],
            line,
        )
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            b.plot(ax=ax, dof="force", curve="polyline")
    finally:
        plt.close(fig)
    warned = any(issubclass(w.category, hf.AccuracyWarning) for w in caught)
    assert warned == bool(est.max() > 1e-4)
