"""Iwan's model: one element is Jenkins, the Masing march equals independent
Jenkins elements marched one by one, Segalman's distribution keeps its
totals and its small-amplitude power law, energy per cycle, roughness, HBM
against time integration, input checks."""

import numpy as np
import pytest
from naive import iwan_march, loop_work

import hbmfric as hf

SEGALMAN = hf.Iwan.segalman(
    slip_force=1.0, stiffness=3.0, chi=-0.4, beta=0.3, n_elements=50
)


def _path(n=240, seed=None):
    theta = 2.0 * np.pi * np.arange(n) / n
    u = 0.9 * np.cos(theta) + 0.35 * np.cos(3.0 * theta + 0.4) + 0.2
    if seed is not None:
        rng = np.random.default_rng(seed)
        for k in range(1, 6):
            u += rng.normal(0.0, 0.3 / k) * np.cos(k * theta + rng.uniform(0, 6))
    return u


@pytest.mark.parametrize("scale", [0.1, 0.4, 1.0, 3.0])
def test_one_element_is_jenkins(scale):
    """Same loops (periodic_force) and same sampled-AFT HBM solutions as
    the Jenkins element, to rounding."""
    jenkins = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    iwan = hf.Iwan(stiffnesses=[3.0], slip_forces=[1.0])
    for seed in (None, 1, 2):
        u = scale * _path(seed=seed)
        np.testing.assert_allclose(
            iwan.hysteresis(u), jenkins.hysteresis(u), rtol=0, atol=1e-13
        )
    assert iwan.energy_per_cycle(scale) == pytest.approx(
        jenkins.energy_per_cycle(scale), rel=1e-14, abs=1e-15
    )
    for omega in (1.1, 1.6):
        a = hf.periodic_solution(
            hf.Oscillator(1.0, 0.02, 1.0, jenkins), scale, omega, aft="samples"
        )
        b = hf.periodic_solution(
            hf.Oscillator(1.0, 0.02, 1.0, iwan), scale, omega, aft="samples"
        )
        np.testing.assert_allclose(b.coefficients, a.coefficients, atol=1e-10)


@pytest.mark.parametrize("seed", [None, 3, 4, 5])
def test_masing_march_equals_independent_elements(seed):
    """The Masing/Madelung march of the whole model against each Jenkins
    element marched on its own to its periodic state (tests/naive.py)."""
    u = _path(seed=seed)
    expected = iwan_march(u, SEGALMAN.stiffnesses, SEGALMAN.slip_forces)
    np.testing.assert_allclose(SEGALMAN.hysteresis(u), expected, rtol=0, atol=1e-12)


def test_segalman_totals_and_power_law():
    """``Σ k = K_T`` and ``Σ f = F_S`` exactly; at small amplitude the energy
    per cycle grows as ``a^(3 + χ)`` (Segalman's power law)."""
    chi = -0.4
    law = hf.Iwan.segalman(
        slip_force=2.0, stiffness=5.0, chi=chi, beta=0.3, n_elements=4000
    )
    assert law.stiffness == pytest.approx(5.0, rel=1e-12)
    assert law.slip_force == pytest.approx(2.0, rel=1e-12)
    a = np.array([1e-3, 2e-3]) * 2.0 / 5.0
    w = np.array([law.energy_per_cycle(x) for x in a])
    slope = np.log(w[1] / w[0]) / np.log(2.0)
    assert slope == pytest.approx(3.0 + chi, abs=0.02)
    # the delta: its element slips last, at φ_max = F_S (1+β)/(K_T (β + c))
    c = (chi + 1.0) / (chi + 2.0)
    phi = np.asarray(law.slip_forces) / np.asarray(law.stiffnesses)
    assert phi.max() == pytest.approx(2.0 * 1.3 / (5.0 * (0.3 + c)), rel=1e-12)


@pytest.mark.parametrize("a", [0.02, 0.2, 0.5, 2.0])
def test_energy_per_cycle_against_the_loop_area(a):
    theta = 2.0 * np.pi * np.arange(8192) / 8192
    u = a * np.cos(theta)
    area = loop_work(u, SEGALMAN.hysteresis(u))
    assert SEGALMAN.energy_per_cycle(a) == pytest.approx(area, rel=1e-6)


def test_virgin_curve_saturates_at_the_slip_force():
    phi = np.asarray(SEGALMAN.slip_forces) / np.asarray(SEGALMAN.stiffnesses)
    assert SEGALMAN.virgin_curve(2.0 * phi.max()) == pytest.approx(1.0, rel=1e-14)
    assert SEGALMAN.virgin_curve(-1e-9) == pytest.approx(-3e-9, rel=1e-6)


def test_normal_load_and_roughness():
    law = hf.Iwan.segalman(
        slip_force=50.0,
        stiffness=3e4,
        chi=-0.5,
        beta=0.1,
        n_elements=20,
        normal_load=500.0,
    )
    assert law.slip_force == pytest.approx(50.0, rel=1e-12)
    moved = law.with_normal_load(1000.0)
    assert moved.slip_force == pytest.approx(100.0, rel=1e-12)
    assert moved.stiffness == pytest.approx(law.stiffness, rel=1e-14)
    rough = hf.Roughness(law, limit_load=300.0)
    np.testing.assert_array_equal(rough.params, law.params)
    low = rough.with_normal_load(37.5)
    assert low.effective.stiffness == pytest.approx(0.5 * 3e4, rel=1e-12)
    assert low.effective.slip_force == pytest.approx(3.75, rel=1e-12)
    with pytest.raises(ValueError, match="friction_coefficients"):
        hf.Iwan([1.0], [1.0]).with_normal_load(2.0)


OMEGAS = [0.8, 1.2, 1.45, 1.6, 1.8, 2.1, 2.6]


def test_hbm_against_time_integration():
    """First harmonic of HBM (H = 15) against the Newmark reference."""
    law = hf.Iwan.segalman(
        slip_force=1.0, stiffness=3.0, chi=-0.5, beta=0.2, n_elements=50
    )
    osc = hf.Oscillator(1.0, 0.02, 1.0, law)
    for omega in OMEGAS:
        sol = hf.periodic_solution(osc, 0.5, omega, harmonics=15)
        ref = hf.validation.steady_state(osc, 0.5, omega, harmonics=15)
        assert ref.converged
        a, b = sol.amplitude(harmonic=1), ref.amplitude(harmonic=1)
        assert abs(a / b - 1.0) < 1e-3, (omega, a, b)


@pytest.mark.parametrize(
    ("args", "kwargs", "match"),
    [
        (([],), {"slip_forces": []}, "stiffnesses"),
        (([1.0, 0.0],), {"slip_forces": [1.0, 1.0]}, "stiffnesses"),
        (([1.0],), {"slip_forces": [-1.0]}, "slip_forces"),
        (([1.0, 2.0],), {"slip_forces": [1.0]}, "length"),
        (([1.0],), {}, "slip_forces"),
        (([1.0],), {"friction_coefficients": [0.3]}, "normal_load"),
        (([1.0],), {"slip_forces": [np.nan]}, "finite"),
    ],
)
def test_bad_iwan_parameters(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        hf.Iwan(*args, **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"chi": -1.0}, "chi"),
        ({"beta": -0.1}, "beta"),
        ({"slip_force": 0.0}, "slip_force"),
        ({"stiffness": -1.0}, "stiffness"),
        ({"n_elements": 1}, "n_elements"),
    ],
)
def test_bad_segalman_parameters(kwargs, match):
    base = {"slip_force": 1.0, "stiffness": 1.0, "chi": -0.5, "beta": 0.1}
    base.update(kwargs)
    with pytest.raises(ValueError, match=match):
        hf.Iwan.segalman(**base)
