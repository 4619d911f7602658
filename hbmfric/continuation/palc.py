"""Pseudo-arclength continuation of HBM solutions in ``(X, Ω)``.

The continuation is an iterator with explicit state: :meth:`Continuation.init`
solves the first point and returns a :class:`ContinuationState`;
:meth:`Continuation.step` advances it by one accepted (or rejected) step,
so a user can drive a run by hand; :meth:`Continuation.run` traces the
whole branch in compiled stretches (:func:`hbmfric.kernels.arclength.trace`,
the same step and rules as ``step``, without a return to Python per point).

One step: tangent predictor ``y_p = y + ds t`` (``t`` from
``[J; t_prevᵀ] t = [0; 1]``, normalised, direction kept), corrector on the
hyperplane through ``y_p`` orthogonal to ``t``, then acceptance tests: Newton
converged, tangent turned less than ``max_angle``, corrected point not far
from the predictor (a short step is accepted at a corner of the branch,
where a contact transition turns the tangent abruptly). Folds (turning
points) are flagged when the Ω-component of the tangent changes sign. The
run ends at the far end of the frequency range (the last point solved
exactly at the boundary), at the end it started from (after a fold the path
can leave the range there, with only part of it covered), at
``max_steps``, or when the step falls below ``min_step`` and no bridge
(:meth:`Continuation._bridge`: a fixed-Ω solve a little further along the
tangent, for seams of the piecewise-smooth residual where the corrector
fails at every step size) gets past; it never raises on a numerical
failure and never stores a non-finite point.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..kernels import arclength as _arclength
from ..kernels import newton as _newton
from .options import ContinuationOptions

#: stop reasons
RANGE_END = "end of frequency range reached"
#: the path turned back (at a fold) and left through the end it started from
RANGE_START = "turned back at a fold and left the range at its starting end"
MAX_STEPS = "maximum number of steps reached"
MIN_STEP = "step size fell below min_step"
NO_START = "no converged starting point"

#: most bridges (:meth:`Continuation._bridge`) in one run
MAX_BRIDGES = 50
#: Ω steps of a bridge, as fractions of the range width, tried in turn
BRIDGE_STEPS = (1e-5, 1e-4, 1e-3)
#: a bridge needs the tangent's Ω component (scaled) at least this large:
#: nearer a fold a solve at fixed Ω could land on another branch
BRIDGE_MIN_SLOPE = 1e-3
#: a bridged point lies within this factor times the scaled arc length of
#: the tangent prediction
BRIDGE_TOLERANCE = 2.0


@dataclass
class ContinuationState:
    """Mutable state of a continuation run (points in physical units)."""

    y: np.ndarray
    tangent: np.ndarray
    step: float
    J: np.ndarray
    points: list = field(default_factory=list)
    tangents_omega: list = field(default_factory=list)
    #: unit tangent at each point in physical units (``tangent * scale``
    #: with the scale at that point), shape (n + 1,) each
    tangents: list = field(default_factory=list)
    folds: list = field(default_factory=list)
    corners: list = field(default_factory=list)
    n_steps: int = 0
    n_rejected: int = 0
    n_newton: int = 0
    n_bridges: int = 0
    finished: bool = False
    stop_reason: str = ""


class Continuation:
    """Pseudo-arclength continuation of an :class:`~hbmfric.hbm.HBMProblem`.

    Parameters
    ----------
    problem : HBMProblem
    omega_range : (float, float)
        ``(low, high)`` in rad/s, ``0 < low < high``.
    direction : {+1, -1}
        +1 starts at ``low`` and sweeps up, -1 starts at ``high`` and sweeps
        down.
    options : ContinuationOptions
    amplitude_scale : float or None
        Scale of the displacement coefficients, m; None: from the linearised
        system.
    """

    def __init__(
        self,
        problem,
        omega_range: tuple[float, float],
        direction: int = 1,
        options: ContinuationOptions | None = None,
        amplitude_scale: float | None = None,
    ) -> None:
        if not isinstance(options, ContinuationOptions | None):
            raise TypeError(
                f"options must be a ContinuationOptions, got {type(options).__name__}"
            )
        self.problem = problem
        self.low, self.high = float(omega_range[0]), float(omega_range[1])
        self.direction = 1 if direction >= 0 else -1
        self.options = options or ContinuationOptions()
        n = problem.n_unknowns
        if amplitude_scale is None:
            amplitude_scale = problem.amplitude_scale((self.low, self.high))
        self.scale = np.full(n + 1, float(amplitude_scale))
        self.scale[n] = self.high - self.low
        self.base_scale = float(amplitude_scale)
        self.tol_residual = self.options.tol_residual * max(
            float(np.max(np.abs(problem.load))), 1e-300
        )
        # work arrays, allocated once per run
        self._R = np.empty(n)
        self._J = np.empty((n, n + 1))
        self._A = np.empty((n + 1, n + 1))
        self._piv = np.empty(n + 1, dtype=np.int64)
        self._y_pred = np.empty(n + 1)
        self._y_new = np.empty(n + 1)
        self._t_new = np.empty(n + 1)
        self._work = (
            self._R,
            self._J,
            self._A,
            self._piv,
            self._y_pred,
            self._y_new,
            self._t_new,
        )
        self._settings = self._settings_array()
        self._no_watch = np.zeros(_arclength.N_WATCH)
        self._no_calibration = None  # built on first use
        #: how the last compiled trace ended (``kernels.arclength`` codes)
        self.trace_outcome = 0

    def _settings_array(self) -> np.ndarray:
        """Options as the flat array of :mod:`hbmfric.kernels.arclength`."""
        o = self.options
        s = np.empty(_arclength.N_SETTINGS)
        s[_arclength.MIN_STEP] = o.min_step
        s[_arclength.MAX_STEP] = o.max_step
        s[_arclength.MAX_ANGLE] = o.max_angle
        s[_arclength.MAX_CORRECTION] = o.max_correction
        s[_arclength.CORNER_STEP] = o.corner_step
        s[_arclength.GROWTH] = o.growth
        s[_arclength.SHRINK] = o.shrink
        s[_arclength.TARGET_NEWTON] = o.target_newton
        s[_arclength.TOL_RESIDUAL] = self.tol_residual
        s[_arclength.TOL_STEP] = o.tol_step
        s[_arclength.MAX_NEWTON] = o.max_newton
        s[_arclength.BASE_SCALE] = self.base_scale
        s[_arclength.LOW] = self.low
        s[_arclength.HIGH] = self.high
        s[_arclength.CURVE_TOL] = o.curve_tolerance or 0.0
        s[_arclength.CURVE_COLUMN] = 0.0
        s[_arclength.CURVE_LAST] = 0.0
        column = self._curve_column()
        if column < 0:
            s[_arclength.CURVE_TOL] = 0.0
        else:
            s[_arclength.CURVE_COLUMN] = column
        return s

    def _curve_column(self) -> int:
        """Index among the unknowns of the first-harmonic cosine
        coefficient of the contact DOF (the drawn DOF of the curve rule),
        -1 without a first harmonic."""
        p = self.problem
        hn = [int(k) for k in p.harmonic_numbers]
        if 1 not in hn:
            return -1
        column = sum(1 if k == 0 else 2 for k in hn[: hn.index(1)])
        n_dof = p.n_unknowns // p.n_coef  # 1 for a problem condensed on a contact
        dof = int(getattr(p.system, "contact_dof", 0) or 0) if n_dof > 1 else 0
        return dof * p.n_coef + column

    # ------------------------------------------------------------------
    def _correct(self, y, y_pred, constraint, max_iter=None):
        o = self.options
        status, iterations, _ = _newton.correct(
            self.problem.kernel_problem,
            y,
            y_pred,
            constraint,
            self.scale,
            self.tol_residual,
            o.tol_step,
            o.max_newton if max_iter is None else max_iter,
            self._R,
            self._J,
            self._A,
            self._piv,
        )
        return int(status), int(iterations)

    def solve_at(
        self, omega: float, guess: np.ndarray, max_iter: int | None = None
    ) -> tuple[np.ndarray, int, int]:
        """Newton's method at fixed Ω from ``guess`` (flat X), with at most
        ``max_iter`` iterations (default ``options.max_newton``).

        Returns ``(y, status, iterations)``.
        """
        n = self.problem.n_unknowns
        y = np.empty(n + 1)
        y[:n] = guess
        y[n] = omega
        e_omega = np.zeros(n + 1)
        e_omega[n] = 1.0
        status, it = self._correct(y, y.copy(), e_omega, max_iter)
        return y, status, it

    def init(self, guess: np.ndarray | None = None) -> ContinuationState:
        """Solve the first point and set up the state."""
        n = self.problem.n_unknowns
        omega0 = self.low if self.direction > 0 else self.high
        guesses = [guess] if guess is not None else []
        guesses += [g[:n] for g in self.problem.initial_guesses(omega0)]
        t0 = np.zeros(n + 1)
        t0[n] = float(self.direction)
        state = ContinuationState(
            y=np.full(n + 1, np.nan),
            tangent=t0,
            step=self.options.initial_step,
            J=self._J,
        )
        # the first point is solved once: a generous iteration budget lets
        # Newton walk from a linearisation deep into gross slip
        budget = max(8 * self.options.max_newton, 100)
        for g in guesses:
            y, status, it = self.solve_at(omega0, g, budget)
            state.n_newton += it
            if status == _newton.CONVERGED:
                break
        else:
            y, status, it = self._load_ramp(omega0)
            state.n_newton += it
        if status == _newton.CONVERGED:
            state.y = y
            state.tangent = self._tangent(t0)
            state.points.append(y.copy())
            state.tangents_omega.append(state.tangent[n])
            state.tangents.append(state.tangent * self.scale)
            return state
        state.finished = True
        state.stop_reason = NO_START
        return state

    def _load_ramp(self, omega: float, max_solves: int = 60):
        """First point by natural continuation in the load amplitude.

        When neither linearisation is close enough for Newton (a contact
        deep in gross slip, a strongly nonlinear spring), start from a
        small fraction of the load, where the response is the stuck linear
        one, and raise it to the full load, each solve starting from the
        previous solution scaled to the new load; a failed increment is
        halved. Returns ``(y, status, evaluations)``.
        """
        load = self.problem.load  # the array the kernel problem holds
        full = load.copy()
        n = self.problem.n_unknowns
        evaluations = 0
        status = _newton.MAX_ITERATIONS
        y = np.full(n + 1, np.nan)
        try:
            lam = 1e-3
            load[:] = lam * full
            budget = max(8 * self.options.max_newton, 100)
            y, status, it = self.solve_at(
                omega, lam * self.problem.initial_guesses(omega)[0][:n], budget
            )
            evaluations += it
            if status != _newton.CONVERGED:
                return y, status, evaluations
            factor = 2.0
            for _ in range(max_solves):
                if lam >= 1.0:
                    break
                target = min(1.0, lam * factor)
                load[:] = target * full
                trial, status, it = self.solve_at(omega, y[:n] * (target / lam), budget)
                evaluations += it
                if status == _newton.CONVERGED:
                    y, lam = trial, target
                    factor = min(factor * 1.5, 4.0)
                else:
                    factor = 1.0 + 0.5 * (factor - 1.0)
                    if factor < 1.0 + 1e-3:
                        break
            status = _newton.CONVERGED if lam >= 1.0 else _newton.MAX_ITERATIONS
        finally:
            load[:] = full
        return y, status, evaluations

    def _tangent(self, previous: np.ndarray) -> np.ndarray:
        return _newton.tangent(self._J, previous, self.scale, self._A)

    def step(self, state: ContinuationState) -> ContinuationState:
        """One predictor–corrector step (accepted or rejected)."""
        if state.finished:
            return state
        if state.n_steps + state.n_rejected >= self.options.max_steps:
            return self._finish(state, MAX_STEPS)
        y = state.y.copy()
        tangent = state.tangent.copy()
        outcome, new_step, evaluations = _arclength.advance(
            self.problem.kernel_problem,
            y,
            tangent,
            state.step,
            self.scale,
            self._settings,
            *self._work,
        )
        state.n_newton += evaluations
        if outcome == _arclength.LEFT_RANGE:
            return self._land_on_boundary(state, self._y_new.copy())
        state.step = new_step
        if outcome in (_arclength.REJECTED, _arclength.STEP_TOO_SMALL):
            state.n_rejected += 1
            if outcome == _arclength.STEP_TOO_SMALL:
                if self._bridge(state):
                    return state
                return self._finish(state, MIN_STEP)
            return state
        self._record(
            state,
            y[None, :].copy(),
            (tangent * self.scale)[None, :],
            np.array([outcome]),
            self.scale[-1],
        )
        state.y = y
        state.tangent = tangent
        return state

    def _trace(
        self,
        state: ContinuationState,
        watch: np.ndarray | None = None,
        capacity: int = 256,
        calibration: tuple | None = None,
    ) -> ContinuationState:
        """Steps until the branch leaves the range, the step collapses,
        ``max_steps`` is spent, ``capacity`` points are accepted or (with a
        ``watch`` array) a point needs an adaptive-harmonics decision, in
        one compiled call (:func:`hbmfric.kernels.arclength.trace`;
        ``calibration``: the next level's problem and work arrays of
        :func:`hbmfric.kernels.arclength.stays`)."""
        budget = self.options.max_steps - (state.n_steps + state.n_rejected)
        if budget <= 0:
            return self._finish(state, MAX_STEPS)
        capacity = min(budget, capacity)
        n = self.problem.n_unknowns
        points = np.empty((capacity, n + 1))
        tangents = np.empty((capacity, n + 1))
        flags = np.zeros(capacity, dtype=np.int64)
        y = state.y.copy()
        tangent = state.tangent.copy()
        outcome, accepted, rejected, evaluations, new_step = _arclength.trace(
            self.problem.kernel_problem,
            y,
            tangent,
            state.step,
            self.scale,
            self._settings,
            budget,
            self._no_watch if watch is None else watch,
            points,
            tangents,
            flags,
            *self._work,
            self._placeholder_calibration() if calibration is None else calibration,
        )
        self.trace_outcome = int(outcome)
        state.n_newton += evaluations
        state.n_rejected += rejected
        state.step = new_step
        self._record(
            state, points[:accepted], tangents[:accepted], flags, self.scale[n]
        )
        state.y = y
        state.tangent = tangent
        if outcome == _arclength.RANGE_LEFT:
            return self._land_on_boundary(state, self._y_new.copy())
        if outcome == _arclength.STEP_BELOW_MIN:
            if self._bridge(state):
                return state
            return self._finish(state, MIN_STEP)
        if outcome == _arclength.BUDGET_SPENT:
            return self._finish(state, MAX_STEPS)
        return state

    def _bridge(self, state: ContinuationState) -> bool:
        """Step over a point where the corrector fails at every step size.

        Contact events make the residual piecewise smooth; at some seams
        (a contact barely slipping, a pair of displacement extremes being
        born or dying) Newton from the tangent predictor cycles whatever
        the step, and the step collapses although the branch goes on. The
        bridge solves at fixed Ω a little further along the branch
        (``BRIDGE_STEPS`` of the range width, in the direction of the
        tangent) from the tangent prediction and accepts the first solution
        within ``BRIDGE_TOLERANCE`` scaled arc lengths of that prediction,
        as a corner; the run then goes on from it at the initial step. No
        bridge where the tangent is nearly vertical in Ω (near a fold a
        fixed-Ω solve could land on another branch), outside the range, or
        after ``MAX_BRIDGES`` bridges. Returns whether a point was added.
        """
        if state.n_bridges >= MAX_BRIDGES:
            return False
        n = self.problem.n_unknowns
        t = state.tangent
        slope = float(t[n])
        if not abs(slope) >= BRIDGE_MIN_SLOPE:
            return False
        y = state.y
        width = self.high - self.low
        # dX/dΩ along the tangent, physical units
        rate = t[:n] * self.scale[:n] / (slope * self.scale[n])
        sign = 1.0 if slope > 0.0 else -1.0
        # the budget of the first point: the guess may be far (after a jump
        # of the adaptive run to a much larger basis, padded with zeros)
        budget = max(8 * self.options.max_newton, 100)
        for fraction in BRIDGE_STEPS:
            d_omega = sign * fraction * width
            omega = y[n] + d_omega
            if not self.low <= omega <= self.high:
                return False
            guess = y[:n] + d_omega * rate
            y_new, status, it = self.solve_at(omega, guess, budget)
            state.n_newton += it
            if status != _newton.CONVERGED or not np.all(np.isfinite(y_new)):
                continue
            distance = float(np.max(np.abs(y_new[:n] - guess) / self.scale[:n]))
            if not distance <= BRIDGE_TOLERANCE * fraction / abs(slope):
                continue
            tangent = self._tangent(t)
            if not np.all(np.isfinite(tangent)):
                continue
            # the run goes on away from the point it could not leave (at a
            # corner the sign rule of the tangent may point back)
            chord = (y_new - y) / self.scale
            if float(np.dot(tangent, chord)) < 0.0:
                tangent = -tangent
            flag = _arclength.ACCEPTED | _arclength.CORNER
            if (tangent[n] > 0.0) != (slope > 0.0):
                flag |= _arclength.FOLD
            self._record(
                state,
                y_new[None, :].copy(),
                (tangent * self.scale)[None, :],
                np.array([flag]),
                self.scale[n],
            )
            state.y = y_new
            state.tangent = tangent
            state.step = self.options.initial_step
            state.n_bridges += 1
            return True
        return False

    def _placeholder_calibration(self) -> tuple:
        """A calibration argument of the right types for a trace without
        adaptive harmonics (never used)."""
        if self._no_calibration is None:
            e1, e2 = np.zeros(1), np.zeros((1, 1))
            self._no_calibration = (self.problem.kernel_problem, e2, e1, e1, e2, e2, e1)
        return self._no_calibration

    @staticmethod
    def _record(state, points, tangents, flags, omega_scale) -> None:
        """Append accepted points with their physical tangents (shape
        (k, n + 1)) and their corner and fold marks."""
        first = len(state.points)
        for j in range(points.shape[0]):
            if flags[j] & _arclength.CORNER:
                state.corners.append(first + j)
            if flags[j] & _arclength.FOLD:
                state.folds.append(first + j)
        state.points.extend(points)
        state.tangents.extend(tangents.copy())
        state.tangents_omega.extend((tangents[:, -1] / omega_scale).tolist())
        state.n_steps += points.shape[0]

    def _land_on_boundary(self, state: ContinuationState, y_out: np.ndarray):
        """The step left the range: solve the last point on the boundary.

        The stop reason says through which end: the far one (``RANGE_END``)
        or, after a fold, the one the run started from (``RANGE_START``)."""
        n = self.problem.n_unknowns
        y_in = state.y
        left_high = y_out[n] > self.high
        bound = self.high if left_high else self.low
        s = (bound - y_in[n]) / (y_out[n] - y_in[n])
        guess = y_in[:n] + s * (y_out[:n] - y_in[:n])
        y, status, it = self.solve_at(bound, guess)
        state.n_newton += it
        if status == _newton.CONVERGED and np.all(np.isfinite(y)):
            state.points.append(y.copy())
            state.tangents_omega.append(state.tangent[n])
            # the tangent at the boundary point itself (Jacobian of its
            # last Newton iterate), the previous one if that fails
            t = self._tangent(state.tangent)
            if not np.all(np.isfinite(t)):
                t = state.tangent
            state.tangents.append(t * self.scale)
            state.y = y
            state.n_steps += 1
        far = left_high == (self.direction > 0)
        return self._finish(state, RANGE_END if far else RANGE_START)

    @staticmethod
    def _finish(state: ContinuationState, reason: str) -> ContinuationState:
        state.finished = True
        state.stop_reason = reason
        return state

    def run(self, guess: np.ndarray | None = None) -> tuple[ContinuationState, float]:
        """Trace the branch; returns the final state and the elapsed time, s."""
        start = time.perf_counter()
        state = self.init(guess)
        while not state.finished:
            state = self._trace(state)
        return state, time.perf_counter() - start
