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
found as for Jenkins (docs/physics.md): in gross slip one march from the sample of
maximum ``v`` with ``λ = +f_s``; a contact stuck over the whole period keeps
``w`` at the reference position 0 (shifted just enough to keep
``|λ| <= f_s``).

The Jacobian is carried analytically through the march (``dλ_i/dV``), then
chained with ``dV/dy = E_c - (dR_lin/dy)_c / ε`` over all unknowns
``y = [X, Ω]``, which gives ``dR/dΩ`` for continuation too.

Two schemes
-----------
:func:`dlft_contact` is the classic scheme above (``aft="samples"``). Its
stick/slip decision rides on the predicted force, whose truncated Fourier
series rings where the Coulomb force jumps; against Den Hartog's exact
solution it is 1.4e-2 off at H = 31 for F_s/P = 0.3 (first order in H).
:func:`dlft_located` (the default, ``aft="events"``) keeps the DLFT idea
(prediction from the linear residual, correction in time, residual
``ε (U - W)``-like) but ends slip where the relative velocity changes sign
(located between samples), decides stick there from the holding force
(the linear residual without the contact DOF's own inertia, which does
not ring), and corrects the DFT for the position of each jump: 2e-3 at
H = 31 for the same case.
"""

import numpy as np

from ..._jit import jit
from ..aft.schemes import GROSS_SLIP, STUCK

#: law code of the rigid Coulomb contact, solved by DLFT (not by the AFT law
#: march of :mod:`hbmfric.kernels.laws.updates`; chosen far from the AFT law codes)
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


# ----------------------------------------------------------------------------
# DLFT with located reversals and the holding force (default scheme)
# ----------------------------------------------------------------------------


@jit
def _jump_correction(harmonic_numbers, theta_e, theta_i, h, jump, out, dout):
    """Fourier-row correction of a jump between two samples.

    The forward DFT (trapezoidal rule) places a jump of size ``jump`` at the
    middle of its sample interval; the exact integral places it at
    ``theta_e``. Adds ``jump g(θ_e) ((θ_i - θ_e) - h/2)`` to ``out`` and the
    derivative of that with respect to ``θ_e`` (at fixed ``jump``) to
    ``dout``, with ``g_r`` the basis function of row ``r`` times its Fourier
    normalisation.
    """
    c1 = np.cos(theta_e)
    s1 = np.sin(theta_e)
    ck = 1.0
    sk = 0.0
    m = 0
    col = 0
    lever = (theta_i - theta_e) - 0.5 * h
    for k in harmonic_numbers:
        while m < k:
            ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
            m += 1
        if k == 0:
            norm = 1.0 / (2.0 * np.pi)
            out[col] += jump * norm * lever
            dout[col] += -jump * norm
            col += 1
        else:
            norm = 1.0 / np.pi
            out[col] += jump * norm * ck * lever
            out[col + 1] += jump * norm * sk * lever
            dout[col] += jump * norm * (-k * sk * lever - ck)
            dout[col + 1] += jump * norm * (k * ck * lever - sk)
            col += 2


@jit
def holding_force(harmonic_numbers, base, m_cc, y, R, J, U, Hc, dH):
    """Coefficients of the contact DOF's motion and of its holding force.

    The holding force ``h = λ_X + M_cc ü`` is the force the linear dynamics
    ask of the contact with the contact DOF's own inertia removed.

    Parameters
    ----------
    harmonic_numbers : ndarray of int64
    base : int
        Index of the contact DOF's first coefficient in ``y``.
    m_cc : float
        Mass of the contact DOF, kg.
    y : ndarray, shape (n + 1,)
        Unknowns ``[X, Ω]``.
    R, J : ndarray, shapes (n,) and (n, n + 1)
        Linear residual ``Z X - P`` (N) and its Jacobian.
    U : ndarray, shape (n_coef,)
        Output: coefficients of ``u``, m.
    Hc : ndarray, shape (n_coef,)
        Output: coefficients of ``h``, N.
    dH : ndarray, shape (n_coef, n + 1)
        Output: ``dHc/dy``.
    """
    n1 = J.shape[1]
    n = n1 - 1
    omega = y[n]
    col = 0
    for k in harmonic_numbers:
        width = 1 if k == 0 else 2
        for q in range(width):
            r = col + q
            U[r] = y[base + r]
            kw2 = (k * omega) ** 2
            Hc[r] = -R[base + r] - m_cc * kw2 * U[r]
            for c in range(n1):
                dH[r, c] = -J[base + r, c]
            dH[r, base + r] -= m_cc * kw2
            dH[r, n] -= 2.0 * m_cc * k * k * omega * U[r]
        col += width


@jit
def contact_samples(harmonic_numbers, base, m_cc, y, R, J, inverse, derivative):
    """:func:`holding_force` and its samples.

    Returns
    -------
    tuple of ndarray
        ``U, Hc, dH`` (as in :func:`holding_force`), then the samples ``u``
        (m), ``d = du/dθ`` (m/rad), ``h`` (N), shapes (n_time,), and
        ``dh/dy``, shape (n_time, n + 1).
    """
    n_coef = inverse.shape[1]
    n1 = J.shape[1]
    U = np.empty(n_coef)
    Hc = np.empty(n_coef)
    dH = np.empty((n_coef, n1))
    holding_force(harmonic_numbers, base, m_cc, y, R, J, U, Hc, dH)
    return U, Hc, dH, inverse @ U, derivative @ U, inverse @ Hc, inverse @ dH


@jit
def stick_sample(i, eps, eta, omega, base, w, dw, u, d, hh, dhh, inverse,
                 derivative, force, grad):  # fmt: skip
    """Force of a sticking contact at sample ``i``,
    ``λ_i = h_i + ε (u_i - w) + η Ω u'_i``, into ``force[i]``, and its
    gradient over ``y`` into ``grad[i]`` (``dw = dw/dy``)."""
    n_coef = inverse.shape[1]
    n1 = grad.shape[1]
    n = n1 - 1
    force[i] = hh[i] + eps * (u[i] - w) + eta * omega * d[i]
    for c in range(n1):
        grad[i, c] = dhh[i, c] - eps * dw[c]
    for c in range(n_coef):
        grad[i, base + c] += eps * inverse[i, c] + eta * omega * derivative[i, c]
    grad[i, n] += eta * d[i]


@jit
def stick_end(harmonic_numbers, i, p, theta_i, h, target, hh, dhh, eps, eta,
              omega, base, w, dw, u, d, inverse, derivative, force, grad, F,
              dF, corr, dcorr):  # fmt: skip
    """End of a stick phase inside the sample interval ``(θ_p, θ_i]``.

    The stick phase holds at sample ``p`` (``force[p]``, ``grad[p]`` hold
    its penalised force ``λ_p``) and the holding force ``h`` has passed
    ``target = ±f_s`` at sample ``i``. The end ``θ_end = θ_i - h + β h`` is
    the crossing of the linear interpolant of ``h`` (``β`` clipped to
    [0, 1]); there the force jumps from the interpolated stick force
    ``λ(θ_end)`` to ``target``. Writes ``force[i] = target`` (zero
    gradient) and adds the DFT correction for the jump's position to ``F``
    and ``dF`` (:func:`_jump_correction`), so that the Fourier coefficients
    stay continuous when the end crosses a sample (a per-sample end jumps
    by ``h (λ_i - target) / π`` there). ``corr``, ``dcorr`` are work arrays
    of shape (n_coef,).
    """
    n1 = grad.shape[1]
    n_coef = corr.size
    # the stick force the phase would have at i
    stick_sample(i, eps, eta, omega, base, w, dw, u, d, hh, dhh, inverse,
                 derivative, force, grad)  # fmt: skip
    den = hh[i] - hh[p]
    beta = (target - hh[p]) / den if den != 0.0 else 1.0
    clipped = beta <= 0.0 or beta >= 1.0
    beta = min(max(beta, 0.0), 1.0)
    lam_p = force[p]
    lam_i = force[i]
    jump = target - (lam_p + beta * (lam_i - lam_p))
    for r in range(n_coef):
        corr[r] = 0.0
        dcorr[r] = 0.0
    theta_e = theta_i - h + beta * h
    _jump_correction(harmonic_numbers, theta_e, theta_i, h, 1.0, corr, dcorr)
    for c in range(n1):
        dbeta = 0.0
        if not clipped:
            dbeta = -(dhh[p, c] + beta * (dhh[i, c] - dhh[p, c])) / den
        djump = -(
            grad[p, c] + beta * (grad[i, c] - grad[p, c]) + (lam_i - lam_p) * dbeta
        )
        for r in range(n_coef):
            dF[r, c] += corr[r] * djump + jump * dcorr[r] * h * dbeta
        grad[i, c] = 0.0
    for r in range(n_coef):
        F[r] += jump * corr[r]
    force[i] = target


@jit
def stuck_at_reference(slip_force, eps, eta, omega, base, u, d, hh, dhh,
                       inverse, forward, derivative, force, grad, R, J):  # fmt: skip
    """If the contact holds with ``w = 0`` all period, add its force
    ``λ = h + ε u + η Ω u'`` (samples ``u``, ``d = u'``, ``hh = h``,
    ``dhh = dh/dy``) to ``R`` and ``J`` and return True (stuck at the
    reference position, the convention of the other laws); else False and
    nothing is added. ``force`` and ``grad`` are work arrays."""
    n_time, n_coef = inverse.shape
    n1 = J.shape[1]
    for i in range(n_time):
        lam = hh[i] + eps * u[i] + eta * omega * d[i]
        if lam > slip_force or lam < -slip_force:
            return False
    dw = np.zeros(n1)
    for i in range(n_time):
        stick_sample(i, eps, eta, omega, base, 0.0, dw, u, d, hh, dhh, inverse,
                     derivative, force, grad)  # fmt: skip
    for r in range(n_coef):
        acc = 0.0
        for i in range(n_time):
            acc += forward[r, i] * force[i]
        R[base + r] += acc
        for i in range(n_time):
            wr = forward[r, i]
            if wr != 0.0:
                for c in range(n1):
                    J[base + r, c] += wr * grad[i, c]
    return True


@jit
def add_samples(forward, force, grad, F, dF):
    """``F += forward @ force`` and ``dF += forward @ grad`` (sampled force
    and its gradient, shapes (n_time,) and (n_time, n + 1))."""
    n_coef, n_time = forward.shape
    n1 = grad.shape[1]
    for r in range(n_coef):
        acc = 0.0
        for i in range(n_time):
            acc += forward[r, i] * force[i]
        F[r] += acc
        for i in range(n_time):
            wr = forward[r, i]
            if wr != 0.0:
                for c in range(n1):
                    dF[r, c] += wr * grad[i, c]


@jit
def dlft_located(params, harmonic_numbers, base, m_cc, y, inverse, forward,
                 derivative, R, J):  # fmt: skip
    """Rigid Coulomb contact by DLFT with located reversals (default scheme).

    Differences from :func:`dlft_contact`, which decides stick and slip on
    the predicted force (whose truncated Fourier series rings where the
    Coulomb force jumps, so that the classic scheme converges only at first
    order in H with a large constant):

    * slip in direction ``s`` lasts until the relative velocity ``u̇``
      changes sign, located between samples by linear interpolation;
    * there the contact sticks if the holding force ``|h| <= f_s``, else it
      slips back at once (force jump ``-2 s f_s``); the holding force is
      the force the linear dynamics ask of the contact with the contact
      DOF's own inertia removed, ``h = λ_X + M_cc ü``, free of the ringing
      of ``λ_X`` for a lumped contact mass;
    * in stick ``λ = h + ε (u - w) + η u̇`` (``w`` = ``u`` at the reversal),
      so that the residual ``λ - λ_X = M_cc ü + η u̇ + ε (u - w)`` vanishes
      exactly when ``u`` stays at ``w``; ``η`` keeps the penalty oscillator
      ``M_cc, η, ε`` from resonating at a harmonic; stick ends when
      ``|λ|`` reaches ``f_s``;
    * the forward DFT is corrected for the position of every jump inside
      its sample interval (second-order accurate Fourier coefficients).

    A contact that holds all period with ``w = 0`` is stuck at the
    reference position (as for the other laws; this fixes the mean).
    Otherwise the march starts at the reversal next to the largest sample
    of ``u``, where the contact has just slid forwards.

    Parameters
    ----------
    params : ndarray, shape (3,)
        ``[slip_force, penalty ε, penalty damping η]`` (N, N/m, N s/m).
    harmonic_numbers : ndarray of int64
    base : int
        Index of the contact DOF's first coefficient in ``y``.
    m_cc : float
        Mass of the contact DOF, kg (diagonal entry).
    y, inverse, forward, derivative, R, J
        As in :func:`dlft_contact`; ``derivative`` is the θ-derivative of
        the inverse DFT.

    Returns
    -------
    int
        ``STUCK`` or ``GROSS_SLIP``.
    """
    slip_force = params[0]
    eps = params[1]
    eta = params[2]
    n_time, n_coef = inverse.shape
    n1 = J.shape[1]
    n = n1 - 1
    omega = y[n]
    h = 2.0 * np.pi / n_time
    # motion and holding force of the contact DOF, coefficients and samples
    U, Hc, dH, u, d, hh, dhh = contact_samples(
        harmonic_numbers, base, m_cc, y, R, J, inverse, derivative
    )
    force = np.zeros(n_time)
    grad = np.zeros((n_time, n1))
    F = np.zeros(n_coef)
    dF = np.zeros((n_coef, n1))
    corr = np.zeros(n_coef)
    dcorr = np.zeros(n_coef)
    dalpha = np.zeros(n1)
    dw = np.zeros(n1)
    dhr = np.zeros(n1)
    # a contact that holds with w = 0 all period is stuck at the reference
    # position (the convention of the other laws; it fixes the mean)
    if stuck_at_reference(slip_force, eps, eta, omega, base, u, d, hh, dhh,
                          inverse, forward, derivative, force, grad, R, J):  # fmt: skip
        return STUCK
    # start: the reversal next to the largest sample
    i_max = np.argmax(u)
    if d[i_max] > 0.0:
        i0 = i_max
    else:
        i0 = (i_max - 1) % n_time
    i1 = (i0 + 1) % n_time
    stuck_all = True
    stick = False
    sign = 1.0  # the contact has just slid forwards
    w = 0.0
    armed = True
    first = True  # the start reversal is the event of interval (i0, i1]
    for j in range(n_time):
        i = (i1 + j) % n_time
        p = (i - 1) % n_time
        theta_i = (i0 + 1 + j) * h
        event = first
        if not first:
            if stick:
                lam = hh[i] + eps * (u[i] - w) + eta * omega * d[i]
                if lam > slip_force or lam < -slip_force:
                    stick = False
                    sign = 1.0 if lam > 0.0 else -1.0
                    armed = sign * d[i] > 0.0
            elif sign * d[i] > 0.0:
                armed = True
            elif armed:
                event = True
        if event:
            # reversal inside (θ_p, θ_i]: locate the zero of u̇
            den = d[p] - d[i]
            alpha = d[p] / den if den != 0.0 else 0.0
            for c in range(n1):
                dalpha[c] = 0.0
            if alpha <= 0.0:
                alpha = 0.0
            elif alpha >= 1.0:
                alpha = 1.0
            else:
                for c in range(n_coef):
                    dalpha[base + c] = (
                        d[p] * derivative[i, c] - d[i] * derivative[p, c]
                    ) / (den * den)
            theta_e = theta_i - h + alpha * h
            h_r = hh[p] + alpha * (hh[i] - hh[p])
            before = sign * slip_force
            if -slip_force <= h_r <= slip_force:
                stick = True
                w = u[p] + alpha * (u[i] - u[p])
                for c in range(n1):
                    dw[c] = (u[i] - u[p]) * dalpha[c]
                    dhr[c] = (
                        dhh[p, c]
                        + alpha * (dhh[i, c] - dhh[p, c])
                        + (hh[i] - hh[p]) * dalpha[c]
                    )
                for c in range(n_coef):
                    dw[base + c] += inverse[p, c] + alpha * (
                        inverse[i, c] - inverse[p, c]
                    )
                jump = h_r - before
            else:
                stick = False
                sign = -sign
                armed = sign * d[i] > 0.0
                jump = -2.0 * before
                for c in range(n1):
                    dhr[c] = 0.0
            # the trapezoidal rule puts the jump mid-interval: correct it
            for r in range(n_coef):
                corr[r] = 0.0
                dcorr[r] = 0.0
            _jump_correction(harmonic_numbers, theta_e, theta_i, h, 1.0, corr, dcorr)
            for r in range(n_coef):
                F[r] += jump * corr[r]
                for c in range(n1):
                    dF[r, c] += corr[r] * dhr[c] + jump * dcorr[r] * h * dalpha[c]
            first = False
        # sample value
        if stick:
            stick_sample(i, eps, eta, omega, base, w, dw, u, d, hh, dhh, inverse,
                         derivative, force, grad)  # fmt: skip
            lam = force[i]
            if event and (lam > slip_force or lam < -slip_force):
                # the stick phase begun in this interval is over by its end
                # (as at later samples): where the holding force at the
                # event reaches -s f_s the stick tends to the reversal
                stick = False
                sign = 1.0 if lam > 0.0 else -1.0
                armed = sign * d[i] > 0.0
                for c in range(n1):
                    grad[i, c] = 0.0
        if not stick:
            stuck_all = False
            force[i] = sign * slip_force
    add_samples(forward, force, grad, F, dF)
    for r in range(n_coef):
        R[base + r] += F[r]
        for c in range(n1):
            J[base + r, c] += dF[r, c]
    return STUCK if stuck_all else GROSS_SLIP
