"""Kernels against closed forms, a plain-NumPy reference and finite
differences: DFT operators, Jenkins and cubic AFT, the HBM residual.

Measured convergence of the Jenkins first harmonic under u = 0.9 cos θ
(kt = 3, f_s = 1) against the closed form, relative error:

    n_time   sampled AFT   event-located AFT
    64       3.6e-04       2.7e-16
    128      9.6e-05       1.8e-16
    256      2.0e-05       2.7e-16
    512      6.9e-06       2.0e-16
    1024     6.5e-07       2.7e-16

The sampled march converges at order 2 in n_time (the Fourier integrals of
a force with kinks between samples); locating the stick/slip events inside
the sample intervals and integrating segment by segment is exact.
"""

import numpy as np
import pytest
from naive_aft import analyse, jenkins_first_harmonic, jenkins_march, synthesize

import hbmfric as hf
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.aft import (
    GROSS_SLIP,
    STUCK,
    aft_jenkins_events,
    aft_samples,
)
from hbmfric.kernels.dft import fourier_matrices

ALL = np.arange(0, 8, dtype=np.int64)
ODD = np.arange(1, 16, 2, dtype=np.int64)
KT, FS = 3.0, 1.0
PARAMS = np.array([KT, FS])


def _coef(harmonics, **terms):
    """Coefficient vector from keywords like c1=0.9, s3=0.1, m=0.2."""
    X = np.zeros(sum(1 if k == 0 else 2 for k in harmonics))
    col = {}
    c = 0
    for k in harmonics:
        col[int(k)] = c
        c += 1 if k == 0 else 2
    for name, value in terms.items():
        if name == "m":
            X[col[0]] = value
        else:
            X[col[int(name[1:])] + (name[0] == "s")] = value
    return X


def _events(harmonics, X, n_time=64):
    inv, _, der = fourier_matrices(harmonics, n_time)
    F = np.empty(X.size)
    dF = np.empty((X.size, X.size))
    state = aft_jenkins_events(PARAMS, harmonics, X, inv, der, F, dF)
    return F, dF, state


def _samples(harmonics, X, n_time=64, code=0, params=PARAMS):
    inv, fwd, _ = fourier_matrices(harmonics, n_time)
    F = np.empty(X.size)
    dF = np.empty((X.size, X.size))
    state = aft_samples(code, params, X, inv, fwd, F, dF)
    return F, dF, state


@pytest.mark.parametrize("harmonics", [ALL, ODD])
def test_dft_matrices_match_explicit_sums(harmonics):
    inv, fwd, der = fourier_matrices(harmonics, 48)
    rng = np.random.default_rng(0)
    X = rng.normal(size=inv.shape[1])
    theta = 2 * np.pi * np.arange(48) / 48
    np.testing.assert_allclose(inv @ X, synthesize(harmonics, X, theta), atol=1e-13)
    np.testing.assert_allclose(fwd @ (inv @ X), X, atol=1e-13)
    np.testing.assert_allclose(
        fwd @ np.sin(theta) ** 3, analyse(harmonics, np.sin(theta) ** 3), atol=1e-14
    )
    h = 1e-6
    fd = (synthesize(harmonics, X, theta + h) - synthesize(harmonics, X, theta - h)) / (
        2 * h
    )
    np.testing.assert_allclose(der @ X, fd, atol=1e-7)


def test_naive_describing_function_matches_spec_formula():
    """Two independent closed forms (SPEC §4 and the loop integral)."""
    law = hf.Jenkins(stiffness=KT, slip_force=FS)
    for a in (0.2, 0.34, 0.5, 0.9, 3.0, 50.0):
        np.testing.assert_allclose(
            law.first_harmonic(a),
            jenkins_first_harmonic(KT, FS, a),
            rtol=1e-13,
            atol=1e-15,
        )


@pytest.mark.parametrize("harmonics", [ALL, ODD])
@pytest.mark.parametrize("amplitude", [FS / KT * 1.001, 0.5, 0.9, 5.0, 100.0])
@pytest.mark.parametrize("n_time", [32, 64])
def test_event_aft_is_exact_under_harmonic_motion(harmonics, amplitude, n_time):
    X = _coef(harmonics, c1=amplitude)
    F, _, state = _events(harmonics, X, n_time)
    c1, s1 = jenkins_first_harmonic(KT, FS, amplitude)
    assert state == GROSS_SLIP
    col = 1 if harmonics[0] == 0 else 0
    assert F[col] == pytest.approx(c1, rel=1e-12)
    assert F[col + 1] == pytest.approx(s1, rel=1e-12, abs=1e-14 * abs(c1))


def test_sampled_aft_converges_at_order_two_and_events_are_exact():
    X = _coef(ODD, c1=0.9)
    c1, s1 = jenkins_first_harmonic(KT, FS, 0.9)
    exact = np.hypot(c1, s1)
    sizes = np.array([64, 128, 256, 512, 1024])
    err_samples, err_events = [], []
    for n in sizes:
        F, _, _ = _samples(ODD, X, n)
        err_samples.append(np.hypot(F[0] - c1, F[1] - s1) / exact)
        F, _, _ = _events(ODD, X, n)
        err_events.append(np.hypot(F[0] - c1, F[1] - s1) / exact)
    order = -np.polyfit(np.log(sizes), np.log(err_samples), 1)[0]
    assert 1.5 < order < 2.5, (err_samples, order)
    assert err_samples[-1] < 1e-6
    assert max(err_events) < 1e-14


def test_inner_loops_match_the_naive_march():
    """Two-harmonic motion with a mean: inner loops (Madelung memory)."""
    X = _coef(ALL, m=0.1, c1=1.0, c3=0.4, s2=0.2)
    n = 4096
    theta = 2 * np.pi * np.arange(n) / n
    u = synthesize(ALL, X, theta)
    naive = analyse(ALL, jenkins_march(u, KT, FS))
    F, _, state = _events(ALL, X, 64)
    assert state == GROSS_SLIP
    # the naive sampled reference carries an O(n^-2) error
    np.testing.assert_allclose(F, naive, atol=2e-6)
    Fs, _, _ = _samples(ALL, X, n)
    np.testing.assert_allclose(Fs, naive, atol=1e-12)


def test_stuck_contact_is_linear_and_slider_shifts_when_forced():
    X = _coef(ALL, c1=0.2)
    F, dF, state = _events(ALL, X)
    assert state == STUCK
    np.testing.assert_allclose(F, KT * X, atol=1e-15)
    np.testing.assert_allclose(dF, KT * np.eye(X.size), atol=1e-15)
    # mean 0.3 + 0.2 cos θ: kt max u = 1.5 > f_s, range 0.4 < 2 f_s/kt
    X = _coef(ALL, m=0.3, c1=0.2)
    F, _, state = _events(ALL, X)
    assert state == STUCK
    n = 512
    u = synthesize(ALL, X, 2 * np.pi * np.arange(n) / n)
    np.testing.assert_allclose(F, analyse(ALL, jenkins_march(u, KT, FS)), atol=1e-12)
    Fs, _, _ = _samples(ALL, X, n)
    np.testing.assert_allclose(Fs, F, atol=1e-12)


def _fd_jacobian(fun, X, eps=1e-7):
    J = np.empty((X.size, X.size))
    for c in range(X.size):
        d = np.zeros_like(X)
        d[c] = eps
        J[:, c] = (fun(X + d) - fun(X - d)) / (2 * eps)
    return J


@pytest.mark.parametrize(
    "terms",
    [{"c1": 0.2}, {"c1": 0.9, "s1": 0.3}, {"m": 0.1, "c1": 1.0, "c3": 0.4, "s2": 0.2}],
)
@pytest.mark.parametrize("scheme", ["events", "samples"])
def test_jenkins_jacobian_matches_finite_differences(terms, scheme):
    X = _coef(ALL, **terms)
    fun = (
        (lambda Y: _events(ALL, Y)[0])
        if scheme == "events"
        else (lambda Y: _samples(ALL, Y, 256)[0])
    )
    J = _events(ALL, X)[1] if scheme == "events" else _samples(ALL, X, 256)[1]
    np.testing.assert_allclose(J, _fd_jacobian(fun, X), atol=2e-6)


def test_cubic_aft_exact_and_jacobian():
    X = _coef(ODD, c1=0.7)
    F, dF, _ = _samples(ODD, X, 64, code=1, params=np.array([0.1]))
    # k3 a³ (3/4 cos θ + 1/4 cos 3θ)
    expected = _coef(ODD, c1=0.1 * 0.7**3 * 0.75, c3=0.1 * 0.7**3 * 0.25)
    np.testing.assert_allclose(F, expected, atol=1e-15)
    rng = np.random.default_rng(3)
    X = rng.normal(size=X.size) * 0.3
    fun = lambda Y: _samples(ODD, Y, 64, code=1, params=np.array([0.1]))[0]  # noqa: E731
    np.testing.assert_allclose(
        _samples(ODD, X, 64, code=1, params=np.array([0.1]))[1],
        _fd_jacobian(fun, X),
        atol=1e-8,
    )


def test_hysteresis_matches_the_naive_loop():
    law = hf.Jenkins(stiffness=KT, slip_force=FS)
    n = 1000
    theta = 2 * np.pi * np.arange(n) / n
    u = 0.8 * np.cos(theta) + 0.3 * np.sin(3 * theta)
    f = law.hysteresis(u)
    np.testing.assert_allclose(f, jenkins_march(u, KT, FS), atol=1e-13)
    assert np.max(np.abs(f)) <= FS
    a = 0.8
    u = a * np.cos(theta)
    f = law.hysteresis(u)
    du = np.diff(np.append(u, u[0]))
    energy = -np.sum(0.5 * (f + np.roll(f, -1)) * du)
    assert abs(energy) == pytest.approx(law.energy_per_cycle(a), rel=1e-4)
    with pytest.raises(ValueError, match="u"):
        law.hysteresis([1.0, np.nan, 0.0])


def test_hbm_residual_matches_naive_and_finite_differences():
    osc = hf.Oscillator(1.3, 0.07, 2.0, hf.Jenkins(stiffness=KT, slip_force=FS))
    problem = HBMProblem(osc, 0.4, harmonics=7, symmetry=False)
    rng = np.random.default_rng(5)
    for omega in (0.7, 1.9):
        X = _coef(ALL, m=0.05, c1=0.8, s1=-0.3) + rng.normal(size=15) * 0.02
        y = np.append(X, omega)
        R, J, _ = problem.residual(y)
        n = 8192
        u = synthesize(ALL, X, 2 * np.pi * np.arange(n) / n)
        Fnl = analyse(ALL, jenkins_march(u, KT, FS))
        expected = np.empty(15)
        expected[0] = 2.0 * X[0]
        for k in range(1, 8):
            c, s = 2 * k - 1, 2 * k
            d = 2.0 - 1.3 * (k * omega) ** 2
            expected[c] = d * X[c] + 0.07 * k * omega * X[s]
            expected[s] = d * X[s] - 0.07 * k * omega * X[c]
        expected[1] -= 0.4
        np.testing.assert_allclose(R, expected + Fnl, atol=1e-6)
        fd = np.empty_like(J)
        for c in range(16):
            d = np.zeros(16)
            d[c] = 1e-7
            fd[:, c] = (problem.residual(y + d)[0] - problem.residual(y - d)[0]) / 2e-7
        np.testing.assert_allclose(J, fd, atol=1e-6)
