"""Harmonic-balance residual and Jacobian of a linear structure with one
contact to ground.

System: ``M ẍ + C ẋ + K x + e_c f_c(x_c) = p(t)``, with ``f_c`` a contact law
acting on DOF ``c``. Unknowns ``y = [X, Ω]`` with ``X`` stored DOF by DOF,
``X[d * n_coef:(d + 1) * n_coef]`` the coefficients of DOF ``d`` (layout of
:mod:`hbmfric.kernels.dft`).

The problem travels to the kernels as one flat tuple (see
:func:`hbm_residual`); the Newton corrector passes it through untouched.
"""

import numpy as np

from .._jit import jit
from .aft import aft_jenkins_events, aft_samples
from .dahl import aft_dahl
from .dlft import COULOMB, dlft_contact, dlft_located
from .dlft_tail import SINGULAR_RECEPTANCE, contact_receptance, dlft_tail
from .laws import DAHL, JENKINS, is_masing
from .masing import aft_masing

NO_CONTACT = -1
#: AFT scheme codes
AFT_SAMPLES = 0
AFT_EVENTS = 1


@jit
def hbm_residual(y, problem, R, J):
    """Residual ``R(X, Ω)`` and Jacobian ``[dR/dX, dR/dΩ]``.

    Parameters
    ----------
    y : ndarray, shape (n_dof * n_coef + 1,)
        Coefficients of all DOFs (m), then Ω (rad/s).
    problem : tuple
        ``(harmonic_numbers, mass, damping, stiffness, load, contact_dof,
        law_code, law_params, aft_scheme, inverse, forward, derivative)``
        with ``mass``, ``damping``, ``stiffness`` of shape (n_dof, n_dof),
        ``load`` of shape (n_dof * n_coef,) (coefficients of ``p(t)``, N),
        ``law_code = -1`` for no contact; ``law_code = COULOMB`` (rigid
        Coulomb, ``law_params = [slip_force, penalty, penalty_damping,
        (M⁻¹)_cc, K]``) is solved by DLFT (:mod:`hbmfric.kernels.dlft`)
        instead of an AFT: for ``aft_scheme = AFT_EVENTS`` with located
        reversals, plus the linear tail of the response summed to ``K``
        when ``K > 0`` (:mod:`hbmfric.kernels.dlft_tail`); the classic
        sampled scheme otherwise.
    R : ndarray, shape (n_dof * n_coef,)
        Output: residual, N.
    J : ndarray, shape (n_dof * n_coef, n_dof * n_coef + 1)
        Output: Jacobian; last column ``dR/dΩ``.

    Returns
    -------
    int
        Contact-state code of the AFT (negative on failure).
    """
    (
        harmonic_numbers,
        mass,
        damping,
        stiffness,
        load,
        contact_dof,
        law_code,
        law_params,
        aft_scheme,
        inverse,
        forward,
        derivative,
    ) = problem
    n_dof = mass.shape[0]
    n_coef = inverse.shape[1]
    n = n_dof * n_coef
    omega = y[n]
    J[:, :] = 0.0
    for r in range(n):
        R[r] = -load[r]
    col = 0
    for k in harmonic_numbers:
        w = k * omega
        for p in range(n_dof):
            for q in range(n_dof):
                kpq = stiffness[p, q]
                mpq = mass[p, q]
                cpq = damping[p, q]
                rp = p * n_coef + col
                cq = q * n_coef + col
                if k == 0:
                    J[rp, cq] += kpq
                    R[rp] += kpq * y[cq]
                else:
                    diag = kpq - mpq * w * w
                    xc = y[cq]
                    xs = y[cq + 1]
                    J[rp, cq] += diag
                    J[rp, cq + 1] += cpq * w
                    J[rp + 1, cq] -= cpq * w
                    J[rp + 1, cq + 1] += diag
                    R[rp] += diag * xc + cpq * w * xs
                    R[rp + 1] += diag * xs - cpq * w * xc
                    ddiag = -2.0 * mpq * k * w
                    J[rp, n] += ddiag * xc + cpq * k * xs
                    J[rp + 1, n] += ddiag * xs - cpq * k * xc
        col += 1 if k == 0 else 2
    status = 0
    if law_code == COULOMB and aft_scheme == AFT_EVENTS and law_params[4] > 0.0:
        n_tail = int(law_params[4])
        q = np.zeros(n_tail + 1, dtype=np.complex128)
        dq = np.zeros(n_tail + 1, dtype=np.complex128)
        a2, da2, ok = contact_receptance(
            mass,
            damping,
            stiffness,
            contact_dof,
            omega,
            harmonic_numbers,
            law_params[3],
            q,
            dq,
        )
        if not ok:
            return SINGULAR_RECEPTANCE
        status = dlft_tail(
            law_params,
            harmonic_numbers,
            contact_dof * n_coef,
            mass[contact_dof, contact_dof],
            q,
            dq,
            a2,
            da2,
            y,
            inverse,
            forward,
            derivative,
            R,
            J,
        )
    elif law_code == COULOMB and aft_scheme == AFT_EVENTS:
        status = dlft_located(
            law_params,
            harmonic_numbers,
            contact_dof * n_coef,
            mass[contact_dof, contact_dof],
            y,
            inverse,
            forward,
            derivative,
            R,
            J,
        )
    elif law_code == COULOMB:
        status = dlft_contact(
            law_params, contact_dof * n_coef, y, inverse, forward, R, J
        )
    elif law_code != NO_CONTACT:
        F = np.empty(n_coef)
        dF = np.empty((n_coef, n_coef))
        base = contact_dof * n_coef
        x_c = y[base : base + n_coef].copy()
        if law_code == JENKINS and aft_scheme == AFT_EVENTS:
            status = aft_jenkins_events(
                law_params, harmonic_numbers, x_c, inverse, derivative, F, dF
            )
        elif is_masing(law_code) and aft_scheme == AFT_EVENTS:
            status = aft_masing(
                law_code,
                law_params,
                harmonic_numbers,
                x_c,
                inverse,
                forward,
                derivative,
                F,
                dF,
            )
        elif law_code == DAHL:
            status = aft_dahl(
                law_params,
                harmonic_numbers,
                x_c,
                inverse,
                forward,
                derivative,
                F,
                dF,
            )
        else:
            status = aft_samples(law_code, law_params, x_c, inverse, forward, F, dF)
        for r in range(n_coef):
            R[base + r] += F[r]
            for c in range(n_coef):
                J[base + r, base + c] += dF[r, c]
    return status
