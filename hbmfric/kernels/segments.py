"""Fourier integrals of a contact force over pieces of the period.

A force known over one period ``θ ∈ [θ0, θ0 + 2π)`` has the coefficients
(layout of :mod:`hbmfric.kernels.dft`)

    F_r = c_r ∫ f(θ) ψ_r(θ) dθ,   c_r = 1/(2π) for the mean, 1/π otherwise,

with ``ψ_r`` the basis function of row ``r`` (``1``, ``cos kθ`` or
``sin kθ``). The AFT kernels build this integral piece by piece:

* exactly, segment by segment, where the force on a segment is a constant
  or linear in the displacement (:func:`segment_integrals`,
  :func:`basis_integrals`, :func:`product_integrals`): a constant ``f``
  adds ``f q`` with ``q = basis_integrals``, a stuck spring
  ``f = kt (u - z)`` adds ``P X - kt z q`` with ``P = kt ∫ φ_j ψ_r``
  (``product_integrals``, ``φ_j`` the basis of ``X``);
* by the trapezoidal rule over samples (:func:`project_samples`), the
  forward DFT of the sampled force and of its gradient ``df/dX``, for a
  whole period or for part of it.
"""

import numpy as np

from .._jit import jit


@jit
def segment_integrals(a, b, cos_int, sin_int):
    """Exact integrals of ``cos mθ`` and ``sin mθ`` over ``[a, b]``.

    ``cos mθ`` and ``sin mθ`` at both ends come from the angle-addition
    recurrence (four trigonometric evaluations whatever ``m_max``).

    Parameters
    ----------
    a, b : float
        Segment ends, rad (any order, any size).
    cos_int, sin_int : ndarray, shape (m_max + 1,)
        Output: ``cos_int[m] = ∫_a^b cos mθ dθ``, ``sin_int[m] = ∫_a^b
        sin mθ dθ``, rad; ``m_max`` is twice the highest harmonic when the
        products of :func:`product_integrals` are wanted.
    """
    m_max = cos_int.size - 1
    ca = np.cos(a)
    sa = np.sin(a)
    cb = np.cos(b)
    sb = np.sin(b)
    cma = 1.0
    sma = 0.0
    cmb = 1.0
    smb = 0.0
    cos_int[0] = b - a
    sin_int[0] = 0.0
    for m in range(1, m_max + 1):
        cma, sma = cma * ca - sma * sa, sma * ca + cma * sa
        cmb, smb = cmb * cb - smb * sb, smb * cb + cmb * sb
        cos_int[m] = (smb - sma) / m
        sin_int[m] = (cma - cmb) / m


@jit
def basis_integrals(harmonic_numbers, cos_int, sin_int, out):
    """Fourier coefficients of a unit force on one segment, zero elsewhere.

    Parameters
    ----------
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
    cos_int, sin_int : ndarray, shape (>= max(harmonic_numbers) + 1,)
        From :func:`segment_integrals`.
    out : ndarray, shape (n_coef,)
        Output: ``c_r ∫ ψ_r`` over the segment (dimensionless).
    """
    row = 0
    for k in harmonic_numbers:
        if k == 0:
            out[row] = cos_int[0] * (1.0 / (2.0 * np.pi))
            row += 1
        else:
            norm = 1.0 / np.pi
            out[row] = cos_int[k] * norm
            out[row + 1] = sin_int[k] * norm
            row += 2


@jit
def product_integrals(harmonic_numbers, cos_int, sin_int, scale, P):
    """Add the Fourier coefficients of ``f = scale · u`` on one segment.

    Adds ``scale c_r ∫ φ_j ψ_r`` over the segment to ``P[r, j]``, so that
    ``P @ X`` is the contribution of the segment to the coefficients of a
    force proportional to the displacement ``u = Σ X_j φ_j`` there (and
    ``P`` its derivative with respect to ``X``). The products are reduced
    by ``cos jθ cos kθ = ½ (cos (j-k)θ + cos (j+k)θ)`` and its siblings.

    Parameters
    ----------
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
    cos_int, sin_int : ndarray, shape (>= 2 max(harmonic_numbers) + 1,)
        From :func:`segment_integrals`.
    scale : float
        Stiffness of the segment, N/m.
    P : ndarray, shape (n_coef, n_coef)
        Accumulated in place, N/m.
    """
    row = 0
    for k in harmonic_numbers:
        n_rows = 1 if k == 0 else 2
        norm = 1.0 / (2.0 * np.pi) if k == 0 else 1.0 / np.pi
        for rr in range(n_rows):
            is_sin_row = rr == 1
            col = 0
            for j in harmonic_numbers:
                n_cols = 1 if j == 0 else 2
                for cc in range(n_cols):
                    is_sin_col = cc == 1
                    s = j + k
                    d = j - k
                    ad = abs(d)
                    if j == 0 or k == 0:
                        if j == 0 and k == 0:
                            val = cos_int[0]
                        elif j == 0:
                            val = sin_int[k] if is_sin_row else cos_int[k]
                        else:
                            val = sin_int[j] if is_sin_col else cos_int[j]
                    elif not is_sin_col and not is_sin_row:
                        val = 0.5 * (cos_int[ad] + cos_int[s])
                    elif is_sin_col and is_sin_row:
                        val = 0.5 * (cos_int[ad] - cos_int[s])
                    elif is_sin_col:
                        # sin jθ cos kθ
                        sgn = 1.0 if d > 0 else (-1.0 if d < 0 else 0.0)
                        val = 0.5 * (sin_int[s] + sgn * sin_int[ad])
                    else:
                        # cos jθ sin kθ
                        sgn = 1.0 if d < 0 else (-1.0 if d > 0 else 0.0)
                        val = 0.5 * (sin_int[s] + sgn * sin_int[ad])
                    P[row, col] += scale * val * norm
                    col += 1
            row += 1


@jit
def project_samples(forward, force, grad, start, count, weight, F, dF):
    """Add the forward DFT of sampled force values and of their gradient.

    For the samples ``i = (start + j) mod n_time``, ``j = 0 … count - 1``
    (in that order), adds ``Σ w_ri force[i]`` to ``F[r]`` and
    ``Σ w_ri grad[i, c]`` to ``dF[r, c]``, with ``w_ri = weight
    forward[r, i]``. A whole period is ``start = 0, count = n_time,
    weight = 1``; half a period of a half-wave antisymmetric force is
    ``count = n_time / 2, weight = 2``.

    Parameters
    ----------
    forward : ndarray, shape (n_coef, n_time)
        Forward DFT matrix (:func:`hbmfric.kernels.dft.fourier_matrices`).
    force : ndarray, shape (n_time,)
        Force samples, N (only the selected ones are read).
    grad : ndarray, shape (>= n_time, n_grad)
        ``d force[i] / d y`` in row ``i``, N per unit of ``y`` (only the
        selected rows are read).
    start, count : int
        First sample and number of samples, ``0 <= count <= n_time``.
    weight : float
        Quadrature weight factor.
    F : ndarray, shape (n_coef,)
        Accumulated in place, N.
    dF : ndarray, shape (n_coef, n_grad)
        Accumulated in place.
    """
    n_time = force.size
    n_grad = dF.shape[1]
    first = start % n_time
    for r in range(F.size):
        acc = 0.0
        i = first
        for _ in range(count):
            w = weight * forward[r, i]
            acc += w * force[i]
            if w != 0.0:
                for c in range(n_grad):
                    dF[r, c] += w * grad[i, c]
            i += 1
            if i == n_time:
                i = 0
        F[r] += acc
