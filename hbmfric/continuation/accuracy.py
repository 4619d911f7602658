"""Truncation-error estimate of every point of a fixed-``H`` branch.

A branch traced with a fixed highest harmonic ``H`` carries, per point, the
same estimate the adaptive-harmonics run keeps below its tolerance
(:mod:`hbmfric.continuation.adaptive`): the relative error of the
first-harmonic amplitude and of half the peak-to-peak value of the watched
output (the contact DOF's displacement, or the system's ``output_weights``),

    ``CHANGE_FACTOR * change``

where ``change`` is the first-order change of those two measures when the
basis grows to the probe level (:func:`~hbmfric.continuation.adaptive.probe_level`,
about ``2 H``; :func:`hbmfric.kernels.steps.truncation.truncation_change`, one
residual and one LU in the larger basis) and ``m`` the free measure
``H max(|X_H|, (K'/H)^4 |X_K'|) / |X_1|`` of the point.

Cost. ``change`` is computed at every ``EVERY``-th point whose response is
not linear, at the first and last of each stretch of consecutive branch
points (an adaptive run's level is used on several separate stretches)
and at the ``N_WORST`` points of largest free measure (one compiled call
for all of them); between them the estimate is the free measure times the
larger of the ratios ``estimate / m`` at the two neighbouring calibrated
points of the same stretch (at least ``CARRY_FLOOR``; the ratio drifts
slowly along a branch; the free measure alone does not, see
:mod:`hbmfric.continuation.adaptive`). With a ``tolerance``, every point
whose carried estimate exceeds it is calibrated too (until ``MAX_CONFIRMED``
of them exceed it: the branch then misses it for sure), so that no warning
rests on a carried estimate alone. The whole rule runs in one compiled call
(:func:`hbmfric.kernels.steps.truncation.branch_truncation`). A
point whose response is linear (stuck contact: no higher harmonic) has
estimate 0. The problem's own level and its probe level (problem, work
arrays) are built once per problem.
"""

from __future__ import annotations

import numpy as np

from ..kernels.steps.truncation import MAX_CONFIRMED, branch_truncation
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


def truncation_errors(
    problem,
    points: np.ndarray,
    tolerance: float | None = None,
    stretch: np.ndarray | None = None,
    max_confirmed: int = MAX_CONFIRMED,
    known: np.ndarray | None = None,
    every: int | None = None,
    probe=None,
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
    stretch : ndarray of int, shape (n_points,), optional
        Label of the stretch of consecutive branch points each point lies
        on (non-decreasing; default: one stretch). Ratios are carried only
        within a stretch, whose first and last points are calibrated: the
        points of one level of an adaptive run come from separate parts of
        the branch.
    max_confirmed : int, default ``MAX_CONFIRMED``
        Calibrations of carried estimates that exceed ``tolerance`` after
        which the rest keep their carried value (a bound on the cost of a
        branch far above it; the final pass of an adaptive run gives the
        number of points: every point it would solve again is calibrated).
    known : ndarray, shape (n_points,), optional
        Estimates the adaptive run calibrated at these points (same level
        and probe level), NaN elsewhere: used as they are (each counts as
        a calibrated point; no second calibration).
    every : int, optional
        Calibrate every ``every``-th non-linear point of each stretch
        (default ``EVERY``; the final pass of an adaptive run, whose own
        calibrations are at most ``RECALIBRATE`` points apart, gives more).
    probe : optional
        The probe level to calibrate with, as the adaptive run built it
        (:class:`~hbmfric.continuation.adaptive._Level`; its ``known``
        estimates come from it); default: built once per problem at
        :func:`~hbmfric.continuation.adaptive.probe_level`.

    Returns
    -------
    ndarray, shape (n_points,)
        Estimated relative error of the first-harmonic amplitude and of half
        the peak-to-peak value of the watched output (the contact DOF by
        default; dimensionless); 0 for a linear (stuck) point; inf where
        the estimate could not be formed (``H = 1``, or a failed evaluation
        in the larger basis).
    """
    points = np.asarray(points, dtype=np.float64)
    n_points = points.shape[0]
    errors = np.zeros(n_points)
    if n_points == 0:
        return errors
    cached = getattr(problem, "_accuracy_levels", None)
    if cached is None:
        cached = problem._accuracy_levels = _levels(problem, probe is None)
    level, own, columns, weights = cached
    if probe is None:
        if own is None and columns is not None:
            own = _levels(problem, True)[1]
            problem._accuracy_levels = (level, own, columns, weights)
        probe = own
    if probe is None or columns is None:
        errors[:] = np.inf
        return errors
    kp, residual_at, synthesis, output, rates, y, R, J, A, dX = probe.work()
    if stretch is None:
        stretch = np.zeros(n_points, dtype=np.int64)
    else:
        stretch = np.ascontiguousarray(stretch, dtype=np.int64)
        if stretch.shape != (n_points,) or np.any(np.diff(stretch) < 0):
            raise ValueError(
                f"stretch must be a non-decreasing label per point, shape ({n_points},)"
            )
    if known is None:
        known = np.full(n_points, np.nan)
    else:
        known = np.ascontiguousarray(known, dtype=np.float64)
        if known.shape != (n_points,):
            raise ValueError(f"known must have shape ({n_points},)")
    branch_truncation(
        points,
        known,
        stretch,
        columns,
        weights,
        EVERY if every is None else max(1, int(every)),
        N_WORST,
        np.inf if tolerance is None else float(tolerance),
        int(max_confirmed),
        kp,
        residual_at,
        output,
        rates,
        probe.first_column,
        synthesis,
        y,
        R,
        J,
        A,
        dX,
        errors,
    )
    return errors


def _levels(problem, with_probe: bool = True) -> tuple:
    """The problem's own level, its probe level (None for ``H = 1`` or
    when not ``with_probe``) and the column and weight arguments of
    :func:`~hbmfric.kernels.steps.truncation.branch_truncation` (None for
    ``H = 1``)."""
    level = _Level(problem, None)
    if not level.top:
        return level, None, None, None
    probe = None
    if with_probe:
        probe = _Level(problem.with_harmonics(probe_level(level.h)), None)
    columns = np.array(level.columns, dtype=np.int64)
    weights = np.array(
        [level.h, level.prev_weight, LINEAR * 1e-4, CHANGE_FACTOR, CARRY_FLOOR]
    )
    return level, probe, columns, weights


__all__ = ["truncation_errors", "next_level"]
