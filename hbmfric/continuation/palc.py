"""Pseudo-arclength continuation of HBM solutions in ``(X, Ω)``.

The continuation is an iterator with explicit state: :meth:`Continuation.init`
solves the first point and returns a :class:`ContinuationState`;
:meth:`Continuation.step` advances it by one accepted (or rejected) step; the
driver :meth:`Continuation.run` is a short loop over ``step`` that a user can
also write by hand.

One step: tangent predictor ``y_p = y + ds t`` (``t`` from
``[J; t_prevᵀ] t = [0; 1]``, normalised, direction kept), corrector on the
hyperplane through ``y_p`` orthogonal to ``t``, then acceptance tests: Newton
converged, tangent turned less than ``max_angle``, corrected point not far
from the predictor (a short step is accepted at a corner of the branch,
where a contact transition turns the tangent abruptly). Folds (turning
points) are flagged when the Ω-component of the tangent changes sign. The
run ends at the end of the frequency range (the last point solved exactly
at the boundary), at ``max_steps``, or when the step falls below
``min_step``; it never raises on a numerical failure and never stores a
non-finite point.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..kernels import newton as _newton
from .options import ContinuationOptions
from .step_control import StepController

#: stop reasons
RANGE_END = "end of frequency range reached"
MAX_STEPS = "maximum number of steps reached"
MIN_STEP = "step size fell below min_step"
NO_START = "no converged starting point"


@dataclass
class ContinuationState:
    """Mutable state of a continuation run (points in physical units)."""

    y: np.ndarray
    tangent: np.ndarray
    step: float
    J: np.ndarray
    points: list = field(default_factory=list)
    tangents_omega: list = field(default_factory=list)
    folds: list = field(default_factory=list)
    corners: list = field(default_factory=list)
    n_steps: int = 0
    n_rejected: int = 0
    n_newton: int = 0
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
        self.problem = problem
        self.low, self.high = float(omega_range[0]), float(omega_range[1])
        self.direction = 1 if direction >= 0 else -1
        self.options = options or ContinuationOptions()
        self.controller = StepController(self.options)
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
        o = self.options
        n = self.problem.n_unknowns
        if state.n_steps + state.n_rejected >= o.max_steps:
            return self._finish(state, MAX_STEPS)
        ds = state.step
        status, it, effort, distance, angle = _newton.palc_step(
            self.problem.kernel_problem,
            state.y,
            state.tangent,
            ds,
            self.scale,
            self.tol_residual,
            o.tol_step,
            o.max_newton,
            self._R,
            self._J,
            self._A,
            self._piv,
            self._y_pred,
            self._y_new,
            self._t_new,
        )
        state.n_newton += it
        ok = status == _newton.CONVERGED
        corner = False
        if ok:
            smooth = angle <= o.max_angle and distance <= o.max_correction * ds
            corner = (
                not smooth
                and ds <= o.corner_step
                and (distance <= 2.0 * ds or self._short_turn(state.y))
            )
            ok = smooth or corner
        if not ok:
            state.n_rejected += 1
            state.step = self.controller.reject(ds)
            if state.step < o.min_step:
                return self._finish(state, MIN_STEP)
            return state
        # accepted
        if corner:
            state.corners.append(len(state.points))
            angle = 0.0
        y = self._y_new.copy()
        omega = y[n]
        if omega > self.high or omega < self.low:
            return self._land_on_boundary(state, y)
        new_tangent = self._t_new.copy()
        t_old = state.tangent[n]
        t_now = new_tangent[n]
        if t_now != 0.0 and (t_old == 0.0 or (t_now > 0.0) != (t_old > 0.0)):
            state.folds.append(len(state.points))
        state.y = y
        state.tangent = new_tangent
        state.points.append(y)
        state.tangents_omega.append(t_now)
        state.n_steps += 1
        state.step = self.controller.accept(ds, effort, angle)
        self._follow_amplitude(state)
        return state

    def _follow_amplitude(self, state: ContinuationState) -> None:
        """Keep the displacement scale at least a tenth of the amplitude.

        The base scale is the peak of the linearised response; a branch
        may climb far above it (a resonance that friction cannot bound, at
        small damping, peaks at ``(F - 4 f_s/π) / (c Ω)``, 4000 base scales
        in the stress matrix) and would then need as many steps as it is
        scales high. Once the largest coefficient exceeds 15 base scales,
        the scale follows a tenth of it (back down to the base scale as the
        branch descends), so that a step changes the amplitude by at most
        ``10 max_step`` relative to itself. Branches within 15 base scales
        (every ordinary FRF) keep the base scale and their resolution. The
        tangent is carried over to the new scaled variables.
        """
        n = self.problem.n_unknowns
        target = max(self.base_scale, 0.1 * _newton._norm_inf(state.y[:n]))
        current = self.scale[0]
        if current / 1.5 <= target <= 1.5 * current:
            return
        t = state.tangent * self.scale
        self.scale[:n] = target
        t /= self.scale
        state.tangent = t / np.linalg.norm(t)

    def _short_turn(self, y: np.ndarray) -> bool:
        """A sharp corner: the new branch piece leaves the corner at a large
        angle ``α`` to the old tangent, so the corrector's hyperplane meets it
        about ``ds tan α`` from the predictor (``α = 88°`` where a stuck
        resonance at ζ = 1e-4 starts to slip), beyond the ``2 ds`` of the
        plain corner rule at every step size. Accepted when the corrected
        point is within ``corner_step`` of the current one (scaled) and the
        chord to it runs along the new tangent (cosine >= 0.9): a step that
        short along the new piece cannot have left the branch."""
        chord = (self._y_new - y) / self.scale
        length = float(np.linalg.norm(chord))
        if not length <= self.options.corner_step:
            return False
        return float(np.dot(chord, self._t_new)) >= 0.9 * length

    def _land_on_boundary(self, state: ContinuationState, y_out: np.ndarray):
        """The step left the range: solve the last point on the boundary."""
        n = self.problem.n_unknowns
        y_in = state.y
        bound = self.high if y_out[n] > self.high else self.low
        s = (bound - y_in[n]) / (y_out[n] - y_in[n])
        guess = y_in[:n] + s * (y_out[:n] - y_in[:n])
        y, status, it = self.solve_at(bound, guess)
        state.n_newton += it
        if status == _newton.CONVERGED and np.all(np.isfinite(y)):
            state.points.append(y.copy())
            state.tangents_omega.append(state.tangent[n])
            state.y = y
            state.n_steps += 1
        return self._finish(state, RANGE_END)

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
            state = self.step(state)
        return state, time.perf_counter() - start
