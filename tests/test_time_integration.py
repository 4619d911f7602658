"""The time-integration reference (``hbmfric.validation``) against references
that do not use it: closed-form linear FRFs (one and two DOFs, stuck and
slipping limits of the Jenkins law), the convergence order of the scheme
fitted over step sizes, and the energy balance of the steady state."""

import warnings
from dataclasses import dataclass

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.validation import SteadyState, steady_state
from hbmfric.validation import integrator as kernels

M, C, K = 1.0, 0.02, 1.0
KT, FS = 3.0, 1.0


def linear_amplitude(force, omega, mass, damping, stiffness):
    """``F / |k - m Ω² + i c Ω|``, m."""
    return force / abs(stiffness - mass * omega**2 + 1j * damping * omega)


@pytest.fixture(scope="module")
def jenkins():
    return hf.Oscillator(M, C, K, hf.Jenkins(stiffness=KT, slip_force=FS))


@dataclass(frozen=True)
class Chain:
    """Two masses in a chain to ground, contact on the second one."""

    contact: hf.ContactLaw | None = None
    n_dof = 2
    contact_dof = 1

    def matrices(self):
        mass = np.diag([1.0, 0.5])
        stiffness = np.array([[3.0, -1.0], [-1.0, 1.0]])
        return mass, 0.01 * mass + 0.01 * stiffness, stiffness

    def load_vector(self, force):
        return np.array([force, 0.0])


def spectrum(x):
    """All harmonics of one sampled period: ``(k, Xc_k, Xs_k)``, k < N/2."""
    c = np.fft.rfft(x) / x.size
    k = np.arange(1, x.size // 2)
    return k, 2.0 * c[k].real, -2.0 * c[k].imag


def energy_per_period(ref: SteadyState, damping):
    """Work of ``F cos Ωt``, viscous and contact dissipation over the last
    period, J; the first from the first harmonic alone (``π F Xs1``)."""
    x = ref.samples[0]
    k, xc, xs = spectrum(x)
    work_input = np.pi * ref.force * ref.coefficients[0, 2]
    viscous = np.pi * damping * ref.omega * np.sum(k**2 * (xc**2 + xs**2))
    f = ref.contact_force
    contact = np.sum(0.5 * (f + np.roll(f, -1)) * (np.roll(x, -1) - x))
    return work_input, viscous, contact


# --- linear limits ------------------------------------------------------------


@pytest.mark.parametrize(
    ("contact", "stiffness", "omegas"),
    [
        (None, K, (0.5, 2.5)),
        (hf.Jenkins(stiffness=KT, slip_force=1e9), K + KT, (1.2, 3.0)),  # stuck
        (hf.Jenkins(stiffness=KT, slip_force=0.0), K, (0.5, 2.5)),  # free slider
    ],
)
def test_linear_limits_match_closed_form_frf(contact, stiffness, omegas):
    osc = hf.Oscillator(M, C, K, contact)
    for omega in omegas:
        ref = steady_state(osc, 0.5, omega, steps_per_period=4096)
        exact = linear_amplitude(0.5, omega, M, C, stiffness)
        assert ref.converged
        # Newmark's relative error is about (Ω h)²/12 = 2e-7 at 4096 steps
        assert ref.amplitude(harmonic=1) == pytest.approx(exact, rel=1e-6)
        assert ref.amplitude() == pytest.approx(exact, rel=1e-6)
        assert ref.amplitude(harmonic=3) < 1e-9 * exact


@pytest.mark.parametrize(
    ("contact", "contact_stiffness"),
    [(None, 0.0), (hf.Jenkins(stiffness=2.0, slip_force=1e9), 2.0)],
)
def test_two_dof_linear_matches_complex_frf(contact, contact_stiffness):
    system = Chain(contact)
    mass, damping, stiffness = system.matrices()
    stiffness = stiffness.copy()
    stiffness[1, 1] += contact_stiffness
    omega = 0.8
    X = np.linalg.solve(
        stiffness - omega**2 * mass + 1j * omega * damping, system.load_vector(0.3)
    )
    ref = steady_state(system, 0.3, omega, steps_per_period=4096)
    assert ref.converged
    assert ref.coefficients.shape == (2, 31)
    # x = Re(X e^{iΩt}) = Re X cos Ωt - Im X sin Ωt
    np.testing.assert_allclose(
        ref.coefficients[:, 1:3],
        np.column_stack((X.real, -X.imag)),
        rtol=0,
        atol=1e-6 * np.abs(X).max(),
    )


# --- convergence order ----------------------------------------------------------


def test_second_order_against_the_exact_linear_response():
    """Fitted order from three step sizes, near resonance."""
    osc = hf.Oscillator(1.0, 0.05, 1.0)
    omega = 1.05
    exact = linear_amplitude(0.3, omega, 1.0, 0.05, 1.0)
    steps = np.array([32, 64, 128])
    errors = [
        abs(
            steady_state(osc, 0.3, omega, steps_per_period=int(n)).amplitude(harmonic=1)
            / exact
            - 1
        )
        for n in steps
    ]
    order = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 1.9 < order < 2.1, (errors, order)


def test_second_order_on_duffing_by_self_convergence():
    """No closed form: the differences between successive halvings shrink
    fourfold."""
    osc = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    amplitudes = [
        steady_state(osc, 0.2, 0.8, steps_per_period=n, tol=1e-12).amplitude(harmonic=1)
        for n in (32, 64, 128, 256)
    ]
    differences = np.abs(np.diff(amplitudes))
    orders = np.log2(differences[:-1] / differences[1:])
    np.testing.assert_allclose(orders, 2.0, atol=0.05)


def test_halving_estimate_predicts_the_error():
    """For a second-order scheme the error is 4/3 of the halving change."""
    osc = hf.Oscillator(M, C, K, hf.Jenkins(stiffness=KT, slip_force=1e9))
    ref = steady_state(osc, 0.5, 1.2, steps_per_period=512, check_halving=True)
    exact = linear_amplitude(0.5, 1.2, M, C, K + KT)
    error = abs(ref.amplitude(harmonic=1) / exact - 1)
    assert ref.halving_periods > 0
    assert 4.0 / 3.0 * ref.error_estimate == pytest.approx(error, rel=0.02)


def test_halving_estimate_of_the_jenkins_oscillator(jenkins):
    ref = steady_state(jenkins, 2.0, 1.2, check_halving=True)
    assert ref.converged
    assert 0.0 < ref.error_estimate < 1e-5
    assert np.isnan(steady_state(jenkins, 2.0, 1.2).error_estimate)


# --- energy balance -------------------------------------------------------------


def test_energy_balance_stuck_jenkins(jenkins):
    """F = 0.5, Ω = 1.2: the contact sticks once the transient has died
    (|f| < f_s), so it dissipates nothing and the excitation feeds the
    viscous damper alone."""
    ref = steady_state(jenkins, 0.5, 1.2)
    assert ref.converged
    assert np.abs(ref.contact_force).max() < 0.99 * FS
    work_input, viscous, contact = energy_per_period(ref, C)
    assert abs(contact) < 1e-9 * work_input
    assert work_input == pytest.approx(viscous + contact, rel=1e-4)
    # stuck: the linear FRF with k + kt (the slider offset only shifts X0)
    exact = linear_amplitude(0.5, 1.2, M, C, K + KT)
    assert ref.amplitude(harmonic=1) == pytest.approx(exact, rel=2e-6)


def test_energy_balance_slipping_jenkins(jenkins):
    """F = 2, Ω = 1.2: gross slip. The friction work from the force loop
    closes the balance and equals the Masing loop ``4 f_s (A - f_s/kt)``."""
    ref = steady_state(jenkins, 2.0, 1.2)
    assert ref.converged
    assert np.abs(ref.contact_force).max() == pytest.approx(FS, rel=1e-12)
    work_input, viscous, contact = energy_per_period(ref, C)
    assert contact > 0.2 * work_input
    assert work_input == pytest.approx(viscous + contact, rel=1e-4)
    masing = 4.0 * FS * (ref.amplitude() - FS / KT)
    assert contact == pytest.approx(masing, rel=1e-4)


def test_duffing_basins_from_the_initial_state():
    """Inside the fold region the upper and lower stable states coexist;
    each is a steady state (energy balance, no friction)."""
    osc = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    upper = steady_state(osc, 0.2, 1.25, initial_state=(3.5, 0.0))
    lower = steady_state(osc, 0.2, 1.25)
    assert upper.converged and lower.converged
    assert upper.amplitude(harmonic=1) > 5 * lower.amplitude(harmonic=1)
    for ref in (upper, lower):
        work_input, viscous, contact = energy_per_period(ref, 0.05)
        # a conservative spring: its discrete loop closes to O(h²)
        assert abs(contact) < 1e-5 * work_input
        assert work_input == pytest.approx(viscous + contact, rel=1e-4)


# --- start, counters, result object -------------------------------------------


def test_linear_start_skips_the_transient_when_stuck(jenkins):
    rest = steady_state(jenkins, 0.5, 1.2)
    linear = steady_state(jenkins, 0.5, 1.2, initial_state="linear")
    assert linear.converged and linear.periods <= 8 < rest.periods
    assert linear.amplitude(harmonic=1) == pytest.approx(
        rest.amplitude(harmonic=1), rel=1e-9
    )
    # the stuck steady state is not unique: the transient from rest left the
    # slider off centre, the linear start did not
    assert abs(linear.coefficients[0, 0]) < 1e-9
    assert abs(rest.coefficients[0, 0]) > 1e-3


def test_work_counters(jenkins):
    stuck = steady_state(jenkins, 0.5, 1.2, initial_state="linear")
    assert stuck.steps == stuck.periods * stuck.steps_per_period
    # stuck: one Newton step lands on the linear branch
    assert stuck.newton_iterations == stuck.steps
    slipping = steady_state(jenkins, 2.0, 1.2)
    assert slipping.steps < slipping.newton_iterations <= 2 * slipping.steps
    free = steady_state(hf.Oscillator(M, C, K), 0.5, 1.2)
    assert free.newton_iterations == 0
    assert free.elapsed > 0 and free.status == kernels.OK and free.message == "ok"


def test_max_periods_reports_not_converged(jenkins):
    with pytest.warns(hf.ConvergenceWarning, match="3 periods: max_periods"):
        ref = steady_state(jenkins, 0.5, 1.2, max_periods=3)
    assert ref.periods == 3
    assert not ref.converged and ref.change > 1e-3
    assert "max_periods" in ref.message
    assert ref.samples.shape == (1, 2048)


def test_kernel_failure_is_reported_not_raised():
    """A softening spring thrown far out escapes to infinity."""
    osc = hf.Oscillator(1.0, 0.0, 1.0, hf.Cubic(-10.0))
    with pytest.warns(hf.ConvergenceWarning, match="did not reach"):
        ref = steady_state(osc, 1.0, 1.0, initial_state=(10.0, 0.0))
    assert not ref.converged
    assert ref.status != kernels.OK
    assert ref.message == kernels.MESSAGES[ref.status]
    assert np.isnan(ref.amplitude(harmonic=1))


def test_failure_raises_when_asked(jenkins):
    with pytest.raises(hf.ConvergenceError, match="max_periods"):
        steady_state(jenkins, 0.5, 1.2, max_periods=3, on_failure="raise")
    osc = hf.Oscillator(1.0, 0.0, 1.0, hf.Cubic(-10.0))
    with pytest.raises(hf.ConvergenceError, match="did not reach"):
        steady_state(osc, 1.0, 1.0, initial_state=(10.0, 0.0), on_failure="raise")
    with pytest.raises(ValueError, match="on_failure"):
        steady_state(jenkins, 0.5, 1.2, on_failure="ignore")


def test_converged_steady_state_does_not_warn(jenkins):
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        ref = steady_state(jenkins, 0.5, 1.2)
    assert ref.converged


def test_time_response_interpolates_the_samples(jenkins):
    ref = steady_state(jenkins, 2.0, 1.2, steps_per_period=256, harmonics=15)
    t, x = ref.time_response(n=256)
    np.testing.assert_allclose(x, ref.samples[0], rtol=0, atol=1e-13)
    np.testing.assert_allclose(t, np.arange(256) * ref.period / 256)
    t4, x4 = ref.time_response(n=1024)
    np.testing.assert_allclose(x4[::4], ref.samples[0], rtol=0, atol=1e-13)
    # coarse resampling keeps the harmonics below n/2
    _, x32 = ref.time_response(n=32)
    theta = 2 * np.pi * np.arange(32) / 32
    k, xc, xs = spectrum(ref.samples[0])
    keep = k < 16
    series = ref.coefficients[0, 0] + (
        xc[keep] @ np.cos(np.outer(k[keep], theta))
        + xs[keep] @ np.sin(np.outer(k[keep], theta))
    )
    nyquist = xc[15] * np.cos(16 * theta)
    np.testing.assert_allclose(x32, series + nyquist, rtol=0, atol=1e-13)


def test_result_layout(jenkins):
    ref = steady_state(jenkins, 2.0, 1.2, harmonics=7)
    np.testing.assert_array_equal(ref.harmonic_numbers, np.arange(8))
    assert ref.coefficients.shape == (1, 15)
    assert ref.contact_force.shape == (2048,)
    # odd law, symmetric system: even harmonics vanish
    assert ref.amplitude(harmonic=2) < 1e-9 * ref.amplitude(harmonic=1)
    assert ref.amplitude(harmonic=0) < 1e-9 * ref.amplitude(harmonic=1)
    assert ref.amplitude(harmonic=3) > 1e-3 * ref.amplitude(harmonic=1)
    assert "converged=True" in repr(ref)
    with pytest.raises(ValueError, match="harmonic"):
        ref.amplitude(harmonic=8)
    with pytest.raises(ValueError, match="dof"):
        ref.amplitude(dof=1)
    with pytest.raises(ValueError, match="n must"):
        ref.time_response(n=1)


@pytest.mark.filterwarnings("ignore::hbmfric.ConvergenceWarning")
def test_kernels_compile_once(jenkins):
    steady_state(jenkins, 0.5, 1.2, max_periods=2)
    steady_state(hf.Oscillator(M, C, K), 0.5, 1.2, max_periods=2)
    steady_state(Chain(hf.Jenkins(stiffness=2.0, slip_force=0.1)), 0.5, 1.2)
    steady_state(hf.Oscillator(M, C, K, hf.Cubic(0.1)), 0.5, 1.2, max_periods=2)
    assert len(kernels.newmark_periods.signatures) == 1
    assert len(kernels.record_period.signatures) == 1


# --- input validation -----------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"omega": 0.0}, "omega"),
        ({"omega": -1.0}, "omega"),
        ({"omega": np.nan}, "omega"),
        ({"omega": np.inf}, "omega"),
        ({"force": np.inf}, "force"),
        ({"force": np.nan}, "force"),
        ({"steps_per_period": 8}, "steps_per_period"),
        ({"steps_per_period": 64.0}, "steps_per_period"),
        ({"steps_per_period": 30}, "steps_per_period"),  # not > 2 H
        ({"harmonics": 0}, "harmonics"),
        ({"harmonics": True}, "harmonics"),
        ({"tol": 0.0}, "tol"),
        ({"tol": -1.0}, "tol"),
        ({"max_periods": 0}, "max_periods"),
        ({"initial_state": (np.nan, 0.0)}, "initial_state"),
        ({"initial_state": (0.0, np.inf)}, "initial_state"),
        ({"initial_state": 1.0}, "initial_state"),
        ({"initial_state": (1.0, 2.0, 3.0)}, "initial_state"),
        ({"initial_state": ([1.0, 2.0], 0.0)}, "initial_state"),
        ({"initial_state": "rest"}, "initial_state"),
        ({"check_halving": "yes"}, "check_halving"),
    ],
)
def test_bad_input(jenkins, kwargs, match):
    args = {"force": 0.5, "omega": 1.2} | kwargs
    with pytest.raises(ValueError, match=match):
        steady_state(jenkins, **args)


def test_non_numbers_are_type_errors(jenkins):
    with pytest.raises(TypeError, match="omega"):
        steady_state(jenkins, 0.5, "fast")


def test_bad_system():
    with pytest.raises(TypeError, match="system"):
        steady_state(object(), 0.5, 1.2)

    @dataclass(frozen=True)
    class Broken(Chain):
        def matrices(self):
            mass, damping, stiffness = super().matrices()
            return mass[:1, :1], damping, stiffness

    with pytest.raises(ValueError, match="system.mass"):
        steady_state(Broken(), 0.5, 1.2)
