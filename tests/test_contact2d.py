"""The 2D contact element (Jenkins friction under a unilateral normal contact).

References, none produced by the element itself: the Jenkins AFT of the
package (constant normal load), closed forms (stuck, open, the clipped
cosine of the normal force), central finite differences of the AFT, a
plain-NumPy march written here in the force form (marched over many
periods), and a 2-DOF oscillator integrated in time here, against a harmonic
balance solved with ``scipy.optimize.root`` on the element's AFT.
"""

import numba
import numpy as np
import pytest
from scipy.optimize import root

import hbmfric as hf
from hbmfric.errors import ConvergenceError
from hbmfric.kernels.aft import contact2d as k2
from hbmfric.kernels.aft.schemes import aft_samples
from hbmfric.kernels.fourier.dft import fourier_matrices
from hbmfric.kernels.laws.updates import JENKINS

KT = 3e4
KN = 1e5
MU = 0.4
N0 = 50.0
ELEMENT = hf.Contact2D(
    tangential_stiffness=KT, normal_stiffness=KN, friction_coefficient=MU, preload=N0
)


def _coefs(harmonics, rng, scale_u, scale_v, mean_v=0.0):
    """Random (2, n_coef) displacement coefficients decaying with the order."""
    rows = []
    for scale, mean in ((scale_u, 0.0), (scale_v, mean_v)):
        row = []
        for k in harmonics:
            if k == 0:
                row.append(mean + 0.1 * scale * rng.normal())
            else:
                row.extend(scale * rng.normal(size=2) / k)
        rows.append(row)
    return np.array(rows)


# ----------------------------------------------------------------------------
# constant normal load: the element is the package's Jenkins law
# ----------------------------------------------------------------------------


@pytest.mark.parametrize("harmonics", [list(range(8)), [1, 3, 5, 7]])
@pytest.mark.parametrize("amplitude", [2e-4, 8e-4, 3e-3, 2e-2])
@pytest.mark.parametrize("offset", [0.0, 5e-4])
def test_constant_load_is_jenkins(harmonics, amplitude, offset):
    """v = 0, a stiff normal spring: the tangential force and its Jacobian
    are those of the Jenkins AFT with f_s = μ N0, stuck (also with a shifted
    slider) and in gross slip; the normal force is the preload."""
    element = hf.Contact2D(
        tangential_stiffness=KT,
        normal_stiffness=1e9,
        friction_coefficient=MU,
        preload=N0,
    )
    h = np.array(harmonics)
    rng = np.random.default_rng(int(1e6 * amplitude) + len(h))
    X = _coefs(h, rng, amplitude, 0.0)
    X[1] = 0.0
    if h[0] == 0:
        X[0, 0] = offset
    n_time = 64
    out = element.harmonic_forces(X, h, n_time)
    inverse, forward, _ = fourier_matrices(h, n_time)
    nc = inverse.shape[1]
    F = np.empty(nc)
    dF = np.empty((nc, nc))
    jenkins = element.tangential_law()
    state = aft_samples(
        np.int64(JENKINS), jenkins.params, X[0], inverse, forward, F, dF
    )
    assert state == out.state  # the STUCK/GROSS_SLIP codes are shared
    scale = KT * np.abs(X[0]).sum() + MU * N0
    np.testing.assert_allclose(out.force[0], F, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(out.jacobian[:nc, :nc], dF, rtol=0, atol=1e-11 * KT)
    normal = np.zeros(nc)
    if h[0] == 0:
        normal[0] = N0
    np.testing.assert_allclose(out.force[1], normal, rtol=0, atol=1e-12 * N0)
    np.testing.assert_allclose(out.jacobian[nc:, :nc], 0.0, atol=0)
    np.testing.assert_allclose(
        out.jacobian[nc:, nc:], 1e9 * np.eye(nc), rtol=0, atol=1e-12 * 1e9
    )
    # the time history too, against the Jenkins loop of the package
    u = inverse @ X[0]
    t, n = element.periodic_forces(u, np.zeros_like(u))
    np.testing.assert_allclose(t, jenkins.hysteresis(u), rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(n, N0, rtol=1e-15)


# ----------------------------------------------------------------------------
# closed forms
# ----------------------------------------------------------------------------


def test_fully_stuck_is_linear():
    """μ N(t) above kt |u(t)| throughout: T = kt u, N = N0 + kn v exactly."""
    h = np.arange(6)
    rng = np.random.default_rng(3)
    X = _coefs(h, rng, 1e-4, 1e-4)  # kt |u| < 10 N, kn |v| < 25 N
    out = ELEMENT.harmonic_forces(X, h, 48)
    assert out.state == k2.STUCK
    nc = X.shape[1]
    expected = np.vstack([KT * X[0], KN * X[1]])
    expected[1, 0] += N0
    np.testing.assert_allclose(out.force, expected, rtol=0, atol=1e-12 * N0)
    J = np.zeros((2 * nc, 2 * nc))
    J[:nc, :nc] = KT * np.eye(nc)
    J[nc:, nc:] = KN * np.eye(nc)
    np.testing.assert_allclose(out.jacobian, J, rtol=0, atol=1e-10 * KN)


@pytest.mark.parametrize("preload", [N0, -20.0])
def test_fully_open_is_zero(preload):
    """N0 + kn v < 0 throughout (also with an initial gap): no force."""
    element = ELEMENT.with_preload(preload)
    h = np.arange(5)
    X = _coefs(h, np.random.default_rng(4), 1e-3, 1e-4, mean_v=-2e-3)
    out = element.harmonic_forces(X, h, 40)
    assert out.state == k2.OPEN
    assert not np.any(out.force) and not np.any(out.jacobian)
    t, n = element.periodic_forces(np.linspace(0, 1, 16), np.full(16, -1e-3))
    assert not np.any(t) and not np.any(n)


def _clipped_cosine(n0, kn, a, k):
    """Fourier coefficients (mean, cos k) of max(0, n0 + kn a cos θ)."""
    c = n0 / (kn * a)
    th = np.arccos(-c)
    if k == 0:
        return kn * a / np.pi * (np.sin(th) + c * th)
    if k == 1:
        prod = th / 2 + np.sin(2 * th) / 4
    else:
        prod = 0.5 * (np.sin((k - 1) * th) / (k - 1) + np.sin((k + 1) * th) / (k + 1))
    return 2 * kn * a / np.pi * (prod + c * np.sin(k * th) / k)


@pytest.mark.parametrize("ratio", [0.3, -0.4, 0.95])
def test_normal_force_alone_is_a_clipped_cosine(ratio):
    """u = 0, v = a cos θ with separation: the normal force is the clipped
    cosine (closed form), the tangential force 0; trapezoidal error below
    kn a h² (h the sample interval)."""
    a = N0 / (KN * ratio) if ratio > 0 else 2 * N0 / KN
    element = ELEMENT if ratio > 0 else ELEMENT.with_preload(ratio * KN * a)
    n0 = element.preload
    h = np.arange(10)
    n_time = 2048
    X = np.zeros((2, 19))
    X[1, 1] = a
    out = element.harmonic_forces(X, h, n_time)
    assert out.state == k2.SEPARATES
    assert not np.any(out.force[0])
    expected = np.zeros(19)
    expected[0] = _clipped_cosine(n0, KN, a, 0)
    for k in range(1, 10):
        expected[2 * k - 1] = _clipped_cosine(n0, KN, a, k)
    bound = KN * a * (2 * np.pi / n_time) ** 2
    np.testing.assert_allclose(out.force[1], expected, rtol=0, atol=bound)
    # not the unclipped spring
    assert abs(out.force[1][0] - n0) > 100 * bound


# ----------------------------------------------------------------------------
# Jacobian against central finite differences
# ----------------------------------------------------------------------------

#: (u scale, v scale, v mean, expected state)
STATES = {
    "stuck": (1e-5, 1e-5, 0.0, k2.STUCK),
    "slip": (3e-3, 1e-4, 0.0, k2.GROSS_SLIP),
    "separation": (3e-3, 1e-3, 0.0, k2.SEPARATES),
    "separation-mostly-open": (2e-3, 1e-3, -1e-3, k2.SEPARATES),
    "microslip-under-varying-load": (6e-4, 3e-4, 0.0, None),
}


@pytest.mark.parametrize("name", list(STATES))
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_jacobian_against_finite_differences(name, seed):
    su, sv, mv, state = STATES[name]
    h = np.arange(6)
    rng = np.random.default_rng(100 * seed + len(name))
    X = _coefs(h, rng, su, sv, mean_v=mv)
    n_time = 96
    out = ELEMENT.harmonic_forces(X, h, n_time)
    if state is not None:
        assert out.state == state, k2.STATE_NAMES[out.state]
    nc = X.shape[1]
    J = np.empty((2 * nc, 2 * nc))
    flat = X.ravel()
    for col in range(2 * nc):
        step = 1e-7 * (su if col < nc else sv)
        plus = flat.copy()
        minus = flat.copy()
        plus[col] += step
        minus[col] -= step
        fp = ELEMENT.harmonic_forces(plus.reshape(2, nc), h, n_time).force.ravel()
        fm = ELEMENT.harmonic_forces(minus.reshape(2, nc), h, n_time).force.ravel()
        J[:, col] = (fp - fm) / (2 * step)
    scale = np.abs(out.jacobian).max()
    np.testing.assert_allclose(out.jacobian, J, rtol=0, atol=1e-6 * scale)


# ----------------------------------------------------------------------------
# plain-NumPy march (force form, many periods)
# ----------------------------------------------------------------------------


def _naive_march(kt, kn, mu, n0, u, v, periods=6):
    """Force-form march from the virgin contact (closed at u = 0, no force),
    ``periods`` periods; a re-closure restarts the force from 0 at the
    crossing of n0 + kn v (linear interpolation). Returns the last period."""
    n = len(u)
    t_prev, u_prev, open_prev, nn_prev = 0.0, 0.0, False, n0
    for _ in range(periods):
        t_out = np.zeros(n)
        n_out = np.zeros(n)
        for i in range(n):
            nn = n0 + kn * v[i]
            if nn <= 0.0:
                t_prev, u_prev, open_prev, nn_prev = 0.0, u[i], True, nn
                continue
            if open_prev:
                frac = nn_prev / (nn_prev - nn)
                u_prev = u_prev + frac * (u[i] - u_prev)
                t_prev = 0.0
            trial = t_prev + kt * (u[i] - u_prev)
            t_out[i] = min(max(trial, -mu * nn), mu * nn)
            n_out[i] = nn
            t_prev, u_prev, open_prev, nn_prev = t_out[i], u[i], False, nn
    return t_out, n_out


@pytest.mark.parametrize("seed", range(6))
def test_march_against_plain_numpy(seed):
    rng = np.random.default_rng(seed)
    h = np.arange(8)
    X = _coefs(h, rng, 2e-3, 8e-4, mean_v=rng.uniform(-5e-4, 2e-4))
    inverse, _, _ = fourier_matrices(h, 200)
    u, v = inverse @ X[0], inverse @ X[1]
    t, n = ELEMENT.periodic_forces(u, v)
    t_ref, n_ref = _naive_march(KT, KN, MU, N0, u, v)
    assert np.any(n_ref == 0) or seed > 3  # most seeds separate
    scale = KT * np.abs(u).max() + MU * np.abs(n_ref).max()
    np.testing.assert_allclose(t, t_ref, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(n, n_ref, rtol=0, atol=1e-12 * np.abs(n_ref).max())


# ----------------------------------------------------------------------------
# input checks, status codes, compiled once
# ----------------------------------------------------------------------------


def test_bad_input():
    good = dict(
        tangential_stiffness=1.0,
        normal_stiffness=1.0,
        friction_coefficient=0.1,
        preload=1.0,
    )
    for name, value in [
        ("tangential_stiffness", 0.0),
        ("normal_stiffness", -1.0),
        ("friction_coefficient", -0.1),
        ("preload", np.nan),
    ]:
        with pytest.raises(ValueError, match=name):
            hf.Contact2D(**{**good, name: value})
    with pytest.raises(TypeError, match="preload"):
        hf.Contact2D(**{**good, "preload": "1"})
    element = hf.Contact2D(**good)
    with pytest.raises(ValueError, match="shape"):
        element.harmonic_forces(np.zeros((2, 4)), [0, 1], 8)
    with pytest.raises(ValueError, match="n_time"):
        element.harmonic_forces(np.zeros((2, 3)), [0, 1], 2)
    with pytest.raises(ValueError, match="harmonics"):
        element.harmonic_forces(np.zeros((2, 3)), [1, 0], 8)
    with pytest.raises(ValueError, match="same shape"):
        element.periodic_forces(np.zeros(4), np.zeros(5))
    with pytest.raises(ValueError, match="open"):
        element.with_preload(-1.0).tangential_law()


def test_pass_budget_status():
    """Two passes always reach the periodic state; a budget of one pass
    cannot confirm it and says so."""
    h = np.arange(4).astype(np.int64)
    inverse, forward, _ = fourier_matrices(h, 32)
    X = _coefs(h, np.random.default_rng(7), 3e-3, 1e-3)
    F = np.empty((2, 7))
    dF = np.empty((14, 14))
    assert k2.aft_contact2d(ELEMENT.params, X, inverse, forward, F, dF, 1) == (
        k2.NOT_PERIODIC
    )
    assert k2.aft_contact2d(ELEMENT.params, X, inverse, forward, F, dF, 2) > 0
    # and in every regime, over many random motions (the period map of the
    # slider is a clamp, so it is idempotent)
    rng = np.random.default_rng(8)
    seen = set()
    for _ in range(200):
        su, sv, mv, _state = STATES[rng.choice(list(STATES))]
        X = _coefs(h, rng, su * rng.uniform(0.2, 5), sv * rng.uniform(0.2, 5), mv)
        state = k2.aft_contact2d(ELEMENT.params, X, inverse, forward, F, dF, 2)
        assert state > 0
        seen.add(state)
    assert seen == {k2.STUCK, k2.GROSS_SLIP, k2.SEPARATES, k2.OPEN}


def test_failed_march_raises(monkeypatch):
    """The Python edge turns a failure code into ConvergenceError."""
    import hbmfric.laws.contact2d as law_module

    monkeypatch.setattr(law_module, "MAX_PASSES", 1)
    h = np.arange(4)
    X = _coefs(h, np.random.default_rng(7), 3e-3, 1e-3)
    with pytest.raises(ConvergenceError, match="pass budget"):
        ELEMENT.harmonic_forces(X, h, 32)


def test_compiled_once():
    """Different parameter values and harmonic sets reuse one compilation.

    The HBM residual compiles the element's kernels as its callees when it
    does not come from the cache (other array layouts of its arguments), so
    the counts are compared after the first call and after the sweep rather
    than against 1."""
    kernels = (k2.aft_contact2d, k2.contact2d_march, k2.contact2d_step)
    counts = None
    for kt, preload, h in [
        (1e3, 1.0, [0, 1]),
        (2e5, -3.0, [0, 1, 2, 3]),
        (7.0, 0.0, [1, 3]),
        (3e4, 20.0, [0, 1, 2]),
    ]:
        element = hf.Contact2D(
            tangential_stiffness=kt,
            normal_stiffness=5e3,
            friction_coefficient=0.2,
            preload=preload,
        )
        nc = 2 * len(h) - (1 if h[0] == 0 else 0)
        element.harmonic_forces(np.full((2, nc), 1e-3), h, 16)
        element.periodic_forces(np.linspace(-1, 1, 9), np.linspace(0, 1e-3, 9))
        now = [len(k.signatures) for k in kernels]
        if counts is None:
            counts = now
            assert 1 <= counts[0] <= 2 and 1 <= counts[1] <= 2, counts
        assert now == counts, [k.signatures for k in kernels]


# ----------------------------------------------------------------------------
# time-domain reference: 2-DOF oscillator with the element
# ----------------------------------------------------------------------------

#: tangential DOF x and normal DOF y (positive closing), each a mass on a
#: spring and a damper, coupled only by the element; loads
#: Fx cos Ωt on x and P0 + Py cos Ωt on y with P0 = N0 (rest at y = 0)
OSC = dict(m=1.0, k=1e4, c=6.0, my=1.0, ky=1e4, cy=6.0, fx=4.0, py=12.0)
OSC_ELEMENT = hf.Contact2D(
    tangential_stiffness=3e4,
    normal_stiffness=2e4,
    friction_coefficient=0.5,
    preload=10.0,
)


@numba.njit(cache=False)
def _integrate(p, osc, omega, steps, n_periods):
    """Velocity Verlet (damping implicit in the velocity update) with the
    element updated at every step in force form, re-closure located by
    linear interpolation. Returns x, y over the last two periods."""
    kt, kn, mu, n0 = p[0], p[1], p[2], p[3]
    m, k, c, my, ky, cy, fx, py = osc
    dt = 2 * np.pi / omega / steps
    x = 0.0
    y = 0.0
    vx = 0.0
    vy = 0.0
    t_c = 0.0  # tangential force
    n_c = n0  # normal force
    x_prev = 0.0
    nn_prev = n0
    open_prev = False
    ax = (fx - k * x - t_c) / m
    ay = (n0 + py - ky * y - n_c) / my
    out = np.empty((2, 2 * steps))
    total = steps * n_periods
    for s in range(total):
        time = (s + 1) * dt
        vxh = vx + 0.5 * dt * ax
        vyh = vy + 0.5 * dt * ay
        x += dt * vxh
        y += dt * vyh
        nn = n0 + kn * y
        if nn <= 0.0:
            t_c = 0.0
            n_c = 0.0
            open_prev = True
            x_prev = x
        else:
            if open_prev:
                frac = nn_prev / (nn_prev - nn)
                x_prev = x_prev + frac * (x - x_prev)
                t_c = 0.0
            trial = t_c + kt * (x - x_prev)
            lim = mu * nn
            t_c = min(max(trial, -lim), lim)
            n_c = nn
            open_prev = False
            x_prev = x
        nn_prev = nn
        cs = np.cos(omega * time)
        vx = (vxh + 0.5 * dt * (fx * cs - k * x - t_c) / m) / (1 + 0.5 * dt * c / m)
        vy = (vyh + 0.5 * dt * (n0 + py * cs - ky * y - n_c) / my) / (
            1 + 0.5 * dt * cy / my
        )
        ax = (fx * cs - c * vx - k * x - t_c) / m
        ay = (n0 + py * cs - cy * vy - ky * y - n_c) / my
        j = s - (total - 2 * steps)
        if j >= 0:
            out[0, j] = x
            out[1, j] = y
    return out


def _hbm_solve(element, omega, H, n_time, guess):
    """Harmonic balance of the 2-DOF oscillator with the element's AFT,
    solved by scipy.optimize.root (the element's Jacobian)."""
    o = OSC
    h = np.arange(H + 1)
    nc = 2 * H + 1
    inverse, forward, _ = fourier_matrices(h, n_time)
    params = element.params

    def dyn(m, k, c):
        D = np.zeros((nc, nc))
        D[0, 0] = k
        for q in range(1, H + 1):
            w = q * omega
            i = 2 * q - 1
            D[i, i] = D[i + 1, i + 1] = k - m * w * w
            D[i, i + 1] = c * w
            D[i + 1, i] = -c * w
        return D

    D = np.zeros((2 * nc, 2 * nc))
    D[:nc, :nc] = dyn(o["m"], o["k"], o["c"])
    D[nc:, nc:] = dyn(o["my"], o["ky"], o["cy"])
    load = np.zeros(2 * nc)
    load[1] = o["fx"]
    load[nc] = element.preload
    load[nc + 1] = o["py"]
    F = np.empty((2, nc))
    dF = np.empty((2 * nc, 2 * nc))

    def fun(z):
        state = k2.aft_contact2d(params, z.reshape(2, nc), inverse, forward, F, dF, 4)
        assert state > 0
        return D @ z + F.ravel() - load, D + dF

    sol = root(fun, guess, jac=True, method="hybr", options={"xtol": 1e-13})
    res = np.abs(fun(sol.x)[0]).max()
    assert res < 1e-9 * max(o["fx"], o["py"]), (omega, sol.message, res)
    return sol.x


def _first_harmonic(samples):
    n = samples.size
    theta = 2 * np.pi * np.arange(1, n + 1) / n  # samples at the end of steps
    return 2 / n * np.array([samples @ np.cos(theta), samples @ np.sin(theta)])


def test_hbm_against_time_integration_with_separation():
    """Ten frequencies through the stuck, slipping and separating regimes
    (the normal DOF is a unilateral spring oscillator, which the friction
    does not feed back into; the tangential one carries the friction under
    the varying load): first-harmonic amplitudes of both DOFs within 1e-3
    (relative) of the time integration (measured: <= 6e-5, largest at the
    peak near 130 rad/s). The solver steps over 129-135 rad/s, where root()
    from the previous solution stalls at the resonance peak."""
    H = 24
    nc = 2 * H + 1
    n_time = 1024
    steps = 8192
    omegas = [50.0, 70.0, 90.0, 110.0, 120.0, 126.0, 141.0, 150.0, 170.0, 220.0]
    guess = np.zeros(2 * nc)
    p = OSC_ELEMENT.params
    osc = np.array([OSC[k] for k in ("m", "k", "c", "my", "ky", "cy", "fx", "py")])
    inverse, _, _ = fourier_matrices(np.arange(H + 1), n_time)
    separated = 0
    for omega in omegas:
        z = _hbm_solve(OSC_ELEMENT, omega, H, n_time, guess)
        guess = z
        n_periods = int(np.ceil(15.0 * omega / (2 * np.pi)))
        rec = _integrate(p, osc, omega, steps, n_periods)
        # steady state reached: the last two periods agree
        drift = np.abs(rec[:, steps:] - rec[:, :steps]).max()
        assert drift < 1e-9 * np.abs(rec).max(), (omega, drift)
        X = z.reshape(2, nc)
        separated += np.any(OSC_ELEMENT.preload + 2e4 * (inverse @ X[1]) <= 0)
        for dof in range(2):
            ref = _first_harmonic(rec[dof, steps:])
            amp_ref = np.hypot(*ref)
            amp = np.hypot(X[dof, 1], X[dof, 2])
            assert abs(amp - amp_ref) <= 1e-3 * amp_ref, (omega, dof, amp, amp_ref)
    assert separated >= 8


@pytest.mark.parametrize("seed", range(4))
def test_second_order_in_n_time(seed):
    """With separation and re-closure the sampled AFT converges at second
    order in the sample interval (the located re-closure; without it the
    slider is off by O(h) and so is the force): fitted slope of the force
    error against n_time (64 … 2048; reference n_time = 2^17) below -1.6."""
    h = np.arange(6)
    X = _coefs(h, np.random.default_rng(seed), 2e-3, 8e-4, mean_v=-1e-4)
    ref = ELEMENT.harmonic_forces(X, h, 2**17)
    assert ref.state == k2.SEPARATES
    ns = np.array([64, 128, 256, 512, 1024, 2048])
    errs = [
        np.abs(ELEMENT.harmonic_forces(X, h, n).force - ref.force).max() for n in ns
    ]
    slope = np.polyfit(np.log(ns), np.log(errs), 1)[0]
    assert slope < -1.6, (slope, errs)


def test_a_single_dof_oscillator_refuses_the_element():
    """The oscillator has one DOF: the element needs two (tangential and
    normal), so it is refused there instead of run wrongly."""
    with pytest.raises(ValueError, match="Contact2D"):
        hf.Oscillator(1.0, 4.0, 1e4, contact=ELEMENT)


class _TwoDofRig:
    """The 2-DOF oscillator of the time-domain reference as a system of the
    protocol (a user's own object): x tangential, y normal, the element
    between them and ground, the static load P0 = N0 on y."""

    n_dof = 2
    symmetric = False

    def __init__(self, element):
        self.contacts = [hf.Contact(element, 0, normal=1)]
        self.contact = element
        self.contact_dof = 0

    def matrices(self):
        o = OSC
        return (
            np.diag([o["m"], o["my"]]),
            np.diag([o["c"], o["cy"]]),
            np.diag([o["k"], o["ky"]]),
        )

    def load_vector(self, force):
        return force * np.array([OSC["fx"], OSC["py"]])

    def static_load(self):
        return np.array([0.0, self.contact.preload])


def test_hf_periodic_solution_against_time_integration():
    """The element in the engine (``hf.periodic_solution`` on a system that
    lists it in ``contacts``) against the time integration of this module at
    frequencies where the contact sticks, slips and separates: first-harmonic
    amplitudes of both DOFs within 1e-3."""
    rig = _TwoDofRig(OSC_ELEMENT)
    p = OSC_ELEMENT.params
    osc = np.array([OSC[k] for k in ("m", "k", "c", "my", "ky", "cy", "fx", "py")])
    steps = 8192
    for omega in (50.0, 110.0, 150.0, 220.0):
        sol = hf.periodic_solution(rig, 1.0, omega, harmonics=24, n_time=1024)
        assert sol.converged, omega
        n_periods = int(np.ceil(15.0 * omega / (2 * np.pi)))
        rec = _integrate(p, osc, omega, steps, n_periods)
        for dof in range(2):
            amp_ref = np.hypot(*_first_harmonic(rec[dof, steps:]))
            amp = sol.amplitude(harmonic=1, dof=dof)
            assert abs(amp - amp_ref) <= 1e-3 * amp_ref, (omega, dof, amp, amp_ref)


def test_hf_frf_through_separation_against_time_integration():
    """A whole branch over 40-250 rad/s (through the normal resonance, where
    the contact separates) by ``hf.frf``: complete, and its curve at six
    frequencies within 2e-3 of the time integration."""
    rig = _TwoDofRig(OSC_ELEMENT)
    branch = hf.frf(rig, 1.0, (40.0, 250.0), harmonics=24)
    assert branch.complete, branch.stop_reason
    p = OSC_ELEMENT.params
    osc = np.array([OSC[k] for k in ("m", "k", "c", "my", "ky", "cy", "fx", "py")])
    steps = 8192
    for omega in (60.0, 100.0, 126.0, 141.0, 180.0, 240.0):
        n_periods = int(np.ceil(15.0 * omega / (2 * np.pi)))
        rec = _integrate(p, osc, omega, steps, n_periods)
        for dof in range(2):
            amp_ref = np.hypot(*_first_harmonic(rec[dof, steps:]))
            # all the values where the branch passes (past a fold, several):
            # the integration lands on one of them
            amps = np.ravel(branch.amplitude_at(omega, dof=dof, harmonic=1))
            err = np.min(np.abs(amps - amp_ref)) / amp_ref
            assert err <= 2e-3, (omega, dof, amps, amp_ref)


def test_linear_structure_with_the_element_and_a_static_load():
    """The same rig as a LinearStructure (``contacts`` with a normal DOF,
    ``static_load`` for the preload) gives the solution of the protocol
    object checked against time integration above."""
    o = OSC
    structure = hf.LinearStructure(
        np.diag([o["m"], o["my"]]),
        np.diag([o["k"], o["ky"]]),
        np.diag([o["c"], o["cy"]]),
        load={"x": o["fx"], "y": o["py"]},
        static_load={"y": OSC_ELEMENT.preload},
        contacts=[hf.Contact(OSC_ELEMENT, "x", normal="y")],
        dof_names={"x": 0, "y": 1},
    )
    assert not structure.symmetric
    a = hf.periodic_solution(_TwoDofRig(OSC_ELEMENT), 1.0, 110.0, harmonics=24)
    b = hf.periodic_solution(structure, 1.0, 110.0, harmonics=24)
    for dof in (0, 1):
        assert b.amplitude(harmonic=1, dof=dof) == pytest.approx(
            a.amplitude(harmonic=1, dof=dof), rel=1e-9
        )
    with pytest.raises(ValueError, match="normal DOF"):
        hf.Contact(OSC_ELEMENT, 0)
    with pytest.raises(ValueError, match="Contact2D only"):
        hf.Contact(hf.Jenkins(1.0, 1.0), 0, normal=1)
    with pytest.raises(ValueError, match="static_load must be real"):
        hf.LinearStructure(np.eye(2), np.eye(2), static_load=[1j, 0.0])
