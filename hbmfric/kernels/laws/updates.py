"""Contact laws as time-domain updates, selected by integer codes.

The law contract
----------------
A law is an integer ``code``, a flat float64 ``params`` array and a flat
float64 ``state`` array of ``state_size(code, params)`` entries whose first
entry is always the contact force, ``state[0] = f``. Everything that marches a
law (the AFT of the harmonic balance, the time-integration reference) goes
through these functions, so that the two paths share one definition of each
law:

``law_init(code, params, u0, state)``
    The virgin law (contact closed at ``u = 0`` with no force) moved to
    ``u0``; writes ``state`` and returns ``(f, df/du)``.
``law_step(code, params, state, u_prev, u, commit)``
    The force at ``u`` given the state at ``u_prev``, and ``df/du`` at fixed
    history; with ``commit=True`` the state is advanced to ``u`` in place
    (trial evaluations, such as the Newton iterations of an implicit time
    step, pass ``commit=False`` and leave it untouched).

Two families implement it:

* **scalar-state laws** (the state is the force alone): ``law_update(code,
  params, f_prev, u_prev, u)`` returns the new force and its partials with
  respect to ``f_prev``, ``u_prev`` and ``u`` (the AFT carries its Jacobian
  through them). A new law of this kind is one more branch in
  :func:`law_update` and nothing else; ``law_step`` delegates to it, and the
  time integrator calls it directly for these laws (the force as a float in
  its inner loop: same definition, no state array).
* **Masing laws** with Madelung memory (``MENQ``, ``IWAN``): a virgin loading
  curve ``F_load(δ)`` (:func:`virgin_curve`) and Masing's rule applied from
  the last reversal point, ``F = F_r + 2 s F_load(s (u - u_r) / 2)`` with ``s``
  the direction of travel, with a stack of reversal points so that inner
  loops close exactly: when the displacement passes the reversal point below
  the top of the stack, both are forgotten and the older branch continues
  (:func:`masing_step`). The virgin curve itself is the bottom of the stack:
  a branch that reaches the mirror image ``-u_1`` of the first reversal
  point rejoins it.

Masing state layout: ``state = [f, depth, direction, hint_x, hint_delta,
hint_slope, u_1, F_1, tag_1, u_2, F_2, tag_2, …]`` with ``depth`` reversal
points stored, ``direction`` the sign of the last movement (0 before any),
three ``hint`` entries that warm-start the inversion of the virgin curve (no
effect on the result beyond rounding, see :func:`menq_virgin`), and
``tag`` an identifier of each reversal given by the caller (the AFT stores
the index of the marched point there, to find ``df_r/dX`` for its
Jacobian). The capacity is
``(state.size - 6) // 3`` reversal points; when a push would exceed it, the
oldest pair (the outermost loop, reached again only if the motion grows back
beyond it) is dropped. ``state_size`` allows :data:`MEMORY_CAPACITY` points,
plenty for a decaying transient; the AFT sizes its own state for one period,
where nothing is ever dropped.

Law codes and their parameter arrays
------------------------------------
``JENKINS`` (Masing macroslip): ``params = [tangential_stiffness, slip_force]``
    A spring ``kt`` in series with a Coulomb slider (slip force ``f_s``).
    Predictor ``f = f_prev + kt (u - u_prev)``, then ``|f| <= f_s``.
``CUBIC`` (smooth, memoryless): ``params = [coefficient]``
    ``f = k3 u**3``.
``MENQ`` (microslip of an elastic bar on an elastic shear layer, docs/laws.md):
    ``params = [δ1, λ, F_q, K0, δ_gs, F*]`` with ``δ1 = q/k_s`` the end of
    the stuck (linear) range, ``λ = αL`` (``α = √(k_s/EA)``),
    ``F_q = q/α``, ``K0 = F_q tanh(λ)/δ1`` the stuck stiffness,
    ``δ_gs = δ1 (1 + λ²/2)`` the start of gross slip and ``F* = F_q λ = qL``
    the gross-slip force. With ``x = α l`` the dimensionless slip length,
    the microslip part of the virgin curve is
    ``δ = δ1 (1 + x²/2 + x tanh(λ - x))``, ``F = F_q (x + tanh(λ - x))``.
``IWAN`` (parallel Jenkins elements, sorted by slip displacement
    ``φ_e = f_e/k_e``): ``params = [n, φ_1 … φ_n, C_0 … C_n, R_0 … R_n]``
    with ``C_j = Σ_{e<j} f_e`` the force of the slipped elements and
    ``R_j = Σ_{e≥j} k_e`` the stiffness of the stuck ones when
    ``φ_j ≤ δ < φ_{j+1}``, so ``F_load(δ) = C_j + R_j δ``.
``DAHL`` (modified Dahl restoring force): ``params = [β, μ, a, b, d, e]``
    Rate-independent relaxation towards the envelopes ``h_u = a u + b``
    (loading) and ``h_l = d u + e`` (unloading); see
    :mod:`hbmfric.kernels.laws.dahl`.
"""

import numpy as np

from ..._jit import jit
from .dahl import dahl_update

JENKINS = 0
CUBIC = 1
DAHL = 2
MENQ = 4
IWAN = 5

#: laws whose force depends on the displacement history
HYSTERETIC = (JENKINS, DAHL, MENQ, IWAN)
#: laws defined by a virgin curve, Masing's rule and Madelung's memory
MASING = (MENQ, IWAN)

STICK = 0
SLIP = 1

#: reversal points a Masing state from :func:`state_size` can hold
MEMORY_CAPACITY = 64
#: header entries of a Masing state before the reversal points
MASING_HEADER = 6
#: entries per reversal point ``(u_r, F_r, tag_r)``
MASING_ENTRY = 3

#: relative step at which the Menq inversion stops (Newton is quadratic, so
#: the returned slip length is exact to rounding)
_MENQ_XTOL = 1e-8


@jit
def law_update(code, params, f_prev, u_prev, u):
    """Advance a scalar-state contact law from ``u_prev`` to ``u``.

    Parameters
    ----------
    code : int
        Law code (``JENKINS``, ``CUBIC``).
    params : ndarray, shape (n_params,)
        Law parameters, see the module docstring.
    f_prev : float
        Force at ``u_prev``, N (ignored by memoryless laws).
    u_prev, u : float
        Relative displacement before and after the increment, m.

    Returns
    -------
    f : float
        Force at ``u``, N.
    df_dfprev, df_duprev, df_du : float
        Partial derivatives of ``f`` with respect to ``f_prev``, ``u_prev``
        and ``u``; they drive the analytic AFT Jacobian.
    """
    if code == JENKINS:
        kt = params[0]
        slip_force = params[1]
        trial = f_prev + kt * (u - u_prev)
        if trial > slip_force:
            return slip_force, 0.0, 0.0, 0.0
        if trial < -slip_force:
            return -slip_force, 0.0, 0.0, 0.0
        return trial, 1.0, -kt, kt
    if code == DAHL:
        return dahl_update(params, f_prev, u_prev, u)
    # CUBIC
    k3 = params[0]
    return k3 * u * u * u, 0.0, 0.0, 3.0 * k3 * u * u


@jit
def is_masing(code):
    """True for laws given by a virgin curve and Masing's rule."""
    return code == MENQ or code == IWAN


@jit
def linear_stiffness(code, params):
    """Tangent stiffness of the law at rest (stuck contact), N/m."""
    if code == JENKINS:
        return params[0]
    if code == MENQ:
        return params[3]
    if code == IWAN:
        n = int(params[0])
        return params[2 + 2 * n]
    if code == DAHL:
        # small-loop stiffness at u = 0: β ((b - e) / 2)^μ
        return params[0] * max(0.5 * (params[3] - params[5]), 0.0) ** params[1]
    return 0.0


@jit
def linear_limit(code, params):
    """Half-range of displacement over which a Masing law (or Jenkins)
    stays linear: the end of the stuck part of its virgin curve, m."""
    if code == JENKINS:
        return params[1] / params[0]
    if code == MENQ:
        return params[0]
    if code == IWAN:
        return params[1]
    return 0.0


@jit
def slip_limit(code, params):
    """Start of gross slip on the virgin curve, m (``F_load`` constant
    beyond it)."""
    if code == JENKINS:
        return params[1] / params[0]
    if code == MENQ:
        return params[4]
    if code == IWAN:
        n = int(params[0])
        return params[n]
    return np.inf


@jit
def _menq_cold_guess(lam, c):
    """A lower bound of the Menq slip length at ``δ/δ1 - 1 = c`` (from
    ``tanh y <= 1`` and ``tanh y <= y``)."""
    x = max(
        np.sqrt(1.0 + 2.0 * c) - 1.0,
        lam - np.sqrt(max(lam * lam - 2.0 * c, 0.0)),
    )
    return x if x < lam else 0.5 * lam


@jit
def menq_virgin(params, delta, hint_x, hint_delta, hint_slope):
    """Menq virgin curve at ``δ >= 0`` with a warm-started inversion.

    In microslip the dimensionless slip length ``x`` solves
    ``g(x) = x²/2 + x tanh(λ - x) - (δ/δ1 - 1) = 0`` in ``(0, λ)``: Newton's
    method kept inside a shrinking bracket (bisection when a step leaves
    it), started from a tangent step off the previous solution (the hint)
    when there is one. It stops when the Newton step falls below
    ``1e-8 (1 + x)`` and evaluates ``F`` and ``dF/dδ`` at the stepped point
    by a first-order correction, so the result is exact to rounding
    (quadratic convergence) at one ``exp`` per iteration, typically two per
    call along a sampled path.

    Parameters
    ----------
    params : ndarray, shape (6,)
        Menq parameters (module docstring).
    delta : float
        Displacement from the virgin state, m, >= 0.
    hint_x, hint_delta, hint_slope : float
        A previous solution ``x`` (anything outside ``(0, λ)`` for none),
        its ``δ`` and ``dg/dx`` there; they only speed the iteration up.

    Returns
    -------
    F, k : float
        ``F_load(δ)`` (N) and ``dF_load/dδ`` (N/m).
    hint_x, hint_delta, hint_slope : float
        Updated hint.
    """
    d1 = params[0]
    lam = params[1]
    if delta <= d1:
        return params[3] * delta, params[3], hint_x, hint_delta, hint_slope
    if delta >= params[4]:
        return params[5], 0.0, hint_x, hint_delta, hint_slope
    fq = params[2]
    c = delta / d1 - 1.0
    lo = 0.0
    hi = lam
    x = -1.0
    if 0.0 < hint_x < lam and hint_slope > 0.0:
        x = hint_x + (delta - hint_delta) / (d1 * hint_slope)
    if not 0.0 < x < lam:
        x = _menq_cold_guess(lam, c)
    for _ in range(200):
        e = np.exp(-2.0 * (lam - x))
        t = (1.0 - e) / (1.0 + e)
        w = 1.0 + x * t
        g = x * (0.5 * x + t) - c
        dg = t * w
        if g > 0.0:
            hi = x
        elif g < 0.0:
            lo = x
        step = g / dg if dg > 0.0 else np.inf
        new = x - step
        if abs(step) <= _MENQ_XTOL * (1.0 + x):
            # F' = F_q t², (t/w)' = -1/w²: first-order move to the root
            F = fq * (x + t - t * t * step)
            k = (fq / d1) * (t / w + step / (w * w))
            return F, k, new, delta, dg
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
            if hi - lo <= 1e-15 * lam:
                break
        x = new
    e = np.exp(-2.0 * (lam - x))
    t = (1.0 - e) / (1.0 + e)
    return fq * (x + t), (fq / d1) * t / (1.0 + x * t), x, delta, t * (1.0 + x * t)


@jit
def menq_slip_length(params, delta):
    """Dimensionless slip length ``x = α l`` of the Menq virgin curve at
    ``δ1 < δ < δ_gs`` (see :func:`menq_virgin`)."""
    return menq_virgin(params, delta, -1.0, 0.0, 0.0)[2]


@jit
def virgin_curve(code, params, delta, hint_x, hint_delta, hint_slope):
    """Virgin loading curve of a Masing law at ``δ >= 0``.

    Parameters
    ----------
    code : int
        ``MENQ`` or ``IWAN``.
    params : ndarray
        Law parameters.
    delta : float
        Displacement from the virgin state, m, >= 0.
    hint_x, hint_delta, hint_slope : float
        Warm start of the Menq inversion (see :func:`menq_virgin`; pass
        ``-1, 0, 0`` for none); ignored by Iwan.

    Returns
    -------
    F : float
        ``F_load(δ)``, N.
    k : float
        ``dF_load/dδ``, N/m.
    hint_x, hint_delta, hint_slope : float
        Updated hint.
    """
    if code == MENQ:
        return menq_virgin(params, delta, hint_x, hint_delta, hint_slope)
    # IWAN: elements with φ <= δ have slipped
    n = int(params[0])
    lo = 0
    hi = n
    while lo < hi:
        mid = (lo + hi) // 2
        if params[1 + mid] <= delta:
            lo = mid + 1
        else:
            hi = mid
    k = params[2 + 2 * n + lo]
    return params[1 + n + lo] + k * delta, k, hint_x, hint_delta, hint_slope


@jit
def masing_step(code, params, state, u_prev, u, tag, commit):
    """Masing's rule with Madelung's memory from ``u_prev`` to ``u``.

    Parameters
    ----------
    code : int
        ``MENQ`` or ``IWAN``.
    params : ndarray
        Law parameters.
    state : ndarray, shape (6 + 3 capacity,)
        Masing state at ``u_prev`` (layout in the module docstring);
        advanced in place to ``u`` when ``commit``.
    u_prev, u : float
        Displacement before and after the increment, m.
    tag : float
        Identifier stored with ``u_prev`` if it becomes a reversal point.
    commit : bool
        Advance ``state``.

    Returns
    -------
    f : float
        Force at ``u``, N.
    df_du : float
        Tangent stiffness at fixed history, N/m.
    top : int
        Index of the reversal point whose branch gives ``f`` (-1: the
        virgin curve). The force is ``F_top + 2 s F_load(s (u - u_top)/2)``,
        so ``df/du_top = -df_du`` and ``df/dF_top = 1``.
    """
    f_prev = state[0]
    depth = int(state[1])
    direction = state[2]
    d = u - u_prev
    s = direction
    if d > 0.0:
        s = 1.0
    elif d < 0.0:
        s = -1.0
    push = direction != 0.0 and s != direction
    top = depth if push else depth - 1
    # Madelung: a branch that reaches the reversal point below its origin
    # closes that inner loop, and the older branch continues
    while top >= 0:
        if top == 0:
            u_first = u_prev if push and depth == 0 else state[MASING_HEADER]
            if s * (u + u_first) >= 0.0:
                top = -1
            break
        below = MASING_HEADER + MASING_ENTRY * (top - 1)
        if s * (u - state[below]) >= 0.0:
            top -= 2
        else:
            break
    hx = state[3]
    hd = state[4]
    hs = state[5]
    if top < 0:
        F, k, hx, hd, hs = virgin_curve(code, params, abs(u), hx, hd, hs)
        f = F if u >= 0.0 else -F
    else:
        if push and top == depth:
            u_r = u_prev
            f_r = f_prev
        else:
            at = MASING_HEADER + MASING_ENTRY * top
            u_r = state[at]
            f_r = state[at + 1]
        F, k, hx, hd, hs = virgin_curve(code, params, 0.5 * s * (u - u_r), hx, hd, hs)
        f = f_r + 2.0 * s * F
    if commit:
        new_depth = top + 1
        if push and top >= depth:
            at = MASING_HEADER + MASING_ENTRY * depth
            capacity = (state.size - MASING_HEADER) // MASING_ENTRY
            if depth == capacity:
                # full: forget the oldest (outermost) loop
                for i in range(MASING_HEADER, state.size - 2 * MASING_ENTRY):
                    state[i] = state[i + 2 * MASING_ENTRY]
                at -= 2 * MASING_ENTRY
                new_depth -= 2
                top -= 2
            state[at] = u_prev
            state[at + 1] = f_prev
            state[at + 2] = tag
        state[0] = f
        state[1] = new_depth
        state[2] = s
        state[3] = hx
        state[4] = hd
        state[5] = hs
    return f, k, top


@jit
def state_size(code, params):
    """Length of the state array of a law (``state[0]`` is the force)."""
    if code == MENQ or code == IWAN:
        return MASING_HEADER + MASING_ENTRY * MEMORY_CAPACITY
    return 1


@jit
def law_init(code, params, u0, state):
    """Virgin law (closed at ``u = 0`` with no force) moved to ``u0``.

    Parameters
    ----------
    code : int
        Law code.
    params : ndarray
        Law parameters.
    u0 : float
        Displacement, m.
    state : ndarray, shape (state_size(code, params),)
        Output: the law state at ``u0``.

    Returns
    -------
    f : float
        Force at ``u0``, N.
    df_du : float
        Tangent stiffness there, N/m.
    """
    if code == MENQ or code == IWAN:
        state[:] = 0.0
        F, k, hx, hd, hs = virgin_curve(code, params, abs(u0), -1.0, 0.0, 0.0)
        f = F if u0 >= 0.0 else -F
        state[0] = f
        state[2] = 1.0 if u0 > 0.0 else (-1.0 if u0 < 0.0 else 0.0)
        state[3] = hx
        state[4] = hd
        state[5] = hs
        return f, k
    f, _, _, k = law_update(code, params, 0.0, 0.0, u0)
    state[0] = f
    return f, k


@jit
def law_step(code, params, state, u_prev, u, commit):
    """Force at ``u`` from the law state at ``u_prev``.

    Parameters
    ----------
    code : int
        Law code.
    params : ndarray
        Law parameters.
    state : ndarray, shape (state_size(code, params),)
        State at ``u_prev`` (``state[0]`` the force there); advanced in place
        to ``u`` when ``commit``.
    u_prev, u : float
        Displacement before and after the increment, m.
    commit : bool
        Advance ``state``.

    Returns
    -------
    f : float
        Force at ``u``, N.
    df_du : float
        ``df/du`` at fixed history, N/m.
    """
    if code == MENQ or code == IWAN:
        f, k, _ = masing_step(code, params, state, u_prev, u, 0.0, commit)
        return f, k
    f, _, _, k = law_update(code, params, state[0], u_prev, u)
    if commit:
        state[0] = f
    return f, k
