"""Stress rows for stop 31: the normal DOF of a 2D contact element.

The 2-DOF rig of ``tests/test_contact2d.py`` (tangential DOF x, normal DOF
y, a ``Contact2D`` with preload 10 N) with a small or no tangential load,
so that the watched (tangential) DOF moves little or not at all while the
contact separates. Each row: ``hf.periodic_solution`` at a fixed ``H``
(or its ``ConvergenceWarning``); the normal DOF's first-harmonic
amplitude is within ``harmonic_tolerance`` (1e-4) of the time
integration, or an ``AccuracyWarning`` says it may not be. Before stop
31 nothing watched the normal DOF (no warning at 8.2e-4 off). Known
limit: at 130 rad/s, ``H = 7``, the change to the probe level is 4e-5
while the error is 2.4e-4 (convergence in ``H`` is not monotone through
a separation): that row is marked xfail.

Run with ``python -m pytest -m stress tests/stress/test_stop31_contact2d_normal.py``.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest
from test_contact2d import OSC, OSC_ELEMENT, _first_harmonic, _integrate

import hbmfric as hf

pytestmark = pytest.mark.stress

STEPS = 8192


def _rig(fx):
    o = OSC
    return hf.LinearStructure(
        np.diag([o["m"], o["my"]]),
        np.diag([o["k"], o["ky"]]),
        np.diag([o["c"], o["cy"]]),
        load={"x": fx, "y": o["py"]},
        static_load={"y": OSC_ELEMENT.preload},
        contacts=[hf.Contact(OSC_ELEMENT, "x", normal="y")],
        dof_names={"x": 0, "y": 1},
    )


@functools.cache
def _reference(fx, omega):
    keys = ("m", "k", "c", "my", "ky", "cy")
    osc = np.array([OSC[k] for k in keys] + [fx, OSC["py"]])
    n_periods = int(np.ceil(15.0 * omega / (2 * np.pi)))
    rec = _integrate(OSC_ELEMENT.params, osc, omega, STEPS, n_periods)
    return float(np.hypot(*_first_harmonic(rec[1, STEPS:])))


ROWS = [
    pytest.param(
        fx,
        h,
        w,
        marks=pytest.mark.xfail(reason="estimate low at 130 rad/s, H = 7")
        if (fx, h, w) == (0.0, 7, 130.0)
        else (),
    )
    for fx in (0.0, 0.1)
    for h in (7, 11)
    for w in (100.0, 120.0, 126.0, 130.0, 140.0)
]


@pytest.mark.parametrize(("fx", "harmonics", "omega"), ROWS)
def test_normal_dof_right_or_warned(fx, harmonics, omega):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol = hf.periodic_solution(_rig(fx), 1.0, omega, harmonics=harmonics)
    if not sol.converged:  # said loudly: no accuracy to check
        assert any(issubclass(w.category, hf.ConvergenceWarning) for w in caught)
        return
    err = abs(sol.amplitude(harmonic=1, dof="y") / _reference(fx, omega) - 1.0)
    warned = any(issubclass(w.category, hf.AccuracyWarning) for w in caught)
    assert err <= 1e-4 or warned, err
