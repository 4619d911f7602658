"""The exact event-driven Jenkins reference (:mod:`hbmfric.validation.exact`)
against closed forms (stuck and free linear limits, the exponential
propagator), invariants (energy balance per cycle, finite-difference
monodromy), the HBM engine at high H (with its convergence in H) and time
integration (with its convergence in the step)."""

import math

import numpy as np
import pytest
import scipy.linalg

import hbmfric as hf
from hbmfric.errors import ConvergenceError
from hbmfric.validation import (
    branch_errors,
    exact_branch,
    exact_periodic_solution,
    steady_state,
)
from hbmfric.validation.exact import _Model, _simulate

# SDOF scene: free resonance 100 rad/s, stuck resonance 200 rad/s, ζ = 2 %
M, C, K, KT = 1.0, 4.0, 1.0e4, 3.0e4
F = 1.0


def oscillator(slip_force: float) -> hf.Oscillator:
    return hf.Oscillator(M, C, K, hf.Jenkins(stiffness=KT, slip_force=slip_force))


def receptance(stiffness: float, omega: float) -> complex:
    return F / (stiffness - M * omega**2 + 1j * C * omega)


def stick_slip_point():
    """Ω = 150 rad/s with the slip force at half the stuck response's peak
    contact force: four events per period."""
    w = 150.0
    fs = 0.5 * KT * abs(receptance(K + KT, w))
    return oscillator(fs), w


@pytest.fixture(scope="module")
def sdof_solution():
    osc, w = stick_slip_point()
    return osc, w, exact_periodic_solution(osc, F, w, on_failure="raise")


@pytest.fixture(scope="module")
def beam_solution():
    from hbmfric.paper.beam import HZ, paper_beam

    beam = paper_beam(0.5)
    w = 26.0 * HZ
    return beam, w, exact_periodic_solution(beam, 2.0, w, on_failure="raise")


# ----------------------------------------------------------------------------
# closed forms
# ----------------------------------------------------------------------------
def test_always_stuck_is_the_linear_response_with_k_plus_kt():
    w = 150.0
    X = receptance(K + KT, w)
    sol = exact_periodic_solution(oscillator(1.01 * KT * abs(X)), F, w)
    assert sol.kind == "stuck"
    assert sol.amplitude(harmonic=1) == pytest.approx(abs(X), rel=1e-13)
    assert sol.amplitude() == pytest.approx(abs(X), rel=1e-12)


def test_zero_slip_force_is_the_linear_response_with_k():
    w = 90.0
    sol = exact_periodic_solution(oscillator(0.0), F, w)
    assert sol.kind == "free"
    assert sol.amplitude(harmonic=1) == pytest.approx(abs(receptance(K, w)), rel=1e-13)


@pytest.mark.parametrize("eps", [1e-4, 1e-6])
def test_barely_slipping_tends_to_the_stuck_response(eps):
    """Just below the stuck limit the shooting runs (events every period)
    and its answer tends to the stuck closed form."""
    w = 150.0
    X = receptance(K + KT, w)
    sol = exact_periodic_solution(
        oscillator((1.0 - eps) * KT * abs(X)), F, w, on_failure="raise"
    )
    assert sol.kind == "stick-slip" and sol.events == 4
    assert sol.amplitude(harmonic=1) == pytest.approx(abs(X), rel=50 * eps)


@pytest.mark.parametrize("ratio", [1e-3, 1e-4])
def test_tiny_slip_force_tends_to_the_free_response(ratio):
    """Slip force ``r`` times the stuck-spring force of the free response:
    the stick phases last ``~ sqrt(r)`` of the period near the reversals,
    so the amplitude tends to the free closed form like ``sqrt(r)``."""
    w = 150.0
    X = receptance(K, w)
    sol = exact_periodic_solution(
        oscillator(ratio * KT * abs(X)), F, w, on_failure="raise"
    )
    assert sol.kind == "stick-slip"
    err = abs(sol.amplitude(harmonic=1) / abs(X) - 1.0)
    assert err < 0.1 * math.sqrt(ratio)


@pytest.mark.parametrize("which", ["sdof", "beam"])
def test_propagator_is_the_matrix_exponential(which, sdof_solution, beam_solution):
    system, w = (sdof_solution if which == "sdof" else beam_solution)[:2]
    force = F if which == "sdof" else 2.0
    model = _Model(system, force, w)
    for phase in model.phases:
        for tau in (1e-4, 0.3 * model.period, model.period):
            E = scipy.linalg.expm(phase.A * tau)
            err = np.max(np.abs(phase.transition(tau) - E))
            assert err < 1e-11 * max(1.0, np.max(np.abs(E)))


# ----------------------------------------------------------------------------
# invariants
# ----------------------------------------------------------------------------
def _energy_terms(system, force, sol, n_gauss=30):
    """Input, viscous and friction work over one period by Gauss–Legendre
    quadrature between events (the motion is smooth there), on pieces
    graded towards each event (the stiff modes of the beam ring down in
    microseconds after it)."""
    Mm, Cm, Km = system.matrices()
    p = system.load_vector(force)
    edges = np.sort(np.concatenate(([sol._segments[0].ta], sol.event_times)))
    edges = np.append(edges, sol._segments[0].ta + sol.period)
    xg, wg = np.polynomial.legendre.leggauss(n_gauss)
    w_in = w_damp = w_fric = 0.0
    c = system.contact_dof
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        grid = a + (b - a) * np.concatenate(([0.0], np.geomspace(1e-9, 1.0, 60)))
        for a2, b2 in zip(grid[:-1], grid[1:], strict=True):
            t = 0.5 * (a2 + b2) + 0.5 * (b2 - a2) * xg
            x, v, fc = sol.states(t)
            wt = 0.5 * (b2 - a2) * wg
            w_in += np.sum(wt * (p @ v) * np.cos(sol.omega * t))
            w_damp += np.sum(wt * np.einsum("it,ij,jt->t", v, Cm, v))
            slipping = np.abs(np.abs(fc) - system.contact.slip_force) < 1e-9 * abs(
                system.contact.slip_force
            )
            w_fric += np.sum(wt * np.where(slipping, fc * v[c], 0.0))
    return w_in, w_damp, w_fric


@pytest.mark.parametrize("which", ["sdof", "beam"])
def test_energy_balance_per_cycle(which, sdof_solution, beam_solution):
    system, _, sol = sdof_solution if which == "sdof" else beam_solution
    force = F if which == "sdof" else 2.0
    w_in, w_damp, w_fric = _energy_terms(system, force, sol)
    assert w_fric == pytest.approx(sol.friction_dissipation(), rel=1e-10)
    assert w_fric > 0.05 * w_in  # a real stick-slip point
    assert w_damp + w_fric == pytest.approx(w_in, rel=1e-10)


def test_monodromy_matches_finite_differences(sdof_solution, beam_solution):
    for _, _, sol in (sdof_solution, beam_solution):
        model = sol._model
        t0 = sol._segments[0].ta
        y0 = sol.states(np.array([t0]))
        y0 = model.state(y0[0][:, 0], y0[1][:, 0], y0[2][0])
        _, y1, J = _simulate(model, t0, y0, jacobian=True)
        assert np.max(np.abs(y1 - y0)) < 1e-11 * np.max(np.abs(y0))
        h = 1e-6 * np.max(np.abs(y0))
        # every column for the SDOF, a spread of 9 for the beam (79 states)
        cols = np.unique(np.linspace(0, model.size - 1, min(model.size, 9)).astype(int))
        Jfd = J.copy()
        for j in cols:
            e = np.zeros(model.size)
            e[j] = h
            yp = _simulate(model, t0, y0 + e)[1]
            ym = _simulate(model, t0, y0 - e)[1]
            Jfd[:, j] = (yp - ym) / (2 * h)
        assert np.max(np.abs(J - Jfd)) < 1e-6 * np.max(np.abs(J))


def test_period_map_residual_and_events(sdof_solution):
    _, w, sol = sdof_solution
    assert sol.kind == "stick-slip"
    assert sol.residual < 1e-12
    assert sol.events == 4
    # symmetric response: events half a period apart, odd waveform
    t = sol.event_times
    assert t[2] - t[0] == pytest.approx(math.pi / w, rel=1e-9)
    assert abs(sol.fourier(0)) < 1e-9 * sol.amplitude(harmonic=1)
    assert abs(sol.fourier(2)) < 1e-9 * sol.amplitude(harmonic=1)


def test_fourier_matches_a_fine_dft(sdof_solution):
    _, _, sol = sdof_solution
    n = 1 << 15
    t, x = sol.time_response(n)
    for k in (1, 3, 5):
        dft = 2.0 * np.mean(x * np.exp(-1j * k * sol.omega * t))
        # trapezoidal rule on a C² signal with kinks in the 3rd derivative
        assert abs(dft - sol.fourier(k)) < 1e-9 * sol.amplitude(harmonic=1)


# ----------------------------------------------------------------------------
# against the engine and time integration
# ----------------------------------------------------------------------------
def test_hbm_converges_to_the_exact_reference(sdof_solution):
    """Relative error of the first harmonic falls with H, at least like
    H^-3 (a fitted order), and is below 1e-8 at H = 63."""
    osc, w, sol = sdof_solution
    hs = np.array([7, 15, 31, 63])
    errs = []
    for h in hs:
        hb = hf.periodic_solution(osc, F, w, harmonics=int(h))
        assert hb.converged
        errs.append(abs(hb.amplitude(harmonic=1) / sol.amplitude(harmonic=1) - 1.0))
    errs = np.array(errs)
    assert np.all(np.diff(errs) < 0.0)
    order = -np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert order > 3.0
    assert errs[-1] < 1e-8
    hb = hf.periodic_solution(osc, F, w, harmonics=63)
    assert hb.amplitude() == pytest.approx(sol.amplitude(), rel=1e-8)


def test_beam_hbm_at_high_h(beam_solution):
    """The slipping beam resonance: H = 63 within its truncation level, and
    better than H = 15 by more than ten times, at the tip and the forced
    DOF."""
    beam, w, sol = beam_solution
    hb63 = hf.periodic_solution(beam, 2.0, w, harmonics=63)
    hb15 = hf.periodic_solution(beam, 2.0, w, harmonics=15)
    for dof in ("tip", "force"):
        ref = sol.amplitude(harmonic=1, dof=dof)
        e63 = abs(hb63.amplitude(harmonic=1, dof=dof) / ref - 1.0)
        e15 = abs(hb15.amplitude(harmonic=1, dof=dof) / ref - 1.0)
        assert e63 < 2e-5
        assert e63 < 0.1 * e15


def test_time_integration_converges_to_the_exact_reference(sdof_solution):
    """Newmark's error against the reference falls with the step (at least
    fourfold per halving) and is below 2e-6 at 2048 steps per period."""
    osc, w, sol = sdof_solution
    ref = sol.amplitude(harmonic=1)
    errs = []
    for n in (1024, 2048):
        s = steady_state(osc, F, w, steps_per_period=n, tol=1e-12)
        assert s.converged
        errs.append(abs(np.hypot(*s.coefficients[0, 1:3]) / ref - 1.0))
    assert errs[1] < errs[0] / 4.0
    assert errs[1] < 2e-6


def test_beam_time_integration_converges_to_the_exact_reference():
    """Beam, Fn = 1 N at 40 Hz (stuck 29 % of the period): Newmark at 1024
    and 4096 steps per period, at least tenfold closer at the finer step,
    within 1e-5 at it (measured 9.4e-5 and 4.7e-6)."""
    from hbmfric.paper.beam import HZ, paper_beam

    beam = paper_beam(1.0)
    w = 40.0 * HZ
    ref = exact_periodic_solution(beam, 2.0, w, on_failure="raise")
    errs = []
    for n in (1024, 4096):
        s = steady_state(beam, 2.0, w, steps_per_period=n, tol=1e-10)
        assert s.converged
        a1 = np.hypot(*s.coefficients[beam.contact_dof, 1:3])
        errs.append(abs(a1 / ref.amplitude(harmonic=1) - 1.0))
    assert errs[1] < errs[0] / 10.0
    assert errs[1] < 1e-5


def test_branch_seeds_from_the_previous_point():
    osc, w = stick_slip_point()
    omegas = np.linspace(140.0, 160.0, 5)
    branch = exact_branch(osc, F, omegas, on_failure="raise")
    for om, sol in zip(omegas, branch, strict=True):
        alone = exact_periodic_solution(osc, F, om, on_failure="raise")
        assert sol.omega == om
        assert sol.amplitude(harmonic=1) == pytest.approx(
            alone.amplitude(harmonic=1), rel=1e-11
        )
    assert max(s.newton_iterations for s in branch) <= 4


# ----------------------------------------------------------------------------
# edges
# ----------------------------------------------------------------------------
def test_rejects_other_laws_and_bad_input():
    with pytest.raises(ValueError, match="Jenkins"):
        exact_periodic_solution(hf.Oscillator(1.0, 0.1, 1.0), 1.0, 1.0)
    with pytest.raises(ValueError, match="omega"):
        exact_periodic_solution(oscillator(1.0), 1.0, -1.0)
    with pytest.raises(ValueError, match="positive definite"):
        hf_free = hf.Oscillator(
            1.0, 0.1, 0.0, hf.Jenkins(stiffness=1.0, slip_force=0.1)
        )
        exact_periodic_solution(hf_free, 1.0, 1.0)


def test_failure_raises_when_asked():
    osc, w = stick_slip_point()
    with pytest.raises(ConvergenceError):
        exact_periodic_solution(osc, F, w, max_iterations=1, on_failure="raise")


def test_stick_phase_starting_on_the_slip_limit_is_not_an_event():
    """Regression: a stick phase starts with ``|f_c| = f_s`` and ``ẋ_c ≈ 0``;
    rounding made its first grid interval look like a dip touching the
    limit, so a zero-length slip followed, then a zero-length stick, ...
    (paper SDOF scene, Fex/Fn = 0.2, seeded from the continued HBM)."""
    from hbmfric.paper.scenes import paper_oscillator

    osc = paper_oscillator(5.0)
    omegas = [189.59632748112378, 192.26669829071707]
    branch = exact_branch(osc, 1.0, omegas, on_failure="raise")
    for sol in branch:
        assert sol.kind == "stick-slip" and sol.events == 4
        assert sol.residual < 1e-12


def test_coefficients_layout_matches_hbm_and_a_fine_dft(beam_solution):
    """Every DOF of the beam: the exact coefficients in the PeriodicSolution
    layout agree with H = 63 HBM to its truncation level and with a fine DFT
    of the exact time history."""
    beam, w, sol = beam_solution
    hb = hf.periodic_solution(beam, 2.0, w, harmonics=63)
    X = sol.coefficients(hb.harmonic_numbers)
    assert X.shape == hb.coefficients.shape
    scale = np.max(np.abs(X))
    assert np.max(np.abs(X - hb.coefficients)) < 1e-5 * scale
    n = 1 << 14
    t = sol.period * np.arange(n) / n
    x, _, _ = sol.states(t)
    for k in (1, 3):
        dft = 2.0 * np.mean(x * np.exp(-1j * k * w * t), axis=1)
        col = 2 * (k // 2)  # odd harmonics only: 1 -> 0, 3 -> 2
        exact = X[:, col] - 1j * X[:, col + 1]
        assert np.max(np.abs(dft - exact)) < 1e-9 * scale


def test_two_stick_slip_cycles_per_half_period():
    """Beam, Fn = 0.2 N at 6.75 Hz (below a fourth of the first slipping
    resonance): eight events per period. Time integration converges to the
    reference (measured 3.6e-5 at 1024 and 2.0e-6 at 4096 steps per
    period), and the energy balances."""
    from hbmfric.paper.beam import HZ, paper_beam

    beam = paper_beam(0.2)
    w = 6.75 * HZ
    sol = exact_periodic_solution(beam, 2.0, w, on_failure="raise")
    assert sol.events == 8
    ref = sol.amplitude(harmonic=1)
    errs = []
    for n in (1024, 4096):
        s = steady_state(beam, 2.0, w, steps_per_period=n, tol=1e-10)
        assert s.converged
        a1 = np.hypot(*s.coefficients[beam.contact_dof, 1:3])
        errs.append(abs(a1 / ref - 1.0))
    assert errs[1] < errs[0] / 10.0
    assert errs[1] < 1e-5
    w_in, w_damp, w_fric = _energy_terms(beam, 2.0, sol)
    assert w_damp + w_fric == pytest.approx(w_in, rel=1e-10)


@pytest.mark.filterwarnings("ignore::hbmfric.errors.AccuracyWarning")  # H = 7
def test_branch_errors_of_whole_frfs():
    """Whole SDOF FRFs (Fex/Fn = 0.5, 140-240 rad/s): every point compared;
    the stuck stretches are exact to the Newton tolerance, H = 31 is better than H = 7
    in the worst point, and a point's error is the one a separate solve
    gives."""
    from hbmfric.paper.scenes import paper_oscillator

    osc = paper_oscillator(2.0)
    worst = {}
    for h in (7, 31):
        branch = hf.frf(osc, 1.0, (140.0, 240.0), h)
        err = branch_errors(branch, osc, every=4, on_failure="raise")
        assert err.index[0] == 0 and err.index[-1] == len(branch) - 1
        assert np.all(np.diff(err.index) <= 4)
        stuck = np.array([r.kind == "stuck" for r in err.references])
        assert 0 < stuck.sum() < len(branch)
        assert np.max(err.error_h1[stuck]) < 1e-9  # HBM Newton tolerance
        worst[h] = np.max(err.error_h1)
        i = int(np.argmax(err.error_h1))
        alone = exact_periodic_solution(osc, 1.0, err.omega[i])
        a1 = branch.amplitude(harmonic=1)[err.index[i]]
        ref = alone.amplitude(harmonic=1)
        assert abs(a1 - ref) / ref == pytest.approx(err.error_h1[i], rel=1e-6)
    assert worst[31] < 0.05 * worst[7]


def test_many_events_per_period_with_a_stiff_contact():
    """Regression (a random case of a fuzz run): kt/k = 510, ζ = 2.7 %,
    f_s = 0.0026 F below resonance: stick phases of 0.13 % of the period
    with a stiff, lightly damped stuck mode. Newton used to diverge (its
    residual was measured against the diverging iterate itself); now it is
    damped on a fixed scale and falls back to a time-integration start."""
    law = hf.Jenkins(stiffness=509.58989727445805, slip_force=0.0025614418369508617)
    osc = hf.Oscillator(1.0, 0.053994650228932246, 1.0, law)
    w = 0.38588829772549693
    sol = exact_periodic_solution(osc, 1.0, w, on_failure="raise")
    assert sol.kind == "stick-slip" and sol.residual < 1e-12
    s = steady_state(osc, 1.0, w, steps_per_period=4096, tol=1e-11)
    a1 = np.hypot(*s.coefficients[0, 1:3])
    assert a1 == pytest.approx(sol.amplitude(harmonic=1), rel=1e-4)
