"""Alternating frequency–time (AFT) evaluation of contact forces.

Two AFT schemes share one contract: coefficients ``X`` of the relative
displacement in, coefficients ``F`` of the steady-state periodic contact force
and the Jacobian ``dF/dX`` out, plus an integer contact-state code.

``aft_samples``
    The classic scheme: sample ``u(θ)`` at ``n_time`` instants, march the law
    through the samples (:func:`hbmfric.kernels.laws.updates.law_update`), transform
    the sampled force back with the forward DFT. The Jacobian is carried
    through the march analytically. Works for every law.
``aft_jenkins_events``
    Jenkins only. Every reversal of ``u(θ)`` is found (the samples bracket
    them; derivative bounds prove the other intervals free of reversals, so
    that a pair of reversals inside one sample interval is not lost) and
    located by a safeguarded Newton iteration on the trigonometric
    polynomial; between reversals ``u`` is monotone, so each stick-to-slip
    crossing is bracketed and unique. The Fourier integrals of the piecewise
    force (``kt (u - z)`` in stick, ``±f_s`` in slip) are evaluated in
    closed form segment by segment (Gauss quadrature on short stick arcs,
    where the closed forms cancel). The coefficients are exact to rounding
    for any ``n_time > 2 H``, and the Jacobian needs one ``n_coef²``
    assembly instead of ``O(n_time n_coef²)`` work.

Steady-state rules (docs/physics.md): a contact in gross slip is marched once, from
the sample of maximum displacement in the saturated state ``f = +f_s``; a
stuck contact is linear and is not marched (``f = kt (u - z)``, slider at the
reference position ``z = 0`` unless the displacement forces it to shift).

Masing laws with Madelung memory (Menq, Iwan) follow the same convention:
the contact closed at ``u = 0`` in its virgin state, so the vertex of the
loop with the largest ``|u|`` lies on the virgin curve, ``F_v = ±F_load(|u_v|)``
(for Jenkins this is the slider at 0 shifted only as far as needed). Marching
one period from that vertex closes every inner loop on the way back to it,
so one pass is exact; a loop that stays on the linear part of the curves
(``|u_v| <= δ_lin``, or half its range ``<= δ_lin``) is linear and is not
marched: ``F = F_v + K0 (u - u_v)``.
"""

import numpy as np

from ..._jit import jit, jit_inline
from ..fourier.dft import basis_at, evaluate
from ..fourier.segments import trig_series
from ..laws.updates import (
    CUBIC,
    JENKINS,
    MASING_ENTRY,
    MASING_HEADER,
    is_masing,
    law_init,
    law_update,
    linear_limit,
    linear_stiffness,
    masing_step,
    slip_limit,
    virgin_curve,
)

#: contact-state codes returned by the AFT kernels
MEMORYLESS = 0
STUCK = 1
GROSS_SLIP = 2
MARCHED = 3
MICROSLIP = 4
#: failure codes (negative)
EVENT_OVERFLOW = -1
#: the reversal search ran out of its work budget (a displacement that is
#: not finite, or a degenerate one that no bound can resolve)
SEARCH_BUDGET = -2

STATE_NAMES = {
    MEMORYLESS: "memoryless law",
    STUCK: "contact stuck over the whole period",
    GROSS_SLIP: "contact slips during the period",
    MARCHED: "law marched to its periodic state",
    MICROSLIP: "contact partially slips (microslip) during the period",
    EVENT_OVERFLOW: "too many stick/slip events for the sampling",
    SEARCH_BUDGET: "event search ran out of its work budget (non-finite motion?)",
}


@jit
def _stuck_slider(kt, slip_force, u_max, u_min):
    """Slider position of a stuck contact and which extreme fixes it.

    Returns ``(z, which)`` with ``which = 1`` when ``z`` follows the maximum,
    ``-1`` when it follows the minimum and ``0`` when it stays at 0.
    """
    if kt * u_max > slip_force:
        return u_max - slip_force / kt, 1
    if kt * u_min < -slip_force:
        return u_min + slip_force / kt, -1
    return 0.0, 0


@jit
def _masing_march(code, params, u, inverse, force, grad, with_grad):
    """Steady-state force of a Masing law over one sampled period.

    Marches from the vertex of largest ``|u|`` (on the virgin curve) through
    :func:`hbmfric.kernels.laws.updates.masing_step`; with ``with_grad`` also fills
    ``grad[i] = df_i/dX``: on the branch from the reversal sample ``r``,
    ``f_i = f_r + 2 s F_load(s (u_i - u_r)/2)`` so
    ``df_i/dX = df_r/dX + k_i (E_i - E_r)``.

    Returns the contact-state code.
    """
    n = u.size
    n_coef = inverse.shape[1]
    i_max = np.argmax(u)
    i_min = np.argmin(u)
    i_v = i_max if u[i_max] >= -u[i_min] else i_min
    u_v = u[i_v]
    half_range = 0.5 * (u[i_max] - u[i_min])
    lin = linear_limit(code, params)
    k0 = linear_stiffness(code, params)
    if abs(u_v) <= lin:
        for i in range(n):
            force[i] = k0 * u[i]
            if with_grad:
                for c in range(n_coef):
                    grad[i, c] = k0 * inverse[i, c]
        return STUCK
    F, k_v, _, _, _ = virgin_curve(code, params, abs(u_v), -1.0, 0.0, 0.0)
    f_v = F if u_v >= 0.0 else -F
    if half_range <= lin:
        for i in range(n):
            force[i] = f_v + k0 * (u[i] - u_v)
            if with_grad:
                for c in range(n_coef):
                    grad[i, c] = k0 * inverse[i, c] + (k_v - k0) * inverse[i_v, c]
        return STUCK
    state = np.empty(MASING_HEADER + MASING_ENTRY * (n + 1))
    law_init(code, params, u_v, state)
    force[i_v] = state[0]
    if with_grad:
        for c in range(n_coef):
            grad[i_v, c] = k_v * inverse[i_v, c]
    for j in range(1, n):
        i = (i_v + j) % n
        p = (i - 1) % n
        f, k, top = masing_step(code, params, state, u[p], u[i], float(p), True)
        force[i] = f
        if with_grad:
            if top < 0:
                for c in range(n_coef):
                    grad[i, c] = k * inverse[i, c]
            else:
                r = int(state[MASING_HEADER + MASING_ENTRY * top + 2])
                for c in range(n_coef):
                    grad[i, c] = grad[r, c] + k * (inverse[i, c] - inverse[r, c])
    if half_range >= slip_limit(code, params):
        return GROSS_SLIP
    return MICROSLIP


@jit
def periodic_force(code, params, u, force):
    """Steady-state periodic force for one sampled period of ``u``.

    Parameters
    ----------
    code : int
        Law code.
    params : ndarray, shape (n_params,)
        Law parameters.
    u : ndarray, shape (n_time,)
        Displacement samples over one period, m.
    force : ndarray, shape (n_time,)
        Output: force samples, N.

    Returns
    -------
    int
        Contact-state code.
    """
    n = u.size
    if code == CUBIC:
        for i in range(n):
            force[i] = law_update(code, params, 0.0, 0.0, u[i])[0]
        return MEMORYLESS
    if code == JENKINS:
        kt = params[0]
        slip_force = params[1]
        i_max = np.argmax(u)
        i_min = np.argmin(u)
        if kt * (u[i_max] - u[i_min]) <= 2.0 * slip_force:
            z, _ = _stuck_slider(kt, slip_force, u[i_max], u[i_min])
            for i in range(n):
                force[i] = kt * (u[i] - z)
            return STUCK
        f = slip_force
        force[i_max] = f
        for j in range(1, n):
            i = (i_max + j) % n
            f = law_update(code, params, f, u[(i - 1) % n], u[i])[0]
            force[i] = f
        return GROSS_SLIP
    if is_masing(code):
        empty = np.empty((0, 0))
        return _masing_march(code, params, u, empty, force, empty, False)
    # generic hysteretic law: march two periods from the virgin state
    f = law_update(code, params, 0.0, 0.0, u[0])[0]
    for _sweep in range(2):
        for j in range(n):
            i = (j + 1) % n
            f = law_update(code, params, f, u[j], u[i])[0]
            force[i] = f
    return MARCHED


@jit
def aft_samples(code, params, X, inverse, forward, F, dF):
    """Sampled AFT with analytic Jacobian.

    Parameters
    ----------
    code : int
        Law code.
    params : ndarray, shape (n_params,)
        Law parameters.
    X : ndarray, shape (n_coef,)
        Displacement coefficients, m.
    inverse : ndarray, shape (n_time, n_coef)
        Inverse DFT matrix.
    forward : ndarray, shape (n_coef, n_time)
        Forward DFT matrix.
    F : ndarray, shape (n_coef,)
        Output: force coefficients, N.
    dF : ndarray, shape (n_coef, n_coef)
        Output: ``dF/dX``, N/m.

    Returns
    -------
    int
        Contact-state code.
    """
    n_time, n_coef = inverse.shape
    u = inverse @ X
    force = np.empty(n_time)
    grad = np.zeros((n_time, n_coef))
    state = MARCHED
    if code == CUBIC:
        state = MEMORYLESS
        for i in range(n_time):
            f, _, _, df_du = law_update(code, params, 0.0, 0.0, u[i])
            force[i] = f
            for c in range(n_coef):
                grad[i, c] = df_du * inverse[i, c]
    elif code == JENKINS:
        kt = params[0]
        slip_force = params[1]
        i_max = np.argmax(u)
        i_min = np.argmin(u)
        if kt * (u[i_max] - u[i_min]) <= 2.0 * slip_force:
            state = STUCK
            z, which = _stuck_slider(kt, slip_force, u[i_max], u[i_min])
            i_ref = i_max if which == 1 else i_min
            for i in range(n_time):
                force[i] = kt * (u[i] - z)
                for c in range(n_coef):
                    shift = inverse[i_ref, c] if which != 0 else 0.0
                    grad[i, c] = kt * (inverse[i, c] - shift)
        else:
            state = GROSS_SLIP
            f = slip_force
            force[i_max] = f
            for j in range(1, n_time):
                i = (i_max + j) % n_time
                p = (i - 1) % n_time
                f, a, b, d = law_update(code, params, f, u[p], u[i])
                force[i] = f
                for c in range(n_coef):
                    grad[i, c] = a * grad[p, c] + b * inverse[p, c] + d * inverse[i, c]
    elif is_masing(code):
        state = _masing_march(code, params, u, inverse, force, grad, True)
    else:
        f, _, _, d = law_update(code, params, 0.0, 0.0, u[0])
        g0 = np.empty(n_coef)
        for c in range(n_coef):
            g0[c] = d * inverse[0, c]
        for sweep in range(2):
            for j in range(n_time):
                i = (j + 1) % n_time
                f, a, b, d = law_update(code, params, f, u[j], u[i])
                force[i] = f
                for c in range(n_coef):
                    prev = g0[c] if (sweep == 0 and j == 0) else grad[j, c]
                    grad[i, c] = a * prev + b * inverse[j, c] + d * inverse[i, c]
    for r in range(n_coef):
        acc = 0.0
        for i in range(n_time):
            acc += forward[r, i] * force[i]
        F[r] = acc
    for r in range(n_coef):
        for c in range(n_coef):
            dF[r, c] = 0.0
        for i in range(n_time):
            w = forward[r, i]
            if w != 0.0:
                for c in range(n_coef):
                    dF[r, c] += w * grad[i, c]
    return state


# ----------------------------------------------------------------------------
# Event-located Jenkins AFT
# ----------------------------------------------------------------------------

# The helpers the kernel calls several times per evaluation (the segment
# sums, the root refinement, the assembly) are inlined (``jit_inline``): a
# call between compiled kernels passes each array as its unpacked fields,
# and with a dozen arrays per call that was 0.1-0.2 µs a call, about a tenth
# of an evaluation at H = 21 (bench/README.md "Issue 18, stop 29"). The
# arithmetic is unchanged: the same bits.


@jit
def _locate(harmonic_numbers, X, lo, hi, level, on_slope):
    """Root of ``u(θ) - level`` (``on_slope=False``) or of ``u'(θ)``
    (``on_slope=True``) in ``[lo, hi]``, by safeguarded Newton iteration.

    The caller guarantees a sign change (or a zero) over the bracket.
    """
    v, d1, d2 = evaluate(harmonic_numbers, X, lo)
    g_lo = d1 if on_slope else v - level
    v, d1, d2 = evaluate(harmonic_numbers, X, hi)
    g_hi = d1 if on_slope else v - level
    return _refine(harmonic_numbers, X, lo, hi, g_lo, g_hi, level, on_slope)


@jit_inline
def _refine(harmonic_numbers, X, lo, hi, g_lo, g_hi, level, on_slope):
    """:func:`_locate` with the bracket-end values ``g_lo``, ``g_hi`` of the
    function (``u - level`` or ``u'``) already known."""
    if g_lo == 0.0:
        return lo
    if g_hi == 0.0:
        return hi
    if (g_lo > 0.0) == (g_hi > 0.0):
        # no sign change: the event sits at the bracket end nearest to zero
        return lo if abs(g_lo) < abs(g_hi) else hi
    theta = lo + (hi - lo) * g_lo / (g_lo - g_hi)
    return _newton_from(harmonic_numbers, X, lo, hi, g_lo, theta, level, on_slope)


@jit
def _hermite_root(a, b, va, vb, wa, wb):
    """Root in ``[a, b]`` of the cubic Hermite interpolant of values
    ``va, vb`` and slopes ``wa, wb`` (signs of ``va``, ``vb`` differ): two
    Newton steps from the secant root, kept inside the bracket. A starting
    point for :func:`_newton_from` good to ``O((b - a)⁴)``."""
    L = b - a
    t = va / (va - vb)
    for _ in range(2):
        t2 = t * t
        t3 = t2 * t
        p = (
            (2.0 * t3 - 3.0 * t2 + 1.0) * va
            + (t3 - 2.0 * t2 + t) * L * wa
            + (3.0 * t2 - 2.0 * t3) * vb
            + (t3 - t2) * L * wb
        )
        dp = (
            (6.0 * t2 - 6.0 * t) * va
            + (3.0 * t2 - 4.0 * t + 1.0) * L * wa
            + (6.0 * t - 6.0 * t2) * vb
            + (3.0 * t2 - 2.0 * t) * L * wb
        )
        if dp == 0.0:
            break
        t = min(max(t - p / dp, 0.0), 1.0)
    return a + t * L


@jit_inline
def _newton_from(harmonic_numbers, X, lo, hi, g_lo, theta, level, on_slope):
    """The safeguarded Newton iteration of :func:`_locate` from ``theta``
    inside the bracket ``[lo, hi]`` (``g_lo``: the function at ``lo``)."""
    for _ in range(60):
        v, d1, d2 = evaluate(harmonic_numbers, X, theta)
        g = d1 if on_slope else v - level
        dg = d2 if on_slope else d1
        if (g > 0.0) == (g_lo > 0.0):
            lo = theta
            g_lo = g
        else:
            hi = theta
        if dg != 0.0:
            step = g / dg
            # Newton converges quadratically: once a step is below 1e-10 the
            # stepped point is exact to rounding (waiting for a step at
            # rounding level, which may land on a bracket end, lets the
            # iteration fall back to bisection for dozens of steps)
            if abs(step) <= 1e-10 * (1.0 + abs(theta)):
                return min(max(theta - step, lo), hi)
            new = theta - step
        else:
            new = 0.5 * (lo + hi)
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        if hi - lo <= 1e-15:
            return new
        theta = new
    return theta


#: subdivision depth of the reversal search: an interval of ``h / 2**40``
#: (about 5e-14 rad at n_time = 120) is not split further
_MAX_DEPTH = 40


@jit
def _samples_uv(harmonic_numbers, X, inverse, derivative, u, v):
    """Samples ``u(θ_i)`` and ``u'(θ_i)`` of the signal ``X``.

    For ``n_time`` divisible by 4 only the first quarter of the rows is
    read: ``θ → 2π - θ`` flips the sines, ``θ → π ± θ`` flips the odd
    harmonics, so each row gives four samples from eight partial sums
    (a quarter of the products of ``inverse @ X`` and ``derivative @ X``).
    Two rows are summed in one pass over the harmonics: the sums are
    chains of dependent additions, and two rows' chains run side by side
    (each sum in the same order as one row alone: the same bits).
    """
    n = u.size
    n_coef = X.size
    if n % 4 != 0:
        for i in range(n):
            a = 0.0
            b = 0.0
            for c in range(n_coef):
                a += inverse[i, c] * X[c]
                b += derivative[i, c] * X[c]
            u[i] = a
            v[i] = b
        return
    quarter = n // 4
    i = 0
    while i <= quarter:
        # rows i and i2 (i2 = i when i is the last row: computed twice)
        i2 = i + 1 if i < quarter else i
        ce = 0.0  # Σ_even a_k cos kθ
        se = 0.0  # Σ_even b_k sin kθ
        co = 0.0
        so = 0.0
        dce = 0.0  # Σ_even k b_k cos kθ
        dse = 0.0  # Σ_even k a_k sin kθ
        dco = 0.0
        dso = 0.0
        ce2 = 0.0
        se2 = 0.0
        co2 = 0.0
        so2 = 0.0
        dce2 = 0.0
        dse2 = 0.0
        dco2 = 0.0
        dso2 = 0.0
        col = 0
        for k in harmonic_numbers:
            if k == 0:
                ce += X[col]
                ce2 += X[col]
                col += 1
                continue
            a = X[col]
            b = X[col + 1]
            ck = inverse[i, col]
            sk = inverse[i, col + 1]
            ck2 = inverse[i2, col]
            sk2 = inverse[i2, col + 1]
            if k % 2 == 0:
                ce += a * ck
                se += b * sk
                dce += k * b * ck
                dse += k * a * sk
                ce2 += a * ck2
                se2 += b * sk2
                dce2 += k * b * ck2
                dse2 += k * a * sk2
            else:
                co += a * ck
                so += b * sk
                dco += k * b * ck
                dso += k * a * sk
                co2 += a * ck2
                so2 += b * sk2
                dco2 += k * b * ck2
                dso2 += k * a * sk2
            col += 2
        _scatter(u, v, i, ce, se, co, so, dce, dse, dco, dso)
        _scatter(u, v, i2, ce2, se2, co2, so2, dce2, dse2, dco2, dso2)
        i += 2


@jit_inline
def _scatter(u, v, i, ce, se, co, so, dce, dse, dco, dso):
    """The four samples of row ``i`` of :func:`_samples_uv` from its
    partial sums: at ``θ_i``, ``2π - θ_i``, ``π + θ_i``, ``π - θ_i``."""
    n = u.size
    half = n // 2
    j = (n - i) % n
    u[j] = ce - se + co - so
    v[j] = dce + dse + dco + dso
    u[half + i] = ce + se - co - so
    v[half + i] = dce - dse - dco + dso
    u[half - i] = ce - se - co + so
    v[half - i] = dce + dse - dco - dso
    u[i] = ce + se + co + so
    v[i] = dce - dse + dco - dso


@jit
def _derivative_bounds(harmonic_numbers, X, X2):
    """Bounds ``Σ k² |X_k|`` and ``Σ k³ |X_k|`` of the second and third
    θ-derivatives of ``u``; fills ``X2`` with the coefficients ``-k² X`` of
    the second derivative."""
    b2 = 0.0
    b3 = 0.0
    col = 0
    for k in harmonic_numbers:
        if k == 0:
            X2[col] = 0.0
            col += 1
            continue
        amp = np.sqrt(X[col] * X[col] + X[col + 1] * X[col + 1])
        b2 += k * k * amp
        b3 += k * k * k * amp
        X2[col] = -k * k * X[col]
        X2[col + 1] = -k * k * X[col + 1]
        col += 2
    return b2, b3


@jit
def _find_reversals(
    harmonic_numbers, X, X2, inverse, u, v, b2, b3, theta, value, stack
):
    """All sign changes of ``u'`` over one period, in increasing order.

    A sample interval whose end slopes have one sign and exceed what the
    bound ``|u''| <= b2`` lets them lose inside it holds no reversal. Any
    other interval is examined with ``u''`` at its ends and the bound
    ``|u'''| <= b3``: either a quadratic lower bound proves ``u'`` keeps its
    sign, or ``u''`` provably keeps its sign (one reversal, located by
    :func:`_locate`), or the interval is halved (depth :data:`_MAX_DEPTH`).
    So a pair of reversals closer than a sample interval (a stick arc
    shorter than one interval) is found whatever its length above
    ``h / 2**_MAX_DEPTH``.

    ``X2`` holds the coefficients of ``u''`` (``-k² X``): at the samples
    ``u''`` is a row of ``inverse`` times ``X2``.

    The work is bounded: a motion with ``u'' ≡ 0`` (constant ``u``, for
    instance the zero response to zero forcing) has no reversal and returns
    at once, a non-finite one fails at once, and the number of examined
    intervals is capped at ``4 _MAX_DEPTH (n_time + theta.size)``, enough
    for every reversal pair to be resolved to full depth.

    Returns the number of reversals, ``EVENT_OVERFLOW`` if ``theta``
    overflows or ``SEARCH_BUDGET`` if the budget runs out or the motion is
    not finite; ``theta[i]`` in ``(0, 2π]``, ``value[i] = u(theta[i])``.
    """
    n_coef = X.size
    n = u.size
    h = 2.0 * np.pi / n
    count = 0
    if not (np.isfinite(b2) and np.isfinite(b3)):
        return SEARCH_BUDGET
    if b2 == 0.0:
        return 0  # u is constant: it never reverses
    budget = 4 * _MAX_DEPTH * (n + theta.size)
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        va = v[i]
        vb = v[j]
        if (va > 0.0) == (vb > 0.0) and abs(va) + abs(vb) > b2 * h:
            continue
        stack[0, 0] = i * h
        stack[0, 1] = (i + 1) * h
        stack[0, 2] = va
        stack[0, 3] = vb
        stack[0, 4] = 0.0
        top = 1
        while top > 0:
            budget -= 1
            if budget < 0:
                return SEARCH_BUDGET
            top -= 1
            a = stack[top, 0]
            b = stack[top, 1]
            va = stack[top, 2]
            vb = stack[top, 3]
            depth = stack[top, 4]
            width = b - a
            pa = va > 0.0
            pb = vb > 0.0
            if pa == pb and abs(va) + abs(vb) > b2 * width:
                continue
            if depth == 0.0:
                wa = 0.0
                wb = 0.0
                for c in range(n_coef):
                    wa += inverse[i, c] * X2[c]
                    wb += inverse[j, c] * X2[c]
            else:
                wa = evaluate(harmonic_numbers, X, a)[2]
                wb = evaluate(harmonic_numbers, X, b)[2]
            bend = 0.125 * b3 * width * width
            if pa == pb:
                s = 1.0 if pa else -1.0
                if (
                    s * (va + 0.5 * wa * width) > bend
                    and s * (vb - 0.5 * wb * width) > bend
                ):
                    continue
            elif (wa > 0.0) == (wb > 0.0) and abs(wa) + abs(wb) > b3 * width:
                if count == theta.size:
                    return EVENT_OVERFLOW
                if va == 0.0 or vb == 0.0:
                    th = a if va == 0.0 else b
                else:
                    th0 = _hermite_root(a, b, va, vb, wa, wb)
                    # np.bool_: a bool, not a literal True (one signature)
                    th = _newton_from(
                        harmonic_numbers, X, a, b, va, th0, 0.0, np.bool_(True)
                    )
                theta[count] = th
                value[count] = evaluate(harmonic_numbers, X, th)[0]
                count += 1
                continue
            if depth >= _MAX_DEPTH:
                if pa != pb:
                    if count == theta.size:
                        return EVENT_OVERFLOW
                    th = _refine(harmonic_numbers, X, a, b, va, vb, 0.0, np.bool_(True))
                    theta[count] = th
                    value[count] = evaluate(harmonic_numbers, X, th)[0]
                    count += 1
                continue
            mid = 0.5 * (a + b)
            vm = evaluate(harmonic_numbers, X, mid)[1]
            # right half below the left one: the left is examined first
            stack[top, 0] = mid
            stack[top, 1] = b
            stack[top, 2] = vm
            stack[top, 3] = vb
            stack[top, 4] = depth + 1.0
            stack[top + 1, 0] = a
            stack[top + 1, 1] = mid
            stack[top + 1, 2] = va
            stack[top + 1, 3] = vm
            stack[top + 1, 4] = depth + 1.0
            top += 2
    return count


#: Gauss–Legendre rule of :func:`_stick_quadrature` (nodes on [-1, 1])
_GAUSS_NODES = tuple(float(x) for x in np.polynomial.legendre.leggauss(6)[0])
_GAUSS_WEIGHTS = tuple(float(w) for w in np.polynomial.legendre.leggauss(6)[1])
#: a stick segment is short when ``max(harmonic_numbers) * length`` is below
#: this: the 6-point rule is then exact to rounding (error below
#: ``(0.25)**12 / 12! ≈ 1e-16`` relative)
_SHORT_ARC = 0.5


@jit
def _stick_quadrature(harmonic_numbers, X, a, b, entry_force, kt, out):
    """Add ``∫_a^b f ψ_k`` (normalised rows) of a short stick segment to
    ``out``, with ``f = entry_force + kt (u(θ) - u(a))``.

    The closed-form integrals of ``kt u`` and ``kt z`` over a short arc are
    each about ``kt |u| (b - a)`` while their difference is at most
    ``2 f_s (b - a)``: with ``kt |u| / f_s = 1e8`` the rounding of the
    integrals alone (relative ``1e-16 / (m (b - a))``) leaves 1e-9 N of
    noise in ``F``, the Newton tolerance. Here ``u(θ) - u(a)`` is summed
    from ``-2 sin(k (θ - a)/2) sin(k (θ + a)/2)`` (cosines) and
    ``2 sin(k (θ - a)/2) cos(k (θ + a)/2)`` (sines), which keeps its
    relative accuracy, and integrated by Gauss–Legendre.
    """
    half = 0.5 * (b - a)
    mid = 0.5 * (a + b)
    inv_pi = 1.0 / np.pi
    for g in range(len(_GAUSS_NODES)):
        theta = mid + half * _GAUSS_NODES[g]
        d = 0.5 * (theta - a)
        sm = 0.5 * (theta + a)
        cd1 = np.cos(d)
        sd1 = np.sin(d)
        cs1 = np.cos(sm)
        ss1 = np.sin(sm)
        c1 = np.cos(theta)
        s1 = np.sin(theta)
        cdk = 1.0
        sdk = 0.0
        csk = 1.0
        ssk = 0.0
        ck = 1.0
        sk = 0.0
        m = 0
        du = 0.0
        col = 0
        for k in harmonic_numbers:
            while m < k:
                cdk, sdk = cdk * cd1 - sdk * sd1, sdk * cd1 + cdk * sd1
                csk, ssk = csk * cs1 - ssk * ss1, ssk * cs1 + csk * ss1
                m += 1
            if k == 0:
                col += 1
            else:
                du += 2.0 * sdk * (X[col + 1] * csk - X[col] * ssk)
                col += 2
        f = (entry_force + kt * du) * half * _GAUSS_WEIGHTS[g]
        m = 0
        row = 0
        for k in harmonic_numbers:
            while m < k:
                ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
                m += 1
            if k == 0:
                out[row] += f * (0.5 * inv_pi)
                row += 1
            else:
                out[row] += f * ck * inv_pi
                out[row + 1] += f * sk * inv_pi
                row += 2


@jit_inline
def _close_segment(
    harmonic_numbers,
    X,
    a,
    b,
    ca,
    sa,
    cb,
    sb,
    stuck,
    sign,
    z,
    kt,
    slip_force,
    C,
    S,
    C_short,
    S_short,
    slip,
    Q,
    Phi,
    zs,
    ns,
):
    """Add the segment ``[a, b]`` (trigonometric series ``ca, sa`` at ``a``,
    ``cb, sb`` at ``b``) to the Fourier integrals.

    Stick, ``f = kt (u - z)`` with the slider ``z = u(a) - sign f_s / kt``
    set at the segment start ``a`` (a reversal, or the global maximum):
    adds ``∫ cos mθ``, ``∫ sin mθ`` to ``C``, ``S`` (``C_short``,
    ``S_short`` for a short segment) which assemble ``kt ∫ φ_j ψ_k`` once
    at the end, and stores row ``ns`` of ``Q`` (``∫ ψ_k``, normalised),
    ``Phi`` (the basis at ``a``: ``dz/dX``) and ``zs`` (0 for a short
    segment, whose force integrals :func:`_stick_quadrature` adds to
    ``slip`` directly). Slip, ``f = sign f_s``: adds ``sign f_s ∫ ψ_k`` to
    ``slip``. Returns the new stick-segment count.
    """
    m_max = C.size - 1
    inv_pi = 1.0 / np.pi
    short = stuck and harmonic_numbers[-1] * (b - a) <= _SHORT_ARC
    if stuck:
        CC = C_short if short else C
        SS = S_short if short else S
        CC[0] += b - a
        for m in range(1, m_max + 1):
            CC[m] += (sb[m] - sa[m]) / m
            SS[m] += (ca[m] - cb[m]) / m
    row = 0
    for k in harmonic_numbers:
        if k == 0:
            qc = (b - a) * (0.5 * inv_pi)
            qs = 0.0
        else:
            qc = (sb[k] - sa[k]) / k * inv_pi
            qs = (ca[k] - cb[k]) / k * inv_pi
        if stuck:
            Q[ns, row] = qc
            if k == 0:
                Phi[ns, row] = 1.0
            else:
                Phi[ns, row] = ca[k]
                Q[ns, row + 1] = qs
                Phi[ns, row + 1] = sa[k]
        else:
            slip[row] += sign * slip_force * qc
            if k != 0:
                slip[row + 1] += sign * slip_force * qs
        row += 1 if k == 0 else 2
    if not stuck:
        return ns
    if short:
        zs[ns] = 0.0
        _stick_quadrature(harmonic_numbers, X, a, b, sign * slip_force, kt, slip)
    else:
        zs[ns] = z
    return ns + 1


@jit_inline
def _stick_matrix(harmonic_numbers, kt, C, S, P):
    """``P[r, c] = kt ∫_stick φ_c ψ_r`` (normalised rows) from the summed
    segment integrals ``C[m] = ∫ cos mθ``, ``S[m] = ∫ sin mθ``: products of
    harmonics ``j`` and ``k`` reduce to harmonics ``|j - k|`` and ``j + k``.
    Apart from the mean row (normalised by ``1/2π``, the others by ``1/π``)
    ``P`` is symmetric: the upper triangle is computed and mirrored."""
    nh = harmonic_numbers.size
    first = 1 if harmonic_numbers[0] == 0 else 0
    fk = kt / np.pi
    hf = 0.5 * fk
    if first == 1:
        f0 = kt / (2.0 * np.pi)
        P[0, 0] = f0 * C[0]
        for jb in range(1, nh):
            j = harmonic_numbers[jb]
            c = 2 * jb - 1
            P[0, c] = f0 * C[j]
            P[0, c + 1] = f0 * S[j]
            P[c, 0] = fk * C[j]
            P[c + 1, 0] = fk * S[j]
    for kb in range(first, nh):
        k = harmonic_numbers[kb]
        r = first + 2 * (kb - first)
        # j = k: the difference harmonic is 0 (S[0] = 0)
        c2 = C[2 * k]
        s2 = S[2 * k]
        P[r, r] = hf * (C[0] + c2)
        P[r, r + 1] = hf * s2
        P[r + 1, r] = hf * s2
        P[r + 1, r + 1] = hf * (C[0] - c2)
        for jb in range(kb + 1, nh):
            j = harmonic_numbers[jb]
            c = first + 2 * (jb - first)
            cd = C[j - k]
            sd = S[j - k]
            cs = C[j + k]
            ss = S[j + k]
            cc = hf * (cd + cs)  # cos jθ cos kθ
            sc = hf * (ss + sd)  # sin jθ cos kθ
            cs_ = hf * (ss - sd)  # cos jθ sin kθ
            s_s = hf * (cd - cs)  # sin jθ sin kθ
            P[r, c] = cc
            P[r, c + 1] = sc
            P[r + 1, c] = cs_
            P[r + 1, c + 1] = s_s
            P[c, r] = cc
            P[c + 1, r] = sc
            P[c, r + 1] = cs_
            P[c + 1, r + 1] = s_s


@jit_inline
def _assemble(
    harmonic_numbers, kt, X, C, S, C_short, S_short, slip, Q, Phi, zs, ns, F, dF
):
    """``F`` and ``dF`` from the segment sums.

    ``dF = P(C, S) + P(C_short, S_short) - kt Σ_s Q[s] ⊗ Phi[s]`` and
    ``F = P(C, S) X - kt Σ_s zs[s] Q[s] + slip`` (the short stick segments'
    force is in ``slip`` already).
    """
    n = X.size
    _stick_matrix(harmonic_numbers, kt, C, S, dF)
    for r in range(n):
        # four partial sums: independent addition chains
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        a3 = 0.0
        c = 0
        while c + 3 < n:
            a0 += dF[r, c] * X[c]
            a1 += dF[r, c + 1] * X[c + 1]
            a2 += dF[r, c + 2] * X[c + 2]
            a3 += dF[r, c + 3] * X[c + 3]
            c += 4
        while c < n:
            a0 += dF[r, c] * X[c]
            c += 1
        acc = (a0 + a1) + (a2 + a3)
        for s in range(ns):
            acc -= kt * zs[s] * Q[s, r]
        F[r] = acc + slip[r]
    if C_short[0] != 0.0:
        # rare (kt |u| >> f_s): allocated only here
        tmp = np.empty((n, n))
        _stick_matrix(harmonic_numbers, kt, C_short, S_short, tmp)
        for r in range(n):
            for c in range(n):
                dF[r, c] += tmp[r, c]
    for s in range(ns):
        for r in range(n):
            g = kt * Q[s, r]
            for c in range(n):
                dF[r, c] -= g * Phi[s, c]


@jit
def aft_jenkins_events(params, harmonic_numbers, X, inverse, derivative, F, dF):
    """Event-located AFT of a Jenkins element, with analytic Jacobian.

    Every reversal of ``u`` (sign change of ``u'``) is found and located
    (:func:`_find_reversals`), so that ``u`` is monotone between successive
    reversals. Marching from the global maximum (stuck at ``f = +f_s``): a
    slip ends at the next reversal, where the contact sticks with the
    slider ``z = u_r ∓ f_s/kt``; a stick ends inside a monotone stretch
    where ``u`` crosses ``z ± f_s/kt`` (bracketed by the samples, located by
    :func:`_locate`). The force is continuous at every event, so the
    Jacobian of the exact Fourier integrals is that of the integrands with
    frozen event angles: ``kt ∫ φ ψ`` over the stick segments, minus
    ``kt ∫ψ ⊗ φ(θ_r)`` for the slider of each stick segment.

    Parameters
    ----------
    params : ndarray, shape (2,)
        ``[tangential_stiffness, slip_force]``.
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
        Harmonics of ``X``.
    X : ndarray, shape (n_coef,)
        Displacement coefficients, m.
    inverse, derivative : ndarray, shape (n_time, n_coef)
        Inverse DFT matrix and its θ-derivative at ``θ_i = 2π i / n_time``
        (they bracket the events; any ``n_time > 2 max(harmonic_numbers)``
        finds them all).
    F : ndarray, shape (n_coef,)
        Output: force coefficients, N (exact Fourier integrals).
    dF : ndarray, shape (n_coef, n_coef)
        Output: ``dF/dX``, N/m.

    Returns
    -------
    int
        ``STUCK``, ``GROSS_SLIP``, or a negative failure code
        (``EVENT_OVERFLOW``, ``SEARCH_BUDGET``).
    """
    kt = params[0]
    slip_force = params[1]
    n_time, n_coef = inverse.shape
    if slip_force == 0.0:
        F[:] = 0.0
        dF[:, :] = 0.0
        return GROSS_SLIP
    two_pi = 2.0 * np.pi
    h = two_pi / n_time
    k_max = harmonic_numbers[-1]
    m_max = 2 * k_max
    cap = 4 * k_max + 8  # reversals: at most 2 k_max, with room for rounding
    # one work buffer, cut into views
    # work buffers (views of two allocations: the second is sized by the
    # number of reversals, which bounds the stick segments)
    work = np.empty(2 * n_time + 2 * cap + 5 * (_MAX_DEPTH + 2) + 2 * n_coef)
    o = 0
    u = work[o : o + n_time]
    o += n_time
    v = work[o : o + n_time]
    o += n_time
    rev_th = work[o : o + cap]
    o += cap
    rev_u = work[o : o + cap]
    o += cap
    stack = work[o : o + 5 * (_MAX_DEPTH + 2)].reshape((_MAX_DEPTH + 2, 5))
    o += 5 * (_MAX_DEPTH + 2)

    _samples_uv(harmonic_numbers, X, inverse, derivative, u, v)
    X2 = work[o : o + n_coef]
    o += n_coef
    b2, b3 = _derivative_bounds(harmonic_numbers, X, X2)
    n_rev = _find_reversals(
        harmonic_numbers, X, X2, inverse, u, v, b2, b3, rev_th, rev_u, stack
    )
    if n_rev < 0:
        F[:] = 0.0
        dF[:, :] = 0.0
        return n_rev
    i_max = 0
    i_min = 0
    for q in range(1, n_rev):
        if rev_u[q] > rev_u[i_max]:
            i_max = q
        if rev_u[q] < rev_u[i_min]:
            i_min = q
    if n_rev == 0:
        u_max = u[0]
        u_min = u[0]
        th_max = 0.0
        th_min = 0.0
    else:
        u_max = rev_u[i_max]
        u_min = rev_u[i_min]
        th_max = rev_th[i_max]
        th_min = rev_th[i_min]

    if kt * (u_max - u_min) <= 2.0 * slip_force:
        z, which = _stuck_slider(kt, slip_force, u_max, u_min)
        for r in range(n_coef):
            F[r] = kt * X[r]
            for c in range(n_coef):
                dF[r, c] = 0.0
            dF[r, r] = kt
        if which != 0 and harmonic_numbers[0] == 0:
            basis_r = work[o : o + n_coef]
            basis_at(harmonic_numbers, th_max if which == 1 else th_min, basis_r)
            F[0] -= kt * z
            for c in range(n_coef):
                dF[0, c] -= kt * basis_r[c]
        return STUCK

    n_seg = n_rev + 2
    work = np.empty(8 * (m_max + 1) + n_coef + n_seg * (2 * n_coef + 1))
    o = 0
    ca = work[o : o + m_max + 1]
    o += m_max + 1
    sa = work[o : o + m_max + 1]
    o += m_max + 1
    cb = work[o : o + m_max + 1]
    o += m_max + 1
    sb = work[o : o + m_max + 1]
    o += m_max + 1
    C = work[o : o + m_max + 1]
    o += m_max + 1
    S = work[o : o + m_max + 1]
    o += m_max + 1
    C_short = work[o : o + m_max + 1]
    o += m_max + 1
    S_short = work[o : o + m_max + 1]
    o += m_max + 1
    slip = work[o : o + n_coef]
    o += n_coef
    Q = work[o : o + n_seg * n_coef].reshape((n_seg, n_coef))
    o += n_seg * n_coef
    Phi = work[o : o + n_seg * n_coef].reshape((n_seg, n_coef))
    o += n_seg * n_coef
    zs = work[o : o + n_seg]
    C[:] = 0.0
    S[:] = 0.0
    C_short[:] = 0.0
    S_short[:] = 0.0
    slip[:] = 0.0

    # march from the global maximum, stuck at f = +f_s
    stuck = True
    sign = 1.0
    z = u_max - slip_force / kt
    seg_start = th_max
    trig_series(th_max, ca, sa)
    ns = np.int64(0)  # not a literal 0: one signature of _close_segment
    p = int(th_max / h) + 1  # next sample (unwrapped index)
    t_prev = th_max
    u_prev = u_max
    for q in range(1, n_rev + 1):
        r = i_max + q
        if r < n_rev:
            t_next = rev_th[r]
        else:
            t_next = rev_th[r - n_rev] + two_pi
        u_next = rev_u[r % n_rev]
        if stuck:
            d = 1.0 if u_next > u_prev else -1.0
            level = z + d * slip_force / kt
            if d * (u_next - level) > 0.0:
                # the stick ends inside this monotone stretch: bracket the
                # crossing of the slip limit by the samples
                while p * h <= t_prev:
                    p += 1
                lo = t_prev
                u_lo = u_prev
                while p * h < t_next and d * (u[p % n_time] - level) <= 0.0:
                    lo = p * h
                    u_lo = u[p % n_time]
                    p += 1
                if p * h < t_next:
                    hi = p * h
                    u_hi = u[p % n_time]
                else:
                    hi = t_next
                    u_hi = u_next
                event = _refine(
                    harmonic_numbers,
                    X,
                    lo,
                    hi,
                    u_lo - level,
                    u_hi - level,
                    level,
                    np.bool_(False),  # a bool, not a literal: one signature
                )
                trig_series(event, cb, sb)
                ns = _close_segment(
                    harmonic_numbers,
                    X,
                    seg_start,
                    event,
                    ca,
                    sa,
                    cb,
                    sb,
                    np.bool_(True),  # a bool, not a literal: one signature
                    sign,
                    z,
                    kt,
                    slip_force,
                    C,
                    S,
                    C_short,
                    S_short,
                    slip,
                    Q,
                    Phi,
                    zs,
                    ns,
                )
                ca, cb = cb, ca
                sa, sb = sb, sa
                seg_start = event
                stuck = False
                sign = d
        if not stuck and q < n_rev:
            # the slip ends at the reversal
            trig_series(t_next, cb, sb)
            ns = _close_segment(
                harmonic_numbers,
                X,
                seg_start,
                t_next,
                ca,
                sa,
                cb,
                sb,
                np.bool_(False),  # a bool, not a literal: one signature
                sign,
                z,
                kt,
                slip_force,
                C,
                S,
                C_short,
                S_short,
                slip,
                Q,
                Phi,
                zs,
                ns,
            )
            ca, cb = cb, ca
            sa, sb = sb, sa
            seg_start = t_next
            stuck = True
            z = u_next - sign * slip_force / kt
        t_prev = t_next
        u_prev = u_next
    theta_end = th_max + two_pi
    trig_series(theta_end, cb, sb)
    ns = _close_segment(
        harmonic_numbers,
        X,
        seg_start,
        theta_end,
        ca,
        sa,
        cb,
        sb,
        np.bool_(stuck),  # a bool, never a literal: one signature
        sign,
        z,
        kt,
        slip_force,
        C,
        S,
        C_short,
        S_short,
        slip,
        Q,
        Phi,
        zs,
        ns,
    )
    _assemble(
        harmonic_numbers,
        kt,
        X,
        C,
        S,
        C_short,
        S_short,
        slip,
        Q,
        Phi,
        zs,
        ns,
        F,
        dF,
    )
    return GROSS_SLIP
