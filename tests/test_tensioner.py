"""The belt-tensioner rig: statics against the equations of motion, the JIT
integrator against scipy's BDF, HBM against time integration, and the
regimes of the paper's Fig. 5 (stuck, slipping, bounded tension, softening,
the resonance at one third of the stuck one)."""

import math

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.signals import synthesis_matrix
from hbmfric.systems.tensioner import tension_coefficients
from hbmfric.systems.tensioner_response import hbm_frf, time_domain_frf

RIG = hf.BeltTensioner()


def test_static_solution_balances_the_equations_of_motion():
    x = RIG.static_solution()
    T = RIG.tension(x, np.zeros(2))
    F = float(RIG.tensioner.hysteresis(np.full(4, x[1]))[0])
    g = RIG.gravity
    # m2 ü2 = T − F + m2 g = 0, m1 ü1 = −T + f0 + m1 g = 0
    assert T - F + RIG.mass_pulley * g == pytest.approx(0.0, abs=1e-9)
    assert -T + RIG.static_force + RIG.mass_shaker * g == pytest.approx(0.0, abs=1e-9)


def test_matrices_and_loads_reproduce_the_paper_equations():
    M, C, K = RIG.matrices()
    rng = np.random.default_rng(0)
    x, v, a = rng.standard_normal((3, 2)) * 1e-3
    F, t, om, f1 = 210.0, 0.013, 90.0, 7.0
    T = RIG.tension(x, v)
    forcing = RIG.static_load() + RIG.load_vector(f1) * math.cos(
        om * t - RIG.load_phase
    )
    lhs = M @ a + C @ v + K @ x + np.array([0.0, F])
    g = RIG.gravity
    rhs_paper = np.array(
        [
            -T + RIG.static_force + f1 * math.sin(om * t) + RIG.mass_shaker * g,
            T - F + RIG.mass_pulley * g,
        ]
    )
    # M a = paper right-hand side  <=>  lhs = forcing
    np.testing.assert_allclose(lhs - forcing, M @ a - rhs_paper, atol=1e-9)


def test_default_parameters_put_the_regimes_in_the_band():
    stuck = RIG.resonances()[0]
    slip = RIG.resonances(RIG.tensioner.upper[0])[0]
    assert 5.0 < slip < stuck < 100.0 and 5.0 < stuck / 3.0
    with pytest.raises(ValueError, match="tensioner"):
        hf.BeltTensioner(tensioner=hf.Jenkins(1.0, 1.0))
    with pytest.raises(ValueError, match="mass_shaker"):
        hf.BeltTensioner(mass_shaker=-1.0)


def test_tension_coefficients_match_the_sampled_tension():
    h = np.arange(0, 4)
    rng = np.random.default_rng(1)
    X = rng.standard_normal((2, 7)) * 1e-4
    om = 120.0
    theta = 2 * np.pi * np.arange(64) / 64
    basis = synthesis_matrix(h, theta)
    x = X @ basis.T
    dbasis = np.zeros_like(basis)
    col = 1
    for k in h[1:]:
        dbasis[:, col] = -k * om * np.sin(k * theta)
        dbasis[:, col + 1] = k * om * np.cos(k * theta)
        col += 2
    v = X @ dbasis.T
    T = tension_coefficients(RIG, h, X, om) @ basis.T
    np.testing.assert_allclose(T, RIG.tension(x, v), rtol=1e-12, atol=1e-9)


def test_jit_integrator_agrees_with_scipy_bdf():
    freqs = [38.0]
    jit = time_domain_frf(RIG, 40.0, freqs, "jit")
    bdf = time_domain_frf(RIG, 40.0, freqs, "bdf")
    assert jit.converged.all() and bdf.converged.all()
    np.testing.assert_allclose(jit.tension_range, bdf.tension_range, rtol=2e-3)


@pytest.mark.parametrize("force", [2.0, 40.0])
def test_hbm_agrees_with_time_integration(force):
    hbm = hbm_frf(RIG, force, (8.0, 60.0), harmonics=15)
    assert hbm.info["stop_reason"] == "end of frequency range reached"
    pick = np.linspace(0, hbm.frequency.size - 1, 6).astype(int)
    td = time_domain_frf(RIG, force, hbm.frequency[pick], "jit", steps_per_period=1024)
    assert td.converged.all()
    np.testing.assert_allclose(hbm.tension_range[pick], td.tension_range, rtol=3e-3)


def test_regimes_of_the_paper():
    freqs = (5.0, 100.0)
    low = [hbm_frf(RIG, f, freqs, harmonics=9) for f in (0.1, 0.2)]
    high = [hbm_frf(RIG, f, freqs, harmonics=9) for f in (20.0, 80.0)]
    stuck = RIG.resonances()[0]
    # stuck: peak at the small-loop resonance, response linear in force
    peak_low = low[1].frequency[np.argmax(low[1].tension_range)]
    assert peak_low == pytest.approx(stuck, rel=0.03)
    grid = np.linspace(20.0, 80.0, 31)
    # (not at the peak itself: there the loop dissipation, which grows like
    # the cube of the stroke, sets the height, so it is never linear)
    grid = grid[np.abs(grid - stuck) > 3.0]
    ratio = low[1].at(grid) / low[0].at(grid)
    np.testing.assert_allclose(ratio, 2.0, rtol=0.02)
    # slip and softening: the peak moves down as the forcing grows
    peaks = [b.frequency[np.argmax(b.tension_range)] for b in high]
    assert peaks[1] < peaks[0] < 0.95 * stuck
    # bounded tension: at the stuck resonance, 400x the force gives far less
    # than 400x the tension variation
    at_stuck = [b.at(stuck) for b in (low[1], high[1])]
    assert at_stuck[1] / at_stuck[0] < 0.1 * 400.0
    # the resonance at one third of the stuck one (its third harmonic drives
    # the stuck mode): a local maximum there once the loops are large enough
    curve = high[0]
    band = (curve.frequency > 0.27 * stuck) & (curve.frequency < 0.40 * stuck)
    f_band, t_band = curve.frequency[band], curve.tension_range[band]
    i = int(np.argmax(t_band - np.interp(f_band, f_band[[0, -1]], t_band[[0, -1]])))
    assert f_band[i] == pytest.approx(stuck / 3.0, rel=0.04)
    assert 0 < i < f_band.size - 1


def test_subharmonic_balance_captures_the_one_third_resonance():
    """HBM on the fundamental Ω/3 (forcing on its harmonic 3) around the
    resonance at one third of the stuck one, against time integration. The
    time integration settles to period T there (no 3T response is found),
    so the harmonics of Ω/3 that are not multiples of 3 must vanish."""
    sub = hbm_frf(RIG, 20.0, (12.0, 16.0), harmonics=45, subharmonic=3)
    assert sub.method == "hbm/3"
    assert sub.info["stop_reason"] == "end of frequency range reached"
    h = sub.info["harmonic_numbers"]
    X = sub.info["coefficients"]
    cols = np.concatenate([[2 * k - 1, 2 * k] for k in h[1:] if k % 3 != 0])
    assert np.max(np.abs(X[:, :, cols])) < 1e-9 * np.max(np.abs(X[:, :, 1:]))
    pick = np.linspace(0, sub.frequency.size - 1, 4).astype(int)
    td = time_domain_frf(RIG, 20.0, sub.frequency[pick], "jit", steps_per_period=1024)
    assert td.converged.all()
    np.testing.assert_allclose(sub.tension_range[pick], td.tension_range, rtol=3e-3)
    peak = sub.frequency[np.argmax(sub.tension_range)]
    assert peak == pytest.approx(RIG.resonances()[0] / 3.0, rel=0.04)


@pytest.mark.slow
def test_paper_figures_3_and_5(tmp_path):
    from hbmfric.paper import tensioner_frf, tensioner_loop

    loop = tensioner_loop()
    p = loop.true_law.params
    r = loop.identification
    np.testing.assert_allclose([*r.upper, *r.lower], p[2:], rtol=0.02)
    assert r.beta == pytest.approx(p[0], rel=0.05)
    fig = tensioner_frf(r.law, forces=(5.0,), n_time_domain=5)
    (hbm,), (td,) = fig.hbm, fig.time_domain
    pick = [int(np.argmin(np.abs(hbm.frequency - f))) for f in td.frequency]
    np.testing.assert_allclose(hbm.tension_range[pick], td.tension_range, rtol=3e-3)
    for f in (loop, fig):
        assert f.write_csv(tmp_path / f"{f.name}.csv").stat().st_size > 1000
        assert f.write_png(tmp_path / f"{f.name}.png").stat().st_size > 10_000
