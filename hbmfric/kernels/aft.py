"""Alternating frequency–time (AFT) evaluation of contact forces.

Two AFT schemes share one contract: coefficients ``X`` of the relative
displacement in, coefficients ``F`` of the steady-state periodic contact force
and the Jacobian ``dF/dX`` out, plus an integer contact-state code.

``aft_samples``
    The classic scheme: sample ``u(θ)`` at ``n_time`` instants, march the law
    through the samples (:func:`hbmfric.kernels.laws.law_update`), transform
    the sampled force back with the forward DFT. The Jacobian is carried
    through the march analytically. Works for every law.
``aft_jenkins_events``
    Jenkins only. The samples serve to *detect* stick/slip events; each event
    is then located inside its sample interval by a safeguarded Newton
    iteration on the trigonometric polynomial ``u(θ)``, and the Fourier
    integrals of the piecewise force (``kt (u - z)`` in stick, ``±f_s`` in
    slip) are evaluated in closed form segment by segment. The coefficients
    are exact to rounding for any ``n_time`` that resolves the events, and the
    Jacobian needs ``O(n_segments n_coef²)`` work instead of
    ``O(n_time n_coef²)``.

Steady-state rules (SPEC §3): a contact in gross slip is marched once, from
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

from .._jit import jit
from .dft import basis_at, evaluate
from .laws import (
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

STATE_NAMES = {
    MEMORYLESS: "memoryless law",
    STUCK: "contact stuck over the whole period",
    GROSS_SLIP: "contact slips during the period",
    MARCHED: "law marched to its periodic state",
    MICROSLIP: "contact partially slips (microslip) during the period",
    EVENT_OVERFLOW: "too many stick/slip events for the sampling",
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
    :func:`hbmfric.kernels.laws.masing_step`; with ``with_grad`` also fills
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
    if g_lo == 0.0:
        return lo
    if g_hi == 0.0:
        return hi
    if (g_lo > 0.0) == (g_hi > 0.0):
        # no sign change: the event sits at the bracket end nearest to zero
        return lo if abs(g_lo) < abs(g_hi) else hi
    theta = lo + (hi - lo) * g_lo / (g_lo - g_hi)
    for _ in range(60):
        v, d1, d2 = evaluate(harmonic_numbers, X, theta)
        g = d1 if on_slope else v - level
        dg = d2 if on_slope else d1
        if (g > 0.0) == (g_lo > 0.0):
            lo = theta
            g_lo = g
        else:
            hi = theta
        step_ok = dg != 0.0
        new = theta - g / dg if step_ok else 0.5 * (lo + hi)
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        if abs(new - theta) <= 1e-15 * (1.0 + abs(theta)) or hi - lo <= 1e-15:
            return new
        theta = new
    return theta


@jit
def _segment_integrals(harmonic_numbers, a, b, cos_int, sin_int):
    """``cos_int[m] = ∫_a^b cos mθ dθ`` and ``sin_int[m] = ∫_a^b sin mθ dθ``
    for ``m = 0 … 2 max(harmonic_numbers)``, by the angle-addition
    recurrence."""
    m_max = cos_int.size - 1
    ca = np.cos(a)
    sa = np.sin(a)
    cb = np.cos(b)
    sb = np.sin(b)
    cma = 1.0
    sma = 0.0
    cmb = 1.0
    smb = 0.0
    cos_int[0] = b - a
    sin_int[0] = 0.0
    for m in range(1, m_max + 1):
        cma, sma = cma * ca - sma * sa, sma * ca + cma * sa
        cmb, smb = cmb * cb - smb * sb, smb * cb + cmb * sb
        cos_int[m] = (smb - sma) / m
        sin_int[m] = (cma - cmb) / m


@jit
def _add_segment(
    harmonic_numbers,
    cos_int,
    sin_int,
    stuck,
    sign,
    slip_force,
    kt,
    z,
    basis_r,
    P,
    F,
    dF,
):
    """Add one stick or slip segment to the Fourier integrals.

    Stick (``stuck=True``): ``f = kt (u - z)`` adds ``kt ∫ φ_j ψ_k`` to ``P``
    and ``-kt z ∫ ψ_k`` to ``F`` and ``-kt ∫ψ_k ⊗ φ(θ_r)`` to ``dF`` (the
    slider ``z = u(θ_r) ∓ f_s/kt`` moves with the reversal point ``θ_r``).
    Slip: ``f = sign f_s`` adds ``sign f_s ∫ ψ_k`` to ``F``.
    """
    row = 0
    for k in harmonic_numbers:
        n_rows = 1 if k == 0 else 2
        for rr in range(n_rows):
            norm = 1.0 / (2.0 * np.pi) if k == 0 else 1.0 / np.pi
            is_sin_row = rr == 1
            q = (sin_int[k] if is_sin_row else cos_int[k]) * norm
            if not stuck:
                F[row] += sign * slip_force * q
            else:
                F[row] -= kt * z * q
                col = 0
                for j in harmonic_numbers:
                    n_cols = 1 if j == 0 else 2
                    for cc in range(n_cols):
                        is_sin_col = cc == 1
                        dF[row, col] -= kt * q * basis_r[col]
                        # ∫ φ_j ψ_k over the segment
                        s = j + k
                        d = j - k
                        ad = abs(d)
                        if j == 0 or k == 0:
                            if j == 0 and k == 0:
                                val = cos_int[0]
                            elif j == 0:
                                val = sin_int[k] if is_sin_row else cos_int[k]
                            else:
                                val = sin_int[j] if is_sin_col else cos_int[j]
                        elif not is_sin_col and not is_sin_row:
                            val = 0.5 * (cos_int[ad] + cos_int[s])
                        elif is_sin_col and is_sin_row:
                            val = 0.5 * (cos_int[ad] - cos_int[s])
                        elif is_sin_col:
                            # sin jθ cos kθ
                            sgn = 1.0 if d > 0 else (-1.0 if d < 0 else 0.0)
                            val = 0.5 * (sin_int[s] + sgn * sin_int[ad])
                        else:
                            # cos jθ sin kθ
                            sgn = 1.0 if d < 0 else (-1.0 if d > 0 else 0.0)
                            val = 0.5 * (sin_int[s] + sgn * sin_int[ad])
                        P[row, col] += kt * val * norm
                        col += 1
            row += 1


@jit
def aft_jenkins_events(params, harmonic_numbers, X, inverse, derivative, F, dF):
    """Event-located AFT of a Jenkins element, with analytic Jacobian.

    Parameters
    ----------
    params : ndarray, shape (2,)
        ``[tangential_stiffness, slip_force]``.
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
        Harmonics of ``X``.
    X : ndarray, shape (n_coef,)
        Displacement coefficients, m.
    inverse, derivative : ndarray, shape (n_time, n_coef)
        Inverse DFT matrix and its θ-derivative (used to detect events).
    F : ndarray, shape (n_coef,)
        Output: force coefficients, N (exact Fourier integrals).
    dF : ndarray, shape (n_coef, n_coef)
        Output: ``dF/dX``, N/m.

    Returns
    -------
    int
        ``STUCK``, ``GROSS_SLIP`` or ``EVENT_OVERFLOW``.
    """
    kt = params[0]
    slip_force = params[1]
    n_time, n_coef = inverse.shape
    F[:] = 0.0
    dF[:, :] = 0.0
    if slip_force == 0.0:
        return GROSS_SLIP
    two_pi = 2.0 * np.pi
    h = two_pi / n_time
    u = inverse @ X
    v = derivative @ X
    # global extremes: refine every sampled local extreme (sign change of
    # the sampled slope) and keep the largest and the smallest, so that two
    # nearly equal peaks cannot be confused
    i_max = np.argmax(u)
    i_min = np.argmin(u)
    th_max = i_max * h
    th_min = i_min * h
    u_max = u[i_max]
    u_min = u[i_min]
    for i in range(n_time):
        j = (i + 1) % n_time
        if v[i] > 0.0 and v[j] <= 0.0:
            th = _locate(harmonic_numbers, X, i * h, (i + 1) * h, 0.0, True)
            val = evaluate(harmonic_numbers, X, th)[0]
            if val > u_max:
                u_max = val
                th_max = th
                i_max = i
        elif v[i] < 0.0 and v[j] >= 0.0:
            th = _locate(harmonic_numbers, X, i * h, (i + 1) * h, 0.0, True)
            val = evaluate(harmonic_numbers, X, th)[0]
            if val < u_min:
                u_min = val
                th_min = th
                i_min = i
    basis_r = np.empty(n_coef)
    if kt * (u_max - u_min) <= 2.0 * slip_force:
        z, which = _stuck_slider(kt, slip_force, u_max, u_min)
        for r in range(n_coef):
            F[r] = kt * X[r]
            dF[r, r] = kt
        if which != 0 and harmonic_numbers[0] == 0:
            basis_at(harmonic_numbers, th_max if which == 1 else th_min, basis_r)
            F[0] -= kt * z
            for c in range(n_coef):
                dF[0, c] -= kt * basis_r[c]
        return STUCK

    m_max = 2 * harmonic_numbers[-1]
    cos_int = np.empty(m_max + 1)
    sin_int = np.empty(m_max + 1)
    P = np.zeros((n_coef, n_coef))
    theta_end = th_max + two_pi
    # start: just after the global maximum, stuck with f = +f_s
    stuck = True
    sign = 1.0
    z = u_max - slip_force / kt
    basis_at(harmonic_numbers, th_max, basis_r)
    seg_start = th_max
    prev = th_max
    prev_slope = 0.0
    n_events = 0
    # one sample more than a period: the refined maximum may lie after its
    # sample, and the last partial interval must be scanned too
    for j in range(1, n_time + 2):
        theta = (i_max + j) * h
        if theta <= seg_start:
            continue
        last = theta >= theta_end
        if last:
            theta = theta_end
        idx = (i_max + j) % n_time
        while True:
            if last:
                val, slope, _ = evaluate(harmonic_numbers, X, theta)
            else:
                val = u[idx]
                slope = v[idx]
            lo = prev if prev > seg_start else seg_start
            event = 0.0
            if stuck:
                g = kt * (val - z)
                # an extremum inside the interval may graze the slip limit
                # although both ends stay inside it
                # (a stick segment starts at a reversal, where u' = 0)
                slope_lo = prev_slope if prev > seg_start else 0.0
                if slope_lo * slope < 0.0 and abs(g) <= slip_force:
                    th_e = _locate(harmonic_numbers, X, lo, theta, 0.0, True)
                    g_e = kt * (evaluate(harmonic_numbers, X, th_e)[0] - z)
                    if abs(g_e) > slip_force:
                        theta_hit = th_e
                        g = g_e
                    else:
                        theta_hit = theta
                else:
                    theta_hit = theta
                if g > slip_force:
                    event = _locate(
                        harmonic_numbers, X, lo, theta_hit, z + slip_force / kt, False
                    )
                    new_sign = 1.0
                elif g < -slip_force:
                    event = _locate(
                        harmonic_numbers, X, lo, theta_hit, z - slip_force / kt, False
                    )
                    new_sign = -1.0
                else:
                    break
            else:
                if sign * slope >= 0.0 or last:
                    break
                event = _locate(harmonic_numbers, X, lo, theta, 0.0, True)
                new_sign = sign
            n_events += 1
            if n_events > 4 * n_time:
                return EVENT_OVERFLOW
            _segment_integrals(harmonic_numbers, seg_start, event, cos_int, sin_int)
            _add_segment(
                harmonic_numbers,
                cos_int,
                sin_int,
                stuck,
                sign,
                slip_force,
                kt,
                z,
                basis_r,
                P,
                F,
                dF,
            )
            seg_start = event
            if stuck:
                stuck = False
                sign = new_sign
            else:
                stuck = True
                basis_at(harmonic_numbers, event, basis_r)
                z = evaluate(harmonic_numbers, X, event)[0] - sign * slip_force / kt
        prev = theta
        prev_slope = slope
        if last:
            break
    _segment_integrals(harmonic_numbers, seg_start, theta_end, cos_int, sin_int)
    _add_segment(
        harmonic_numbers,
        cos_int,
        sin_int,
        stuck,
        sign,
        slip_force,
        kt,
        z,
        basis_r,
        P,
        F,
        dF,
    )
    for r in range(n_coef):
        acc = 0.0
        for c in range(n_coef):
            acc += P[r, c] * X[c]
            dF[r, c] += P[r, c]
        F[r] += acc
    return GROSS_SLIP
