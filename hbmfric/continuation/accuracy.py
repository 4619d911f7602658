"""Truncation-error estimate of every point of a fixed-``H`` branch.

A branch traced with a fixed highest harmonic ``H`` carries, per point, the
same estimate the adaptive-harmonics run keeps below its tolerance
(:mod:`hbmfric.continuation.adaptive`): the relative error of the
first-harmonic amplitude and of half the peak-to-peak value at the contact
DOF,

    ``CHANGE_FACTOR * change``

where ``change`` is the first-order change of those two measures when the
basis grows to the probe level (:func:`~hbmfric.continuation.adaptive.probe_level`,
about ``2 H``; :func:`hbmfric.kernels.truncation.truncation_change`, one
residual and one LU in the larger basis) and ``m`` the free measure
``H max(|X_H|, (K'/H)^4 |X_K'|) / |X_1|`` of the point.

Cost. ``change`` is computed at every ``EVERY``-th point whose response is
not linear and at the ``N_WORST`` points of largest free measure (one
compiled call for all of them); between them the estimate is the free
measure times the larger of the ratios ``estimate / m`` at the two
neighbouring calibrated points, at least ``CARRY_FLOOR`` (the ratio drifts
slowly along a branch; the free measure alone does not, see
:mod:`hbmfric.continuation.adaptive`). With a ``tolerance``, every point
whose carried estimate exceeds it is calibrated too, so that no warning
rests on a carried estimate. A
point whose response is linear (stuck contact: no higher harmonic) has
estimate 0. The problem's own level and its probe level (problem, work
arrays) are built once per problem.
"""

from __future__ import annotations

import numpy as np

from ..kernels.truncation import truncation_changes
from .adaptive import (
    CARRY_FLOOR,
    CHANGE_FACTOR,
    LINEAR,
    _Level,
    next_level,
    probe_level,
)

#: calibrate the free measure at every this many non-linear points
EVERY = 32
#: ... and at this many points of largest free measure
N_WORST = 2


def _free_measure(level: _Level, points: np.ndarray) -> np.ndarray:
    """:meth:`_Level.measure` of every point at once, shape (n_points,)."""

    def largest(columns: list[int]) -> np.ndarray:
        if not columns:
            return np.zeros(points.shape[0])
        cols = np.array(columns)
        return np.hypot(points[:, cols], points[:, cols + 1]).max(axis=1)

    a1 = largest(level.first)
    top = np.maximum(largest(level.top), level.prev_weight * largest(level.prev))
    with np.errstate(divide="ignore", invalid="ignore"):
        measure = level.h * top / a1
    measure[a1 == 0.0] = np.where(top[a1 == 0.0] == 0.0, 0.0, np.inf)
    return measure


def truncation_errors(
    problem, points: np.ndarray, tolerance: float | None = None
) -> np.ndarray:
    """Estimated relative truncation error of each point of a branch.

    Parameters
    ----------
    problem : HBMProblem or CondensedHBMProblem
        The discretisation the points solve.
    points : ndarray, shape (n_points, n_unknowns + 1)
        ``[X, Ω]`` per point, in the layout of ``problem``.
    tolerance : float, optional
        Points whose carried estimate exceeds it are calibrated as well.

    Returns
    -------
    ndarray, shape (n_points,)
        Estimated relative error of the first-harmonic amplitude and of half
        the peak-to-peak value at the contact DOF (dimensionless); 0 for a
        linear (stuck) point; inf where the estimate could not be formed
        (``H = 1``, or a failed evaluation in the larger basis).
    """
    points = np.asarray(points, dtype=np.float64)
    n_points = points.shape[0]
    errors = np.zeros(n_points)
    if n_points == 0:
        return errors
    cached = getattr(problem, "_accuracy_levels", None)
    if cached is None:
        level = _Level(problem, None)
        probe = None
        if level.top:
            probe = _Level(problem.with_harmonics(probe_level(level.h)), None)
        cached = problem._accuracy_levels = (level, probe)
    level, probe = cached
    if probe is None:
        errors[:] = np.inf
        return errors
    measure = _free_measure(level, points)
    nonlinear = np.flatnonzero(measure > LINEAR * 1e-4)
    if nonlinear.size == 0:
        return errors
    chosen = np.zeros(n_points, dtype=bool)
    chosen[nonlinear[::EVERY]] = True
    chosen[nonlinear[-1]] = True
    worst = nonlinear[np.argsort(measure[nonlinear])[-N_WORST:]]
    chosen[worst] = True
    calibrated = np.flatnonzero(chosen)
    estimate = _calibrated(probe, points, calibrated)
    errors[calibrated] = estimate
    ratio = np.maximum(estimate / measure[calibrated], CARRY_FLOOR)
    others = nonlinear[~chosen[nonlinear]]
    if others.size:
        right = np.searchsorted(calibrated, others)
        left = np.clip(right - 1, 0, calibrated.size - 1)
        right = np.clip(right, 0, calibrated.size - 1)
        errors[others] = np.maximum(ratio[left], ratio[right]) * measure[others]
        if tolerance is not None:
            over = others[errors[others] > tolerance]
            if over.size:
                errors[over] = _calibrated(probe, points, over)
    return errors


def _calibrated(probe: _Level, points: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``CHANGE_FACTOR`` times the first-order change to ``probe`` of the
    points ``rows`` (one compiled call)."""
    change = np.empty(rows.size)
    kp, synthesis, y, R, J, A, dX = probe.work()
    truncation_changes(
        points,
        rows,
        kp,
        probe.n_dof,
        probe.dof,
        probe.first_column,
        synthesis,
        y,
        R,
        J,
        A,
        dX,
        change,
    )
    return CHANGE_FACTOR * change


__all__ = ["truncation_errors", "next_level"]
