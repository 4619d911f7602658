"""AFT of Masing laws (Menq, Iwan) with located reversal points.

The law is marched through the samples by
:func:`hbmfric.kernels.laws.updates.masing_step`, the same update the time integrator
uses, but the path between samples is not taken as straight: every extreme
of ``u(θ)`` is found and located (:func:`hbmfric.kernels.aft.schemes._find_reversals`,
the search of the Jenkins event AFT, which also finds a pair of extremes
closer than a sample interval) and inserted into the path, so the reversal
points and the loop vertex carry their exact displacement. The force at the
samples is then the exact Masing force of the continuous motion, and only
the quadrature of its Fourier integrals is sampled: the first harmonic
converges about ten times faster in ``n_time`` than with sampled reversals.
(A pair of extremes inside one sample interval, which a sampled slope
cannot bracket, used to be dropped with its minor loop: the force then
jumped when the pair grew across a sample, and continuation stalled there,
e.g. a stiff Menq contact near the third superharmonic resonance.)

Steady state: the march starts at the located extreme of largest ``|u|``, on
the virgin curve (the contact closed at ``u = 0``; see
:mod:`hbmfric.kernels.aft.schemes`), and one pass is exact. A loop that stays on the
linear part of the curves is linear and is not marched. When every harmonic
is odd the loop is antisymmetric, ``f(θ + π) = -f(θ)``, and half a period is
marched.

Jacobian: at a reversal ``u'(θ_r) = 0``, so ``du_r/dX`` is the basis at
``θ_r`` whatever ``θ_r`` does; along the branch from ``r``,
``df/dX = df_r/dX + k (E(θ) - E(θ_r))`` with ``k`` the tangent stiffness.
"""

import numpy as np

from ..._jit import jit
from ..fourier.dft import basis_at, evaluate
from ..fourier.segments import project_samples
from ..laws.updates import (
    MASING_ENTRY,
    MASING_HEADER,
    law_init,
    linear_limit,
    linear_stiffness,
    masing_step,
    slip_limit,
    virgin_curve,
)
from .schemes import (
    _MAX_DEPTH,
    GROSS_SLIP,
    MICROSLIP,
    STUCK,
    _derivative_bounds,
    _find_reversals,
    _samples_uv,
)


@jit
def _masing_point(code, params, state, u_prev, u, prev_row, row, basis, grad):
    """March from the point in row ``prev_row`` to ``u``, whose basis row is
    ``basis[row]``; fills ``grad[row] = df/dX`` and returns ``f``.

    On the branch from the reversal point in row ``r``, ``df/dX = df_r/dX +
    k (E - E_r)`` (``k`` the tangent stiffness); on the virgin curve
    ``df/dX = k E``.
    """
    f, k, top = masing_step(code, params, state, u_prev, u, float(prev_row), True)
    r = int(state[MASING_HEADER + MASING_ENTRY * top + 2]) if top >= 0 else -1
    for c in range(basis.shape[1]):
        g = k * basis[row, c]
        if r >= 0:
            g += grad[r, c] - k * basis[r, c]
        grad[row, c] = g
    return f


@jit
def aft_masing(code, params, harmonic_numbers, X, inverse, forward, derivative, F, dF):
    """AFT of a Masing law with located reversals and analytic Jacobian.

    Parameters
    ----------
    code : int
        ``MENQ`` or ``IWAN``.
    params : ndarray, shape (n_params,)
        Law parameters.
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
        Harmonics of ``X``.
    X : ndarray, shape (n_coef,)
        Displacement coefficients, m.
    inverse, derivative : ndarray, shape (n_time, n_coef)
        Inverse DFT matrix and its θ-derivative.
    forward : ndarray, shape (n_coef, n_time)
        Forward DFT matrix.
    F : ndarray, shape (n_coef,)
        Output: force coefficients, N.
    dF : ndarray, shape (n_coef, n_coef)
        Output: ``dF/dX``, N/m.

    Returns
    -------
    int
        ``STUCK``, ``MICROSLIP``, ``GROSS_SLIP``, or the negative code of
        the reversal search (``EVENT_OVERFLOW``: more reversals than
        ``4 H + 8``; ``SEARCH_BUDGET``: non-finite motion or work budget
        spent); ``F``, ``dF`` zero on failure.
    """
    n, n_coef = inverse.shape
    two_pi = 2.0 * np.pi
    h = two_pi / n
    cap = 4 * harmonic_numbers[-1] + 8  # reversals: at most 2 H, with room
    u = np.empty(n)
    v = np.empty(n)
    rev_th = np.empty(cap)
    rev_u = np.empty(cap)
    stack = np.empty((_MAX_DEPTH + 2, 5))
    X2 = np.empty(n_coef)
    _samples_uv(harmonic_numbers, X, inverse, derivative, u, v)
    b2, b3 = _derivative_bounds(harmonic_numbers, X, X2)
    # every reversal, also a pair closer than a sample interval: one that
    # went unseen would drop a minor loop, and the force would jump when
    # the pair grows across a sample
    n_rev = _find_reversals(
        harmonic_numbers, X, X2, inverse, u, v, b2, b3, rev_th, rev_u, stack
    )
    if n_rev < 0:  # EVENT_OVERFLOW or SEARCH_BUDGET
        F[:] = 0.0
        dF[:, :] = 0.0
        return n_rev
    q_max = 0
    q_min = 0
    for q in range(1, n_rev):
        if rev_u[q] > rev_u[q_max]:
            q_max = q
        if rev_u[q] < rev_u[q_min]:
            q_min = q
    if n_rev == 0:  # a constant
        u_max = u[0]
        u_min = u[0]
        q_v = -1
        th_v = 0.0
    else:
        u_max = rev_u[q_max]
        u_min = rev_u[q_min]
        q_v = q_max if u_max >= -u_min else q_min
        th_v = rev_th[q_v]
    u_v = u_max if u_max >= -u_min else u_min
    half_range = 0.5 * (u_max - u_min)
    lin = linear_limit(code, params)
    k0 = linear_stiffness(code, params)
    dF[:, :] = 0.0
    basis_v = np.empty(n_coef)
    if abs(u_v) <= lin or half_range <= lin:
        # linear loop F = F_v + k0 (u - u_v): no march, no DFT
        for r in range(n_coef):
            F[r] = k0 * X[r]
            dF[r, r] = k0
        if abs(u_v) > lin and harmonic_numbers[0] == 0:
            F_load, k_v, _, _, _ = virgin_curve(code, params, abs(u_v), -1.0, 0.0, 0.0)
            f_v = F_load if u_v >= 0.0 else -F_load
            basis_at(harmonic_numbers, th_v, basis_v)
            F[0] += f_v - k0 * u_v
            for c in range(n_coef):
                dF[0, c] += (k_v - k0) * basis_v[c]
        return STUCK

    odd = n % 2 == 0
    for k in harmonic_numbers:
        if k % 2 == 0:
            odd = False
    n_march = n // 2 if odd else n
    weight = 2.0 if odd else 1.0
    # the sample interval [base h, (base + 1) h) holds the vertex (a vertex
    # on a sample ends the interval before it); the march visits samples
    # base + 1 ... base + n_march and, before each, the reversals since the
    # previous one, by their angle past the vertex
    base = int(np.floor(th_v / h))
    if base * h >= th_v:
        base -= 1
    i_v = base % n
    past = np.empty(n_rev)
    n_past = 0
    for q in range(n_rev):
        if q == q_v:
            continue
        d = rev_th[q] - th_v
        while d < 0.0:
            d += two_pi
        while d >= two_pi:
            d -= two_pi
        if 1e-12 < d < two_pi - 1e-12:  # not the vertex again
            past[n_past] = d
            n_past += 1
    order = np.argsort(past[:n_past])
    # marched points keep their basis row and df/dX, the reversal tags
    # index these rows: sample i in row i, the vertex in row n, the located
    # extremes after it
    basis = np.empty((n + 1 + n_past, n_coef))
    grad = np.empty((n + 1 + n_past, n_coef))
    force = np.empty(n)
    state = np.empty(MASING_HEADER + MASING_ENTRY * (2 * (n_march + n_past) + 2))
    f_v, k_v = law_init(code, params, u_v, state)
    basis_at(harmonic_numbers, th_v, basis_v)
    for c in range(n_coef):
        basis[n, c] = basis_v[c]
        grad[n, c] = k_v * basis_v[c]
    prev_row = n
    next_extreme = n + 1
    u_prev = u_v
    e = 0
    for j in range(1, n_march + 1):
        i = (base + j) % n
        reach = (base + j) * h - th_v
        while e < n_past and past[order[e]] <= reach:
            # a reversal inside the sample interval: march to it first
            th_e = th_v + past[order[e]]
            u_e = evaluate(harmonic_numbers, X, th_e)[0]
            basis_at(harmonic_numbers, th_e, basis[next_extreme])
            _masing_point(
                code, params, state, u_prev, u_e, prev_row, next_extreme, basis, grad
            )
            prev_row = next_extreme
            next_extreme += 1
            u_prev = u_e
            e += 1
        for c in range(n_coef):
            basis[i, c] = inverse[i, c]
        force[i] = _masing_point(
            code, params, state, u_prev, u[i], prev_row, i, basis, grad
        )
        prev_row = i
        u_prev = u[i]
    # F = Σ w f φ(θ_i), dF = Σ w φ(θ_i) ⊗ df_i/dX over the marched samples
    F[:] = 0.0
    project_samples(forward, force, grad, i_v + 1, n_march, weight, F, dF)
    if half_range >= slip_limit(code, params):
        return GROSS_SLIP
    return MICROSLIP
