"""The exact Jenkins reference with a stiff stuck mode (stop 32).

``exact_periodic_solution`` scans each phase for its end on a grid of
1024 points per forcing period. A stuck mode far faster than the forcing
(kt = 1e6 N/m on an oscillator of 1 N/m: 1000 rad/s, forced at 3 rad/s)
rang about three times per grid step, the scan missed the instant the
stuck force reached the slip force, and the solution kept sticking with
the force at 3.9 times the slip force: a period-map residual of 6e-14,
the first harmonic 3.4e-3 off the time integration, no warning.
References: the law's invariant ``|f| <= f_s`` and ``steady_state``.
"""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf


@pytest.mark.parametrize("kt", [1e5, 1e6])
def test_stiff_stuck_mode_keeps_the_force_within_the_slip_force(kt):
    osc = hf.Oscillator(1.0, 0.02, 1.0, contact=hf.Jenkins(kt, 1.0))
    sol = hf.validation.exact_periodic_solution(osc, 2.0, 3.0)
    assert sol.residual < 1e-10
    _, f = sol.contact_force(n=40000)
    assert np.max(np.abs(f)) <= 1.0 + 1e-9
    # Newmark at 16384 steps per period resolves the 1000 rad/s stuck mode
    # (about 35 steps per its period); 4096 -> 32768 steps moved it 2.3e-4
    ref = hf.validation.steady_state(osc, 2.0, 3.0, steps_per_period=16384)
    assert ref.converged
    assert sol.amplitude(1) == pytest.approx(ref.amplitude(1), rel=2e-4)
