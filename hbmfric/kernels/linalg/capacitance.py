"""The slipping contacts' coupling of harmonics as a low-rank correction of
the harmonic-block preconditioner (Woodbury).

The harmonic blocks ``P`` of a condensed harmonic-balance Jacobian
(:mod:`.blocks`) leave out one part of the matrix: the entries by which a
slipping contact couples its own coordinate's coefficients of different
harmonics (a stuck contact's Jacobian is diagonal in the harmonics, the
linear part is block diagonal over harmonics). With ``U`` the columns of
the identity at the chosen slipping coordinates' unknowns (``k = n_s
n_coef`` of them) and ``E`` those coordinates' off-harmonic entries (block
diagonal over the coordinates, each ``n_coef × n_coef`` with its harmonic
blocks zero), the matrix is ``A = P + U E Uᵀ`` and

    ``A⁻¹ v = w - Z K⁻¹ E Uᵀ w``,  ``w = P⁻¹ v``,  ``Z = P⁻¹ U``,
    ``K = I + E Uᵀ P⁻¹ U``,

the capacitance matrix ``K`` of order ``k`` (this form needs no inverse of
``E``, which is singular). ``Z`` has the sparsity of ``P⁻¹``: the column of
a coefficient of harmonic group ``g`` is nonzero on that group's rows
only, so it costs ``2 n_s`` solves with the factored block of each group
and is stored per group; ``Uᵀ P⁻¹ U`` is read from it. Building costs
those solves, ``O(k² width)`` to form ``K`` and one LU of order ``k``;
applying it ``O(n_s n_coef² + k² + n_dof n_coef n_s)`` after the blocks.

When more coordinates slip than the arrays hold, the ones with the
largest off-harmonic entries (Frobenius norm) are corrected. The
correction changes the preconditioner only; GMRES still solves the true
system to its tolerance.

Layout of the unknowns and of the harmonic groups as in :mod:`.blocks`
(``x[d * n_coef + j]``). Plain loops, as :mod:`.lu`.
"""

import numpy as np

from ..._jit import jit
from .lu import lu_factor, lu_solve


@jit
def _groups(n_coef, first):
    return first + (n_coef - first) // 2


@jit
def _group_of(j, first):
    """Harmonic group of coefficient column ``j`` within a coordinate."""
    if first == 1:
        if j == 0:
            return 0
        return 1 + (j - 1) // 2
    return j // 2


@jit
def _column(g, first):
    """First column within a coordinate and width (1 or 2) of group ``g``."""
    if first == 1:
        if g == 0:
            return 0, 1
        return 1 + 2 * (g - 1), 2
    return 2 * g, 2


@jit
def capacitance_work(n_dof, n_coef, first, n_slip_max):
    """Arrays of the correction for at most ``n_slip_max`` slipping
    coordinates: ``(count, chosen, Z, E, K, kpiv, t)``.

    ``count`` (int64, shape (1,)): coordinates corrected (0: none, the
    plain harmonic blocks); ``chosen`` (int64, shape (n_slip_max,)): which;
    ``Z`` (shape (n_groups, 2 n_dof, 2 n_slip_max)): ``P⁻¹ U`` per group;
    ``E`` (shape (n_slip_max, n_coef, n_coef)): their off-harmonic
    entries; ``K`` (flat, ``k_max²``) and ``kpiv`` (``k_max``): the LU of
    the capacitance matrix; ``t`` (``k_max``): work; ``k_max = n_slip_max
    n_coef``."""
    k_max = n_slip_max * n_coef
    return (
        np.zeros(1, dtype=np.int64),
        np.zeros(n_slip_max, dtype=np.int64),
        np.zeros((_groups(n_coef, first), 2 * n_dof, 2 * n_slip_max)),
        np.zeros((n_slip_max, n_coef, n_coef)),
        np.zeros(k_max * k_max),
        np.zeros(k_max, dtype=np.int64),
        np.zeros(k_max),
    )


@jit
def _choose(A, n_dof, n_coef, first, chosen):
    """Coordinates of ``A`` with off-harmonic entries in their own block
    (slipping), at most ``chosen.size`` of them, the largest first by
    Frobenius norm; returns how many (stored in ``chosen`` in increasing
    order)."""
    size = np.zeros(n_dof)
    for d in range(n_dof):
        base = d * n_coef
        acc = 0.0
        for j in range(n_coef):
            gj = _group_of(j, first)
            for col in range(n_coef):
                if _group_of(col, first) != gj:
                    a = A[base + j, base + col]
                    acc += a * a
        size[d] = acc
    count = 0
    while count < chosen.size:
        best = -1
        big = 0.0
        for d in range(n_dof):
            if size[d] > big:
                big = size[d]
                best = d
        if best < 0:
            break
        size[best] = 0.0
        # insertion in increasing order
        i = count
        while i > 0 and chosen[i - 1] > best:
            chosen[i] = chosen[i - 1]
            i -= 1
        chosen[i] = best
        count += 1
    return count


@jit
def prepare_capacitance(A, n_dof, n_coef, first, blocks, pivots, arrays, work):
    """Build the correction of the harmonic blocks ``P`` (factored in
    ``blocks``, ``pivots`` by :func:`~.blocks.factor_blocks`, of ``A`` or
    of an earlier matrix) for the slipping coordinates of ``A`` (its
    leading ``n_dof n_coef`` rows and columns; not modified).

    Parameters
    ----------
    A : ndarray, shape (>= n, >= n)
        The matrix whose off-harmonic entries are corrected.
    n_dof, n_coef, first : int
        Layout of the unknowns (:mod:`.blocks`).
    blocks, pivots : ndarray
        The factored harmonic blocks.
    arrays : tuple
        :func:`capacitance_work`; out: the correction.
    work : ndarray, shape (2 n_dof,)

    Returns
    -------
    int
        Coordinates corrected (0: no coordinate slips, none fit the
        arrays, or the capacitance matrix is singular to the pivot test:
        the plain blocks then precondition).
    """
    count, chosen, Z, E, K, kpiv, _ = arrays
    count[0] = 0
    if chosen.size == 0:
        return 0
    n_s = _choose(A, n_dof, n_coef, first, chosen)
    if n_s == 0:
        return 0
    size = 2 * n_dof
    for p in range(n_s):
        base = chosen[p] * n_coef
        for j in range(n_coef):
            gj = _group_of(j, first)
            for col in range(n_coef):
                if _group_of(col, first) != gj:
                    E[p, j, col] = A[base + j, base + col]
                else:
                    E[p, j, col] = 0.0
    # Z = P⁻¹ U, group by group: the unit vectors of the chosen coordinates
    for g in range(_groups(n_coef, first)):
        _, width = _column(g, first)
        for p in range(n_s):
            for v in range(width):
                for i in range(size):
                    work[i] = 0.0
                work[chosen[p] * width + v] = 1.0
                lu_solve(blocks[g], pivots[g], work)
                for i in range(size):
                    Z[g, i, p * width + v] = work[i]
    # K = I + E Uᵀ Z: row (p, j), column (q, col); (Uᵀ Z) couples a
    # coefficient with those of its own group only
    k = n_s * n_coef
    C = K[: k * k].reshape((k, k))
    for p in range(n_s):
        for j in range(n_coef):
            r = p * n_coef + j
            for q in range(n_s):
                for col in range(n_coef):
                    g = _group_of(col, first)
                    c0, width = _column(g, first)
                    acc = 1.0 if (p == q and j == col) else 0.0
                    zc = q * width + col - c0
                    zr = chosen[p] * width
                    for u in range(width):
                        acc += E[p, j, c0 + u] * Z[g, zr + u, zc]
                    C[r, q * n_coef + col] = acc
    if not lu_factor(C, kpiv[:k]):
        return 0
    count[0] = n_s
    return n_s


@jit
def apply_capacitance(arrays, n_dof, n_coef, first, v):
    """``v[:n] ← v[:n] - Z K⁻¹ E Uᵀ v[:n]``: with ``v`` holding ``P⁻¹ x``
    on entry, ``(P + U E Uᵀ)⁻¹ x`` on return (nothing when no coordinate
    is corrected)."""
    count, chosen, Z, E, K, kpiv, t = arrays
    n_s = count[0]
    if n_s == 0:
        return
    k = n_s * n_coef
    for p in range(n_s):
        base = chosen[p] * n_coef
        for j in range(n_coef):
            acc = 0.0
            for col in range(n_coef):
                acc += E[p, j, col] * v[base + col]
            t[p * n_coef + j] = acc
    C = K[: k * k].reshape((k, k))
    lu_solve(C, kpiv[:k], t[:k])
    for g in range(_groups(n_coef, first)):
        c0, width = _column(g, first)
        for d in range(n_dof):
            for u in range(width):
                zr = d * width + u
                acc = 0.0
                for q in range(n_s):
                    for w in range(width):
                        acc += Z[g, zr, q * width + w] * t[q * n_coef + c0 + w]
                v[d * n_coef + c0 + u] -= acc
