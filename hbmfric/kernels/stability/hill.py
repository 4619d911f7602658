"""Kernels of Hill's stability (:mod:`hbmfric.stability`): the HBM
Jacobians of many solutions in one compiled loop, and the signs of the
determinants of diagonal blocks of them.

The sign of ``det Δ0`` (``Δ0`` the HBM Jacobian, Hill's pencil at λ = 0)
is ``sign(det Δ2) (-1)^m`` with ``m`` the number of positive real
eigenvalues of the pencil (``det Δ0 = det Δ2 Π(-λ_j)``, complex pairs
contributing ``|λ_j|² > 0``): it changes exactly where an odd number of
real exponents crosses zero.
"""

import numpy as np

from ..._jit import jit
from ..laws.updates import law_update
from ..linalg.lu import lu_factor
from ..residuals.hbm import hbm_residual


@jit
def hill_jacobians(
    points,
    problem,
    jac,
    status,
    blocks,
    sizes,
    signs,
    parity,
    weight,
    skew,
    tolerance,
    extremes,
):
    """``∂R/∂X`` of the HBM residual at many solutions, and optionally the
    signs of the determinants of diagonal blocks of each and the size of
    the coupling between two index sets (computed while the Jacobian is
    fresh in the cache).

    Parameters
    ----------
    points : ndarray, shape (n_points, n + 1)
        Unknowns ``[X, Ω]`` of each solution (``n = n_dof * n_coef``,
        coefficients in m, Ω in rad/s).
    problem : tuple
        Kernel problem of :func:`hbmfric.kernels.residuals.hbm.hbm_residual`.
    jac : ndarray, shape (n_points, n, n) or (1, n, n)
        Output: the Jacobians (the Ω column left out), N/m; with one
        slot for several points, the last point's (the signs and the
        measures without holding every Jacobian).
    status : ndarray of int64, shape (n_points,)
        Output: contact-state code of each AFT (negative on failure).
    blocks : ndarray of int64, shape (n_blocks, m_max)
        Row (and column) indices of each block (``n_blocks = 0``: no
        signs), the first ``sizes[b]`` of row ``b`` used.
    sizes : ndarray of int64, shape (n_blocks,)
    signs : ndarray of int64, shape (n_points, n_blocks)
        Output: as :func:`block_determinant_signs`.
    parity : ndarray of int64, shape (n,) or (0,)
        Class (0 or 1) of each row and column, e.g. the parity of its
        harmonic; empty: no coupling measured.
    weight : ndarray, shape (n,) or (0,)
        Row weights of the symmetry test (``W jac`` is tested, ``W =
        diag(weight)``: the inverse of the Galerkin weight of each row).
    skew : ndarray, shape (n, n) or (0, 0)
        Skew part of ``W jac`` per unit Ω that the symmetry test discounts
        (``2 W C ⊗ D₁``, the damping's ``Ω C ⊗ D₁`` doubled, ``D₁`` the
        derivative operator at Ω = 1); empty: no test.
    tolerance : float
        The symmetry test stops at the first point whose asymmetry
        exceeds ``tolerance`` (relative to its largest entry).
    extremes : ndarray, shape (3,)
        Output: the largest ``|jac[i, r, c]|`` with ``parity[r] !=
        parity[c]`` over all points (0 when ``parity`` is empty), the
        largest entry of all (inf where an entry is not finite, as
        :func:`split_extremes`), and the asymmetry: the largest over the
        points of ``max |W jac - (W jac)ᵀ - Ω_i skew|`` relative to the
        point's largest ``|jac|`` up to the first point above
        ``tolerance`` (0 when ``skew`` is empty; inf for a point with a
        non-finite entry or no nonzero one).
    """
    n = jac.shape[1]
    R = np.empty(n)
    J = np.empty((n, n + 1))
    coupling = 0.0
    largest = 0.0
    asymmetry = 0.0
    check = parity.size == n
    symmetric = skew.shape[0] == n
    keep_all = jac.shape[0] == points.shape[0]
    for i in range(points.shape[0]):
        status[i] = hbm_residual(points[i], problem, R, J)
        slot = i if keep_all else 0
        here = 0.0
        for r in range(n):
            for c in range(n):
                v = J[r, c]
                jac[slot, r, c] = v
                a = abs(v)
                if not a <= here:
                    here = a if a == a else np.inf
        if not here <= largest:
            largest = here
        if check:
            for r in range(n):
                for c in range(n):
                    if parity[r] != parity[c]:
                        a = abs(J[r, c])
                        if not a <= coupling:
                            coupling = a if a == a else np.inf
        if symmetric:
            w = points[i, n]
            worst = 0.0
            for r in range(n):
                for c in range(r + 1, n):
                    d = weight[r] * J[r, c] - weight[c] * J[c, r] - w * skew[r, c]
                    a = abs(d)
                    if not a <= worst:
                        worst = a if a == a else np.inf
            ratio = worst / here if 0.0 < here < np.inf else np.inf
            if not ratio <= asymmetry:
                asymmetry = ratio if ratio == ratio else np.inf
            if not asymmetry <= tolerance:
                symmetric = False  # one point suffices to refuse
        for b in range(blocks.shape[0]):
            signs[i, b] = _sign_of_det(J, blocks[b, : sizes[b]])
    extremes[0] = coupling
    extremes[1] = largest
    extremes[2] = asymmetry


@jit
def _sign_of_det(J, block):
    """Sign of ``det J[block][:, block]`` (0: singular or not finite)."""
    m = block.size
    W = np.empty((m, m))
    p = np.empty(m, dtype=np.int64)
    for r in range(m):
        for c in range(m):
            W[r, c] = J[block[r], block[c]]
    if not lu_factor(W, p):
        return 0
    s = 1
    for k in range(m):
        if p[k] != k:
            s = -s
        if W[k, k] < 0.0:
            s = -s
    return s


@jit
def block_determinant_signs(jac, blocks, sizes, signs):
    """Signs of the determinants of diagonal blocks of many matrices.

    Parameters
    ----------
    jac : ndarray, shape (n_points, n, n)
    blocks : ndarray of int64, shape (n_blocks, m_max)
        Row (and column) indices of each block, the first ``sizes[b]`` of
        row ``b`` used.
    sizes : ndarray of int64, shape (n_blocks,)
    signs : ndarray of int64, shape (n_points, n_blocks)
        Output: ``+1`` or ``-1``, ``0`` for a (numerically) singular or
        non-finite block.
    """
    for i in range(jac.shape[0]):
        for b in range(blocks.shape[0]):
            signs[i, b] = _sign_of_det(jac[i], blocks[b, : sizes[b]])


@jit
def split_extremes(jac, odd, even):
    """Largest ``|jac[i, r, c]|`` coupling the index sets ``odd`` and
    ``even`` (either way), and the largest entry of all, over all
    matrices ``i``; inf where an entry is not finite."""
    coupling = 0.0
    largest = 0.0
    for i in range(jac.shape[0]):
        for r in range(jac.shape[1]):
            for c in range(jac.shape[2]):
                a = abs(jac[i, r, c])
                if not a <= largest:
                    largest = a if a == a else np.inf
        for r in odd:
            for c in even:
                a = max(abs(jac[i, r, c]), abs(jac[i, c, r]))
                if not a <= coupling:
                    coupling = a if a == a else np.inf
    return coupling, largest


@jit
def memoryless_jacobians(
    points,
    harmonic_numbers,
    structure,
    law_codes,
    law_params,
    cos_table,
    sin_table,
    jac,
    blocks,
    sizes,
    signs,
    parity,
    guard,
    odd_law,
    extremes,
):
    """HBM Jacobians of one DOF with memoryless contacts to ground, from
    the spectrum of the tangent stiffness, and the signs of diagonal
    blocks of them.

    The sampled AFT Jacobian of a memoryless law is ``dF[r, s] = Σ_i
    forward[r, i] k(θ_i) inverse[i, s]`` with ``k = Σ f'(x)`` the tangent
    stiffness of the contacts at the samples. Products of two basis
    functions are sums of ``cos`` and ``sin`` of ``(a ± b) θ``, so ``dF``
    is assembled from the discrete coefficients ``C_m = Σ_i k_i cos mθ_i``
    and ``S_m = Σ_i k_i sin mθ_i`` (``m = 0 … 2H``) at ``O(n_time H)`` per
    point instead of the ``O(n_time n²)`` of the product: the same matrix
    up to rounding (``tests/test_stability_reflection.py``).

    Parameters
    ----------
    points : ndarray, shape (n_points, n + 1)
        Unknowns ``[X, Ω]`` in the full basis ``0 … H`` (``n = 2H + 1``),
        m and rad/s.
    harmonic_numbers : ndarray of int64, shape (H + 1,)
        ``0, 1, …, H``.
    structure : ndarray, shape (3,)
        Mass, damping and stiffness of the DOF (kg, N s/m, N/m).
    law_codes : ndarray of int64, shape (n_contacts,)
    law_params : ndarray, shape (n_contacts, n_params)
    cos_table, sin_table : ndarray, shape (2H + 1, n_time)
        ``cos mθ_i`` and ``sin mθ_i`` at the AFT samples ``θ_i = 2π i /
        n_time``.
    jac : ndarray, shape (n, n)
        Work array: the Jacobian of the current point, N/m.
    blocks, sizes, signs
        As :func:`hill_jacobians` (a sign is 0 also where the block's
        smallest LU pivot is below ``guard`` times its largest).
    parity : ndarray of int64, shape (n,)
        Parity of each row's harmonic.
    guard : float
    odd_law : bool
        Every law is odd (``f(-u) = -f(u)``): at a point with no even
        harmonic, the sums run over half a period (the tangent stiffness
        repeats after it, its odd harmonics are zero).
    extremes : ndarray, shape (2,)
        Output: the largest odd-even coupling and the largest entry over
        the points, as :func:`hill_jacobians`.
    """
    n = jac.shape[0]
    n_h = harmonic_numbers.size
    n_time = cos_table.shape[1]
    m_max = cos_table.shape[0]
    mass = structure[0]
    damping = structure[1]
    stiffness = structure[2]
    k_t = np.empty(n_time)
    C = np.empty(m_max)
    S = np.empty(m_max)
    coupling = 0.0
    largest = 0.0
    inv_n = 1.0 / n_time
    for p in range(points.shape[0]):
        X = points[p]
        w = X[n]
        # odd solution (no even harmonic) and an even sample count: the
        # tangent stiffness of an odd law repeats after half a period,
        # its odd harmonics vanish and the even ones are twice the sum
        # over the first half
        half = n_time % 2 == 0 and odd_law
        for k in range(0, n_h, 2):
            if X[max(2 * k - 1, 0)] != 0.0 or X[2 * k] != 0.0:
                half = False
        count = n_time // 2 if half else n_time
        step = 2 if half else 1
        for i in range(count):
            u = 0.0 if half else X[0]
            for k in range(1, n_h, step):
                u += X[2 * k - 1] * cos_table[k, i] + X[2 * k] * sin_table[k, i]
            kk = 0.0
            for c in range(law_codes.size):
                kk += law_update(law_codes[c], law_params[c], 0.0, 0.0, u)[3]
            k_t[i] = kk
        scale = 2.0 * inv_n if half else inv_n
        for m in range(m_max):
            if half and m % 2 == 1:
                C[m] = 0.0
                S[m] = 0.0
                continue
            acc_c = 0.0
            acc_s = 0.0
            for i in range(count):
                acc_c += k_t[i] * cos_table[m, i]
                acc_s += k_t[i] * sin_table[m, i]
            C[m] = acc_c * scale
            S[m] = acc_s * scale
        # harmonic 0 (row and column 0), then the pairs (cos k, sin k) at
        # rows 2k - 1, 2k
        jac[0, 0] = stiffness + C[0]
        for b_ in range(1, n_h):
            jac[0, 2 * b_ - 1] = C[b_]
            jac[0, 2 * b_] = S[b_]
            jac[2 * b_ - 1, 0] = 2.0 * C[b_]
            jac[2 * b_, 0] = 2.0 * S[b_]
        for a_ in range(1, n_h):
            ra = 2 * a_ - 1
            for b_ in range(1, n_h):
                cb = 2 * b_ - 1
                d = a_ - b_
                cd = C[d] if d >= 0 else C[-d]
                sd = S[d] if d >= 0 else -S[-d]  # sin((a - b) θ)
                jac[ra, cb] = cd + C[a_ + b_]
                jac[ra, cb + 1] = S[a_ + b_] - sd
                jac[ra + 1, cb] = S[a_ + b_] + sd
                jac[ra + 1, cb + 1] = cd - C[a_ + b_]
            kw = a_ * w
            jac[ra, ra] += stiffness - mass * kw * kw
            jac[ra + 1, ra + 1] += stiffness - mass * kw * kw
            jac[ra, ra + 1] += damping * kw
            jac[ra + 1, ra] -= damping * kw
        for r in range(n):
            for c in range(n):
                v = abs(jac[r, c])
                if not v <= largest:
                    largest = v if v == v else np.inf
                if parity[r] != parity[c] and not v <= coupling:
                    coupling = v if v == v else np.inf
        for blk in range(blocks.shape[0]):
            signs[p, blk] = _guarded_sign(jac, blocks[blk, : sizes[blk]], guard)
    extremes[0] = coupling
    extremes[1] = largest


@jit
def _guarded_sign(J, block, guard):
    """Sign of ``det J[block][:, block]``; 0 where the LU fails or its
    smallest pivot is below ``guard`` times its largest."""
    m = block.size
    W = np.empty((m, m))
    p = np.empty(m, dtype=np.int64)
    for r in range(m):
        for c in range(m):
            W[r, c] = J[block[r], block[c]]
    if not lu_factor(W, p):
        return 0
    small = np.inf
    big = 0.0
    s = 1
    for k in range(m):
        if p[k] != k:
            s = -s
        d = W[k, k]
        if d < 0.0:
            s = -s
        small = min(small, abs(d))
        big = max(big, abs(d))
    if not small > guard * big:
        return 0
    return s
