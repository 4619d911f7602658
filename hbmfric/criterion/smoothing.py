"""Noise-tolerant resampling of FRFs: interpolation of the log amplitude onto
a common uniform frequency grid, local quadratic smoothing there, noise
estimate, sub-grid peak location and flank crossings."""

from __future__ import annotations

import numpy as np


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
    """Local quadratic smoothing (tricube weights) of a curve already on the
    uniform ``grid`` (NaN outside its range); ``half_width <= 0`` returns it
    unchanged.

    The same linear operator acts on every curve, so stretches where two
    curves coincide stay identical after smoothing.
    """
    if half_width <= 0.0:
        return values.copy()
    dx = grid[1] - grid[0]
    hp = max(int(np.ceil(half_width / dx)), 2)
    h = (hp + 1) * dx
    pad = np.full(values.size + 2 * hp, np.nan)
    pad[hp:-hp] = values
    win = np.lib.stride_tricks.sliding_window_view(pad, 2 * hp + 1)  # (n, 2hp+1)
    x = np.arange(-hp, hp + 1) * dx / h
    ok = np.isfinite(win)
    w = np.where(ok, (1.0 - np.abs(x) ** 3) ** 3, 0.0)
    y = np.where(ok, win, 0.0)
    s = [w.sum(axis=1)] + [(w * x**p).sum(axis=1) for p in range(1, 5)]
    t = [(w * y).sum(axis=1), (w * x * y).sum(axis=1), (w * x**2 * y).sum(axis=1)]
    A = np.stack(
        [
            np.stack([s[0], s[1], s[2]], axis=-1),
            np.stack([s[1], s[2], s[3]], axis=-1),
            np.stack([s[2], s[3], s[4]], axis=-1),
        ],
        axis=-2,
    )
    out = np.full(values.shape, np.nan)
    inside = np.isfinite(values)
    if np.count_nonzero(inside) < 3:
        return out
    A = A[inside] + 1e-12 * s[0][inside, None, None] * np.eye(3)
    b = np.stack(t, axis=-1)[inside, :, None]
    coef = np.linalg.solve(A, b)[..., 0]
    hi = np.max(np.where(ok, win, -np.inf), axis=1)[inside]
    lo = np.min(np.where(ok, win, np.inf), axis=1)[inside]
    out[inside] = np.clip(coef[:, 0], lo, hi)
    return out
