"""GMRES preconditioned by the harmonic blocks of a harmonic-balance
Jacobian.

The Jacobian of a harmonic-balance residual is the sum of a linear part,
block diagonal over harmonics (the dynamic stiffness of harmonic ``k``
couples the DOFs or coordinates within that harmonic only), and a contact
part, block diagonal over contacts (each contact's force depends on its
own coordinate's coefficients only; a stuck contact's part is diagonal in
the harmonics as well). Its *harmonic blocks*, the entries that couple the
unknowns of one harmonic among themselves (the linear part and the
harmonic-diagonal part of every contact's Jacobian), make a preconditioner
that costs one small LU per harmonic (order ``2 n_dof``) to build and
``O(n_harmonics (2 n_dof)²)`` to apply, against ``O(m³)`` and ``O(m²)`` for
the LU of the whole matrix (``m = n_dof n_coef``). What the blocks leave
out, the coupling of harmonics by the slipping contacts, is a small part of
the matrix where the structure between the contacts is stiff against them
(the lap joint: its condensed dynamic stiffness against the tangential
contact stiffness), so GMRES needs few iterations (9-20 on the lap joint's
truncation estimate at ``N = 40``, ``H = 31``, order 1088).

A bordered matrix ``[[A, a], [cᵀ, d]]`` (the continuation corrector's) is
preconditioned by ``[[P, a], [cᵀ, d]]`` with ``P`` the harmonic blocks of
``A``: exact block elimination with ``z = P⁻¹ a``.

Unknowns are stored DOF by DOF (``x[d * n_coef + j]``); within a DOF the
columns are the constant (column 0, when ``first = 1``) and then the
cosine and sine coefficient of each harmonic. Plain loops (no BLAS
threads, :mod:`.lu`); the result of GMRES is checked against the residual
recomputed from it, so the preconditioner costs iterations, never accuracy.
"""

import numpy as np

from ..._jit import jit
from .capacitance import apply_capacitance, capacitance_work, prepare_capacitance
from .krylov import (
    GMRES_CONVERGED,
    GMRES_NOT_CONVERGED,
    GMRES_NOT_FINITE,
    REUSE_BLOCK_BUILDS,
    REUSE_BLOCKS_FRESH,
    REUSE_BLOCKS_KEEP,
    REUSE_BLOCKS_LAST,
    REUSE_CAPACITANCE_BUILDS,
    REUSE_CAPACITANCE_EVERY,
    REUSE_FACTORISATIONS,
    REUSE_FALLBACKS,
    REUSE_NONZEROS,
    REUSE_PREPARED,
    REUSE_PRODUCTS,
    REUSE_SOLVES,
    REUSE_TOL,
    _norm2,
    arnoldi_step,
    krylov_combination,
    sparse_matvec,
    sparse_rows,
)
from .lu import lu_factor, lu_solve
from .pattern import pattern_nonzeros, pattern_size, scatter_pattern


@jit
def n_harmonic_groups(n_coef, first):
    """Number of harmonic blocks: the constant (if ``first = 1``) and one
    per cosine/sine pair."""
    return first + (n_coef - first) // 2


@jit
def _group(g, first):
    """Column within a DOF and width (1 or 2) of harmonic block ``g``."""
    if first == 1:
        if g == 0:
            return 0, 1
        return 1 + 2 * (g - 1), 2
    return 2 * g, 2


@jit
def factor_blocks(A, n_dof, n_coef, first, blocks, pivots):
    """LU factors of the harmonic blocks of the leading ``n = n_dof n_coef``
    rows and columns of ``A``.

    Parameters
    ----------
    A : ndarray, shape (>= n, >= n)
        The matrix (not modified).
    n_dof : int
        DOFs (or contact coordinates) among the unknowns.
    n_coef : int
        Coefficients per DOF.
    first : int
        1 if column 0 of each DOF is the constant, else 0.
    blocks : ndarray, shape (n_groups, 2 n_dof, 2 n_dof)
        Out: the factors, block ``g`` in ``blocks[g]`` (a block of the
        constant, order ``n_dof``, is padded with the identity).
    pivots : ndarray of int64, shape (n_groups, 2 n_dof)
        Out: their pivots.

    Returns
    -------
    bool
        False if a block is singular to the pivot test of
        :func:`~.lu.lu_factor`.
    """
    size = 2 * n_dof
    for g in range(n_harmonic_groups(n_coef, first)):
        col, width = _group(g, first)
        B = blocks[g]
        for i in range(size):
            for j in range(size):
                B[i, j] = 0.0
        for i in range(width * n_dof, size):
            B[i, i] = 1.0
        for d in range(n_dof):
            for u in range(width):
                row = d * n_coef + col + u
                for e in range(n_dof):
                    for v in range(width):
                        B[d * width + u, e * width + v] = A[row, e * n_coef + col + v]
        if not lu_factor(B, pivots[g]):
            return False
    return True


@jit
def apply_blocks(blocks, pivots, n_dof, n_coef, first, v, work):
    """``v[:n] ← P⁻¹ v[:n]`` for the harmonic blocks ``P`` factored by
    :func:`factor_blocks`; ``work``: shape (2 n_dof,)."""
    size = 2 * n_dof
    for g in range(n_harmonic_groups(n_coef, first)):
        col, width = _group(g, first)
        for i in range(size):
            work[i] = 0.0
        for d in range(n_dof):
            for u in range(width):
                work[d * width + u] = v[d * n_coef + col + u]
        lu_solve(blocks[g], pivots[g], work)
        for d in range(n_dof):
            for u in range(width):
                v[d * n_coef + col + u] = work[d * width + u]


@jit
def block_work(n_dof, n_coef, first, m, k_max):
    """Work arrays of :func:`gmres_blocks` for a matrix of order ``m``
    (``n_dof n_coef`` or one more, bordered) and at most ``k_max``
    iterations: ``(blocks, pivots, border, V, work)``."""
    n_groups = n_harmonic_groups(n_coef, first)
    size = 2 * n_dof
    return (
        np.empty((n_groups, size, size)),
        np.empty((n_groups, size), dtype=np.int64),
        np.empty(m),
        np.empty((k_max + 1, m)),
        np.empty(size),
    )


@jit
def prepare_blocks(A, n_dof, n_coef, first, blocks, pivots, border, work):
    """Build the preconditioner of ``A`` (order ``m = n`` or ``n + 1``
    bordered, ``n = n_dof n_coef``): factor its harmonic blocks and, when
    bordered, ``border[:n] = z = P⁻¹ a`` (``a`` the last column) and
    ``border[n] = d - cᵀ z`` (``cᵀ`` the last row). False if a block or
    the bordered preconditioner is singular."""
    if not factor_blocks(A, n_dof, n_coef, first, blocks, pivots):
        return False
    none = capacitance_work(n_dof, n_coef, first, 0)
    return prepare_border(A, n_dof, n_coef, first, blocks, pivots, none, border, work)


@jit
def prepare_border(A, n_dof, n_coef, first, blocks, pivots, correction, border, work):
    """The bordered part of :func:`prepare_blocks` for ``A`` with harmonic
    blocks already factored (of ``A`` or of an earlier matrix) and their
    slipping-contact ``correction`` built (:mod:`.capacitance`; none when
    its count is 0): ``border[:n] = z = M⁻¹ a`` with ``M`` the corrected
    blocks, ``border[n] = d - cᵀ z``. True at once when ``A`` is not
    bordered; False if the bordered preconditioner is singular."""
    n = n_dof * n_coef
    m = A.shape[0]
    if m == n:
        return True
    for i in range(n):
        border[i] = A[i, n]
    apply_blocks(blocks, pivots, n_dof, n_coef, first, border, work)
    apply_capacitance(correction, n_dof, n_coef, first, border)
    delta = A[n, n]
    for i in range(n):
        delta -= A[n, i] * border[i]
    border[n] = delta
    return np.isfinite(delta) and delta != 0.0


@jit
def _eliminate_border(A, border, v, n):
    """The bordered step of the preconditioner: ``v[:n]`` holds ``M⁻¹
    v[:n]``; solve for the last unknown and correct the others."""
    s = v[n]
    for i in range(n):
        s -= A[n, i] * v[i]
    s /= border[n]
    for i in range(n):
        v[i] -= s * border[i]
    v[n] = s


@jit
def apply_preconditioner(A, blocks, pivots, n_dof, n_coef, first, border, v, work):
    """``v ← M⁻¹ v`` for the preconditioner of :func:`prepare_blocks`:
    the harmonic blocks, bordered by the last row and column of ``A`` when
    ``v`` has one more entry than ``n_dof n_coef``."""
    n = n_dof * n_coef
    apply_blocks(blocks, pivots, n_dof, n_coef, first, v, work)
    if v.size == n:
        return
    _eliminate_border(A, border, v, n)


@jit
def apply_corrected(
    A, blocks, pivots, correction, n_dof, n_coef, first, border, v, work
):
    """:func:`apply_preconditioner` with the harmonic blocks corrected for
    the slipping coordinates (:func:`~.capacitance.apply_capacitance`;
    ``border`` from :func:`prepare_border` with the same correction)."""
    n = n_dof * n_coef
    apply_blocks(blocks, pivots, n_dof, n_coef, first, v, work)
    apply_capacitance(correction, n_dof, n_coef, first, v)
    if v.size == n:
        return
    _eliminate_border(A, border, v, n)


@jit
def gmres_blocks(A, b, x, n_dof, n_coef, first, tol, arrays):
    """Solve ``A x = b`` by GMRES right-preconditioned by the harmonic
    blocks of ``A`` (bordered when ``A`` has order ``n_dof n_coef + 1``).

    Parameters
    ----------
    A : ndarray, shape (m, m)
        The matrix (not modified), ``m = n_dof n_coef`` or one more.
    b : ndarray, shape (m,)
        Right-hand side (not modified).
    x : ndarray, shape (m,)
        Out: the solution (meaningless unless converged).
    n_dof, n_coef, first : int
        Layout of the unknowns (:func:`factor_blocks`).
    tol : float
        Converged when ``‖b - A x‖₂ <= tol ‖b‖₂``, checked on the residual
        recomputed from ``x``.
    arrays : tuple
        :func:`block_work` (its Krylov basis bounds the iterations).

    Returns
    -------
    status : int
        :data:`~.krylov.GMRES_CONVERGED`, ``GMRES_NOT_CONVERGED`` (the
        iteration bound, the recomputed residual above ``tol`` or a
        singular preconditioner) or ``GMRES_NOT_FINITE``.
    iterations : int
        Products with ``A`` spent (the check included).
    """
    blocks, pivots, border, V, work = arrays
    if not np.isfinite(_norm2(b)):
        return GMRES_NOT_FINITE, 0
    if not prepare_blocks(A, n_dof, n_coef, first, blocks, pivots, border, work):
        return GMRES_NOT_CONVERGED, 0
    none = capacitance_work(n_dof, n_coef, first, 0)
    starts, columns, values = sparse_rows(A)
    return gmres_prepared(
        A,
        b,
        x,
        n_dof,
        n_coef,
        first,
        tol,
        blocks,
        pivots,
        border,
        V,
        work,
        none,
        starts,
        columns,
        values,
    )


@jit
def gmres_pattern(J, b, x, n_dof, n_coef, first, tol, arrays):
    """:func:`gmres_blocks` of the leading ``n × n`` part of a Jacobian
    ``J`` (shape (n, >= n), ``n = n_dof n_coef``) with the nonzero pattern
    of a residual on several contact coordinates (:mod:`.pattern`),
    without copying it into a square matrix: the harmonic blocks are
    factored from ``J`` and the nonzeros read at the pattern's places only
    (:func:`~.pattern.pattern_nonzeros`), so the solve is that of
    :func:`gmres_blocks` on ``J[:, :n]`` step for step, bit for bit (the
    same blocks, the same nonzeros in the same order). The truncation
    estimate's probe system (``b`` of shape (n,)); same arguments and
    results as :func:`gmres_blocks`, ``J`` not modified."""
    blocks, pivots, border, V, work = arrays
    if not np.isfinite(_norm2(b)):
        return GMRES_NOT_FINITE, 0
    if not prepare_blocks(J, n_dof, n_coef, first, blocks, pivots, border, work):
        return GMRES_NOT_CONVERGED, 0
    none = capacitance_work(n_dof, n_coef, first, 0)
    n = n_dof * n_coef
    room = pattern_size(n_dof, n_coef, first) - 2 * n - 1
    starts = np.empty(n + 1, dtype=np.int64)
    columns = np.empty(room, dtype=np.int64)
    values = np.empty(room)
    pattern_nonzeros(J, n_dof, n_coef, first, starts, columns, values)
    return gmres_prepared(
        J,
        b,
        x,
        n_dof,
        n_coef,
        first,
        tol,
        blocks,
        pivots,
        border,
        V,
        work,
        none,
        starts,
        columns,
        values,
    )


@jit
def gmres_prepared(
    A,
    b,
    x,
    n_dof,
    n_coef,
    first,
    tol,
    blocks,
    pivots,
    border,
    V,
    work,
    correction,
    starts,
    columns,
    values,
):
    """:func:`gmres_blocks` with the preconditioner of ``A`` already built
    by :func:`prepare_blocks` (same arguments and results; ``V`` and
    ``work`` the Krylov basis, shape (k_max + 1, m), and shape (2 n_dof,);
    ``correction`` the blocks' correction for the slipping coordinates,
    :mod:`.capacitance`, with which ``border`` was prepared; ``starts``,
    ``columns``, ``values`` the nonzeros of ``A``, CSR as
    :func:`~.krylov.sparse_rows` gives them: every product is taken with
    them, ``A`` itself is read only at its last row and column and its
    harmonic blocks)."""
    m = b.size
    k_max = V.shape[0] - 1
    beta = _norm2(b)
    if not np.isfinite(beta):
        return GMRES_NOT_FINITE, 0
    if beta == 0.0:
        for i in range(m):
            x[i] = 0.0
        return GMRES_CONVERGED, 0
    H = np.zeros((k_max + 1, k_max))
    cs = np.empty(k_max)
    sn = np.empty(k_max)
    g = np.zeros(k_max + 1)
    u = np.empty(m)
    inv = 1.0 / beta
    for i in range(m):
        V[0, i] = b[i] * inv
    g[0] = beta
    target = tol * beta
    k = np.int64(0)  # not a literal 0: one signature of arnoldi_step
    converged = False
    while k < k_max:
        for i in range(m):
            u[i] = V[k, i]
        apply_corrected(
            A, blocks, pivots, correction, n_dof, n_coef, first, border, u, work
        )
        sparse_matvec(starts, columns, values, u, V[k + 1])
        status, h_next = arnoldi_step(V, H, cs, sn, g, k)
        if status != GMRES_CONVERGED:
            return status, k + 1
        k += 1
        if abs(g[k]) <= 0.5 * target or h_next == 0.0:
            converged = True
            break
    if not converged:
        return GMRES_NOT_CONVERGED, k
    krylov_combination(V, H, g, k, u)
    apply_corrected(
        A, blocks, pivots, correction, n_dof, n_coef, first, border, u, work
    )
    for i in range(m):
        x[i] = u[i]
    sparse_matvec(starts, columns, values, x, u)
    for i in range(m):
        u[i] = b[i] - u[i]
    res = _norm2(u)
    if not np.isfinite(res):
        return GMRES_NOT_FINITE, k + 1
    if res > target:
        return GMRES_NOT_CONVERGED, k + 1
    return GMRES_CONVERGED, k + 1


#: values of ``state[REUSE_PREPARED]`` (:func:`block_solve`)
PREPARED_NONE = 0.0
PREPARED_BLOCKS = 1.0
PREPARED_DENSE = 2.0


@jit
def _prepare_corrected(A, n_dof, n_coef, first, solver):
    """Factor the harmonic blocks of ``A``, build their correction for its
    slipping coordinates and the border (:func:`block_solve`'s arrays);
    False if a block or the bordered preconditioner is singular."""
    state, blocks, pivots = solver[3], solver[4], solver[5]
    border, work, correction = solver[6], solver[7], solver[8]
    state[REUSE_BLOCK_BUILDS] += 1.0
    if not factor_blocks(A, n_dof, n_coef, first, blocks, pivots):
        return False
    state[REUSE_CAPACITANCE_BUILDS] += 1.0
    prepare_capacitance(A, n_dof, n_coef, first, blocks, pivots, correction, work)
    return prepare_border(
        A, n_dof, n_coef, first, blocks, pivots, correction, border, work
    )


@jit
def block_solve(A, b, solver, n_dof, n_coef, first, again, tol=-1.0, built=False):
    """Solve the corrector's bordered system ``A x = b`` by GMRES
    preconditioned by harmonic blocks (:func:`gmres_prepared`), with a
    dense LU when GMRES fails. ``b`` holds ``x`` on return; ``A`` is not
    modified.

    The harmonic blocks are corrected for the coordinates of ``A`` whose
    slipping contacts couple harmonics (:mod:`.capacitance`, as many as
    its arrays hold): on the matrix whose blocks were factored, the
    preconditioner is then the exact inverse of the bordered matrix.
    The blocks factored for an earlier matrix (an earlier Newton iteration
    or point) are kept, with the border of ``A`` (:func:`prepare_border`)
    and, when ``state[REUSE_CAPACITANCE_EVERY]`` is set, their correction
    rebuilt for ``A``,
    while the solves on them need at most ``state[REUSE_BLOCKS_KEEP]``
    products more than the first solve after they were factored; then the
    next matrix's blocks are factored. A GMRES on kept blocks that fails is
    run again on the blocks of ``A`` before the dense fallback. The
    solution is held to the same tolerance either way.

    Parameters
    ----------
    A : ndarray, shape (m, m)
        The bordered matrix, ``m = n_dof n_coef + 1``.
    b : ndarray, shape (m,)
        In: right-hand side. Out: the solution.
    solver : tuple
        ``(F, piv, V, state, blocks, pivots, border, work, correction,
        nonzeros)`` of :func:`hbmfric.condensation.solver_arrays`: dense
        factors (the fallback), Krylov basis, state (counters and settings
        of :mod:`.krylov`; ``state[REUSE_PREPARED]`` says what the arrays
        hold for the last matrix), the preconditioner's arrays
        (:func:`block_work`), those of its correction
        (:func:`~.capacitance.capacitance_work`) and room for the
        nonzeros of ``A`` (``(starts, columns, values)``,
        :func:`~.pattern.pattern_size` entries).
    n_dof, n_coef, first : int
        Layout of the unknowns (:func:`factor_blocks`).
    again : bool
        ``A`` is the matrix of the previous call (the tangent after the
        corrector): its preconditioner, or its dense factors after a
        fallback, serve as they are.
    tol : float, optional
        Relative residual of GMRES; negative (default): ``state[REUSE_TOL]``.
    built : bool, optional
        The solver's ``nonzeros`` hold those of ``A``
        (:func:`~.pattern.equilibrate_pattern` and
        :func:`~.pattern.append_last_row`): GMRES multiplies with them and
        ``A`` is read only at its last row and column (its other entries
        may hold anything); before its harmonic blocks and the slipping
        coordinates' blocks are factored, its places of the pattern are
        written from the nonzeros (:func:`~.pattern.scatter_pattern`).
        False (default): the nonzeros are gathered from the whole of ``A``
        (:func:`~.krylov.sparse_rows`), unless ``again`` follows a call
        that had them built.

    Returns
    -------
    bool
        False if ``A`` is singular to the pivot test of the dense LU or
        the solution is not finite (``b`` is then meaningless).
    """
    F, fpiv, V, state, blocks, pivots, border, work, correction = solver[:9]
    starts, columns, values = solver[9]
    m = b.size
    kept = built or (again and state[REUSE_NONZEROS] != 0.0)
    state[REUSE_NONZEROS] = 1.0 if kept else 0.0
    ready = state[REUSE_PREPARED] if again else PREPARED_NONE
    if ready == PREPARED_DENSE:
        lu_solve(F, fpiv, b)
        return np.isfinite(b).all()
    fresh = False
    # built nonzeros: A's places of the pattern are written from them only
    # before its blocks are factored (equilibrate_pattern leaves them)
    written = False
    if ready != PREPARED_BLOCKS:
        keep = (
            state[REUSE_PREPARED] == PREPARED_BLOCKS
            and state[REUSE_BLOCKS_KEEP] >= 0.0
            and state[REUSE_BLOCKS_LAST]
            <= state[REUSE_BLOCKS_FRESH] + state[REUSE_BLOCKS_KEEP]
        )
        state[REUSE_PREPARED] = PREPARED_NONE
        if keep and state[REUSE_CAPACITANCE_EVERY] != 0.0:
            if kept:
                scatter_pattern(A, n_dof, n_coef, first, starts, columns, values)
                written = True
            state[REUSE_CAPACITANCE_BUILDS] += 1.0
            prepare_capacitance(
                A, n_dof, n_coef, first, blocks, pivots, correction, work
            )
        if keep and prepare_border(
            A, n_dof, n_coef, first, blocks, pivots, correction, border, work
        ):
            state[REUSE_PREPARED] = PREPARED_BLOCKS
        else:
            fresh = True
            if kept and not written:
                scatter_pattern(A, n_dof, n_coef, first, starts, columns, values)
                written = True
            if _prepare_corrected(A, n_dof, n_coef, first, solver):
                state[REUSE_PREPARED] = PREPARED_BLOCKS
    x = np.empty(m)
    if not tol > 0.0:
        tol = state[REUSE_TOL]
    if not kept:
        starts, columns, values = sparse_rows(A)
    for attempt in range(2):
        if state[REUSE_PREPARED] != PREPARED_BLOCKS:
            break
        status, products = gmres_prepared(
            A,
            b,
            x,
            n_dof,
            n_coef,
            first,
            tol,
            blocks,
            pivots,
            border,
            V,
            work,
            correction,
            starts,
            columns,
            values,
        )
        state[REUSE_PRODUCTS] += products
        if status == GMRES_CONVERGED:
            for i in range(m):
                b[i] = x[i]
            state[REUSE_SOLVES] += 1.0
            if fresh:
                state[REUSE_BLOCKS_FRESH] = products
            if not again:
                state[REUSE_BLOCKS_LAST] = products
            return True
        if fresh or attempt == 1:
            break
        # kept blocks of an earlier matrix: once more on those of A
        fresh = True
        state[REUSE_PREPARED] = PREPARED_NONE
        if kept and not written:
            scatter_pattern(A, n_dof, n_coef, first, starts, columns, values)
            written = True
        if _prepare_corrected(A, n_dof, n_coef, first, solver):
            state[REUSE_PREPARED] = PREPARED_BLOCKS
    if state[REUSE_PREPARED] == PREPARED_BLOCKS:
        state[REUSE_FALLBACKS] += 1.0
    state[REUSE_PREPARED] = PREPARED_NONE
    # the dense matrix from its nonzeros (A itself may hold anything off
    # them when they were built on the pattern)
    for i in range(m):
        for j in range(m):
            F[i, j] = 0.0
        for e in range(starts[i], starts[i + 1]):
            F[i, columns[e]] = values[e]
    if not lu_factor(F, fpiv):
        return False
    state[REUSE_FACTORISATIONS] += 1.0
    state[REUSE_PREPARED] = PREPARED_DENSE
    lu_solve(F, fpiv, b)
    return np.isfinite(b).all()
