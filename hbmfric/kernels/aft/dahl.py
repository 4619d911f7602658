"""AFT of the modified Dahl law: its periodic state over one period of
samples (the increment update is :func:`hbmfric.kernels.laws.dahl.dahl_update`).

Periodic state (:func:`dahl_periodic`, :func:`aft_dahl`): marching one period
of samples from a starting force ``F₀`` gives ``F_N(F₀)``, a contraction with
slope ``A = Π ∂F_i/∂F_{i-1} = exp(−β TV(u))`` for μ = 1 (TV the total
variation of ``u`` over the period). In the AFT (:func:`aft_dahl`) the
march also passes through every reversal of ``u`` between two samples,
located on the Fourier series, so that for μ = 1 the force at the samples
is exact (a march that turned at the samples would be off by O(h²)).
The periodic force is the fixed point
``F_N(F₀) = F₀``, solved by Newton's method on ``F₀`` (one step for μ = 1,
where ``F_N`` is affine in ``F₀``), and the Jacobian ``dF/dX`` follows from
the implicit function theorem: ``dF₀/dX = (∂F_N/∂X) / (1 − A)``. A constant
displacement (``TV = 0``) has no loop: its limit, a vanishing loop, sits at
the mid-envelope ``½(h_u + h_l)`` with the small-loop stiffness
``β ((h_u − h_l)/2)^μ`` (equal relaxation rates towards both envelopes).
"""

import numpy as np

from ..._jit import jit
from ..fourier.segments import project_samples
from ..laws.dahl import dahl_update

#: status codes of the periodic solvers
DAHL_CONVERGED = 3  # same value as schemes.MARCHED: "law marched to its periodic state"
DAHL_STATIC = 4
DAHL_NOT_CONVERGED = -2

#: Newton iterations allowed for the periodic starting force (μ ≠ 1)
MAX_FIXED_POINT_ITERATIONS = 60
#: relative tolerance of the periodic fixed point
FIXED_POINT_RTOL = 1e-13


@jit
def _mid_envelope(params, u):
    """``½(h_u + h_l)(u)`` and the small-loop stiffness there."""
    upper = params[2] * u + params[3]
    lower = params[4] * u + params[5]
    width = 0.5 * (upper - lower)
    k0 = params[0] * (max(width, 0.0) ** params[1])
    return 0.5 * (upper + lower), k0


@jit
def _march(params, u, f0, force):
    """March one period from ``force[0] = f0``; returns ``(f_N, A)`` with
    ``A = ∂f_N/∂f0``."""
    n = u.size
    force[0] = f0
    f = f0
    slope = 1.0
    for j in range(n):
        i = (j + 1) % n
        f, a, _, _ = dahl_update(params, f, u[j], u[i])
        slope *= a
        if i != 0:
            force[i] = f
    return f, slope


@jit
def _fixed_point(params, u, force):
    """Periodic force samples in ``force``; returns ``(status, A)``."""
    n = u.size
    u_min = u[0]
    u_max = u[0]
    for i in range(n):
        u_min = min(u_min, u[i])
        u_max = max(u_max, u[i])
    if u_max == u_min:
        mid, _ = _mid_envelope(params, u[0])
        for i in range(n):
            force[i] = mid
        return DAHL_STATIC, 1.0
    f0, _ = _mid_envelope(params, u[0])
    scale = abs(params[3]) + abs(params[5]) + abs(params[2] * u[0]) + 1e-300
    scale += abs(params[4] * u[0])
    slope = 0.0
    for _it in range(MAX_FIXED_POINT_ITERATIONS):
        fn, slope = _march(params, u, f0, force)
        g = fn - f0
        if slope >= 1.0:
            return DAHL_STATIC, slope
        step = g / (1.0 - slope)
        f0 += step
        if abs(step) <= FIXED_POINT_RTOL * scale:
            _march(params, u, f0, force)
            return DAHL_CONVERGED, slope
        if params[1] == 1.0:
            # affine map: one Newton step is exact; one more march fills force
            fn, slope = _march(params, u, f0, force)
            return DAHL_CONVERGED, slope
    return DAHL_NOT_CONVERGED, slope


@jit
def dahl_periodic(params, u, force):
    """Steady-state periodic Dahl force for one sampled period of ``u``.

    Parameters
    ----------
    params : ndarray, shape (6,)
    u : ndarray, shape (n_time,)
        Displacement samples over one period, m.
    force : ndarray, shape (n_time,)
        Output: force samples, N.

    Returns
    -------
    int
        ``DAHL_CONVERGED``, ``DAHL_STATIC`` (constant ``u``: mid-envelope
        force) or ``DAHL_NOT_CONVERGED``.
    """
    status, _ = _fixed_point(params, u, force)
    return status


#: iterations of the safeguarded Newton search for a reversal of ``u``
MAX_REVERSAL_ITERATIONS = 60


@jit
def _reversal(harmonic_numbers, X, a, b, ga):
    """``θ`` in ``(a, b)`` where ``u'(θ) = 0``, given that ``u'`` changes
    sign on ``[a, b]`` (``ga = u'(a)``): Newton safeguarded by bisection,
    at most ``MAX_REVERSAL_ITERATIONS`` steps."""
    lo = a
    hi = b
    t = 0.5 * (a + b)
    for _ in range(MAX_REVERSAL_ITERATIONS):
        g = 0.0
        dg = 0.0
        col = 0
        for k in harmonic_numbers:
            if k == 0:
                col += 1
                continue
            c = np.cos(k * t)
            s = np.sin(k * t)
            g += k * (X[col + 1] * c - X[col] * s)
            dg -= k * k * (X[col] * c + X[col + 1] * s)
            col += 2
        if g == 0.0:
            return t
        if (g > 0.0) == (ga > 0.0):
            lo = t
        else:
            hi = t
        step_ok = dg != 0.0
        t_new = t - g / dg if step_ok else 0.5 * (lo + hi)
        if not (lo < t_new < hi):
            t_new = 0.5 * (lo + hi)
        if abs(t_new - t) <= 1e-15 * (1.0 + abs(t)) or hi - lo <= 1e-15:
            return t_new
        t = t_new
    return t


@jit
def aft_dahl(params, harmonic_numbers, X, inverse, forward, derivative, F, dF):
    """AFT of the modified Dahl law at its periodic state, with the
    reversals of the displacement located.

    The law is rate independent and integrated exactly along a monotone
    path (μ = 1), so the force at the samples is exact once every reversal
    of ``u`` between two samples is a node of the march: each sign change
    of ``u'`` between neighbouring samples is located
    (:func:`_reversal`) and inserted, with ``du(θ*)/dX`` the basis at
    ``θ*`` (``u'(θ*) = 0``, so ``θ*`` moving with ``X`` does not count).
    The coefficients are then the forward DFT of the force samples.

    Parameters
    ----------
    params : ndarray, shape (6,)
        ``[β, μ, a, b, d, e]``.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    X : ndarray, shape (n_coef,)
        Displacement coefficients, m.
    inverse : ndarray, shape (n_time, n_coef)
    forward : ndarray, shape (n_coef, n_time)
    derivative : ndarray, shape (n_time, n_coef)
    F : ndarray, shape (n_coef,)
        Output: force coefficients, N.
    dF : ndarray, shape (n_coef, n_coef)
        Output: ``dF/dX``, N/m.

    Returns
    -------
    int
        Status of :func:`dahl_periodic`.
    """
    n_time, n_coef = inverse.shape
    u = inverse @ X
    du = derivative @ X
    # the path: samples and located reversals in between
    path_u = np.empty(2 * n_time)
    path_basis = np.empty((2 * n_time, n_coef))
    sample_at = np.empty(n_time, dtype=np.int64)
    n_path = 0
    h = 2.0 * np.pi / n_time
    for i in range(n_time):
        sample_at[i] = n_path
        path_u[n_path] = u[i]
        for c in range(n_coef):
            path_basis[n_path, c] = inverse[i, c]
        n_path += 1
        j = (i + 1) % n_time
        if (du[i] > 0.0 and du[j] < 0.0) or (du[i] < 0.0 and du[j] > 0.0):
            t = _reversal(harmonic_numbers, X, i * h, (i + 1) * h, du[i])
            value = 0.0
            col = 0
            for k in harmonic_numbers:
                if k == 0:
                    path_basis[n_path, col] = 1.0
                    col += 1
                else:
                    path_basis[n_path, col] = np.cos(k * t)
                    path_basis[n_path, col + 1] = np.sin(k * t)
                    col += 2
            for c in range(n_coef):
                value += path_basis[n_path, c] * X[c]
            path_u[n_path] = value
            n_path += 1
    pu = path_u[:n_path].copy()
    basis = path_basis[:n_path]
    force = np.empty(n_path)
    grad = np.zeros((n_path, n_coef))
    status, _ = _fixed_point(params, pu, force)
    if status == DAHL_STATIC:
        # vanishing loop: F = mid(ū) + k0 (u - ū)
        mean = np.zeros(n_coef)
        for i in range(n_time):
            for c in range(n_coef):
                mean[c] += inverse[i, c] / n_time
        _, k0 = _mid_envelope(params, u[0])
        k_mid = 0.5 * (params[2] + params[4])
        for i in range(n_path):
            for c in range(n_coef):
                grad[i, c] = k_mid * mean[c] + k0 * (basis[i, c] - mean[c])
    elif status == DAHL_CONVERGED:
        # partial derivatives with dF0/dX = 0, and products of ∂F_i/∂F_{i-1}
        carry = np.empty(n_path + 1)
        carry[0] = 1.0
        last = np.zeros(n_coef)
        f = force[0]
        for j in range(n_path):
            i = (j + 1) % n_path
            f, a, b, d = dahl_update(params, f, pu[j], pu[i])
            carry[j + 1] = carry[j] * a
            for c in range(n_coef):
                prev = grad[j, c] if j > 0 else 0.0
                value = a * prev + b * basis[j, c] + d * basis[i, c]
                if i == 0:
                    last[c] = value
                else:
                    grad[i, c] = value
        gain = 1.0 / (1.0 - carry[n_path])
        for c in range(n_coef):
            dstart = last[c] * gain
            grad[0, c] = dstart
            for i in range(1, n_path):
                grad[i, c] += carry[i] * dstart
    sample_force = np.empty(n_time)
    sample_grad = np.empty((n_time, n_coef))
    for i in range(n_time):
        sample_force[i] = force[sample_at[i]]
        for c in range(n_coef):
            sample_grad[i, c] = grad[sample_at[i], c]
    F[:] = 0.0
    dF[:, :] = 0.0
    project_samples(
        forward, sample_force, sample_grad, np.int64(0), n_time, 1.0, F, dF
    )  # np.int64: not a literal 0, one signature
    return status


@jit
def dahl_march(params, u, f0, force):
    """March the law along a displacement record (a transient, not a loop).

    Parameters
    ----------
    params : ndarray, shape (6,)
    u : ndarray, shape (n,)
        Displacement path, m.
    f0 : float
        Force at ``u[0]``, N.
    force : ndarray, shape (n,)
        Output: force along the path, N.
    """
    f = f0
    force[0] = f
    for i in range(1, u.size):
        f = dahl_update(params, f, u[i - 1], u[i])[0]
        force[i] = f
