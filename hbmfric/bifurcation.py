"""Special points of a branch located between its points: folds (turning
points in Ω) and the stability changes that Hill's method finds (branch
points, period doublings, Neimark–Sacker bifurcations).

A traced branch knows only between which two points ``i - 1`` and ``i``
something happens: ``Branch.folds`` (the Ω component of the tangent
changes sign) and :meth:`hbmfric.stability.Stability.changes` (the largest
real part of the Floquet exponents changes sign). Here each is located by
a scalar root search along the *bordered* path between the two points:
every trial solution ``y = [X, Ω]`` solves

    R(y) = 0,    pᵀ D⁻¹ (y − y_{i−1}) = σ,

with ``p`` the unit secant from ``y_{i−1}`` to ``y_i`` in the scaled
variables ``D⁻¹ y`` (``D``: the largest coefficient of the two points for
``X``, Ω itself for Ω). Near a fold the secant is not orthogonal to the
path, so this system stays regular where the fixed-Ω one is singular.
Along it,

* a **fold** is the zero of the Ω component of the tangent ``t`` (``[J;
  pᵀD⁻¹] t = [0; 1]``): Brent's method on ``σ``;
* a **stability change** is the zero of the largest real part of the
  Floquet exponents (:func:`hbmfric.stability.floquet_exponents` at the
  trial solution): Brent's method on ``σ``. The exponent that crosses
  names it: a real one (multiplier +1) is the fold itself when a fold
  lies in the same interval, else a **branch point**; one with
  ``|Im λ| = Ω/2`` (multiplier −1) a **period doubling**; a complex pair a
  **Neimark–Sacker** bifurcation.

Every trial solution is a full Newton solve in the problem's full basis
(every DOF, harmonics ``0 … H`` of the interval's points), so the located
points carry the accuracy of the branch's discretisation, not of the
interpolation between points. For hysteretic laws the stability change is
located with the exponents of Hill's method, exact only where they cross
zero through a real exponent (:mod:`hbmfric.stability`): a branch point of
a friction branch is located exactly, a period doubling or
Neimark–Sacker crossing approximately.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.optimize

from .errors import ConvergenceWarning
from .stability import (
    _stability_problem,
    _to_full_basis,
    floquet_exponents,
)

#: kinds of special points
FOLD = "fold"
BRANCH_POINT = "branch point"
PERIOD_DOUBLING = "period doubling"
NEIMARK_SACKER = "Neimark-Sacker"

#: Newton iterations per trial solution
MAX_NEWTON = 30
#: scaled step under which a trial solution has converged
NEWTON_TOL = 1e-12
#: relative σ tolerance of the root searches
ROOT_TOL = 1e-12
#: a crossing exponent with ``|Im λ|`` below this fraction of Ω is real
REAL_TOL = 1e-6
#: points within which a change of the time-domain monodromy through a
#: real multiplier near +1 is the change of a fold that has none of its
#: own (the same reach as :data:`hbmfric.results.FOLD_SNAP`)
FOLD_REACH = 12


@dataclass
class SpecialPoint:
    """A located special point of a branch.

    Attributes
    ----------
    kind : str
        ``"fold"``, ``"branch point"``, ``"period doubling"`` or
        ``"Neimark-Sacker"``.
    index : int
        The point lies between branch points ``index - 1`` and ``index``.
    omega : float
        Ω of the located point, rad/s: the branch's own ``omega``, so on a
        branch of :func:`hbmfric.period_doubled_branch` the fundamental
        ``Ω/2`` (the forcing pulsation is ``2 * omega`` there).
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
        Harmonics of ``coefficients`` (``0 … H``; of ``Ω/2`` on a
        period-doubled branch).
    coefficients : ndarray, shape (n_dof, n_coef)
        The periodic solution there, m.
    multiplier : complex or None
        The Floquet multiplier that crosses the unit circle (None for a
        fold located without stability).
    stability_omega : float or None
        For a fold: Ω where the stability changes in the same interval
        (located independently; equal to ``omega`` up to the root
        searches' tolerance), else None.
    """

    kind: str
    index: int
    omega: float
    harmonic_numbers: np.ndarray
    coefficients: np.ndarray
    multiplier: complex | None = None
    stability_omega: float | None = None

    def amplitude(self, harmonic: int = 1, dof: int = 0) -> float:
        """Amplitude of one harmonic (``0 … H``) of one DOF, m."""
        k = int(harmonic)
        if not 0 <= k <= int(self.harmonic_numbers[-1]):
            raise ValueError(f"harmonic must be in 0..{self.harmonic_numbers[-1]}")
        if k == 0:
            return float(abs(self.coefficients[dof, 0]))
        return float(np.hypot(*self.coefficients[dof, 2 * k - 1 : 2 * k + 1]))


class _BorderedPath:
    """Solutions between two branch points, parametrised by ``σ`` along
    their scaled secant (module docstring)."""

    def __init__(self, problem, y0: np.ndarray, y1: np.ndarray) -> None:
        self.problem = problem
        n = problem.n_unknowns
        amp = max(float(np.max(np.abs(y0[:-1]))), float(np.max(np.abs(y1[:-1]))))
        amp = amp if amp > 0.0 else 1.0
        self.scale = np.full(n + 1, amp)
        # Ω relative to itself: the Ω span of two points that straddle a
        # fold is small, and scaling by it would turn the secant towards
        # Ω, where the bordered system is singular at the fold
        self.scale[-1] = max(abs(float(y0[-1])), abs(float(y1[-1])))
        d = (y1 - y0) / self.scale
        self.length = float(np.linalg.norm(d))
        self.direction = d / self.length
        self.y0 = y0
        self._last = (0.0, y0.copy())
        self.failed = False

    def solve(self, sigma: float) -> tuple[np.ndarray, np.ndarray]:
        """Solution ``y`` at ``σ`` and the Jacobian ``∂R/∂y`` there."""
        s_prev, y_prev = self._last
        # start from the last trial solution moved along the secant
        y = y_prev + (sigma - s_prev) * self.direction * self.scale
        border = self.direction / self.scale
        for _ in range(MAX_NEWTON):
            R, J, state = self.problem.residual(y)
            if state < 0:
                break
            g = float(border @ (y - self.y0)) - sigma
            A = np.vstack([J, border[None, :]])
            step = np.linalg.solve(A, -np.append(R, g))
            y = y + step
            if float(np.max(np.abs(step / self.scale))) <= NEWTON_TOL:
                R, J, state = self.problem.residual(y)
                self._last = (sigma, y.copy())
                return y, J
        self.failed = True
        raise _NotSolved(sigma)

    def tangent_omega(self, sigma: float) -> float:
        """Ω component of the unit tangent at ``σ`` (oriented with σ)."""
        y, J = self.solve(sigma)
        border = self.direction / self.scale
        A = np.vstack([J, border[None, :]])
        rhs = np.zeros(A.shape[0])
        rhs[-1] = 1.0
        t = np.linalg.solve(A, rhs) / self.scale  # scaled dy/dσ
        return float(t[-1] / np.linalg.norm(t))


class _NotSolved(RuntimeError):
    """A trial solution of the bordered path did not converge."""


def _exponents(problem, y: np.ndarray, J: np.ndarray, symmetric: bool) -> np.ndarray:
    mass, damping = problem.kernel_problem[1], problem.kernel_problem[2]
    return floquet_exponents(
        J[None, :, :-1],
        mass,
        damping,
        problem.harmonic_numbers,
        np.array([float(y[-1])]),
        symmetric,
    )[0]


def _kind(exponents: np.ndarray, omega: float) -> tuple[str, complex]:
    """Kind of crossing from the exponent with the largest real part."""
    lam = exponents[int(np.argmax(exponents.real))]
    period = 2.0 * math.pi / omega
    mult = complex(np.exp(lam * period))
    im = abs(lam.imag)
    if im <= REAL_TOL * omega:
        return BRANCH_POINT, mult
    if abs(im - 0.5 * omega) <= REAL_TOL * omega:
        return PERIOD_DOUBLING, mult
    return NEIMARK_SACKER, mult


def locate_special_points(
    system,
    force: float,
    omega: np.ndarray,
    harmonic_numbers: np.ndarray,
    coefficients: np.ndarray,
    point_harmonics: np.ndarray,
    folds: np.ndarray,
    changes: np.ndarray | None,
    *,
    n_time: int | None = None,
    aft: str = "auto",
    subharmonic: int = 1,
    symmetric: bool = False,
    stability_method: str = "hill",
) -> list[SpecialPoint]:
    """Locate the folds and stability changes of a branch.

    Parameters
    ----------
    system, force
        The system traced and its forcing amplitude, N.
    omega : ndarray, shape (n_points,)
        Ω of the branch points, rad/s.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (n_points, n_dof, n_coef)
        Coefficients of every DOF, m.
    point_harmonics : ndarray of int, shape (n_points,)
        Highest harmonic of each point; an interval is solved at the larger
        of its two points'.
    folds : ndarray of int
        Intervals (``i``: between ``i - 1`` and ``i``) with a fold.
    changes : ndarray of int or None
        Intervals with a stability change (None: stability not located).
    n_time, aft, subharmonic, symmetric
        The discretisation (as for :func:`hbmfric.stability.stability_of_points`).
    stability_method : {"hill", "monodromy"}
        How ``changes`` were found. ``"monodromy"`` (the time-domain
        monodromy decided, :attr:`hbmfric.stability.Stability.criterion`):
        a change in an interval without a fold is located on the largest
        modulus of the monodromy's multipliers (Brent's method on
        ``max |μ| - (1 + NEUTRAL_TOLERANCE)`` along the bordered path,
        each trial a full Newton solve and a monodromy), where Hill's
        exponents, which disagree with it, keep one sign; a change at a
        fold stays with Hill's exponents (exact there), and a branch point
        located within ``FOLD_REACH`` points of a fold without a change of
        its own is that fold's change (:func:`_fold_changes_on_monodromy`).

    Returns
    -------
    list of SpecialPoint
        Sorted by ``index``. An interval whose trial solutions do not
        converge is skipped with a :class:`~hbmfric.errors.ConvergenceWarning`.
    """
    folds = [int(i) for i in np.asarray(folds, dtype=np.int64)]
    change_set = set() if changes is None else {int(i) for i in np.asarray(changes)}
    found: list[SpecialPoint] = []
    problems: dict[int, object] = {}
    for i in sorted(set(folds) | change_set):
        h = int(max(point_harmonics[i - 1], point_harmonics[i]))
        if h not in problems:
            nt = n_time if n_time is not None and n_time > 2 * h else None
            problems[h] = _stability_problem(system, force, h, nt, aft, subharmonic)
        problem = problems[h]  # a refusal (rigid Coulomb) raises here
        ends = []
        for j in (i - 1, i):
            full = _to_full_basis(harmonic_numbers, coefficients[j], h)
            ends.append(np.append(full.reshape(-1), float(omega[j])))
        path = _BorderedPath(problem, ends[0], ends[1])
        on_monodromy = None
        if stability_method == "monodromy" and i not in folds:
            on_monodromy = (system, force, subharmonic)
        try:
            found.extend(
                _locate(
                    path,
                    problem,
                    i,
                    i in folds,
                    i in change_set,
                    symmetric,
                    on_monodromy,
                )
            )
        except (_NotSolved, ValueError) as exc:
            warnings.warn(
                f"special point between branch points {i - 1} and {i} "
                f"(Ω = {omega[i - 1]:.6g}-{omega[i]:.6g} rad/s) not located: "
                f"{exc.__class__.__name__} {exc}",
                ConvergenceWarning,
                stacklevel=3,
            )
    if stability_method == "monodromy":
        found = _fold_changes_on_monodromy(found)
    return found


def _fold_changes_on_monodromy(found: list[SpecialPoint]) -> list[SpecialPoint]:
    """Give a fold the stability change located on the monodromy next to it.

    The time-domain monodromy belongs to the orbit near each HBM point, so
    the change at a fold (a real multiplier through +1) can fall a few
    points past the HBM fold (the two-DOF friction Duffing at H = 15: 4
    points, 3.6e-6 rad/s). Located there it would read as a separate
    branch point. A branch point within :data:`FOLD_REACH` points of a
    fold that carries no change of its own, with no other special point
    between them, is that fold's change: the fold takes its Ω
    (``stability_omega``) and multiplier, and the branch point is dropped.
    Period doublings and Neimark–Sacker points are never merged.

    Parameters
    ----------
    found : list of SpecialPoint
        The located points, sorted by ``index``.

    Returns
    -------
    list of SpecialPoint
        The same points, merged as above, sorted by ``index``.
    """
    points = sorted(found, key=lambda p: p.index)
    drop: set[int] = set()
    for k, bp in enumerate(points):
        if bp.kind != BRANCH_POINT:
            continue
        best = None
        for j, fp in enumerate(points):
            if (
                fp.kind != FOLD
                or fp.stability_omega is not None
                or abs(fp.index - bp.index) > FOLD_REACH
            ):
                continue
            lo, hi = sorted((j, k))
            if any(points[m].kind != FOLD for m in range(lo + 1, hi)):
                continue  # another change between them
            if best is None or abs(fp.index - bp.index) < abs(
                points[best].index - bp.index
            ):
                best = j
        if best is not None:
            points[best].stability_omega = bp.omega
            points[best].multiplier = bp.multiplier
            drop.add(k)
    return [p for m, p in enumerate(points) if m not in drop]


def _locate(
    path,
    problem,
    i: int,
    fold: bool,
    change: bool,
    symmetric: bool,
    on_monodromy=None,
):
    """The special points of one interval (``on_monodromy``: ``(system,
    force, subharmonic)`` to locate the stability change on the
    time-domain monodromy)."""
    L = path.length
    hn = problem.harmonic_numbers
    n_dof = problem.n_unknowns // problem.n_coef
    out = []
    fold_point = None
    if fold:
        g0, g1 = path.tangent_omega(0.0), path.tangent_omega(L)
        if g0 * g1 > 0.0:
            raise ValueError("the Ω tangent has one sign over the interval")
        s = scipy.optimize.brentq(path.tangent_omega, 0.0, L, xtol=ROOT_TOL * L)
        y, _ = path.solve(s)
        fold_point = SpecialPoint(
            FOLD, i, float(y[-1]), hn.copy(), y[:-1].reshape(n_dof, -1).copy()
        )
        out.append(fold_point)
    if change and on_monodromy is not None:
        out.append(_locate_on_monodromy(path, problem, i, *on_monodromy))
    elif change:

        def largest_real(sigma: float) -> float:
            y, J = path.solve(sigma)
            return float(_exponents(problem, y, J, symmetric).real.max())

        r0, r1 = largest_real(0.0), largest_real(L)
        if r0 * r1 > 0.0:
            raise ValueError("the largest real part has one sign over the interval")
        s = scipy.optimize.brentq(largest_real, 0.0, L, xtol=ROOT_TOL * L)
        y, J = path.solve(s)
        kind, mult = _kind(_exponents(problem, y, J, symmetric), float(y[-1]))
        if kind == BRANCH_POINT and fold_point is not None:
            # the real exponent crosses at the fold itself
            fold_point.multiplier = mult
            fold_point.stability_omega = float(y[-1])
        else:
            out.append(
                SpecialPoint(
                    kind,
                    i,
                    float(y[-1]),
                    hn.copy(),
                    y[:-1].reshape(n_dof, -1).copy(),
                    multiplier=mult,
                )
            )
    return out


#: a crossing multiplier with ``|Im μ|`` below this (it is formed by
#: finite differences of a time integration) is real
MONODROMY_REAL_TOL = 1e-3


def _locate_on_monodromy(path, problem, i: int, system, force, subharmonic):
    """The stability change of one interval located on the time-domain
    monodromy: the root of ``max |μ| - (1 + NEUTRAL_TOLERANCE)`` (the
    monodromy's stability verdict) along the bordered path; its kind
    from the crossing multiplier (real positive: branch point, real
    negative: period doubling, else Neimark–Sacker)."""
    from .stability import NEUTRAL_TOLERANCE, monodromy_multipliers

    hn = problem.harmonic_numbers
    n_dof = problem.n_unknowns // problem.n_coef
    L = path.length

    def multipliers(sigma: float) -> np.ndarray:
        y, _ = path.solve(sigma)
        X = y[:-1].reshape(n_dof, -1)
        return monodromy_multipliers(system, force, hn, X, float(y[-1]), subharmonic)

    def excess(sigma: float) -> float:
        return float(np.abs(multipliers(sigma)).max()) - (1.0 + NEUTRAL_TOLERANCE)

    r0, r1 = excess(0.0), excess(L)
    if r0 * r1 > 0.0:
        raise ValueError(
            "the monodromy's largest |μ| has one side of 1 over the interval"
        )
    s = scipy.optimize.brentq(excess, 0.0, L, xtol=ROOT_TOL * L)
    y, _ = path.solve(s)
    mu = multipliers(s)
    crossing = complex(mu[int(np.argmax(np.abs(mu)))])
    if abs(crossing.imag) > MONODROMY_REAL_TOL:
        kind = NEIMARK_SACKER
    elif crossing.real < 0.0:
        kind = PERIOD_DOUBLING
    else:
        kind = BRANCH_POINT
    return SpecialPoint(
        kind,
        i,
        float(y[-1]),
        hn.copy(),
        y[:-1].reshape(n_dof, -1).copy(),
        multiplier=crossing,
    )


__all__ = [
    "BRANCH_POINT",
    "FOLD",
    "NEIMARK_SACKER",
    "PERIOD_DOUBLING",
    "SpecialPoint",
    "locate_special_points",
]
