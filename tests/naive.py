"""Plain-NumPy references for the kernels (STYLE point 9).

Nothing here imports Numba or ``hbmfric``: every function is written from the
definitions in SPEC §3–§4, the slow and obvious way, so that the kernels can be
compared with something they did not produce.

Coefficient layout (as in the package): for the harmonic numbers ``harmonics``
(for example ``[0, 1, …, H]`` or ``[1, 3, …, H]``), ``X = [X0, Xc1, Xs1, …]``
with ``X0`` only when 0 is among them, and
``x(θ) = X0 + Σ_k (Xc_k cos kθ + Xs_k sin kθ)``. One period is sampled at
``θ_i = 2π i / n``, ``i = 0 … n - 1``.
"""

from __future__ import annotations

import numpy as np

# ----------------------------------------------------------------------------
# Real DFT
# ----------------------------------------------------------------------------


def n_coefficients(harmonics) -> int:
    """Length of the real coefficient vector.

    Parameters
    ----------
    harmonics : sequence of int, shape (n_harmonics,)
        Harmonic numbers, 0 for the mean.

    Returns
    -------
    int
        ``1`` per zero harmonic plus ``2`` per other harmonic.
    """
    return sum(1 if int(k) == 0 else 2 for k in harmonics)


def sample_angles(n: int) -> np.ndarray:
    """Equidistant angles of one period.

    Parameters
    ----------
    n : int
        Samples per period.

    Returns
    -------
    ndarray, shape (n,)
        ``θ_i = 2π i / n``, rad.
    """
    return 2.0 * np.pi * np.arange(n) / n


def synthesize(harmonics, X, theta) -> np.ndarray:
    """Evaluate a trigonometric polynomial by explicit sums.

    Parameters
    ----------
    harmonics : sequence of int, shape (n_harmonics,)
        Harmonic numbers.
    X : ndarray, shape (n_coef,)
        Coefficients ``[X0, Xc1, Xs1, …]``.
    theta : ndarray, shape (n_theta,)
        Angles, rad.

    Returns
    -------
    ndarray, shape (n_theta,)
        ``x(θ)``.
    """
    theta = np.asarray(theta, dtype=float)
    x = np.zeros_like(theta)
    col = 0
    for k in harmonics:
        k = int(k)
        if k == 0:
            x = x + X[col]
            col += 1
        else:
            x = x + X[col] * np.cos(k * theta) + X[col + 1] * np.sin(k * theta)
            col += 2
    return x


def synthesize_derivative(harmonics, X, theta) -> np.ndarray:
    """``dx/dθ`` of a trigonometric polynomial, by explicit sums.

    Parameters
    ----------
    harmonics : sequence of int, shape (n_harmonics,)
        Harmonic numbers.
    X : ndarray, shape (n_coef,)
        Coefficients.
    theta : ndarray, shape (n_theta,)
        Angles, rad.

    Returns
    -------
    ndarray, shape (n_theta,)
        ``x'(θ)``.
    """
    theta = np.asarray(theta, dtype=float)
    dx = np.zeros_like(theta)
    col = 0
    for k in harmonics:
        k = int(k)
        if k == 0:
            col += 1
        else:
            dx = dx + k * (-X[col] * np.sin(k * theta) + X[col + 1] * np.cos(k * theta))
            col += 2
    return dx


def synthesis_matrix(harmonics, n: int) -> np.ndarray:
    """Inverse real DFT matrix by explicit evaluation of the basis.

    Parameters
    ----------
    harmonics : sequence of int, shape (n_harmonics,)
        Harmonic numbers.
    n : int
        Samples per period.

    Returns
    -------
    ndarray, shape (n, n_coef)
        Column ``j`` holds basis function ``j`` at the ``n`` sample angles.
    """
    m = n_coefficients(harmonics)
    theta = sample_angles(n)
    E = np.empty((n, m))
    for j in range(m):
        e = np.zeros(m)
        e[j] = 1.0
        E[:, j] = synthesize(harmonics, e, theta)
    return E


def analyse(harmonics, f) -> np.ndarray:
    """Fourier coefficients of one sampled period, with ``np.fft.rfft``.

    Parameters
    ----------
    harmonics : sequence of int, shape (n_harmonics,)
        Harmonic numbers to extract, all ``< n / 2``.
    f : ndarray, shape (n,)
        Samples of one period at ``θ_i = 2π i / n``.

    Returns
    -------
    ndarray, shape (n_coef,)
        ``[F0, Fc1, Fs1, …]``: ``F0 = mean``, ``Fc_k = 2 Re(c_k) / n``,
        ``Fs_k = -2 Im(c_k) / n`` with ``c = rfft(f)``.
    """
    f = np.asarray(f, dtype=float)
    n = f.size
    c = np.fft.rfft(f)
    out = []
    for k in harmonics:
        k = int(k)
        if k == 0:
            out.append(c[0].real / n)
        else:
            out.append(2.0 * c[k].real / n)
            out.append(-2.0 * c[k].imag / n)
    return np.array(out)


# ----------------------------------------------------------------------------
# Contact laws
# ----------------------------------------------------------------------------


def jenkins_update(f_prev, u_prev, u, kt, fs):
    """One Jenkins step: elastic predictor, then the Coulomb limit.

    Parameters
    ----------
    f_prev : float
        Force at ``u_prev``, N.
    u_prev, u : float
        Displacements before and after the step, m.
    kt : float
        Tangential stiffness, N/m.
    fs : float
        Slip force, N.

    Returns
    -------
    float
        Force at ``u``, N.
    """
    trial = f_prev + kt * (u - u_prev)
    if trial > fs:
        return fs
    if trial < -fs:
        return -fs
    return trial


def jenkins_march(u, kt, fs, u_ref=0.0, max_periods=200, rtol=1e-13):
    """Steady-state Jenkins force over one sampled period, the naive way.

    The contact closes at rest at ``u_ref`` (slider at ``u_ref``, zero force),
    then the sampled period is repeated until the force at the period start
    repeats (to ``rtol`` times the force scale: a stuck element accumulates
    rounding); the last period is returned.

    Parameters
    ----------
    u : ndarray, shape (n,)
        Displacement samples of one period, m.
    kt : float
        Tangential stiffness, N/m.
    fs : float
        Slip force, N.
    u_ref : float, optional
        Position where the contact closed, m.
    max_periods : int, optional
        Give up (``RuntimeError``) after this many periods.
    rtol : float, optional
        Loop-closure tolerance relative to ``max(fs, kt max|u - u_ref|)``.

    Returns
    -------
    loop : ndarray, shape (n,)
        Force samples of the last period, N.
    n_periods : int
        Periods marched.
    """
    u = np.asarray(u, dtype=float)
    f = 0.0
    u_prev = u_ref
    loop = np.empty_like(u)
    start = None
    tol = rtol * max(fs, kt * np.max(np.abs(u - u_ref)))
    for period in range(1, max_periods + 1):
        for i in range(u.size):
            f = jenkins_update(f, u_prev, u[i], kt, fs)
            u_prev = u[i]
            loop[i] = f
        if start is not None and abs(loop[0] - start) <= tol:
            return loop, period
        start = loop[0]
    raise RuntimeError("the Jenkins loop did not close")


def jenkins_loop_cos(theta, a, kt, fs):
    """Exact steady-state Jenkins force under ``u = a cos θ``, ``a > fs/kt``.

    On ``[0, π]`` the displacement falls from ``a``: the element unloads
    elastically from ``+fs`` until it saturates at ``-fs``; the second half
    period is the mirror image ``f(θ + π) = -f(θ)``.

    Parameters
    ----------
    theta : ndarray, shape (n_theta,)
        Angles, rad.
    a : float
        Amplitude, m.
    kt, fs : float
        Tangential stiffness (N/m) and slip force (N).

    Returns
    -------
    ndarray, shape (n_theta,)
        Force, N.
    """
    theta = np.mod(np.asarray(theta, dtype=float), 2.0 * np.pi)
    first = theta < np.pi
    t = np.where(first, theta, theta - np.pi)
    half = np.maximum(fs - kt * a * (1.0 - np.cos(t)), -fs)
    return np.where(first, half, -half)


def jenkins_coefficients_cos(harmonics, a, kt, fs, n_gauss=80):
    """Fourier coefficients of :func:`jenkins_loop_cos` by quadrature.

    Gauss–Legendre quadrature on each of the four smooth pieces of the loop
    (stick and slip on both half periods), so the result is exact to rounding
    for moderate harmonic numbers. A stuck contact (``kt a <= fs``) gives
    ``kt a cos θ``.

    Parameters
    ----------
    harmonics : sequence of int, shape (n_harmonics,)
        Harmonic numbers.
    a : float
        Amplitude, m.
    kt, fs : float
        Tangential stiffness (N/m) and slip force (N).
    n_gauss : int, optional
        Nodes per piece.

    Returns
    -------
    ndarray, shape (n_coef,)
        Force coefficients, N.
    """
    out = np.zeros(n_coefficients(harmonics))
    if kt * a <= fs:
        col = 0
        for k in harmonics:
            if int(k) == 1:
                out[col] = kt * a
            col += 1 if int(k) == 0 else 2
        return out
    beta = np.arccos(1.0 - 2.0 * fs / (kt * a))
    edges = [0.0, beta, np.pi, np.pi + beta, 2.0 * np.pi]
    nodes, weights = np.polynomial.legendre.leggauss(n_gauss)
    theta = []
    w = []
    for lo, hi in zip(edges[:-1], edges[1:], strict=True):
        theta.append(0.5 * (hi - lo) * nodes + 0.5 * (hi + lo))
        w.append(0.5 * (hi - lo) * weights)
    theta = np.concatenate(theta)
    w = np.concatenate(w)
    f = jenkins_loop_cos(theta, a, kt, fs)
    col = 0
    for k in harmonics:
        k = int(k)
        if k == 0:
            out[col] = np.sum(w * f) / (2.0 * np.pi)
            col += 1
        else:
            out[col] = np.sum(w * f * np.cos(k * theta)) / np.pi
            out[col + 1] = np.sum(w * f * np.sin(k * theta)) / np.pi
            col += 2
    return out


def jenkins_first_harmonic(a, kt, fs):
    """Describing function of a Jenkins element, closed form of SPEC §4.

    Parameters
    ----------
    a : float
        Amplitude of ``u = a cos θ``, m.
    kt, fs : float
        Tangential stiffness (N/m) and slip force (N).

    Returns
    -------
    C1, S1 : float
        ``f ≈ C1 cos θ + S1 sin θ``, N; ``S1 = -(kt a / π) sin² β*`` with
        ``β* = arccos(1 - 2 fs / (kt a))``.
    """
    if a * kt <= fs:
        return kt * a, 0.0
    beta = np.arccos(1.0 - 2.0 * fs / (kt * a))
    c1 = kt * a * (beta - 0.5 * np.sin(2.0 * beta)) / np.pi
    s1 = -kt * a * np.sin(beta) ** 2 / np.pi
    return c1, s1


def jenkins_energy(a, kt, fs):
    """Energy dissipated per cycle under ``u = a cos θ`` (SPEC §4).

    Parameters
    ----------
    a : float
        Amplitude, m.
    kt, fs : float
        Tangential stiffness (N/m) and slip force (N).

    Returns
    -------
    float
        ``4 fs (a - fs/kt)`` in gross slip, 0 when stuck, J.
    """
    return max(0.0, 4.0 * fs * (a - fs / kt))


def loop_work(u, f):
    """Work ``∮ f du`` around a closed sampled loop (trapezoidal rule).

    Parameters
    ----------
    u, f : ndarray, shape (n,)
        Displacement (m) and force (N) samples of one period.

    Returns
    -------
    float
        Work done on the contact over the period, J (positive for a
        dissipative loop).
    """
    u1 = np.roll(u, -1)
    f1 = np.roll(f, -1)
    return float(np.sum(0.5 * (f + f1) * (u1 - u)))


def menq_virgin(delta, axial_rigidity, length, shear_stiffness, friction_limit):
    """Menq virgin curve from SPEC §4 in the physical slip length ``l``,
    inverted by plain bisection (not the kernel's Newton iteration).

    Parameters
    ----------
    delta : float
        Displacement from the virgin state, m, >= 0.
    axial_rigidity, length, shear_stiffness, friction_limit : float
        ``EA`` (N), ``L`` (m), ``k_s`` (N/m²), ``q`` (N/m).

    Returns
    -------
    float
        ``F_load(δ)``, N.
    """
    ea, L, ks, q = axial_rigidity, length, shear_stiffness, friction_limit
    alpha = np.sqrt(ks / ea)
    d1 = q / ks
    if delta <= d1:
        return np.sqrt(ks * ea) * np.tanh(alpha * L) * delta
    if delta >= d1 + q * L * L / (2.0 * ea):
        return q * L

    def force(l):
        return q * l + q / alpha * np.tanh(alpha * (L - l))

    def disp(l):
        return d1 + (force(l) * l - 0.5 * q * l * l) / ea

    lo, hi = 0.0, L
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if disp(mid) < delta:
            lo = mid
        else:
            hi = mid
    return force(0.5 * (lo + hi))


def shear_lag_bar(path, axial_rigidity, length, shear_stiffness, friction_limit, n):
    """Quasi-static bar on a shear layer of ``n`` Jenkins elements, driven
    by its end displacement along ``path``: the discretised Menq model.

    Cells of length ``h = L/n``, a node at each cell centre carrying a
    Jenkins element (stiffness ``k_s h``, slip force ``q h``), axial springs
    ``EA/h`` between nodes and ``2 EA/h`` from the loaded end to the first
    node, free far end. Each increment of the end displacement is solved
    exactly: the Jenkins forces are ``clip(s_prev + k Δw, ±q h)`` and the
    stick/slip set is iterated (semismooth Newton on the tridiagonal
    system) until it repeats.

    Parameters
    ----------
    path : ndarray, shape (n_steps,)
        End displacements, m, starting from the virgin bar at 0.
    axial_rigidity, length, shear_stiffness, friction_limit : float
        ``EA`` (N), ``L`` (m), ``k_s`` (N/m²), ``q`` (N/m).
    n : int
        Number of elements.

    Returns
    -------
    ndarray, shape (n_steps,)
        End force at each path point, N.
    """
    from scipy.linalg import solve_banded

    h = length / n
    k = shear_stiffness * h
    fs = friction_limit * h
    ka = axial_rigidity / h
    diag = np.full(n, 2.0 * ka)
    diag[0] = 3.0 * ka
    diag[-1] = ka
    bands = np.zeros((3, n))
    bands[0, 1:] = -ka
    bands[2, :-1] = -ka

    def increment(w, s, delta):
        """Exact state after moving the end to ``delta``; None if the
        stick/slip set cycles (the caller then halves the increment)."""
        slip = np.zeros(n, dtype=bool)
        sign = np.zeros(n)
        for _ in range(60):
            stuck = ~slip
            bands[1] = diag + k * stuck
            rhs = -np.where(stuck, s - k * w, sign * fs)
            rhs[0] += 2.0 * ka * delta
            w_new = solve_banded((1, 1), bands, rhs)
            trial = s + k * (w_new - w)
            # hysteresis in the classification: a slipping node stays so
            # while its trial force is at the limit to rounding
            keep = slip & (sign * trial >= fs * (1.0 - 1e-10))
            new_slip = keep | (np.abs(trial) > fs)
            new_sign = np.where(keep, sign, np.sign(trial) * new_slip)
            if np.array_equal(new_slip, slip) and np.array_equal(new_sign, sign):
                return w_new, np.clip(trial, -fs, fs)
            slip, sign = new_slip, new_sign
        return None

    def advance(w, s, start, end, depth=0):
        result = increment(w, s, end)
        if result is not None:
            return result
        if depth > 40:
            raise RuntimeError("the stick/slip set did not settle")
        mid = 0.5 * (start + end)
        w, s = advance(w, s, start, mid, depth + 1)
        return advance(w, s, mid, end, depth + 1)

    w = np.zeros(n)
    s = np.zeros(n)
    out = np.empty(len(path))
    previous = 0.0
    for step, delta in enumerate(path):
        w, s = advance(w, s, previous, delta)
        previous = delta
        out[step] = 2.0 * ka * (delta - w[0])
    return out


def iwan_march(u, stiffnesses, slip_forces):
    """Steady-state Iwan force: the sum of independent Jenkins elements,
    each marched by :func:`jenkins_march` (closed at 0).

    Parameters
    ----------
    u : ndarray, shape (n,)
        Displacement samples of one period, m.
    stiffnesses, slip_forces : sequence of float, shape (n_elements,)
        ``k_e`` (N/m) and ``f_e`` (N).

    Returns
    -------
    ndarray, shape (n,)
        Force samples, N.
    """
    total = np.zeros(len(u))
    for k, f in zip(stiffnesses, slip_forces, strict=True):
        total += jenkins_march(u, k, f)[0]
    return total


def cubic_force(u, k3):
    """Cubic spring ``f = k3 u³``.

    Parameters
    ----------
    u : ndarray, shape (n,)
        Displacement, m.
    k3 : float
        Coefficient, N/m³.

    Returns
    -------
    ndarray, shape (n,)
        Force, N.
    """
    u = np.asarray(u, dtype=float)
    return k3 * u * u * u


def _to_complex(harmonics, X):
    """Two-sided complex coefficients ``c[h_max + m]`` of ``e^{i m θ}``."""
    h_max = int(max(harmonics))
    c = np.zeros(2 * h_max + 1, dtype=complex)
    col = 0
    for k in harmonics:
        k = int(k)
        if k == 0:
            c[h_max] += X[col]
            col += 1
        else:
            xc, xs = X[col], X[col + 1]
            c[h_max + k] += 0.5 * (xc - 1j * xs)
            c[h_max - k] += 0.5 * (xc + 1j * xs)
            col += 2
    return c


def cubic_coefficients(harmonics, X, k3):
    """Exact Fourier coefficients of ``k3 u(θ)³`` (no sampling).

    The cube of the trigonometric polynomial is formed by convolving its
    two-sided complex coefficients; the harmonics asked for are read off.

    Parameters
    ----------
    harmonics : sequence of int, shape (n_harmonics,)
        Harmonic numbers of ``X`` and of the result.
    X : ndarray, shape (n_coef,)
        Displacement coefficients, m.
    k3 : float
        Coefficient, N/m³.

    Returns
    -------
    ndarray, shape (n_coef,)
        Force coefficients, N (the harmonics of ``u³`` above
        ``max(harmonics)`` are dropped).
    """
    c = _to_complex(harmonics, X)
    cube = np.convolve(np.convolve(c, c), c) * k3
    centre = (cube.size - 1) // 2
    out = []
    for k in harmonics:
        k = int(k)
        if k == 0:
            out.append(cube[centre].real)
        else:
            out.append(2.0 * cube[centre + k].real)
            out.append(-2.0 * cube[centre + k].imag)
    return np.array(out)


# ----------------------------------------------------------------------------
# Harmonic balance of the single-DOF oscillator
# ----------------------------------------------------------------------------


def sdof_residual(harmonics, X, omega, mass, damping, stiffness, force, contact=None):
    """Harmonic-balance residual of ``m ẍ + c ẋ + k x + f_c = F cos Ωt``.

    Parameters
    ----------
    harmonics : sequence of int, shape (n_harmonics,)
        Harmonic numbers.
    X : ndarray, shape (n_coef,)
        Displacement coefficients, m.
    omega : float
        Pulsation Ω, rad/s.
    mass, damping, stiffness : float
        ``m`` (kg), ``c`` (N s/m), ``k`` (N/m).
    force : float
        Amplitude ``F`` of the cosine forcing, N.
    contact : ndarray, shape (n_coef,), optional
        Fourier coefficients of the contact force, N.

    Returns
    -------
    ndarray, shape (n_coef,)
        Residual, N: per harmonic ``k`` the block
        ``[[k_s - m (kΩ)², c kΩ], [-c kΩ, k_s - m (kΩ)²]]`` on ``(Xc, Xs)``,
        ``k_s X0`` on the mean, minus ``F`` on ``Xc1``, plus ``contact``.
    """
    R = np.zeros(n_coefficients(harmonics))
    col = 0
    for k in harmonics:
        k = int(k)
        if k == 0:
            R[col] = stiffness * X[col]
            col += 1
            continue
        w = k * omega
        block = np.array(
            [
                [stiffness - mass * w**2, damping * w],
                [-damping * w, stiffness - mass * w**2],
            ]
        )
        R[col : col + 2] = block @ X[col : col + 2]
        if k == 1:
            R[col] -= force
        col += 2
    if contact is not None:
        R = R + contact
    return R


def _bisect(fun, lo, hi, iterations=200):
    """Root of ``fun`` in ``[lo, hi]`` (signs differ at the ends) by
    bisection to the last bit."""
    f_lo = fun(lo)
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        f_mid = fun(mid)
        if (f_mid > 0.0) == (f_lo > 0.0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def jenkins_exact_coefficients(harmonics, X, kt, fs, n_grid=40000, n_gauss=48):
    """Fourier coefficients of the steady-state Jenkins force of the
    trigonometric polynomial ``u`` (coefficients ``X``), without sampling
    error.

    Reversals: sign changes of ``u'`` on a grid of ``n_grid`` points,
    bisected to the last bit (pairs closer than ``2π / n_grid`` are not
    seen). From the global maximum (stuck at ``f = +fs``), the contact
    sticks from each reversal after a slip until ``|kt (u - z)|`` reaches
    ``fs`` (bisection), then slips to the next reversal. The force
    ``kt (u - z)`` or ``±fs`` is integrated against ``cos kθ``, ``sin kθ``
    segment by segment with Gauss–Legendre rules on pieces of at most
    0.1 rad.

    Returns
    -------
    ndarray, shape (n_coef,)
        ``[F0, Fc1, Fs1, …]``, N (gross slip only: ``ValueError`` when the
    contact sticks over the whole period).
    """
    X = np.asarray(X, dtype=float)

    def u(t):
        return float(synthesize(harmonics, X, np.array([t]))[0])

    def du(t):
        return float(synthesize_derivative(harmonics, X, np.array([t]))[0])

    grid = 2.0 * np.pi * np.arange(n_grid + 1) / n_grid
    slope = synthesize_derivative(harmonics, X, grid)
    slope[n_grid] = slope[0]  # the same instant: one sign for both
    reversals = []
    for i in range(n_grid):
        if (slope[i] > 0.0) != (slope[i + 1] > 0.0):
            reversals.append(_bisect(du, grid[i], grid[i + 1]))
    values = [u(t) for t in reversals]
    if kt * (max(values) - min(values)) <= 2.0 * fs:
        raise ValueError("the contact sticks: gross slip only")
    top = int(np.argmax(values))
    start = reversals[top]
    order = [
        (reversals[(top + q) % len(reversals)], values[(top + q) % len(reversals)])
        for q in range(1, len(reversals))
    ]
    order = [(t if t > start else t + 2.0 * np.pi, v) for t, v in order]
    order.append((start + 2.0 * np.pi, values[top]))
    # segments (a, b, kind, value): kind "stick" with slider z, "slip" with sign
    segments = []
    seg_start, stuck, sign, z = start, True, 1.0, values[top] - fs / kt
    t_prev, u_prev = start, values[top]
    for t_next, u_next in order:
        if stuck:
            d = 1.0 if u_next > u_prev else -1.0
            level = z + d * fs / kt
            if d * (u_next - level) > 0.0:
                event = _bisect(lambda t, lv=level: u(t) - lv, t_prev, t_next)
                segments.append((seg_start, event, True, z))
                seg_start, stuck, sign = event, False, d
        if not stuck and t_next < start + 2.0 * np.pi:
            segments.append((seg_start, t_next, False, sign))
            seg_start, stuck, z = t_next, True, u_next - sign * fs / kt
        t_prev, u_prev = t_next, u_next
    segments.append((seg_start, start + 2.0 * np.pi, stuck, z if stuck else sign))
    nodes, weights = np.polynomial.legendre.leggauss(n_gauss)
    out = np.zeros(n_coefficients(harmonics))
    for a, b, is_stick, val in segments:
        pieces = max(1, int(np.ceil((b - a) / 0.1)))
        edges = np.linspace(a, b, pieces + 1)
        for lo, hi in zip(edges[:-1], edges[1:], strict=True):
            t = 0.5 * (lo + hi) + 0.5 * (hi - lo) * nodes
            w = 0.5 * (hi - lo) * weights
            f = kt * (synthesize(harmonics, X, t) - val) if is_stick else val * fs
            col = 0
            for k in harmonics:
                k = int(k)
                if k == 0:
                    out[col] += np.sum(w * f) / (2.0 * np.pi)
                    col += 1
                else:
                    out[col] += np.sum(w * f * np.cos(k * t)) / np.pi
                    out[col + 1] += np.sum(w * f * np.sin(k * t)) / np.pi
                    col += 2
    return out
