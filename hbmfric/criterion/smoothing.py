"""Noise-tolerant resampling of FRFs: local quadratic regression of the log
amplitude onto a common frequency grid, and sub-grid peak location."""

from __future__ import annotations

import numpy as np


def smooth_log(
    omega: np.ndarray,
    log_amp: np.ndarray,
    grid: np.ndarray,
    half_width: float,
    min_points: int = 7,
) -> np.ndarray:
    """Local quadratic regression (tricube weights) of ``log_amp(omega)``
    evaluated at ``grid``.

    Parameters
    ----------
    omega : ndarray, shape (n,)
        Sample frequencies, increasing (uneven spacing allowed).
    log_amp : ndarray, shape (n,)
        Log amplitude at the samples.
    grid : ndarray, shape (m,)
        Where to evaluate; points outside ``[omega[0], omega[-1]]`` get NaN.
    half_width : float
        Half width of the regression window, same unit as ``omega``; it is
        widened locally to hold at least ``min_points`` samples.
    min_points : int, default 7

    Returns
    -------
    ndarray, shape (m,)
        Smoothed log amplitude (NaN outside the sampled range).

    Notes
    -----
    A quadratic keeps the height of a resonance peak whose width exceeds the
    window, which a moving average would shave off; in log amplitude the
    multiplicative noise of measurements becomes additive.
    """
    out = np.full(grid.shape, np.nan)
    inside = (grid >= omega[0]) & (grid <= omega[-1])
    g = grid[inside]
    if g.size == 0:
        return out
    d = omega[None, :] - g[:, None]  # (m, n)
    k = min(min_points, omega.size) - 1
    kth = np.partition(np.abs(d), k, axis=1)[:, k]
    # samples on both sides (where there are any): a one-sided window lets
    # the parabola swing across a gap of an uneven grid
    side = []
    for mask in (d <= 0.0, d >= 0.0):
        dist = np.where(mask, np.abs(d), np.inf)
        m = min(2, omega.size - 1)
        near = np.partition(dist, m - 1, axis=1)[:, m - 1]
        side.append(np.where(np.isfinite(near), near, 0.0))
    h = np.maximum.reduce([np.full(g.shape, half_width), kth, *side])
    h = (h * 1.0001)[:, None]
    w = np.clip(1.0 - (np.abs(d) / h) ** 3, 0.0, None) ** 3
    x = d / h
    s = [np.sum(w * x**p, axis=1) for p in range(5)]
    t = [np.sum(w * x**p * log_amp[None, :], axis=1) for p in range(3)]
    A = np.stack(
        [
            np.stack([s[0], s[1], s[2]], axis=-1),
            np.stack([s[1], s[2], s[3]], axis=-1),
            np.stack([s[2], s[3], s[4]], axis=-1),
        ],
        axis=-2,
    )
    A += 1e-12 * s[0][:, None, None] * np.eye(3)
    b = np.stack(t, axis=-1)[..., None]
    coef = np.linalg.solve(A, b)[..., 0]
    # never leave the range of the samples in the window
    inwin = w > 0.0
    hi = np.max(np.where(inwin, log_amp[None, :], -np.inf), axis=1)
    lo = np.min(np.where(inwin, log_amp[None, :], np.inf), axis=1)
    out[inside] = np.clip(coef[:, 0], lo, hi)
    return out


def peak(grid: np.ndarray, log_amp: np.ndarray) -> tuple[float, float, bool]:
    """Location and height of the maximum of a smoothed curve.

    The grid maximum is refined by the parabola through it and its two
    neighbours.

    Returns
    -------
    omega_peak : float
    log_amp_peak : float
    interior : bool
        False when the maximum sits at an end of the sampled range (the true
        peak may lie outside the data).
    """
    ok = np.nonzero(np.isfinite(log_amp))[0]
    if ok.size < 3:
        return float("nan"), float("nan"), False
    i = int(ok[np.argmax(log_amp[ok])])
    if i == ok[0] or i == ok[-1]:
        return float(grid[i]), float(log_amp[i]), False
    y0, y1, y2 = log_amp[i - 1], log_amp[i], log_amp[i + 1]
    den = y0 - 2.0 * y1 + y2
    step = grid[i + 1] - grid[i]
    if den >= 0.0:
        return float(grid[i]), float(y1), True
    delta = 0.5 * (y0 - y2) / den
    return (
        float(grid[i] + delta * step),
        float(y1 - 0.25 * (y0 - y2) * delta),
        True,
    )


def left_crossing(grid: np.ndarray, log_amp: np.ndarray, level: float, below: float):
    """Highest frequency under ``below`` where the curve rises through
    ``level`` (the low-frequency flank of a resonance), or NaN."""
    ok = np.isfinite(log_amp) & (grid <= below)
    idx = np.nonzero(ok)[0]
    if idx.size < 2:
        return float("nan")
    y = log_amp[idx] - level
    up = np.nonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))[0]
    if up.size == 0:
        return float("nan")
    j = up[-1]
    x0, x1 = grid[idx[j]], grid[idx[j + 1]]
    return float(x0 + (x1 - x0) * (-y[j]) / (y[j + 1] - y[j]))


def interp_log(omega: np.ndarray, log_amp: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Linear interpolation of ``log_amp(omega)`` at ``grid`` (NaN outside the
    sampled range)."""
    out = np.interp(grid, omega, log_amp)
    out[(grid < omega[0]) | (grid > omega[-1])] = np.nan
    return out


def noise_level(omega: np.ndarray, log_amp: np.ndarray) -> float:
    """Robust estimate of the standard deviation of additive noise on
    ``log_amp`` (multiplicative noise on the amplitude).

    Each interior sample is compared with the straight line through its two
    neighbours; the median absolute residual, scaled for a Gaussian, is the
    estimate. A smooth curve sampled densely gives nearly 0.
    """
    if omega.size < 3:
        return 0.0
    w0, w1, w2 = omega[:-2], omega[1:-1], omega[2:]
    t = (w1 - w0) / (w2 - w0)
    r = log_amp[1:-1] - ((1.0 - t) * log_amp[:-2] + t * log_amp[2:])
    gain = np.sqrt(1.0 + (1.0 - t) ** 2 + t**2)
    return float(np.median(np.abs(r) / gain) / 0.6745)


def smooth_grid(grid: np.ndarray, values: np.ndarray, half_width: float) -> np.ndarray:
    """Local quadratic smoothing of curves already on the uniform ``grid``
    (NaN outside their range); ``half_width <= 0`` returns them unchanged.

    The same linear operator acts on every curve, so stretches where two
    curves coincide stay identical after smoothing.
    """
    if half_width <= 0.0:
        return values.copy()
    ok = np.isfinite(values)
    out = np.full(values.shape, np.nan)
    if np.count_nonzero(ok) < 3:
        return out
    out[ok] = smooth_log(grid[ok], values[ok], grid[ok], half_width, min_points=3)
    return out
