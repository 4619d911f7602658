"""Branch switching at a period doubling: the branch of period ``2T`` born
there.

At a period doubling of a branch of period ``T`` a Floquet multiplier is
−1: the perturbation ``e^{iΩt/2} q(t)`` (``q`` of period ``T``) neither
grows nor decays. Written in the harmonics of ``Ω/2`` (a subharmonic
balance of order ``ν = 2``, :class:`~hbmfric.hbm.HBMProblem`), the
``T``-periodic solution has only even harmonics, that perturbation only odd
ones, and the balance's Jacobian at the embedded solution is singular with
a null vector ``φ`` in the odd harmonics: the ``2T`` problem has a
pitchfork there, one of its branches the embedded ``T`` branch, the other
the period-doubled branch (its two halves the same motion shifted by
``T``).

The switch: the embedded solution ``X*`` at the located point, ``φ`` the
right singular vector of the Jacobian's smallest singular value, then one
point of the new branch from the bordered system

    R(X, Ω) = 0,    φᵀ (X − X*) = ε,

whose Jacobian ``[∂R/∂X, ∂R/∂Ω; φᵀ, 0]`` is regular at a pitchfork, with
``ε`` a small fraction of the solution's size. Its Ω says on which side of
the bifurcation the branch lies (super- or subcritical), and an ordinary
continuation from it traces the branch. Where it returns to the ``T``
branch (at another period doubling, the projection on ``φ`` changes
sign) the trace is cut.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from ._validate import finite_float
from .continuation import Continuation, ContinuationOptions
from .continuation.palc import MAX_STEPS, RANGE_END, RANGE_START
from .errors import ConvergenceError, CoverageWarning

#: Newton iterations of the bordered solve
MAX_NEWTON = 40
#: smallest-to-next singular value ratio under which the Jacobian at the
#: embedded solution counts as singular (a located period doubling)
SINGULAR_RATIO = 1e-3


def period_doubled_branch(
    branch,
    point,
    omega_range: tuple[float, float] | None = None,
    *,
    system=None,
    harmonics: int | None = None,
    offset: float = 1e-2,
    options: ContinuationOptions | None = None,
) -> object:
    """The branch of period ``2T`` born at a period doubling of ``branch``.

    Parameters
    ----------
    branch : Branch
        A branch of period ``T`` (``hf.frf``), with the system it was
        traced for (or give ``system``).
    point : SpecialPoint
        A ``"period doubling"`` of ``branch.special_points()``.
    omega_range : (float, float), optional
        Range of the forcing pulsation Ω (rad/s) to trace the new branch
        over; default: the range ``branch`` was asked for.
    system : optional
        The system, if ``branch`` does not record it (a loaded branch).
    harmonics : int, optional
        Highest harmonic of ``Ω/2`` of the new branch; default ``2H + 1``
        for the point's ``H`` (every harmonic of the ``T`` solution, and
        the odd ones between).
    offset : float
        Size of the first point's subharmonic part, relative to the
        largest coefficient of the solution at the bifurcation (in
        ``(0, 0.5]``).
    options : ContinuationOptions, optional
        Continuation settings of the trace (its ``max_steps`` bounds it).

    Returns
    -------
    Branch
        ``omega`` is the fundamental ``Ω/2`` of the new branch's points
        (rad/s; the forcing pulsation is ``2 * omega``),
        ``harmonic_numbers`` are harmonics of it; ``info["subharmonic"]``
        is 2 and ``info["born_at"]`` the forcing Ω of the period doubling.
        ``omega_range`` (and so ``coverage``, ``gaps``) is in the units of
        ``omega``, half the forcing range asked for (that one is
        ``info["forcing_omega_range"]``); ``plot()`` draws against the
        forcing Ω. ``stability()`` works as for any branch.

    Raises
    ------
    ValueError
        When ``point`` is not a period doubling, or the Jacobian at the
        embedded solution is not singular (the point is not a period
        doubling of this system at these harmonics).
    ConvergenceError
        When no point of the new branch is found next to the bifurcation.
    """
    from .api import _branch, _branch_tangents, _describe, _problem

    # the special points load scipy.optimize: imported on use
    from .bifurcation import PERIOD_DOUBLING, SpecialPoint
    from .results import _stability_source

    if not isinstance(point, SpecialPoint) or point.kind != PERIOD_DOUBLING:
        raise ValueError(
            "point must be a 'period doubling' of branch.special_points(), got "
            f"{getattr(point, 'kind', type(point).__name__)!r}"
        )
    offset = finite_float("offset", offset, low=0.0, low_open=True, high=0.5)
    if not isinstance(options, ContinuationOptions | None):
        raise TypeError(
            f"options must be a ContinuationOptions, got {type(options).__name__}"
        )
    options = options or ContinuationOptions()
    src = _stability_source(branch._source, system)
    if system is not None:
        branch._check_system(system)
    system = src["system"]
    if int(branch.info.get("subharmonic", 1)) != 1:
        raise ValueError("branch is already a subharmonic branch")
    h_point = int(point.harmonic_numbers[-1])
    if harmonics is None:
        harmonics = 2 * h_point + 1
    if not isinstance(harmonics, int | np.integer) or harmonics < 2 * h_point:
        raise ValueError(
            f"harmonics must be an integer >= 2H = {2 * h_point}, got {harmonics!r}"
        )
    lo, hi = omega_range if omega_range is not None else branch.info["omega_range"]
    lo = finite_float("omega_range", lo, low=0.0, low_open=True)
    hi = finite_float("omega_range", hi, low=lo, low_open=True)
    if not lo < point.omega < hi:
        raise ValueError(
            f"omega_range ({lo:g}, {hi:g}) must contain the period doubling at "
            f"{point.omega:g} rad/s"
        )
    problem = _problem(
        system,
        branch.force,
        int(harmonics),
        None,
        False,
        branch.info.get("aft", "auto"),
        None,
        2,
    )
    n = problem.n_unknowns
    y_star = np.append(_embedded(problem, point), 0.5 * point.omega)
    _, J, status = problem.residual(y_star)
    if status < 0:
        raise ConvergenceError(f"the AFT failed at the period doubling (code {status})")
    _, singular, vt = np.linalg.svd(J[:, :n])
    if not singular[-1] <= SINGULAR_RATIO * singular[-2]:
        raise ValueError(
            f"the Jacobian of the period-2T balance at the point is not singular "
            f"(smallest singular values {singular[-1]:.3e}, {singular[-2]:.3e}): "
            "not a period doubling at these harmonics"
        )
    phi = vt[-1]
    size = max(float(np.max(np.abs(y_star[:n]))), 1e-300)
    first = _bordered_point(problem, y_star, phi, offset * size)
    # trace away from the bifurcation
    direction = 1 if first[-1] > y_star[-1] else -1
    bounds = (0.5 * lo, 0.5 * hi)
    state, points, tangents, returned, base_scale = _trace(
        problem, bounds, direction, options, first, phi, y_star
    )
    info = _describe(
        system,
        problem,
        {
            # the range of the branch's own ``omega`` (the fundamental Ω/2),
            # as every subharmonic branch records it: coverage, gaps and the
            # arc-length metric of the tangents read it against ``omega``
            "omega_range": list(bounds),
            "forcing_omega_range": [lo, hi],
            "sweep": "up" if direction > 0 else "down",
            "amplitude_scale": base_scale,
            "subharmonic": 2,
            "born_at": float(point.omega),
        },
    )
    result = _branch(
        system,
        problem,
        state,
        state.elapsed,
        points[:, n].copy(),
        problem.full_coefficients(points),
        info,
        truncation_error=None,
        tangents=_branch_tangents(
            problem,
            points,
            tangents,
            base_scale,
            bounds[1] - bounds[0],
        ),
    )
    if not returned and state.stop_reason not in (RANGE_END, RANGE_START):
        warnings.warn(
            f"the period-doubled branch from {point.omega:.6g} rad/s stopped "
            f"early: {state.stop_reason}",
            CoverageWarning,
            stacklevel=2,
        )
    return result


def _embedded(problem, point) -> np.ndarray:
    """The unknowns of ``problem`` (harmonics of Ω/2) holding the ``T``
    solution of ``point`` on the even harmonics."""
    X = np.zeros((problem.n_dof, problem.n_coef))
    columns = {}
    col = 0
    for k in problem.harmonic_numbers:
        columns[int(k)] = col
        col += 1 if k == 0 else 2
    src = 0
    for k in point.harmonic_numbers:
        k = int(k)
        width = 1 if k == 0 else 2
        if 2 * k in columns:
            dst = columns[2 * k]
            X[:, dst : dst + width] = point.coefficients[:, src : src + width]
        src += width
    return problem.unknowns_from_full(X)


def _bordered_point(problem, y_star, phi, epsilon) -> np.ndarray:
    """Newton on ``R(y) = 0``, ``φᵀ (X − X*) = ε`` from ``X* + ε φ``."""
    n = problem.n_unknowns
    y = y_star.copy()
    y[:n] += epsilon * phi
    scale = max(float(np.max(np.abs(y[:n]))), 1e-300)
    A = np.zeros((n + 1, n + 1))
    rhs = np.zeros(n + 1)
    for _ in range(MAX_NEWTON):
        R, J, status = problem.residual(y)
        if status < 0:
            break
        A[:n] = J
        A[n, :n] = phi
        A[n, n] = 0.0
        rhs[:n] = R
        rhs[n] = phi @ (y[:n] - y_star[:n]) - epsilon
        try:
            dy = np.linalg.solve(A, rhs)
        except np.linalg.LinAlgError:
            break
        y -= dy
        if np.max(np.abs(dy[:n])) <= 1e-12 * scale and abs(dy[n]) <= 1e-12 * abs(y[n]):
            R, _, status = problem.residual(y)
            if status >= 0 and np.all(np.isfinite(y)):
                return y
            break
    raise ConvergenceError(
        "no point of the period-doubled branch found next to the bifurcation "
        "(bordered Newton did not converge); try a smaller offset"
    )


#: continuation steps per piece of the trace, between checks for the return
#: to the period-T branch
PIECE_STEPS = 100


@dataclasses.dataclass
class _Trace:
    """What :func:`hbmfric.api._branch` reads of a continuation state."""

    folds: list
    stop_reason: str
    n_steps: int = 0
    n_rejected: int = 0
    n_newton: int = 0
    n_bridges: int = 0
    elapsed: float = 0.0


def _trace(problem, bounds, direction, options, first, phi, y_star):
    """Continuation from ``first`` in pieces of ``PIECE_STEPS`` steps, up to
    the return to the ``T`` branch (the projection on ``φ`` changes sign:
    past it the path runs through the same motion shifted by ``T``), the
    range's end or ``options.max_steps`` in all.

    Returns ``(trace, points, tangents, returned, amplitude_scale)``."""
    n = problem.n_unknowns
    sign = np.sign(phi @ (first[:n] - y_star[:n]))
    total = _Trace(folds=[], stop_reason="")
    points, tangents = [], []
    start, omega0, base_scale = first[:n], float(first[-1]), None
    returned = False
    while True:
        budget = options.max_steps - (total.n_steps + total.n_rejected)
        piece = dataclasses.replace(options, max_steps=max(1, min(PIECE_STEPS, budget)))
        cont = Continuation(problem, bounds, direction, piece, base_scale)
        state, elapsed = cont.run(start, start_omega=omega0)
        base_scale = cont.base_scale
        total.elapsed += elapsed
        total.n_steps += state.n_steps
        total.n_rejected += state.n_rejected
        total.n_newton += state.n_newton
        total.n_bridges += state.n_bridges
        p = np.array(state.points).reshape(-1, n + 1)
        t = np.array(state.tangents).reshape(-1, n + 1)
        skip = 1 if points else 0  # a piece starts on the last point
        offset = sum(len(q) for q in points) - skip
        projection = (p[:, :n] - y_star[:n]) @ phi
        cut = np.flatnonzero(np.sign(projection[skip:]) != sign)
        end = p.shape[0] if cut.size == 0 else skip + int(cut[0])
        points.append(p[skip:end])
        tangents.append(t[skip:end])
        total.folds += [offset + f for f in state.folds if skip <= f < end]
        total.stop_reason = state.stop_reason
        if cut.size:
            returned = True
            total.stop_reason = (
                "returned to the period-T branch (another period doubling)"
            )
            break
        if state.stop_reason != MAX_STEPS or budget <= PIECE_STEPS:
            break
        start, omega0 = p[-1, :n], float(p[-1, n])
        direction = 1 if t[-1, n] >= 0.0 else -1
    return (
        total,
        np.concatenate(points),
        np.concatenate(tangents),
        returned,
        base_scale,
    )
