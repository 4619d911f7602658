"""Noise-tolerant resampling of FRFs: interpolation of the log amplitude onto
a common uniform frequency grid, local quadratic smoothing there, noise
estimate and its propagation through both steps, sub-grid peak location and
flank crossings."""

from __future__ import annotations

import numpy as np
from scipy import sparse


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


#: a change of the interpolation within this many of its own noise's
#: standard deviations is read as noise (:func:`interpolation_error`)
INTERPOLATION_NOISE_Z = 3.0


def interpolation_error(
    omega: np.ndarray,
    log_amp: np.ndarray,
    grid: np.ndarray,
    half_width: float,
    noise: float = 0.0,
) -> np.ndarray:
    """Estimated error of the smoothed linear interpolation of ``log_amp``
    at ``grid`` due to the spacing of the samples: the largest change of
    ``smooth_grid(interp_log(...))`` when every other sample is left out
    (once the odd, once the even ones; the first and last are kept).

    Where the samples resolve the curve this change is small (three times
    the chord error at second order, plus noise averaged by the window);
    where they straddle a resonance peak it is of the size of the part of
    the peak the chords cut off. The change itself is taken, not a third
    of it (Richardson): outside the asymptotic regime a third still left
    a Menq family at 40 uneven samples per curve read macroslip (1 of 12
    draws). Without it, the criterion read clean
    Jenkins families sampled at 15 uneven frequencies per curve as
    microslip (3 of 12 draws) and Menq families at 40 as macroslip
    (4 of 12), at margins of 4-120 noise units (stop 34).

    Parameters
    ----------
    omega, log_amp : ndarray, shape (n,)
        Samples (increasing ``omega``) and their log amplitudes.
    grid : ndarray, shape (n_grid,)
        Uniform common grid.
    half_width : float
        Smoothing half width (unit of ``omega``), as for :func:`smooth_grid`.
    noise : float, default 0
        Standard deviation of the samples' log-amplitude noise. The part of
        the change that noise explains (up to ``INTERPOLATION_NOISE_Z``
        standard deviations of the change's own noise, the variance of the
        smoothed half less that of the smoothed whole) is not counted: that
        noise is already in the criterion's noise unit.

    Returns
    -------
    ndarray, shape (n_grid,)
        Non-negative; NaN outside the sampled range.
    """
    n = omega.size
    full = smooth_grid(grid, interp_log(omega, log_amp, grid), half_width)
    sd_full = smoothed_noise(omega, grid, half_width, noise) if noise > 0 else 0.0

    def change(step: int) -> np.ndarray:
        """Largest change when only every ``step``-th sample is kept."""
        out = np.zeros(grid.shape)
        for start in range(step):
            keep = np.zeros(n, dtype=bool)
            keep[start::step] = True
            keep[0] = keep[-1] = True
            if np.count_nonzero(keep) == n:
                continue
            coarse = smooth_grid(
                grid, interp_log(omega[keep], log_amp[keep], grid), half_width
            )
            with np.errstate(invalid="ignore"):
                d = np.abs(coarse - full)
                if noise > 0:
                    sd_c = smoothed_noise(omega[keep], grid, half_width, noise)
                    sd_d = np.sqrt(np.maximum(sd_c**2 - sd_full**2, 0.0))
                    d = np.maximum(d - INTERPOLATION_NOISE_Z * sd_d, 0.0)
            out = np.fmax(out, np.where(np.isfinite(d), d, 0.0))
        return out

    if n < 8:
        err = np.full(grid.shape, np.inf)
    else:
        d2, d4 = change(2), change(4)
        # Richardson where the chords converge at second order (d4 = 4 d2:
        # the error is d2 / 3); where they do not (a peak the samples
        # straddle at both spacings, d4 close to d2) the change itself
        with np.errstate(invalid="ignore", divide="ignore"):
            factor = np.clip(np.where(d2 > 0, d4 / d2 - 1.0, 1.0), 1.0, 3.0)
        err = d2 / factor
    err[~np.isfinite(full)] = np.nan
    return err


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


def without_dips(
    omega: np.ndarray,
    log_amp: np.ndarray,
    grid: np.ndarray,
    half_width: float,
    sigma: float,
    depth: float = 3.5,
    passes: int = 2,
) -> np.ndarray:
    """Samples to keep once isolated deep dips are removed.

    The noise model of the criterion is Gaussian in log amplitude. The
    magnitude of a noisy measurement is not: where the noise is a sizeable
    fraction of the signal, ``log |1 + e|`` has a heavy *lower* tail (a
    sample can fall close to zero, never far above the signal), and a few
    such dips pull a smoothed curve down by several of its noise units.
    This drops every sample lying more than ``depth * sigma`` below the
    smoothed curve (interpolated back at the sample), and repeats it
    ``passes`` times. Only dips are dropped: a resonance peak is a feature
    the smoother flattens, so the samples at its top lie *above* the
    smoothed curve and are always kept. For Gaussian noise the rule drops
    about 0.02 % of the samples.

    Parameters
    ----------
    omega : ndarray, shape (n,)
        Sorted sample frequencies.
    log_amp : ndarray, shape (n,)
        Log amplitude of the samples.
    grid : ndarray, shape (n_grid,)
        Uniform common grid of :func:`smooth_grid`.
    half_width : float
        Smoothing half width (unit of ``grid``); ``<= 0`` (clean data, no
        smoothing) keeps every sample.
    sigma : float
        Noise of the samples (log amplitude), e.g. :func:`noise_level`.
    depth : float
        Dips deeper than ``depth * sigma`` are dropped.
    passes : int
        Rounds of smoothing and dropping.

    Returns
    -------
    ndarray of bool, shape (n,)
        True for the samples to keep (at least 3 are always kept).
    """
    keep = np.ones(omega.size, dtype=bool)
    if half_width <= 0.0 or sigma <= 0.0 or omega.size < 8:
        return keep
    for _ in range(passes):
        w, y = omega[keep], log_amp[keep]
        smooth = smooth_grid(grid, interp_log(w, y, grid), half_width)
        ok = np.isfinite(smooth)
        if np.count_nonzero(ok) < 3:
            break
        at_samples = np.interp(omega, grid[ok], smooth[ok])
        dip = log_amp - at_samples < -depth * sigma
        new = keep & ~dip
        if np.count_nonzero(new) < max(3, omega.size // 2) or np.array_equal(new, keep):
            break
        keep = new
    return keep


def _local_weights(
    grid: np.ndarray, finite: np.ndarray, half_width: float
) -> tuple[np.ndarray, int]:
    """Equivalent kernel of the local quadratic smoother.

    Parameters
    ----------
    grid : ndarray, shape (n_grid,)
        Uniform grid.
    finite : ndarray of bool, shape (n_grid,)
        Where the curve has a value.
    half_width : float, > 0
        Half width of the window (unit of ``grid``).

    Returns
    -------
    weights : ndarray, shape (n_grid, 2 * hp + 1)
        ``weights[k, m]`` multiplies the value at grid index ``k - hp + m``
        in the smoothed value at ``k`` (0 outside the curve).
    hp : int
        Half width of the window in grid steps.
    """
    dx = grid[1] - grid[0]
    hp = max(int(np.ceil(half_width / dx)), 2)
    h = (hp + 1) * dx
    pad = np.zeros(finite.size + 2 * hp, dtype=bool)
    pad[hp:-hp] = finite
    ok = np.lib.stride_tricks.sliding_window_view(pad, 2 * hp + 1)  # (n, 2hp+1)
    x = np.arange(-hp, hp + 1) * dx / h
    tricube = (1.0 - np.abs(x) ** 3) ** 3
    # windows wholly on the curve share one kernel; only those that reach
    # past an end of it (or a gap) need their own
    full = ok.all(axis=1)
    rows = np.r_[np.nonzero(~full)[0], np.nonzero(full)[0][:1]]
    w = np.where(ok[rows], tricube, 0.0)
    s = [w.sum(axis=1)] + [w @ x**p for p in range(1, 5)]
    A = np.stack(
        [
            np.stack([s[0], s[1], s[2]], axis=-1),
            np.stack([s[1], s[2], s[3]], axis=-1),
            np.stack([s[2], s[3], s[4]], axis=-1),
        ],
        axis=-2,
    )
    A = A + (1e-12 * s[0] + 1e-300)[:, None, None] * np.eye(3)
    # the fitted value is e1 . A^-1 (sum w [1, x, x^2] y): A is symmetric, so
    # the kernel is w (r0 + r1 x + r2 x^2) with r = A^-1 e1
    r = np.linalg.solve(A, np.broadcast_to(np.eye(3)[:, :1], A.shape[:-1] + (1,)))
    r = r[..., 0]
    kernels = w * (r[:, :1] + r[:, 1:2] * x + r[:, 2:3] * x**2)
    weights = np.empty(ok.shape)
    n_partial = np.count_nonzero(~full)
    weights[~full] = kernels[:n_partial]
    if n_partial < rows.size:
        weights[full] = kernels[n_partial]
    return weights, hp


def smooth_grid(grid: np.ndarray, values: np.ndarray, half_width: float) -> np.ndarray:
    """Local quadratic smoothing (tricube weights) of a curve already on the
    uniform ``grid`` (NaN outside its range); ``half_width <= 0`` returns it
    unchanged.

    The same linear operator acts on every curve, so stretches where two
    curves coincide stay identical after smoothing. Each smoothed value is
    clipped to the range of the data in its window.
    """
    if half_width <= 0.0:
        return values.copy()
    inside = np.isfinite(values)
    out = np.full(values.shape, np.nan)
    if np.count_nonzero(inside) < 3:
        return out
    weights, hp = _local_weights(grid, inside, half_width)
    pad = np.full(values.size + 2 * hp, np.nan)
    pad[hp:-hp] = values
    win = np.lib.stride_tricks.sliding_window_view(pad, 2 * hp + 1)[inside]
    ok = np.isfinite(win)
    fit = np.sum(weights[inside] * np.where(ok, win, 0.0), axis=1)
    hi = np.max(np.where(ok, win, -np.inf), axis=1)
    lo = np.min(np.where(ok, win, np.inf), axis=1)
    out[inside] = np.clip(fit, lo, hi)
    return out


def smoothed_noise(
    omega: np.ndarray, grid: np.ndarray, half_width: float, sigma: float
) -> np.ndarray:
    """Standard deviation, on ``grid``, of the noise left on a curve after
    :func:`interp_log` and :func:`smooth_grid`, when its samples carry
    independent noise of standard deviation ``sigma``.

    Both steps are linear, so each smoothed value is a weighted sum of the
    samples; its standard deviation is ``sigma`` times the 2-norm of those
    weights (the clipping in :func:`smooth_grid` only lowers it).

    Parameters
    ----------
    omega : ndarray, shape (n,)
        Sorted sample frequencies of the curve.
    grid : ndarray, shape (n_grid,)
        Uniform common grid.
    half_width : float
        Smoothing half width (unit of ``grid``); ``<= 0``: no smoothing.
    sigma : float
        Noise of each sample (log amplitude).

    Returns
    -------
    ndarray, shape (n_grid,)
        NaN outside the sampled range.
    """
    n = omega.size
    inside = (grid >= omega[0]) & (grid <= omega[-1])
    j = np.clip(np.searchsorted(omega, grid, side="right") - 1, 0, n - 2)
    t = np.clip((grid - omega[j]) / (omega[j + 1] - omega[j]), 0.0, 1.0)
    out = np.full(grid.shape, np.nan)
    if half_width <= 0.0:
        out[inside] = sigma * np.sqrt((1.0 - t[inside]) ** 2 + t[inside] ** 2)
        return out
    if np.count_nonzero(inside) < 3:
        return out
    weights, hp = _local_weights(grid, inside, half_width)
    # smoothed = L @ (Phi @ samples): L the banded smoother, Phi the
    # interpolation (two weights a row); the variance is sigma^2 times the
    # squared row norms of their product
    k = np.nonzero(inside)[0]
    cols = k[:, None] + np.arange(-hp, hp + 1)[None, :]
    lk = weights[k]
    keep = lk != 0.0  # zero off the curve, so cols stay in range
    rows = np.broadcast_to(k[:, None], cols.shape)
    smoother = sparse.csr_matrix(
        (lk[keep], (rows[keep], cols[keep])), shape=(grid.size, grid.size)
    )
    phi = sparse.csr_matrix(
        (
            np.concatenate([1.0 - t[k], t[k]]),
            (np.concatenate([k, k]), np.concatenate([j[k], j[k] + 1])),
        ),
        shape=(grid.size, n),
    )
    c = smoother @ phi
    var = np.asarray(c.multiply(c).sum(axis=1)).ravel()
    out[inside] = sigma * np.sqrt(var[inside])
    return out


#: a change of the smoothed curve, when the window is halved, within this
#: many of its own noise's standard deviations is read as noise
#: (:func:`smoothing_bias`)
SMOOTHING_BIAS_NOISE_Z = 3.0


def smoothing_bias(
    omega: np.ndarray,
    log_amp: np.ndarray,
    grid: np.ndarray,
    half_width: float,
    noise: float = 0.0,
) -> np.ndarray:
    """Estimated bias of :func:`smooth_grid` at ``half_width``: the change
    of the smoothed curve when the half width is halved, less
    ``SMOOTHING_BIAS_NOISE_Z`` standard deviations of that change's noise.

    Where the window is narrow against the curve's features the change is
    small; on a resonance peak narrower than the window (a fully stuck or
    fully sliding curve of a lightly damped structure smoothed over 5 % of
    the band) it is the part of the peak the smoother flattens, which
    differs from one sampling of the curve to the next (the samples on the
    flanks then lie below the flattened curve and some are dropped as
    dips). The criterion compares curves point by point only where this
    is small (:func:`hbmfric.criterion.choose_contact_model`, step 1's
    local test).

    Parameters
    ----------
    omega, log_amp : ndarray, shape (n,)
        Samples (increasing ``omega``) and their log amplitudes.
    grid : ndarray, shape (n_grid,)
        Uniform common grid.
    half_width : float
        Smoothing half width (unit of ``omega``); ``<= 0``: no smoothing,
        no bias.
    noise : float, default 0
        Standard deviation of the samples' log-amplitude noise.

    Returns
    -------
    ndarray, shape (n_grid,)
        Non-negative; NaN outside the sampled range.
    """
    base = interp_log(omega, log_amp, grid)
    if half_width <= 0.0:
        return np.where(np.isfinite(base), 0.0, np.nan)
    full = smooth_grid(grid, base, half_width)
    half = smooth_grid(grid, base, 0.5 * half_width)
    with np.errstate(invalid="ignore"):
        change = np.abs(half - full)
        if noise > 0.0:
            sd_full = smoothed_noise(omega, grid, half_width, noise)
            sd_half = smoothed_noise(omega, grid, 0.5 * half_width, noise)
            sd = np.sqrt(np.maximum(sd_half**2 - sd_full**2, 0.0))
            change = np.maximum(change - SMOOTHING_BIAS_NOISE_Z * sd, 0.0)
    change[~np.isfinite(full)] = np.nan
    return change
