"""Fixed-step time integration of a linear structure with one contact.

System: ``M ẍ + C ẋ + K x + e_c f_c(x_c) = p cos(Ω t)``. Scheme: Newmark's
average-acceleration rule (trapezoidal, second order, unconditionally
stable). The contact force enters implicitly: each step solves the scalar
equation of the contact DOF,

    u + g_c f(u) = x_lin,c ,     f(u) = law_update(code, params, f_n, u_n, u),

by a safeguarded Newton iteration, where ``x_lin`` is the step's solution
without the contact force and ``g = K_eff⁻¹ e_c``. The law is evaluated only
through :func:`hbmfric.kernels.laws.law_update`, the same function the AFT
march uses. For Jenkins the update is piecewise linear, so the iteration
ends exactly on the right branch.
"""

import numpy as np

from .._jit import jit
from ..kernels.laws import law_update

OK = 0
NEWTON_FAILED = 1
NOT_FINITE = 2

MESSAGES = {
    OK: "ok",
    NEWTON_FAILED: "contact update did not converge",
    NOT_FINITE: "non-finite state",
}


@jit
def _contact_solve(code, params, f_prev, u_prev, x_lin_c, g_c, u0):
    """Solve ``u + g_c f(u) = x_lin_c`` for the contact displacement ``u``.

    Returns ``(u, f, converged)``.
    """
    u = u0
    lo = -np.inf
    hi = np.inf
    for _ in range(60):
        f, _, _, df_du = law_update(code, params, f_prev, u_prev, u)
        phi = u + g_c * f - x_lin_c
        if phi > 0.0:
            hi = min(hi, u)
        else:
            lo = max(lo, u)
        dphi = 1.0 + g_c * df_du
        new = u - phi / dphi if dphi > 0.0 else 0.5 * (lo + hi)
        if not (lo <= new <= hi) and np.isfinite(lo) and np.isfinite(hi):
            new = 0.5 * (lo + hi)
        if abs(new - u) <= 1e-15 * (abs(u) + abs(x_lin_c)) + 1e-300:
            f = law_update(code, params, f_prev, u_prev, new)[0]
            return new, f, True
        u = new
    f = law_update(code, params, f_prev, u_prev, u)[0]
    return u, f, abs(u + g_c * f - x_lin_c) <= 1e-10 * (abs(x_lin_c) + 1e-300)


@jit
def initial_acceleration(
    mass, damping, stiffness, load, contact_dof, law_code, law_params, x, v, f
):
    """Acceleration at t = 0 from the equation of motion (``f`` contact
    force, N)."""
    rhs = load - damping @ v - stiffness @ x
    if law_code >= 0:
        rhs[contact_dof] -= f
    return np.linalg.solve(mass, rhs)


@jit
def newmark_periods(
    mass,
    damping,
    stiffness,
    load,
    contact_dof,
    law_code,
    law_params,
    omega,
    steps_per_period,
    max_periods,
    tol,
    x,
    v,
    a,
    force_state,
    samples,
):
    """Integrate whole forcing periods until the periodic steady state.

    Parameters
    ----------
    mass, damping, stiffness : ndarray, shape (n_dof, n_dof)
    load : ndarray, shape (n_dof,)
        Amplitude of the ``cos(Ω t)`` forcing per DOF, N.
    contact_dof : int
        DOF of the contact (to ground).
    law_code : int
        Law code, ``-1`` for no contact.
    law_params : ndarray
        Law parameters.
    omega : float
        Forcing pulsation, rad/s.
    steps_per_period : int
        Time steps per forcing period.
    max_periods : int
        Upper limit on integrated periods.
    tol : float
        Steady state: the relative change of ``x``, ``v`` and the contact
        force between successive period starts is below ``tol``.
    x, v, a : ndarray, shape (n_dof,)
        State at t = 0 (multiple of the period); updated in place.
    force_state : ndarray, shape (1,)
        Contact force at the start; updated in place.
    samples : ndarray, shape (n_dof + 1, steps_per_period)
        Output: displacements (rows ``0 … n_dof-1``) and contact force (last
        row) at the step instants of the last period.

    Returns
    -------
    status : int
    periods : int
        Periods integrated.
    change : float
        Last period-to-period relative change.
    """
    n = x.size
    h = 2.0 * np.pi / omega / steps_per_period
    k_eff = stiffness + (2.0 / h) * damping + (4.0 / (h * h)) * mass
    k_inv = np.linalg.inv(k_eff)
    g = k_inv[:, contact_dof].copy()
    g_c = g[contact_dof]
    has_contact = law_code >= 0
    f = force_state[0]
    rhs = np.empty(n)
    x_new = np.empty(n)
    x_start = x.copy()
    v_start = v.copy()
    change = np.inf
    for period in range(1, max_periods + 1):
        x_start[:] = x
        v_start[:] = v
        f_start = f
        x_peak = 0.0
        f_peak = 0.0
        for step in range(steps_per_period):
            for d in range(n):
                samples[d, step] = x[d]
            samples[n, step] = f
            t1 = (step + 1) * h
            c1 = np.cos(omega * t1)
            # rhs = p1 + M (4/h² x + 4/h v + a) + C (2/h x + v)
            for i in range(n):
                acc = load[i] * c1
                for j in range(n):
                    acc += mass[i, j] * (
                        (4.0 / (h * h)) * x[j] + (4.0 / h) * v[j] + a[j]
                    ) + damping[i, j] * ((2.0 / h) * x[j] + v[j])
                rhs[i] = acc
            for i in range(n):
                acc = 0.0
                for j in range(n):
                    acc += k_inv[i, j] * rhs[j]
                x_new[i] = acc
            if has_contact:
                u_prev = x[contact_dof]
                u, f_new, ok = _contact_solve(
                    law_code, law_params, f, u_prev, x_new[contact_dof], g_c, u_prev
                )
                if not ok:
                    return NEWTON_FAILED, period, change
                for i in range(n):
                    x_new[i] -= g[i] * f_new
                x_new[contact_dof] = u
                f = f_new
            for i in range(n):
                a_new = (4.0 / (h * h)) * (x_new[i] - x[i]) - (4.0 / h) * v[i] - a[i]
                v[i] = v[i] + 0.5 * h * (a[i] + a_new)
                a[i] = a_new
                x[i] = x_new[i]
                if abs(x[i]) > x_peak:
                    x_peak = abs(x[i])
            if abs(f) > f_peak:
                f_peak = abs(f)
            if not np.isfinite(x[0] + v[0] + f):
                return NOT_FINITE, period, change
        change = 0.0
        v_peak = omega * x_peak + 1e-300
        for i in range(n):
            change = max(change, abs(x[i] - x_start[i]) / (x_peak + 1e-300))
            change = max(change, abs(v[i] - v_start[i]) / v_peak)
        if has_contact and f_peak > 0.0:
            change = max(change, abs(f - f_start) / f_peak)
        force_state[0] = f
        if change <= tol:
            return OK, period, change
    return OK, max_periods, change
