"""AFT of the 2D friction contact element (Jenkins friction, unilateral normal).

The element couples two relative displacements of a contact point pair:
``u`` tangential and ``v`` normal, **positive closing** (``v > 0`` presses
the surfaces together). Parameters ``params = [kt, kn, mu, n0]``:

* normal force ``N = max(0, n0 + kn v)`` (penalty stiffness ``kn``, preload
  ``n0``; a negative ``n0`` is an initial gap ``-n0 / kn``);
* tangential force ``T``: a spring ``kt`` in series with a slider at
  ``w``, ``T = kt (u - w)``, held to ``|T| <= mu N`` (Jenkins with the
  friction limit following the normal load).

Both forces act on the relative displacements like spring forces: in an
equation of motion they enter as ``+T`` on ``u`` and ``+N`` on ``v``.

Time update from sample ``i - 1`` to ``i`` (:func:`contact2d_step`):

* ``N_i <= 0`` (separated): ``T_i = 0`` and the slider follows the
  displacement, ``w_i = u_i``, so that the contact sticks where it closes
  again. The closure falls between samples: the march locates it by linear
  interpolation of ``n0 + kn v`` between the last open sample ``j`` and
  the first closed one ``i`` (``s = -N'_j / (N'_i - N'_j)``, ``N' = n0 +
  kn v``) and puts the slider at ``u_j + s (u_i - u_j)``, so that the
  force error of the sampled closure is second order in the sample
  interval, not first;
* otherwise the slider is projected, ``w_i = clamp(w_{i-1}, u_i - mu N_i /
  kt, u_i + mu N_i / kt)``: stick if ``w`` stays, slip if it moves.

Steady state: every step maps the slider position by a clamp onto an
interval (a point when separated), so one period maps it by a clamp too,
``P(w) = clamp(w, A, B)``, and ``P(P(w)) = P(w)``: one pass from the
reference state reaches a periodic state and the second pass is that
periodic state. The march starts at sample 0 with the slider at the
reference position ``w = 0`` (the contact closed at ``u = 0``), marches
passes until the slider at the end of a pass repeats the previous one (two
passes, unless rounding decides otherwise) within the pass budget, and
keeps the last pass. With a constant normal load this is the Jenkins
convention of :mod:`hbmfric.kernels.aft.schemes`: a stuck slider sits at 0, shifted
only as far as needed.

Jacobian: with ``E_i`` the inverse-DFT row of sample ``i``, the slider
gradient is carried through the march (stick ``dw_i = dw_{i-1}``; slip
``dw_i = (E_i, 0) - dT_i / kt``; separated ``dw_i = (E_i, 0)``) and
``dT_i = kt ((E_i, 0) - dw_{i-1})`` in stick, ``s mu kn (0, E_i)`` in slip
(``s = ±1``), 0 when separated; ``dN_i = kn (0, E_i)`` in contact. At a
located closure ``dw = ((1 - s) E_j + s E_i, (u_i - u_j) ds)`` with
``ds = kn (-N'_i E_j + N'_j E_i) / (N'_i - N'_j)²``.

Coefficient layout: ``X`` and ``F`` have shape ``(2, n_coef)``, row 0
tangential, row 1 normal, each row in the layout of
:mod:`hbmfric.kernels.fourier.dft`; the Jacobian has shape ``(2 n_coef, 2 n_coef)``
with the tangential block first in both directions.
"""

import numpy as np

from ..._jit import jit

#: phases of one time step (:func:`contact2d_step`)
PHASE_OPEN = 0
PHASE_STICK = 1
PHASE_SLIP_POSITIVE = 2
PHASE_SLIP_NEGATIVE = 3

#: contact-state codes returned by :func:`aft_contact2d` (the positive ones
#: that mean the same as in :mod:`hbmfric.kernels.aft.schemes` share its values)
STUCK = 1
GROSS_SLIP = 2
SEPARATES = 5
OPEN = 6
#: failure code: the slider did not repeat within the pass budget
NOT_PERIODIC = -3

STATE_NAMES = {
    STUCK: "contact closed and stuck over the whole period",
    GROSS_SLIP: "contact closed over the whole period, slips during it",
    SEPARATES: "contact separates during the period",
    OPEN: "contact open over the whole period",
    NOT_PERIODIC: "the march did not repeat within its pass budget",
}

#: relative tolerance on the slider position for the periodicity check
REPEAT_RTOL = 1e-12
#: law code of the element in the HBM kernels' contact arrays
CONTACT2D = 200
#: pass budget of the march inside the HBM residual
MAX_PASSES = 4


@jit
def contact2d_step(kt, kn, mu, n0, w_prev, u, v):
    """Advance the element from the slider position ``w_prev`` to ``(u, v)``.

    Parameters
    ----------
    kt, kn : float
        Tangential and normal stiffness, N/m (> 0).
    mu : float
        Friction coefficient (>= 0).
    n0 : float
        Preload, N (normal force at ``v = 0``).
    w_prev : float
        Slider position before the step, m.
    u, v : float
        Tangential and normal relative displacement after the step, m
        (``v`` positive closing).

    Returns
    -------
    t : float
        Tangential force, N.
    n : float
        Normal force, N (>= 0).
    w : float
        Slider position after the step, m.
    phase : int
        ``PHASE_OPEN``, ``PHASE_STICK``, ``PHASE_SLIP_POSITIVE`` or
        ``PHASE_SLIP_NEGATIVE``.
    """
    n = n0 + kn * v
    if not n > 0.0:
        return 0.0, 0.0, u, PHASE_OPEN
    limit = mu * n
    t = kt * (u - w_prev)
    if t > limit:
        return limit, n, u - limit / kt, PHASE_SLIP_POSITIVE
    if t < -limit:
        return -limit, n, u + limit / kt, PHASE_SLIP_NEGATIVE
    return t, n, w_prev, PHASE_STICK


@jit
def contact2d_march(
    params, u, v, force_t, force_n, inverse, grad_t, with_grad, max_passes
):
    """Steady-state forces of the element over one sampled period.

    Parameters
    ----------
    params : ndarray, shape (4,)
        ``[kt, kn, mu, n0]``.
    u, v : ndarray, shape (n_time,)
        Tangential and normal relative displacement samples, m.
    force_t, force_n : ndarray, shape (n_time,)
        Output: tangential and normal force samples, N, of the last pass.
    inverse : ndarray, shape (n_time, n_coef)
        Inverse DFT matrix (read only with ``with_grad``).
    grad_t : ndarray, shape (n_time, 2 n_coef)
        Output with ``with_grad``: ``dT_i / d(X_u, X_v)``, N/m.
    with_grad : bool
        Carry the gradient through the march.
    max_passes : int
        Pass budget (>= 2).

    Returns
    -------
    int
        ``STUCK``, ``GROSS_SLIP``, ``SEPARATES``, ``OPEN`` or
        ``NOT_PERIODIC``. ``force_n`` does not depend on the march; the
        slip/stick/open classification is that of the last pass.
    """
    kt = params[0]
    kn = params[1]
    mu = params[2]
    n0 = params[3]
    n = u.size
    n_coef = inverse.shape[1] if with_grad else 0
    dw = np.zeros(2 * n_coef)
    scale = 0.0
    for i in range(n):
        scale = max(scale, abs(u[i]))
        scale = max(scale, mu * max(n0 + kn * v[i], 0.0) / kt)
    w = 0.0
    w_last = 0.0
    was_open = False  # the march starts closed, slider at 0
    status = NOT_PERIODIC
    for p in range(max_passes):
        n_open = 0
        n_slip = 0
        for i in range(n):
            if was_open and n0 + kn * v[i] > 0.0:
                # re-closure between samples i - 1 and i: the slider stops
                # where the normal force crosses zero (linear interpolation)
                j = (i - 1) % n
                a = n0 + kn * v[j]
                b = n0 + kn * v[i]
                s = -a / (b - a)
                w = u[j] + s * (u[i] - u[j])
                if with_grad:
                    du = u[i] - u[j]
                    ga = -b * kn / ((b - a) * (b - a))
                    gb = a * kn / ((b - a) * (b - a))
                    for c in range(n_coef):
                        dw[c] = (1.0 - s) * inverse[j, c] + s * inverse[i, c]
                        dw[n_coef + c] = du * (ga * inverse[j, c] + gb * inverse[i, c])
            t, f_n, w, phase = contact2d_step(kt, kn, mu, n0, w, u[i], v[i])
            was_open = phase == PHASE_OPEN
            force_t[i] = t
            force_n[i] = f_n
            if phase == PHASE_OPEN:
                n_open += 1
            elif phase != PHASE_STICK:
                n_slip += 1
            if with_grad:
                if phase == PHASE_OPEN:
                    for c in range(n_coef):
                        grad_t[i, c] = 0.0
                        grad_t[i, n_coef + c] = 0.0
                        dw[c] = inverse[i, c]
                        dw[n_coef + c] = 0.0
                elif phase == PHASE_STICK:
                    for c in range(n_coef):
                        grad_t[i, c] = kt * (inverse[i, c] - dw[c])
                        grad_t[i, n_coef + c] = -kt * dw[n_coef + c]
                else:
                    s = mu * kn if phase == PHASE_SLIP_POSITIVE else -mu * kn
                    for c in range(n_coef):
                        grad_t[i, c] = 0.0
                        grad_t[i, n_coef + c] = s * inverse[i, c]
                        dw[c] = inverse[i, c]
                        dw[n_coef + c] = -s * inverse[i, c] / kt
        if p >= 1 and abs(w - w_last) <= REPEAT_RTOL * scale:
            if n_open == n:
                status = OPEN
            elif n_open > 0:
                status = SEPARATES
            elif n_slip > 0:
                status = GROSS_SLIP
            else:
                status = STUCK
            break
        w_last = w
    return status


@jit
def aft_contact2d(params, X, inverse, forward, F, dF, max_passes):
    """AFT of the 2D contact element with analytic Jacobian.

    Parameters
    ----------
    params : ndarray, shape (4,)
        ``[kt, kn, mu, n0]``: stiffnesses N/m, friction coefficient,
        preload N.
    X : ndarray, shape (2, n_coef)
        Coefficients of the tangential (row 0) and normal (row 1, positive
        closing) relative displacements, m.
    inverse : ndarray, shape (n_time, n_coef)
        Inverse DFT matrix (:func:`hbmfric.kernels.fourier.dft.fourier_matrices`).
    forward : ndarray, shape (n_coef, n_time)
        Forward DFT matrix.
    F : ndarray, shape (2, n_coef)
        Output: coefficients of the tangential and normal forces, N.
    dF : ndarray, shape (2 n_coef, 2 n_coef)
        Output: ``dF / dX`` (tangential block first), N/m.
    max_passes : int
        Pass budget of the march (>= 2).

    Returns
    -------
    int
        Contact-state code (``STUCK``, ``GROSS_SLIP``, ``SEPARATES``,
        ``OPEN``) or ``NOT_PERIODIC`` (``F`` and ``dF`` then hold the last
        pass).
    """
    n_time, n_coef = inverse.shape
    kn = params[1]
    n0 = params[3]
    u = np.empty(n_time)
    v = np.empty(n_time)
    v_max = -np.inf
    for i in range(n_time):
        a = 0.0
        b = 0.0
        for c in range(n_coef):
            a += inverse[i, c] * X[0, c]
            b += inverse[i, c] * X[1, c]
        u[i] = a
        v[i] = b
        v_max = max(v_max, b)
    F[:, :] = 0.0
    dF[:, :] = 0.0
    if not n0 + kn * v_max > 0.0:
        return OPEN
    force_t = np.empty(n_time)
    force_n = np.empty(n_time)
    grad_t = np.empty((n_time, 2 * n_coef))
    # a run-time flag, not the literal True: one compiled signature of the
    # march serves this caller and the Python edge
    with_grad = n_coef > 0
    status = contact2d_march(
        params, u, v, force_t, force_n, inverse, grad_t, with_grad, max_passes
    )
    for r in range(n_coef):
        acc_t = 0.0
        acc_n = 0.0
        for i in range(n_time):
            w = forward[r, i]
            acc_t += w * force_t[i]
            acc_n += w * force_n[i]
            if w != 0.0:
                for c in range(2 * n_coef):
                    dF[r, c] += w * grad_t[i, c]
                if force_n[i] > 0.0:
                    wk = w * kn
                    for c in range(n_coef):
                        dF[n_coef + r, n_coef + c] += wk * inverse[i, c]
        F[0, r] = acc_t
        F[1, r] = acc_n
    return status
