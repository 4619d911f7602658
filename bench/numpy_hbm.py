"""A plain NumPy HBM of the Jenkins oscillator: the comparison baseline.

Written the way a competent engineer writes it without a JIT and without
analytic Jacobians: FFT-based AFT with the law marched over two periods from
rest, finite-difference Jacobians, pseudo-arclength continuation with a
tangent predictor and a bordered Newton corrector. It does not import
hbmfric.

Problem: ``m ẍ + c ẋ + k x + f(x) = F cos Ωt``, ``f`` a Jenkins element.
Unknowns per point: odd harmonics ``1, 3, …, H`` (``[Xc1, Xs1, …]``) and Ω.
"""

from __future__ import annotations

import time

import numpy as np


def jenkins_aft(
    X: np.ndarray, harmonics: np.ndarray, n_time: int, kt: float, fs: float
):
    """Force coefficients of a Jenkins element, sampled AFT.

    Parameters
    ----------
    X : ndarray, shape (2 n_h,)
        ``[Xc_h, Xs_h]`` per harmonic in ``harmonics``, m.
    harmonics : ndarray of int, shape (n_h,)
    n_time : int
        Samples per period.
    kt, fs : float
        Tangential stiffness (N/m) and slip force (N).

    Returns
    -------
    ndarray, shape (2 n_h,)
    """
    spec = np.zeros(n_time // 2 + 1, dtype=complex)
    spec[harmonics] = (X[0::2] - 1j * X[1::2]) * (n_time / 2)
    u = np.fft.irfft(spec, n_time)
    f = np.empty(n_time)
    force, previous = 0.0, 0.0
    for _ in range(2):
        for i in range(n_time):
            force = min(max(force + kt * (u[i] - previous), -fs), fs)
            previous = u[i]
            f[i] = force
    c = np.fft.rfft(f)[harmonics] * (2.0 / n_time)
    out = np.empty_like(X)
    out[0::2] = c.real
    out[1::2] = -c.imag
    return out


def residual(y: np.ndarray, p: dict) -> np.ndarray:
    """HBM residual at ``y = [X, Ω]``, shape (2 n_h,)."""
    X, omega = y[:-1], y[-1]
    h = p["harmonics"]
    w = h * omega
    d = p["k"] - p["m"] * w**2
    R = np.empty_like(X)
    R[0::2] = d * X[0::2] + p["c"] * w * X[1::2]
    R[1::2] = d * X[1::2] - p["c"] * w * X[0::2]
    R += jenkins_aft(X, h, p["n_time"], p["kt"], p["fs"])
    R[0] -= p["F"]
    return R


def jacobian(y: np.ndarray, p: dict, r0: np.ndarray) -> np.ndarray:
    """Forward-difference Jacobian ``dR/dy``, shape (n, n + 1)."""
    J = np.empty((r0.size, y.size))
    for j in range(y.size):
        step = 1e-7 * max(abs(y[j]), 1e-6)
        yp = y.copy()
        yp[j] += step
        J[:, j] = (residual(yp, p) - r0) / step
    return J


def trace_frf(
    m: float = 1.0,
    c: float = 0.02,
    k: float = 1.0,
    kt: float = 3.0,
    fs: float = 1.0,
    F: float = 0.5,
    omega: tuple[float, float] = (0.5, 3.0),
    H: int = 15,
    n_time: int = 256,
    ds: float = 0.02,
    ds_max: float = 0.08,
    max_steps: int = 2000,
) -> dict:
    """Trace the FRF by pseudo-arclength continuation.

    Returns
    -------
    dict
        ``omega`` (n_points,), ``X`` (n_points, 2 n_h), ``amp1`` first-harmonic
        amplitude, ``n_steps``, ``n_newton``, ``elapsed`` (s).
    """
    start = time.perf_counter()
    p = dict(m=m, c=c, k=k, kt=kt, fs=fs, F=F, n_time=n_time)
    p["harmonics"] = np.arange(1, H + 1, 2)
    n = 2 * p["harmonics"].size
    w_grid = np.linspace(*omega, 65)
    peak = max(
        np.max(F / np.abs(kk - m * w_grid**2 + 1j * c * w_grid)) for kk in (k, k + kt)
    )
    scale = np.full(n + 1, peak)
    scale[-1] = omega[1] - omega[0]
    y = np.zeros(n + 1)
    y[0] = F / (k + kt - m * omega[0] ** 2)
    y[-1] = omega[0]
    n_newton = 0
    for _ in range(50):  # Newton at fixed Ω for the first point
        r = residual(y, p)
        n_newton += 1
        if np.max(np.abs(r)) < 1e-10:
            break
        y[:-1] -= np.linalg.solve(jacobian(y, p, r)[:, :-1], r)
    tangent = np.zeros(n + 1)
    tangent[-1] = 1.0
    points = [y.copy()]
    n_steps = 0
    while n_steps < max_steps and omega[0] <= y[-1] <= omega[1]:
        J = jacobian(y, p, residual(y, p)) * scale
        A = np.vstack((J, tangent))
        t = np.linalg.solve(A, np.r_[np.zeros(n), 1.0])
        t /= np.linalg.norm(t)
        y_pred = y + ds * t * scale
        z = y_pred.copy()
        converged = False
        for it in range(1, 11):  # noqa: B007 (it is read after the loop)
            r = residual(z, p)
            n_newton += 1
            if np.max(np.abs(r)) < 1e-10:
                converged = True
                break
            A = np.vstack((jacobian(z, p, r), t / scale))
            z -= np.linalg.solve(A, np.r_[r, t @ ((z - y_pred) / scale)])
        n_steps += 1
        if not converged:
            ds *= 0.5
            if ds < 1e-7:
                break
            continue
        y, tangent = z, t
        points.append(y.copy())
        ds = min(ds * (1.5 if it <= 3 else 0.7), ds_max)
    pts = np.array(points)
    X = pts[:, :-1]
    return {
        "omega": pts[:, -1],
        "X": X,
        "amp1": np.hypot(X[:, 0], X[:, 1]),
        "n_steps": n_steps,
        "n_newton": n_newton,
        "elapsed": time.perf_counter() - start,
    }
