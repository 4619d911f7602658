"""Fixed-step time integration of a linear structure with one contact to ground.

System: ``M ẍ + C ẋ + K x + e_c f_c(x_c) = p₀ + p_c cos Ωt + p_s sin Ωt``,
with ``e_c`` the unit vector of the contact DOF ``c`` and ``p₀`` a constant
load (``p₀`` enters through ``q₀ = 2 K_eff⁻¹ p₀``, the trapezoidal sum
``p₀ + p₀`` of a step; a load ``p cos(Ωt − φ)`` is ``p_c = p cos φ``,
``p_s = p sin φ``).

Scheme: Newmark's average-acceleration rule, which is the trapezoidal rule on
``(x, v)``: second order, unconditionally stable, no numerical damping.
Eliminating the acceleration, one step of length ``h`` reads

    K_eff x₁ = (K_eff - 2 K) x₀ + (4/h) M v₀ + p_c (cos Ωt₀ + cos Ωt₁)
               + p_s (sin Ωt₀ + sin Ωt₁) - e_c (f₀ + f₁),
    v₁ = (2/h)(x₁ - x₀) - v₀,         K_eff = (4/h²) M + (2/h) C + K,

so with ``S = K_eff⁻¹`` factorised once (by the caller) every step is

    x_lin = x₀ + A x₀ + B v₀ + q_c (cos Ωt₀ + cos Ωt₁)
            + q_s (sin Ωt₀ + sin Ωt₁) - g f₀,
    A = -2 S K,  B = (4/h) S M,  q_c,s = S p_c,s,  g = S e_c,

two matrix-vector products, then a scalar equation for the contact DOF

    u + g_c f(u) = x_lin[c],     f(u) = law_step(code, params, state₀, u₀, u),

and ``x₁ = x_lin - g f₁``. The contact force is therefore implicit and
updated exactly at every step instant: the law is evaluated only through
:func:`hbmfric.kernels.laws.updates.law_step`, the contract the AFT march of the
harmonic balance uses too (the law state, whose first entry is the force, is
advanced once the step is solved). The scalar equation is solved by Newton's method
on ``df/du`` with a bisection safeguard; for the piecewise-linear Jenkins law
Newton ends on the right branch after at most two steps, to rounding.

The state carried from step to step is ``(x, v, law state)``; the acceleration is
never formed. Kernels report problems by the status codes below.
"""

import numpy as np

from .._jit import jit
from ..kernels.laws.updates import is_masing, law_step, law_update

#: law code meaning "no contact" (``g`` and the contact force are ignored)
NO_CONTACT = -1

#: status codes returned by the kernels
OK = 0
NEWTON_FAILED = 1
NOT_FINITE = 2

MESSAGES = {
    OK: "ok",
    NEWTON_FAILED: "the contact update (scalar Newton) did not converge",
    NOT_FINITE: "the state became non-finite (NaN or inf)",
}

#: Newton iterations allowed for one contact update
MAX_CONTACT_ITERATIONS = 60
#: relative residual at which the contact update is accepted
CONTACT_RTOL = 1e-14


@jit
def _newton_update(u, phi, df_du, g_c, lo, hi):
    """One Newton step on ``u + g_c f(u) = target`` (residual ``phi``), kept
    inside the bracket ``(lo, hi)`` that the residual signs define
    (bisection when the step leaves it or the slope is not positive).

    Returns ``(u_new, lo, hi)``.
    """
    if phi > 0.0:
        hi = min(hi, u)
    else:
        lo = max(lo, u)
    slope = 1.0 + g_c * df_du
    u_new = u - phi / slope if slope > 0.0 else u - phi
    if not (lo < u_new < hi) and lo > -np.inf and hi < np.inf:
        u_new = 0.5 * (lo + hi)
    return u_new, lo, hi


@jit
def contact_update(code, params, f_prev, u_prev, target, g_c):
    """Solve ``u + g_c f(u) = target`` for a scalar-state law.

    ``f(u) = law_update(code, params, f_prev, u_prev, u)`` (the law's state
    is its force, so this is :func:`hbmfric.kernels.laws.updates.law_step` without
    an array); Newton's method from ``u_prev`` (the stick predictor) through
    :func:`_newton_update`. :func:`contact_update_state` is the same for
    laws with a state array.

    Parameters
    ----------
    code : int
        Law code.
    params : ndarray, shape (n_params,)
        Law parameters.
    f_prev, u_prev : float
        Contact force (N) and displacement (m) at the start of the step.
    target : float
        Contact displacement the step would reach without the contact
        force, m.
    g_c : float
        Compliance of the step at the contact DOF, ``(K_eff⁻¹)_cc``, m/N
        (> 0).

    Returns
    -------
    u : float
        Contact displacement at the end of the step, m.
    f : float
        Contact force at ``u``, N.
    iterations : int
        Newton (or bisection) updates of ``u``.
    converged : bool
    """
    u = u_prev
    f, _, _, df_du = law_update(code, params, f_prev, u_prev, u)
    phi = u + g_c * f - target
    # the residual is a difference of terms as large as the start values:
    # its rounding floor scales with them too, not only with the new ones
    # (a contact crossing u = 0 would otherwise ask for a relative 1e-14 of
    # a value 1e7 times smaller than the terms it is computed from)
    base = abs(u_prev) + abs(g_c * f)
    if abs(phi) <= CONTACT_RTOL * (abs(target) + 2.0 * base):
        return u, f, 0, True
    lo = -np.inf
    hi = np.inf
    for iteration in range(1, MAX_CONTACT_ITERATIONS + 1):
        u_new, lo, hi = _newton_update(u, phi, df_du, g_c, lo, hi)
        f, _, _, df_du = law_update(code, params, f_prev, u_prev, u_new)
        phi = u_new + g_c * f - target
        scale = abs(u_new) + abs(target) + abs(g_c * f) + base
        if abs(phi) <= CONTACT_RTOL * scale:
            return u_new, f, iteration, True
        if u_new == u:
            # stagnation at rounding level
            return u, f, iteration, abs(phi) <= 1e3 * CONTACT_RTOL * scale
        u = u_new
    return u, f, MAX_CONTACT_ITERATIONS, False


@jit
def contact_update_state(code, params, state, u_prev, target, g_c):
    """:func:`contact_update` for a law with a state array (Masing laws).

    ``f(u) = law_step(code, params, state, u_prev, u)``; on convergence
    ``state`` (shape ``(state_size(code, params),)``, ``state[0]`` the
    force) is advanced in place to the returned ``u``. Same returns as
    :func:`contact_update`.
    """
    u = u_prev
    f, df_du = law_step(code, params, state, u_prev, u, False)
    phi = u + g_c * f - target
    base = abs(u_prev) + abs(g_c * f)  # see contact_update
    if abs(phi) <= CONTACT_RTOL * (abs(target) + 2.0 * base):
        law_step(code, params, state, u_prev, u, True)
        return u, f, 0, True
    lo = -np.inf
    hi = np.inf
    for iteration in range(1, MAX_CONTACT_ITERATIONS + 1):
        u_new, lo, hi = _newton_update(u, phi, df_du, g_c, lo, hi)
        f, df_du = law_step(code, params, state, u_prev, u_new, False)
        phi = u_new + g_c * f - target
        scale = abs(u_new) + abs(target) + abs(g_c * f) + base
        if abs(phi) <= CONTACT_RTOL * scale:
            law_step(code, params, state, u_prev, u_new, True)
            return u_new, f, iteration, True
        if u_new == u:
            ok = abs(phi) <= 1e3 * CONTACT_RTOL * scale
            if ok:
                law_step(code, params, state, u_prev, u, True)
            return u, f, iteration, ok
        u = u_new
    return u, f, MAX_CONTACT_ITERATIONS, False


@jit
def _period(system, x, v, law_state, x_new, peaks, record, samples, contact_force):
    """Advance ``(x, v, law state)`` over one forcing period, in place.

    ``peaks`` receives ``max |x|``, ``max |v|`` (over all DOFs) and
    ``max |f|`` over the step instants of the period; with ``record`` the
    displacements and contact force at the ``N`` step instants (period start
    included, end excluded) go to ``samples`` and ``contact_force``.

    Returns ``(status, newton_iterations)``.
    """
    (
        A_t,
        B_t,
        q,
        q0,
        g,
        cos_sum,
        contact_dof,
        law_code,
        law_params,
        two_over_h,
    ) = system
    n = x.size
    n_steps = cos_sum.shape[1]
    has_contact = law_code != NO_CONTACT
    with_state = has_contact and is_masing(law_code)
    f = law_state[0]
    x_peak = 0.0
    v_peak = 0.0
    f_peak = abs(f)
    for i in range(n):
        x_peak = max(x_peak, abs(x[i]))
        v_peak = max(v_peak, abs(v[i]))
    check = 0.0
    iterations = 0
    for step in range(n_steps):
        if record:
            for i in range(n):
                samples[i, step] = x[i]
            contact_force[step] = f
        s_c = cos_sum[0, step]
        s_s = cos_sum[1, step]
        for i in range(n):
            x_new[i] = x[i] + q[0, i] * s_c + q[1, i] * s_s + q0[i] - g[i] * f
        # column by column (rows of the transposes): contiguous, vectorised
        for j in range(n):
            x_j = x[j]
            v_j = v[j]
            for i in range(n):
                x_new[i] += A_t[j, i] * x_j + B_t[j, i] * v_j
        if has_contact:
            if with_state:
                u, f_new, its, ok = contact_update_state(
                    law_code,
                    law_params,
                    law_state,
                    x[contact_dof],
                    x_new[contact_dof],
                    g[contact_dof],
                )
            else:
                u, f_new, its, ok = contact_update(
                    law_code,
                    law_params,
                    f,
                    x[contact_dof],
                    x_new[contact_dof],
                    g[contact_dof],
                )
                law_state[0] = f_new
            iterations += its
            if not ok:
                if not np.isfinite(x_new[contact_dof]):
                    return NOT_FINITE, iterations
                return NEWTON_FAILED, iterations
            for i in range(n):
                x_new[i] -= g[i] * f_new
            # the law state belongs to u: keep x_c exactly the u it was given
            x_new[contact_dof] = u
            f = f_new
            f_peak = max(f_peak, abs(f))
        for i in range(n):
            v_i = two_over_h * (x_new[i] - x[i]) - v[i]
            v[i] = v_i
            x[i] = x_new[i]
            ax = abs(x_new[i])
            av = abs(v_i)
            x_peak = max(x_peak, ax)
            v_peak = max(v_peak, av)
            check += ax + av
        check += abs(f)
    peaks[0] = x_peak
    peaks[1] = v_peak
    peaks[2] = f_peak
    if not np.isfinite(check):
        return NOT_FINITE, iterations
    return OK, iterations


@jit
def newmark_periods(system, x, v, law_state, x_new, starts, peaks):
    """Integrate whole forcing periods and record the state at each start.

    Parameters
    ----------
    system : tuple
        ``(A_t, B_t, q, q0, g, cos_sum, contact_dof, law_code, law_params,
        two_over_h)``, the operators of one step size, entry by entry:
    A_t : ndarray, shape (n_dof, n_dof)
        Transpose of ``A = -2 K_eff⁻¹ K`` (dimensionless), C-contiguous, so
        that ``A x`` runs over contiguous memory column by column.
    B_t : ndarray, shape (n_dof, n_dof)
        Transpose of ``B = (4/h) K_eff⁻¹ M``, s.
    q : ndarray, shape (2, n_dof)
        ``K_eff⁻¹ p_c`` and ``K_eff⁻¹ p_s``, m (per unit of ``cos``, ``sin``).
    q0 : ndarray, shape (n_dof,)
        ``2 K_eff⁻¹ p₀``, m (constant load; zeros without one).
    g : ndarray, shape (n_dof,)
        ``K_eff⁻¹ e_c``, m/N (zeros without contact).
    cos_sum : ndarray, shape (2, N)
        ``cos Ωt_k + cos Ωt_{k+1}`` and ``sin Ωt_k + sin Ωt_{k+1}`` for the
        ``N`` steps of a period.
    contact_dof : int
        DOF of the contact to ground.
    law_code : int
        Law code, ``NO_CONTACT`` for none.
    law_params : ndarray, shape (n_params,)
        Law parameters.
    two_over_h : float
        ``2/h``, 1/s.
    x, v : ndarray, shape (n_dof,)
        Displacement (m) and velocity (m/s) at a period start; advanced in
        place.
    law_state : ndarray, shape (state_size(law_code, law_params),)
        Contact-law state at ``x[contact_dof]`` (``law_state[0]`` the contact
        force, N); advanced in place.
    x_new : ndarray, shape (n_dof,)
        Workspace.
    starts : ndarray, shape (n_periods + 1, 2 n_dof + 1)
        Output: ``[x, v, f]`` at the start of each period, row 0 the input
        state, row ``p`` the state after ``p`` periods.
    peaks : ndarray, shape (n_periods, 3)
        Output: ``max |x|``, ``max |v|``, ``max |f|`` over each period.

    Returns
    -------
    status : int
        ``OK``, ``NEWTON_FAILED`` or ``NOT_FINITE``.
    periods : int
        Periods completed (``n_periods`` unless the status is not ``OK``).
    newton_iterations : int
        Contact-update iterations, summed over all steps.
    """
    n = x.size
    n_periods = peaks.shape[0]
    no_samples = np.empty((0, 0))
    no_forces = np.empty(0)
    _store_state(starts, 0, x, v, law_state[0], n)
    iterations = 0
    for period in range(n_periods):
        status, its = _period(
            system, x, v, law_state, x_new, peaks[period], False, no_samples, no_forces
        )
        iterations += its
        if status != OK:
            return status, period, iterations
        _store_state(starts, period + 1, x, v, law_state[0], n)
    return OK, n_periods, iterations


@jit
def record_period(system, x, v, law_state, x_new, peaks, samples, contact_force):
    """Integrate one period and record it at the step instants.

    Arguments as :func:`newmark_periods`, except:

    Parameters
    ----------
    peaks : ndarray, shape (3,)
        Output: ``max |x|``, ``max |v|``, ``max |f|`` over the period.
    samples : ndarray, shape (n_dof, N)
        Output: displacements at ``t_k = k T / N``, ``k = 0 … N-1``, m.
    contact_force : ndarray, shape (N,)
        Output: contact force at the same instants, N.

    Returns
    -------
    status : int
    newton_iterations : int
    """
    return _period(system, x, v, law_state, x_new, peaks, True, samples, contact_force)


@jit
def _store_state(starts, row, x, v, f, n):
    for i in range(n):
        starts[row, i] = x[i]
        starts[row, n + i] = v[i]
    starts[row, 2 * n] = f
