"""Trust hunt, stop 35: the exact Jenkins reference at a stiff contact's
resonance.

``validation.exact_periodic_solution`` scans each phase for its end on a
grid of 1/16 of the stuck mode's period. At a velocity reversal far from
the static slip load (Jenkins kt = 1e6 N/m on 1 N/m, F = 2 N against a slip
force of 1 N, at the resonance, amplitude 35 m) the stick phase lasts
2 f_s / (kt |ẍ|) ≈ 3e-4 s, less than one grid step (3.9e-4 s): the scan
started on the boundary, saw the next grid value outside and no crossing,
and the contact stayed stuck with its force at 72 f_s. Period-map residual
7e-16, no warning, first harmonic 35.85 where time integration (131072
steps per period) gives 34.772.
"""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf

OMEGA = 0.9944446725110113  # a point of hf.frf's branch near the peak


@pytest.mark.parametrize("kt", [1e5, 1e6])
def test_short_stick_phase_at_a_stiff_resonance(kt):
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(kt, 1.0))
    exact = hf.validation.exact_periodic_solution(osc, 2.0, OMEGA, on_failure="raise")
    _, force = exact.contact_force(n=50000)
    assert np.max(np.abs(force)) <= 1.0 + 1e-9  # the friction law's bound
    # independent: time integration (16384 steps per period: 2e-6 / 4.6e-5
    # off the 131072-step value at kt 1e5 / 1e6)
    ref = hf.validation.steady_state(
        osc, 2.0, OMEGA, steps_per_period=2**14, max_periods=400, tol=1e-9
    )
    assert ref.converged
    a, b = exact.amplitude(harmonic=1), ref.amplitude(harmonic=1)
    assert abs(a - b) <= 1e-4 * b, (a, b)
