"""Real discrete Fourier operators for harmonic balance.

A periodic signal with harmonics ``harmonic_numbers`` (for example
``[0, 1, 2, ..., H]`` or the odd ones ``[1, 3, ..., H]``) is stored as the
coefficient vector ``X = [X0, Xc1, Xs1, ...]``: one entry for the mean (only if
0 is among the harmonics), then a cosine and a sine coefficient per harmonic,
so that ``x(θ) = X0 + Σ_k (Xc_k cos kθ + Xs_k sin kθ)`` with ``θ = Ω t``.

The signal is sampled at ``θ_i = 2π i / n_time``, ``i = 0 … n_time - 1``.
Dense matrices are used on purpose: for the harmonic counts of HBM they are as
fast as an FFT inside Numba and they give the AFT Jacobian directly.
"""

import numpy as np

from ..._jit import jit


@jit
def n_coefficients(harmonic_numbers):
    """Length of the real coefficient vector for these harmonics."""
    n = 0
    for k in harmonic_numbers:
        n += 1 if k == 0 else 2
    return n


@jit
def fourier_matrices(harmonic_numbers, n_time):
    """Inverse, forward and derivative DFT matrices.

    Parameters
    ----------
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
        Distinct non-negative harmonic indices, increasing.
    n_time : int
        Number of samples per period, ``> 2 * max(harmonic_numbers)``.

    Returns
    -------
    inverse : ndarray, shape (n_time, n_coef)
        ``x = inverse @ X`` gives the samples ``x(θ_i)``.
    forward : ndarray, shape (n_coef, n_time)
        ``X = forward @ x`` gives the coefficients of a sampled signal
        (exact for trigonometric polynomials of degree ``< n_time / 2``).
    derivative : ndarray, shape (n_time, n_coef)
        ``dx/dθ (θ_i) = derivative @ X``.
    """
    n_coef = n_coefficients(harmonic_numbers)
    inverse = np.empty((n_time, n_coef))
    forward = np.empty((n_coef, n_time))
    derivative = np.empty((n_time, n_coef))
    for i in range(n_time):
        theta = 2.0 * np.pi * i / n_time
        col = 0
        for k in harmonic_numbers:
            if k == 0:
                inverse[i, col] = 1.0
                forward[col, i] = 1.0 / n_time
                derivative[i, col] = 0.0
                col += 1
            else:
                c = np.cos(k * theta)
                s = np.sin(k * theta)
                inverse[i, col] = c
                inverse[i, col + 1] = s
                forward[col, i] = 2.0 * c / n_time
                forward[col + 1, i] = 2.0 * s / n_time
                derivative[i, col] = -k * s
                derivative[i, col + 1] = k * c
                col += 2
    return inverse, forward, derivative


@jit
def evaluate(harmonic_numbers, X, theta):
    """Value and first two θ-derivatives of the signal ``X`` at one angle.

    ``cos kθ`` and ``sin kθ`` come from the angle-addition recurrence, so one
    call costs two trigonometric evaluations whatever the harmonic count.

    Returns
    -------
    value, first, second : float
    """
    c1 = np.cos(theta)
    s1 = np.sin(theta)
    ck = 1.0
    sk = 0.0
    m = 0
    value = 0.0
    first = 0.0
    second = 0.0
    col = 0
    for k in harmonic_numbers:
        while m < k:
            ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
            m += 1
        if k == 0:
            value += X[col]
            col += 1
        else:
            a = X[col]
            b = X[col + 1]
            value += a * ck + b * sk
            first += k * (b * ck - a * sk)
            second -= k * k * (a * ck + b * sk)
            col += 2
    return value, first, second


@jit
def basis_at(harmonic_numbers, theta, out):
    """Fill ``out`` (shape (n_coef,)) with the basis functions at ``theta``."""
    c1 = np.cos(theta)
    s1 = np.sin(theta)
    ck = 1.0
    sk = 0.0
    m = 0
    col = 0
    for k in harmonic_numbers:
        while m < k:
            ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
            m += 1
        if k == 0:
            out[col] = 1.0
            col += 1
        else:
            out[col] = ck
            out[col + 1] = sk
            col += 2
