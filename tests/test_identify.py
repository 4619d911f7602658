"""Identification of the modified Dahl law from noisy synthesised loops.

The loops are generated here by plain NumPy (the exact exponential branches
for μ = 1, a fine Runge–Kutta march for μ ≠ 1), independently of the kernel
that the identification simulates with."""

import numpy as np
import pytest

import hbmfric as hf

TRUE = {"beta": 900.0, "a": 2.0e4, "b": 300.0, "d": 1.2e4, "e": 150.0}


def _exact_loop(u, beta, a, b, d, e):
    f = np.empty_like(u)
    f[0] = 0.5 * ((a + d) * u[0] + b + e)
    for i in range(1, u.size):
        du = u[i] - u[i - 1]
        if du > 0:
            g = f[i - 1] - a * u[i - 1] - b + a / beta
            f[i] = a * u[i] + b - a / beta + g * np.exp(-beta * du)
        else:
            g = f[i - 1] - d * u[i - 1] - e - d / beta
            f[i] = d * u[i] + e + d / beta + g * np.exp(beta * du)
    return f


def _rk4_loop(u, beta, mu, a, b, d, e, substeps=8):
    def rate(uu, f, up):
        x = (a * uu + b - f) if up else (f - d * uu - e)
        return beta * np.sign(x) * abs(x) ** mu

    f = np.empty_like(u)
    f[0] = 0.5 * ((a + d) * u[0] + b + e)
    for i in range(1, u.size):
        up = u[i] > u[i - 1]
        h = (u[i] - u[i - 1]) / substeps
        y = f[i - 1]
        x = u[i - 1]
        for _ in range(substeps):
            k1 = rate(x, y, up)
            k2 = rate(x + h / 2, y + h / 2 * k1, up)
            k3 = rate(x + h / 2, y + h / 2 * k2, up)
            k4 = rate(x + h, y + h * k3, up)
            y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            x += h
        f[i] = y
    return f


def _record(cycles, n_per=1000, mean=2e-3, amplitude=4e-3):
    t = np.arange(int(cycles * n_per)) / n_per
    return mean + amplitude * np.cos(2 * np.pi * t + 0.7)


def _noisy(u, f, force_noise, u_noise, seed):
    rng = np.random.default_rng(seed)
    return (
        u + u_noise * np.ptp(u) * rng.standard_normal(u.size),
        f + force_noise * np.ptp(f) * rng.standard_normal(u.size),
    )


@pytest.mark.parametrize(
    ("force_noise", "u_noise", "cycles", "seed"),
    [(0.02, 0.01, 6.3, 0), (0.02, 0.01, 6.3, 1), (0.01, 0.01, 3.4, 2)],
)
def test_recovers_the_parameters_from_a_noisy_loop(force_noise, u_noise, cycles, seed):
    u = _record(cycles)
    f = _exact_loop(u, **TRUE)
    r = hf.identify.modified_dahl(*_noisy(u, f, force_noise, u_noise, seed))
    np.testing.assert_allclose(r.upper, (TRUE["a"], TRUE["b"]), rtol=0.02)
    np.testing.assert_allclose(r.lower, (TRUE["d"], TRUE["e"]), rtol=0.02)
    assert r.beta == pytest.approx(TRUE["beta"], rel=0.05)
    assert r.exponent == 1.0
    assert r.n_cycles == pytest.approx(cycles, rel=0.02)
    # the residual is the noise, not a misfit
    assert r.residual_rms < 1.3 * force_noise * np.ptp(f)
    # the straight-line start is off by the asymptote shift; the fit fixes it
    assert isinstance(r.law, hf.ModifiedDahl)
    np.testing.assert_allclose(r.law.params, [r.beta, 1.0, *r.upper, *r.lower])


def test_fits_the_exponent_when_asked():
    law = {"beta": 60.0, "mu": 1.5, "a": 2.0e4, "b": 300.0, "d": 1.2e4, "e": 150.0}
    u = _record(5.3)
    f = _rk4_loop(u, **law)
    r = hf.identify.modified_dahl(*_noisy(u, f, 0.01, 0.005, 4), exponent=None)
    assert r.exponent == pytest.approx(1.5, rel=0.05)
    np.testing.assert_allclose(r.upper, (law["a"], law["b"]), rtol=0.02)
    np.testing.assert_allclose(r.lower, (law["d"], law["e"]), rtol=0.02)


def test_a_loop_too_short_is_refused():
    u = _record(0.7)
    with pytest.raises(ValueError, match="too short"):
        hf.identify.modified_dahl(u, _exact_loop(u, **TRUE))
    with pytest.raises(ValueError, match="too short"):
        hf.identify.modified_dahl(u[:50], _exact_loop(u[:50], **TRUE))


def test_a_loop_too_noisy_is_refused():
    u = _record(3.4)
    f = _exact_loop(u, **TRUE)
    with pytest.raises(ValueError, match="too noisy"):
        hf.identify.modified_dahl(*_noisy(u, f, 0.3, 0.01, 0))


def test_bad_input():
    with pytest.raises(ValueError, match="same shape"):
        hf.identify.modified_dahl(np.zeros(100), np.zeros(99))
    with pytest.raises(ValueError, match="force"):
        hf.identify.modified_dahl(np.zeros(100), np.full(100, np.nan))


def test_csv_helper_and_plot(tmp_path):
    u = _record(3.4)
    u_n, f_n = _noisy(u, _exact_loop(u, **TRUE), 0.01, 0.01, 5)
    path = tmp_path / "loop.csv"
    np.savetxt(
        path, np.column_stack((u_n, f_n)), delimiter=",", header="u_m,F_N", comments=""
    )
    r = hf.identify.modified_dahl_csv(path, u_column="u_m", force_column="F_N")
    r2 = hf.identify.modified_dahl(u_n, f_n)
    np.testing.assert_allclose(r.law.params, r2.law.params, rtol=1e-9)
    ax = r.plot(path=tmp_path / "loop.png")
    assert (tmp_path / "loop.png").stat().st_size > 0
    assert len(ax.lines) == 4
