"""Fourier integrals of a contact force over pieces of the period.

A force known over one period has the coefficients (layout of
:mod:`hbmfric.kernels.fourier.dft`)

    F_r = c_r ∫ f(θ) ψ_r(θ) dθ,   c_r = 1/(2π) for the mean, 1/π otherwise,

with ``ψ_r`` the basis function of row ``r`` (``1``, ``cos kθ`` or
``sin kθ``). The AFT kernels build this integral piece by piece:

* exactly, where the force on a set of segments is constant or linear in
  the displacement: the sums ``C[m] = Σ ∫ cos mθ``, ``S[m] = Σ ∫ sin mθ``
  over the segments (:func:`add_segment_integrals`, from the series of
  :func:`trig_series` at the segment ends) give a constant force ``f`` the
  coefficients ``f q`` (``q`` from :func:`basis_integrals`) and a spring
  ``f = kt u`` the coefficients ``P X`` with ``P = kt c_r ∫ φ_j ψ_r``
  (:func:`product_integrals`, row by row :func:`product_rows`; ``φ_j`` the
  basis of ``X``);
* by the trapezoidal rule over samples (:func:`project_samples`), the
  forward DFT of the sampled force and of its gradient ``df/dX``, for a
  whole period or for part of it.
"""

import numpy as np

from ..._jit import jit


@jit
def trig_series(theta, c, s):
    """``c[m] = cos mθ``, ``s[m] = sin mθ`` for ``m = 0 … c.size - 1``, by
    the angle-addition recurrence (two trigonometric evaluations).

    Parameters
    ----------
    theta : float
        Angle, rad.
    c, s : ndarray, shape (m_max + 1,)
        Output.
    """
    c1 = np.cos(theta)
    s1 = np.sin(theta)
    cm = 1.0
    sm = 0.0
    c[0] = 1.0
    s[0] = 0.0
    for m in range(1, c.size):
        cm, sm = cm * c1 - sm * s1, sm * c1 + cm * s1
        c[m] = cm
        s[m] = sm


@jit
def add_segment_integrals(a, b, ca, sa, cb, sb, C, S):
    """Add ``∫_a^b cos mθ dθ`` to ``C[m]`` and ``∫_a^b sin mθ dθ`` to
    ``S[m]``, exactly.

    Parameters
    ----------
    a, b : float
        Segment ends, rad (any order, any length).
    ca, sa, cb, sb : ndarray, shape (>= m_max + 1,)
        :func:`trig_series` at ``a`` and at ``b``.
    C, S : ndarray, shape (m_max + 1,)
        Accumulated in place, rad; ``m_max`` is twice the highest harmonic
        when the products of :func:`product_integrals` are wanted.
    """
    C[0] += b - a
    for m in range(1, C.size):
        C[m] += (sb[m] - sa[m]) / m
        S[m] += (ca[m] - cb[m]) / m


@jit
def basis_integrals(harmonic_numbers, C, S, out):
    """Fourier coefficients of a unit force on the segments, zero elsewhere.

    Parameters
    ----------
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
    C, S : ndarray, shape (>= max(harmonic_numbers) + 1,)
        Segment integrals (:func:`add_segment_integrals`).
    out : ndarray, shape (n_coef,)
        Output: ``c_r ∫ ψ_r`` over the segments (dimensionless).
    """
    inv_pi = 1.0 / np.pi
    row = 0
    for k in harmonic_numbers:
        if k == 0:
            out[row] = C[0] * (0.5 * inv_pi)
            row += 1
        else:
            out[row] = C[k] * inv_pi
            out[row + 1] = S[k] * inv_pi
            row += 2


@jit
def product_rows(harmonic_numbers, k, f, C, S, row0, row1):
    """Rows of ``f ∫ φ_j ψ_r`` for the row harmonic ``k`` (``f`` the
    stiffness times the row normalisation ``c_r``).

    Products of harmonics ``j`` and ``k`` reduce to harmonics ``|j - k|``
    and ``j + k`` (``cos jθ cos kθ = ½ (cos (j-k)θ + cos (j+k)θ)`` and its
    siblings).

    Parameters
    ----------
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
    k : int
        Row harmonic, one of ``harmonic_numbers``.
    f : float
        Scale of the rows.
    C, S : ndarray, shape (>= 2 max(harmonic_numbers) + 1,)
        Segment integrals (:func:`add_segment_integrals`).
    row0, row1 : ndarray, shape (n_coef,)
        Output (overwritten): the cosine row and the sine row of ``k``;
        ``row1`` is not touched for ``k = 0``.
    """
    first = 0
    col = 0
    if harmonic_numbers[0] == 0:
        # the mean column
        if k == 0:
            row0[0] = f * C[0]
        else:
            row0[0] = f * C[k]
            row1[0] = f * S[k]
        first = 1
        col = 1
    if k == 0:
        for jb in range(first, harmonic_numbers.size):
            j = harmonic_numbers[jb]
            row0[col] = f * C[j]
            row0[col + 1] = f * S[j]
            col += 2
        return
    hf = 0.5 * f
    for jb in range(first, harmonic_numbers.size):
        j = harmonic_numbers[jb]
        d = j - k
        ad = d if d >= 0 else -d
        sd = S[ad] if d >= 0 else -S[ad]
        sp = j + k
        row0[col] = hf * (C[ad] + C[sp])  # cos jθ cos kθ
        row0[col + 1] = hf * (S[sp] + sd)  # sin jθ cos kθ
        row1[col] = hf * (S[sp] - sd)  # cos jθ sin kθ
        row1[col + 1] = hf * (C[ad] - C[sp])  # sin jθ sin kθ
        col += 2


@jit
def product_integrals(harmonic_numbers, C, S, scale, P):
    """Fourier coefficients of ``f = scale · u`` on the segments.

    ``P[r, j] = scale c_r ∫ φ_j ψ_r`` over the segments, so that ``P @ X``
    is the coefficient vector of a force proportional to the displacement
    ``u = Σ X_j φ_j`` there and zero elsewhere (and ``P`` its derivative
    with respect to ``X``).

    Parameters
    ----------
    harmonic_numbers : ndarray of int64, shape (n_harmonics,)
    C, S : ndarray, shape (>= 2 max(harmonic_numbers) + 1,)
        Segment integrals (:func:`add_segment_integrals`).
    scale : float
        Stiffness on the segments, N/m.
    P : ndarray, shape (n_coef, n_coef)
        Output (overwritten), N/m.
    """
    row = 0
    for k in harmonic_numbers:
        if k == 0:
            product_rows(
                harmonic_numbers, k, scale / (2.0 * np.pi), C, S, P[row], P[row]
            )
            row += 1
        else:
            product_rows(harmonic_numbers, k, scale / np.pi, C, S, P[row], P[row + 1])
            row += 2


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
        Forward DFT matrix (:func:`hbmfric.kernels.fourier.dft.fourier_matrices`).
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
    i = start % n_time
    # sample by sample: the gradient row is read once, F and dF stay in
    # cache (measured 15-20 % faster than row by row on the Masing AFT)
    for _ in range(count):
        f = force[i]
        for r in range(F.size):
            w = weight * forward[r, i]
            F[r] += w * f
            if w != 0.0:
                for c in range(n_grad):
                    dF[r, c] += w * grad[i, c]
        i += 1
        if i == n_time:
            i = 0
