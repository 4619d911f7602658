"""Amplitude measures of periodic signals given by their Fourier coefficients
(layout of :mod:`hbmfric.kernels.fourier.dft`)."""

from __future__ import annotations

import numpy as np


def coefficient_columns(harmonic_numbers: np.ndarray) -> dict[int, int]:
    """Map harmonic ``k`` to the column of its first coefficient."""
    cols: dict[int, int] = {}
    col = 0
    for k in harmonic_numbers:
        cols[int(k)] = col
        col += 1 if k == 0 else 2
    return cols


def harmonic_amplitude(
    harmonic_numbers: np.ndarray, coefficients: np.ndarray, harmonic: int
) -> np.ndarray:
    """Amplitude ``sqrt(Xc_k² + Xs_k²)`` of harmonic ``k`` (``|X0|`` for 0).

    Parameters
    ----------
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (..., n_coef)
    harmonic : int

    Returns
    -------
    ndarray, shape (...)
        Zero if the harmonic is not among ``harmonic_numbers`` (for example an
        even harmonic of an odd-harmonic solution, which is zero by symmetry).
    """
    cols = coefficient_columns(harmonic_numbers)
    if isinstance(harmonic, bool) or not isinstance(harmonic, int | np.integer):
        raise ValueError(f"harmonic must be an integer >= 0 or None, got {harmonic!r}")
    if harmonic < 0:
        raise ValueError(f"harmonic must be >= 0, got {harmonic}")
    if harmonic not in cols:
        if harmonic > int(np.max(harmonic_numbers)):
            raise ValueError(
                f"harmonic must be <= {int(np.max(harmonic_numbers))} (the highest "
                f"harmonic computed), got {harmonic}"
            )
        return np.zeros(coefficients.shape[:-1])
    c = cols[harmonic]
    if harmonic == 0:
        return np.abs(coefficients[..., c])
    return np.hypot(coefficients[..., c], coefficients[..., c + 1])


def synthesis_matrix(harmonic_numbers: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Basis functions at the angles ``theta``, shape (n_theta, n_coef)."""
    blocks = []
    for k in harmonic_numbers:
        if k == 0:
            blocks.append(np.ones((theta.size, 1)))
        else:
            blocks.append(np.column_stack((np.cos(k * theta), np.sin(k * theta))))
    return np.hstack(blocks)


def half_peak_to_peak(
    harmonic_numbers: np.ndarray, coefficients: np.ndarray
) -> np.ndarray:
    """Half the peak-to-peak value of ``x(θ)`` over one period.

    The extremes are found on a grid of ``max(256, 16 H)`` points and refined
    by Newton steps on ``x'(θ) = 0``, so the result is accurate to rounding.

    Parameters
    ----------
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (..., n_coef)

    Returns
    -------
    ndarray, shape (...)
    """
    X = np.asarray(coefficients, dtype=float)
    lead = X.shape[:-1]
    X2 = X.reshape(-1, X.shape[-1])
    h_max = int(np.max(harmonic_numbers))
    n = max(256, 16 * h_max)
    theta = 2.0 * np.pi * np.arange(n) / n
    x = X2 @ synthesis_matrix(harmonic_numbers, theta).T
    extremes = []
    for pick in (np.argmax, np.argmin):
        th = theta[pick(x, axis=1)]
        for _ in range(6):
            d1, d2 = _derivatives(harmonic_numbers, X2, th)
            safe = np.abs(d2) > 0
            step = np.where(safe, d1 / np.where(safe, d2, 1.0), 0.0)
            th = th - np.clip(step, -np.pi / n, np.pi / n)
        val = np.einsum("ij,ij->i", X2, _rows(harmonic_numbers, th))
        extremes.append(val)
    grid_max = x.max(axis=1)
    grid_min = x.min(axis=1)
    top = np.maximum(extremes[0], grid_max)
    bottom = np.minimum(extremes[1], grid_min)
    return (0.5 * (top - bottom)).reshape(lead)


def sampled_peak_to_peak(samples: np.ndarray) -> float:
    """Peak-to-peak value of one sampled period.

    Each extreme is refined by the parabola through its sample and the two
    neighbours (the samples wrap around the period): the error falls like
    the cube of the sampling step or faster, instead of its square.

    Parameters
    ----------
    samples : ndarray, shape (N,)
        One period at ``t_k = k T / N``, ``N >= 3``.

    Returns
    -------
    float
        ``max − min`` in the unit of ``samples``.
    """
    m = samples.size
    extremes = []
    for i in (int(np.argmax(samples)), int(np.argmin(samples))):
        y_minus, y0, y_plus = samples[i - 1], samples[i], samples[(i + 1) % m]
        curvature = y_plus - 2.0 * y0 + y_minus
        value = y0
        if curvature != 0.0:
            value = y0 - (y_plus - y_minus) ** 2 / (8.0 * curvature)
        extremes.append(value)
    return float(extremes[0] - extremes[1])


def state_at_zero(
    harmonic_numbers: np.ndarray, coefficients: np.ndarray, fundamental: float
) -> tuple[np.ndarray, np.ndarray]:
    """Displacement and velocity at ``t = 0`` of a harmonic series.

    Parameters
    ----------
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (n_dof, n_coef)
        ``[X0, Xc1, Xs1, ...]`` per DOF (``x = X0 + Σ Xc_k cos kωt + Xs_k
        sin kωt``), m.
    fundamental : float
        ω, rad/s.

    Returns
    -------
    x, v : ndarray, shape (n_dof,)
        m and m/s.
    """
    coefficients = np.atleast_2d(coefficients)
    x = np.zeros(coefficients.shape[0])
    v = np.zeros(coefficients.shape[0])
    col = 0
    for k in harmonic_numbers:
        k = int(k)
        x += coefficients[:, col]
        if k == 0:
            col += 1
        else:
            v += k * fundamental * coefficients[:, col + 1]
            col += 2
    return x, v


def _rows(harmonic_numbers: np.ndarray, theta: np.ndarray) -> np.ndarray:
    return synthesis_matrix(harmonic_numbers, np.atleast_1d(theta))


def _derivatives(
    harmonic_numbers: np.ndarray, X: np.ndarray, theta: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    d1 = np.zeros(theta.size)
    d2 = np.zeros(theta.size)
    col = 0
    for k in harmonic_numbers:
        if k == 0:
            col += 1
            continue
        c, s = np.cos(k * theta), np.sin(k * theta)
        a, b = X[:, col], X[:, col + 1]
        d1 += k * (-a * s + b * c)
        d2 -= k * k * (a * c + b * s)
        col += 2
    return d1, d2
