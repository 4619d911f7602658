"""The stability of a modified Dahl law that gives energy is decided by the
monodromy (stop 33).

Hill's method linearises the contact force in the harmonics of the orbit,
with no term for the law's own memory. For a dissipating law that memory
contracts and Hill's verdicts hold on one DOF; for a law whose loops give
energy (``ModifiedDahl.active_reason()``) they did not: on the oscillator
m 1, c 0.01, k 1, F 0.5 with ``ModifiedDahl(beta=1, upper=(5, 1),
lower=(5, -1))``, ``Branch.stability()`` (Hill, one DOF) called the 30
points above 3.9 rad/s stable. The reference here is time integration
started on the orbit (its displacement and velocity at t = 0): from a
stable orbit it stays near it, from an unstable one it leaves.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.validation import steady_state

FORCE = 0.5


def _branch(upper, lower):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        law = hf.ModifiedDahl(beta=1.0, upper=upper, lower=lower)
    osc = hf.Oscillator(mass=1.0, damping=0.01, stiffness=1.0, contact=law)
    return osc, hf.frf(osc, force=FORCE, omega=(0.5, 5.0))


def _growth(osc, branch, index: int, periods: int = 200) -> float:
    """Amplitude of the last of ``periods`` periods integrated from the
    orbit's state at t = 0, over the orbit's amplitude."""
    point = branch.point(index)
    k = point.harmonic_numbers
    c = point.coefficients[0]
    omega = float(branch.omega[index])
    x0 = float(np.sum(c[0::2])) if k[0] != 0 else None
    v0 = float(np.sum(k * omega * c[1::2]))
    assert x0 is not None  # the symmetric branch: odd harmonics only
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = steady_state(
            osc, FORCE, omega, initial_state=(x0, v0), max_periods=periods
        )
    return run.amplitude(harmonic=1) / point.amplitude(harmonic=1)


def test_active_law_is_decided_by_the_monodromy():
    osc, branch = _branch((5.0, 1.0), (5.0, -1.0))
    hill = branch.stability(method="hill").stable.copy()
    called_stable = np.flatnonzero(hill)
    assert called_stable.size >= 10  # the case that misled Hill
    auto = branch.stability()
    assert not auto.stable[called_stable].any()
    # the reference: time integration from two of the points Hill called
    # stable leaves the orbit by orders of magnitude
    for omega in (4.0, 4.6):
        i = called_stable[np.argmin(np.abs(branch.omega[called_stable] - omega))]
        assert _growth(osc, branch, int(i), periods=1000) > 100.0


def test_dissipating_law_keeps_hill_and_its_verdicts_hold():
    # b - e = 3 > (a + d) / beta = 2: every loop dissipates
    osc, branch = _branch((1.0, 1.5), (1.0, -1.5))
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.AccuracyWarning)
        stability = branch.stability()
    assert stability.stable.all()
    for omega in (1.0, 2.0, 4.6):
        i = int(np.argmin(np.abs(branch.omega - omega)))
        assert _growth(osc, branch, i, periods=2000) == pytest.approx(1.0, abs=1e-4)


def test_dissipating_unequal_slopes_law_is_decided_by_the_monodromy():
    """A law whose loops dissipate (``b − e = 3.2`` above the large-loop
    limit 3, loop areas positive) whose memory still matters: at F = 2,
    4.6 rad/s Hill's verdict was stable (largest |μ| 0.993)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.AccuracyWarning)
        law = hf.ModifiedDahl(
            beta=1.0, exponent=2.0, upper=(4.0, 2.2), lower=(1.0, -1.0)
        )
    osc = hf.Oscillator(mass=1.0, damping=0.01, stiffness=1.0, contact=law)
    solution = hf.periodic_solution(osc, 2.0, 4.6)
    assert solution.stability(method="hill").stable[0]  # the misleading verdict
    assert not solution.stability().stable[0]
    k, c = solution.harmonic_numbers, solution.coefficients[0]
    assert k[0] == 0  # unequal slopes: the mean moves
    x0 = float(c[0] + np.sum(c[1::2]))
    v0 = float(np.sum(k[1:] * 4.6 * c[2::2]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = steady_state(osc, 2.0, 4.6, initial_state=(x0, v0), max_periods=1000)
    assert run.amplitude(harmonic=1) > 3.0 * solution.amplitude(harmonic=1)
