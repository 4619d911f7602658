"""Monodromy matrix of a periodic solution by the time-integration reference.

The period map ``P`` of the Newmark scheme of
:mod:`hbmfric.validation.integrator` takes the state at an instant ``t_m``
of the period to the state one period (or ``periods`` periods) later. Its
derivative at a periodic solution, the monodromy matrix, is formed here by
central differences of ``P``: each column is two integrations over the
period from the state perturbed forward and backward in one entry. The
eigenvalues are the Floquet multipliers; the solution is asymptotically
stable when all their moduli are below 1.

This route is independent of the harmonic balance (it shares only the
contact-law kernels) and so checks Hill's method
(:meth:`hbmfric.Branch.stability`) where Hill is exact (memoryless laws) and
where it is an approximation (hysteretic laws).

The state. ``x`` and ``v`` of every DOF, and, for a contact law with memory
whose whole history is its force (Jenkins, modified Dahl), that force: for
Jenkins a perturbed force at fixed ``x`` is a moved slider. A memoryless law
(``hf.Cubic``) adds nothing: its force is recomputed from the perturbed
displacement. Laws whose state is a history of reversal points (Menq, Iwan)
have no finite state of this kind and are refused, as are the 2D element and
the rigid Coulomb contact.

The section instant. The Jenkins law is piecewise linear; a central
difference across one of its kinks averages two slopes. The section ``t_m``
is therefore the step instant of the period where every Jenkins contact is
furthest inside its stick range (``|f| / f_s`` smallest), so that a small
perturbation of the start changes no step's stick/slip state. The
multipliers do not depend on the section.

Accuracy: the scheme's multipliers differ from the exact flow's by
``O(h²)`` (second order in the step ``h = T/N``), a few 1e-5 at the default
``N = 2048`` on the single-DOF cases of ``tests/test_monodromy.py``.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from .._validate import finite_float, positive_int
from ..errors import AccuracyWarning, ConvergenceError
from ..kernels.laws.updates import CUBIC, DAHL, JENKINS
from ..signals import state_at_zero
from .integrator import MESSAGES, NO_CONTACT, OK
from .multi_integrator import LAW_1D

#: law codes whose state is the force alone and carries memory
_MEMORY_LAWS = (JENKINS, DAHL)
#: law codes without memory (the force follows the displacement)
_MEMORYLESS_LAWS = (CUBIC,)
#: periods integrated from a harmonic-balance start before the section, so
#: that a law with memory forgets its initial (virgin) state
SETTLE_PERIODS = 2
#: largest :attr:`Monodromy.closure` of a start on a periodic orbit
CLOSURE_TOL = 1e-2
#: without ``settle_periods``, the start settles on past the default periods
#: while its closure exceeds this and decreases, at most
#: :data:`MAX_EXTRA_SETTLE` periods more
SETTLE_TOL = 1e-6
MAX_EXTRA_SETTLE = 50
#: ... and stops after this many maps without a better closure
SETTLE_PATIENCE = 8


@dataclass
class Monodromy:
    """Monodromy matrix of a periodic solution and its Floquet multipliers.

    Attributes
    ----------
    matrix : ndarray, shape (n_state, n_state)
        Derivative of the state after ``periods`` forcing periods with
        respect to the state at the section instant (dimensionless blocks
        ``∂x/∂x``, ``∂v/∂v``, ``∂f/∂f``; s or 1/s in the mixed blocks).
    multipliers : ndarray of complex, shape (n_state,)
        Eigenvalues of ``matrix``, sorted by decreasing modulus.
    labels : list of str
        The state entries: ``"x[i]"``, ``"v[i]"`` (DOF ``i``) and
        ``"f[k]"`` (force of the ``k``-th contact, for laws with memory).
    omega : float
        Forcing pulsation Ω, rad/s.
    periods : int
        Forcing periods of the map (``ν`` for a subharmonic of order ``ν``).
    section_time : float
        Instant ``t_m`` of the section within the forcing period, s.
    steps_per_period : int
        Newmark steps ``N`` per forcing period.
    perturbation : float
        Relative size of the finite-difference perturbations.
    elapsed : float
        Wall time, s.
    closure : float
        How far the map moves the start: ``max |P(z) - z|`` over the state
        entries, each in units of its peak over the period (``x``, ``v``,
        ``f``). Small on a periodic orbit (the harmonic balance's truncation
        and the scheme's ``O(h²)``); above :data:`CLOSURE_TOL` the start is
        not on an orbit of this system at this force and Ω, and an
        :class:`~hbmfric.AccuracyWarning` says so.
    settle_periods : int
        Forcing periods integrated from the start before the section.
    """

    matrix: np.ndarray = field(repr=False)
    multipliers: np.ndarray
    labels: list
    omega: float
    periods: int
    section_time: float
    steps_per_period: int
    perturbation: float
    elapsed: float
    closure: float = float("nan")
    settle_periods: int = 0

    @property
    def max_modulus(self) -> float:
        """Largest modulus of the multipliers."""
        return float(np.max(np.abs(self.multipliers)))


def monodromy(
    system,
    start,
    force: float | None = None,
    omega: float | None = None,
    *,
    steps_per_period: int | None = None,
    periods: int | None = None,
    settle_periods: int | None = None,
    perturbation: float = 1e-5,
) -> Monodromy:
    """Monodromy matrix and Floquet multipliers by time integration.

    Parameters
    ----------
    system : Oscillator or compatible
        The system of the solution (:mod:`hbmfric.systems.protocol`), with
        no contact, one contact or several 1D contacts of the laws Jenkins,
        modified Dahl or Cubic.
    start : SteadyState, PeriodicSolution or (x0, v0)
        The periodic solution: a converged
        :func:`~hbmfric.validation.steady_state` result (its last state is
        the start), a converged harmonic-balance solution (its
        displacement and velocity at ``t = 0``; stable or not), or a state
        (m, m/s; arrays of shape (n_dof,) or scalars) on or near the
        periodic orbit.
    force, omega : float, optional
        Forcing amplitude (N) and pulsation (rad/s); taken from ``start``
        when it is a solution, required with a state.
    steps_per_period : int, optional
        Newmark steps per forcing period (>= 16); default: those of a
        :class:`~hbmfric.validation.SteadyState` start, else 2048.
    periods : int, optional
        Forcing periods of the map; default 1 (``ν`` for a subharmonic
        :class:`~hbmfric.PeriodicSolution` of order ``ν``).
    settle_periods : int, optional
        Periods integrated from the start before the section (the contact
        laws' memory settles along the orbit); default 0 for a
        :class:`~hbmfric.validation.SteadyState` or without a law with
        memory, else 2, and then (by default only) one period more at a
        time while the start still approaches the orbit (the state of best
        :attr:`Monodromy.closure` is kept; until it is below
        :data:`SETTLE_TOL`, at most :data:`MAX_EXTRA_SETTLE` maps more, or
        :data:`SETTLE_PATIENCE` maps without improvement). Along
        an unstable solution the state drifts from the orbit by the largest
        multiplier per period: keep it short.
    perturbation : float
        Relative size of the central-difference perturbations, in units of
        the peak of each kind of state entry over the period (``x``,
        ``v``, ``f``), in ``(0, 1e-2]``.

    Returns
    -------
    Monodromy

    Raises
    ------
    ValueError
        On invalid input, an unconverged solution as ``start``, or a
        contact without a finite state (Menq, Iwan, the 2D element, rigid
        Coulomb).
    ConvergenceError
        When an integration of the period map fails (a contact update that
        does not converge, a state that is no longer finite).
    """
    from ..results import PeriodicSolution
    from .problems import SeveralContacts, SingleContact
    from .steady_state import SteadyState

    clock = time.perf_counter()
    perturbation = finite_float(
        "perturbation", perturbation, low=0.0, low_open=True, high=1e-2
    )
    subharmonic = 1
    if isinstance(start, PeriodicSolution):
        subharmonic = int((start._source or {}).get("subharmonic", 1) or 1)
    if isinstance(start, SteadyState | PeriodicSolution):
        if not start.converged:
            raise ValueError(
                "start is not a converged solution: a monodromy matrix belongs "
                "to a periodic solution"
            )
        if force is None:
            force = start.force
        if omega is None:
            # a subharmonic solution's omega is its fundamental Ω/ν
            omega = start.omega * subharmonic
    elif force is None or omega is None:
        raise ValueError("give force and omega with a state (x0, v0) as start")
    force = finite_float("force", force)
    omega = finite_float("omega", omega, low=0.0, low_open=True)
    if steps_per_period is None:
        steps_per_period = (
            start.steps_per_period if isinstance(start, SteadyState) else 2048
        )
    steps = positive_int("steps_per_period", steps_per_period, low=16)
    periods = positive_int("periods", subharmonic if periods is None else periods)

    problem = SingleContact.build(system, force)
    state = _StateMap(problem, isinstance(problem, SeveralContacts))

    # the start (x, v, law state)
    if isinstance(start, SteadyState):
        if start.final_state is None:
            raise ValueError("start holds no final state (a SteadyState of an old run)")
        x, v, law_state = (np.array(a, dtype=np.float64) for a in start.final_state)
        if x.size != problem.n_dof or law_state.size != state.law_size:
            raise ValueError("start is a steady state of another system")
        default_settle = 0
    else:
        if isinstance(start, PeriodicSolution):
            x, v = _state_at_zero(start, omega / subharmonic, problem.n_dof)
            # the laws' state on the orbit's hysteresis loop, sampled as the
            # integrator steps (a virgin law there is off the loop, and the
            # integration forgets it only at the slowest multiplier's rate:
            # tens of periods on a lightly damped structure)
            law_state = problem.loop_law_state(
                _orbit_samples(start, problem.n_dof, steps * subharmonic)
            )
        else:
            x, v = problem.initial_state(start, omega, steps)
            law_state = problem.initial_law_state(x)
        default_settle = SETTLE_PERIODS if state.memory.size else 0
    settle = default_settle if settle_periods is None else settle_periods
    settle = positive_int("settle_periods", settle, low=0)

    ops = problem.kernel_system(omega, steps)
    periods_kernel, record_kernel = problem.kernels()
    work = np.empty(problem.n_dof)
    if settle:
        _run(periods_kernel, ops, x, v, law_state, work, settle)

    # one recorded period: peaks for the scales, forces for the section
    samples = np.empty((problem.n_dof, steps))
    contact_force = np.empty(steps)
    peaks = np.empty(3)
    xs, vs, ls = x.copy(), v.copy(), law_state.copy()
    status, _ = record_kernel(ops, xs, vs, ls, work, peaks, samples, contact_force)
    _check(status)
    section = state.section(samples, ops, steps)
    if section:
        _run(periods_kernel, _partial(ops, section), x, v, law_state, work, 1)
    period_ops = _rolled(ops, section)

    section_time = section * 2.0 * np.pi / (omega * steps)
    x_scale = peaks[0] if peaks[0] > 0.0 else 1e-6
    v_scale = peaks[1] if peaks[1] > 0.0 else omega * x_scale
    f_scale = peaks[2] if peaks[2] > 0.0 else 1.0
    z0 = state.pack(x, v, law_state)
    scale = state.scales(x_scale, v_scale, f_scale)

    def period_map(z):
        xz, vz, lz = state.unpack(z, law_state)
        _run(periods_kernel, period_ops, xz, vz, lz, work, periods)
        return state.pack(xz, vz, lz)

    state_k = period_map(z0.copy())  # the start after k = 1 map
    closure = float(np.max(np.abs(state_k - z0) / scale))
    extra = k = stall = 0
    while (
        settle_periods is None
        and closure > SETTLE_TOL
        and k < MAX_EXTRA_SETTLE
        and stall < SETTLE_PATIENCE
    ):
        # settle on: a contact started virgin forgets it at the rate of the
        # slowest multiplier (0.18 to 0.47 per period on stick-slip Jenkins
        # orbits: after two periods the start was still 1e-2 off and the
        # multipliers up to 4 % off); keep the state that closes best
        following = period_map(state_k.copy())
        k += 1
        change = float(np.max(np.abs(following - state_k) / scale))
        if change < closure:
            z0, closure, extra, stall = state_k, change, k, 0
        else:
            stall += 1  # a rotating (complex) or growing (unstable) approach
        state_k = following
    drift = 0.0
    if isinstance(start, PeriodicSolution):
        # the settled start against the solution's own state at the section
        xs, vs = _state_at(start, omega / subharmonic, problem.n_dof, section_time)
        n_dof = problem.n_dof
        drift = max(
            float(np.max(np.abs(z0[:n_dof] - xs))) / x_scale,
            float(np.max(np.abs(z0[n_dof : 2 * n_dof] - vs))) / v_scale,
        )
    if not drift <= CLOSURE_TOL:
        warnings.warn(
            f"monodromy: the start settled {drift:.2e} (of its peak) away from "
            f"the solution it was given (force = {force:.6g} N, omega = "
            f"{omega:.6g} rad/s): these are the multipliers of another orbit; "
            "check force, omega and the system",
            AccuracyWarning,
            stacklevel=2,
        )
    if not closure <= CLOSURE_TOL:
        warnings.warn(
            f"monodromy: the start is not on a periodic orbit of this system at "
            f"force = {force:.6g} N, omega = {omega:.6g} rad/s: {periods} "
            f"period(s) move it by {closure:.2e} of its peak (the multipliers "
            "are not those of a periodic solution; check force, omega and the "
            "system, or start from a converged solution)",
            AccuracyWarning,
            stacklevel=2,
        )
    n = z0.size
    matrix = np.empty((n, n))
    for j in range(n):
        dz = perturbation * scale[j]
        plus, minus = z0.copy(), z0.copy()
        plus[j] += dz
        minus[j] -= dz
        matrix[:, j] = (period_map(plus) - period_map(minus)) / (2.0 * dz)
    mu = np.linalg.eigvals(matrix)
    mu = mu[np.argsort(-np.abs(mu), kind="stable")]
    return Monodromy(
        matrix=matrix,
        multipliers=mu,
        labels=state.labels,
        omega=omega,
        periods=periods,
        section_time=section_time,
        steps_per_period=steps,
        perturbation=perturbation,
        elapsed=time.perf_counter() - clock,
        closure=closure,
        settle_periods=settle + extra * periods,
    )


class _StateMap:
    """Which entries of ``(x, v, law state)`` form the monodromy's state,
    and how a perturbed state is made consistent (memoryless forces
    recomputed from the displacement)."""

    def __init__(self, problem, multi: bool) -> None:
        self.problem = problem
        self.multi = multi
        self.n_dof = problem.n_dof
        memory, memoryless, contacts = [], [], []
        if multi:
            self.law_size = int(problem.state_length)
            for k, kind in enumerate(problem.kinds):
                code = int(problem.codes[k])
                if kind != LAW_1D:
                    raise ValueError(
                        "the monodromy by time integration has no 2D contact "
                        "element (its state includes the slider and the gap)"
                    )
                contacts.append((k, code))
        else:
            code = int(problem.law_code)
            self.law_size = int(problem.initial_law_state(np.zeros(self.n_dof)).size)
            if code != NO_CONTACT:
                contacts.append((0, code))
        for k, code in contacts:
            if code in _MEMORY_LAWS:
                memory.append(k)
            elif code in _MEMORYLESS_LAWS:
                memoryless.append(k)
            else:
                raise ValueError(
                    "the monodromy by time integration needs contact laws whose "
                    "state is their force (Jenkins, modified Dahl) or none "
                    "(Cubic); Menq and Iwan carry a history of reversal points"
                )
        self.memory = np.array(memory, dtype=np.int64)
        self.memoryless = np.array(memoryless, dtype=np.int64)
        self.codes = dict(contacts)
        n = self.n_dof
        self.labels = (
            [f"x[{i}]" for i in range(n)]
            + [f"v[{i}]" for i in range(n)]
            + [f"f[{k}]" for k in memory]
        )

    def _slots(self, k: int) -> list[int]:
        """Positions of contact ``k``'s force in the law state."""
        if not self.multi:
            return [0]
        p = self.problem
        return [int(p.first[k]), int(p.state_at[k])]

    def pack(self, x, v, law_state) -> np.ndarray:
        forces = [law_state[self._slots(k)[0]] for k in self.memory]
        return np.concatenate((x, v, np.array(forces, dtype=np.float64)))

    def unpack(self, z, template):
        n = self.n_dof
        x = np.ascontiguousarray(z[:n])
        v = np.ascontiguousarray(z[n : 2 * n])
        law_state = template.copy()
        for i, k in enumerate(self.memory):
            for s in self._slots(k):
                law_state[s] = z[2 * n + i]
        if self.memoryless.size:
            fresh = self.problem.initial_law_state(x)
            for k in self.memoryless:
                for s in self._slots(k):
                    law_state[s] = fresh[s]
        return x, v, law_state

    def scales(self, x_scale, v_scale, f_scale) -> np.ndarray:
        n = self.n_dof
        return np.concatenate(
            (
                np.full(n, x_scale),
                np.full(n, v_scale),
                np.full(self.memory.size, f_scale),
            )
        )

    def section(self, samples, ops, steps: int) -> int:
        """Step index of the section: where the Jenkins contacts are
        furthest inside their stick range (0 without one)."""
        jenkins = [k for k in self.memory if self.codes[k] == JENKINS]
        if not jenkins:
            return 0
        p = self.problem
        ratio = np.zeros(steps)
        if self.multi:
            coordinates = p.reader() @ samples
            for k in jenkins:
                params = p.params[p.param_at[k] : p.param_at[k + 1]]
                kt, fs = params[0], params[1]
                ratio = np.maximum(ratio, _stick_ratio(coordinates[p.first[k]], kt, fs))
        else:
            kt, fs = p.law_params[0], p.law_params[1]
            ratio = _stick_ratio(samples[p.contact_dof], kt, fs)
        return int(np.argmin(ratio))


def _stick_ratio(u: np.ndarray, kt: float, fs: float) -> np.ndarray:
    """``|f| / f_s`` along a periodic displacement, the Jenkins force by
    its periodic march (two passes from the virgin state at ``u[0]``)."""
    if fs <= 0.0:
        return np.ones(u.size)
    f = 0.0
    out = np.empty(u.size)
    previous = u[0]
    for _ in range(2):
        for i in range(u.size):
            f = min(max(f + kt * (u[i] - previous), -fs), fs)
            previous = u[i]
            out[i] = abs(f) / fs
    return out


def _state_at_zero(solution, fundamental: float, n_dof: int):
    """Displacement and velocity at ``t = 0`` of a harmonic-balance
    solution (harmonics of ``fundamental``, rad/s)."""
    if np.shape(solution.coefficients)[0] != n_dof:
        raise ValueError("start is a solution of another system")
    return state_at_zero(
        solution.harmonic_numbers,
        np.asarray(solution.coefficients, dtype=np.float64),
        fundamental,
    )


def _orbit_samples(solution, n_dof: int, n_samples: int) -> np.ndarray:
    """Displacements of a harmonic-balance solution at ``n_samples``
    instants evenly spaced over its period (the first at ``t = 0``), shape
    (n_dof, n_samples), m."""
    from ..signals import synthesis_matrix

    if np.shape(solution.coefficients)[0] != n_dof:
        raise ValueError("start is a solution of another system")
    theta = 2.0 * np.pi * np.arange(n_samples) / n_samples
    basis = synthesis_matrix(np.asarray(solution.harmonic_numbers), theta)
    return np.asarray(solution.coefficients, dtype=np.float64) @ basis.T


def _state_at(solution, fundamental: float, n_dof: int, time: float):
    """Displacement and velocity of a harmonic-balance solution at
    ``time`` (s; its series shifted by ``time``)."""
    if np.shape(solution.coefficients)[0] != n_dof:
        raise ValueError("start is a solution of another system")
    shifted = np.array(solution.coefficients, dtype=np.float64)
    col = 0
    for k in solution.harmonic_numbers:
        k = int(k)
        if k == 0:
            col += 1
            continue
        c, s = np.cos(k * fundamental * time), np.sin(k * fundamental * time)
        xc, xs = shifted[:, col].copy(), shifted[:, col + 1].copy()
        shifted[:, col] = xc * c + xs * s
        shifted[:, col + 1] = xs * c - xc * s
        col += 2
    return state_at_zero(solution.harmonic_numbers, shifted, fundamental)


def _partial(ops: tuple, steps: int) -> tuple:
    """The kernels' system for the first ``steps`` steps of the period."""
    out = list(ops)
    out[5] = np.ascontiguousarray(ops[5][:, :steps])
    return tuple(out)


def _rolled(ops: tuple, section: int) -> tuple:
    """The kernels' system for a period that starts at step ``section``."""
    if section == 0:
        return ops
    out = list(ops)
    out[5] = np.ascontiguousarray(np.roll(ops[5], -section, axis=1))
    return tuple(out)


def _run(kernel, ops, x, v, law_state, work, periods: int) -> None:
    """``periods`` periods in place; raise on a kernel failure."""
    starts = np.empty((periods + 1, 2 * x.size + 1))
    peaks = np.empty((periods, 3))
    status, _, _ = kernel(ops, x, v, law_state, work, starts, peaks)
    _check(status)


def _check(status: int) -> None:
    if status != OK:
        raise ConvergenceError(
            "monodromy: an integration of the period map failed: "
            + MESSAGES.get(int(status), f"kernel status {status}")
        )
