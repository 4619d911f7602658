"""Stress rows for stop 33: the stability of a modified Dahl law on one DOF.

Hill's method leaves out the memory of the law; on one DOF it was the
default, and it called orbits stable that time integration leaves by
orders of magnitude (four laws whose loops give energy; a dissipating
law with unequal slopes: tests/test_dahl_stability.py). Each row solves one point
(``hf.periodic_solution``, oscillator m 1, c 0.01, k 1), integrates 1000
periods from the orbit's displacement and velocity at t = 0
(``hf.validation.steady_state``, the law started virgin there), and
checks that the motion leaves the orbit more than 10-fold (36-3800 fold)
and the default verdict (``PeriodicSolution.stability()``) is unstable. Before
stop 33, 8 of the 12 rows (every row at 4.6 rad/s) read stable.

Run with ``python -m pytest -m stress tests/stress/test_stop33_dahl_stability.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.validation import steady_state

pytestmark = pytest.mark.stress

# (beta, exponent, upper, lower)
LAWS = {
    "mu1-wide": (1.0, 1.0, (5.0, 1.0), (5.0, -1.0)),  # gives energy
    "mu1-narrow": (1.0, 1.0, (3.0, 0.5), (3.0, -0.5)),  # gives energy
    "mu2-unequal": (1.0, 2.0, (4.0, 1.0), (1.0, -1.0)),  # large loops give energy
    "mu1.5-equal": (1.0, 1.5, (4.0, 1.0), (4.0, -1.0)),  # large loops give energy
}
# 4.6 rad/s, where Hill called every law's orbits stable; 2 rad/s for the
# laws of exponent 1 (whose time integration is cheap)
ROWS = [
    (name, force, omega)
    for name in LAWS
    for force in (0.5, 2.0)
    for omega in ((2.0, 4.6) if LAWS[name][1] == 1.0 else (4.6,))
]


def _state_at_zero(solution, omega: float) -> tuple[float, float]:
    k, c = solution.harmonic_numbers, solution.coefficients[0]
    if k[0] == 0:
        return float(c[0] + np.sum(c[1::2])), float(np.sum(k[1:] * omega * c[2::2]))
    return float(np.sum(c[0::2])), float(np.sum(k * omega * c[1::2]))


@pytest.mark.parametrize("name, force, omega", ROWS, ids=str)
def test_dahl_orbit_left_by_time_integration_is_unstable(name, force, omega):
    beta, exponent, upper, lower = LAWS[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        law = hf.ModifiedDahl(beta=beta, exponent=exponent, upper=upper, lower=lower)
    osc = hf.Oscillator(mass=1.0, damping=0.01, stiffness=1.0, contact=law)
    solution = hf.periodic_solution(osc, force, omega)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = steady_state(
            osc,
            force,
            omega,
            initial_state=_state_at_zero(solution, omega),
            max_periods=1000,
        )
        stable = bool(solution.stability().stable[0])
    growth = run.amplitude(harmonic=1) / solution.amplitude(harmonic=1)
    assert growth > 10.0  # every row leaves its orbit
    assert not stable, growth
