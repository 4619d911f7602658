"""The corrector's bordered matrix of a problem condensed onto several
contact coordinates, built on the nonzero pattern of its Jacobian.

The Jacobian of the residual on ``n_dof`` contact coordinates of
``n_coef`` coefficients each
(:func:`hbmfric.kernels.residuals.condensed._coordinates_residual`, shape
``(n, n + 1)``, ``n = n_dof n_coef``) can be nonzero only at

- the harmonic blocks of the linear part ``D_k = G_k⁻¹``: row ``a n_coef +
  c``, column ``b n_coef + c'`` with ``c`` and ``c'`` in the same harmonic
  group (the constant, or the cosine and sine of one harmonic), every
  coordinate ``b``;
- each coordinate's own ``n_coef × n_coef`` block (its contact's AFT
  Jacobian, every entry when the contact slips): columns ``a n_coef + j``;
- the last column, ``dR/dΩ``.

Every other entry is written 0.0 by the residual. A row has ``(n_dof - 1)
w + n_coef + 1`` such places (``w`` = 1 or 2, the width of its group)
against ``n + 1`` columns: on the lap joint at H = 15 (``n_coef = 16``),
185 of 1345 at ``n_dof = 84``. The continuation corrector's passes over
the dense matrix (the rounding floor of the residual, the row
equilibration, the gather of the nonzeros for GMRES's products), ``O(n²)``
each per Newton iteration, visit those places only here; the results are
those of the dense passes bit for bit (the same entries in the same column
order; the skipped ones are exact zeros).

Unknowns are stored coordinate by coordinate (``x[d * n_coef + j]``), the
layout of :mod:`.blocks`. Of the dense bordered matrix only the last
column is written at each Newton iteration; the other places of the
pattern are written from the nonzeros (:func:`scatter_pattern`) when the
block solver factors its harmonic blocks (a few times per hundred solves);
whatever the entries off the pattern hold is never read by the block
solver (:func:`hbmfric.kernels.linalg.blocks.block_solve`, which
multiplies with the nonzeros built here).
"""

import numpy as np

from ..._jit import jit


@jit
def _row_places(i, n_dof, n_coef, first, places):
    """Columns of row ``i`` of the pattern (module docstring), ascending,
    into ``places`` (room ``2 n_dof + n_coef + 1``), the last one ``n``;
    returns their count."""
    n = n_dof * n_coef
    a = i // n_coef
    c = i - a * n_coef
    if first == 1 and c == 0:
        lo, width = 0, 1
    else:
        lo = c - ((c - first) % 2)
        width = 2
    k = 0
    for b in range(n_dof):
        base = b * n_coef
        if b == a:
            for j in range(n_coef):
                places[k] = base + j
                k += 1
        else:
            for u in range(width):
                places[k] = base + lo + u
                k += 1
    places[k] = n
    return k + 1


@jit
def pattern_size(n_dof, n_coef, first):
    """Places of the pattern in rows ``0 .. n - 1`` of the Jacobian plus the
    ``n + 1`` entries of the bordered matrix's last (constraint) row: the
    room :func:`bordered_nonzeros` needs."""
    n = n_dof * n_coef
    n_groups = first + (n_coef - first) // 2
    total = n + 1
    for g in range(n_groups):
        width = 1 if first == 1 and g == 0 else 2
        # each of the group's n_dof * width rows
        total += n_dof * width * ((n_dof - 1) * width + n_coef + 1)
    return total


@jit
def pattern_term_sum(J, y, n_dof, n_coef, first):
    """``max_i Σ_j |J_ij y_j|`` of a Jacobian ``J`` (shape (n, n + 1)) with
    the pattern of the module docstring, summed over its places only (the
    terms left out are ``|0 · y_j| = 0``): the sum of
    :func:`hbmfric.kernels.steps.newton.rounding_floor`, bit for bit for a
    finite ``y``."""
    n = J.shape[0]
    places = np.empty(2 * n_dof + n_coef + 1, dtype=np.int64)
    worst = 0.0
    for i in range(n):
        k = _row_places(i, n_dof, n_coef, first, places)
        acc = 0.0
        for p in range(k):
            j = places[p]
            acc += abs(J[i, j] * y[j])
        if acc > worst:
            worst = acc
    return worst


@jit
def equilibrate_pattern(
    J, scale, A, row_scale, n_dof, n_coef, first, starts, columns, values
):
    """Rows ``0 .. n - 1`` of the bordered matrix, ``J diag(scale)`` with
    each row divided by its largest entry, as
    :func:`hbmfric.kernels.steps.newton.equilibrate_rows` (the same
    products, the same factors), as their nonzeros (CSR, column order, as
    :func:`~.krylov.sparse_rows` gathers them from the dense matrix) and
    their last column written into ``A`` (:func:`scatter_pattern` writes
    the other places of the pattern from the nonzeros).

    Parameters
    ----------
    J : ndarray, shape (n, n + 1)
        Jacobian with the pattern of the module docstring, physical units.
    scale : ndarray, shape (n + 1,)
        Variable scales.
    A : ndarray, shape (n + 1, n + 1)
        Output: the last column of rows ``0 .. n - 1`` (the border, read at
        every solve); the other places are written only by
        :func:`scatter_pattern`, when the block solver factors (writing
        them at every Newton iteration cost a third of this pass at
        ``N = 100``); entries off the pattern untouched.
    row_scale : ndarray, shape (>= n,)
        Output: the factor applied to each row (1 for a zero row).
    n_dof, n_coef, first : int
        Layout of the unknowns (:mod:`.blocks`).
    starts, columns, values : ndarray
        Output: ``starts[0 .. n]`` and the nonzeros of rows ``0 .. n - 1``;
        room for :func:`pattern_size` entries (int64, int64, float64).
    """
    n = J.shape[0]
    places = np.empty(2 * n_dof + n_coef + 1, dtype=np.int64)
    e = 0
    for i in range(n):
        k = _row_places(i, n_dof, n_coef, first, places)
        row_max = 0.0
        for p in range(k):
            j = places[p]
            v = J[i, j] * scale[j]
            if abs(v) > row_max:
                row_max = abs(v)
        inv = 1.0 / row_max if row_max > 0.0 else 1.0
        row_scale[i] = inv
        starts[i] = e
        for p in range(k):
            j = places[p]
            v = (J[i, j] * scale[j]) * inv
            if v != 0.0:
                columns[e] = j
                values[e] = v
                e += 1
        A[i, n] = (J[i, n] * scale[n]) * inv  # the last place: the border
    starts[n] = e


@jit
def scatter_pattern(A, n_dof, n_coef, first, starts, columns, values):
    """Rows ``0 .. n - 1`` of ``A`` (shape (m, m), ``m = n + 1``) at the
    places of the pattern from their nonzeros (CSR of
    :func:`equilibrate_pattern`): every place written, the nonzeros' own
    entries and zeros at the others; the entries off the pattern are left
    as they were. What :func:`equilibrate_pattern` leaves unwritten, for
    the readers of ``A``'s blocks (the harmonic blocks and the slipping
    coordinates' blocks of :func:`hbmfric.kernels.linalg.blocks.block_solve`,
    which call it only when they factor: a few times per hundred solves)."""
    n = n_dof * n_coef
    places = np.empty(2 * n_dof + n_coef + 1, dtype=np.int64)
    for i in range(n):
        k = _row_places(i, n_dof, n_coef, first, places)
        for p in range(k):
            A[i, places[p]] = 0.0
        for e in range(starts[i], starts[i + 1]):
            A[i, columns[e]] = values[e]


@jit
def append_last_row(A, starts, columns, values):
    """Append the nonzeros of the last row of ``A`` (shape (m, m), every
    column read) to the CSR whose rows ``0 .. m - 2`` are in ``starts``,
    ``columns``, ``values`` (:func:`equilibrate_pattern`)."""
    m = A.shape[0]
    n = m - 1
    e = starts[n]
    for j in range(m):
        v = A[n, j]
        if v != 0.0:
            columns[e] = j
            values[e] = v
            e += 1
    starts[m] = e


@jit
def pattern_nonzeros(J, n_dof, n_coef, first, starts, columns, values):
    """The nonzeros (CSR, column order) of the leading ``n × n`` part of a
    Jacobian ``J`` (shape (n, >= n)) with the pattern of the module
    docstring, read at its places only: :func:`~.krylov.sparse_rows` of
    ``J[:, :n]``, the same entries in the same order (the places left out
    hold exact zeros). The truncation estimate's probe system
    (:func:`hbmfric.kernels.steps.truncation.probe_solve`) is that part,
    unbordered and unscaled.

    Parameters
    ----------
    J : ndarray, shape (n, >= n)
        Jacobian, ``n = n_dof n_coef``; its columns from ``n`` on are not
        read.
    n_dof, n_coef, first : int
        Layout of the unknowns (:mod:`.blocks`).
    starts, columns, values : ndarray
        Output: ``starts[0 .. n]`` and the nonzeros; room for
        :func:`pattern_size` ``- 2 n - 1`` entries (int64, int64, float64).
    """
    n = n_dof * n_coef
    places = np.empty(2 * n_dof + n_coef + 1, dtype=np.int64)
    e = 0
    for i in range(n):
        k = _row_places(i, n_dof, n_coef, first, places) - 1  # not column n
        starts[i] = e
        for p in range(k):
            j = places[p]
            v = J[i, j]
            if v != 0.0:
                columns[e] = j
                values[e] = v
                e += 1
    starts[n] = e
