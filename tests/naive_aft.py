"""Plain-NumPy references for the kernels (no Numba, no hbmfric imports):
the real DFT by explicit sums, the Jenkins march from rest until the loop
closes, the cubic law and the Jenkins describing function."""

from __future__ import annotations

import numpy as np


def synthesize(harmonics, X, theta):
    """``x(θ) = X0 + Σ Xc_k cos kθ + Xs_k sin kθ`` for the given harmonics."""
    x = np.zeros_like(theta)
    col = 0
    for k in harmonics:
        if k == 0:
            x += X[col]
            col += 1
        else:
            x += X[col] * np.cos(k * theta) + X[col + 1] * np.sin(k * theta)
            col += 2
    return x


def analyse(harmonics, f):
    """Fourier coefficients of one sampled period by explicit sums."""
    n = f.size
    theta = 2 * np.pi * np.arange(n) / n
    out = []
    for k in harmonics:
        if k == 0:
            out.append(f.mean())
        else:
            out.append(2 * np.mean(f * np.cos(k * theta)))
            out.append(2 * np.mean(f * np.sin(k * theta)))
    return np.array(out)


def jenkins_march(u, kt, fs, max_periods=50):
    """Steady loop of a Jenkins element: march from rest, period after
    period, until the force at the period start repeats."""
    f = 0.0
    prev = 0.0
    start = np.nan
    loop = np.empty_like(u)
    for _ in range(max_periods):
        for i, ui in enumerate(u):
            f = min(max(f + kt * (ui - prev), -fs), fs)
            prev = ui
            loop[i] = f
        if f == start:
            break
        start = f
    return loop


def jenkins_first_harmonic(kt, fs, a):
    """Describing function of a Jenkins element under ``u = a cos θ``,
    derived from the loop: unloading branch ``f = fs - kt a (1 - cos θ)``
    until it saturates at ``-fs`` (θ = β), mirrored on the second half."""
    if kt * a <= fs:
        return kt * a, 0.0
    beta = np.arccos(1 - 2 * fs / (kt * a))
    # ∫₀^β (fs - kt a + kt a cos θ) cos θ dθ + ∫_β^π (-fs) cos θ dθ, ×2/π
    c = (fs - kt * a) * np.sin(beta) + kt * a * (beta / 2 + np.sin(2 * beta) / 4)
    c += fs * np.sin(beta)
    s = (fs - kt * a) * (1 - np.cos(beta)) + kt * a * np.sin(beta) ** 2 / 2
    s += -fs * (1 + np.cos(beta))
    return 2 * c / np.pi, 2 * s / np.pi
