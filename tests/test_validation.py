"""HBM against the time-integration reference, and the reference against
closed forms (linear FRF, second-order convergence, energy balance)."""

import numpy as np
import pytest

import hbmfric as hf

OMEGAS = np.linspace(0.55, 2.95, 8)


@pytest.fixture(scope="module")
def law():
    return hf.Jenkins(stiffness=3.0, slip_force=1.0)


@pytest.fixture(scope="module")
def oscillator(law):
    return hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)


@pytest.mark.parametrize("force", [0.1, 0.5, 2.0])
def test_hbm_agrees_with_time_integration(oscillator, force):
    """First harmonic within 1e-3 at 8 frequencies over [0.5, 3] (SPEC §7)."""
    errors = []
    for omega in OMEGAS:
        sol = hf.periodic_solution(oscillator, force, omega, harmonics=15)
        ref = hf.validation.steady_state(oscillator, force, omega)
        assert sol.converged and ref.converged
        a_hbm, a_ref = sol.amplitude(harmonic=1), ref.amplitude(harmonic=1)
        errors.append(abs(a_hbm / a_ref - 1))
        # the full signal too: half peak-to-peak and the third harmonic
        assert sol.amplitude() == pytest.approx(ref.amplitude(), rel=1e-3)
        assert sol.amplitude(harmonic=3) == pytest.approx(
            ref.amplitude(harmonic=3), rel=2e-2, abs=1e-4 * a_ref
        )
    assert max(errors) < 1e-3, errors


def test_branch_points_agree_with_time_integration(oscillator):
    """Points of the traced FRF (not just Newton at fixed Ω) are steady states."""
    branch = hf.frf(oscillator, force=0.5, omega=(0.5, 3.0), harmonics=15)
    peak = int(np.argmax(branch.amplitude(harmonic=1)))
    for i in sorted({1, peak, len(branch) // 2, len(branch) - 2}):
        ref = hf.validation.steady_state(oscillator, 0.5, branch.omega[i])
        assert branch.amplitude(harmonic=1)[i] == pytest.approx(
            ref.amplitude(harmonic=1), rel=1e-3
        )


@pytest.mark.parametrize(
    ("slip_force", "effective_stiffness"), [(1e9, 4.0), (0.0, 1.0)]
)
def test_reference_linear_limits(slip_force, effective_stiffness):
    osc = hf.Oscillator(
        1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=slip_force)
    )
    for omega in (0.7, 1.6, 2.4):
        ref = hf.validation.steady_state(osc, 0.5, omega, steps_per_period=4096)
        exact = 0.5 / abs(effective_stiffness - omega**2 + 0.02j * omega)
        # Newmark's phase error is (Ω h)²/12 per step: ~2e-7 at 4096 steps
        assert ref.amplitude(harmonic=1) == pytest.approx(exact, rel=2e-5)


def test_reference_converges_at_second_order():
    """Step halving on the linear oscillator near resonance: fitted order 2."""
    osc = hf.Oscillator(1.0, 0.05, 1.0)
    omega = 1.05
    exact = 0.3 / abs(1.0 - omega**2 + 0.05j * omega)
    steps = np.array([64, 128, 256, 512])
    errors = [
        abs(
            hf.validation.steady_state(
                osc, 0.3, omega, steps_per_period=int(n)
            ).amplitude(harmonic=1)
            / exact
            - 1
        )
        for n in steps
    ]
    order = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 1.8 < order < 2.2, (errors, order)


def test_energy_balance_over_a_period(oscillator):
    """Work of the excitation = viscous + friction dissipation per period
    (F = 2: the contact slips; at F = 0.5 and Ω = 1.2 it sticks)."""
    omega, force = 1.2, 2.0
    ref = hf.validation.steady_state(oscillator, force, omega, steps_per_period=8192)
    x = ref.samples[0]
    n = x.size
    h = 2 * np.pi / omega / n
    t = np.arange(n) * h
    # velocity from the Fourier series of the samples (spectral derivative)
    k = np.fft.rfftfreq(n, d=1.0 / n)
    v = np.fft.irfft(1j * k * omega * np.fft.rfft(x), n)
    w_input = np.sum(force * np.cos(omega * t) * v) * h
    w_viscous = np.sum(0.02 * v * v) * h
    f = ref.contact_force
    dx = np.diff(np.append(x, x[0]))
    w_friction = np.sum(0.5 * (f + np.append(f[1:], f[0])) * dx)
    assert w_friction > 0
    assert w_input == pytest.approx(w_viscous + w_friction, rel=1e-4)


def test_duffing_coexisting_states_match_hbm():
    """Upper and lower stable Duffing branches at one Ω inside the fold
    region, each reached by time integration from its own initial state."""
    osc = hf.Oscillator(mass=1.0, damping=0.05, stiffness=1.0, contact=hf.Cubic(0.1))
    branch = hf.frf(osc, 0.2, (0.5, 2.0), harmonics=9)
    omega = 1.25
    lo, hi = np.sort(branch.omega[branch.folds])
    assert lo < omega < hi
    # HBM: the three solutions at Ω = 1.25 from the branch (path order)
    a1 = branch.amplitude(harmonic=1)
    crossings = np.nonzero(np.diff(np.sign(branch.omega - omega)))[0]
    hbm = np.sort([a1[i] for i in crossings])
    assert hbm.size == 3
    upper = hf.validation.steady_state(osc, 0.2, omega, initial_state=(3.5, 0.0))
    lower = hf.validation.steady_state(osc, 0.2, omega, initial_state=(0.0, 0.0))
    assert upper.converged and lower.converged
    # branch points bracket Ω; compare to HBM solved exactly at Ω from them
    for ref, guess_amp in ((upper, hbm[2]), (lower, hbm[0])):
        i = crossings[np.argmin(np.abs(a1[crossings] - guess_amp))]
        sol = hf.periodic_solution(
            osc, 0.2, omega, harmonics=9, initial_guess=branch.point(i)
        )
        assert sol.converged
        assert sol.amplitude(harmonic=1) == pytest.approx(
            ref.amplitude(harmonic=1), rel=1e-4
        )
    assert upper.amplitude(harmonic=1) > 2 * lower.amplitude(harmonic=1)


def test_step_halving_estimate(oscillator):
    ref = hf.validation.steady_state(oscillator, 0.5, 1.2, check_halving=True)
    assert 0 < ref.error_estimate < 1e-4


def test_time_response_resamples_the_period(oscillator):
    ref = hf.validation.steady_state(oscillator, 0.5, 1.2, steps_per_period=1024)
    t, x = ref.time_response(n=1024)
    np.testing.assert_allclose(x, ref.samples[0], atol=1e-12 * np.abs(x).max())
    assert t[-1] < 2 * np.pi / 1.2


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"omega": 0.0}, "omega"),
        ({"omega": np.nan}, "omega"),
        ({"force": np.inf}, "force"),
        ({"steps_per_period": 8}, "steps_per_period"),
        ({"harmonics": 0}, "harmonics"),
        ({"tol": -1.0}, "tol"),
        ({"initial_state": (np.nan, 0.0)}, "initial_state"),
        ({"initial_state": 1.0}, "initial_state"),
    ],
)
def test_reference_bad_input(oscillator, kwargs, match):
    args = {"force": 0.5, "omega": 1.2} | kwargs
    with pytest.raises(ValueError, match=match):
        hf.validation.steady_state(oscillator, **args)
