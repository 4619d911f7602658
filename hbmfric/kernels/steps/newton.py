"""Newton kernels for continuation: the bordered corrector and the tangent.

Both work on ``y = [X, Ω]`` in physical units; ``scale`` (same shape as
``y``) defines the scaled variables ``y / scale`` in which arc length,
tangents and step norms are measured, so that Ω and the amplitudes weigh
alike.
"""

import numpy as np
from numba.extending import overload

from ..._jit import jit, jit_inline
from ..dlft.coulomb import COULOMB
from ..linalg.blocks import (
    block_solve,
    block_work,
    factor_blocks,
    gmres_prepared,
    prepare_border,
)
from ..linalg.capacitance import capacitance_work, prepare_capacitance
from ..linalg.krylov import (
    GMRES_CONVERGED,
    REUSE_MODE,
    REUSE_MODE_BLOCKS,
    reuse_solve,
    sparse_rows,
)
from ..linalg.lu import lu_factor, lu_solve, solve_inplace
from ..linalg.pattern import append_last_row, equilibrate_pattern, pattern_term_sum
from ..residuals.dispatch import _is_condensed, _on_coordinates, rounding_level
from ..residuals.hbm import JIT_OPTIONS
from ..residuals.pointer import call_residual

#: relative residual to which GMRES on the harmonic blocks solves a
#: corrector's Newton update (the tangent keeps ``state[REUSE_TOL]``,
#: 1e-10): an update solved to 1e-6 differs from the exact one by a
#: millionth of itself (times the bordered matrix's condition), far below
#: the quadratic error it leaves; convergence is judged on the residual
#: recomputed at the new point and on the size of the next update. The lap
#: joint at N = 40: a quarter fewer GMRES products, the same evaluations
#: (bench/README.md "Issue 15, stop 28")
NEWTON_KRYLOV_TOL = 1e-6

#: the corrector of a problem condensed onto several contact coordinates
#: (:func:`applies_last_update`) applies its last Newton update without a new
#: evaluation when the updates contract by at most this factor per
#: iteration and the error left, estimated from that contraction, is below
#: ``tol_step`` (:func:`correct`)
CONTRACTION_MAX = 0.5

CONVERGED = 0
MAX_ITERATIONS = 1
SINGULAR = 2
NOT_FINITE = 3
AFT_FAILED = 4

MESSAGES = {
    CONVERGED: "converged",
    MAX_ITERATIONS: "Newton iteration limit reached",
    SINGULAR: "singular Jacobian",
    NOT_FINITE: "non-finite residual or update",
    AFT_FAILED: "AFT evaluation failed",
}


@jit
def _norm_inf(a):
    m = 0.0
    for x in a:
        ax = abs(x)
        if not ax <= m:  # also catches NaN
            m = ax
    return m


@jit
def equilibrate_rows(J, scale, A, row_scale):
    """First ``n`` rows of ``A``: ``J diag(scale)`` with each row divided by
    its largest entry (rows of residuals in N next to a constraint row of
    order one; the pivot tests are relative to the largest entry).

    Parameters
    ----------
    J : ndarray, shape (n, n + 1)
        Jacobian, physical units.
    scale : ndarray, shape (n + 1,)
        Variable scales.
    A : ndarray, shape (n + 1, n + 1)
        Output: rows ``0 .. n - 1`` filled.
    row_scale : ndarray, shape (>= n,)
        Output: the factor applied to each row (1 for a zero row).
    """
    n = J.shape[0]
    for i in range(n):
        row_max = 0.0
        for j in range(n + 1):
            v = J[i, j] * scale[j]
            A[i, j] = v
            if abs(v) > row_max:
                row_max = abs(v)
        inv = 1.0 / row_max if row_max > 0.0 else 1.0
        for j in range(n + 1):
            A[i, j] *= inv
        row_scale[i] = inv


def _pattern_rows(problem, A):
    """Whether the corrector of ``problem`` builds the rows of its bordered
    matrix ``A`` on the Jacobian's pattern (:func:`bordered_rows`): a
    problem condensed onto several contact coordinates whose bordered
    systems are solved on the harmonic blocks (:func:`bordered_solve`).
    Callable from jitted code only."""
    raise NotImplementedError("_pattern_rows is for jit code")


@overload(_pattern_rows, jit_options=JIT_OPTIONS, inline="always")
def _pattern_rows_impl(problem, A):
    if _on_coordinates(problem):

        def condensed(problem, A):
            solver = problem.solver
            return (
                solver[0].shape[0] == A.shape[0]
                and solver[3][REUSE_MODE] == REUSE_MODE_BLOCKS
            )

        return condensed
    return lambda problem, A: False


def jacobian_floor(problem, J, y):
    """:func:`rounding_floor` of the Jacobian ``J`` of ``problem`` at
    ``y``: over the places of its pattern for a problem condensed onto
    several contact coordinates
    (:func:`hbmfric.kernels.linalg.pattern.pattern_term_sum`, the same
    value bit for bit),
    over every entry for any other. Callable from jitted code only."""
    raise NotImplementedError("jacobian_floor is for jit code")


@overload(jacobian_floor, jit_options=JIT_OPTIONS)
def _jacobian_floor(problem, J, y):
    if _on_coordinates(problem):

        def condensed(problem, J, y):
            n_c, n_coef, first = _layout(problem)
            if n_c > 0 and n_c * n_coef == J.shape[0]:
                worst = pattern_term_sum(J, y, n_c, n_coef, first)
                return ROUNDING_EPS * 2.220446049250313e-16 * worst
            return rounding_floor(J, y)

        return condensed

    def full(problem, J, y):
        return rounding_floor(J, y)

    return full


def bordered_rows(problem, J, scale, A, row_scale):
    """Rows ``0 .. n - 1`` of the corrector's bordered matrix into ``A``:
    :func:`equilibrate_rows`, or for a problem whose bordered systems are
    solved on the harmonic blocks (:func:`bordered_solve`) the same rows
    written at the places of the Jacobian's pattern only, with their
    nonzeros into the solver's arrays
    (:func:`hbmfric.kernels.linalg.pattern.equilibrate_pattern`; the other
    entries of ``A`` are then left as they were and never read).
    Callable from jitted code only."""
    raise NotImplementedError("bordered_rows is for jit code")


@overload(bordered_rows, jit_options=JIT_OPTIONS)
def _bordered_rows(problem, J, scale, A, row_scale):
    if _on_coordinates(problem):

        def condensed(problem, J, scale, A, row_scale):
            if _pattern_rows(problem, A):
                n_c, n_coef, first = _layout(problem)
                starts, columns, values = problem.solver[9]
                equilibrate_pattern(
                    J, scale, A, row_scale, n_c, n_coef, first, starts, columns, values
                )
            else:
                equilibrate_rows(J, scale, A, row_scale)

        return condensed

    def full(problem, J, scale, A, row_scale):
        equilibrate_rows(J, scale, A, row_scale)

    return full


def bordered_solve(problem, A, piv, b):
    """Solve the corrector's bordered system ``A x = b`` (``b`` holds ``x``
    on return); False if ``A`` is singular to the pivot test. Callable from
    jitted code only.

    Dispatched at compile time on the type of ``problem``: a condensed
    problem that carries the work arrays of an iterative solve
    (``solver``, :class:`~hbmfric.kernels.residuals.condensed.CondensedProblem`;
    large problems only, see :data:`hbmfric.condensation.REUSE_MIN_UNKNOWNS`)
    solves by GMRES and leaves ``A`` unchanged: preconditioned by the
    harmonic blocks of ``A`` (:func:`~hbmfric.kernels.linalg.blocks.block_solve`,
    the default) or by the factors of an earlier iteration or point
    (:func:`~hbmfric.kernels.linalg.krylov.reuse_solve`), as
    ``state[REUSE_MODE]`` says, a dense factorisation when that fails;
    any other problem factors ``A`` in place (its factors in ``A``, ``piv``).
    On the harmonic blocks, rows ``0 .. n - 1`` of ``A`` and their
    nonzeros are those :func:`bordered_rows` built on the Jacobian's
    pattern (its other entries are not read); the last row is read whole.
    """
    raise NotImplementedError("bordered_solve is for jit code")


@overload(bordered_solve, jit_options=JIT_OPTIONS)
def _bordered_solve(problem, A, piv, b):
    # one contact to ground carries no solver arrays (order 0): dense
    if _on_coordinates(problem):

        def condensed(problem, A, piv, b):
            solver = problem.solver
            F, fpiv, V, state = solver[0], solver[1], solver[2], solver[3]
            if F.shape[0] == A.shape[0]:
                if state[REUSE_MODE] == REUSE_MODE_BLOCKS:
                    # rows 0 .. n - 1 and their nonzeros were built on the
                    # Jacobian's pattern (bordered_rows): add the last row
                    starts, columns, values = solver[9]
                    append_last_row(A, starts, columns, values)
                    n_c, n_coef, first = _layout(problem)
                    return block_solve(
                        A,
                        b,
                        solver,
                        n_c,
                        n_coef,
                        first,
                        np.bool_(False),
                        NEWTON_KRYLOV_TOL,
                        np.bool_(True),
                    )
                return reuse_solve(A, b, F, fpiv, V, state)
            if not lu_factor(A, piv):
                return False
            lu_solve(A, piv, b)
            return True

        return condensed

    def full(problem, A, piv, b):
        if not lu_factor(A, piv):
            return False
        lu_solve(A, piv, b)
        return True

    return full


#: largest last applied Newton update (scaled) after which a confirming
#: evaluation reuses the LU factors of the iterate before it
#: (:func:`correct_core`): the Jacobians differ by about this much times
#: their variation along the branch
LAG_MAX = 1e-6
#: refinement sweeps at most of a tangent from reused factors
#: (:func:`lagged_tangent`), and the relative correction below which a
#: sweep is the last (the error left is about its square)
LAG_SWEEPS = 3
LAG_CORRECTION = 1e-6


def lagged_factors(problem):
    """Whether :func:`correct_core` may confirm an iterate with the LU
    factors of the previous one: for a full problem (the dense path of
    :func:`bordered_solve`, whose factors are in ``A``, ``piv``) unless its
    contact is rigid Coulomb (the DLFT's Jacobian jumps with the stick set
    of the samples, so a tiny update does not mean nearby factors: the
    rigid Coulomb H = 3 sweep of ``tests/test_coverage.py`` stalled at a
    seam with them); never for a condensed one (its solves may be iterative
    and leave no factors: a compile-time False). Callable from jitted code
    only."""
    raise NotImplementedError("lagged_factors is for jit code")


@overload(lagged_factors, jit_options=JIT_OPTIONS, inline="always")
def _lagged_factors(problem):
    if _is_condensed(problem):
        return lambda problem: False

    def full(problem):
        codes = problem.law_codes
        return codes.size == 0 or codes[0] != COULOMB

    return full


@jit_inline
def _layout(problem):
    """Coordinates, coefficients per coordinate and the column of the first
    cosine (1 with a constant) of a condensed problem's unknowns."""
    hn = problem.harmonic_numbers
    first = 1 if hn.size > 0 and hn[0] == 0 else 0
    return problem.law_codes.size, problem.inverse.shape[1], first


def applies_last_update(problem):
    """True when :func:`correct` may end by applying an update whose error
    it estimates from the contraction of the last two: a problem condensed
    onto several contact coordinates (``law_codes``, one per coordinate),
    whichever way it solves its bordered systems (:func:`bordered_solve`);
    False for any other problem (uncondensed, or condensed onto one
    contact as the paper beam). Callable from jitted code only."""
    raise NotImplementedError("applies_last_update is for jit code")


@overload(applies_last_update, jit_options=JIT_OPTIONS)
def _applies_last_update(problem):
    if _on_coordinates(problem):

        def condensed(problem):
            return problem.law_codes.size > 1

        return condensed

    def full(problem):
        return False

    return full


def bordered_tangent(problem, A, piv, out):
    """Unit tangent ``A⁻¹ e_n / ‖A⁻¹ e_n‖`` into ``out`` after
    :func:`correct` left ``A``, ``piv`` (:func:`tangent_from_lu` of its
    factors, or for a problem solved by :func:`bordered_solve`'s reuse path
    one more such solve with the matrix left in ``A``); False if not
    finite. Callable from jitted code only."""
    raise NotImplementedError("bordered_tangent is for jit code")


@overload(bordered_tangent, jit_options=JIT_OPTIONS)
def _bordered_tangent(problem, A, piv, out):
    if _on_coordinates(problem):

        def condensed(problem, A, piv, out):
            solver = problem.solver
            F, fpiv, V, state = solver[0], solver[1], solver[2], solver[3]
            if F.shape[0] != A.shape[0]:
                return tangent_from_lu(A, piv, out)
            m = out.size
            for i in range(m):
                out[i] = 0.0
            out[m - 1] = 1.0
            if state[REUSE_MODE] == REUSE_MODE_BLOCKS:
                n_c, n_coef, first = _layout(problem)
                if not block_solve(A, out, solver, n_c, n_coef, first, np.bool_(True)):
                    return False
            elif not reuse_solve(A, out, F, fpiv, V, state):
                return False
            return _normalise(out)

        return condensed

    def full(problem, A, piv, out):
        return tangent_from_lu(A, piv, out)

    return full


#: a residual within this many machine epsilons of the size of the terms it
#: sums counts as zero (:func:`rounding_floor`)
ROUNDING_EPS = 8.0


@jit
def rounding_floor(J, y):
    """``ROUNDING_EPS · eps · max_i Σ_j |J_ij y_j|``: the rounding level of
    the residual at ``y``, N (the size of the terms that make up each
    equation, the linear ones exactly and the contact forces to first
    order); ``J`` has shape (n, n + 1), ``y`` (n + 1,)."""
    n = J.shape[0]
    worst = 0.0
    for i in range(n):
        acc = 0.0
        for j in range(n + 1):
            acc += abs(J[i, j] * y[j])
        if acc > worst:
            worst = acc
    return ROUNDING_EPS * 2.220446049250313e-16 * worst


@jit
def correct(
    problem,
    residual_at,
    y,
    y_pred,
    constraint,
    scale,
    tol_residual,
    tol_step,
    max_iter,
    R,
    J,
    A,
    piv,
):
    """Solve ``R(y) = 0`` together with ``constraint · (y - y_pred) / scale = 0``.

    With ``constraint`` the unit tangent this is the pseudo-arclength
    corrector (orthogonal to the tangent through the predictor ``y_pred``);
    with ``constraint = e_Ω`` it is Newton's method at fixed Ω.

    Convergence: ``max |R| <= max(tol_residual, rounding_floor(J, y),
    rounding_level(problem))`` (the rounding level of the residual's terms,
    and the one a condensed residual reports for its receptance inverse,
    :func:`hbmfric.kernels.residuals.dispatch.rounding_level`) and the Newton
    update *from the current iterate* is below ``tol_step`` in scaled variables; the
    update is then not applied (the point is within ``tol_step`` of the
    solution of the linearisation), which saves the residual evaluation
    that checking the size of the last applied update would cost. A
    problem condensed onto several contact coordinates
    (:func:`applies_last_update`) also
    converges without evaluating at the end: after a full Newton step, with
    ``theta`` the larger of the contraction of the updates and of
    ``max |R|`` over it (at most :data:`CONTRACTION_MAX`), when the error
    left after the present update, estimated at ``theta / (1 - theta)``
    times it, is below ``tol_step`` and the residual after it, estimated
    at ``theta max |R|``, below the tolerance: the update is applied and
    the point returned (the lap joint: updates 5e-6 then 3e-9 in scaled
    variables, the residual from 5e4 to 30 times the tolerance, where the
    plain test needed a third evaluation; bench/README.md "Issue 15,
    stop 29").

    Contact laws make ``R`` piecewise smooth (the Jacobian jumps where the
    contact starts to slip), so full Newton steps can cycle across such a
    seam; each step is therefore backtracked until ``max |R|`` decreases.
    The constraint is linear and stays satisfied along the step.

    Parameters
    ----------
    problem : tuple
        HBM problem, see :func:`hbmfric.kernels.residuals.hbm.hbm_residual`.
    residual_at : int
        Address of the residual compiled for ``problem``'s type
        (:func:`hbmfric.kernels.residuals.pointer.residual_address`).
    y : ndarray, shape (n + 1,)
        In: start point. Out: the last iterate (the solution on success).
    y_pred : ndarray, shape (n + 1,)
        Point the constraint hyperplane passes through.
    constraint : ndarray, shape (n + 1,)
        Normal of the constraint hyperplane, in scaled variables.
    scale : ndarray, shape (n + 1,)
        Variable scales.
    tol_residual : float
        Convergence threshold on ``max |R|``, N.
    tol_step : float
        Convergence threshold on the scaled Newton update.
    max_iter : int
        Limit on Newton iterations.
    R, J, A, piv : ndarray
        Work arrays: shapes (n,), (n, n + 1), (n + 1, n + 1), (n + 1,)
        int64. On success ``R`` and ``J`` hold the residual and Jacobian at
        the solution (after an applied last update: at the iterate before
        it) and ``A``, ``piv`` the LU factors of the bordered matrix in
        scaled variables, ``[D J diag(scale); constraint]`` with ``D`` the
        row equilibration (reused for the tangent by
        :func:`bordered_tangent`); on the reuse path of
        :func:`bordered_solve` ``A`` holds that matrix itself (on the
        harmonic blocks: at the places of the Jacobian's pattern and the
        last row, :func:`bordered_rows`; its other entries undefined).

    Returns
    -------
    status : int
        ``CONVERGED`` or a failure code (see ``MESSAGES``).
    evaluations : int
        Number of residual-and-Jacobian evaluations.
    iterations : int
        Effort measure for the step controller: the evaluations a corrector
        that tests the size of the last *applied* update would have needed
        (``evaluations + 1`` when the look-ahead test ended the iteration),
        so that the controller's tuning is independent of this saving.
    """
    rows = np.empty(R.size)
    status, evaluations, iterations, _ = correct_core(
        problem,
        residual_at,
        y,
        y_pred,
        constraint,
        scale,
        tol_residual,
        tol_step,
        max_iter,
        R,
        J,
        A,
        piv,
        rows,
        np.bool_(False),
    )
    return status, evaluations, iterations


@jit
def correct_core(
    problem,
    residual_at,
    y,
    y_pred,
    constraint,
    scale,
    tol_residual,
    tol_step,
    max_iter,
    R,
    J,
    A,
    piv,
    rows,
    lag,
):
    """:func:`correct`, with confirming evaluations that may reuse the
    factors of the previous iterate (``lag``).

    With ``lag`` (and a full problem, :func:`lagged_factors`), an iterate
    reached by an update of at most :data:`LAG_MAX` (scaled) whose residual
    is within the tolerance is confirmed without factoring the Jacobian
    there: the next Newton update is solved with the previous iterate's
    factors (the Jacobians differ by ``O(LAG_MAX)``, so the update by that
    much relative to itself, far below what the test ``<= tol_step``
    resolves). The point accepted is the one :func:`correct` accepts, with
    the same counts; ``R`` and ``J`` are those at the point, but ``A``,
    ``piv`` hold the factors at the previous iterate and ``rows`` their
    row scales: the tangent is then :func:`lagged_tangent`, not
    :func:`bordered_tangent`.

    Parameters
    ----------
    rows : ndarray, shape (n,)
        Output: row scales of the factors left in ``A``.
    lag : bool
        Allow the reuse.

    Returns
    -------
    status, evaluations, iterations
        As in :func:`correct`.
    lagged : bool
        True if ``A``, ``piv`` hold the factors of the previous iterate.
    """
    n = R.size
    b = np.empty(n + 1)
    y_try = np.empty(n + 1)
    factored = False
    aft = call_residual(residual_at, y, problem, R, J)
    evaluations = 1
    if aft < 0:
        return AFT_FAILED, evaluations, evaluations, False
    res = _norm_inf(R)
    last = np.inf
    last_full = False
    res_last = np.inf
    contract = applies_last_update(problem)
    for it in range(max_iter + 1):
        if not np.isfinite(res):
            return NOT_FINITE, evaluations, evaluations, False
        # the residual cannot fall below the rounding of the terms it sums
        # (a stiff FE model at resonance: terms 1e7 N, rounding 2e-9 N,
        # where tol_residual = 1e-10 |F| asked 2e-10 N and Newton ran its
        # whole budget, then periodic_solution's fallbacks for minutes)
        tol = max(tol_residual, jacobian_floor(problem, J, y), rounding_level(problem))
        g = 0.0
        for i in range(n + 1):
            g += constraint[i] * (y[i] - y_pred[i]) / scale[i]
        if factored and res <= tol and last <= LAG_MAX:
            # confirming evaluation after a tiny update: the convergence
            # tests below, the next update from the previous factors; if
            # they fail, the Newton step is solved anew
            if last <= tol_step:
                return CONVERGED, evaluations, evaluations, True
            for i in range(n):
                b[i] = -R[i] * rows[i]
            b[n] = -g
            lu_solve(A, piv, b)
            if _norm_inf(b) <= tol_step:
                return CONVERGED, evaluations, evaluations + 1, True
        # solve in scaled variables with equilibrated rows: the unknowns
        # may differ by many orders of magnitude (X in m, Ω in rad/s)
        bordered_rows(problem, J, scale, A, b)
        for i in range(n):
            rows[i] = b[i]
            b[i] = -R[i] * b[i]
        for j in range(n + 1):
            A[n, j] = constraint[j]
        b[n] = -g
        if not bordered_solve(problem, A, piv, b):
            return SINGULAR, evaluations, evaluations, False
        factored = lag and lagged_factors(problem)
        full = _norm_inf(b)
        if not np.isfinite(full):
            return SINGULAR, evaluations, evaluations, False
        for i in range(n + 1):
            b[i] *= scale[i]
        if res <= tol and last <= tol_step:
            return CONVERGED, evaluations, evaluations, False
        if res <= tol and full <= tol_step:
            return CONVERGED, evaluations, evaluations + 1, False
        if contract and last_full and full < last and res < res_last:
            # Newton contracts: after this update the error left is at most
            # theta / (1 - theta) of it and the residual at most theta times
            # the present one, theta the larger contraction of the updates
            # and of the residual over the last full step (quadratic
            # convergence leaves far less); applied without an evaluation
            theta = max(full / last, res / res_last)
            if (
                theta <= CONTRACTION_MAX
                and theta / (1.0 - theta) * full <= tol_step
                and theta * res <= tol
            ):
                for i in range(n + 1):
                    y[i] += b[i]
                return CONVERGED, evaluations, evaluations + 1, False
        if it == max_iter:
            break
        lam = 1.0
        for _ls in range(10):
            for i in range(n + 1):
                y_try[i] = y[i] + lam * b[i]
            aft = call_residual(residual_at, y_try, problem, R, J)
            evaluations += 1
            res_try = _norm_inf(R) if aft >= 0 else np.inf
            if res_try <= tol or res_try < (1.0 - 1e-4 * lam) * res:
                break
            lam *= 0.5
        if aft < 0:
            return AFT_FAILED, evaluations, evaluations, False
        for i in range(n + 1):
            y[i] = y_try[i]
        res_last = res
        res = res_try
        last = lam * full
        last_full = lam == 1.0
    return MAX_ITERATIONS, evaluations, evaluations, False


@jit
def lagged_tangent(J, scale, constraint, A, piv, rows, out):
    """Unit tangent at the point of a lagged :func:`correct_core` (``J``
    the Jacobian there, ``A``, ``piv``, ``rows`` the factors and row scales
    of the previous iterate's bordered matrix): the tangent of those
    factors, refined against ``[diag(rows) J diag(scale); constraint]``.

    Each sweep ``t += A⁻¹ (e_n - M t)`` shrinks the error by the relative
    difference of the two matrices (about the last update, at most
    :data:`LAG_MAX` times the Jacobian's variation); the sweeps stop once a
    correction is below :data:`LAG_CORRECTION` of ``t`` (the error left is
    about its square). If :data:`LAG_SWEEPS` sweeps do not get there, the
    bordered matrix at the point is factored (into ``A``, ``piv``) and the
    tangent taken from it, as :func:`tangent_from_lu`.

    Returns
    -------
    bool
        False if the result is not finite.
    """
    n = J.shape[0]
    m = n + 1
    for i in range(m):
        out[i] = 0.0
    out[n] = 1.0
    lu_solve(A, piv, out)
    r = np.empty(m)
    st = np.empty(m)
    for _ in range(LAG_SWEEPS):
        for j in range(m):
            st[j] = scale[j] * out[j]
        for i in range(n):
            a0 = 0.0
            a1 = 0.0
            j = 0
            while j + 1 < m:
                a0 += J[i, j] * st[j]
                a1 += J[i, j + 1] * st[j + 1]
                j += 2
            if j < m:
                a0 += J[i, j] * st[j]
            r[i] = -(a0 + a1) * rows[i]
        c = 0.0
        for j in range(m):
            c += constraint[j] * out[j]
        r[n] = 1.0 - c
        lu_solve(A, piv, r)
        for i in range(m):
            out[i] += r[i]
        size = _norm_inf(out)
        if not np.isfinite(size):
            return False
        if _norm_inf(r) <= LAG_CORRECTION * size:
            return _normalise(out)
    # not converged: factor the bordered matrix at the point
    equilibrate_rows(J, scale, A, r)
    for j in range(m):
        A[n, j] = constraint[j]
    if not lu_factor(A, piv):
        return False
    return tangent_from_lu(A, piv, out)


@jit
def tangent(J, previous, scale, A):
    """Unit tangent of the solution curve in scaled variables.

    Solves ``[J diag(scale); previousᵀ] t = [0; 1]`` and normalises, so that
    the new tangent keeps the direction of ``previous``. The rows of
    ``J diag(scale)`` are equilibrated first (as in :func:`correct`): their
    size follows the units of the load (N) while the last row is of order
    one, and the pivot test is relative to the largest entry.

    Parameters
    ----------
    J : ndarray, shape (n, n + 1)
        Jacobian at the point, physical units.
    previous : ndarray, shape (n + 1,)
        Previous unit tangent (scaled variables).
    scale : ndarray, shape (n + 1,)
        Variable scales.
    A : ndarray, shape (n + 1, n + 1)
        Work array.

    Returns
    -------
    ndarray, shape (n + 1,)
        The unit tangent; all NaN if the bordered matrix is singular.
    """
    n = J.shape[0]
    b = np.zeros(n + 1)
    equilibrate_rows(J, scale, A, b)
    b[:n] = 0.0
    for j in range(n + 1):
        A[n, j] = previous[j]
    b[n] = 1.0
    if not solve_inplace(A, b):
        b[:] = np.nan
        return b
    norm = np.sqrt(np.sum(b * b))
    return b / norm


@jit
def block_tangent(J, previous, scale, A, n_dof, n_coef, first, n_slip, k_max, tol, out):
    """The unit tangent of :func:`tangent` solved by GMRES on the harmonic
    blocks corrected for at most ``n_slip`` slipping coordinates
    (:func:`hbmfric.kernels.linalg.blocks.gmres_prepared`, arrays of its
    own: the corrector's kept preconditioner and counters are not
    touched), for a Jacobian on ``n_dof`` contact coordinates
    (:mod:`hbmfric.kernels.linalg.pattern`).

    Parameters
    ----------
    J, previous, scale, A
        As in :func:`tangent` (``A``: the bordered matrix on return).
    n_dof, n_coef, first : int
        Layout of the unknowns (:mod:`hbmfric.kernels.linalg.blocks`).
    n_slip : int
        Slipping coordinates corrected at most.
    k_max : int
        GMRES iterations at most.
    tol : float
        Relative residual (2-norm) of the bordered system.
    out : ndarray, shape (n + 1,)
        Output: the unit tangent in scaled variables.

    Returns
    -------
    bool
        False if a block or the bordered preconditioner is singular, GMRES
        did not converge or the result is not finite (``out`` is then
        meaningless; :func:`tangent` factors the matrix instead).
    """
    n = J.shape[0]
    m = n + 1
    b = np.zeros(m)
    equilibrate_rows(J, scale, A, b)
    for j in range(m):
        A[n, j] = previous[j]
        b[j] = 0.0
    b[n] = 1.0
    blocks, pivots, border, V, work = block_work(n_dof, n_coef, first, m, k_max)
    if not factor_blocks(A, n_dof, n_coef, first, blocks, pivots):
        return False
    correction = capacitance_work(n_dof, n_coef, first, n_slip)
    prepare_capacitance(A, n_dof, n_coef, first, blocks, pivots, correction, work)
    if not prepare_border(
        A, n_dof, n_coef, first, blocks, pivots, correction, border, work
    ):
        return False
    starts, columns, values = sparse_rows(A)
    status, _ = gmres_prepared(
        A,
        b,
        out,
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
    if status != GMRES_CONVERGED:
        return False
    return _normalise(out)


@jit
def tangent_from_lu(A, piv, out):
    """Unit tangent from the LU factors left by :func:`correct`.

    The corrector's bordered matrix ``[D J diag(scale); c]`` is, up to the
    row equilibration ``D``, the tangent system ``[J diag(scale); c]``, so
    the tangent at the corrected point costs one pair of triangular solves
    instead of a new factorisation: ``t = A⁻¹ e_n``, normalised. It
    satisfies ``c · t > 0`` (the direction of ``c`` is kept).

    Parameters
    ----------
    A, piv : ndarray
        LU factors from :func:`correct`, shapes (n + 1, n + 1), (n + 1,).
    out : ndarray, shape (n + 1,)
        Output: the unit tangent in scaled variables.

    Returns
    -------
    bool
        False if the result is not finite.
    """
    m = out.size
    for i in range(m):
        out[i] = 0.0
    out[m - 1] = 1.0
    lu_solve(A, piv, out)
    return _normalise(out)


@jit_inline
def _normalise(out):
    """Divide ``out`` by its 2-norm; False if that is not finite and
    positive (inlined: no kernel of its own on the plain path)."""
    m = out.size
    norm = 0.0
    for i in range(m):
        norm += out[i] * out[i]
    norm = np.sqrt(norm)
    if not (np.isfinite(norm) and norm > 0.0):
        return False
    for i in range(m):
        out[i] /= norm
    return True


@jit_inline
def palc_step(
    problem,
    residual_at,
    y,
    tangent_prev,
    ds,
    scale,
    tol_residual,
    tol_step,
    max_iter,
    R,
    J,
    A,
    piv,
    y_pred,
    y_new,
    t_new,
):
    """One pseudo-arclength predictor–corrector step, compiled whole.

    Predictor ``y_pred = y + ds t scale``, then :func:`palc_correct`.
    Acceptance is decided by the caller.

    Parameters
    ----------
    problem : tuple
        HBM problem (:func:`hbmfric.kernels.residuals.hbm.hbm_residual`).
    residual_at : int
        Address of its residual, as in :func:`correct`.
    y, tangent_prev : ndarray, shape (n + 1,)
        Current point (physical units) and unit tangent (scaled).
    ds : float
        Arc-length step, scaled.
    scale, tol_residual, tol_step, max_iter, R, J, A, piv
        As in :func:`correct`.
    y_pred, y_new, t_new : ndarray, shape (n + 1,)
        Outputs: predictor, corrected point, new unit tangent.

    Returns
    -------
    status, evaluations, iterations, distance, angle
        As in :func:`palc_correct`.
    """
    m = y.size
    for i in range(m):
        y_pred[i] = y[i] + ds * tangent_prev[i] * scale[i]
    return palc_correct(
        problem,
        residual_at,
        tangent_prev,
        scale,
        tol_residual,
        tol_step,
        max_iter,
        R,
        J,
        A,
        piv,
        y_pred,
        y_new,
        t_new,
    )


@jit_inline
def palc_correct(
    problem,
    residual_at,
    tangent_prev,
    scale,
    tol_residual,
    tol_step,
    max_iter,
    R,
    J,
    A,
    piv,
    y_pred,
    y_new,
    t_new,
):
    """The corrector of a pseudo-arclength step from a given predictor.

    Corrector :func:`correct_core` from ``y_pred`` on the hyperplane
    through it orthogonal to ``tangent_prev`` (confirming evaluations may
    reuse the previous iterate's factors), then the new tangent from the
    corrector's last factorisation (:func:`bordered_tangent`), or refined
    from the reused factors against the Jacobian at the point
    (:func:`lagged_tangent`), the scaled distance between predictor and
    corrected point, and the angle between the tangents.

    Parameters
    ----------
    problem : tuple
        HBM problem (:func:`hbmfric.kernels.residuals.hbm.hbm_residual`).
    residual_at : int
        Address of its residual, as in :func:`correct`.
    tangent_prev : ndarray, shape (n + 1,)
        Unit tangent at the current point (scaled).
    scale, tol_residual, tol_step, max_iter, R, J, A, piv
        As in :func:`correct`.
    y_pred : ndarray, shape (n + 1,)
        The predictor (physical units): the tangent's (:func:`palc_step`)
        or a second-order one
        (:func:`hbmfric.kernels.steps.arclength.predict`).
    y_new, t_new : ndarray, shape (n + 1,)
        Outputs: corrected point, new unit tangent.

    Returns
    -------
    status : int
        ``CONVERGED`` or a failure code.
    evaluations, iterations : int
        As in :func:`correct`.
    distance : float
        ``max |y_new - y_pred| / scale`` (inf on failure).
    angle : float
        Angle between ``tangent_prev`` and ``t_new``, rad (inf on failure).
    """
    m = y_pred.size
    for i in range(m):
        y_new[i] = y_pred[i]
    rows = np.empty(m - 1)
    status, evaluations, iterations, lagged = correct_core(
        problem,
        residual_at,
        y_new,
        y_pred,
        tangent_prev,
        scale,
        tol_residual,
        tol_step,
        max_iter,
        R,
        J,
        A,
        piv,
        rows,
        np.bool_(True),
    )
    if status != CONVERGED:
        return status, evaluations, iterations, np.inf, np.inf
    distance = 0.0
    for i in range(m):
        d = abs(y_new[i] - y_pred[i]) / scale[i]
        if not d <= distance:
            distance = d
    if lagged:
        ok = lagged_tangent(J, scale, tangent_prev, A, piv, rows, t_new)
    else:
        ok = bordered_tangent(problem, A, piv, t_new)
    if not np.isfinite(distance) or not ok:
        return NOT_FINITE, evaluations, iterations, np.inf, np.inf
    c = 0.0
    for i in range(m):
        c += t_new[i] * tangent_prev[i]
    c = min(1.0, max(-1.0, c))
    return CONVERGED, evaluations, iterations, distance, np.arccos(c)
