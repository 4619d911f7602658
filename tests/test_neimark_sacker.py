"""A Neimark–Sacker case: a forced oscillator with a nonlinear energy sink.

Primary mass ``m1 = 1`` on ``k1 = 1`` with damping 0.002, forced by
``F cos Ωt`` (``F = 0.005``); a light mass ``m2 = 0.05`` attached by a weak
linear spring (0.005), a damper (0.01) and a cubic spring (``k3 = 1``, a
relative ``hf.Cubic`` contact between the two DOFs): the classic nonlinear
energy sink, whose periodic response near the primary resonance loses
stability through a complex pair of Floquet multipliers (the strongly
modulated responses of the literature). Hill finds the pair crossing the
unit circle at Ω = 0.98723 rad/s.

Checked by independent routes: the monodromy of the time-integration
reference (the cubic law is memoryless, so Hill is exact up to
truncation), convergence in H of the located point, and time integration
that settles where Hill says stable and keeps modulating where it says
unstable.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.signals import state_at_zero
from hbmfric.validation import monodromy, steady_state

FORCE = 0.005
OMEGA_RANGE = (0.9, 1.1)


def energy_sink():
    m2, k2, c1, c2 = 0.05, 0.005, 0.002, 0.01
    return hf.LinearStructure(
        np.diag([1.0, m2]),
        np.array([[1.0 + k2, -k2], [-k2, k2]]),
        np.array([[c1 + c2, -c2], [-c2, c2]]),
        load={0: 1.0},
        contacts=[hf.Contact(hf.Cubic(1.0), 1, 0)],
    )


@pytest.fixture(scope="module")
def branch():
    return hf.frf(energy_sink(), FORCE, OMEGA_RANGE, harmonics=5)


def test_neimark_sacker_located_and_converged_in_harmonics(branch):
    """One Neimark–Sacker point (a complex pair of modulus 1, to 1e-9) at
    the same Ω at H = 5 and H = 9 (measured 5e-10 apart), followed by the
    two folds of the bent resonance."""
    points = branch.special_points()
    kinds = [p.kind for p in points]
    assert kinds.count("Neimark-Sacker") == 1
    ns = points[kinds.index("Neimark-Sacker")]
    assert abs(abs(ns.multiplier) - 1.0) < 1e-9
    assert abs(ns.multiplier.imag) > 0.1
    assert ns.omega == pytest.approx(0.98723, abs=1e-4)
    finer = hf.frf(energy_sink(), FORCE, OMEGA_RANGE, harmonics=9)
    ns9 = [p for p in finer.special_points() if p.kind == "Neimark-Sacker"]
    assert len(ns9) == 1 and abs(ns9[0].omega - ns.omega) < 1e-6
    # the time-domain monodromy of the located solution: a pair on the circle
    system = energy_sink()
    sol = state_at_zero(ns.harmonic_numbers, ns.coefficients, ns.omega)
    td = monodromy(system, sol, force=FORCE, omega=ns.omega)
    pair = td.multipliers[np.abs(td.multipliers.imag) > 0.1]
    assert pair.size == 2 and np.all(np.abs(np.abs(pair) - 1.0) < 1e-3)


def test_hill_against_the_time_domain_monodromy(branch):
    """5 points of each stretch between stability changes and folds: the
    same verdict, the moduli within 1e-3 (measured 1e-5)."""
    hill = branch.stability()
    cuts = sorted(set(hill.changes().tolist()) | set(branch.folds.tolist()))
    bounds = [0, *cuts, len(branch)]
    system = energy_sink()
    for lo, hi in zip(bounds[:-1], bounds[1:], strict=True):
        if hi - lo < 12:
            continue
        for i in np.linspace(lo + 3, hi - 4, 5).round().astype(int):
            td = monodromy(system, branch.point(int(i)))
            assert (td.max_modulus < 1.0) == bool(hill.stable[i])
            np.testing.assert_allclose(
                np.sort(np.abs(td.multipliers)),
                np.sort(np.abs(hill.multipliers[i])),
                atol=1e-3,
            )


@pytest.mark.slow
def test_time_integration_settles_before_and_modulates_after(branch):
    """Started on the HBM solution nudged by 1e-4: at Ω = 0.975 (stable)
    the integration settles back on it (first harmonic of the primary mass
    within 1e-4); at Ω = 0.995 (after the Neimark–Sacker point, unstable)
    it does not settle in 3000 periods."""
    system = energy_sink()
    hill = branch.stability()
    for omega, settles in ((0.975, True), (0.995, False)):
        i = int(np.argmin(np.abs(branch.omega[:200] - omega)))
        assert bool(hill.stable[i]) == settles
        sol = branch.point(i)
        x0, v0 = state_at_zero(sol.harmonic_numbers, sol.coefficients, sol.omega)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", hf.ConvergenceWarning)
            ref = steady_state(
                system,
                FORCE,
                sol.omega,
                initial_state=(x0 * (1 + 1e-4), v0),
                tol=1e-9,
                max_periods=3000,
            )
        if settles:
            assert ref.converged
            a = sol.amplitude(harmonic=1, dof=0)
            assert abs(ref.amplitude(harmonic=1, dof=0) - a) < 1e-4 * a
        else:
            assert not ref.converged
            assert any(issubclass(w.category, hf.ConvergenceWarning) for w in caught)
            assert ref.change > 1e-3
