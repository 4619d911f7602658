"""Pseudo-arclength continuation of HBM solutions in ``(X, Ω)``.

The continuation is an iterator with explicit state: :meth:`Continuation.init`
solves the first point and returns a :class:`ContinuationState`;
:meth:`Continuation.step` advances it by one accepted (or rejected) step,
so a user can drive a run by hand; :meth:`Continuation.run` traces the
whole branch in compiled stretches (:func:`hbmfric.kernels.steps.arclength.trace`,
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
fails at every step size) and no turn (:meth:`Continuation._turn`: a step
along the tangent of the piece beyond a seam, where the branch leaves the
seam at more than a right angle) gets past; it never raises on a numerical
failure and never stores a non-finite point.

The first point: Newton from the stuck and the free linearisations, then a
load ramp (:meth:`Continuation._load_ramp`), then arc-length continuation
in the load (:meth:`Continuation._load_arclength`), which goes round a fold
in the load where the solution the linear guesses lead to ceases to exist.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..kernels.linalg.krylov import REUSE_MODE, REUSE_MODE_BLOCKS, REUSE_TOL
from ..kernels.residuals.condensed import CondensedChainProblem
from ..kernels.residuals.pointer import chain_problem, residual_address
from ..kernels.steps import arclength as _arclength
from ..kernels.steps import newton as _newton
from ..laws.coulomb import Coulomb
from .options import ContinuationOptions

#: stop reasons
RANGE_END = "end of frequency range reached"
#: the path turned back (at a fold) and left through the end it started from
RANGE_START = "turned back at a fold and left the range at its starting end"
MAX_STEPS = "maximum number of steps reached"
MIN_STEP = "step size fell below min_step"
NO_START = "no converged starting point"
#: added to RANGE_END / RANGE_START when the step left the range but Newton
#: found no point on the boundary itself
NO_BOUNDARY_POINT = "but no converged point on the boundary"


def rigid_coulomb(system) -> bool:
    """Whether ``system`` holds a rigid Coulomb contact (DLFT)."""
    contacts = getattr(system, "contacts", None)
    laws = [c.law for c in contacts] if contacts else []
    laws.append(getattr(system, "contact", None))
    return any(isinstance(law, Coulomb) for law in laws)


#: scaled steps of a leap over a Coulomb seam (:meth:`Continuation._leap`)
LEAP_STEPS = (1e-3, 1e-2, 1e-1)
#: a leap's chord is kept only while its estimated curve error stays below
#: this factor times ``curve_tolerance``: a longer jump is not a traced
#: stretch of the branch, and the range it skips is left as a gap
LEAP_CURVE_FACTOR = 100.0
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
#: a turn past a seam (:meth:`Continuation._turn`): distances past the
#: stalled point (scaled) at which the Jacobian of the next piece is taken,
#: the probe distance that picks the tangent's sign, the steps tried, and
#: the cosine to the reversed old tangent above which a step leads back
TURN_PROBES = (1e-6, 1e-5, 1e-4)
TURN_PROBE = 1e-5
TURN_STEPS = (1e-3, 1e-4)
TURN_BACK = 0.99
#: arc-length continuation in the load (:meth:`Continuation._load_arclength`):
#: load factor of its first solve, most steps, smallest and largest step
LOAD_START = 1e-3
LOAD_STEPS = 400
LOAD_MIN_STEP = 1e-7
LOAD_MAX_STEP = 0.2
#: with the curve rule on, the first step of a run is this fraction of
#: ``initial_step``: the rule judges a chord by its ends and sizes each
#: step from the last chord's error (growing by at most ``growth``); the
#: first chord has no history, and at the full initial step (2 % of the
#: range) it stepped over a bump of the beam at Fn = 1 N between two
#: points that looked smooth (94-106 rad/s, 1.1e-4 off, chord estimate
#: 3.2e-5; the next steps were 2 rad/s)
FIRST_CURVE_STEP = 0.125


def _single_condensed(problem) -> bool:
    """Whether ``problem`` is condensed onto one contact coordinate (the
    paper beam), where the continuation keeps the tangent's straight
    predictor."""
    if not getattr(problem, "condensed", False):
        return False
    return int(getattr(problem, "n_coordinates", 1)) <= 1


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
        # the previous point and the point it preceded (second-order
        # predictor, kernels.steps.arclength.predict); NaN: none yet
        self._history = np.full((2, n + 1), np.nan)
        self._work = (
            self._R,
            self._J,
            self._A,
            self._piv,
            self._y_pred,
            self._y_new,
            self._t_new,
            self._history,
        )
        self._settings = self._settings_array()
        self._no_watch = np.zeros(_arclength.N_WATCH)
        self._no_calibration = None  # built on first use
        self._views = None  # (kernel problem, its chain view, address)
        #: how the last compiled trace ended (``kernels.steps.arclength`` codes)
        self.trace_outcome = 0
        self.trace_estimates = np.zeros(0)

    def _settings_array(self) -> np.ndarray:
        """Options as the flat array of :mod:`hbmfric.kernels.steps.arclength`."""
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
        s[_arclength.CURVE_POINT] = 0.0
        column = self._curve_column()
        if column < 0:
            s[_arclength.CURVE_TOL] = 0.0
        else:
            s[_arclength.CURVE_COLUMN] = column
        # the second-order predictor goes with the curve rule's short steps
        # (without it the step control is the old one, point for point).
        # Not on condensed problems: the paper beam's corrector takes three
        # evaluations per point from either predictor (2.9 against 3.1
        # from a predictor 15 times closer), and the longer steps the
        # parabola allows moved its adaptive levels up (H = 63 on 70
        # points; 1.2x the CPU time at Fn = 1 N; bench/README.md "Issue
        # 18, stop 26"). On problems condensed onto several contact
        # coordinates it is on: through microslip (each contact's stick-slip
        # transition in turn) the tangent's corrector needed three
        # evaluations at any step over a few 1e-4 and the Newton target
        # held the step at 1/2-1/4 of what the curve rule allows; with the
        # parabola two suffice and the curve rule sets the step (the lap
        # joint at H = 15: N = 10 348 points and 858 evaluations against
        # 587 and 1691, the same peak within 3e-8 and drawn curve,
        # bench/README.md "Issue 15, stop 28")
        s[_arclength.PREDICTOR] = float(
            s[_arclength.CURVE_TOL] > 0.0 and not _single_condensed(self.problem)
        )
        # a rigid Coulomb contact (DLFT): its branch has kinks wherever a
        # stick phase appears or goes (the tangent is one-sided there), so
        # the curve rule stops shortening a step at the kink floor and takes
        # it with its estimate (kernels.steps.arclength.KINK_FLOOR)
        s[_arclength.KINK_FLOOR] = float(
            rigid_coulomb(getattr(self.problem, "system", None))
        )
        return s

    def _curve_column(self) -> int:
        """Index among the unknowns of the cosine coefficient of the
        forced harmonic (the first; ``ν`` for a subharmonic balance, whose
        unknowns are harmonics of ``Ω/ν``) of the contact DOF (the drawn
        DOF of the curve rule), -1 without it."""
        p = self.problem
        hn = [int(k) for k in p.harmonic_numbers]
        forced = int(getattr(p, "subharmonic", 1) or 1)
        if forced not in hn:
            return -1
        column = sum(1 if k == 0 else 2 for k in hn[: hn.index(forced)])
        n_dof = p.n_unknowns // p.n_coef  # 1 for a problem condensed on a contact
        dof = int(getattr(p.system, "contact_dof", 0) or 0) if n_dof > 1 else 0
        return dof * p.n_coef + column

    # ------------------------------------------------------------------
    def _correct(self, y, y_pred, constraint, max_iter=None):
        o = self.options
        status, iterations, _ = _newton.correct(
            self._chain_problem(),
            self._residual_at(),
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

    def init(
        self, guess: np.ndarray | None = None, start_omega: float | None = None
    ) -> ContinuationState:
        """Solve the first point and set up the state: Newton from ``guess``
        and the linearisations, then the load ramp, then arc-length
        continuation in the load (module doc). The first point is at the
        range's starting end, or at ``start_omega`` inside the range."""
        n = self.problem.n_unknowns
        omega0 = self.low if self.direction > 0 else self.high
        if start_omega is not None:
            omega0 = float(start_omega)
        guesses = [guess] if guess is not None else []
        guesses += [g[:n] for g in self.problem.initial_guesses(omega0)]
        t0 = np.zeros(n + 1)
        t0[n] = float(self.direction)
        state = ContinuationState(
            y=np.full(n + 1, np.nan),
            tangent=t0,
            step=self._first_step(),
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
        if status != _newton.CONVERGED:
            y, status, it = self._load_arclength(omega0)
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

    def _load_arclength(self, omega: float, max_steps: int = LOAD_STEPS):
        """First point by pseudo-arclength continuation in the load factor.

        The load ramp (:meth:`_load_ramp`) follows the solution of the
        stuck linear start in the load factor ``λ`` at fixed Ω and stalls
        where that solution ceases to exist: at a fold in ``λ`` (a
        hardening spring above its linear resonance, where the
        non-resonant solution merges with the middle one before full load
        and only the resonant one is left, so that Newton from the linear
        guesses stagnates at the fold). Here the path in ``(X, λ)`` is
        followed by arc length, around such folds, until it crosses
        ``λ = 1``; the point there is then solved at fixed Ω by Newton from
        the interpolation of the two points around the crossing.

        Scaled variables: ``X`` divided by the peak of the linear responses
        at full load (the size a solution is expected to have), ``λ`` as is.
        Steps follow the acceptance tests of the continuation (converged,
        correction at most ``max_correction`` times the step, turn at most
        ``max_angle``); the path is abandoned when it returns to ``λ <= 0``,
        after ``max_steps`` steps or below ``LOAD_MIN_STEP``.

        Parameters
        ----------
        omega : float
            Frequency of the point, rad/s.
        max_steps : int, optional
            Most arc-length steps in the load.

        Returns
        -------
        y : ndarray, shape (n_unknowns + 1,)
            ``[X, Ω]`` at full load (NaN when nothing converged).
        status : int
            ``CONVERGED`` or a failure code of :mod:`hbmfric.kernels.steps.newton`.
        evaluations : int
            Residual evaluations spent.
        """
        problem = self.problem
        load = problem.load  # the array the kernel problem holds
        full = load.copy()
        n = problem.n_unknowns
        o = self.options
        guesses = problem.initial_guesses(omega)
        sx = max(max(float(np.max(np.abs(g[:n]))) for g in guesses), 1e-300)
        scale = np.ones(n + 1)
        scale[:n] = sx
        tol = self.tol_residual
        evaluations = 0
        y = np.empty(n + 1)
        y[n] = omega

        def evaluate(w):
            nonlocal evaluations
            load[:] = w[n] * full
            y[:n] = w[:n]
            R, J, state = problem.residual(y)
            evaluations += 1
            if state < 0 or not np.all(np.isfinite(R)):
                return None, None
            return R, J

        def bordered(J, d, row):
            """[J_X diag(sx), dR/dλ; row] with equilibrated rows, and the
            row factors."""
            A = np.empty((n + 1, n + 1))
            A[:n, :n] = J[:, :n] * scale[:n]
            A[:n, n] = d
            rows = 1.0 / np.maximum(np.max(np.abs(A[:n]), axis=1), 1e-300)
            A[:n] *= rows[:, None]
            A[n] = row
            return A, rows

        def correct(w, w_pred, t, d):
            """Newton on the hyperplane through w_pred orthogonal to t."""
            w = w.copy()
            R, J = evaluate(w)
            if R is None:
                return None, 0
            res = float(np.max(np.abs(R)))
            for it in range(o.max_newton):
                A, rows = bordered(J, d, t)
                b = np.empty(n + 1)
                b[:n] = -R * rows
                b[n] = -float(np.dot(t, (w - w_pred) / scale))
                try:
                    dw = np.linalg.solve(A, b) * scale
                except np.linalg.LinAlgError:
                    return None, it
                if not np.all(np.isfinite(dw)):
                    return None, it
                step = float(np.max(np.abs(dw / scale)))
                if res <= tol and step <= o.tol_step:
                    return w, it
                lam = 1.0
                for _ in range(10):
                    trial = w + lam * dw
                    Rt, Jt = evaluate(trial)
                    rt = float(np.max(np.abs(Rt))) if Rt is not None else np.inf
                    if rt <= tol or rt < (1.0 - 1e-4 * lam) * res:
                        break
                    lam *= 0.5
                if Rt is None:
                    return None, it
                w, R, J, res = trial, Rt, Jt, rt
            return (w, o.max_newton) if res <= tol else (None, o.max_newton)

        def tangent(J, d, previous):
            A, _ = bordered(J, d, previous)
            rhs = np.zeros(n + 1)
            rhs[n] = 1.0
            try:
                t = np.linalg.solve(A, rhs)
            except np.linalg.LinAlgError:
                return None
            norm = float(np.linalg.norm(t))
            return t / norm if np.isfinite(norm) and norm > 0.0 else None

        status = _newton.MAX_ITERATIONS
        out = np.full(n + 1, np.nan)
        try:
            lam0 = LOAD_START
            load[:] = lam0 * full
            budget = max(8 * o.max_newton, 100)
            y0, status, it = self.solve_at(omega, lam0 * guesses[0][:n], budget)
            evaluations += it
            if status != _newton.CONVERGED:
                return out, status, evaluations
            status = _newton.MAX_ITERATIONS
            w = np.append(y0[:n], lam0)
            # dR/dλ: the residual is affine in the load
            R1, _ = evaluate(np.append(w[:n], 1.0))
            R0, J0 = evaluate(np.append(w[:n], 0.0))
            if R1 is None or R0 is None:
                return out, status, evaluations
            d = R1 - R0
            e_lam = np.zeros(n + 1)
            e_lam[n] = 1.0
            t = tangent(J0, d, e_lam)
            ds = 0.05
            for _ in range(max_steps):
                if t is None or ds < LOAD_MIN_STEP:
                    break
                w_pred = w + ds * t * scale
                w_new, it = correct(w_pred, w_pred, t, d)
                ok = w_new is not None
                if ok:
                    _, J = evaluate(w_new)
                    t_new = tangent(J, d, t) if J is not None else None
                    ok = (
                        t_new is not None
                        and float(np.max(np.abs(w_new - w_pred) / scale))
                        <= o.max_correction * ds
                        and float(np.dot(t_new, t)) >= np.cos(o.max_angle)
                    )
                if not ok:
                    ds *= o.shrink
                    continue
                if w_new[n] >= 1.0:
                    # crossed full load: solve there from the interpolation
                    s = (1.0 - w[n]) / (w_new[n] - w[n])
                    guess = w[:n] + s * (w_new[:n] - w[:n])
                    load[:] = full
                    y1, st, it = self.solve_at(omega, guess, budget)
                    evaluations += it
                    if st == _newton.CONVERGED:
                        return y1, st, evaluations
                    ds *= o.shrink  # land nearer λ = 1
                    continue
                if w_new[n] <= 0.0:
                    break  # the path went back to no load
                w, t = w_new, t_new
                if it <= o.target_newton:
                    ds = min(ds * o.growth, LOAD_MAX_STEP)
        finally:
            load[:] = full
        return out, status, evaluations

    def _first_step(self) -> float:
        """Step of the first continuation step (``FIRST_CURVE_STEP``)."""
        o = self.options
        if self._settings[_arclength.CURVE_TOL] > 0.0:
            return max(FIRST_CURVE_STEP * o.initial_step, o.min_step)
        return o.initial_step

    def _tangent(self, previous: np.ndarray) -> np.ndarray:
        layout = self._block_layout()
        if layout is not None:
            out = np.empty(self._A.shape[0])
            if _newton.block_tangent(
                self._J, previous, self.scale, self._A, *layout, out
            ):
                return out
        return _newton.tangent(self._J, previous, self.scale, self._A)

    def _block_layout(self) -> tuple | None:
        """Arguments of :func:`hbmfric.kernels.steps.newton.block_tangent`
        after the Jacobian (coordinates, coefficients per coordinate, column
        of the first cosine, slipping coordinates corrected at most, GMRES
        iterations at most, relative residual) for a problem condensed onto
        several contact coordinates whose corrector solves on the harmonic
        blocks (as it solves the tangents inside the trace; stop 32: the
        dense LU of order 1345 cost 0.6 s per tangent on the lap joint at
        N = 100); None for any other problem (the dense LU of
        :func:`~hbmfric.kernels.steps.newton.tangent`)."""
        kp = self._chain_problem()
        if not isinstance(kp, CondensedChainProblem):
            return None
        solver = kp.solver
        state = solver[3]
        if (
            solver[0].shape[0] != self._A.shape[0]
            or state[REUSE_MODE] != REUSE_MODE_BLOCKS
        ):
            return None
        hn = kp.harmonic_numbers
        first = 1 if hn.size > 0 and hn[0] == 0 else 0
        return (
            int(kp.law_codes.size),
            int(kp.inverse.shape[1]),
            first,
            int(solver[8][1].size),
            int(solver[2].shape[0] - 1),
            float(state[REUSE_TOL]),
        )

    def step(self, state: ContinuationState) -> ContinuationState:
        """One predictor–corrector step (accepted or rejected)."""
        if state.finished:
            return state
        if state.n_steps + state.n_rejected >= self.options.max_steps:
            return self._finish(state, MAX_STEPS)
        y = state.y.copy()
        tangent = state.tangent.copy()
        outcome, new_step, evaluations = _arclength.advance(
            self._chain_problem(),
            self._residual_at(),
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
                if self._bridge(state) or self._turn(state) or self._leap(state):
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
        one compiled call (:func:`hbmfric.kernels.steps.arclength.trace`;
        ``calibration``: the next level's problem and work arrays of
        :func:`hbmfric.kernels.steps.arclength.stays`)."""
        budget = self.options.max_steps - (state.n_steps + state.n_rejected)
        if budget <= 0:
            return self._finish(state, MAX_STEPS)
        capacity = min(budget, capacity)
        n = self.problem.n_unknowns
        points = np.empty((capacity, n + 1))
        tangents = np.empty((capacity, n + 1))
        flags = np.zeros(capacity, dtype=np.int64)
        estimates = np.full(capacity, np.nan)
        y = state.y.copy()
        tangent = state.tangent.copy()
        outcome, accepted, rejected, evaluations, new_step = _arclength.trace(
            self._chain_problem(),
            self._residual_at(),
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
            estimates,
            *self._work,
            self._placeholder_calibration() if calibration is None else calibration,
        )
        self.trace_outcome = int(outcome)
        #: calibrated truncation estimate of each point the compiled
        #: stretch accepted (NaN where it did not calibrate)
        self.trace_estimates = estimates[:accepted]
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
            if self._bridge(state) or self._turn(state) or self._leap(state):
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

    def _leap(self, state: ContinuationState) -> bool:
        """Step over a seam of a rigid Coulomb contact's branch with the
        step control of before the curve rule.

        The DLFT residual is discontinuous where a stick phase is born or
        dies at some sample (the beam at f_s = 1 and 2 N, H = 15, 62.1 and
        77.1 Hz): the curve rule's short steps land next to it and the
        corrector fails at every shorter step, where the longer steps of the
        former step control passed over it. Tries ``LEAP_STEPS`` with the
        curve rule off (``corner_step`` and above; the usual acceptance
        tests, a corner below ``corner_step``) and records the first point
        accepted as a corner; the chord to it keeps its estimate in
        ``Branch.curve_errors`` (warned about when above the tolerance). A
        leap whose chord estimate exceeds ``LEAP_CURVE_FACTOR`` times the
        tolerance is refused (the run stops there and the range it would
        skip stays a gap of the branch).
        Only for rigid Coulomb contacts with the curve rule on, at most
        ``MAX_BRIDGES`` times a run (counted with the bridges)."""
        s = self._settings
        if s[_arclength.KINK_FLOOR] == 0.0 or not s[_arclength.CURVE_TOL] > 0.0:
            return False
        if state.n_bridges >= MAX_BRIDGES:
            return False
        tol = s[_arclength.CURVE_TOL]
        s[_arclength.CURVE_TOL] = 0.0
        try:
            for step in LEAP_STEPS:
                y = state.y.copy()
                tangent = state.tangent.copy()
                scale = self.scale.copy()
                outcome, _, evaluations = _arclength.advance(
                    self.problem.kernel_problem,
                    self._residual_at(),
                    y,
                    tangent,
                    max(step, self.options.corner_step),
                    scale,
                    s,
                    *self._work,
                )
                state.n_newton += evaluations
                if not outcome & _arclength.ACCEPTED:
                    continue
                curve = _arclength.problem_chord_error(
                    self.problem.kernel_problem,
                    state.y,
                    state.tangent,
                    y,
                    tangent,
                    scale,
                    int(s[_arclength.CURVE_COLUMN]),
                    s[_arclength.BASE_SCALE],
                    True,
                )
                if not curve <= LEAP_CURVE_FACTOR * tol:
                    # a longer step only leaps further
                    return False
                self.scale[:] = scale
                self._record(
                    state,
                    y[None, :].copy(),
                    (tangent * self.scale)[None, :],
                    np.array([outcome | _arclength.CORNER]),
                    self.scale[-1],
                )
                state.y = y
                state.tangent = tangent
                state.step = self.options.initial_step
                state.n_bridges += 1
                return True
        finally:
            s[_arclength.CURVE_TOL] = tol
        return False

    def _turn(self, state: ContinuationState) -> bool:
        """Go on past a seam where the branch turns by more than a right
        angle.

        Where the residual is only piecewise smooth (a contact law's
        Jacobian jumps when a pair of reversals of the contact displacement
        is born or dies), the branch can run into a seam and leave it along
        a direction at more than 90° to the one it came from: a fold
        without a smooth turn (the stiff Masing laws in gross slip at the
        third superharmonic resonance, where the branch zigzags in Ω). The
        predictor along the old tangent then points away from every
        solution and the corrector fails at every step size, so the step
        collapses at the seam; a fixed-Ω bridge does not apply where the
        tangent is nearly vertical in Ω.

        The tangent of the piece beyond the seam is the null direction of
        the Jacobian just past it (``TURN_PROBES`` along the old tangent);
        its sign is the one along which the residual stays smaller (the
        other sign enters the old piece's side, where the residual grows
        at first order). From the point, a step of ``TURN_STEPS`` along
        that tangent is accepted by the ordinary tests relative to it
        (converged, correction at most ``max_correction`` times the step,
        turn at most ``max_angle``) and when it does not lead back along
        the traced piece; the point is recorded as a corner (and a fold when
        Ω turns). Counted with the bridges (at most ``MAX_BRIDGES``).

        Parameters
        ----------
        state : ContinuationState
            Stalled state; on success its point, tangent (unit, scaled,
            shape (n_unknowns + 1,)) and step are replaced.

        Returns
        -------
        bool
            Whether a point was added.
        """
        if state.n_bridges >= MAX_BRIDGES:
            return False
        n = self.problem.n_unknowns
        o = self.options
        y0 = state.y
        t0 = state.tangent
        scale = self.scale
        work = self._work
        R, J, A, piv, y_pred, y_new, t_new = work[:7]
        for delta in TURN_PROBES:
            _, J_side, aft = self.problem.residual(y0 + delta * t0 * scale)
            state.n_newton += 1
            if aft < 0:
                continue
            t1 = _newton.tangent(J_side, t0, scale, A)
            if not np.all(np.isfinite(t1)):
                continue
            sizes = []
            for sign in (1.0, -1.0):
                r, _, aft = self.problem.residual(y0 + sign * TURN_PROBE * t1 * scale)
                state.n_newton += 1
                sizes.append(float(np.max(np.abs(r))) if aft >= 0 else np.inf)
            if not min(sizes) < np.inf:
                continue
            t1 = t1 if sizes[0] <= sizes[1] else -t1
            for ds in TURN_STEPS:
                y = y0.copy()
                status, evaluations, _, distance, angle = _newton.palc_step(
                    self._chain_problem(),
                    self._residual_at(),
                    y,
                    t1,
                    ds,
                    scale,
                    self.tol_residual,
                    o.tol_step,
                    o.max_newton,
                    R,
                    J,
                    A,
                    piv,
                    y_pred,
                    y_new,
                    t_new,
                )
                state.n_newton += evaluations
                if status != _newton.CONVERGED:
                    continue
                if not (distance <= o.max_correction * ds and angle <= o.max_angle):
                    continue
                if not self.low <= y_new[n] <= self.high:
                    continue
                chord = (y_new - y0) / scale
                length = float(np.linalg.norm(chord))
                if not length > 0.0 or -float(np.dot(chord, t0)) > TURN_BACK * length:
                    continue  # back along the traced piece
                flag = _arclength.ACCEPTED | _arclength.CORNER
                if (t_new[n] > 0.0) != (t0[n] > 0.0):
                    flag |= _arclength.FOLD
                tangent = t_new.copy()
                self._record(
                    state,
                    y_new[None, :].copy(),
                    (tangent * self.scale)[None, :],
                    np.array([flag]),
                    self.scale[n],
                )
                state.y = y_new.copy()
                state.tangent = tangent
                state.step = ds
                state.n_bridges += 1
                return True
        return False

    def _kernel_views(self) -> tuple:
        """``(kernel problem, chain problem, residual address)`` of the
        problem's current kernel problem, formed again only when the
        problem holds another one (``plan_band`` replaces it)."""
        kp = self.problem.kernel_problem
        views = self._views
        if views is None or views[0] is not kp:
            views = self._views = (kp, chain_problem(kp), residual_address(kp))
        return views

    def _residual_at(self) -> int:
        """Address of the compiled residual of the problem's kernel problem
        (:func:`hbmfric.kernels.residuals.pointer.residual_address`), which
        the continuation kernels call."""
        return self._kernel_views()[2]

    def _chain_problem(self):
        """The problem's kernel problem as the continuation kernels take it
        (:func:`hbmfric.kernels.residuals.pointer.chain_problem`: one type
        for every law family)."""
        return self._kernel_views()[1]

    def _placeholder_calibration(self) -> tuple:
        """A calibration argument of the right types for a trace without
        adaptive harmonics (never used)."""
        if self._no_calibration is None:
            e1, e2 = np.zeros(1), np.zeros((1, 1))
            kp = self._chain_problem()
            self._no_calibration = (kp, 0, e2, e2, e1, e1, e1, e2, e2, e1)
        return self._no_calibration

    @staticmethod
    def _record(state, points, tangents, flags, omega_scale) -> None:
        """Append accepted points with their physical tangents (shape
        (k, n + 1)) and their corner and fold marks."""
        first = len(state.points)
        marks = flags[: points.shape[0]]
        if np.any(marks & (_arclength.CORNER | _arclength.FOLD)):
            corners = np.flatnonzero(marks & _arclength.CORNER)
            state.corners.extend((first + corners).tolist())
            folds = np.flatnonzero(marks & _arclength.FOLD)
            state.folds.extend((first + folds).tolist())
        state.points.extend(points)
        # every caller passes arrays of its own (a trace's fresh buffers):
        # the rows are kept as they are, as the points' are
        state.tangents.extend(tangents)
        state.tangents_omega.extend((tangents[:, -1] / omega_scale).tolist())
        state.n_steps += points.shape[0]

    def _land_on_boundary(self, state: ContinuationState, y_out: np.ndarray):
        """The step left the range: solve the last point on the boundary.

        The stop reason says through which end: the far one (``RANGE_END``)
        or, after a fold, the one the run started from (``RANGE_START``),
        and, when Newton finds no point on the boundary (the branch ends
        short of it), ``NO_BOUNDARY_POINT`` with where the last point is."""
        n = self.problem.n_unknowns
        y_in = state.y
        left_high = y_out[n] > self.high
        bound = self.high if left_high else self.low
        s = (bound - y_in[n]) / (y_out[n] - y_in[n])
        guess = y_in[:n] + s * (y_out[:n] - y_in[:n])
        y, status, it = self.solve_at(bound, guess)
        state.n_newton += it
        far = left_high == (self.direction > 0)
        reason = RANGE_END if far else RANGE_START
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
        else:
            reason += (
                f" ({NO_BOUNDARY_POINT} Ω = {bound:.6g} rad/s; last point at "
                f"Ω = {y_in[n]:.6g} rad/s)"
            )
        return self._finish(state, reason)

    @staticmethod
    def _finish(state: ContinuationState, reason: str) -> ContinuationState:
        state.finished = True
        state.stop_reason = reason
        return state

    def run(
        self, guess: np.ndarray | None = None, start_omega: float | None = None
    ) -> tuple[ContinuationState, float]:
        """Trace the branch (from ``start_omega`` inside the range, if
        given, else from its starting end); returns the final state and the
        elapsed time, s."""
        start = time.perf_counter()
        state = self.init(guess, start_omega)
        while not state.finished:
            state = self._trace(state)
        return state, time.perf_counter() - start
