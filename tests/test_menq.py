"""Menq microslip: the kernel against a discretised bar of Jenkins elements
(virgin curve, Masing branches, inner loops, arbitrary paths), the energy per
cycle against its closed form and the loop area, the AFT Jacobian against
finite differences, HBM against time integration, constructors and input
checks."""

import numpy as np
import pytest
from naive import loop_work, menq_virgin, shear_lag_bar
from scipy.integrate import quad

import hbmfric as hf
from hbmfric.kernels.laws import updates as kl

LAW = hf.Menq.from_stiffness(stiffness=3e4, slip_force=10.0, microslip_onset=0.5)
BAR = (LAW.axial_rigidity, LAW.length, LAW.shear_stiffness, LAW.friction_limit)
#: Jenkins elements of the reference bar (its error is ~3e-6 F* at 400)
N_BAR = 400
TOL = 1e-5 * LAW.slip_force
D_GS = LAW.gross_slip_displacement


def _reversals(u):
    du = np.diff(np.append(u, u[0]))
    s = np.sign(du[du != 0.0])
    return int(np.sum(s != np.roll(s, 1)))


def test_virgin_curve_against_the_bar_and_the_closed_form():
    delta = np.linspace(0.0, 1.3 * D_GS, 80)
    kernel = LAW.virgin_curve(delta)
    closed = np.array([menq_virgin(d, *BAR) for d in delta])
    np.testing.assert_allclose(kernel, closed, rtol=0, atol=1e-13 * LAW.slip_force)
    bar = shear_lag_bar(delta, *BAR, N_BAR)
    assert np.max(np.abs(bar - kernel)) < TOL
    # the three regimes are all present
    assert delta[1] < LAW.slip_displacement < D_GS < delta[-1]


@pytest.mark.parametrize(
    ("a1", "a3", "mean", "inner"),
    [
        (0.6, 0.0, 0.0, False),  # microslip loop (Masing branches)
        (1.5, 0.0, 0.0, False),  # gross slip
        (0.6, 0.25, 0.1, True),  # inner loops, mean offset
        (1.2, 0.5, 0.3, True),  # inner loops in gross slip
        (0.3, 0.1, 0.5, True),  # one-sided motion, partial slip
    ],
)
def test_steady_loop_against_the_bar(a1, a3, mean, inner):
    """Steady loop of the kernel against the bar closed at 0, brought to the
    first sample and driven through two periods (the second is compared)."""
    n = 256
    theta = 2.0 * np.pi * np.arange(n) / n
    u = D_GS * (mean + a1 * np.cos(theta) + a3 * np.cos(3.0 * theta + 0.7))
    assert (_reversals(u) > 2) == inner
    force = LAW.hysteresis(u)
    path = np.concatenate((np.linspace(0.0, u[0], 20), u, u))
    bar = shear_lag_bar(path, *BAR, N_BAR)[-n:]
    assert np.max(np.abs(bar - force)) < TOL


def _march_law_step(path):
    """Forces along ``path`` from the virgin state through ``law_step``;
    each step is first taken without committing (a trial must give the same
    force). Returns ``(forces, final state)``."""
    params = LAW.params
    code = np.int64(LAW.code)
    state = np.empty(kl.state_size(code, params))
    kl.law_init(code, params, 0.0, state)
    forces = np.empty(path.size)
    u_prev = 0.0
    for i, u in enumerate(path):
        trial = kl.law_step(code, params, state, u_prev, u, False)[0]
        forces[i] = kl.law_step(code, params, state, u_prev, u, True)[0]
        assert trial == forces[i]
        u_prev = u
    return forces, state


def test_arbitrary_path_through_law_step_against_the_bar():
    """Madelung's memory on a random path (nested loops opened and closed in
    every order), through the time-integration contract ``law_step``."""
    rng = np.random.default_rng(3)
    turns = D_GS * np.cumsum(rng.normal(0.0, 0.5, 40))
    path = np.concatenate(
        [np.linspace(a, b, 6)[1:] for a, b in zip(turns[:-1], turns[1:], strict=True)]
    )
    forces, _ = _march_law_step(path)
    bar = shear_lag_bar(path, *BAR, N_BAR)
    assert np.max(np.abs(bar - forces)) < TOL


def test_memory_overflow_drops_only_outer_loops():
    """A decaying oscillation leaves more reversal points than the state
    holds; forgetting the oldest (outermost) loops does not change the
    force, checked against the bar."""
    n_turns = 2 * kl.MEMORY_CAPACITY + 20
    turns = D_GS * 1.2 * (-0.985) ** np.arange(n_turns)
    path = np.concatenate(
        [np.linspace(a, b, 4)[1:] for a, b in zip(turns[:-1], turns[1:], strict=True)]
    )
    forces, state = _march_law_step(path)
    assert int(state[1]) <= kl.MEMORY_CAPACITY
    bar = shear_lag_bar(path, *BAR, N_BAR)
    assert np.max(np.abs(bar - forces)) < TOL


def _virgin_integral(a):
    """``∫₀^a F_load`` by adaptive quadrature, piece by piece; on the
    microslip piece ``s = s_end - v²`` removes the square-root behaviour of
    the curve at the onset of gross slip."""
    d1 = LAW.slip_displacement
    total = quad(lambda s: menq_virgin(s, *BAR), 0.0, min(a, d1), epsrel=1e-14)[0]
    if a > d1:
        end = min(a, D_GS)
        total += quad(
            lambda v: 2.0 * v * menq_virgin(end - v * v, *BAR),
            0.0,
            np.sqrt(end - d1),
            epsrel=1e-14,
            limit=200,
        )[0]
    if a > D_GS:
        total += quad(lambda s: menq_virgin(s, *BAR), D_GS, a, epsrel=1e-14)[0]
    return total


@pytest.mark.parametrize("ratio", [0.3, 0.8, 1.0, 1.5, 4.0])
def test_energy_per_cycle(ratio):
    """Closed form ``8 ∫ F_load − 4 a F_a`` against the same formula by
    adaptive quadrature of the bisection-inverted curve, and against the
    area of the sampled loop (trapezoidal, 8192 samples)."""
    a = ratio * D_GS
    w = LAW.energy_per_cycle(a)
    integral = _virgin_integral(a)
    expected = 8.0 * integral - 4.0 * a * menq_virgin(a, *BAR)
    assert w == pytest.approx(expected, rel=1e-9, abs=1e-14)
    theta = 2.0 * np.pi * np.arange(8192) / 8192
    u = a * np.cos(theta)
    area = loop_work(u, LAW.hysteresis(u))
    assert w == pytest.approx(area, rel=2e-6, abs=1e-12)
    if a <= LAW.slip_displacement:
        assert w == 0.0


def test_energy_in_gross_slip_grows_like_jenkins():
    """Beyond gross slip the loop only gains the slipping strips:
    ``dW/da = 4 F*``."""
    a = 2.0 * D_GS
    slope = (LAW.energy_per_cycle(a * 1.01) - LAW.energy_per_cycle(a)) / (0.01 * a)
    assert slope == pytest.approx(4.0 * LAW.slip_force, rel=1e-9)


def test_stuck_loop_is_linear_and_skips_the_march():
    u = 0.9 * LAW.slip_displacement * np.cos(np.linspace(0, 2 * np.pi, 32, False))
    np.testing.assert_allclose(LAW.hysteresis(u), LAW.stiffness * u, rtol=1e-14)


def test_from_stiffness_round_trip_and_normal_load():
    law = hf.Menq.from_stiffness(
        stiffness=2e5,
        friction_coefficient=0.4,
        normal_load=50.0,
        microslip_onset=0.2,
        length=0.02,
    )
    assert law.stiffness == pytest.approx(2e5, rel=1e-12)
    assert law.slip_force == pytest.approx(20.0, rel=1e-12)
    assert law.microslip_onset == pytest.approx(0.2, rel=1e-12)
    assert law.length == 0.02
    moved = law.with_normal_load(100.0)
    assert moved.slip_force == pytest.approx(40.0, rel=1e-12)
    assert moved.stiffness == pytest.approx(law.stiffness, rel=1e-14)
    assert moved.microslip_onset == pytest.approx(0.2, rel=1e-12)
    # the physical constructor with q = μ F_n / L is the same law
    physical = hf.Menq(
        law.axial_rigidity,
        law.length,
        law.shear_stiffness,
        friction_limit=0.4 * 50.0 / 0.02,
    )
    np.testing.assert_allclose(physical.params, law.params, rtol=1e-13)
    # near-Jenkins limit: onset -> 1 gives Jenkins' loop
    near = hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0, microslip_onset=0.9999)
    jenkins = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    assert near.energy_per_cycle(1.0) == pytest.approx(
        jenkins.energy_per_cycle(1.0), rel=1e-3
    )


def _paper(contact):
    return hf.Oscillator(mass=1.0, damping=4.0, stiffness=1e4, contact=contact)


def test_roughness_on_menq():
    """Above the limit load the wrapped law is the plain law; below it the
    shear-layer stiffness follows the roughness rule."""
    plain = hf.Menq.from_stiffness(
        stiffness=3e4, friction_coefficient=1.0, normal_load=500.0, microslip_onset=0.5
    )
    rough = hf.Roughness(plain, limit_load=300.0)
    np.testing.assert_array_equal(rough.params, plain.params)
    a = hf.frf(_paper(plain), 50.0, (50.0, 300.0), harmonics=7)
    b = hf.frf(_paper(rough), 50.0, (50.0, 300.0), harmonics=7)
    np.testing.assert_allclose(b.amplitude(harmonic=1), a.amplitude(harmonic=1))
    low = rough.with_normal_load(37.5)
    assert low.effective.shear_stiffness == pytest.approx(
        0.5 * plain.shear_stiffness, rel=1e-14
    )
    assert low.effective.slip_force == pytest.approx(37.5, rel=1e-14)
    assert low.stuck_stiffness < plain.stuck_stiffness


OMEGAS = [0.8, 1.2, 1.45, 1.6, 1.8, 2.1, 2.6]


@pytest.mark.parametrize("rough", [False, True])
def test_hbm_against_time_integration(rough):
    """First harmonic of HBM (H = 15, located reversals) against the Newmark
    reference at frequencies that cover stick, microslip and gross slip;
    also through the roughness wrapper below its limit load (shear layer
    at half its stiffness)."""
    law = hf.Menq.from_stiffness(
        stiffness=3.0, friction_coefficient=1.0, normal_load=1.0, microslip_onset=0.5
    )
    if rough:
        law = hf.Roughness(law.with_normal_load(0.6), limit_load=4.8)
        assert law.effective.shear_stiffness == pytest.approx(
            0.5 * law.law.shear_stiffness
        )
    osc = hf.Oscillator(1.0, 0.02, 1.0, law)
    states = set()
    for omega in OMEGAS:
        sol = hf.periodic_solution(osc, 0.5, omega, harmonics=15)
        ref = hf.validation.steady_state(osc, 0.5, omega, harmonics=15)
        assert ref.converged
        states.add(sol.contact_state.split()[1])
        a, b = sol.amplitude(harmonic=1), ref.amplitude(harmonic=1)
        assert abs(a / b - 1.0) < 1e-3, (omega, a, b)
    assert states == {"stuck", "partially", "slips"}


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"axial_rigidity": 0.0}, "axial_rigidity"),
        ({"length": -1.0}, "length"),
        ({"shear_stiffness": np.nan}, "shear_stiffness"),
        ({"friction_limit": None}, "friction_limit"),
        ({"friction_limit": -1.0}, "friction_limit"),
        ({"friction_limit": None, "friction_coefficient": 0.3}, "normal_load"),
    ],
)
def test_bad_menq_parameters(kwargs, match):
    base = {
        "axial_rigidity": 1.0,
        "length": 1.0,
        "shear_stiffness": 1.0,
        "friction_limit": 1.0,
    }
    base.update(kwargs)
    with pytest.raises(ValueError, match=match):
        hf.Menq(**base)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"stiffness": 0.0}, "stiffness"),
        ({"microslip_onset": 1.0}, "microslip_onset"),
        ({"microslip_onset": 0.0}, "microslip_onset"),
        ({"slip_force": None}, "slip_force"),
        ({"length": 0.0}, "length"),
    ],
)
def test_bad_from_stiffness(kwargs, match):
    base = {"stiffness": 1.0, "slip_force": 1.0, "microslip_onset": 0.5}
    base.update(kwargs)
    with pytest.raises(ValueError, match=match):
        hf.Menq.from_stiffness(**base)


def test_with_normal_load_needs_a_friction_coefficient():
    with pytest.raises(ValueError, match="friction_coefficient"):
        LAW.with_normal_load(2.0)
