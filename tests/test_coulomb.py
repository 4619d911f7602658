"""Rigid Coulomb contact by DLFT, against Den Hartog's exact steady state of
``m ẍ + c ẋ + k x + F_s sgn ẋ = P cos ωt`` and an event-driven integration
with stick phases (both written here, independent of hbmfric).

Den Hartog (1931), non-stop regime, derived here with viscous damping too:
over the half period ``0 < t < τ = π/ω`` after the reversal at ``x = -A``
the mass slides forwards, ``m ẍ + c ẋ + k x = P cos(ωt + φ) - F_s``, and the
motion is antiperiodic, ``x(t + τ) = -x(t)``. Write the state as
homogeneous + particular + static parts, ``s = h + p + d`` with
``d = (-F_s/k, 0)``, ``p(t) = Re(z e^{iωt}) `` (``z = B e^{iφ}``, ``B`` the
complex receptance times ``P``), ``h(τ) = Φ h(0)`` (``Φ`` the free-motion
transition over ``τ``). ``s(τ) = -s(0)`` and ``p(τ) = -p(0)`` give
``s(0) - p(0) = g = -(I + Φ)⁻¹ (I - Φ) d``, so with ``s(0) = (-A, 0)``:
``ω Im z = g₂`` and ``A = -g₁ - Re z``, ``Re z = -sqrt(|B|² - (g₂/ω)²)``.
Undamped, ``g₁ = 0``, ``g₂ = ω F_s tan(πω/2ωₙ)/(k r)`` and
``A/(P/k) = sqrt(1/(1 - r²)² - (F_s U/P)²)``,
``U = sin(π/r) / (r (1 + cos(π/r)))``, ``r = ω/ωₙ``: Den Hartog's formula.

Measured accuracy (H = 31). Default (``hf.Coulomb(linear_tail=True)``,
:mod:`hbmfric.kernels.dlft.tail`: switches located on the velocity plus its
linear tail above H): peak within 3e-4, first harmonic within 2e-7 for
F_s/P = 0.1-0.7 in the non-stop regime, third order in H; 2e-4 to 5e-4 in
the stop regime (F_s/P = 0.3). Located DLFT without the tail
(``linear_tail=False``, :func:`hbmfric.kernels.dlft.coulomb.dlft_located`): 5e-4
to 3e-3 relative in the non-stop regime for F_s/P <= 0.3, 6e-3 at 0.4 and
1e-2 at 0.6; 2e-4 to 2e-3 in the stop regime; first order in H. The
classic DLFT (``aft="samples"``, stick/slip decided on the predicted force)
is 1e-2 to 7e-2 off at H = 31. Tests that need the located scheme pass
``linear_tail=False`` (the default of :func:`_coulomb_oscillator`).
"""

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import hbmfric as hf
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.dlft.coulomb import dlft_correct

M, K = 1.0, 1.0


# ----------------------------------------------------------------------------
# references
# ----------------------------------------------------------------------------
def _free(c, x0, v0, t):
    """Free motion of ``M x'' + c x' + K x = 0`` (underdamped): x, v."""
    wn = math.sqrt(K / M)
    zeta = c / (2.0 * math.sqrt(K * M))
    wd = wn * math.sqrt(1.0 - zeta**2)
    e = np.exp(-zeta * wn * t)
    b = (v0 + zeta * wn * x0) / wd
    cs, sn = np.cos(wd * t), np.sin(wd * t)
    x = e * (x0 * cs + b * sn)
    v = e * (-zeta * wn * (x0 * cs + b * sn) + wd * (-x0 * sn + b * cs))
    return x, v


def den_hartog(c, fs, P, w):
    """Non-stop steady state: ``(A, φ, motion)`` or None if none exists.

    ``motion(t) -> (x, v)`` with ``t`` from the reversal at ``x = -A``,
    where the forcing is ``P cos(ωt + φ)``.
    """
    tau = math.pi / w
    d = np.array([-fs / K, 0.0])
    Phi = np.array([_free(c, 1.0, 0.0, tau), _free(c, 0.0, 1.0, tau)]).T
    eye = np.eye(2)
    g = -np.linalg.solve(eye + Phi, (eye - Phi) @ d)
    B = P / (K - M * w**2 + 1j * c * w)
    im_z = g[1] / w
    disc = abs(B) ** 2 - im_z**2
    if disc < 0.0:
        return None
    z = -math.sqrt(disc) + 1j * im_z
    A = -g[0] - z.real
    h0 = g - d

    def motion(t):
        t = np.asarray(t, dtype=float) % (2.0 * tau)
        sign = np.where(t < tau, 1.0, -1.0)
        s = np.where(t < tau, t, t - tau)
        hx, hv = _free(c, h0[0], h0[1], s)
        ze = z * np.exp(1j * w * s)
        return sign * (hx + ze.real + d[0]), sign * (hv + (1j * w * ze).real)

    return A, float(np.angle(z / B)), motion


def is_non_stop(c, fs, P, w):
    """Den Hartog's solution exists, the velocity keeps its sign over the
    half period and the breakaway force at the reversal exceeds F_s."""
    sol = den_hartog(c, fs, P, w)
    if sol is None:
        return False
    A, phi, motion = sol
    t = np.linspace(0.0, math.pi / w, 2001)[1:-1]
    _, v = motion(t)
    return bool(v.min() > 0.0 and P * math.cos(phi) + K * A > fs)


def den_hartog_measures(c, fs, P, w, n=8192):
    """Half peak-to-peak and first-harmonic amplitude of the exact motion."""
    A, _, motion = den_hartog(c, fs, P, w)
    t = 2.0 * math.pi / w * np.arange(n) / n
    x, _ = motion(t)
    a1 = 2.0 * abs(np.mean(x * np.exp(-1j * w * t)))
    return A, a1


def event_driven_steady_state(c, fs, P, w, n_out=4096, max_periods=200, max_events=200):
    """Steady state by event-driven integration with stick phases.

    Slip: ``solve_ivp`` with the friction sign fixed, stopped at the zero of
    the velocity; there the mass sticks if the holding force
    ``|P cos ωt - K x| <= F_s``, else it slides back at once; a stick phase
    ends when the holding force reaches ``±F_s``. Returns the displacement
    at ``n_out`` instants of the last period.
    """
    T = 2.0 * math.pi / w

    def slide(t, s, sign):
        return [s[1], (P * math.cos(w * t) - K * s[0] - c * s[1] - fs * sign) / M]

    def holding(t, x):
        return P * math.cos(w * t) - K * x

    t, x, v, mode = 0.0, 0.0, 0.0, 0
    previous = None
    for period in range(max_periods):
        t_end = (period + 1) * T
        pieces = []
        while t < t_end - 1e-13:
            # a work budget: near the regime boundary the stick phases shrink
            # to nothing and the events pile up (Zeno-like chatter)
            if len(pieces) > max_events:
                raise RuntimeError(f"event-driven reference chatters at w={w}")
            if mode == 0:
                x_stuck = x

                def leave(tt, s, x_stuck=x_stuck):
                    return abs(holding(tt, x_stuck)) - fs

                leave.terminal = True
                leave.direction = 1
                sol = solve_ivp(
                    lambda tt, s: [0.0],
                    (t, t_end),
                    [0.0],
                    events=leave,
                    max_step=T / 256,
                    rtol=1e-12,
                    atol=1e-14,
                )
                t_next = sol.t_events[0][0] if sol.t_events[0].size else t_end
                pieces.append((t, t_next, x_stuck))
                if sol.t_events[0].size:
                    mode = 1 if holding(t_next, x) > 0.0 else -1
                t = t_next
            else:

                def stop(tt, s, sign):
                    return s[1]

                stop.terminal = True
                stop.direction = -mode
                sol = solve_ivp(
                    slide,
                    (t, t_end),
                    [x, v],
                    args=(mode,),
                    events=stop,
                    dense_output=True,
                    rtol=1e-12,
                    atol=1e-14,
                )
                if sol.t_events[0].size:
                    t_next = sol.t_events[0][0]
                    x, v = sol.y_events[0][0][0], 0.0
                    hold = holding(t_next, x)
                    mode = 0 if abs(hold) <= fs else (1 if hold > 0.0 else -1)
                else:
                    t_next = t_end
                    x, v = sol.y[:, -1]
                pieces.append((t, t_next, sol.sol))
                t = t_next
        state = (x, v, mode)
        if previous is not None and previous[2] == mode:
            if abs(x - previous[0]) + abs(v - previous[1]) / w < 1e-10 * abs(x):
                break
        previous = state
    times = (period + np.arange(n_out) / n_out) * T
    out = np.empty(n_out)
    for a, b, piece in pieces:
        sel = (times >= a - 1e-12) & (times <= b + 1e-12)
        out[sel] = piece if isinstance(piece, float) else piece(times[sel])[0]
    return out


def _measures(samples):
    n = samples.size
    a1 = 2.0 * abs(np.mean(samples * np.exp(-2j * np.pi * np.arange(n) / n)))
    return 0.5 * (samples.max() - samples.min()), a1


def _coulomb_oscillator(c, fs, penalty=None, linear_tail=False):
    law = hf.Coulomb(slip_force=fs, penalty=penalty, linear_tail=linear_tail)
    return hf.Oscillator(M, c, K, law)


def _errors(sol, reference):
    A, a1 = reference
    return sol.amplitude() / A - 1.0, sol.amplitude(harmonic=1) / a1 - 1.0


# ----------------------------------------------------------------------------
# the references themselves
# ----------------------------------------------------------------------------
@pytest.mark.parametrize(("c", "fs", "w"), [(0.0, 0.3, 0.7), (0.0, 0.3, 1.5)])
def test_den_hartog_matches_the_undamped_closed_form(c, fs, w):
    r = w / math.sqrt(K / M)
    U = math.sin(math.pi / r) / (r * (1.0 + math.cos(math.pi / r)))
    closed = math.sqrt(1.0 / (1.0 - r**2) ** 2 - (fs * U) ** 2)  # P = K = 1
    assert den_hartog(c, fs, 1.0, w)[0] == pytest.approx(closed, rel=1e-12)


@pytest.mark.parametrize(
    ("c", "fs", "w"), [(0.0, 0.3, 0.7), (0.0, 0.6, 1.2), (0.02, 0.3, 2.5)]
)
def test_den_hartog_is_a_periodic_orbit_of_the_friction_oscillator(c, fs, w):
    """From (-A, 0) at forcing phase φ, integrate the nonlinear ODE with the
    friction sign switched at the located velocity zeros: the velocity
    vanishes exactly at τ, 2τ, ... and the state returns after a period."""
    P = 1.0
    assert is_non_stop(c, fs, P, w)
    A, phi, _ = den_hartog(c, fs, P, w)
    tau = math.pi / w

    def rhs(t, s, sign):
        return [s[1], (P * math.cos(w * t + phi) - K * s[0] - c * s[1] - fs * sign)]

    t0, state, sign = 0.0, np.array([-A, 0.0]), 1.0
    for half in range(1, 5):

        def stop(t, s, sign):
            return s[1]

        stop.terminal = True
        stop.direction = -sign
        sol = solve_ivp(
            rhs, (t0, t0 + 4 * tau), state, args=(sign,), events=stop,
            rtol=1e-12, atol=1e-14,
        )  # fmt: skip
        t0, state = sol.t_events[0][0], sol.y_events[0][0]
        assert t0 == pytest.approx(half * tau, rel=1e-9)
        assert state[0] == pytest.approx(A if half % 2 else -A, rel=1e-9)
        sign = -sign


@pytest.mark.slow
def test_event_driven_integration_reaches_den_hartog():
    ref = event_driven_steady_state(0.02, 0.3, 1.0, 0.7)
    exact = den_hartog_measures(0.02, 0.3, 1.0, 0.7)
    np.testing.assert_allclose(_measures(ref), exact, rtol=1e-7)


# ----------------------------------------------------------------------------
# DLFT harmonic balance against the references
# ----------------------------------------------------------------------------
NON_STOP = [
    (0.0, 0.3, 0.7),
    (0.0, 0.3, 1.5),
    (0.0, 0.3, 2.5),
    (0.02, 0.3, 0.7),
    (0.02, 0.2, 1.3),
]


@pytest.mark.parametrize(("c", "fs", "w"), NON_STOP)
def test_dlft_against_den_hartog(c, fs, w):
    """The target of issue 3 for the located scheme without the tail: H =
    31, peak and first-harmonic amplitude within 5e-3 (measured 5e-4 to
    3e-3)."""
    assert is_non_stop(c, fs, 1.0, w)
    sol = hf.periodic_solution(_coulomb_oscillator(c, fs), 1.0, w, harmonics=31)
    assert sol.converged
    assert sol.contact_state == "contact slips during the period"
    peak, first = _errors(sol, den_hartog_measures(c, fs, 1.0, w))
    assert abs(peak) < 5e-3 and abs(first) < 5e-3


@pytest.mark.parametrize(("c", "fs", "w"), [(0.02, 0.4, 2.0), (0.0, 0.6, 1.2)])
def test_dlft_against_den_hartog_at_larger_friction(c, fs, w):
    """F_s/P = 0.4 and 0.6 with the linear tail: within 5e-3 (measured 2e-5
    peak, 3e-8 first harmonic). Without it (``linear_tail=False``) the
    located scheme is 5.9e-3 and 9.6e-3 off: asserted outside 5e-3 so that
    the test shows what the tail does."""
    assert is_non_stop(c, fs, 1.0, w)
    exact = den_hartog_measures(c, fs, 1.0, w)
    sol = hf.periodic_solution(
        _coulomb_oscillator(c, fs, linear_tail=True), 1.0, w, harmonics=31
    )
    assert sol.converged
    peak, first = _errors(sol, exact)
    assert abs(peak) < 5e-3 and abs(first) < 5e-3
    located = hf.periodic_solution(_coulomb_oscillator(c, fs), 1.0, w, harmonics=31)
    assert abs(_errors(located, exact)[0]) > 5e-3


TAIL_CASES = [
    (c, fs, w)
    for c in (0.0, 0.02)
    for fs, ws in (
        (0.1, (0.5, 2.5)),
        (0.3, (0.7, 1.5)),
        (0.5, (0.8, 2.0)),
        (0.7, (0.8, 1.2)),
    )  # fmt: skip
    for w in ws
]
# half of them run by default, all with -m slow
TAIL_CASES = [
    case if i % 2 == 0 else pytest.param(*case, marks=pytest.mark.slow)
    for i, case in enumerate(TAIL_CASES)
]


@pytest.mark.parametrize(("c", "fs", "w"), TAIL_CASES)
def test_linear_tail_against_den_hartog(c, fs, w):
    """Issue 3 for every non-stop case: F_s/P = 0.1-0.7, with and without
    damping, below and above resonance; H = 31, peak and first harmonic
    within 5e-3 of Den Hartog (measured: peak <= 3e-5, the truncated
    series missing the tail's displacement at the peak; first harmonic
    <= 1e-7)."""
    assert is_non_stop(c, fs, 1.0, w)
    sol = hf.periodic_solution(
        _coulomb_oscillator(c, fs, linear_tail=True), 1.0, w, harmonics=31
    )
    assert sol.converged
    assert sol.contact_state == "contact slips during the period"
    peak, first = _errors(sol, den_hartog_measures(c, fs, 1.0, w))
    assert abs(peak) < 5e-3 and abs(first) < 5e-3
    assert abs(first) < 1e-5  # far below the target: the tail is exact


def test_linear_tail_converges_at_third_order_in_harmonics():
    """With the tail, first-harmonic error against Den Hartog at H = 15, 31,
    63: measured 2.1e-7, 2.9e-8, 3.5e-9 (F_s/P = 0.3) and 2.4e-7, 3.3e-8,
    3.9e-9 (0.6): fitted order 3 (asserted 2.5-3.5); without the tail
    order 1 (test below)."""
    for c, fs, w in ((0.02, 0.3, 0.7), (0.0, 0.6, 1.2)):
        exact = den_hartog_measures(c, fs, 1.0, w)
        orders = [15, 31, 63]
        errors = []
        for h in orders:
            sol = hf.periodic_solution(
                _coulomb_oscillator(c, fs, linear_tail=True), 1.0, w, harmonics=h
            )
            assert sol.converged
            errors.append(abs(_errors(sol, exact)[1]))
        slope = np.polyfit(np.log(orders), np.log(errors), 1)[0]
        assert -3.5 < slope < -2.5


def test_linear_tail_does_not_depend_on_the_sampling():
    """Pure slip: the force is integrated exactly, so the solution does not
    move with the number of samples (8 H and 32 H)."""
    osc = _coulomb_oscillator(0.02, 0.4, linear_tail=True)
    a = hf.periodic_solution(osc, 1.0, 2.0, harmonics=15)
    b = hf.periodic_solution(osc, 1.0, 2.0, harmonics=15, n_time=480)
    np.testing.assert_allclose(a.coefficients, b.coefficients, atol=1e-10)


@pytest.mark.parametrize(("c", "fs", "w"), [(0.0, 0.3, 0.7), (0.02, 0.4, 2.0)])
def test_classic_dlft_is_less_accurate(c, fs, w):
    """The classic sampled DLFT (``aft="samples"``) decides stick and slip
    on the predicted force, whose truncated series rings at the jumps:
    measured 1.4e-2 and 4.0e-2 off, 7-10 times the located scheme."""
    exact = den_hartog_measures(c, fs, 1.0, w)
    classic = hf.periodic_solution(
        _coulomb_oscillator(c, fs), 1.0, w, harmonics=31, aft="samples"
    )
    located = hf.periodic_solution(_coulomb_oscillator(c, fs), 1.0, w, harmonics=31)
    assert classic.converged and located.converged
    err_classic = abs(_errors(classic, exact)[0])
    assert 0.03 * fs < err_classic < 0.12 * fs
    assert abs(_errors(located, exact)[0]) < err_classic / 4.0


def test_dlft_converges_at_first_order_in_harmonics():
    """Without the tail (``linear_tail=False``): error against Den Hartog at H = 15, 31,
    63 (4.0e-3, 2.0e-3, 9.8e-4): fitted order 1 (± 0.2)."""
    c, fs, w = 0.02, 0.3, 0.7
    exact = den_hartog_measures(c, fs, 1.0, w)
    orders = [15, 31, 63]
    errors = []
    for h in orders:
        sol = hf.periodic_solution(_coulomb_oscillator(c, fs), 1.0, w, harmonics=h)
        assert sol.converged
        errors.append(abs(_errors(sol, exact)[0]))
    slope = np.polyfit(np.log(orders), np.log(errors), 1)[0]
    assert -1.2 < slope < -0.8


@pytest.mark.parametrize(("fs", "w"), [(0.3, 0.7), (0.6, 0.5)])
def test_solution_is_insensitive_to_the_penalty(fs, w):
    """ε = K and 10 K: without stick phases (0.3, 0.7) the solution does not
    depend on ε at all; with them (0.6, 0.5, stop regime) it moves by
    less than its truncation error (measured 1e-3; 2e-3 allowed)."""
    c = 0.02
    peaks = []
    for eps in (1.0, 10.0):
        sol = hf.periodic_solution(
            _coulomb_oscillator(c, fs, penalty=eps), 1.0, w, harmonics=31
        )
        assert sol.converged
        peaks.append(sol.amplitude())
    if is_non_stop(c, fs, 1.0, w):
        assert peaks[0] == pytest.approx(peaks[1], rel=1e-9)
    else:
        assert peaks[0] == pytest.approx(peaks[1], rel=2e-3)


@pytest.mark.parametrize("w", [0.3, 0.9, 1.0, 2.0])
@pytest.mark.parametrize("symmetry", [None, False])
def test_small_forcing_sticks(w, symmetry):
    """P < F_s: the contact holds the mass still at every frequency."""
    sol = hf.periodic_solution(
        _coulomb_oscillator(0.02, 1.0), 0.8, w, harmonics=15, symmetry=symmetry
    )
    assert sol.converged
    assert sol.contact_state == "contact stuck over the whole period"
    assert np.max(np.abs(sol.coefficients)) < 1e-10  # Newton tolerance 1e-10 P


@pytest.mark.slow
@pytest.mark.parametrize("linear_tail", [False, True])
@pytest.mark.parametrize(("fs", "w"), [(0.3, 0.3), (0.6, 0.5)])
def test_dlft_in_the_stop_regime(fs, w, linear_tail):
    """Stick phases inside the period: against the event-driven integration,
    amplitudes within 5e-3 at H = 31 (measured 2.5e-4 to 1.7e-3), the whole
    motion within 1e-2 of its peak (measured 4e-3), and no relative motion
    where the reference sticks: median |u̇| there below 5e-3 of its peak
    (measured 2e-3; the largest values, 2e-2, sit at the stick ends where
    the truncated series cannot turn sharply)."""
    c = 0.02
    assert not is_non_stop(c, fs, 1.0, w)
    samples = event_driven_steady_state(c, fs, 1.0, w)
    sol = hf.periodic_solution(
        _coulomb_oscillator(c, fs, linear_tail=linear_tail), 1.0, w, harmonics=31
    )
    assert sol.converged
    peak, first = _errors(sol, _measures(samples))
    assert abs(peak) < 5e-3 and abs(first) < 5e-3
    n = samples.size
    _, x = sol.time_response(n=n)
    assert np.max(np.abs(x - samples)) < 1e-2 * np.max(np.abs(samples))
    stuck = np.diff(samples, append=samples[0]) == 0.0  # exactly constant
    assert 0.1 < stuck.mean() < 0.9
    theta = 2.0 * np.pi * np.arange(n) / n
    X = sol.coefficients[0]
    velocity = sum(
        k * (X[2 * j + 1] * np.cos(k * theta) - X[2 * j] * np.sin(k * theta))
        for j, k in enumerate(sol.harmonic_numbers)
    )
    peak_velocity = np.max(np.abs(velocity))
    assert np.median(np.abs(velocity[stuck])) < 5e-3 * peak_velocity


# ----------------------------------------------------------------------------
# Jacobian
# ----------------------------------------------------------------------------
class _TwoDof:
    """Two masses in a chain, the contact on the second (duck-typed system)."""

    n_dof = 2
    contact_dof = 1
    symmetric = True

    def __init__(self, contact):
        self.contact = contact

    def matrices(self):
        m = np.diag([1.0, 0.5])
        k = np.array([[3.0, -1.0], [-1.0, 1.0]])
        return m, 0.01 * k + 0.02 * m, k

    def load_vector(self, force):
        return np.array([force, 0.3 * force])


def _with_contact(system, law):
    if isinstance(system, _TwoDof):
        return _TwoDof(law)
    return system.with_contact(law)


def _fd_jacobian(problem, y, h=1e-7):
    J = np.empty((problem.n_unknowns, y.size))
    for j in range(y.size):
        yp, ym = y.copy(), y.copy()
        yp[j] += h
        ym[j] -= h
        J[:, j] = (problem.residual(yp)[0] - problem.residual(ym)[0]) / (2.0 * h)
    return J


@pytest.mark.parametrize("aft", ["events", "samples", "tail"])
@pytest.mark.parametrize(
    ("system", "force", "omega", "state"),
    [
        (_coulomb_oscillator(0.02, 0.3), 1.0, 0.7, 2),
        (_coulomb_oscillator(0.02, 0.6), 1.0, 0.4, 2),
        (_coulomb_oscillator(0.02, 1.0), 0.5, 0.7, 1),
        (_TwoDof(hf.Coulomb(slip_force=0.2)), 1.0, 1.1, 2),
    ],
)
def test_jacobian_against_finite_differences(system, force, omega, state, aft):
    """Analytic [dR/dX, dR/dΩ] against central differences at a point off
    the solution (the DLFT residual is piecewise linear; the point and the
    step are chosen away from its seams, checked by the stick/slip state).
    "tail": the located scheme with the linear tail (``dθ/dy`` by the
    implicit function theorem on the switching conditions)."""
    if aft == "tail":
        system = _with_contact(system, replace(system.contact, linear_tail=True))
        aft = "events"
    problem = HBMProblem(system, force, harmonics=7, aft=aft)
    sol = hf.periodic_solution(system, force, omega, harmonics=7, aft=aft)
    rng = np.random.default_rng(3)
    y = np.append(sol.coefficients.reshape(-1), omega)
    y[:-1] += 0.02 * np.max(np.abs(y[:-1]) + 1e-3) * rng.standard_normal(y.size - 1)
    R, J, got = problem.residual(y)
    assert got == state
    np.testing.assert_allclose(
        J, _fd_jacobian(problem, y), atol=1e-6 * np.max(np.abs(J))
    )


def test_kernels_compile_once():
    """Other slip forces, penalties, masses and harmonic counts reuse the
    compiled DLFT kernels (no recompilation per parameter value)."""
    from hbmfric.kernels.dlft.coulomb import dlft_contact, dlft_located
    from hbmfric.kernels.dlft.tail import contact_receptance, dlft_tail

    # Other tests may already have compiled these kernels from inside other
    # jitted callers (with other array layouts), so the count is compared
    # before and after the parameter sweep rather than against 1.
    counts = None
    for fs, eps, h in ((0.3, 1.0, 7), (0.5, 3.0, 9), (0.2, 0.5, 15), (0.9, 7.0, 3)):
        osc = hf.Oscillator(1.3, 0.02, 1.0, hf.Coulomb(slip_force=fs, penalty=eps))
        problem = HBMProblem(osc, 1.0, h)
        hn, mass, _, _, _, pairs, _, rows, _, inverse, forward, derivative = (
            problem.kernel_problem
        )
        c, params = int(pairs[0, 0]), rows[0]
        y = np.append(problem.linear_response(0.8, "free"), 0.8)
        R, J, _ = HBMProblem(osc.with_contact(None), 1.0, h).residual(y)
        base = int(c) * problem.n_coef
        dlft_located(
            params, hn, base, mass[c, c], y, inverse, forward, derivative, R, J
        )
        dlft_contact(params, base, y, inverse, forward, R, J)
        tail = HBMProblem(osc.with_contact(replace(osc.contact, linear_tail=True)),
                          1.0, h)  # fmt: skip
        tp = tail.kernel_problem[7][0]
        q = np.zeros(int(tp[4]) + 1, dtype=np.complex128)
        dq = np.zeros_like(q)
        a2, da2, _ = contact_receptance(
            mass, tail.kernel_problem[2], tail.kernel_problem[3], c, 0.8, hn,
            tp[3], q, dq,
        )  # fmt: skip
        dlft_tail(tp, hn, base, mass[c, c], q, dq, a2, da2, y, inverse, forward,
                  derivative, R, J)  # fmt: skip
        now = (
            len(dlft_located.signatures),
            len(dlft_contact.signatures),
            len(dlft_tail.signatures),
            len(contact_receptance.signatures),
        )
        if counts is None:
            counts = now
    assert now == counts


def test_correction_kernel_is_a_jenkins_march_on_the_prediction():
    """In terms of v = λ_pred/ε the correction is a Jenkins element of
    stiffness ε; compare with the plain-NumPy Jenkins march."""
    from naive import analyse, jenkins_march, synthesis_matrix

    harmonics = np.arange(0, 8)
    problem = HBMProblem(_coulomb_oscillator(0.0, 1.0), 1.0, 7, symmetry=False)
    inverse, forward = problem.kernel_problem[9], problem.kernel_problem[10]
    rng = np.random.default_rng(1)
    V = rng.standard_normal(problem.n_coef) / np.arange(1, problem.n_coef + 1)
    F = np.empty(problem.n_coef)
    dF = np.empty((problem.n_coef, problem.n_coef))
    eps, fs = 2.0, 0.4
    state = dlft_correct(fs, eps, V, inverse, forward, F, dF)
    assert state == 2
    v = synthesis_matrix(harmonics, problem.n_time) @ V
    force, _ = jenkins_march(v, eps, fs)
    np.testing.assert_allclose(F, analyse(harmonics, force), atol=1e-12)


# ----------------------------------------------------------------------------
# FRF branch
# ----------------------------------------------------------------------------
def _default_branch(c, fs):
    """The default law (linear tail) over 0.3-3 rad/s, H = 31."""
    law = hf.Coulomb(slip_force=fs)
    assert law.linear_tail
    return hf.frf(hf.Oscillator(M, c, K, law), 1.0, (0.3, 3.0), harmonics=31)


def test_frf_branch_through_stop_and_slip_regimes():
    """F_s/P = 0.3 with 1 % damping over 0.3-3 rad/s, default law (linear
    tail): stop regime at low frequency (up to 0.487 rad/s), non-stop around
    and above resonance, one branch to the end. Non-stop points against Den
    Hartog within 1e-3 (measured 2.3e-4; the located scheme without the
    tail is 3.3e-3 off)."""
    c, fs = 0.02, 0.3
    branch = _default_branch(c, fs)
    assert branch.stop_reason == "end of frequency range reached"
    assert branch.omega[0] == pytest.approx(0.3) and branch.omega[-1] == 3.0
    stop = [w for w in branch.omega if not is_non_stop(c, fs, 1.0, w)]
    # through the stop regime (the count depends on the step sizes: 19 points
    # since the located stick end, more than 20 before)
    assert len(stop) > 15 and max(stop) > 0.48
    peaks = branch.amplitude()
    checked = 0
    for w, a in zip(branch.omega[::10], peaks[::10], strict=True):
        if is_non_stop(c, fs, 1.0, w) and abs(w - 1.0) > 0.05:
            A = den_hartog(c, fs, 1.0, w)[0]
            assert abs(a / A - 1.0) < 1e-3, w
            checked += 1
    assert checked >= 10


@pytest.mark.slow
def test_frf_branch_stop_regime_against_event_driven_integration():
    """Stop-regime points of the default branch (F_s/P = 0.3), mid-regime
    and the last one before the non-stop regime, against the event-driven
    integration: peak and first harmonic within 1e-3 (measured <= 4.5e-4
    and 2.3e-4 over the regime; the located scheme without the tail: 1.8e-3
    and 6e-3)."""
    c, fs = 0.02, 0.3
    branch = _default_branch(c, fs)
    stop = [i for i, w in enumerate(branch.omega) if not is_non_stop(c, fs, 1.0, w)]
    # the last stop-regime point at least 2 % below the regime boundary:
    # near the boundary the stick phases shrink to nothing and the
    # event-driven reference chatters (at 0.47998, 1.5 % below it, it ran for
    # over 10 minutes before its event budget; at 0.4762 it takes 7 s)
    edge = min(w for w in branch.omega if is_non_stop(c, fs, 1.0, w) and w > 0.4)
    last = max(i for i in stop if branch.omega[i] <= 0.98 * edge)
    for i in (stop[len(stop) // 2], last):
        w = branch.omega[i]
        ref = _measures(event_driven_steady_state(c, fs, 1.0, w))
        point = branch.point(i)
        assert abs(point.amplitude() / ref[0] - 1.0) < 1e-3, w
        assert abs(point.amplitude(harmonic=1) / ref[1] - 1.0) < 1e-3, w


# ----------------------------------------------------------------------------
# what a stiff Jenkins element does instead (the point of the issue)
# ----------------------------------------------------------------------------
@pytest.mark.slow
def test_stiff_jenkins_against_dlft_with_light_damping(capsys):
    """kt = 1e4 k, 1 % damping, H = 31, against the exact references.

    Measured: in the non-stop regime the stiff Jenkins HBM is close
    (3.5e-3 at F_s/P = 0.3, 2.3e-2 at 0.6) and DLFT is 1.4e-2 and 7.6e-2
    off; in the stop regime (stick phases) the stiff Jenkins HBM does not
    converge while DLFT converges within 3e-2. Asserted: DLFT converges
    everywhere; Jenkins, where it converges (also in the stop regime since
    periodic_solution's larger Newton budget: 6e-3 off at F_s/P = 0.3,
    ω = 0.3), is within 3e-2.
    """
    c = 0.02
    cases = [(0.3, 0.7), (0.6, 1.2), (0.3, 0.3), (0.6, 0.5)]
    for fs, w in cases:
        if is_non_stop(c, fs, 1.0, w):
            ref = den_hartog_measures(c, fs, 1.0, w)
        else:
            ref = _measures(event_driven_steady_state(c, fs, 1.0, w))
        jenkins = hf.periodic_solution(
            hf.Oscillator(M, c, K, hf.Jenkins(stiffness=1e4 * K, slip_force=fs)),
            1.0,
            w,
            harmonics=31,
        )
        dlft = hf.periodic_solution(_coulomb_oscillator(c, fs), 1.0, w, harmonics=31)
        with capsys.disabled():
            print(
                f"\nF_s/P={fs} ω={w} non-stop={is_non_stop(c, fs, 1.0, w)}: "
                f"Jenkins converged={jenkins.converged} "
                f"err={_errors(jenkins, ref)[0]:+.2e}; DLFT "
                f"converged={dlft.converged} err={_errors(dlft, ref)[0]:+.2e}"
            )
        assert dlft.converged
        # the stiff Jenkins HBM converges too since periodic_solution starts
        # Newton with a first-point budget (stop 19); where it does, it is a
        # solution whose truncation error is that of a stiff contact at H = 31
        if jenkins.converged:
            assert abs(_errors(jenkins, ref)[0]) < 3e-2


# ----------------------------------------------------------------------------
# the law object
# ----------------------------------------------------------------------------
def test_friction_coefficient_and_normal_load():
    law = hf.Coulomb(friction_coefficient=0.5, normal_load=20.0)
    assert law.slip_force == 10.0
    assert law.with_normal_load(40.0).slip_force == 20.0
    with pytest.raises(ValueError, match="friction_coefficient"):
        hf.Coulomb(slip_force=1.0).with_normal_load(2.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({}, "slip_force"),
        ({"slip_force": 0.0}, "slip_force"),
        ({"slip_force": 1.0, "penalty": -1.0}, "penalty"),
        ({"normal_load": 2.0}, "friction_coefficient"),
        (
            {"slip_force": 3.0, "friction_coefficient": 0.5, "normal_load": 2.0},
            "either",
        ),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        hf.Coulomb(**kwargs)


def test_penalty_needs_static_stiffness_or_a_value():
    free_mass = hf.Oscillator(1.0, 0.1, 0.0, hf.Coulomb(slip_force=0.1))
    with pytest.raises(ValueError, match="penalty"):
        HBMProblem(free_mass, 1.0, 5)
    given = free_mass.with_contact(hf.Coulomb(slip_force=0.1, penalty=2.0))
    assert HBMProblem(given, 1.0, 5).penalty == 2.0
    assert HBMProblem(_coulomb_oscillator(0.0, 0.1), 1.0, 5).penalty == K


def test_time_integration_refuses_a_rigid_contact():
    with pytest.raises(ValueError, match="stiff hf.Jenkins"):
        hf.validation.steady_state(_coulomb_oscillator(0.0, 0.3), 1.0, 0.7)


def test_hysteresis_is_the_rigid_limit_of_jenkins():
    theta = 2.0 * np.pi * np.arange(256) / 256
    u = 0.7 * np.cos(theta) + 0.2 * np.sin(3 * theta)
    law = hf.Coulomb(slip_force=0.4)
    stiff = hf.Jenkins(stiffness=1e12, slip_force=0.4)
    np.testing.assert_allclose(law.hysteresis(u), stiff.hysteresis(u), atol=1e-9)


def test_energy_and_first_harmonic_under_a_cosine():
    a, fs = 0.8, 0.4
    law = hf.Coulomb(slip_force=fs)
    theta = 2.0 * np.pi * (np.arange(4096) + 0.5) / 4096
    f = -fs * np.sign(np.sin(theta))
    u = a * np.cos(theta)
    work = -np.sum(f * a * np.sin(theta)) * 2.0 * np.pi / 4096  # ∮ f du
    assert law.energy_per_cycle(a) == pytest.approx(work, rel=1e-6)
    c1, s1 = law.first_harmonic(a)
    assert c1 == 0.0
    assert s1 == pytest.approx(2.0 * np.mean(f * np.sin(theta)), rel=1e-6)
    assert u.size == f.size


def test_coulomb_problem_type_carries_the_dlft():
    """A rigid Coulomb contact builds a ``CoulombProblem`` (full) or a
    ``CondensedCoulombProblem``, the only types whose residual compiles the
    DLFT kernels; a Jenkins contact builds the types of its AFT family
    (``JenkinsProblem``, ``CondensedSingleJenkinsProblem``, without the DLFT),
    a memoryless one the plain tuple. The same Coulomb data in a plain tuple
    give the refusal status (the DLFT is not compiled into it), in a
    CoulombProblem the DLFT residual of the problem itself."""
    from hbmfric.condensation import CondensedHBMProblem
    from hbmfric.kernels.residuals.condensed import (
        CondensedCoulombProblem,
        CondensedSingleJenkinsProblem,
    )
    from hbmfric.kernels.residuals.hbm import (
        NOT_A_COULOMB_PROBLEM,
        CoulombProblem,
        JenkinsProblem,
        hbm_residual,
    )

    osc = _coulomb_oscillator(0.02, 0.3)
    problem = HBMProblem(osc, 1.0, 5)
    assert type(problem.kernel_problem) is CoulombProblem
    jenkins = hf.Oscillator(M, 0.02, K, hf.Jenkins(stiffness=3.0, slip_force=0.3))
    assert type(HBMProblem(jenkins, 1.0, 5).kernel_problem) is JenkinsProblem
    cubic = hf.Oscillator(M, 0.02, K, hf.Cubic(0.2))
    assert type(HBMProblem(cubic, 1.0, 5).kernel_problem) is tuple
    cond = CondensedHBMProblem(osc, 1.0, 5)
    assert type(cond.kernel_problem) is CondensedCoulombProblem
    assert type(CondensedHBMProblem(jenkins, 1.0, 5).kernel_problem) is (
        CondensedSingleJenkinsProblem
    )
    y = np.zeros(problem.n_unknowns + 1)
    y[0] = 0.1
    y[-1] = 1.1
    R, J, state = problem.residual(y)
    assert state >= 0
    plain = tuple(problem.kernel_problem)
    R2 = np.empty_like(R)
    J2 = np.empty_like(J)
    assert hbm_residual(y, plain, R2, J2) == NOT_A_COULOMB_PROBLEM
