"""Fixed-step time integration of a linear structure with several contacts:
laws to ground or between two DOFs, and the 2D element (tangential
friction under a unilateral normal contact).

The scheme is the one of :mod:`hbmfric.validation.integrator` (Newmark's
average-acceleration rule, contact forces implicit and exact at every step
instant), with the contact DOF replaced by *contact coordinates*: one per
1D contact (``u = x_a`` to ground, ``u = x_a − x_b`` between two DOFs) and
two per 2D element (tangential ``u`` and normal ``v``, positive closing).
With ``Bc`` the ``m × n`` matrix that reads the coordinates from ``x``
(entries ±1) and ``f`` the forces on them (``+f`` on ``a``, ``−f`` on
``b``: the load ``−Bcᵀ f``), one step reads

    x_lin = x₀ + A x₀ + B v₀ + q_c (cos Ωt₀ + cos Ωt₁)
            + q_s (sin Ωt₀ + sin Ωt₁) + q₀ − G f₀,       G = K_eff⁻¹ Bcᵀ,
    c + Gc f(c) = Bc x_lin,                              Gc = Bc G,
    x₁ = x_lin − G f(c₁),

an ``m``-dimensional equation for the coordinates at the end of the step,
solved by Newton's method on the block-diagonal tangent of the laws
(``df/du`` of each 1D law at fixed history through
:func:`hbmfric.kernels.laws.updates.law_step`; for the 2D element the tangent of
:func:`hbmfric.kernels.aft.contact2d.contact2d_step`: ``kt`` while stuck,
``±μ kn`` on ``v`` while slipping, ``kn`` on the normal while closed, 0
while open), with halving of the step while the residual does not
decrease. The laws' states are advanced once the step is solved.

For the 2D element a re-closure inside a step is located by linear
interpolation of the normal force over the step, and the slider placed at
the tangential coordinate there (as the harmonic balance's AFT does
between its samples).

Law state layout (``law_state``, flat): the ``m`` coordinate forces first
(``law_state[0]`` the first coordinate's force, which the caller's
convergence test reads), then each contact's own state (a 1D law's
:func:`~hbmfric.kernels.laws.updates.state_size` entries, whose first is its
force; a 2D element's slider position).
"""

import numpy as np

from .._jit import jit
from ..kernels.aft.contact2d import PHASE_OPEN, PHASE_STICK, contact2d_step
from ..kernels.laws.updates import law_step
from .integrator import NEWTON_FAILED, NOT_FINITE, OK, _store_state

#: kind of a contact in the kernels' arrays
LAW_1D = 0
ELEMENT_2D = 1

#: Newton iterations allowed for one step's contact update
MAX_ITERATIONS = 60
#: relative residual at which the update is accepted
RTOL = 1e-13
#: halvings of a Newton step whose residual does not decrease
MAX_HALVINGS = 30


#: the kernels' ``system`` tuple, entry by entry:
#: 0 ``A_t`` (n, n), 1 ``B_t`` (n, n), 2 ``q`` (2, n), 3 ``q0`` (n,), as in
#: :func:`hbmfric.validation.integrator.newmark_periods`; 4 ``G`` (n, m)
#: ``K_eff⁻¹ Bcᵀ``; 5 ``cos_sum`` (2, N); 6 ``Gc`` (m, m) ``Bc G``; per
#: contact (n_c,): 7 kind, 8 law code, 10 first coordinate, 11 offset of its
#: state in ``law_state``, 13 state size; 9 all parameters (flat) with 16
#: their offsets (n_c + 1,); 12 work (m,): coordinates at the step start;
#: 14 ``rows`` (m, 2) the coordinates' DOFs ``(a, b)`` (b = -1: ground);
#: 15 ``2/h``; 17, 18 work (m, m): the laws' tangent and Newton's matrix
SYSTEM_FIELDS = 19


@jit
def _forces(system, c, law_state, f, D, commit):
    """Forces ``f`` (m,) at coordinates ``c`` and their tangent ``D``
    (m × m, block diagonal) from the states at the step start; with
    ``commit`` the states are advanced to ``c``."""
    kinds, codes, params, first, state_at = (
        system[7],
        system[8],
        system[9],
        system[10],
        system[11],
    )
    param_at = system[16]
    m = c.size
    for i in range(m):
        for j in range(m):
            D[i, j] = 0.0
    prev = system[12]  # coordinates at the step start
    for k in range(kinds.size):
        j = first[k]
        s = state_at[k]
        if kinds[k] == LAW_1D:
            code = codes[k]
            size = system[13][k]
            state = law_state[s : s + size]
            p = params[param_at[k] : param_at[k + 1]]
            force, slope = law_step(code, p, state, prev[j], c[j], commit)
            f[j] = force
            D[j, j] = slope
        else:
            a = param_at[k]
            kt, kn, mu, n0 = params[a], params[a + 1], params[a + 2], params[a + 3]
            w_prev = law_state[s]
            n_start = n0 + kn * prev[j + 1]
            n_end = n0 + kn * c[j + 1]
            if not n_start > 0.0 and n_end > 0.0:
                # re-closure inside the step: the slider where the normal
                # force (linear over the step) turns positive
                theta = n_start / (n_start - n_end)
                w_prev = prev[j] + theta * (c[j] - prev[j])
            t, n, w, phase = contact2d_step(kt, kn, mu, n0, w_prev, c[j], c[j + 1])
            f[j] = t
            f[j + 1] = n
            if phase != PHASE_OPEN:
                D[j + 1, j + 1] = kn
                if phase == PHASE_STICK:
                    D[j, j] = kt
                else:
                    D[j, j + 1] = (1.0 if t > 0.0 else -1.0) * mu * kn
            if commit:
                law_state[s] = w
    if commit:
        for i in range(m):
            law_state[i] = f[i]


@jit
def _coordinates(rows, x, out):
    """``out = Bc x`` from the coordinate rows ``(a, b)`` (b = -1: ground)."""
    for i in range(rows.shape[0]):
        a, b = rows[i, 0], rows[i, 1]
        out[i] = x[a] - (x[b] if b >= 0 else 0.0)


@jit
def _solve_small(J, rhs, out):
    """``out = J⁻¹ rhs`` by Gaussian elimination with partial pivoting (J
    and rhs are overwritten; m is the handful of contact coordinates)."""
    m = rhs.size
    for k in range(m):
        pivot = k
        for i in range(k + 1, m):
            if abs(J[i, k]) > abs(J[pivot, k]):
                pivot = i
        if pivot != k:
            for j in range(m):
                J[k, j], J[pivot, j] = J[pivot, j], J[k, j]
            rhs[k], rhs[pivot] = rhs[pivot], rhs[k]
        d = J[k, k]
        for i in range(k + 1, m):
            factor = J[i, k] / d
            if factor != 0.0:
                for j in range(k, m):
                    J[i, j] -= factor * J[k, j]
                rhs[i] -= factor * rhs[k]
    for i in range(m - 1, -1, -1):
        acc = rhs[i]
        for j in range(i + 1, m):
            acc -= J[i, j] * out[j]
        out[i] = acc / J[i, i]


@jit
def _residual(Gc, c, f, target, r):
    """``r = c + Gc f − target``; returns ``(max |r|, max |Gc f|)``."""
    m = c.size
    norm = 0.0
    size = 0.0
    for i in range(m):
        acc = 0.0
        for j in range(m):
            acc += Gc[i, j] * f[j]
        r[i] = c[i] + acc - target[i]
        norm = max(norm, abs(r[i]))
        size = max(size, abs(acc))
    return norm, size


@jit
def _update(system, law_state, target, work):
    """Solve ``c + Gc f(c) = target`` from the start coordinates; advances
    the states. ``work`` (9, m) holds the scratch rows; returns
    ``(iterations, converged)`` with the coordinates in ``work[0]`` and
    their forces in ``work[1]``."""
    Gc = system[6]
    start = system[12]
    m = target.size
    c, f, r, step, trial, f_trial, r_trial = (
        work[0],
        work[1],
        work[2],
        work[3],
        work[4],
        work[5],
        work[6],
    )
    D = system[17]
    J = system[18]
    for i in range(m):
        c[i] = start[i]
    _forces(system, c, law_state, f, D, False)
    norm, size = _residual(Gc, c, f, target, r)
    scale = size
    for i in range(m):
        scale = max(scale, abs(start[i]) + abs(target[i]))
    if norm <= RTOL * scale:
        _forces(system, c, law_state, f, D, True)
        return 0, True
    for iteration in range(1, MAX_ITERATIONS + 1):
        for i in range(m):
            for j in range(m):
                acc = 1.0 if i == j else 0.0
                for k in range(m):
                    acc += Gc[i, k] * D[k, j]
                J[i, j] = acc
            trial[i] = -r[i]
        _solve_small(J, trial, step)
        alpha = 1.0
        accepted = False
        new_norm = norm
        for _ in range(MAX_HALVINGS):
            for i in range(m):
                trial[i] = c[i] + alpha * step[i]
            _forces(system, trial, law_state, f_trial, D, False)
            new_norm, size = _residual(Gc, trial, f_trial, target, r_trial)
            if new_norm < norm or new_norm <= RTOL * scale:
                accepted = True
                break
            alpha *= 0.5
        if not accepted:
            return iteration, False
        for i in range(m):
            c[i] = trial[i]
            f[i] = f_trial[i]
            r[i] = r_trial[i]
        norm = new_norm
        if norm <= RTOL * max(scale, size):
            _forces(system, c, law_state, f, D, True)
            return iteration, True
    return MAX_ITERATIONS, False


@jit
def _period(system, x, v, law_state, x_new, peaks, record, samples, contact_force):
    """One forcing period, as :func:`hbmfric.validation.integrator._period`."""
    A_t, B_t, q, q0, G, cos_sum = (
        system[0],
        system[1],
        system[2],
        system[3],
        system[4],
        system[5],
    )
    rows = system[14]
    two_over_h = system[15]
    start = system[12]
    n = x.size
    m = rows.shape[0]
    n_steps = cos_sum.shape[1]
    target = np.empty(m)
    work = np.empty((7, m))
    x_peak = 0.0
    v_peak = 0.0
    f_peak = 0.0
    for i in range(m):
        f_peak = max(f_peak, abs(law_state[i]))
    for i in range(n):
        x_peak = max(x_peak, abs(x[i]))
        v_peak = max(v_peak, abs(v[i]))
    check = 0.0
    iterations = 0
    for step in range(n_steps):
        if record:
            for i in range(n):
                samples[i, step] = x[i]
            contact_force[step] = law_state[0]
        s_c = cos_sum[0, step]
        s_s = cos_sum[1, step]
        for i in range(n):
            acc = x[i] + q[0, i] * s_c + q[1, i] * s_s + q0[i]
            for j in range(m):
                acc -= G[i, j] * law_state[j]
            x_new[i] = acc
        for j in range(n):
            x_j = x[j]
            v_j = v[j]
            for i in range(n):
                x_new[i] += A_t[j, i] * x_j + B_t[j, i] * v_j
        _coordinates(rows, x, start)
        _coordinates(rows, x_new, target)
        if not np.all(np.isfinite(target)):
            return NOT_FINITE, iterations
        its, ok = _update(system, law_state, target, work)
        f = work[1]
        iterations += its
        if not ok:
            return NEWTON_FAILED, iterations
        for i in range(n):
            acc = 0.0
            for j in range(m):
                acc += G[i, j] * f[j]
            x_new[i] -= acc
        for i in range(m):
            f_peak = max(f_peak, abs(f[i]))
        for i in range(n):
            v_i = two_over_h * (x_new[i] - x[i]) - v[i]
            v[i] = v_i
            x[i] = x_new[i]
            ax = abs(x_new[i])
            av = abs(v_i)
            x_peak = max(x_peak, ax)
            v_peak = max(v_peak, av)
            check += ax + av
    peaks[0] = x_peak
    peaks[1] = v_peak
    peaks[2] = f_peak
    if not np.isfinite(check):
        return NOT_FINITE, iterations
    return OK, iterations


@jit
def newmark_periods_multi(system, x, v, law_state, x_new, starts, peaks):
    """:func:`hbmfric.validation.integrator.newmark_periods` for several
    contacts (``system`` built by
    :class:`hbmfric.validation.problems.SeveralContacts`)."""
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
def record_period_multi(system, x, v, law_state, x_new, peaks, samples, contact_force):
    """:func:`hbmfric.validation.integrator.record_period` for several
    contacts (``contact_force``: the first coordinate's force)."""
    return _period(system, x, v, law_state, x_new, peaks, True, samples, contact_force)
