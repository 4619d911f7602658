"""Dynamic Lagrangian frequency–time (DLFT) method for a rigid Coulomb contact.

A rigid Coulomb contact (no tangential compliance, slip force ``f_s``) has no
force law ``f(u)``: while it sticks, its force is whatever holds the relative
displacement ``u`` still. The DLFT scheme of Nacivet et al. (2003) finds that
force from the equations of motion themselves.

With the linear residual ``R_lin = Z(Ω) X - P`` already assembled, the contact
rows need the force ``Λ_X = -R_lin`` (coefficients of ``λ_X(θ)``, the force
that the linear dynamics ask of the contact). Prediction, in the frequency
domain, with a penalty ``ε`` (N/m)::

    Λ_pred = Λ_X + ε U            (U: coefficients of u)

Correction, sample by sample in time (``p_i = λ_pred(θ_i)``, ``w`` the
corrected relative displacement)::

    stick:  λ_i = p_i - ε w_{i-1},  w_i = w_{i-1}   (u does not move)
    slip:   if |λ_i| > f_s:  λ_i = ±f_s,  w_i = (p_i - λ_i) / ε

so that ``λ_i = p_i - ε w_i`` always. The corrected force ``Λ`` (forward DFT of
``λ_i``) enters the residual, whose contact rows become
``R_lin + Λ = Λ - Λ_X = ε (U - W)``: zero exactly when the relative
displacement equals its corrected value, i.e. does not move during stick and
slips only under ``|λ| = f_s`` (opposing the relative velocity). The residual
is kept in force units (``ε`` times the displacement mismatch) so that the
Newton tolerance means the same as for the other laws; the solution does not
depend on ``ε`` (up to the harmonic truncation), only Newton's conditioning
does: ``ε`` of the order of the dynamic stiffness at the contact works.

In terms of ``v = p / ε`` the correction is a Jenkins element of stiffness
``ε`` and slip force ``f_s`` driven by ``v``; its periodic steady state is
found as for Jenkins (SPEC §3): in gross slip one march from the sample of
maximum ``v`` with ``λ = +f_s``; a contact stuck over the whole period keeps
``w`` at the reference position 0 (shifted just enough to keep
``|λ| <= f_s``).

The Jacobian is carried analytically through the march (``dλ_i/dV``), then
chained with ``dV/dy = E_c - (dR_lin/dy)_c / ε`` over all unknowns
``y = [X, Ω]``, which gives ``dR/dΩ`` for continuation too.
"""

import numpy as np

from .._jit import jit
from .aft import GROSS_SLIP, STUCK

#: law code of the rigid Coulomb contact, solved by DLFT (not by the AFT law
#: march of :mod:`hbmfric.kernels.laws`; chosen far from the AFT law codes)
COULOMB = 100


@jit
def dlft_correct(slip_force, penalty, V, inverse, forward, F, dF):
    """Coulomb correction of a predicted contact force, with Jacobian.

    Parameters
    ----------
    slip_force : float
        ``f_s``, N (> 0).
    penalty : float
        ``ε``, N/m (> 0).
    V : ndarray, shape (n_coef,)
        Coefficients of ``v = λ_pred / ε``, m.
    inverse : ndarray, shape (n_time, n_coef)
        Inverse DFT matrix.
    forward : ndarray, shape (n_coef, n_time)
        Forward DFT matrix.
    F : ndarray, shape (n_coef,)
        Output: coefficients of the corrected force ``λ``, N.
    dF : ndarray, shape (n_coef, n_coef)
        Output: ``dF/dV``, N/m.

    Returns
    -------
    int
        ``STUCK`` (the contact sticks over the whole period) or
        ``GROSS_SLIP``.
    """
    n_time, n_coef = inverse.shape
    v = inverse @ V
    force = np.empty(n_time)
    grad = np.zeros((n_time, n_coef))
    i_max = np.argmax(v)
    i_min = np.argmin(v)
    eps = penalty
    if eps * (v[i_max] - v[i_min]) <= 2.0 * slip_force:
        state = STUCK
        # w stays at 0 unless |λ| <= f_s needs it shifted
        w = 0.0
        i_ref = -1
        if eps * v[i_max] > slip_force:
            w = v[i_max] - slip_force / eps
            i_ref = i_max
        elif eps * v[i_min] < -slip_force:
            w = v[i_min] + slip_force / eps
            i_ref = i_min
        for i in range(n_time):
            force[i] = eps * (v[i] - w)
            for c in range(n_coef):
                shift = inverse[i_ref, c] if i_ref >= 0 else 0.0
                grad[i, c] = eps * (inverse[i, c] - shift)
    else:
        state = GROSS_SLIP
        # at the maximum of v the force is saturated at +f_s
        f = slip_force
        force[i_max] = f
        for j in range(1, n_time):
            i = (i_max + j) % n_time
            p = (i - 1) % n_time
            trial = f + eps * (v[i] - v[p])
            if trial > slip_force:
                f = slip_force
                for c in range(n_coef):
                    grad[i, c] = 0.0
            elif trial < -slip_force:
                f = -slip_force
                for c in range(n_coef):
                    grad[i, c] = 0.0
            else:
                f = trial
                for c in range(n_coef):
                    grad[i, c] = grad[p, c] + eps * (inverse[i, c] - inverse[p, c])
            force[i] = f
    for r in range(n_coef):
        acc = 0.0
        for i in range(n_time):
            acc += forward[r, i] * force[i]
        F[r] = acc
    for r in range(n_coef):
        for c in range(n_coef):
            dF[r, c] = 0.0
        for i in range(n_time):
            wr = forward[r, i]
            if wr != 0.0:
                for c in range(n_coef):
                    dF[r, c] += wr * grad[i, c]
    return state


@jit
def dlft_contact(params, base, y, inverse, forward, R, J):
    """Add a rigid Coulomb contact to an assembled linear HBM residual.

    Parameters
    ----------
    params : ndarray, shape (2,)
        ``[slip_force, penalty]`` (N, N/m).
    base : int
        Index of the contact DOF's first coefficient in ``y``.
    y : ndarray, shape (n + 1,)
        Unknowns ``[X, Ω]`` (m, rad/s).
    inverse, forward : ndarray
        DFT matrices, shapes (n_time, n_coef) and (n_coef, n_time).
    R : ndarray, shape (n,)
        In: linear residual ``Z X - P``, N. Out: plus the contact force.
    J : ndarray, shape (n, n + 1)
        In: its Jacobian ``[dR/dX, dR/dΩ]``. Out: of the full residual.

    Returns
    -------
    int
        Contact-state code (``STUCK`` or ``GROSS_SLIP``).
    """
    slip_force = params[0]
    eps = params[1]
    n_coef = inverse.shape[1]
    n1 = J.shape[1]
    V = np.empty(n_coef)
    dV = np.empty((n_coef, n1))
    for r in range(n_coef):
        V[r] = y[base + r] - R[base + r] / eps
        for c in range(n1):
            dV[r, c] = -J[base + r, c] / eps
        dV[r, base + r] += 1.0
    F = np.empty(n_coef)
    dF = np.empty((n_coef, n_coef))
    state = dlft_correct(slip_force, eps, V, inverse, forward, F, dF)
    for r in range(n_coef):
        R[base + r] += F[r]
        for k in range(n_coef):
            d = dF[r, k]
            if d != 0.0:
                for c in range(n1):
                    J[base + r, c] += d * dV[k, c]
    return state
