"""Harmonic balance condensed onto the contact DOF.

Only the contact is nonlinear, so the linear DOFs are eliminated harmonic by
harmonic. With the modes of the structure (``K φ_r = ω_r² M φ_r``,
mass-normalised, classical damping ``φ_rᵀ C φ_s = c_r δ_rs``) and all modes
kept, the dynamic receptance at pulsation ``ω`` is exact:

    G_ij(ω) = Σ_r φ_ir φ_jr / d_r(ω),   d_r(ω) = ω_r² - ω² + i ω c_r.

Complex amplitudes follow ``x(t) = Re(x̂ e^{iωt})``, i.e. ``x̂ = Xc - i Xs``
for the real coefficients ``[Xc, Xs]`` of one harmonic. For harmonic ``k``
(``ω = kΩ``), with ``g = G_cc(ω)`` the receptance at the contact DOF ``c``
and ``p = Σ_r φ_cr q̂_r / d_r`` the response of the contact DOF to the
external load (modal load ``q̂_r = φ_rᵀ P̂_k``), the contact DOF obeys
``x̂ = p - g F̂``: the condensed residual, in the dynamic-stiffness form

    r̂_k = (x̂_k - p_k) / g_k + F̂_k,       R_c = Re r̂,  R_s = -Im r̂,

is the Schur complement of the full HBM residual on the contact row (units
N, so tolerances mean the same as for the full problem). ``dR/dΩ`` is
analytic: ``d(1/g)/dΩ = -k g'/g²``, ``d(1/d_r)/dω = (2ω - i c_r)/d_r²``.
The mean (harmonic 0, when present) uses ``ω = 0``.

The problem travels as a :class:`CondensedProblem` named tuple; the residual
dispatcher :func:`hbmfric.kernels.residual.residual` recognises its type.
"""

from collections import namedtuple

import numpy as np

from .._jit import jit
from .aft import aft_jenkins_events, aft_samples
from .laws import JENKINS

#: AFT scheme codes (same values as :mod:`hbmfric.kernels.hbm`)
AFT_SAMPLES = 0
AFT_EVENTS = 1

CondensedProblem = namedtuple(
    "CondensedProblem",
    [
        "harmonic_numbers",  # int64 (n_harmonics,)
        "contact_shapes",  # float64 (n_modes,): φ_cr
        "omega_squared",  # float64 (n_modes,): ω_r², rad²/s²
        "modal_damping",  # float64 (n_modes,): c_r = φ_rᵀ C φ_r, 1/s
        "modal_load",  # float64 (n_modes, n_coef): Φᵀ P per coefficient, N
        "law_code",  # int64
        "law_params",  # float64 (n_params,)
        "aft_scheme",  # int64
        "inverse",  # float64 (n_time, n_coef)
        "forward",  # float64 (n_coef, n_time)
        "derivative",  # float64 (n_time, n_coef)
    ],
)
CondensedProblem.__doc__ = """Flat data of the condensed HBM residual (see the
module docstring); built by :class:`hbmfric.condensation.CondensedHBMProblem`."""


@jit
def _harmonic_receptance(k, omega, col, problem):
    """Receptance ``g``, load response ``p`` and their Ω-derivatives for one
    harmonic (complex; derivatives are ``d/dΩ`` at ``ω = kΩ``)."""
    phi = problem.contact_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    q = problem.modal_load
    w = k * omega
    g = 0.0j
    p = 0.0j
    dg = 0.0j
    dp = 0.0j
    for r in range(phi.size):
        if k == 0:
            qr = q[r, col] + 0.0j
        else:
            qr = q[r, col] - 1j * q[r, col + 1]
        inv_d = 1.0 / (w2[r] - w * w + 1j * w * c[r])
        # d(1/d_r)/dΩ = k (2ω - i c_r) / d_r²
        dinv = k * (2.0 * w - 1j * c[r]) * inv_d * inv_d
        g += phi[r] * phi[r] * inv_d
        dg += phi[r] * phi[r] * dinv
        p += phi[r] * qr * inv_d
        dp += phi[r] * qr * dinv
    return g, p, dg, dp


@jit
def condensed_residual(y, problem, R, J):
    """Condensed residual ``R(X_c, Ω)`` and Jacobian ``[dR/dX_c, dR/dΩ]``.

    Parameters
    ----------
    y : ndarray, shape (n_coef + 1,)
        Coefficients of the contact DOF (m), then Ω (rad/s).
    problem : CondensedProblem
    R : ndarray, shape (n_coef,)
        Output: residual, N.
    J : ndarray, shape (n_coef, n_coef + 1)
        Output: Jacobian; last column ``dR/dΩ``.

    Returns
    -------
    int
        Contact-state code of the AFT (negative on failure).
    """
    hn = problem.harmonic_numbers
    n = problem.inverse.shape[1]
    omega = y[n]
    J[:, :] = 0.0
    col = 0
    for k in hn:
        g, p, dg, dp = _harmonic_receptance(k, omega, col, problem)
        D = 1.0 / g
        dD = -dg * D * D
        if k == 0:
            x = y[col] + 0.0j
        else:
            x = y[col] - 1j * y[col + 1]
        r = D * (x - p)
        dr = dD * (x - p) - D * dp
        R[col] = r.real
        J[col, col] = D.real
        J[col, n] = dr.real
        if k != 0:
            R[col + 1] = -r.imag
            J[col, col + 1] = D.imag
            J[col + 1, col] = -D.imag
            J[col + 1, col + 1] = D.real
            J[col + 1, n] = -dr.imag
        col += 1 if k == 0 else 2
    F = np.empty(n)
    dF = np.empty((n, n))
    status = _contact_force(y[:n].copy(), problem, F, dF)
    for i in range(n):
        R[i] += F[i]
        for j in range(n):
            J[i, j] += dF[i, j]
    return status


@jit
def _contact_force(x, problem, F, dF):
    if problem.law_code == JENKINS and problem.aft_scheme == AFT_EVENTS:
        return aft_jenkins_events(
            problem.law_params,
            problem.harmonic_numbers,
            x,
            problem.inverse,
            problem.derivative,
            F,
            dF,
        )
    return aft_samples(
        problem.law_code,
        problem.law_params,
        x,
        problem.inverse,
        problem.forward,
        F,
        dF,
    )


@jit
def condensed_recover(y, problem, shapes, X, F):
    """Response of every DOF at one condensed solution.

    ``x̂_j = Σ_r φ_jr (q̂_r - φ_cr F̂) / d_r`` per harmonic, with ``F`` the
    contact force (AFT at the solution).

    Parameters
    ----------
    y : ndarray, shape (n_coef + 1,)
        Condensed solution ``[X_c, Ω]``.
    problem : CondensedProblem
    shapes : ndarray, shape (n_dof, n_modes)
        Mass-normalised mode shapes.
    X : ndarray, shape (n_dof, n_coef)
        Output: coefficients of every DOF, m.
    F : ndarray, shape (n_coef,)
        Output: contact-force coefficients, N.

    Returns
    -------
    int
        Contact-state code of the AFT.
    """
    n = problem.inverse.shape[1]
    dF = np.empty((n, n))
    status = _contact_force(y[:n].copy(), problem, F, dF)
    omega = y[n]
    phi = problem.contact_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    q = problem.modal_load
    n_dof, n_modes = shapes.shape
    eta = np.empty(n_modes, dtype=np.complex128)
    col = 0
    for k in problem.harmonic_numbers:
        w = k * omega
        if k == 0:
            f = F[col] + 0.0j
        else:
            f = F[col] - 1j * F[col + 1]
        for r in range(n_modes):
            if k == 0:
                qr = q[r, col] + 0.0j
            else:
                qr = q[r, col] - 1j * q[r, col + 1]
            eta[r] = (qr - phi[r] * f) / (w2[r] - w * w + 1j * w * c[r])
        for j in range(n_dof):
            s = 0.0j
            for r in range(n_modes):
                s += shapes[j, r] * eta[r]
            X[j, col] = s.real
            if k != 0:
                X[j, col + 1] = -s.imag
        col += 1 if k == 0 else 2
    return status


@jit
def condensed_modal_coefficients(points, problem, modal):
    """Modal coordinates of the full response at condensed solutions.

    ``η̂_r = (q̂_r - φ_cr F̂) / d_r`` per harmonic, ``F`` the contact force
    (AFT at each solution); the response of every DOF is then
    ``X = Φ η`` (one matrix product, done by the caller).

    Parameters
    ----------
    points : ndarray, shape (n_points, n_coef + 1)
        Condensed solutions ``[X_c, Ω]``.
    problem : CondensedProblem
    modal : ndarray, shape (n_points, n_modes, n_coef)
        Output: real coefficients of each modal coordinate (layout of the
        DOF coefficients), m·kg^½.

    Returns
    -------
    int
        Lowest AFT status met (negative on a failure).
    """
    n = problem.inverse.shape[1]
    F = np.empty(n)
    dF = np.empty((n, n))
    phi = problem.contact_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    q = problem.modal_load
    worst = 1 << 30
    for i in range(points.shape[0]):
        status = _contact_force(points[i, :n].copy(), problem, F, dF)
        if status < worst:
            worst = status
        omega = points[i, n]
        col = 0
        for k in problem.harmonic_numbers:
            w = k * omega
            for r in range(phi.size):
                d = w2[r] - w * w + 1j * w * c[r]
                if k == 0:
                    modal[i, r, col] = (q[r, col] - phi[r] * F[col]) / w2[r]
                else:
                    qr = q[r, col] - 1j * q[r, col + 1]
                    f = F[col] - 1j * F[col + 1]
                    eta = (qr - phi[r] * f) / d
                    modal[i, r, col] = eta.real
                    modal[i, r, col + 1] = -eta.imag
            col += 1 if k == 0 else 2
    return worst
