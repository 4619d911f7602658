"""The periodic steady state at one frequency: :func:`periodic_solution`.

Newton's method at fixed Ω converges only from a start close enough to a
solution; near a resonance with a stiff contact in gross slip neither
linearisation (stuck, free) is. The solve therefore tries, in this order,
and stops at the first converged solution:

1. ``"newton"``: Newton from the user's ``initial_guess`` (if any), then
   from the stuck and the free linearisations, with the generous iteration
   budget a continuation gives its first point;
2. ``"load ramp"``: natural continuation in the load amplitude at the
   target Ω from a small fraction of the load, where the response is the
   stuck linear one (:meth:`hbmfric.continuation.Continuation._load_ramp`);
3. ``"continuation from below"`` / ``"continuation from above"``:
   pseudo-arclength continuation in Ω (the engine of :func:`hbmfric.frf`,
   same discretisation and options) from a frequency far below the target
   (``Ω/2``, else ``Ω/4``) up to it, else from far above (``2 Ω``, else
   ``4 Ω``) down to it. The first crossing of the target along the path is
   interpolated between its two branch points and solved by Newton at the
   target Ω.

A result is converged when ``max |R| <= options.tol_residual * max |F|``
(Newton's step test aside, which a solution on a seam of the piecewise
smooth residual can keep failing). When nothing converges the call warns
(:class:`~hbmfric.ConvergenceWarning`) or raises
(:class:`~hbmfric.ConvergenceError`), and the returned coefficients are the
iterate with the smallest residual.
"""

from __future__ import annotations

import dataclasses
import time
import warnings

import numpy as np

from . import _memory
from ._validate import finite_float
from .continuation import Continuation, ContinuationOptions
from .continuation.adaptive import LADDER, START
from .errors import AccuracyWarning, ConvergenceError, ConvergenceWarning
from .hbm import HBMProblem
from .kernels.aft.schemes import STATE_NAMES, STUCK
from .kernels.steps import newton as _newton
from .results import PeriodicSolution
from .systems.craig_bampton import warn_above_cutoff

#: ``harmonics="auto"`` stops when two successive ladder steps change the
#: amplitudes by at most ``harmonic_tolerance / SETTLE_FACTOR``; measured
#: against H = 63 (bench/README.md, "periodic_solution maps") the error is
#: then at most 0.6 times the tolerance
SETTLE_FACTOR = 1.5

#: how a solution was obtained (``PeriodicSolution.method``)
NEWTON = "newton"
LOAD_RAMP = "load ramp"
FROM_BELOW = "continuation from below"
FROM_ABOVE = "continuation from above"
ZERO_FORCE = "zero force"
FAILED = "failed"

#: start frequencies of the continuation fallback, as factors of the target Ω
BELOW_STARTS = (0.5, 0.25)
ABOVE_STARTS = (2.0, 4.0)
#: the trace runs this fraction of its range past the target, so that the
#: crossing lies between two branch points
OVERSHOOT = 0.02

BRANCH_SIDES = (None, "below", "above")
ON_FAILURE = ("warn", "raise")


def periodic_solution(
    system,
    force: float,
    omega: float,
    harmonics: int | str = "auto",
    *,
    n_time: int | None = None,
    symmetry: bool | None = None,
    aft: str = "auto",
    initial_guess=None,
    options: ContinuationOptions | None = None,
    condense: bool | None = None,
    branch_side: str | None = None,
    harmonic_tolerance: float = 1e-4,
    on_failure: str = "warn",
) -> PeriodicSolution:
    """Periodic steady state at one frequency.

    Newton's method at fixed Ω, started from ``initial_guess``, from the
    linearisations, by a load ramp and finally by continuation in Ω from a
    frequency far below (then far above) the target (module docstring of
    :mod:`hbmfric.periodic`); ``PeriodicSolution.method`` says which one
    succeeded.

    Parameters
    ----------
    system : Oscillator or compatible system
    force : float
        Amplitude ``F`` of the forcing ``F cos Ωt``, N. With ``F = 0`` (and
        no static load) the rest state is returned at once: zero, or where a
        contact carries a force at zero displacement (an unsymmetric
        :class:`ModifiedDahl` law, a :class:`Contact2D` preload without a
        static load) the static balance, solved by Newton.
    omega : float
        Forcing pulsation Ω, rad/s (> 0).
    harmonics : int or "auto", default "auto"
        Highest harmonic ``H``. ``"auto"``: solve at ``H = 7`` and climb the
        ladder of :mod:`hbmfric.continuation.adaptive` (11, 15, 21, ...,
        63), each level started from the previous solution, until the
        first-harmonic amplitude and half the peak-to-peak value at the
        contact DOF change by less than ``harmonic_tolerance / 1.5``
        (relative) over two steps of the ladder in a row (convergence in
        ``H`` is not monotone); the finest level is returned (an
        :class:`~hbmfric.AccuracyWarning` if ``H = 63`` does not get
        there). Measured against ``H = 63`` on SDOF Jenkins (kt/k = 3,
        30), Menq and Iwan (kt/k = 30) at F = 0.05, 0.5, 2 and 30
        frequencies each: error at most 0.6 times the tolerance
        (``bench/README.md``, "periodic_solution maps").
    n_time, symmetry, aft
        As in :func:`hbmfric.frf` (``n_time`` not with ``"auto"``).
    initial_guess : PeriodicSolution or ndarray, optional
        First start for Newton (selects the branch where several coexist
        and Newton converges from it); an array holds the coefficients of
        all DOFs in the layout of this discretisation (with ``condense``,
        of the contact DOF only, or of the contact coordinates for several
        contacts), so it needs an explicit integer
        ``harmonics``; with ``harmonics="auto"`` only a
        :class:`PeriodicSolution` is accepted.
    options : ContinuationOptions, optional
        Newton tolerances and the settings of the continuation fallback;
        its ``max_steps`` bounds the steps of all the fallback traces
        together (from below and from above).
    condense : bool or {"modal", "state", "direct"}, optional
        As in :func:`hbmfric.frf`.
    branch_side : {None, "below", "above"}
        Which solution to return where several coexist (between the folds
        of a bent resonance). None (default): the first one found by the
        sequence above; Newton from the linearisations may land on any of
        them, the continuation fallback returns the one reached from below.
        ``"below"`` (``"above"``): skip Newton and the load ramp and
        return the solution on the branch traced from far below (above) the
        target, at its first crossing of Ω. In the fold region of a
        resonance bent to higher frequencies (hardening) that is the
        large-amplitude (small-amplitude) solution, of one bent to lower
        frequencies (softening) the small-amplitude (large-amplitude) one.
        Not with ``initial_guess`` (which selects a solution by itself).
    harmonic_tolerance : float, default 1e-4
        With ``harmonics="auto"``: target relative truncation error of the
        first-harmonic amplitude and of half the peak-to-peak value at the
        contact DOF (in ``(0, 1]``). With a fixed ``H``: the threshold of
        the :class:`~hbmfric.AccuracyWarning` on the solution's estimated
        truncation error (the estimate of :func:`hbmfric.frf` at a fixed
        ``H``, ``Branch.truncation_error``).
    on_failure : {"warn", "raise"}
        When no start converges: issue a
        :class:`~hbmfric.ConvergenceWarning` and return the iterate with the
        smallest residual (``converged=False``, ``method="failed"``), or
        raise :class:`~hbmfric.ConvergenceError`.

    Returns
    -------
    PeriodicSolution
        ``coefficients`` of shape (n_dof, n_coef), m; ``converged``,
        ``method``, ``residual_norm`` (N) and ``newton_iterations`` (all
        Newton evaluations of every attempt) tell how it was obtained.

    Warns
    -----
    AccuracyWarning
        For a structure reduced by :func:`~hbmfric.craig_bampton`, when
        ``omega`` lies above the pulsation the reduction stands for
        (``valid_below``); and as described under ``harmonic_tolerance``.
    """
    from .api import _problem  # api re-exports this function

    start = time.perf_counter()
    omega = finite_float("omega", omega, low=0.0, low_open=True)
    force = finite_float("force", force)
    warn_above_cutoff(system, omega, "omega", stacklevel=2)
    if on_failure not in ON_FAILURE:
        raise ValueError(f"on_failure must be 'warn' or 'raise', got {on_failure!r}")
    if branch_side not in BRANCH_SIDES:
        raise ValueError(
            f"branch_side must be None, 'below' or 'above', got {branch_side!r}"
        )
    if branch_side is not None and initial_guess is not None:
        raise ValueError("give either initial_guess or branch_side, not both")
    if not isinstance(options, ContinuationOptions | None):
        raise TypeError(
            f"options must be a ContinuationOptions, got {type(options).__name__}"
        )
    options = options or ContinuationOptions()
    auto = isinstance(harmonics, str)
    harmonic_tolerance = finite_float(
        "harmonic_tolerance", harmonic_tolerance, low=0.0, low_open=True, high=1.0
    )
    if auto:
        if harmonics != "auto":
            raise ValueError(
                f"harmonics must be a positive integer or 'auto', got {harmonics!r}"
            )
        if n_time is not None:
            raise ValueError("n_time cannot be given with harmonics='auto'")
        if initial_guess is not None and not isinstance(
            initial_guess, PeriodicSolution
        ):
            raise ValueError(
                "with harmonics='auto' initial_guess must be a PeriodicSolution"
            )
        harmonics = LADDER[START]
    # the fallback continuations start at 0.5 and 1.5 times Ω
    problem = _problem(
        system,
        force,
        harmonics,
        n_time,
        symmetry,
        aft,
        condense,
        at=(omega, 0.5 * omega, 1.5 * omega),
        top=LADDER[-1] if auto else None,
    )
    if not auto:
        _memory.check_fixed(problem, "periodic_solution")
    if not np.any(problem.load):
        # unforced and damped: the steady state is rest, displaced where a
        # contact carries a force at rest (an unsymmetric Dahl law's
        # mid-envelope force, a 2D element's preload without a static load)
        rest, iterations, residual = _rest_state(problem, omega, options)
        converged = rest is not None
        if not converged:
            rest = np.zeros(problem.n_unknowns + 1)
            rest[-1] = omega
            message = (
                f"periodic_solution did not find the rest state at omega = "
                f"{omega:.6g} rad/s, force = 0 N: max|R| = {residual:.3e} N "
                "(a contact carries a force at rest); the returned "
                "coefficients are not a solution"
            )
            if on_failure == "raise":
                raise ConvergenceError(message)
            warnings.warn(message, ConvergenceWarning, stacklevel=2)
        state = STATE_NAMES[STUCK]
        return _solution(
            system,
            problem,
            rest,
            converged,
            iterations,
            residual,
            start,
            ZERO_FORCE if converged else FAILED,
            state,
        )
    guess = None
    if initial_guess is not None:
        guess = _guess_vector(initial_guess, problem)
    solver = _FixedOmega(problem, omega, options)
    y, method = solver.solve(guess, branch_side)
    if auto and y is not None:
        ladder, needed = _memory.fitting_ladder(problem, LADDER, START)
        y, problem, solver = _climb(
            system, problem, omega, options, y, solver, harmonic_tolerance, ladder
        )
    converged = y is not None
    if not converged:
        y = solver.fallback()
    elif not auto and problem.subharmonic == 1:
        _warn_truncation(problem, y, harmonic_tolerance)
    R, _, state = problem.residual(y)
    residual = float(np.max(np.abs(R)))
    if not converged:
        message = (
            f"periodic_solution did not converge at omega = {omega:.6g} rad/s, "
            f"force = {force:.6g} N: max|R| = {residual:.3e} N (tolerance "
            f"{solver.tolerance:.3e} N) after {', '.join(solver.tried)}; the "
            "returned coefficients are not a solution"
        )
        if on_failure == "raise":
            raise ConvergenceError(message)
        warnings.warn(message, ConvergenceWarning, stacklevel=2)
        method = FAILED
    return _solution(
        system,
        problem,
        y,
        converged,
        solver.iterations,
        residual,
        start,
        method,
        STATE_NAMES.get(state, str(state)),
    )


def _warn_truncation(problem, y: np.ndarray, tolerance: float) -> None:
    """An :class:`~hbmfric.AccuracyWarning` when the estimated truncation
    error of the solution ``y`` at a fixed ``H`` exceeds ``tolerance`` (the
    estimate and the threshold of :func:`hbmfric.frf` at a fixed ``H``)."""
    from .continuation.accuracy import watched_truncation_errors

    # the displacement scale frf would use over a range at this Ω alone
    scale = problem.amplitude_scale((float(y[-1]), float(y[-1])))
    estimate = float(
        watched_truncation_errors(
            problem, y[None, :], tolerance, amplitude_scale=scale
        )[0]
    )
    if not np.isfinite(estimate):
        warnings.warn(
            f"the truncation error of the solution at omega = {y[-1]:.6g} rad/s "
            f"with H = {problem.harmonics} could not be estimated (no estimate "
            "below H = 3, or the estimate's solve failed): nothing vouches for "
            "it; use harmonics='auto' or raise harmonics",
            AccuracyWarning,
            stacklevel=3,
        )
    elif estimate > tolerance:
        warnings.warn(
            f"estimated truncation error {estimate:.2g} of the solution at "
            f"omega = {y[-1]:.6g} rad/s with H = {problem.harmonics} exceeds "
            f"harmonic_tolerance={tolerance:g}; use harmonics='auto' or raise "
            "harmonics",
            AccuracyWarning,
            stacklevel=3,
        )


#: Newton iterations allowed for the rest state of an unforced system
REST_ITERATIONS = 50


def _rest_state(problem, omega: float, options) -> tuple:
    """Rest state of an unforced problem: ``(y, iterations, max|R|)``.

    Zero unless a contact carries a force at zero displacement; then the
    static balance is solved by Newton on the means alone, from zero, to
    ``options.tol_residual`` relative to that force (the load is zero and
    gives no scale). The harmonics stay zero: a hysteretic law's force at
    a constant displacement is not smooth in the amplitude of a vanishing
    loop (an unsymmetric Dahl law: Newton on every coefficient wandered
    off the rest state it had reached in one step). ``y`` is None when
    Newton does not get there (or the basis has no mean).
    """
    n = problem.n_unknowns
    y = np.zeros(n + 1)
    y[-1] = omega
    R, J, aft = problem.residual(y)
    res = float(np.max(np.abs(R))) if aft >= 0 else np.inf
    if res == 0.0:
        return y, 0, 0.0
    if problem.harmonic_numbers[0] != 0:
        return None, 0, res
    means = np.arange(0, n, problem.n_coef)
    target = max(options.tol_residual * res, problem.rounding_level())
    for it in range(REST_ITERATIONS + 1):
        if aft >= 0 and np.all(np.isfinite(R)) and res <= target:
            return y, it, res
        if it == REST_ITERATIONS or aft < 0:
            break
        try:
            dx = np.linalg.solve(J[np.ix_(means, means)], -R[means])
        except np.linalg.LinAlgError:
            break
        y[means] += dx
        R, J, aft = problem.residual(y)
        res = float(np.max(np.abs(R))) if aft >= 0 else np.inf
    return None, REST_ITERATIONS, res


def _solution(
    system, problem, y, converged, iterations, residual, start, method, contact_state
) -> PeriodicSolution:
    """The :class:`PeriodicSolution` of the point ``y = [X, Ω]``."""
    return PeriodicSolution(
        omega=float(y[-1]),
        force=problem.force,
        harmonic_numbers=problem.harmonic_numbers.copy(),
        coefficients=problem.full_coefficients(y)[0],
        converged=bool(converged),
        newton_iterations=int(iterations),
        residual_norm=residual,
        elapsed=time.perf_counter() - start,
        contact_state=contact_state,
        dof_names=dict(getattr(system, "dof_names", {})),
        method=method,
        _source={
            "system": system,
            "aft": problem.aft,
            "n_time": problem.n_time,
            "subharmonic": problem.subharmonic,
        },
    )


#: a Newton solve that reports convergence is taken if its residual is
#: within this factor of the tolerance (its own floor, from the
#: factorised Jacobian, can differ from the one recomputed here); beyond,
#: the solve is treated as failed and the next start is tried
CONVERGED_SLACK = 1e3


class _FixedOmega:
    """The attempts at one Ω on one discretisation, with their bookkeeping:
    Newton evaluations, the attempts made and the best failed iterate."""

    def __init__(self, problem: HBMProblem, omega: float, options) -> None:
        self.problem = problem
        self.omega = omega
        self.options = options
        self.cont = Continuation(problem, (0.5 * omega, 1.5 * omega), 1, options)
        self.tolerance = self.cont.tol_residual
        # the budget of a continuation's first point (palc.Continuation.init)
        self.budget = max(8 * options.max_newton, 100)
        self.iterations = 0
        # one budget of continuation steps (accepted and rejected) for all
        # the fallback traces together, so that a point no start reaches
        # costs at most about one FRF's worth of steps, not four
        self.steps_left = options.max_steps
        self.tried: list[str] = []
        self._linear = None
        self.best = None
        self.best_residual = np.inf

    def linear(self) -> list[np.ndarray]:
        """The linearised starts (flat X), computed once: for a rigid
        Coulomb contact they include a presolve of up to hundreds of
        iterations."""
        if self._linear is None:
            n = self.problem.n_unknowns
            self._linear = [g[:n] for g in self.problem.initial_guesses(self.omega)]
        return self._linear

    def fallback(self) -> np.ndarray:
        """The finite iterate with the smallest residual, else the stuck
        linearisation: what a failed solve returns."""
        if self.best is not None:
            return self.best
        return np.append(self.linear()[0], self.omega)

    def accept(self, y: np.ndarray, status: int) -> bool:
        """Whether ``y`` is a solution; a failed finite iterate is kept if it
        is the best so far."""
        if not np.all(np.isfinite(y)):
            return False
        # checked whatever the status: Newton's convergence may rest on step
        # tests in units of the run's amplitude scale, or on a predicted
        # contraction without a last evaluation (condensed problems); a
        # wrong scale (an undamped pole sampled within rounding: 1.1e12 m)
        # let a state-condensed solve report convergence with max|R| =
        # 0.051 N under a 1e-3 N load, 3 % off
        R, J, aft = self.problem.residual(y)
        res = float(np.max(np.abs(R))) if aft >= 0 else np.inf
        floor = max(float(_newton.rounding_floor(J, y)), self.problem.rounding_level())
        limit = max(self.tolerance, floor)
        if status == _newton.CONVERGED and res <= CONVERGED_SLACK * limit:
            return True
        if res <= limit:
            # Newton's look-ahead step test failed on a seam of the
            # piecewise smooth residual; the balance itself holds
            return True
        if res < self.best_residual:
            self.best, self.best_residual = y.copy(), res
        return False

    def newton(self, guess: np.ndarray) -> np.ndarray | None:
        """Newton at the target Ω from ``guess`` (flat X); the solution
        ``[X, Ω]`` or None."""
        y, status, it = self.cont.solve_at(self.omega, guess, self.budget)
        self.iterations += it
        return y if self.accept(y, status) else None

    def solve(self, guess, branch_side):
        """``(y, method)``, ``y = [X, Ω]`` or None when nothing converged."""
        if branch_side is None:
            self.tried.append("Newton")
            starts = ([] if guess is None else [guess]) + self.linear()
            for g in starts:
                y = self.newton(g)
                if y is not None:
                    return y, NEWTON
            self.tried.append("load ramp")
            y, status, it = self.cont._load_ramp(self.omega)
            self.iterations += it
            if self.accept(y, status):
                return y, LOAD_RAMP
        sides = ("below", "above") if branch_side is None else (branch_side,)
        for side in sides:
            self.tried.append(f"continuation from {side}")
            y = self.from_side(side)
            if y is not None:
                return y, FROM_BELOW if side == "below" else FROM_ABOVE
        return None, FAILED

    def from_side(self, side: str) -> np.ndarray | None:
        """Continuation in Ω from far below (above) the target; the solution
        at its first crossing of the target, or None."""
        omega = self.omega
        n = self.problem.n_unknowns
        for factor in BELOW_STARTS if side == "below" else ABOVE_STARTS:
            if self.steps_left <= 0:
                if "step budget used up" not in self.tried:
                    self.tried.append("step budget used up")
                return None
            far = factor * omega
            pad = OVERSHOOT * abs(omega - far)
            options = dataclasses.replace(self.options, max_steps=self.steps_left)
            if side == "below":
                cont = Continuation(self.problem, (far, omega + pad), 1, options)
            else:
                cont = Continuation(self.problem, (omega - pad, far), -1, options)
            state, _ = cont.run()
            self.iterations += state.n_newton
            self.steps_left -= state.n_steps + state.n_rejected
            if not state.points:
                continue
            points = np.array(state.points)
            w = points[:, n] - omega
            for j in range(points.shape[0] - 1):
                if w[j] == 0.0 or w[j] * w[j + 1] < 0.0:
                    s = w[j] / (w[j] - w[j + 1])
                    seed = (1.0 - s) * points[j, :n] + s * points[j + 1, :n]
                    for g in (seed, points[j, :n], points[j + 1, :n]):
                        y = self.newton(g)
                        if y is not None:
                            return y
                    break
                y = self.at_fold(points, j, side)
                if y is not None:
                    return y
        return None

    def at_fold(self, points: np.ndarray, j: int, side: str) -> np.ndarray | None:
        """The solution at the target when the path turns back at point
        ``j`` less than one step short of it (a fold just beyond the
        target, between two points on the near side: the path crosses the
        target twice between them, which no sign change shows), by Newton
        from point ``j``; None otherwise."""
        if j == 0:
            return None
        n = self.problem.n_unknowns
        before, here, after = points[j - 1, n], points[j, n], points[j + 1, n]
        toward = 1.0 if side == "below" else -1.0
        if not (toward * (here - before) > 0.0 and toward * (after - here) < 0.0):
            return None  # no turn at j, or one away from the target
        short = toward * (self.omega - here)
        if not 0.0 < short <= abs(here - before):
            return None
        reach = 2.0 * max(
            float(np.max(np.abs(points[j, :n] - points[j - 1, :n]))),
            float(np.max(np.abs(points[j + 1, :n] - points[j, :n]))),
        )
        # from the approach side first: the first crossing lies between
        # point j - 1 and the fold
        for seed in (points[j - 1, :n], points[j, :n]):
            y = self.newton(seed)
            if y is not None and float(np.max(np.abs(y[:n] - points[j, :n]))) <= reach:
                return y
        return None


def _climb(system, problem, omega, options, y, solver, tolerance, ladder=LADDER):
    """``harmonics="auto"``: up ``ladder`` from the converged ``y`` of
    ``problem`` until the amplitudes at the contact DOF settle (``ladder``:
    the rungs that fit in memory, :func:`hbmfric._memory.fitting_ladder`).

    Returns the finest converged ``(y, problem, solver)``; the solvers'
    iteration counts add up in the returned one.
    """
    from .continuation.accuracy import normal_outputs
    from .signals import half_peak_to_peak

    contact = int(getattr(system, "contact_dof", 0))
    # and the normal displacement of each 2D element: its normal force has
    # kinks where the contact opens (stop 31: loaded normally only, the
    # contact DOF at rest settled at once while the normal DOF was 8e-4
    # off at H = 7)
    # (weights of the DOFs the solution carries, also when condensed: on
    # the coordinates' weights a condensed problem raised a shape error
    # before stop 34, hunt35)
    normals = [w[0] for w in normal_outputs(problem, dofs=True)]

    def measures(p, v):
        sol = _solution(system, p, v, True, 0, 0.0, 0.0, "", "")
        out = [sol.amplitude(harmonic=1, dof=contact), sol.amplitude(dof=contact)]
        hn = np.asarray(p.harmonic_numbers)
        first = 1 if hn[0] == 0 else 0
        for a in normals:
            z = a @ sol.coefficients
            out += [float(np.hypot(z[first], z[first + 1]))]
            out += [float(half_peak_to_peak(hn, z))]
        return np.array(out)

    here = measures(problem, y)
    changes: list[float] = []
    level = ladder.index(problem.harmonics)
    for h in ladder[level + 1 :]:
        finer = problem.with_harmonics(h)
        nxt = _FixedOmega(finer, omega, options)
        nxt.iterations = solver.iterations
        previous = _solution(system, problem, y, True, 0, 0.0, 0.0, "", "")
        seed = _guess_vector(previous, finer)
        y_new = nxt.newton(seed)
        if y_new is None:
            y_new, _ = nxt.solve(seed, None)
        if y_new is None:
            warnings.warn(
                f"periodic_solution(harmonics='auto'): no solution at H = {h} "
                f"from the one at H = {problem.harmonics} (omega = {omega:.6g} "
                f"rad/s); returning H = {problem.harmonics}, whose truncation "
                "error is not estimated",
                AccuracyWarning,
                stacklevel=3,
            )
            solver.iterations = nxt.iterations
            return y, problem, solver
        there = measures(finer, y_new)
        change = float(np.max(np.abs(there - here) / np.maximum(np.abs(there), 1e-300)))
        y, problem, solver, here = y_new, finer, nxt, there
        changes.append(change)
        # two settled steps in a row: convergence in H is not monotone
        # (a single small change can be a crossing of the limit)
        if len(changes) >= 2 and SETTLE_FACTOR * max(changes[-2:]) <= tolerance:
            return y, problem, solver
    if len(changes) < 2:
        stopped = (
            f"the change to H = {ladder[-1]} is {changes[-1]:.2e}"
            if changes
            else (f"no level above H = {ladder[-1]}")
        )
    else:
        stopped = (
            f"the amplitudes still change by {max(changes[-2:]):.2e} (relative) "
            f"between H = {ladder[-3]}, {ladder[-2]} and {ladder[-1]}"
        )
    memory = ""
    if len(ladder) < len(LADDER):
        memory = (
            f"; the ladder stopped at H = {ladder[-1]}: higher levels' dense "
            "matrices need more memory than this machine has available "
            "(condense onto the contacts or reduce the model to go higher)"
        )
    warnings.warn(
        f"periodic_solution(harmonics='auto'): {stopped} at omega = {omega:.6g} "
        f"rad/s, above harmonic_tolerance / {SETTLE_FACTOR:g} = "
        f"{tolerance / SETTLE_FACTOR:.2e}{memory}",
        AccuracyWarning,
        stacklevel=3,
    )
    return y, problem, solver


def _guess_vector(guess, problem: HBMProblem) -> np.ndarray:
    """Coefficients of a guess re-laid onto this problem's harmonics."""
    if isinstance(guess, PeriodicSolution):
        n_dof = guess.coefficients.shape[0]
        if n_dof != problem.n_dof:
            raise ValueError(
                f"initial_guess is a PeriodicSolution of a system with {n_dof} "
                f"DOFs; this system has {problem.n_dof}: give a solution of the "
                "same system (or of one with the same DOF layout)"
            )
        X = np.zeros((problem.n_dof, problem.n_coef))
        src = {int(k): i for i, k in enumerate(guess.harmonic_numbers)}
        src_col = np.cumsum([0] + [1 if k == 0 else 2 for k in guess.harmonic_numbers])
        col = 0
        for k in problem.harmonic_numbers:
            width = 1 if k == 0 else 2
            if int(k) in src:
                c = src_col[src[int(k)]]
                X[:, col : col + width] = guess.coefficients[:, c : c + width]
            col += width
        return problem.unknowns_from_full(X)
    g = np.ascontiguousarray(guess, dtype=np.float64).reshape(-1)
    if g.size != problem.n_unknowns or not np.all(np.isfinite(g)):
        raise ValueError(
            f"initial_guess must hold {problem.n_unknowns} finite coefficients, "
            f"got {g.size}"
        )
    return g
