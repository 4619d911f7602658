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

import copy
import weakref

import numpy as np

from ..kernels.steps.newton import CONVERGED, rounding_floor
from ..kernels.steps.truncation import (
    MAX_CONFIRMED,
    branch_truncation,
)
from ..results import CURVE_REST
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
    amplitude_scale: float | None = None,
    output: np.ndarray | None = None,
    level=None,
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
    amplitude_scale : float, optional
        Displacement scale of the branch, m (the continuation's
        ``base_scale``). With it the estimates are relative to at least
        ``CURVE_REST`` times the output's scale (an output nearly at rest:
        a stuck rigid tip's round-off amplitude of 1e-20 m is no measure;
        the rule of :attr:`hbmfric.Branch.curve_errors`), and a point whose
        first-order change exceeds ``CONFIRM_ABOVE`` times that measure is
        solved at the probe level, and its estimate is the change to that
        solution (:func:`_confirm`).
    output : ndarray, shape (2, n_dof), optional
        Weights ``(a, b)`` of another output to measure (``Σ a_d x_d +
        b_d ẋ_d``; a full problem only) instead of the problem's watched
        one: :func:`watched_truncation_errors` measures the normal DOF of
        a 2D element with it. Not with ``known``; calibrated on ``probe``
        (or the problem's own probe level) with its work arrays.
    level : optional
        The problem's own level as the adaptive run built it
        (:class:`~hbmfric.continuation.adaptive._Level` of ``problem``;
        ignored for another problem or with ``output``): its columns and
        output are read instead of a level built again.

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
    if output is not None:
        if known is not None:
            raise ValueError("output cannot be given with known")
        output = np.ascontiguousarray(output, dtype=np.float64)
        by_output = _own_cache(problem)["by_output"]
        key = output.tobytes()
        if key not in by_output:
            # no probe level of its own: it borrows the watched output's
            by_output[key] = _levels(problem, False, output)
        level, _, columns, weights = by_output[key]
        if columns is not None:
            probe = _output_probe(
                _own_probe(problem) if probe is None else probe, output
            )
    else:
        cache = _own_cache(problem)
        if cache["watched"] is None:
            own_level = level if getattr(level, "problem", None) is problem else None
            cache["watched"] = _levels(problem, probe is None, level=own_level)
        if probe is None:
            probe = _own_probe(problem)
        level, _, columns, weights = cache["watched"]
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
    if amplitude_scale is not None and np.isfinite(amplitude_scale):
        errors = _confirm(
            problem, level, probe, points, errors, amplitude_scale, output
        )
    return errors


def _own_probe(problem):
    """The probe level of ``problem``'s own estimates (None for ``H = 1``),
    built once and kept in :func:`_own_cache`."""
    cache = _own_cache(problem)
    if cache["watched"] is None:
        cache["watched"] = _levels(problem, True)
    level, own, columns, weights = cache["watched"]
    if own is None and columns is not None:
        own = _levels(problem, True)[1]
        cache["watched"] = (level, own, columns, weights)
    return own


def _output_probe(probe, output: np.ndarray):
    """``probe`` measuring another ``output``: the same problem and the same
    work arrays (order ``n`` of the probe level: its residual's Jacobian
    and the factored copy), only the output weights differ.

    Each output had a probe level of its own before stop 34 (its own
    problem and work arrays), all kept in the problem's cache: a full
    problem with ``e`` 2D elements held ``2 (e + 1)`` dense matrices of
    the probe level's order where the memory guard
    (:mod:`hbmfric._memory`) plans 2. A 60-DOF chain at ``H = 15`` with
    four elements peaked 1.17 GB above its start where the guard planned
    0.34 GB (eight: 2.0 GB), bench/README.md "Issue 15, stop 34"."""
    if probe is None:
        return None
    view = copy.copy(probe)
    view.output = output
    work = probe.work()
    view._work = work[:3] + (output,) + work[4:]
    return view


def _own_cache(problem) -> dict:
    """The levels :func:`truncation_errors` built for ``problem``
    (``"watched"``: the watched output's ``_levels`` tuple or None;
    ``"by_output"``: output weights' bytes -> ``_levels`` tuple), built
    once per problem and kept in its ``__dict__``.

    The cache names its owner (a weak reference): ``with_harmonics``
    makes a level by a shallow copy of a problem, whose ``__dict__``
    then carried the original's levels, and the copy measured its points
    with another level's columns and probe. Stop 31: the auto ``frf`` of
    the 2D-contact rig loaded normally (110-140 rad/s) read 2.0e-3 at
    H = 63 (128.1 rad/s, the warning's worst) where each point's own
    estimate is at most 1.2e-4, and 6.7e-5 at H = 21 where its own is
    9.0e-4 (the H = 7 level's, bench/README.md "Issue trust hunt, stop
    31b")."""
    cache = problem.__dict__.get("_accuracy_cache")
    if cache is None or cache["owner"]() is not problem:
        cache = {"owner": weakref.ref(problem), "watched": None, "by_output": {}}
        problem.__dict__["_accuracy_cache"] = cache
    return cache


def normal_outputs(problem, dofs: bool = False) -> list[np.ndarray]:
    """Output weights of the normal relative displacement of each 2D
    element (:class:`~hbmfric.Contact2D`): shape (2, n_dof) for a full
    problem; for one condensed onto contact coordinates shape (2, n_c), the
    element's normal coordinate (the unknowns' own layout), or with
    ``dofs`` shape (2, n_dof), on the recovered DOFs; empty for a problem
    without one."""
    from ..laws import Contact2D

    if getattr(problem, "condensed", False) and not dofs:
        if not getattr(problem, "multi", False):
            return []
        from ..condensation import coordinate_rows

        out = []
        for a, (_c, direction, _i, _j) in enumerate(coordinate_rows(problem._contacts)):
            if direction == 1:
                w = np.zeros((2, problem.n_coordinates))
                w[0, a] = 1.0
                out.append(w)
        return out
    out = []
    for law, _a, _b, a_n, b_n in getattr(problem, "_contacts", ()):
        if isinstance(law, Contact2D) and a_n >= 0:
            w = np.zeros((2, problem.n_dof))
            w[0, a_n] = 1.0
            if b_n >= 0:
                w[0, b_n] = -1.0
            out.append(w)
    return out


def watched_truncation_errors(
    problem,
    points: np.ndarray,
    tolerance: float | None = None,
    stretch: np.ndarray | None = None,
    max_confirmed: int = MAX_CONFIRMED,
    known: np.ndarray | None = None,
    every: int | None = None,
    probe=None,
    amplitude_scale: float | None = None,
    level=None,
) -> np.ndarray:
    """:func:`truncation_errors` of the watched output and, for a problem
    with 2D elements, the larger of it and the estimate of each element's
    normal displacement (the same arguments; ``known`` is the watched
    output's and serves it alone, and so does ``level``; every output is
    calibrated on the same probe level, ``probe`` or the problem's own, with
    the same work arrays: :func:`_output_probe`).

    The normal force of a 2D element has a kink where the contact opens
    and closes, so the normal DOF's harmonics decay slowly while the
    watched (tangential) DOF may be at rest or nearly linear. Stop 31: the
    2-DOF rig of ``tests/test_contact2d.py`` loaded normally only
    (``Fx = 0``), ``H = 7``, 126 rad/s: the normal DOF's first harmonic
    8.2e-4 off ``H = 63``, with no warning (the tangential DOF at rest).
    """
    errors = truncation_errors(
        problem,
        points,
        tolerance,
        stretch,
        max_confirmed,
        known,
        every,
        probe,
        amplitude_scale=amplitude_scale,
        level=level,
    )
    for w in normal_outputs(problem):
        normal = truncation_errors(
            problem,
            points,
            tolerance,
            stretch,
            max_confirmed,
            None,
            every,
            probe,
            amplitude_scale=amplitude_scale,
            output=w,
        )
        errors = np.fmax(errors, normal)
    return errors


#: an estimate whose first-order change (``estimate / CHANGE_FACTOR``) is
#: more than this fraction of the measure it is relative to is checked by
#: a solve at the probe level: a first-order step that large is outside
#: its model (the rigid Coulomb tip of the paper beam at f_s = 2 N: 8.9e3
#: estimated at 77.26 Hz, the tip just short of sticking, where its change
#: to H = 63 is 0.21; 1.7 at 85.6 Hz swept up against 3.7e-3)
CONFIRM_ABOVE = 0.1
#: probe-level solves per branch at most (largest estimates first, in
#: rounds of ``BATCH``, until the largest estimate is a confirmed one). On
#: the f_s = 2 N beam (974 points, 967 above the tolerance) 32 solves cost
#: 2.0 s of CPU and leave a largest (first-order) estimate of 1.38, 128
#: cost 3.4 s for 0.63 (the largest confirmed); the branch itself 3.4 s
MAX_CONFIRM = 32
BATCH = 32


def _output_series(level, points: np.ndarray) -> np.ndarray:
    """Fourier coefficients of the watched output of ``level`` at ``points``
    (its layout), shape (n_points, n_coef): the sums of
    :func:`~hbmfric.kernels.steps.truncation.output_coefficients`, in its
    order, for all points at once."""
    n_coef = level.n_coef
    w = level.output
    first = level.first_column
    n_points = points.shape[0]
    X = points[:, :-1].reshape(n_points, -1, n_coef)
    omega = points[:, -1:]
    cos, sin = slice(first, n_coef - 1, 2), slice(first + 1, n_coef, 2)
    rates = level.rates[cos]
    z = np.zeros((n_points, n_coef))
    for d in np.flatnonzero((w[0] != 0.0) | (w[1] != 0.0)):
        if w[0, d] != 0.0:
            z += w[0, d] * X[:, d, :]
        if w[1, d] != 0.0:
            # (c, s) of harmonic h differentiates to h Ω (s, −c)
            rate = w[1, d] * rates * omega
            z[:, cos] += rate * X[:, d, sin]
            z[:, sin] -= rate * X[:, d, cos]
    return z


def _output_first(level, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The first-harmonic columns ``(cos, sin)`` of :func:`_output_series`
    (each shape (n_points,)), by the same sums in the same order (the same
    values bit for bit) without the other columns."""
    n_coef = level.n_coef
    w = level.output
    first = level.first_column
    n_points = points.shape[0]
    X = points[:, :-1].reshape(n_points, -1, n_coef)
    zc = np.zeros(n_points)
    zs = np.zeros(n_points)
    rates = level.rates[first : first + 1]
    for d in np.flatnonzero((w[0] != 0.0) | (w[1] != 0.0)):
        if w[0, d] != 0.0:
            zc += w[0, d] * X[:, d, first]
            zs += w[0, d] * X[:, d, first + 1]
        if w[1, d] != 0.0:
            rate = (w[1, d] * rates * points[:, -1:])[:, 0]
            zc += rate * X[:, d, first + 1]
            zs -= rate * X[:, d, first]
    return zc, zs


def _rest_floor(level, n_points: int, rest_scale: float) -> np.ndarray:
    """The rest floor of the watched output of ``level`` (``CURVE_REST``
    times the output's scale: the displacement scale ``rest_scale`` for an
    output that reads one DOF, 0 for one that weighs several DOFs or
    velocities), shape (n_points,)."""
    w = level.output
    if np.count_nonzero(w[0]) != 1 or np.any(w[1] != 0.0):
        # an output that weighs several DOFs (the belt tension k (u1 - u2)
        # of the tensioner) has no scale of its own in the displacement
        # scale: the DOFs move together where it is small, and a floor of
        # 0.136 N (from the weights) against tensions of 0.02 N left
        # the point at 91.1 Hz at H = 3, 1.7e-4 off the shooting reference
        # with an estimate of 5.4e-5 (bench/README.md "stop 30"): measured
        # relative to itself
        return np.zeros(n_points)
    return np.full(n_points, CURVE_REST * rest_scale * np.sum(np.abs(w[0])))


def _output_measures(level, points: np.ndarray, rest_scale: float):
    """First-harmonic amplitude, half the peak-to-peak value and the rest
    floor (:func:`_rest_floor`) of the watched output of ``level`` at
    ``points`` (its layout), each shape (n_points,)."""
    from ..signals import half_peak_to_peak

    z = _output_series(level, points)
    first = level.first_column
    a1 = np.hypot(z[:, first], z[:, first + 1])
    hpp = half_peak_to_peak(level.problem.harmonic_numbers, z)
    return a1, hpp, _rest_floor(level, points.shape[0], rest_scale)


def _confirm(problem, level, probe, points, errors, amplitude_scale, output=None):
    """The estimates relative to the rest floor, with the implausible ones
    replaced by the change to a solve at the probe level (module doc of
    :func:`truncation_errors`, ``amplitude_scale``)."""
    from ..signals import half_peak_to_peak

    c, s = _output_first(level, points)
    a1 = np.hypot(c, s)
    rest = _rest_floor(level, points.shape[0], amplitude_scale)
    near_rest = np.flatnonzero(a1 < rest)
    if near_rest.size == 0 and not np.any(a1 == np.inf):
        # the ratio below is exactly 1 at every point (m = a1 >= rest, finite
        # or NaN; or a1 = 0 = rest): the estimates as they are unless one is
        # to be confirmed (the rest of this function, with the same values)
        ok = np.isfinite(errors)
        if probe is None or not np.any(ok & (errors > CHANGE_FACTOR * CONFIRM_ABOVE)):
            return errors.copy()
    # the output's whole series, only where something reads it
    z = _output_series(level, points)
    # half the peak-to-peak value, computed only where it is read (its
    # extremes cost a grid and Newton steps per point: at P1's final pass
    # more than the branch itself): where the first harmonic is below the
    # rest floor, and at the points confirmed at the probe level below
    hpp = np.full(points.shape[0], np.nan)
    harmonic_numbers = level.problem.harmonic_numbers

    def peaks(rows):
        todo = rows[np.isnan(hpp[rows])]
        if todo.size:
            hpp[todo] = half_peak_to_peak(harmonic_numbers, z[todo])
        return hpp[rows]

    peaks(near_rest)
    # relative to max(measure, rest): an upper bound of each measure's own
    # ratio (x / max(x, rest) grows with x); where a1 >= rest the ratio is
    # 1 whatever the peak-to-peak value
    m = a1.copy()
    m[near_rest] = np.maximum(a1[near_rest], hpp[near_rest])
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = np.where(m > 0.0, m / np.maximum(m, rest), 1.0)
    errors = np.where(np.isfinite(errors), errors * factor, errors)
    above = np.isfinite(errors) & (errors > CHANGE_FACTOR * CONFIRM_ABOVE)
    if not np.any(above) or probe is None:
        return errors
    from .palc import Continuation

    big = probe.problem
    omega = points[above, -1]
    cont = Continuation(
        big, (float(np.min(omega)), float(np.max(omega)) * (1.0 + 1e-9) + 1e-300),
        1, None, amplitude_scale,
    )  # fmt: skip
    errors = errors.copy()
    done = ~above
    solved: list = []
    confirmed = 0.0
    unsolved: list = []
    # rounds of the largest open estimates until the largest estimate is
    # a confirmed one (or MAX_CONFIRM solves)
    while np.count_nonzero(above) - np.count_nonzero(~done & above) < MAX_CONFIRM:
        open_ = np.flatnonzero(~done)
        if open_.size == 0 or np.max(errors[open_]) <= confirmed:
            break
        used = np.count_nonzero(above & done)
        batch = open_[np.argsort(errors[open_])[::-1][: min(BATCH, MAX_CONFIRM - used)]]
        done[batch] = True
        rows, ys = _probe_solves(cont, level, probe, points, batch, solved)
        unsolved.extend(np.setdiff1d(batch, rows).tolist())
        if rows.size == 0:
            continue
        b1, bhpp, _ = _output_measures(probe, ys, 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            change = np.fmax(
                np.abs(b1 - a1[rows]) / np.maximum(a1[rows], rest[rows]),
                np.abs(bhpp - peaks(rows)) / np.maximum(hpp[rows], rest[rows]),
            )
        change = np.where(np.isnan(change), 0.0, change)
        errors[rows] = CHANGE_FACTOR * change
        confirmed = max(confirmed, float(np.max(errors[rows])))
    if unsolved:
        # no solution at the probe level (a DLFT basis with none near the
        # point): the point's own first-order change instead of a ratio
        # carried from its neighbours (the structure of the paper beam at
        # mass x 1e4, rigid tip, H = 7, 101.35 Hz: 273 carried, 0.29 own)
        rows = np.array(unsolved)
        own = truncation_errors(problem, points[rows], every=1, output=output)
        errors[rows] = np.where(np.isfinite(own), own * factor[rows], errors[rows])
    return errors


def _probe_solves(cont, level, probe, points, batch, solved):
    """Newton at the probe level at the points ``batch`` from the padded
    points; ``(rows, solutions)`` of those solved (``solved``, a list of
    ``(row, y)``, grows)."""
    n_dof, small, large = level.n_dof, level.n_coef, probe.n_coef
    budget = max(8 * cont.options.max_newton, 100)
    new, failed = [], []
    for i in batch:
        guess = np.zeros((n_dof, large))
        guess[:, :small] = points[i, :-1].reshape(n_dof, small)
        y, status, _ = cont.solve_at(float(points[i, -1]), guess.ravel(), budget)
        if _solved(probe.problem, cont, y, status):
            new.append((i, y))
        else:
            failed.append(i)
    solved += new
    # Newton from the padded point can need hundreds of backtracked steps
    # at a DLFT seam (739 at 77.2604 Hz): a second start from the probe
    # solution at the nearest Ω solved
    for i in failed:
        if not solved:
            break
        near = min(solved, key=lambda s: abs(s[1][-1] - points[i, -1]))[1]
        y, status, _ = cont.solve_at(float(points[i, -1]), near[:-1], budget)
        if _solved(probe.problem, cont, y, status):
            new.append((i, y))
            solved.append((i, y))
    if not new:
        return np.zeros(0, dtype=np.int64), np.zeros((0, points.shape[1]))
    return np.array([i for i, _ in new]), np.array([y for _, y in new])


def _solved(problem, cont, y: np.ndarray, status: int) -> bool:
    """Whether Newton's ``y`` solves ``problem`` (converged, or its
    residual at the rounding floor: a seam of the DLFT residual can fail the
    look-ahead test where the balance holds)."""
    if not np.all(np.isfinite(y)):
        return False
    if status == CONVERGED:
        return True
    R, J, aft = problem.residual(y)
    if aft < 0:
        return False
    floor = max(float(rounding_floor(J, y)), problem.rounding_level())
    return float(np.max(np.abs(R))) <= max(cont.tol_residual, floor)


def _levels(problem, with_probe: bool = True, output=None, level=None) -> tuple:
    """The problem's own level, its probe level (None for ``H = 1`` or
    when not ``with_probe``) and the column and weight arguments of
    :func:`~hbmfric.kernels.steps.truncation.branch_truncation` (None for
    ``H = 1``); ``output``: weights of another output to measure;
    ``level``: the problem's level already built (the adaptive run's; not
    with ``output``)."""
    if level is None or output is not None:
        level = _Level(problem, None)
    if output is not None:
        level.output = output
    if not level.top:
        return level, None, None, None
    probe = None
    if with_probe:
        probe = _Level(problem.with_harmonics(probe_level(level.h)), None)
        if output is not None:
            probe.output = output
    columns = np.array(level.columns, dtype=np.int64)
    weights = np.array(
        [level.h, level.prev_weight, LINEAR * 1e-4, CHANGE_FACTOR, CARRY_FLOOR]
    )
    return level, probe, columns, weights


def fold_estimates(cont, points, levels, errors, tangents) -> int:
    """Estimates of the points at a fold that the ladder's top leaves over
    the tolerance, taken again normal to the branch.

    The estimate is a first-order change at fixed Ω (one Newton step in the
    larger basis, or a solve at the probe level at the point's Ω): at a
    fold its matrix is singular, the larger basis's fold lies at a slightly
    different Ω, and the change read there is the distance between two
    curves measured along a line that touches them. Which value it takes
    depends on how near the fold the point lies, to the rounding: the
    README's several-contacts example (stop 34, a new machine) left its fold
    point at 45.0212 rad/s with 4.8e-4 at H = 63, the top, and warned,
    where earlier machines read under 1e-4 at H = 21-63. For such a point
    (at the top, over the tolerance, at a turning point in Ω: the
    tangents' Ω components before and after it of opposite signs, or its
    own zero; a steep stretch where Ω keeps its direction is not one, its
    fixed-Ω estimate is well posed) the point is solved at its probe level on the
    hyperplane through it normal to its tangent (the continuation's own
    corrector, Ω free), and the estimate is ``CHANGE_FACTOR`` times the
    largest relative change of the first-harmonic amplitude and of half the
    peak-to-peak value of the watched output and of each 2D element's
    normal displacement: the distance between the two curves across them.
    In place in ``errors``; returns the number of points estimated again
    (a point whose normal solve fails keeps its estimate)."""
    if tangents is None:
        return 0
    top = cont.ladder[-1]
    again = 0
    for i in np.flatnonzero(np.asarray(errors) > cont.requested):
        i = int(i)
        if levels[i] != top or not np.all(np.isfinite(tangents[i])):
            continue
        if not _at_fold(tangents, i):
            continue
        level = cont._level(top)
        change = _normal_change(level, cont._probe(top), points[i], tangents[i])
        if change is not None:
            errors[i] = CHANGE_FACTOR * change
            again += 1
    return again


def _at_fold(tangents, i: int) -> bool:
    """Whether point ``i`` of a path is a turning point in Ω: the Ω
    components of the tangents before and after it have opposite signs, or
    its own is zero."""
    before = tangents[max(i - 1, 0)][-1]
    after = tangents[min(i + 1, len(tangents) - 1)][-1]
    return tangents[i][-1] == 0.0 or (before > 0.0) != (after > 0.0)


def _normal_change(level, probe, point, tangent) -> float | None:
    """Largest relative change of the watched output's and each 2D
    element's normal displacement's first harmonic and half peak-to-peak
    value from ``point`` (``level``'s layout) to its solve at ``probe`` on
    the hyperplane normal to ``tangent`` (unscaled, ``level``'s layout);
    None if that solve fails."""
    from ..signals import half_peak_to_peak

    n_dof, small, large = level.n_dof, level.n_coef, probe.n_coef

    def pad(v):
        out = np.zeros(probe.n + 1)
        out[:-1].reshape(n_dof, large)[:, :small] = v[:-1].reshape(n_dof, small)
        out[-1] = v[-1]
        return out

    pc = probe.cont
    guess = pad(point)
    t = pad(tangent) / pc.scale
    t /= float(np.linalg.norm(t))
    y = guess.copy()
    status, _ = pc._correct(y, guess.copy(), t)
    if not _solved(probe.problem, pc, y, status):
        return None
    worst = 0.0
    for w in [level.output, *normal_outputs(level.problem)]:
        measures = []
        for lv, x in ((level, point), (probe, y)):
            view = copy.copy(lv)
            view.output = w
            z = _output_series(view, x[None, :])
            f = lv.first_column
            a1 = float(np.hypot(z[0, f], z[0, f + 1]))
            hpp = float(half_peak_to_peak(lv.problem.harmonic_numbers, z)[0])
            measures.append((a1, hpp))
        (a, p), (b, q) = measures
        for old, new in ((a, b), (p, q)):
            if old > 0.0:
                worst = max(worst, abs(new - old) / old)
    return worst


__all__ = ["truncation_errors", "watched_truncation_errors", "next_level"]
