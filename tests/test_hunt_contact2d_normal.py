"""The normal DOF of a 2D contact element is watched (stop 31 hunt).

The truncation estimates watched the contact (tangential) DOF only. The
normal force of a :class:`hbmfric.Contact2D` has a kink where the contact
opens and closes, so the normal DOF's harmonics decay slowly while the
tangential DOF can be at rest. The 2-DOF rig of ``tests/test_contact2d.py``
loaded normally only (``Fx = 0``, ``Py = 12 N``), at 126 rad/s where the
contact separates: before, ``H = 7`` gave the normal DOF's first harmonic
8.2e-4 off (``H = 11``: 1.7e-4, 3.6e-4 at 130 rad/s) with no warning, and
``harmonics="auto"`` settled at once (the tangential DOF does not move)
and returned ``H = 15``, 2.1e-4 off, with no warning.

Reference: the time integration of ``tests/test_contact2d.py`` (its own
error here: 3.5e-7 against ``H = 63`` at 126 rad/s).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_contact2d import OSC, OSC_ELEMENT, _first_harmonic, _integrate

import hbmfric as hf

OMEGA = 126.0
STEPS = 8192


def _rig():
    o = OSC
    return hf.LinearStructure(
        np.diag([o["m"], o["my"]]),
        np.diag([o["k"], o["ky"]]),
        np.diag([o["c"], o["cy"]]),
        load={"x": 0.0, "y": o["py"]},
        static_load={"y": OSC_ELEMENT.preload},
        contacts=[hf.Contact(OSC_ELEMENT, "x", normal="y")],
        dof_names={"x": 0, "y": 1},
    )


@pytest.fixture(scope="module")
def reference():
    """First-harmonic amplitude of the normal DOF by time integration."""
    keys = ("m", "k", "c", "my", "ky", "cy")
    osc = np.array([OSC[k] for k in keys] + [0.0, OSC["py"]])
    n_periods = int(np.ceil(15.0 * OMEGA / (2 * np.pi)))
    rec = _integrate(OSC_ELEMENT.params, osc, OMEGA, STEPS, n_periods)
    assert np.abs(rec[:, STEPS:] - rec[:, :STEPS]).max() < 1e-12
    assert np.abs(rec[0]).max() == 0.0  # the tangential DOF stays at rest
    return float(np.hypot(*_first_harmonic(rec[1, STEPS:])))


def test_fixed_harmonics_warns_about_the_normal_dof(reference):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol = hf.periodic_solution(_rig(), 1.0, OMEGA, harmonics=7)
    err = abs(sol.amplitude(harmonic=1, dof="y") / reference - 1.0)
    assert err > 3e-4  # H = 7 is that far off here ...
    accuracy = [w for w in caught if issubclass(w.category, hf.AccuracyWarning)]
    assert accuracy, err  # ... and says so


def test_auto_climbs_for_the_normal_dof(reference):
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.AccuracyWarning)
        sol = hf.periodic_solution(_rig(), 1.0, OMEGA)
    err = abs(sol.amplitude(harmonic=1, dof="y") / reference - 1.0)
    assert err < 1e-4, (err, sol.harmonic_numbers[-1])


def test_fixed_harmonics_branch_warns_about_the_normal_dof():
    with pytest.warns(hf.AccuracyWarning, match="truncation error"):
        branch = hf.frf(_rig(), 1.0, (110.0, 140.0), harmonics=7)
    assert np.max(branch.truncation_error) > 1e-3
