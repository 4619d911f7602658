"""The monodromy by time integration started from a harmonic-balance
solution (issue 14). A Jenkins contact starts virgin there and forgets it
at the rate of the slowest multiplier; two settling periods left the start
up to 2e-2 off the orbit on stick-slip responses and the multipliers up to
8e-3 off the exact event-driven ones (5 % of 0.177). A start that is not on
an orbit at all (the force or Ω of another solution) gave multipliers
without a word."""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.signals import state_at_zero
from hbmfric.validation import exact_periodic_solution, monodromy


def _state_at_zero(solution):
    return state_at_zero(
        solution.harmonic_numbers, solution.coefficients, solution.omega
    )


JENKINS3 = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


@pytest.mark.parametrize(
    ("force", "omega"), [(0.5, 1.7), (0.5, 2.0), (0.5, 2.3), (2.0, 1.1)]
)
def test_stick_slip_multipliers_from_a_harmonic_balance_start(force, omega):
    """Against the exact monodromy (phase propagators and saltation):
    within 1e-3 at 8192 steps (measured 1.7e-4 to 6.7e-4; 1.1e-3 to 8.1e-3
    before), the start settled until it closes on itself."""
    exact = exact_periodic_solution(JENKINS3, force, omega)
    assert exact.kind == "stick-slip"
    solution = hf.periodic_solution(JENKINS3, force, omega)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        result = monodromy(JENKINS3, solution, steps_per_period=8192)
    error = np.abs(np.abs(exact.floquet_multipliers()) - np.abs(result.multipliers))
    assert error.max() < 1e-3, (exact.floquet_multipliers(), result.multipliers)
    assert result.closure <= 1e-6
    assert result.settle_periods >= 2


@pytest.mark.parametrize(
    ("force", "omega"), [(0.5, 1.7), (0.5, 2.0), (0.5, 2.3), (2.0, 1.1)]
)
def test_the_start_is_on_the_hysteresis_loop(force, omega):
    """The law's state is marched around the solution's own loop: with no
    settling at all one period moves the start by 1e-5 to 1.3e-4 of its peak
    (the harmonic balance against the integrator's steps); a virgin law
    there was 2e-2 to 1.7e-1 off, and needed 8 to 39 periods to close to
    1e-6 (2 to 14 now)."""
    solution = hf.periodic_solution(JENKINS3, force, omega)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        bare = monodromy(JENKINS3, solution, steps_per_period=8192, settle_periods=0)
    assert bare.closure < 1e-3
    assert bare.settle_periods == 0


def test_a_fixed_settle_is_kept():
    """A state (not a solution) as the start: the law starts virgin there,
    off the orbit, and a fixed settle of 0 is kept and warned about."""
    solution = hf.periodic_solution(JENKINS3, 0.5, 2.0)
    x0, v0 = _state_at_zero(solution)
    with pytest.warns(hf.AccuracyWarning) as record:
        result = monodromy(JENKINS3, (x0, v0), force=0.5, omega=2.0, settle_periods=0)
    messages = " ".join(str(w.message) for w in record)
    assert "not on a periodic orbit" in messages
    assert result.settle_periods == 0
    assert result.closure > 1e-2


@pytest.mark.parametrize(
    "override", [{"force": 0.0}, {"force": 0.4}, {"omega": 1.25}], ids=str
)
def test_a_start_off_the_orbit_warns(override):
    """The solution of F = 0.2, Ω = 1.2 with another force or Ω: the map
    moves it by 1e-1 of its peak; on its own orbit by 3e-6."""
    duffing = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    solution = hf.periodic_solution(duffing, 0.2, 1.2, harmonics=9)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        good = monodromy(duffing, solution)
    assert good.closure < 1e-4
    with pytest.warns(hf.AccuracyWarning) as record:
        bad = monodromy(duffing, solution, settle_periods=0, **override)
    assert "not on a periodic orbit" in " ".join(str(w.message) for w in record)
    assert bad.closure > 1e-2
    # settled by default, it reaches an orbit, not the solution given
    with pytest.warns(hf.AccuracyWarning) as record:
        monodromy(duffing, solution, **override)
    assert "away from the solution" in " ".join(str(w.message) for w in record)
