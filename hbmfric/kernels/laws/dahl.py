"""Modified Dahl restoring-force model: the increment update.

The law (docs/laws.md; Al Majid & Dufour 2002, Bastien et al. 2007) is

    dF/dt = β (h − F sgn u̇)^μ u̇,   h = ½[(h_u + h_l) sgn u̇ + (h_u − h_l)],

with straight envelopes ``h_u = a u + b`` and ``h_l = d u + e``. It is rate
independent: on loading (``du > 0``) ``dF/du = β σ(h_u − F)``, on unloading
(``du < 0``) ``dF/du = β σ(F − h_l)``, with the sign-keeping power
``σ(x) = x |x|^(μ-1)``. So the force is integrated along the displacement
path, not in time.

Parameter array ``params = [β, μ, a, b, d, e]`` (β in 1/m when μ = 1, in
N^(1-μ)/m in general; a, d in N/m; b, e in N).

Increment (:func:`dahl_update`): for μ = 1 each monotone increment has the
exact exponential solution

    loading:   F = h_u(u) − a/β + (F₀ − h_u(u₀) + a/β) exp(−β Δu),
    unloading: F = h_l(u) + d/β + (F₀ − h_l(u₀) − d/β) exp(−β |Δu|),

so the branches tend to ``h_u − a/β`` and ``h_l + d/β``. For μ ≠ 1 the
increment is integrated by classical Runge–Kutta with ``1 + ⌊8 β_eff |Δu|⌋``
substeps (β_eff the local slope rate) and its derivatives are carried
through the stages (forward mode), so they are those of the discrete map.

Its periodic state and AFT: :mod:`hbmfric.kernels.aft.dahl`.
"""

import numpy as np

from ..._jit import jit


@jit
def _signed_power(x, mu):
    """``σ(x) = x |x|^(μ-1)`` and ``σ'(x) = μ |x|^(μ-1)``."""
    ax = abs(x)
    if mu == 1.0:
        return x, 1.0
    if ax == 0.0:
        return 0.0, 0.0 if mu > 1.0 else np.inf
    p = ax ** (mu - 1.0)
    return x * p, mu * p


@jit
def dahl_update(params, f_prev, u_prev, u):
    """Advance the modified Dahl force from ``u_prev`` to ``u``.

    Parameters
    ----------
    params : ndarray, shape (6,)
        ``[β, μ, a, b, d, e]`` (see the module docstring).
    f_prev : float
        Force at ``u_prev``, N.
    u_prev, u : float
        Displacement before and after the increment, m.

    Returns
    -------
    f : float
        Force at ``u``, N.
    df_dfprev, df_duprev, df_du : float
        Partial derivatives of ``f``.
    """
    beta = params[0]
    mu = params[1]
    du = u - u_prev
    if du == 0.0:
        return f_prev, 1.0, 0.0, 0.0
    if du > 0.0:
        slope = params[2]
        offset = params[3]
        s = 1.0
    else:
        slope = params[4]
        offset = params[5]
        s = -1.0
    if mu == 1.0:
        # exact: F = h(u) - s p/β + (F0 - h(u0) + s p/β) exp(-β|du|)
        decay = np.exp(-beta * abs(du))
        g0 = f_prev - slope * u_prev - offset + s * slope / beta
        f = slope * u + offset - s * slope / beta + g0 * decay
        df_du = slope - s * beta * decay * g0
        df_duprev = -slope * decay + s * beta * decay * g0
        return f, decay, df_duprev, df_du
    # μ != 1: RK4 in τ ∈ [0, 1], u(τ) = u_prev + τ du, dF/dτ = du φ(u, F),
    # φ = β σ(s (p u + q - F)); tangents w.r.t. (f_prev, u_prev, u) carried along
    x0 = s * (slope * u_prev + offset - f_prev)
    # relaxation rate |∂φ/∂F| at the start and on the asymptote σ(x) = p/β
    rate = beta * mu * max(abs(x0), (abs(slope) / beta) ** (1.0 / mu)) ** (mu - 1.0)
    n_sub = 1 + int(8.0 * rate * abs(du))
    if n_sub > 200:
        n_sub = 200
    h = 1.0 / n_sub
    f = f_prev
    t0 = 1.0  # dF/df_prev
    t1 = 0.0  # dF/du_prev
    t2 = 0.0  # dF/du
    k_f = np.empty(4)
    k_0 = np.empty(4)
    k_1 = np.empty(4)
    k_2 = np.empty(4)
    for k in range(n_sub):
        tau = k * h
        f_s = f
        d0 = t0
        d1 = t1
        d2 = t2
        for stage in range(4):
            if stage == 0:
                c = 0.0
            elif stage == 3:
                c = 1.0
            else:
                c = 0.5
            ts = tau + c * h
            if stage == 0:
                fs, g0, g1, g2 = f_s, d0, d1, d2
            else:
                fs = f_s + c * h * k_f[stage - 1]
                g0 = d0 + c * h * k_0[stage - 1]
                g1 = d1 + c * h * k_1[stage - 1]
                g2 = d2 + c * h * k_2[stage - 1]
            us = u_prev + ts * du
            val, dval = _signed_power(s * (slope * us + offset - fs), mu)
            phi = beta * val
            phi_u = beta * dval * s * slope
            phi_f = -beta * dval * s
            k_f[stage] = du * phi
            # du/du_prev = 1 - ts, du/du = ts; d(du)/du_prev = -1, d(du)/du = 1
            k_0[stage] = du * phi_f * g0
            k_1[stage] = -phi + du * (phi_u * (1.0 - ts) + phi_f * g1)
            k_2[stage] = phi + du * (phi_u * ts + phi_f * g2)
        f = f_s + h / 6.0 * (k_f[0] + 2.0 * k_f[1] + 2.0 * k_f[2] + k_f[3])
        t0 = d0 + h / 6.0 * (k_0[0] + 2.0 * k_0[1] + 2.0 * k_0[2] + k_0[3])
        t1 = d1 + h / 6.0 * (k_1[0] + 2.0 * k_1[1] + 2.0 * k_1[2] + k_1[3])
        t2 = d2 + h / 6.0 * (k_2[0] + 2.0 * k_2[1] + 2.0 * k_2[2] + k_2[3])
    return f, t0, t1, t2
