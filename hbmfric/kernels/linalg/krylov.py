"""GMRES preconditioned by the LU factors of a nearby matrix.

The continuation corrector solves one bordered system per Newton iteration,
and successive systems along a branch differ little. With the factors of an
earlier matrix ``M`` (:func:`hbmfric.kernels.linalg.lu.lu_factor`) as a
right preconditioner, GMRES on ``A M⁻¹ u = b``, ``x = M⁻¹ u`` needs a few
products with the current matrix ``A`` (its nonzeros, :func:`sparse_rows`)
and a few triangular solves with ``M``, ``O(m²)`` each, instead of a new
``O(m³)`` factorisation. Right
preconditioning keeps the residual GMRES minimises the true one, ``b -
A x``; the result is checked against that residual computed afresh, so a
poor or inconsistent preconditioner costs iterations, never accuracy.
Plain loops, as :mod:`.lu` (no BLAS threads).
"""

import numpy as np

from ..._jit import jit
from .lu import lu_factor, lu_solve

#: status of :func:`gmres_lu`
GMRES_CONVERGED = 0
GMRES_NOT_CONVERGED = 1
GMRES_NOT_FINITE = 2


@jit
def sparse_rows(A):
    """The nonzero entries of ``A`` (shape (m, k)) row by row (CSR):
    ``starts`` (m + 1,) int64, ``columns`` (nnz,) int64, ``values``
    (nnz,). The corrector's bordered matrix of a condensed problem is
    mostly zeros (harmonics couple only through the contacts' own rows: on
    the lap joint at H = 15 about 16 % of the entries are nonzero), so its
    products cost a sixth of the dense ones."""
    m, k = A.shape
    nnz = 0
    for i in range(m):
        for j in range(k):
            if A[i, j] != 0.0:
                nnz += 1
    starts = np.empty(m + 1, dtype=np.int64)
    columns = np.empty(nnz, dtype=np.int64)
    values = np.empty(nnz)
    e = 0
    for i in range(m):
        starts[i] = e
        for j in range(k):
            a = A[i, j]
            if a != 0.0:
                columns[e] = j
                values[e] = a
                e += 1
    starts[m] = e
    return starts, columns, values


@jit
def sparse_matvec(starts, columns, values, x, out):
    """``out = A @ x`` for ``A`` given by :func:`sparse_rows`."""
    m = starts.size - 1
    for i in range(m):
        s = 0.0
        for e in range(starts[i], starts[i + 1]):
            s += values[e] * x[columns[e]]
        out[i] = s


@jit
def _row_dot(A, i, x, lo, hi):
    """``Σ_{lo <= j < hi} A[i, j] x[j]`` with four partial sums (the
    dependency chain of one sum bounds a plain loop; about 1.7 times faster
    at order 545)."""
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    s3 = 0.0
    j = lo
    while j + 3 < hi:
        s0 += A[i, j] * x[j]
        s1 += A[i, j + 1] * x[j + 1]
        s2 += A[i, j + 2] * x[j + 2]
        s3 += A[i, j + 3] * x[j + 3]
        j += 4
    while j < hi:
        s0 += A[i, j] * x[j]
        j += 1
    return (s0 + s1) + (s2 + s3)


@jit
def apply_factors(F, piv, b):
    """``b ← M⁻¹ b`` for the factors ``F``, ``piv`` of ``M``
    (:func:`~.lu.lu_factor`): :func:`~.lu.lu_solve` with the row sums of
    :func:`_row_dot` (the preconditioner of :func:`gmres_lu`; rounding
    differs from ``lu_solve`` in the last bits, which the recomputed
    residual of GMRES does not depend on)."""
    m = b.size
    for k in range(m):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for i in range(1, m):
        b[i] -= _row_dot(F, i, b, np.int64(0), i)  # one signature, not a literal
    for i in range(m - 1, -1, -1):
        b[i] = (b[i] - _row_dot(F, i, b, i + 1, m)) / F[i, i]


@jit
def _norm2(a):
    s = 0.0
    for v in a:
        s += v * v
    return np.sqrt(s)


@jit
def arnoldi_step(V, H, cs, sn, g, k):
    """One GMRES step after the caller has put the preconditioned product
    into ``V[k + 1]``: orthogonalise it against the basis (modified
    Gram-Schmidt, twice: the basis stays orthogonal to rounding), normalise
    it, and rotate column ``k`` of the Hessenberg matrix ``H`` (shape
    (k_max + 1, k_max)) by the Givens rotations ``cs``, ``sn`` (shape
    (k_max,)) into ``g`` (shape (k_max + 1,), the rotated right-hand side).

    Returns
    -------
    status : int
        ``GMRES_CONVERGED`` to go on, ``GMRES_NOT_FINITE`` or
        ``GMRES_NOT_CONVERGED`` (a breakdown of the rotation).
    h_next : float
        The norm of the new vector before normalisation (0: the space is
        invariant, the solution exact).
    """
    m = V.shape[1]
    for _pass in range(2):
        for j in range(k + 1):
            h = 0.0
            for i in range(m):
                h += V[j, i] * V[k + 1, i]
            H[j, k] += h
            for i in range(m):
                V[k + 1, i] -= h * V[j, i]
    h_next = _norm2(V[k + 1])
    H[k + 1, k] = h_next
    if not np.isfinite(h_next):
        return GMRES_NOT_FINITE, h_next
    if h_next > 0.0:
        inv = 1.0 / h_next
        for i in range(m):
            V[k + 1, i] *= inv
    for j in range(k):
        t = cs[j] * H[j, k] + sn[j] * H[j + 1, k]
        H[j + 1, k] = -sn[j] * H[j, k] + cs[j] * H[j + 1, k]
        H[j, k] = t
    r = np.hypot(H[k, k], H[k + 1, k])
    if r == 0.0:
        return GMRES_NOT_CONVERGED, h_next
    cs[k] = H[k, k] / r
    sn[k] = H[k + 1, k] / r
    H[k, k] = r
    H[k + 1, k] = 0.0
    g[k + 1] = -sn[k] * g[k]
    g[k] = cs[k] * g[k]
    return GMRES_CONVERGED, h_next


@jit
def krylov_combination(V, H, g, k, u):
    """``u`` (shape (m,)) = the combination of the first ``k`` basis
    vectors of ``V`` that minimises the residual: the triangular ``H``
    solved against ``g`` by back substitution."""
    y = np.empty(k)
    for j in range(k - 1, -1, -1):
        s = g[j]
        for i in range(j + 1, k):
            s -= H[j, i] * y[i]
        y[j] = s / H[j, j]
    for i in range(u.size):
        u[i] = 0.0
    for j in range(k):
        yj = y[j]
        for i in range(u.size):
            u[i] += yj * V[j, i]


@jit
def gmres_lu(A, F, piv, b, x, V, tol):
    """Solve ``A x = b`` by GMRES, right-preconditioned by LU factors.

    Parameters
    ----------
    A : ndarray, shape (m, m)
        The matrix (not modified).
    F, piv : ndarray, shapes (m, m), (m,) int64
        LU factors of a matrix near ``A`` (:func:`~.lu.lu_factor`).
    b : ndarray, shape (m,)
        Right-hand side (not modified).
    x : ndarray, shape (m,)
        Out: the solution (meaningless unless converged).
    V : ndarray, shape (k_max + 1, m)
        Work array: the Krylov basis; ``k_max`` bounds the iterations
        (no restart).
    tol : float
        Converged when ``‖b - A x‖₂ <= tol ‖b‖₂``, checked on the residual
        recomputed from ``x``.

    Returns
    -------
    status : int
        ``GMRES_CONVERGED``, ``GMRES_NOT_CONVERGED`` (``k_max`` iterations,
        or the recomputed residual above ``tol``) or ``GMRES_NOT_FINITE``.
    iterations : int
        Products with ``A`` spent (the check included).
    """
    m = b.size
    k_max = V.shape[0] - 1
    beta = _norm2(b)
    if not np.isfinite(beta):
        return GMRES_NOT_FINITE, 0
    if beta == 0.0:
        for i in range(m):
            x[i] = 0.0
        return GMRES_CONVERGED, 0
    # a NaN anywhere in A gives a NaN product, caught below
    starts, columns, values = sparse_rows(A)
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
        # w = A M⁻¹ v_k, orthogonalised against the basis (modified
        # Gram-Schmidt, twice: the basis stays orthogonal to rounding)
        for i in range(m):
            u[i] = V[k, i]
        apply_factors(F, piv, u)
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
    # y = H⁻¹ g (upper triangular k × k), u = V y, x = M⁻¹ u
    krylov_combination(V, H, g, k, u)
    apply_factors(F, piv, u)
    for i in range(m):
        x[i] = u[i]
    # the true residual, recomputed (the recurrence drifts with rounding)
    sparse_matvec(starts, columns, values, x, u)
    for i in range(m):
        u[i] = b[i] - u[i]
    res = _norm2(u)
    if not np.isfinite(res):
        return GMRES_NOT_FINITE, k + 1
    if res > target:
        return GMRES_NOT_CONVERGED, k + 1
    return GMRES_CONVERGED, k + 1


# indices into the state array of :func:`reuse_solve`
#: != 0: ``F`` holds usable factors
REUSE_VALID = 0
#: counters (out): fresh factorisations, GMRES solves that converged, products
#: with the matrix spent by GMRES, GMRES runs that failed (then factored)
REUSE_FACTORISATIONS = 1
REUSE_SOLVES = 2
REUSE_PRODUCTS = 3
REUSE_FALLBACKS = 4
#: settings (in): GMRES tolerance (relative 2-norm of the residual) and the
#: products after which the factors count as stale (the next solve factors)
REUSE_TOL = 5
REUSE_REFRESH = 6
#: setting (in): the corrector's preconditioner, ``REUSE_MODE_FACTORS``
#: (kept LU factors of an earlier matrix, :func:`reuse_solve`) or
#: ``REUSE_MODE_BLOCKS`` (the harmonic blocks of the current matrix,
#: :func:`hbmfric.kernels.linalg.blocks.block_solve`)
REUSE_MODE = 7
REUSE_MODE_FACTORS = 0.0
REUSE_MODE_BLOCKS = 1.0
#: what the work arrays hold for the last matrix (blocks path)
REUSE_PREPARED = 8
#: blocks path: products of the first solve on the current harmonic
#: blocks and of the latest one (out), the extra products over the first
#: after which the blocks are factored afresh (in; negative: at every
#: matrix) and the blocks factored (out)
REUSE_BLOCKS_FRESH = 9
REUSE_BLOCKS_LAST = 10
REUSE_BLOCKS_KEEP = 11
REUSE_BLOCK_BUILDS = 12
#: blocks path: the blocks' correction for the slipping coordinates
#: (:mod:`hbmfric.kernels.linalg.capacitance`) built for every matrix, also
#: on kept blocks (in, != 0), or only with fresh blocks (0); and the
#: corrections built (out)
REUSE_CAPACITANCE_EVERY = 13
REUSE_CAPACITANCE_BUILDS = 14
#: blocks path: != 0 when the kept nonzeros (the solver's tenth array,
#: :func:`hbmfric.kernels.linalg.pattern.equilibrate_pattern`) are those of
#: the matrix of the last solve (out; the tangent's solve on the same
#: matrix multiplies with them)
REUSE_NONZEROS = 15
N_REUSE = 16


@jit
def reuse_solve(A, b, F, piv, V, state):
    """Solve ``A x = b`` with the factors of an earlier matrix where they
    serve, else factor ``A``.

    With usable factors in ``F`` (``state[REUSE_VALID]``), GMRES
    preconditioned by them (:func:`gmres_lu`, at most ``V.shape[0] - 1``
    iterations, tolerance ``state[REUSE_TOL]``); a run that spent more than
    ``state[REUSE_REFRESH]`` products marks them stale. Without usable
    factors, or when GMRES fails, ``A`` is copied into ``F`` and factored
    (:func:`~.lu.lu_factor`), and the solve is direct: the factors stay for
    the next calls.

    Parameters
    ----------
    A : ndarray, shape (m, m)
        The matrix (not modified).
    b : ndarray, shape (m,)
        In: right-hand side. Out: the solution.
    F, piv : ndarray, shapes (m, m), (m,) int64
        In/out: factors kept between calls.
    V : ndarray, shape (k_max + 1, m)
        Work array of :func:`gmres_lu`.
    state : ndarray, shape (N_REUSE,)
        Flag, counters and settings (index constants of this module).

    Returns
    -------
    bool
        False if ``A`` is singular to the pivot test of
        :func:`~.lu.lu_factor` or the solution is not finite (``b`` is then
        meaningless).
    """
    m = b.size
    if state[REUSE_VALID] != 0.0:
        x = np.empty(m)
        status, products = gmres_lu(A, F, piv, b, x, V, state[REUSE_TOL])
        state[REUSE_PRODUCTS] += products
        if status == GMRES_CONVERGED:
            for i in range(m):
                b[i] = x[i]
            state[REUSE_SOLVES] += 1.0
            if products > state[REUSE_REFRESH]:
                state[REUSE_VALID] = 0.0
            return True
        state[REUSE_FALLBACKS] += 1.0
    state[REUSE_VALID] = 0.0
    for i in range(m):
        for j in range(m):
            F[i, j] = A[i, j]
    if not lu_factor(F, piv):
        return False
    state[REUSE_VALID] = 1.0
    state[REUSE_FACTORISATIONS] += 1.0
    lu_solve(F, piv, b)
    for i in range(m):
        if not np.isfinite(b[i]):
            state[REUSE_VALID] = 0.0
            return False
    return True
