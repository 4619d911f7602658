"""Modified Dahl law: increments against an independent ODE solution, the
loop energy against the closed form of SPEC §4, envelope limits, the AFT
Jacobian against central finite differences, and HBM/time-domain agreement."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import hbmfric as hf
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.aft.dahl import aft_dahl
from hbmfric.kernels.fourier.dft import fourier_matrices
from hbmfric.kernels.laws.dahl import dahl_update
from hbmfric.kernels.laws.updates import DAHL, law_update

LAW = hf.ModifiedDahl(
    beta=800.0, exponent=1.0, upper=(2.0e4, 300.0), lower=(1.2e4, 150.0)
)
LAW_15 = hf.ModifiedDahl(
    beta=60.0, exponent=1.5, upper=(2.0e4, 300.0), lower=(1.2e4, 150.0)
)


def _reference_increment(law, f0, u0, u1):
    """dF/du integrated by scipy (independent of the kernel)."""
    beta, mu, a, b, d, e = law.params
    if u1 >= u0:

        def rhs(u, f):
            x = a * u + b - f[0]
            return [beta * np.sign(x) * abs(x) ** mu]
    else:

        def rhs(u, f):
            x = f[0] - d * u - e
            return [beta * np.sign(x) * abs(x) ** mu]

    sol = solve_ivp(rhs, (u0, u1), [f0], rtol=1e-12, atol=1e-12, method="DOP853")
    return sol.y[0, -1]


@pytest.mark.parametrize("law", [LAW, LAW_15])
@pytest.mark.parametrize(
    ("f0", "u0", "u1"),
    [(200.0, 0.0, 2e-3), (250.0, 1e-3, -1e-3), (400.0, 0.0, 1e-3), (100.0, 0.0, -3e-3)],
)
def test_increment_matches_an_ode_solution(law, f0, u0, u1):
    f, *_ = law_update(DAHL, law.params, f0, u0, u1)
    ref = _reference_increment(law, f0, u0, u1)
    tol = 1e-10 if law.exponent == 1.0 else 1e-5
    assert abs(f - ref) <= tol * abs(ref)


@pytest.mark.parametrize("law", [LAW, LAW_15])
def test_increment_derivatives_against_finite_differences(law):
    p = law.params
    for f0, u0, u1 in [(220.0, 1e-4, 1.3e-3), (260.0, 2e-3, -5e-4)]:
        _, df0, du0, du1 = dahl_update(p, f0, u0, u1)
        hs = (1e-4, 1e-9, 1e-9)
        fd = []
        for k, h in enumerate(hs):
            plus = [f0, u0, u1]
            minus = [f0, u0, u1]
            plus[k] += h
            minus[k] -= h
            fd.append((dahl_update(p, *plus)[0] - dahl_update(p, *minus)[0]) / (2 * h))
        np.testing.assert_allclose([df0, du0, du1], fd, rtol=1e-5, atol=1e-6 * p[2])


@pytest.mark.parametrize("amplitude", [1e-4, 1e-3, 4e-3, 2e-2])
def test_loop_energy_matches_the_closed_form(amplitude):
    n = 8192
    theta = 2 * np.pi * np.arange(n) / n
    u = amplitude * np.cos(theta)
    f = LAW.hysteresis(u)
    du = np.roll(u, -1) - u
    area = np.sum(0.5 * (f + np.roll(f, -1)) * du)
    beta, _, a, b, d, e = LAW.params
    closed = (
        2 * (b - e - (a + d) / beta) * (amplitude - np.tanh(beta * amplitude) / beta)
    )
    assert abs(area - closed) <= 1e-6 * closed
    assert LAW.energy_per_cycle(amplitude) == pytest.approx(closed, rel=1e-14)


def test_hysteresis_is_the_periodic_state_of_a_long_march():
    n = 400
    u = 3e-3 * np.cos(2 * np.pi * np.arange(n) / n) + 1e-3 * np.sin(
        6 * np.pi * np.arange(n) / n
    )
    for law in (LAW, LAW_15):
        f = law.hysteresis(u)
        g = 0.0
        for _ in range(60):
            for j in range(n):
                g = law_update(DAHL, law.params, g, u[j], u[(j + 1) % n])[0]
        # g is the force at sample 0 after 60 periods from F = 0
        assert abs(g - f[0]) <= 1e-9 * abs(f[0])


@pytest.mark.parametrize(("law", "gap"), [(LAW, None), (LAW_15, None)])
def test_large_loops_follow_the_shifted_envelopes(law, gap):
    beta, mu, a, b, d, e = law.params
    n = 4000
    x = 0.1  # βX >> 1
    u = x * np.cos(2 * np.pi * np.arange(n) / n)
    f = law.hysteresis(u)
    # the branch tends to h - σ⁻¹(slope/β): dF/du = slope on the asymptote
    shift_u = (a / beta) ** (1 / mu)
    shift_l = (d / beta) ** (1 / mu)
    loading = (np.roll(u, -1) > u) & (u > 0.5 * x)
    unloading = (np.roll(u, -1) < u) & (u < -0.5 * x)
    np.testing.assert_allclose(f[loading], a * u[loading] + b - shift_u, atol=1e-6 * b)
    np.testing.assert_allclose(
        f[unloading], d * u[unloading] + e + shift_l, atol=1e-6 * b
    )


@pytest.mark.parametrize("law", [LAW, LAW_15])
def test_aft_jacobian_against_finite_differences(law):
    harmonics = np.arange(0, 6, dtype=np.int64)
    inverse, forward, derivative = fourier_matrices(harmonics, 64)

    def aft(X, F, dF):
        return aft_dahl(law.params, harmonics, X, inverse, forward, derivative, F, dF)

    rng = np.random.default_rng(3)
    X = np.zeros(11)
    X[0] = 2e-3
    X[1:] = 1e-3 * rng.standard_normal(10) / np.repeat(np.arange(1, 6), 2)
    F = np.empty(11)
    dF = np.empty((11, 11))
    aft(X, F, dF)
    # reversals between samples: the located ones are nodes of the march
    du = derivative @ X
    assert np.any(du * np.roll(du, -1) < 0.0)
    fd = np.empty_like(dF)
    h = 1e-9
    Fp = np.empty(11)
    Fm = np.empty(11)
    for c in range(11):
        Xp = X.copy()
        Xm = X.copy()
        Xp[c] += h
        Xm[c] -= h
        aft(Xp, Fp, np.empty((11, 11)))
        aft(Xm, Fm, np.empty((11, 11)))
        fd[:, c] = (Fp - Fm) / (2 * h)
    np.testing.assert_allclose(dF, fd, rtol=1e-5, atol=1e-5 * np.abs(fd).max())


def _rotate(harmonics, coefficients, phi):
    """Coefficients of ``x(θ − φ)`` from those of ``x(θ)``."""
    out = coefficients.copy()
    col = 0
    for k in harmonics:
        if k == 0:
            col += 1
            continue
        c, s = coefficients[col], coefficients[col + 1]
        out[col] = c * np.cos(k * phi) - s * np.sin(k * phi)
        out[col + 1] = c * np.sin(k * phi) + s * np.cos(k * phi)
        col += 2
    return out


@pytest.mark.parametrize("law", [LAW, LAW_15])
def test_aft_is_exact_with_reversals_between_samples(law):
    """The force of ``u(θ − φ)`` is that of ``u(θ)`` shifted by φ. Reference:
    ``u`` with its reversals at θ = 0 and π, on the samples of a fine grid
    (the force is then exact at every sample; the DFT error of its jumping
    second derivative is O(h^4)). Shifted by a fraction of a coarse step,
    the reversals fall between samples: the force samples of the located
    AFT stay exact and only the DFT of the kink in F'' errs, O(h^3)
    (2e-5 at 64 samples); the plain sampled march (the former AFT, which
    turned at the samples) errs O(h^2), 1e-3 at 64 samples."""
    harmonics = np.arange(0, 8, dtype=np.int64)
    X = np.zeros(15)
    X[0], X[1], X[5] = 2e-3, 3e-3, 3e-4  # u' = 0 only at θ = 0, π

    def aft(X, n_time):
        inverse, forward, derivative = fourier_matrices(harmonics, n_time)
        F = np.empty(15)
        aft_dahl(
            law.params,
            harmonics,
            X,
            inverse,
            forward,
            derivative,
            F,
            np.empty((15, 15)),
        )
        return F, inverse, forward

    reference, _, _ = aft(X, 4096)
    errors = []
    for n_time in (64, 128):
        phi = 0.37 * 2.0 * np.pi / n_time
        shifted = _rotate(harmonics, X, phi)
        F, inverse, forward = aft(shifted, n_time)
        expected = _rotate(harmonics, reference, phi)
        scale = np.abs(expected[1:]).max()
        errors.append(np.abs(F - expected).max() / scale)
        if n_time == 64:
            sampled = forward @ law.hysteresis(inverse @ shifted)
            assert np.abs(sampled - expected)[1:].max() > 5e-4 * scale
    assert errors[0] < 3e-5
    assert errors[1] < errors[0] / 6.0  # third order


def test_constant_displacement_holds_the_mid_envelope():
    f = LAW.hysteresis(np.full(16, 2e-3))
    np.testing.assert_allclose(f, LAW.static_force(2e-3))
    assert LAW.static_displacement(LAW.static_force(2e-3)) == pytest.approx(2e-3)


def test_small_loops_have_the_small_loop_stiffness():
    x = 1e-7
    n = 256
    theta = 2 * np.pi * np.arange(n) / n
    f = LAW.hysteresis(1e-3 + x * np.cos(theta))
    c1 = 2 * np.mean(f * np.cos(theta))
    assert c1 / x == pytest.approx(LAW.small_loop_stiffness(1e-3), rel=1e-3)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"beta": 0.0}, "beta"),
        ({"beta": 1.0, "exponent": 0.5}, "exponent"),
        ({"beta": 1.0, "upper": (1.0, 0.0), "lower": (1.0, 1.0)}, "offset"),
        ({"beta": 1.0, "upper": 3.0}, "upper"),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        hf.ModifiedDahl(**kwargs)


def test_hbm_matches_time_integration_on_an_oscillator():
    """A Dahl oscillator with a static load: HBM against the Newmark reference
    (both see the law only through its kernel)."""

    class Loaded(hf.Oscillator):
        def static_load(self):
            return np.array([225.0])

    osc = Loaded(mass=1.0, damping=4.0, stiffness=1.0e4, contact=LAW)
    omega = 150.0
    sol = hf.periodic_solution(osc, force=40.0, omega=omega, harmonics=9)
    assert sol.converged
    ref = hf.validation.steady_state(
        osc, 40.0, omega, harmonics=9, steps_per_period=1024, tol=1e-9
    )
    assert ref.converged
    for k in (0, 1, 2, 3):
        assert sol.amplitude(harmonic=k) == pytest.approx(
            ref.amplitude(harmonic=k), rel=2e-3, abs=1e-4 * sol.amplitude(harmonic=1)
        )


def test_problem_puts_static_and_sine_loads_on_their_harmonics():
    class Rig(hf.Oscillator):
        load_phase = np.pi / 2

        def static_load(self):
            return np.array([5.0])

    p = HBMProblem(Rig(1.0, 0.1, 1.0, LAW), force=2.0, harmonics=3)
    assert not p.odd
    np.testing.assert_allclose(p.load[:3], [5.0, 0.0, 2.0], atol=1e-15)
    p3 = HBMProblem(Rig(1.0, 0.1, 1.0, LAW), force=2.0, harmonics=6, subharmonic=3)
    np.testing.assert_allclose(p3.load[5:7], [0.0, 2.0], atol=1e-15)
    np.testing.assert_allclose(p3.load[1:5], 0.0, atol=0.0)
    assert p3.load[0] == 5.0
    with pytest.raises(ValueError, match="subharmonic"):
        HBMProblem(Rig(1.0, 0.1, 1.0, LAW), force=2.0, harmonics=2, subharmonic=3)
