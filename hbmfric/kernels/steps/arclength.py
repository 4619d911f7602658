"""Pseudo-arclength continuation steps with their acceptance rules, compiled.

:func:`advance` is one step of the continuation as a whole: predictor and
corrector (:func:`hbmfric.kernels.steps.newton.palc_step`), the acceptance tests
(Newton converged, tangent turn, distance from the predictor, the corner
rules), fold detection, the next step size and the displacement scale that
follows the amplitude. :func:`trace` repeats it into preallocated arrays,
so that a whole branch runs without returning to Python (each return costs
≈ 4 µs of argument unboxing plus the Python bookkeeping of a step, a third
of a point's cost on a single-DOF problem). The Python driver
(:class:`hbmfric.continuation.palc.Continuation`) calls :func:`advance` for
hand-stepped runs and :func:`trace` for ``run``: one implementation of the
rules.

Settings come as one flat array indexed by the constants below (built by
:func:`hbmfric.continuation.palc.Continuation`).
"""

import numpy as np

from ..._jit import jit, jit_inline
from ..residuals.dispatch import drawn_output
from .newton import CONVERGED, _norm_inf, palc_correct
from .truncation import output_measure, truncation_change

# indices into the settings array
MIN_STEP = 0
MAX_STEP = 1
MAX_ANGLE = 2
MAX_CORRECTION = 3
CORNER_STEP = 4
GROWTH = 5
SHRINK = 6
TARGET_NEWTON = 7
TOL_RESIDUAL = 8
TOL_STEP = 9
MAX_NEWTON = 10
BASE_SCALE = 11
LOW = 12
HIGH = 13
#: largest estimated chord error allowed (relative amplitude, see
#: :func:`chord_error`); 0 turns the rule off
CURVE_TOL = 14
#: index among the unknowns of the cosine coefficient of the first
#: harmonic of the drawn (output) DOF; its sine follows
CURVE_COLUMN = 15
#: written by the kernels: the chord error per squared scaled step of the
#: last accepted step (0: none yet), for the kink test of :func:`advance`
CURVE_LAST = 16
#: estimated error of the points at both ends of the next chord (relative
#: first-harmonic amplitude of the drawn DOF, as ``CURVE_TOL``): charged
#: against the curve budget, see :func:`chord_target`. Set by the caller
#: (the adaptive-harmonics run: its truncation estimate of the current
#: point) and, in :func:`trace` with an active watch, after every point
#: that stays at its level (the point's estimate); 0: points taken as
#: exact (a fixed ``H``); negative: not charged (a harmonic tolerance
#: above the curve tolerance)
CURVE_POINT = 17
#: != 0: the predictor bends with the branch (:func:`predict`, a second
#: order term from the previous point); 0: the tangent's straight line
PREDICTOR = 18
#: != 0 (a rigid Coulomb contact): a step the curve rule would shorten
#: below ``CORNER_FLOOR`` min_step is tried at that floor and taken there
#: with its estimate, as across a corner (the DLFT branch kinks where a
#: stick phase appears or ends: its tangents there are one-sided and the
#: estimate need not fall with the step; without the floor the steps fell
#: below min_step and the branch stalled); and a chord whose both ends are
#: below ``CURVE_REST`` (the tip stuck or just short of it, 1e-9 of a 1e-3
#: scale on the beam at f_s = 2 N, where steps sized for it stalled the
#: branch at 77.1 Hz) is taken as exact
KINK_FLOOR = 19
N_SETTINGS = 20
#: a step whose chord error per squared step exceeds the last one's this
#: many times may hold a kink (a contact transition), where the cubic
#: estimate falls short by up to 2x: it counts twice
KINK_JUMP = 4.0
#: with the second-order predictor, the next step is sized for the chord
#: error per squared step grown by its last growth, at most this factor
BEND_GROWTH = 2.0

#: fractions of a chord where :func:`chord_error` compares the cubic
#: with the chord: the extremes of the two shapes of a cubic's deviation
#: (``(3 ∓ √3)/6``, an S) and the middle (a bow)
_TAU = (0.21132486540518713, 0.5, 0.7886751345948129)
#: a step across a corner is not shortened by the curve rule below this
#: many ``min_step``
CORNER_FLOOR = 100.0
#: the chord's share of the curve budget never falls below this fraction
#: of ``CURVE_TOL`` (points whose own estimated error takes nearly all of
#: it would otherwise stall the step; steps go as the square root: at the
#: floor half as long)
CURVE_FLOOR = 0.25
#: the vertical distance near a fold is bounded by this factor times the
#: distance perpendicular to the chord
_FOLD_CAP = 1e3
#: amplitudes are compared relative to at least this fraction of the
#: displacement scale (the linearised response's peak or more): below it
#: the drawn DOF is at rest for the rule (a rigid Coulomb tip stuck at
#: round-off, 1e-15 of the scale, or just short of sticking at 1e-9 of
#: it, where relative errors of 1e5 stalled the steps or spent the step
#: budget on the beam); elastic contacts stay above 5e-3 of it (P1, the
#: Jenkins beam, Iwan)
CURVE_REST = 1e-4

# outcome of a step (bit flags on ACCEPTED)
REJECTED = 0
ACCEPTED = 1
CORNER = 2
FOLD = 4
#: the corrected point lies outside [low, high]; it is left in ``y_new``
LEFT_RANGE = 8
#: rejected, and the shrunk step is below ``min_step``
STEP_TOO_SMALL = 16

# outcome of a traced stretch
RANGE_LEFT = 1
STEP_BELOW_MIN = 2
BUDGET_SPENT = 3
BUFFER_FULL = 4
#: the last accepted point needs a decision of the adaptive-harmonics run
WATCH_STOP = 5

# indices into the watch array (the adaptive run's rule for staying at a
# level between calibrations, see :func:`stays`); WATCH_ACTIVE = 0 turns
# the watch off
WATCH_ACTIVE = 0
W_FACTOR = 1
W_LAST = 2
W_AGE = 3
W_RECALIBRATE = 4
W_RAISE = 5
W_LOWER = 6
W_MARGIN = 7
W_MAX_GROWTH = 8
W_LINEAR = 9
W_H = 10
W_PREV_WEIGHT = 11
W_FIRST = 12
W_TOP = 13
W_PREV = 14
W_LOWEST = 15
#: != 0: a due calibration runs inside the trace (there is a next level)
W_CALIBRATE = 16
W_CHANGE_FACTOR = 17
#: a calibrated estimate below this is not carried to the next points
#: (``adaptive.ONSET`` times the tolerance)
W_TOP_FLOOR = 18
#: DOFs among the unknowns, contact DOF (informative: the calibration
#: reads the watched output's weights), column of the first harmonic
W_N_DOF = 19
W_DOF = 20
W_FIRST_COLUMN = 21
#: out: calibrations that kept the level inside the trace
W_CALIBRATIONS = 22
#: out: the change of a calibration after which the level was not kept
#: (NaN if none; the caller decides on it instead of computing it again)
W_CHANGE = 23
#: in/out: points in a row, before the current one, whose estimate was
#: below the lower threshold (``AdaptiveContinuation._low``)
W_LOW = 24
#: such points in a row after which the caller lowers the level
#: (``adaptive.LOWER_PATIENCE``)
W_PATIENCE = 25
#: the run's tolerance: a point whose estimate exceeds it is solved again
#: higher by the caller
W_TOL = 26
#: age below which the carried estimate decides without a calibration when
#: it is within the tolerance and asks for no raise (``adaptive.MIN_GAP``)
W_MIN_GAP = 27
N_WATCH = 28


@jit
def next_step(step, iterations, angle, curve, settings):
    """Step after an accepted corrector run of ``iterations`` Newton
    iterations whose tangent turned by ``angle`` rad and whose chord has
    the estimated error ``curve`` (:func:`chord_error`, 0 if none): grow
    towards ``target_newton`` iterations per step, by at most ``growth``,
    keep the turn below 0.8 ``max_angle`` and (with ``curve_tol > 0``) the
    chord error, which grows as the square of the step, below 0.8
    ``curve_tol``; shrink at most by ``shrink``, never above ``max_step``."""
    factor = min(settings[GROWTH], settings[TARGET_NEWTON] / max(iterations, 1))
    if angle > 0.0:
        factor = min(factor, 0.8 * settings[MAX_ANGLE] / angle)
    factor = max(factor, settings[SHRINK])
    tol = settings[CURVE_TOL]
    if tol > 0.0 and curve > 0.0:
        factor = min(factor, np.sqrt(0.8 * tol / curve))
    return min(step * factor, settings[MAX_STEP])


@jit
def chord_target(settings):
    """Largest estimated chord error the curve rule allows: the curve
    tolerance less the estimated error of the points themselves
    (``settings[CURVE_POINT]``), at least ``CURVE_FLOOR`` times the
    tolerance.

    What a user draws between two points is off the true response by the
    chord's distance from the computed branch plus the branch's own
    (truncation) error, which the straight line carries over from its ends
    (a linear interpolation of the end errors, at most the larger one).
    Charging the points' estimate against ``CURVE_TOL`` keeps the sum
    within it wherever the points use less than ``1 - CURVE_FLOOR`` of it;
    where the points are exact (stuck, linear) the chord keeps the whole
    tolerance."""
    tol = settings[CURVE_TOL]
    point = settings[CURVE_POINT]
    if not point > 0.0:  # also NaN: unknown, taken as exact
        return tol
    return max(tol - point, CURVE_FLOOR * tol)


@jit
def predict(y, tangent, step, scale, settings, history, y_pred):
    """Predictor of a step: the tangent's straight line, or with
    ``settings[PREDICTOR] != 0`` the parabola that also passes through the
    previous point.

    Along the branch ``y(s) = y + s t + s² c / 2 + O(s³)`` (scaled
    variables, ``s`` the arc length); the curvature ``c`` follows from the
    previous point ``y(-h)`` (``h`` its scaled distance, the chord for the
    arc): ``c = 2 ((y(-h) - y) / h + t) / h``. The straight predictor is
    off the branch by ``|c| ds² / 2``, which at the short steps the curve
    rule takes (chord error ``|c| ds² / 8`` relative, at ``0.8`` of the
    tolerance) costs a third corrector evaluation per point; the parabola's
    error is of order ``ds³``, and the corrector converges in two (P1 at
    F = 2, H = 21: 2.1 against 3.0 evaluations per point, bench/README.md
    "Issue 18, stop 26"). The parabola is used only when ``history`` holds
    the previous point of ``y`` (its second row equal to ``y``; a corner
    step, a failed corrector and any change of the point outside the
    kernels leave it unused) and its predicted turn over the step,
    ``ds |c|``, is below ``max_angle``.

    Parameters
    ----------
    y, tangent : ndarray, shape (n + 1,)
        Current point (physical units) and unit tangent (scaled).
    step : float
        Arc-length step, scaled.
    scale : ndarray, shape (n + 1,)
        Variable scales.
    settings : ndarray, shape (N_SETTINGS,)
        Options (``PREDICTOR``, ``MAX_ANGLE``).
    history : ndarray, shape (2, n + 1)
        The previous point and the point it preceded (physical units),
        written by :func:`advance` on acceptance.
    y_pred : ndarray, shape (n + 1,)
        Output: the predictor (physical units).

    Returns
    -------
    bool
        Whether the second-order term was used.
    """
    m = y.size
    for i in range(m):
        y_pred[i] = y[i] + step * tangent[i] * scale[i]
    if settings[PREDICTOR] == 0.0:
        return False
    h2 = 0.0
    for i in range(m):
        if history[1, i] != y[i]:  # also NaN: no previous point
            return False
        d = (history[0, i] - y[i]) / scale[i]
        h2 += d * d
    if not h2 > 0.0:
        return False
    h = np.sqrt(h2)
    bend = 0.0
    for i in range(m):
        c = 2.0 * ((history[0, i] - y[i]) / scale[i] / h + tangent[i]) / h
        bend += c * c
    if not step * np.sqrt(bend) <= settings[MAX_ANGLE]:
        return False
    half = 0.5 * step * step
    for i in range(m):
        c = 2.0 * ((history[0, i] - y[i]) / scale[i] / h + tangent[i]) / h
        y_pred[i] += half * c * scale[i]
    return True


@jit
def _drawn(y, t, scale, column):
    """Ω and the first-harmonic amplitude ``a₁`` (at ``column``) of the
    point ``y``, and their derivatives along the scaled arc length (unit
    tangent ``t``); NaN amplitude parts for a DOF at rest."""
    n = y.size - 1
    c = y[column]
    s = y[column + 1]
    a = np.hypot(c, s)
    dx = t[n] * scale[n]
    if not a > 0.0:
        return y[n], dx, np.nan, np.nan
    da = (c * t[column] * scale[column] + s * t[column + 1] * scale[column + 1]) / a
    return y[n], dx, a, da


@jit
def chord_error(y0, t0, y1, t1, scale, column, rest_exact=False):
    """Estimated largest distance between the branch and the chord
    joining two of its points, in the drawn plane.

    The branch between ``y0`` and ``y1`` is modelled by the cubic Hermite
    curve through both points with their tangents (parameter scaled by the
    chord length ``L`` in the scaled variables), in the plane ``(Ω, a₁)``
    (``a₁``: first-harmonic amplitude of the drawn DOF) where the chord is
    the straight line a plot or a linear interpolation draws. The cubic's
    deviation from the chord is ``τ(1-τ)[(1-τ)(m₀-Δ) - τ(m₁-Δ)]`` (``m = L
    dP/ds``, ``Δ = P₁ - P₀``); it is taken at ``τ = (3-√3)/6, 1/2,
    (3+√3)/6`` (the extremes of its S and bow parts), measured vertically
    (in ``a₁`` at equal Ω) relative to the smaller amplitude of the two
    ends (as read off a log axis; at least ``CURVE_REST`` times the
    displacement scale ``scale[column]``), at most ``1e3`` times the distance
    perpendicular to the chord in the plane of relative Ω and relative
    amplitude, and that distance itself across a fold (the Ω components of
    the tangents differ in sign). Its error is of order ``L⁴``, the estimate's
    own ``L²``.

    Parameters
    ----------
    y0, y1 : ndarray, shape (n + 1,)
        ``[X, Ω]`` of both points, physical units (m, rad/s).
    t0, t1 : ndarray, shape (n + 1,)
        Unit tangents in the scaled variables (same direction of travel).
    scale : ndarray, shape (n + 1,)
        Scales of the variables (m, rad/s).
    column : int
        Index of the first-harmonic cosine coefficient of the drawn DOF.
    rest_exact : bool
        Take a chord whose both ends are below the floor (the drawn DOF at
        rest, or nearly: a rigid Coulomb tip just short of sticking) as
        exact.

    Returns
    -------
    float
        Estimated relative amplitude error, >= 0; 0 for a DOF at rest at
        either point.
    """
    length = 0.0
    for i in range(y0.size):
        d = (y1[i] - y0[i]) / scale[i]
        length += d * d
    length = np.sqrt(length)
    w0, dw0, a0, da0 = _drawn(y0, t0, scale, column)
    w1, dw1, a1, da1 = _drawn(y1, t1, scale, column)
    rest = CURVE_REST * scale[column]
    return _chord(length, w0, dw0, a0, da0, w1, dw1, a1, da1, rest, rest_exact)


@jit
def problem_chord_error(
    problem, y0, t0, y1, t1, scale, column, base_scale, rest_exact=False
):
    """:func:`chord_error` of what ``problem`` draws: the unknown at
    ``column``, or for a problem condensed onto several contact coordinates
    the output DOF recovered from them
    (:func:`hbmfric.kernels.residuals.dispatch.drawn_output`), with the
    cubic parametrised as ``Branch.curve_errors`` does: by the arc length
    on that DOF's coefficients (scale ``base_scale``) and Ω; ``rest_exact``
    as in :func:`chord_error`."""
    m = y0.size
    x0 = np.empty(m)
    x1 = np.empty(m)
    ok, w0, dw0, a0, da0, v0, n_coef = drawn_output(problem, y0, t0, scale, column, x0)
    if not ok:
        return chord_error(y0, t0, y1, t1, scale, column, rest_exact)
    ok, w1, dw1, a1, da1, v1, _ = drawn_output(problem, y1, t1, scale, column, x1)
    if not ok:
        return chord_error(y0, t0, y1, t1, scale, column, rest_exact)
    n = m - 1
    width = scale[n]
    length = ((w1 - w0) / width) ** 2
    for i in range(n_coef):
        d = (x1[i] - x0[i]) / base_scale
        length += d * d
    length = np.sqrt(length)
    # speeds along the kernel's arc length in the branch's metric
    s0 = np.sqrt(v0 / base_scale**2 + (dw0 / width) ** 2)
    s1 = np.sqrt(v1 / base_scale**2 + (dw1 / width) ** 2)
    if not (s0 > 0.0 and s1 > 0.0):
        return 0.0
    rest = CURVE_REST * base_scale
    return _chord(
        length, w0, dw0 / s0, a0, da0 / s0, w1, dw1 / s1, a1, da1 / s1, rest, rest_exact
    )


@jit
def _chord(length, w0, dw0, a0, da0, w1, dw1, a1, da1, rest, rest_exact):
    """The estimate of :func:`chord_error` from the drawn values at both
    ends (Ω, ``a₁`` and their derivatives along the scaled arc length),
    the chord length ``length`` and the amplitude floor ``rest`` (with
    ``rest_exact``: 0 when both ends are below it)."""
    if not (np.isfinite(a0) and np.isfinite(a1)):
        return 0.0
    if rest_exact and max(a0, a1) < rest:
        return 0.0
    # relative units: Ω by the mean of the ends, a by the smaller one (at
    # least CURVE_REST of the displacement scale)
    rw = 0.5 * (w0 + w1)
    ra = max(min(a0, a1), rest)
    ex = (w1 - w0) / rw
    el = (a1 - a0) / ra
    ax = (length * dw0) / rw - ex
    al = (length * da0) / ra - el
    bx = (length * dw1) / rw - ex
    bl = (length * da1) / ra - el
    chord = np.hypot(ex, el)
    if chord == 0.0:
        return 0.0
    run = max(abs(ex), chord / _FOLD_CAP)
    if (dw0 > 0.0) != (dw1 > 0.0):
        # a fold inside: the two sides are drawn over the same Ω, the
        # distance across the chord is what shows
        run = chord
    worst = 0.0
    for tau in _TAU:
        w = tau * (1.0 - tau)
        dx = w * ((1.0 - tau) * ax - tau * bx)
        dl = w * ((1.0 - tau) * al - tau * bl)
        # distance along a at equal Ω from the chord line
        e = abs(dl * ex - dx * el) / run
        if e > worst:
            worst = e
    return worst


@jit
def _short_turn(y, y_new, t_new, scale, corner_step):
    """A sharp corner, accepted at any turn.

    Where the new piece of branch leaves the corner at an angle ``α`` to
    the old tangent, the corrector's hyperplane meets it about ``ds tan α``
    from the predictor (``α = 88°`` where a stuck resonance at ζ = 1e-4
    starts to slip), beyond the ``2 ds`` of the plain corner rule at every
    step size. Accepted when the corrected point is within ``corner_step``
    of the current one (scaled) and the chord to it runs along the new
    tangent (cosine >= 0.9): a step that short along the new piece cannot
    have left the branch."""
    length = 0.0
    along = 0.0
    for i in range(y.size):
        d = (y_new[i] - y[i]) / scale[i]
        length += d * d
        along += d * t_new[i]
    length = np.sqrt(length)
    if not length <= corner_step:
        return False
    return along >= 0.9 * length


@jit
def follow_amplitude(y, tangent, scale, base_scale):
    """Keep the displacement scale at least a tenth of the amplitude.

    The base scale is the peak of the linearised response; a branch may
    climb far above it (a resonance that friction cannot bound peaks at
    ``(F - 4 f_s/π) / (c Ω)``, 4000 base scales at ζ = 1e-4 in the stress
    matrix) and would then need as many steps as it is scales high. The
    scale of every displacement unknown follows a tenth of the largest
    coefficient (never below ``base_scale``), changed only when off by more
    than 1.5×, so that a branch within 15 base scales keeps the base scale.
    The unit tangent is carried over to the new scaled variables.
    ``y``, ``tangent``, ``scale``: shape (n + 1,), the last entry Ω (its
    scale is left alone).
    """
    n = y.size - 1
    target = max(base_scale, 0.1 * _norm_inf(y[:n]))
    current = scale[0]
    if current / 1.5 <= target <= 1.5 * current:
        return
    norm = 0.0
    for i in range(n + 1):
        if i < n:
            tangent[i] *= current / target
            scale[i] = target
        norm += tangent[i] * tangent[i]
    norm = np.sqrt(norm)
    for i in range(n + 1):
        tangent[i] /= norm


@jit
def top_measure(y, watch, weights, rates):
    """Free truncation measure ``H max(|Z_H|, w |Z_K'|) / |Z_1|`` of the
    watched output ``Z`` (``weights``, ``rates``: see
    :func:`~hbmfric.kernels.steps.truncation.output_measure`) at the point ``y``
    (columns and ``w`` from ``watch``, see
    :meth:`hbmfric.continuation.adaptive._Level.measure`): inf without a
    retained harmonic above the first, 0 for an output at rest."""
    return output_measure(
        y,
        weights,
        rates,
        int(watch[W_FIRST]),
        int(watch[W_TOP]),
        int(watch[W_PREV]),
        watch[W_H],
        watch[W_PREV_WEIGHT],
    )


@jit_inline
def stays(y, watch, calibration):
    """Whether the adaptive-harmonics run keeps its level after the point
    ``y`` without a decision in Python: the whole rule of
    :meth:`~hbmfric.continuation.adaptive.AdaptiveContinuation._adapt`
    except its actions (a move to the lowest level for a linear response,
    a raise, a point solved again higher, a lowering), for which it
    returns False with ``watch`` unchanged (but ``watch[W_CHANGE]``) so
    that the caller decides on the same numbers.

    * a linear response stays at the lowest level (estimate 0);
    * between calibrations (age below ``W_RECALIBRATE``), the free measure
      times the calibrated ratio, extrapolated one step ahead, clear of
      the raise threshold by the margin and not below the lower one,
      stays;
    * otherwise the estimate is that carried estimate when the last
      calibration is younger than ``W_MIN_GAP`` points, within the
      tolerance and asks for no raise; else a fresh calibration
      (:func:`~hbmfric.kernels.steps.truncation.truncation_change` on the
      next level's problem, the address of its residual, watched output
      and work arrays ``calibration = (problem, residual_at, synthesis,
      weights, rates, y, R, J, A, dX)``; needs ``watch[W_CALIBRATE] !=
      0``), whose change is left in
      ``watch[W_CHANGE]`` when the caller must decide;
    * that estimate stays when it is within the tolerance, asks for no
      raise and is not the ``W_PATIENCE``-th in a row below the lower
      threshold (the count is kept in ``watch[W_LOW]``).

    Staying updates the last estimate, the age, the count below the lower
    threshold and, after a calibration, the ratio and the count of
    calibrations in ``watch``."""
    measure = top_measure(y, watch, calibration[3], calibration[4])
    if measure <= watch[W_LINEAR]:
        # a linear response: stays only at the lowest level, where it is
        # exact (the estimate is then 0)
        if watch[W_LOWEST] != 0.0:
            watch[W_LAST] = 0.0
            return True
        return False
    age = watch[W_AGE] + 1.0
    last = watch[W_LAST]
    decided = False
    est = 0.0
    if age < watch[W_RECALIBRATE]:
        stale = watch[W_FACTOR] * measure
        ahead = stale
        if last > 0.0 and stale > last:
            ahead = stale * min(stale / last, watch[W_MAX_GROWTH])
        if watch[W_MARGIN] * ahead <= watch[W_RAISE] and stale >= watch[W_LOWER]:
            watch[W_LAST] = stale
            watch[W_AGE] = age
            watch[W_LOW] = 0.0
            return True
        # calibrated a moment ago: the carried estimate decides unless it
        # asks for a raise or exceeds the tolerance
        if age < watch[W_MIN_GAP] and stale <= watch[W_TOL] and ahead <= watch[W_RAISE]:
            est = stale
            decided = True
    change = np.nan
    if not decided:
        if watch[W_CALIBRATE] == 0.0:
            return False
        problem, residual_at, synthesis, weights, rates, cy, cR, cJ, cA, cdX = (
            calibration
        )
        change = truncation_change(
            y,
            problem,
            residual_at,
            weights,
            rates,
            int(watch[W_FIRST_COLUMN]),
            synthesis,
            cy,
            cR,
            cJ,
            cA,
            cdX,
        )
        est = watch[W_CHANGE_FACTOR] * change
    ahead = est
    if last > 0.0 and est > last:
        ahead = est * min(est / last, watch[W_MAX_GROWTH])
    low = 0.0
    act = est > watch[W_TOL] or ahead > watch[W_RAISE]
    if not act and est < watch[W_LOWER]:
        low = watch[W_LOW] + 1.0
        act = low >= watch[W_PATIENCE]
    if act:
        # solved again higher, raised or lowered: the caller's decision
        if not decided:
            watch[W_CHANGE] = change
        return False
    if decided:
        watch[W_AGE] = age
    else:
        # an estimate this small (the onset of slip: its ratio is far
        # below the ones a step later) is not carried: the next point
        # calibrates
        watch[W_FACTOR] = (
            est / max(measure, 1e-300) if est >= watch[W_TOP_FLOOR] else np.inf
        )
        watch[W_AGE] = 0.0
        watch[W_CALIBRATIONS] += 1.0
    watch[W_LAST] = est
    watch[W_LOW] = low
    return True


@jit_inline
def advance(
    problem,
    residual_at,
    y,
    tangent,
    step,
    scale,
    settings,
    R,
    J,
    A,
    piv,
    y_pred,
    y_new,
    t_new,
    history,
):
    """One continuation step, accepted or rejected.

    Parameters
    ----------
    problem : tuple
        HBM problem (:func:`hbmfric.kernels.residuals.dispatch.residual`).
    residual_at : int
        Address of the residual compiled for ``problem``'s type
        (:func:`hbmfric.kernels.residuals.pointer.residual_address`).
    y, tangent : ndarray, shape (n + 1,)
        In: current point (physical units) and unit tangent (scaled). Out,
        when accepted: the new point and tangent.
    step : float
        Arc-length step to try, scaled.
    scale : ndarray, shape (n + 1,)
        Variable scales; the displacement scales may change on acceptance
        (:func:`follow_amplitude`).
    settings : ndarray, shape (N_SETTINGS,)
        Options, see the index constants of this module.
    R, J, A, piv, y_pred, y_new, t_new : ndarray
        Work arrays of :func:`~hbmfric.kernels.steps.newton.palc_correct`.
        On ``LEFT_RANGE``, ``y_new`` holds the corrected point outside the
        range.
    history : ndarray, shape (2, n + 1)
        The previous point and the point it preceded, for the second-order
        predictor (:func:`predict`); updated on acceptance (NaN after a
        corner), its second row set to NaN after a failed corrector.

    Returns
    -------
    outcome : int
        ``REJECTED``, ``STEP_TOO_SMALL``, ``LEFT_RANGE`` or ``ACCEPTED``
        with the ``CORNER`` and ``FOLD`` bits.
    new_step : float
        Step for the next call (unchanged on ``LEFT_RANGE``).
    evaluations : int
        Residual evaluations spent.
    """
    predict(y, tangent, step, scale, settings, history, y_pred)
    status, evaluations, effort, distance, angle = palc_correct(
        problem,
        residual_at,
        tangent,
        scale,
        settings[TOL_RESIDUAL],
        settings[TOL_STEP],
        int(settings[MAX_NEWTON]),
        R,
        J,
        A,
        piv,
        y_pred,
        y_new,
        t_new,
    )
    ok = status == CONVERGED
    corner = False
    if ok:
        smooth = (
            angle <= settings[MAX_ANGLE] and distance <= settings[MAX_CORRECTION] * step
        )
        corner = (
            not smooth
            and step <= settings[CORNER_STEP]
            and (
                distance <= 2.0 * step
                or _short_turn(y, y_new, t_new, scale, settings[CORNER_STEP])
            )
        )
        ok = smooth or corner
    if not ok:
        # the shorter retry predicts along the tangent (as before the
        # second-order predictor: a failure never depends on it twice)
        history[1, y.size - 1] = np.nan
        new_step = step * settings[SHRINK]
        if new_step < settings[MIN_STEP]:
            return STEP_TOO_SMALL, new_step, evaluations
        return REJECTED, new_step, evaluations
    n = y.size - 1
    omega = y_new[n]
    if omega > settings[HIGH] or omega < settings[LOW]:
        return LEFT_RANGE, step, evaluations
    curve = 0.0
    target = settings[CURVE_TOL]
    if target > 0.0:
        target = chord_target(settings)
        curve = problem_chord_error(
            problem,
            y,
            tangent,
            y_new,
            t_new,
            scale,
            int(settings[CURVE_COLUMN]),
            settings[BASE_SCALE],
            settings[KINK_FLOOR] != 0.0,
        )
        length2 = 0.0
        for i in range(y.size):
            d = (y_new[i] - y[i]) / scale[i]
            length2 += d * d
        bend = curve / length2 if length2 > 0.0 else 0.0
        last = settings[CURVE_LAST]
        if corner or (last > 0.0 and bend > KINK_JUMP * last):
            # a kink inside the step: up to twice the cubic's deviation
            curve *= 2.0
        floor = CORNER_FLOOR * settings[MIN_STEP]
        kink = corner or settings[KINK_FLOOR] != 0.0
        if curve > target and (not kink or step > floor):
            # the chord would stray from the branch: shorter, as the
            # error goes with the square of the step (across a corner:
            # linearly, and only down to CORNER_FLOOR min_step: a corner
            # step at the floor is taken as it is, a longer one is tried
            # again at the floor at least, never taken because the
            # shortened step would fall below it)
            factor = max(np.sqrt(0.8 * target / curve), 0.1)
            if corner:
                factor = max(0.8 * target / curve, 0.1)
            new_step = step * min(factor, settings[SHRINK])
            if kink:
                new_step = max(new_step, floor)
            if new_step < settings[MIN_STEP]:
                return STEP_TOO_SMALL, new_step, evaluations
            return REJECTED, new_step, evaluations
        settings[CURVE_LAST] = 0.0 if corner else bend
        if corner:
            curve = 0.0
        elif settings[PREDICTOR] != 0.0 and last > 0.0 and bend > last:
            # the bend grows (towards a resonance): the next step is sized
            # for the bend ahead, as the steps that reach the rule's aim
            # with the second-order predictor were rejected there
            curve *= min(bend / last, BEND_GROWTH)
    outcome = ACCEPTED
    if corner:
        outcome |= CORNER
        angle = 0.0
    t_old = tangent[n]
    t_now = t_new[n]
    if t_now != 0.0 and (t_old == 0.0 or (t_now > 0.0) != (t_old > 0.0)):
        outcome |= FOLD
    for i in range(n + 1):
        history[0, i] = y[i]
        history[1, i] = y_new[i]
        y[i] = y_new[i]
        tangent[i] = t_new[i]
    if corner:  # no parabola through a corner
        history[1, n] = np.nan
    if curve > 0.0:
        # next_step sizes for 0.8 CURVE_TOL: the chord's share instead
        curve *= settings[CURVE_TOL] / target
    new_step = next_step(step, effort, angle, curve, settings)
    if settings[KINK_FLOOR] != 0.0 and target > 0.0:
        # a step taken at the kink floor over its budget is not followed
        # by shorter ones
        new_step = max(new_step, min(step, CORNER_FLOOR * settings[MIN_STEP]))
    follow_amplitude(y, tangent, scale, settings[BASE_SCALE])
    return outcome, new_step, evaluations


@jit
def trace(
    problem,
    residual_at,
    y,
    tangent,
    step,
    scale,
    settings,
    max_attempts,
    watch,
    points,
    tangents,
    flags,
    estimates,
    R,
    J,
    A,
    piv,
    y_pred,
    y_new,
    t_new,
    history,
    calibration,
):
    """Repeat :func:`advance` until the branch leaves the range, the step
    falls below its minimum, ``max_attempts`` steps were tried or the
    output arrays are full.

    Parameters
    ----------
    problem, residual_at, y, tangent, step, scale, settings, R, J, A, piv,
    y_pred, y_new, t_new, history
        As in :func:`advance` (``y``, ``tangent``, ``scale`` updated in
        place).
    calibration : tuple
        Next level's problem, the address of its residual and work arrays
        for :func:`stays` (any of the right types when the watch is off).
    max_attempts : int
        Most steps (accepted plus rejected) to try.
    watch : ndarray, shape (N_WATCH,)
        With ``watch[WATCH_ACTIVE] != 0`` (adaptive harmonics) the trace
        also stops after an accepted point that does not :func:`stays`.
    points : ndarray, shape (capacity, n + 1)
        Out: accepted points.
    tangents : ndarray, shape (capacity, n + 1)
        Out: unit tangent at each accepted point in physical units
        (``tangent * scale`` with the scale at that point: ``dX/ds`` in m,
        ``dΩ/ds`` in rad/s per unit of the scaled arc length ``s``).
    flags : ndarray of int64, shape (capacity,)
        Out: ``CORNER``/``FOLD`` bits of each accepted point.
    estimates : ndarray, shape (capacity,)
        Out: the calibrated truncation estimate of each accepted point
        whose due calibration ran in :func:`stays` and kept the level
        (untouched elsewhere: the caller fills it with NaN), so that the
        final estimate of the branch need not compute it again.

    Returns
    -------
    outcome : int
        ``RANGE_LEFT`` (``y_new`` holds the point outside the range),
        ``STEP_BELOW_MIN``, ``BUDGET_SPENT``, ``BUFFER_FULL`` or
        ``WATCH_STOP``.
    n_accepted, n_rejected, evaluations : int
    step : float
        Step for the next call.
    """
    n_accepted = 0
    n_rejected = 0
    evaluations = 0
    n = y.size - 1
    capacity = points.shape[0]
    attempts = 0
    while True:
        if n_accepted == capacity:
            return BUFFER_FULL, n_accepted, n_rejected, evaluations, step
        if attempts == max_attempts:
            return BUDGET_SPENT, n_accepted, n_rejected, evaluations, step
        attempts += 1
        outcome, step, spent = advance(
            problem,
            residual_at,
            y,
            tangent,
            step,
            scale,
            settings,
            R,
            J,
            A,
            piv,
            y_pred,
            y_new,
            t_new,
            history,
        )
        evaluations += spent
        if outcome == LEFT_RANGE:
            return RANGE_LEFT, n_accepted, n_rejected, evaluations, step
        if outcome == REJECTED or outcome == STEP_TOO_SMALL:
            n_rejected += 1
            if outcome == STEP_TOO_SMALL:
                return STEP_BELOW_MIN, n_accepted, n_rejected, evaluations, step
            continue
        for i in range(n + 1):
            points[n_accepted, i] = y[i]
            tangents[n_accepted, i] = tangent[i] * scale[i]
        flags[n_accepted] = outcome
        n_accepted += 1
        if watch[WATCH_ACTIVE] != 0.0:
            if not stays(y, watch, calibration):
                return WATCH_STOP, n_accepted, n_rejected, evaluations, step
            if watch[W_AGE] == 0.0:  # calibrated at this point
                estimates[n_accepted - 1] = watch[W_LAST]
            # the point's estimate is the points' share of the next
            # chord's budget (what the decision in Python sets, so that
            # both paths step alike)
            if settings[CURVE_POINT] >= 0.0:  # negative: not charged
                settings[CURVE_POINT] = watch[W_LAST]
