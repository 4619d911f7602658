"""Stress rows for stop 32: the exact Jenkins reference with a stuck mode
far faster than the forcing.

Before stop 32 the phase-end scan (1024 points per forcing period)
aliased a stiff stuck mode and missed stick -> slip events: on an
oscillator of 1 N/m with kt = 1e6 N/m at 3 rad/s the returned solution
stuck with the force at 3.9 times the slip force (residual 6e-14, no
warning). Reference: the law's invariant ``|f| <= f_s`` on a fine sampling
of the returned period, and for one stiffness the time integration.

Run with ``python -m pytest -m stress tests/stress/test_stop32_exact_stiff.py``.
"""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf

pytestmark = pytest.mark.stress

ROWS = [
    (kt, omega, force)
    for kt in (1e5, 1e6, 1e7)
    for omega in (2.0, 3.0, 5.0)
    for force in (2.0, 5.0)
]


@pytest.mark.parametrize(("kt", "omega", "force"), ROWS)
def test_stuck_force_never_passes_the_slip_force(kt, omega, force):
    osc = hf.Oscillator(1.0, 0.02, 1.0, contact=hf.Jenkins(kt, 1.0))
    sol = hf.validation.exact_periodic_solution(osc, force, omega, on_failure="raise")
    # 64 samples per period of the stuck mode, at least 20000 per period
    n = max(20000, int(64 * np.sqrt(1.0 + kt) / omega))
    _, f = sol.contact_force(n=n)
    assert np.max(np.abs(f)) <= 1.0 + 1e-9


@pytest.mark.parametrize("omega", [2.0, 3.0, 5.0])
def test_stiff_reference_meets_the_time_integration(omega):
    osc = hf.Oscillator(1.0, 0.02, 1.0, contact=hf.Jenkins(1e6, 1.0))
    sol = hf.validation.exact_periodic_solution(osc, 2.0, omega, on_failure="raise")
    ref = hf.validation.steady_state(osc, 2.0, omega, steps_per_period=16384)
    assert ref.converged
    assert sol.amplitude(1) == pytest.approx(ref.amplitude(1), rel=3e-4)
