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

Two ways to evaluate ``g`` and ``p`` (``method``):

``MODAL``
    the modal sums above (all modes: exact for classical damping);
``DIRECT``
    a direct solve per harmonic, for any damping: ``Z(ω) = K - ω² M + iω C``
    (symmetric), ``z = Z⁻¹ e_c`` gives ``g = z_c``, ``x_p = Z⁻¹ P̂`` gives
    ``p = (x_p)_c``; with ``Z' = dZ/dΩ = k (-2ω M + i C)``,
    ``dg/dΩ = -zᵀ Z' z`` and ``dp/dΩ = -zᵀ Z' x_p``. The complex systems
    are solved in real form (``2 n_dof`` unknowns) by
    :func:`hbmfric.kernels.linalg.solve_inplace`.

The contact force comes from the same AFT kernels as in the full residual
(:func:`_contact_force`). A rigid Coulomb contact is handled by the same DLFT
scheme as in the full residual (:func:`_coulomb`): located reversals
(:func:`hbmfric.kernels.dlft.dlft_located`, the default), with the linear
tail (:func:`hbmfric.kernels.dlft_tail.dlft_tail`) when the law asks for it,
or the classic one (:func:`hbmfric.kernels.dlft.dlft_contact`) for
``aft="samples"``. DLFT reads only the contact rows of the linear residual,
and the condensed residual is their Schur complement: at any point where the
eliminated rows hold (every condensed point, by construction) the force
``λ_X = -R_lin`` that the linear dynamics ask of the contact, hence the
holding force ``h = λ_X + M_cc ü`` of the located scheme, are those of the
full residual, so both paths have the same solutions. The tail needs the
receptance at the contact DOF for the harmonics beyond the balance,
``G(kΩ)`` for ``k <= K``: a modal sum (:func:`_modal_tail_receptance`) or
the direct solves of :func:`hbmfric.kernels.dlft_tail.contact_receptance`.

The problem travels as a :class:`CondensedProblem` named tuple; the residual
dispatcher :func:`hbmfric.kernels.residual.residual` recognises its type.
"""

from collections import namedtuple

import numpy as np

from .._jit import jit
from .aft import aft_jenkins_events, aft_samples
from .dahl import aft_dahl
from .dlft import COULOMB, dlft_contact, dlft_located
from .dlft_tail import contact_receptance, dlft_tail
from .laws import DAHL, JENKINS, is_masing
from .linalg import solve_inplace
from .masing import aft_masing

#: AFT scheme codes (same values as :mod:`hbmfric.kernels.hbm`)
AFT_SAMPLES = 0
AFT_EVENTS = 1
#: receptance methods
MODAL = 0
DIRECT = 1
#: status returned when a direct solve meets a singular dynamic stiffness
SINGULAR_RECEPTANCE = -100

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
        "method",  # int64: MODAL or DIRECT
        "contact_dof",  # int64 (DIRECT)
        "mass",  # float64 (n_dof, n_dof) (DIRECT; (0, 0) for MODAL)
        "damping",  # float64 (n_dof, n_dof) (DIRECT)
        "stiffness",  # float64 (n_dof, n_dof) (DIRECT)
        "load",  # float64 (n_dof, n_coef): P per coefficient, N (DIRECT)
        "contact_mass",  # float64: M_cc, kg (located DLFT of a rigid Coulomb)
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
def _dynamic_stiffness(problem, w, A):
    """Real form ``[[Kd, -ωC], [ωC, Kd]]`` of ``Z(ω)`` into ``A``."""
    n = problem.mass.shape[0]
    for i in range(n):
        for j in range(n):
            kd = problem.stiffness[i, j] - w * w * problem.mass[i, j]
            wc = w * problem.damping[i, j]
            A[i, j] = kd
            A[i, n + j] = -wc
            A[n + i, j] = wc
            A[n + i, n + j] = kd


@jit
def _solve_complex(problem, w, rhs_re, rhs_im, A, b, out):
    """``out = Z(ω)⁻¹ (rhs_re + i rhs_im)``; False if singular."""
    n = rhs_re.size
    _dynamic_stiffness(problem, w, A)
    for i in range(n):
        b[i] = rhs_re[i]
        b[n + i] = rhs_im[i]
    if not solve_inplace(A, b):
        return False
    for i in range(n):
        out[i] = b[i] + 1j * b[n + i]
    return True


@jit
def _harmonic_receptance_direct(k, omega, col, problem, work):
    """As :func:`_harmonic_receptance` by direct solves; the last value is
    False when ``Z(kΩ)`` is singular."""
    n = problem.mass.shape[0]
    A, b, re, im, z, xp = work
    w = k * omega
    c = problem.contact_dof
    re[:] = 0.0
    im[:] = 0.0
    re[c] = 1.0
    if not _solve_complex(problem, w, re, im, A, b, z):
        return 0.0j, 0.0j, 0.0j, 0.0j, False
    load = problem.load
    forced = False
    for i in range(n):
        re[i] = load[i, col]
        im[i] = 0.0 if k == 0 else -load[i, col + 1]
        if re[i] != 0.0 or im[i] != 0.0:
            forced = True
    if forced:
        if not _solve_complex(problem, w, re, im, A, b, xp):
            return 0.0j, 0.0j, 0.0j, 0.0j, False
    else:
        xp[:] = 0.0
    g = z[c]
    p = xp[c]
    dg = 0.0j
    dp = 0.0j
    if k != 0:
        for i in range(n):
            zi = z[i]
            for j in range(n):
                dz = k * (-2.0 * w * problem.mass[i, j] + 1j * problem.damping[i, j])
                dg -= zi * dz * z[j]
                dp -= zi * dz * xp[j]
    return g, p, dg, dp, True


@jit
def _direct_work(problem):
    n = problem.mass.shape[0]
    return (
        np.empty((2 * n, 2 * n)),
        np.empty(2 * n),
        np.empty(n),
        np.empty(n),
        np.empty(n, dtype=np.complex128),
        np.empty(n, dtype=np.complex128),
    )


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
    status = _condensed_linear(y, problem, R, J)
    if status < 0:
        return status
    n = problem.inverse.shape[1]
    if problem.law_code == COULOMB:
        # DLFT on the condensed linear residual: it is the Schur complement
        # of the full one on the contact rows, which is all DLFT reads
        return _coulomb(y, problem, R, J)
    F = np.empty(n)
    dF = np.empty((n, n))
    status = _contact_force(y[:n].copy(), problem, F, dF)
    for i in range(n):
        R[i] += F[i]
        for j in range(n):
            J[i, j] += dF[i, j]
    return status


@jit
def _coulomb(y, problem, R, J):
    """Add a rigid Coulomb contact to the condensed linear residual, by the
    DLFT scheme the full residual uses
    (:func:`hbmfric.kernels.hbm.hbm_residual`): located, with the linear
    tail when ``law_params[4] = K > 0``, classic for ``AFT_SAMPLES``."""
    params = problem.law_params
    if problem.aft_scheme != AFT_EVENTS:
        return dlft_contact(params, 0, y, problem.inverse, problem.forward, R, J)
    hn = problem.harmonic_numbers
    m_cc = problem.contact_mass
    if params[4] > 0.0:
        n_coef = problem.inverse.shape[1]
        omega = y[n_coef]
        q = np.zeros(int(params[4]) + 1, dtype=np.complex128)
        dq = np.zeros(int(params[4]) + 1, dtype=np.complex128)
        if problem.method == DIRECT:
            a2, da2, ok = contact_receptance(
                problem.mass,
                problem.damping,
                problem.stiffness,
                problem.contact_dof,
                omega,
                hn,
                params[3],
                q,
                dq,
            )
        else:
            a2, da2, ok = _modal_tail_receptance(problem, omega, params[3], q, dq)
        if not ok:
            return SINGULAR_RECEPTANCE
        return dlft_tail(
            params,
            hn,
            0,
            m_cc,
            q,
            dq,
            a2,
            da2,
            y,
            problem.inverse,
            problem.forward,
            problem.derivative,
            R,
            J,
        )
    return dlft_located(
        params,
        hn,
        0,
        m_cc,
        y,
        problem.inverse,
        problem.forward,
        problem.derivative,
        R,
        J,
    )


@jit
def _modal_tail_receptance(problem, omega, mu, q, dq):
    """Tail coefficients of the contact receptance by modal sums: as
    :func:`hbmfric.kernels.dlft_tail.contact_receptance` (same outputs and
    conventions: ``q_k = G(kΩ) [k ∉ S] - a₂/k²``, ``a₂ = -μ/Ω²``, ``q[0]``
    flags odd harmonics only), with ``G(kΩ) = Σ_r φ_cr² / d_r(kΩ)``.

    Returns
    -------
    tuple of (float, float, bool)
        ``a₂``, ``da₂/dΩ`` and False if some ``d_r(kΩ)`` is zero.
    """
    n_k = q.size
    hn = problem.harmonic_numbers
    kept = np.zeros(n_k, dtype=np.bool_)
    odd = True
    for k in hn:
        if k % 2 == 0:
            odd = False
        if k < n_k:
            kept[k] = True
    q[0] = 1.0 if odd else 0.0
    dq[0] = 0.0
    a2 = -mu / (omega * omega)
    da2 = 2.0 * mu / (omega * omega * omega)
    phi = problem.contact_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    for k in range(1, n_k):
        if odd and k % 2 == 0:
            q[k] = 0.0
            dq[k] = 0.0
            continue
        g = 0.0j
        dg = 0.0j
        if not kept[k]:
            w = k * omega
            for r in range(phi.size):
                d = w2[r] - w * w + 1j * w * c[r]
                if d == 0.0:
                    return a2, da2, False
                inv_d = 1.0 / d
                g += phi[r] * phi[r] * inv_d
                dg += phi[r] * phi[r] * k * (2.0 * w - 1j * c[r]) * inv_d * inv_d
        q[k] = g - a2 / (k * k)
        dq[k] = dg - da2 / (k * k)
    return a2, da2, True


@jit
def _condensed_linear(y, problem, R, J):
    """Linear part ``D (x̂ - p)`` of the condensed residual and its Jacobian
    (``J`` overwritten); 0, or ``SINGULAR_RECEPTANCE``."""
    hn = problem.harmonic_numbers
    n = problem.inverse.shape[1]
    omega = y[n]
    J[:, :] = 0.0
    work = _direct_work(problem)
    col = 0
    for k in hn:
        if problem.method == DIRECT:
            g, p, dg, dp, ok = _harmonic_receptance_direct(k, omega, col, problem, work)
            if not ok:
                return SINGULAR_RECEPTANCE
        else:
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
    return 0


@jit
def _contact_force(x, problem, F, dF):
    """AFT of the contact law at the contact coefficients ``x`` (the same
    dispatch as :func:`hbmfric.kernels.hbm.hbm_residual`)."""
    code = problem.law_code
    events = problem.aft_scheme == AFT_EVENTS
    if code == JENKINS and events:
        return aft_jenkins_events(
            problem.law_params,
            problem.harmonic_numbers,
            x,
            problem.inverse,
            problem.derivative,
            F,
            dF,
        )
    if is_masing(code) and events:
        return aft_masing(
            code,
            problem.law_params,
            problem.harmonic_numbers,
            x,
            problem.inverse,
            problem.forward,
            problem.derivative,
            F,
            dF,
        )
    if code == DAHL:
        return aft_dahl(
            problem.law_params,
            problem.harmonic_numbers,
            x,
            problem.inverse,
            problem.forward,
            problem.derivative,
            F,
            dF,
        )
    return aft_samples(
        code,
        problem.law_params,
        x,
        problem.inverse,
        problem.forward,
        F,
        dF,
    )


@jit
def condensed_contact_forces(points, problem, F):
    """Contact-force coefficients at condensed solutions (AFT at each; for
    a rigid Coulomb contact the DLFT force).

    Parameters
    ----------
    points : ndarray, shape (n_points, n_coef + 1)
        ``[X_c, Ω]`` per point.
    problem : CondensedProblem
    F : ndarray, shape (n_points, n_coef)
        Output: force coefficients, N.

    Returns
    -------
    int
        Lowest AFT status met (negative on a failure).
    """
    n = problem.inverse.shape[1]
    dF = np.empty((n, n))
    f = np.empty(n)
    R = np.empty(n)
    R_lin = np.empty(n)
    J = np.empty((n, n + 1))
    worst = 1 << 30
    for i in range(points.shape[0]):
        y = points[i].copy()
        if problem.law_code == COULOMB:
            # the DLFT force is what the residual adds to its linear part
            status = condensed_residual(y, problem, R, J)
            _condensed_linear(y, problem, R_lin, J)
            for r in range(n):
                f[r] = R[r] - R_lin[r]
        else:
            status = _contact_force(y[:n].copy(), problem, f, dF)
        if status < worst:
            worst = status
        F[i, :] = f
    return worst


@jit
def condensed_modal_recover(points, F, problem, shapes, X):
    """Response of every DOF at condensed solutions, modal receptance:
    ``x̂_j = Σ_r φ_jr η̂_r`` with ``η̂_r = (q̂_r - φ_cr F̂) / d_r(kΩ)``.

    Parameters
    ----------
    points : ndarray, shape (n_points, n_coef + 1)
        ``[X_c, Ω]`` per point.
    F : ndarray, shape (n_points, n_coef)
        Contact-force coefficients at the points, N.
    problem : CondensedProblem
        With ``method == MODAL``.
    shapes : ndarray, shape (n_dof, n_modes)
        Mass-normalised mode shapes.
    X : ndarray, shape (n_points, n_dof, n_coef)
        Output: coefficients of every DOF, m.
    """
    n = problem.inverse.shape[1]
    phi = problem.contact_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    q = problem.modal_load
    n_dof, n_modes = shapes.shape
    eta = np.empty(n_modes, dtype=np.complex128)
    for i in range(points.shape[0]):
        omega = points[i, n]
        col = 0
        for k in problem.harmonic_numbers:
            w = k * omega
            if k == 0:
                f = F[i, col] + 0.0j
            else:
                f = F[i, col] - 1j * F[i, col + 1]
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
                X[i, j, col] = s.real
                if k != 0:
                    X[i, j, col + 1] = -s.imag
            col += 1 if k == 0 else 2
