"""The high poles of the complex-mode receptance summed once as a series.

The condensed residual with complex modes forms, per harmonic, ``G = L
diag(c) R`` with ``c_r = 1/(iw - λ_r)`` over all ``2 n_dof`` poles
(:func:`hbmfric.kernels.residuals.condensed.state_matrix`). Poles far above
the highest harmonic pulsation ``w`` of a band (on the lap joint the normal
contact springs and the beams' high modes: 124 of 156 poles at N = 40 lie
above 8 times ``15 × 2π × 185 Hz``) enter nearly quasi-statically, and their
part is a convergent series in ``iw``:

    Σ_{|λ_r| ≥ λ_s} L_r R_r / (iw - λ_r) = Σ_j (iw/λ_s)^j M̃_j,
    M̃_j = -λ_s^j Σ_{|λ_r| ≥ λ_s} L_r R_r / λ_r^{j+1},

whose matrices are real (the poles come in conjugate pairs) and fixed:
``J`` real terms per harmonic instead of ``n_high`` complex ones.
:func:`plan_state_series` chooses the split ``λ_s`` for a band (the least
cost ``n_low + J/4``, ``J`` the terms needed at its top) and forms the
matrices; the kernel checks at every pulsation that the stored terms reach
:data:`~hbmfric.kernels.residuals.condensed.SERIES_TOL` and sums every pole
otherwise.
"""

from __future__ import annotations

import numpy as np

from .kernels.residuals.condensed import SERIES_TOL

#: most terms stored (the split is chosen where fewer suffice)
MAX_TERMS = 40
#: cost of one real series term against one complex pole term
TERM_COST = 0.25
#: the series' imaginary part allowed, relative to its absolute terms
#: (conjugate pairs cancel it to rounding)
REAL_TOL = 1e-12


def _terms_needed(rho: float) -> int:
    """Least ``J`` with ``ρ^J / (1 - ρ) <= SERIES_TOL`` (as the kernel's
    :func:`~hbmfric.kernels.residuals.condensed.series_terms`)."""
    if rho == 0.0:
        return 1
    return max(1, int(np.ceil(np.log(SERIES_TOL * (1.0 - rho)) / np.log(rho))))


def plan_state_series(
    poles: np.ndarray, left: np.ndarray, right: np.ndarray, w_max: float
) -> tuple[np.ndarray, np.ndarray, float]:
    """The split and series of the high poles for pulsations up to ``w_max``.

    Parameters
    ----------
    poles : ndarray of complex128, shape (n_states,)
        ``λ_r``, rad/s.
    left : ndarray of complex128, shape (n_c, n_states)
        ``L = B X``.
    right : ndarray of complex128, shape (n_states, n_c)
        ``R = Y Bᵀ``.
    w_max : float
        Highest pulsation ``k Ω`` the series must serve, rad/s.

    Returns
    -------
    low : ndarray of int64, shape (n_low,)
        The poles summed term by term (all of them when no series pays).
    series : ndarray of float64, shape (n_c, n_c, n_terms)
        ``M̃_j`` (m/N), contiguous in ``j``; ``n_terms = 0`` for no series.
    split : float
        ``λ_s`` (rad/s), the least modulus in the series; 0 for none.
    """
    n_c, n_s = left.shape
    none = (
        np.arange(n_s, dtype=np.int64),
        np.zeros((n_c, n_c, 0)),
        0.0,
    )
    if not (np.isfinite(w_max) and w_max > 0.0) or n_s == 0:
        return none
    moduli = np.abs(poles)
    order = np.argsort(moduli, kind="stable")
    sorted_moduli = moduli[order]
    best_cost = float(n_s)
    best = None
    for i in range(1, n_s):
        # split between distinct moduli only (a conjugate pair stays whole)
        if not sorted_moduli[i] > sorted_moduli[i - 1] * (1.0 + 1e-9):
            continue
        rho = w_max / sorted_moduli[i]
        if not rho < 1.0:
            continue
        terms = _terms_needed(rho)
        if terms > MAX_TERMS:
            continue
        cost = i + TERM_COST * terms
        if cost < best_cost:
            best_cost, best = cost, (i, terms)
    if best is None:
        return none
    i, terms = best
    # store what the kernel may need up to MAX_TERMS for pulsations a
    # little above w_max (it checks and falls back beyond)
    terms = MAX_TERMS
    low = np.sort(order[:i]).astype(np.int64)
    high = order[i:]
    split = float(sorted_moduli[i])
    lam = poles[high]
    ratio = split / lam
    weight = -1.0 / lam
    series = np.empty((n_c, n_c, terms))
    L, R = left[:, high], right[high]
    for j in range(terms):
        term = (L * weight) @ R
        scale = (np.abs(L) * np.abs(weight)) @ np.abs(R)
        if not np.all(np.abs(term.imag) <= REAL_TOL * scale + 1e-300):
            return none  # not closed under conjugation: sum every pole
        series[:, :, j] = term.real
        weight = weight * ratio
    return low, np.ascontiguousarray(series), split
