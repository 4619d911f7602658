"""The time-integration reference: periodic steady state reached by fixed-step
integration, analysed into harmonics.

Independent of the harmonic-balance path except for the contact-law kernels
(:func:`hbmfric.kernels.laws.law_step` and ``law_init``), which both evaluate
(so that they cannot disagree on the law). The Newmark kernels are in
:mod:`hbmfric.validation.integrator`.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .._validate import finite_float, positive_int
from ..errors import ConvergenceError, ConvergenceWarning
from ..kernels.contact2d import contact2d_step
from ..kernels.dlft import COULOMB
from ..kernels.laws import law_init, state_size
from ..results import _resolve_dof
from ..signals import harmonic_amplitude, sampled_peak_to_peak
from ..systems.protocol import check_load, check_system
from .integrator import (
    MESSAGES,
    NO_CONTACT,
    OK,
    newmark_periods,
    record_period,
)
from .multi_integrator import (
    ELEMENT_2D,
    LAW_1D,
    newmark_periods_multi,
    record_period_multi,
)

if TYPE_CHECKING:
    from ..systems import Oscillator

#: periods per kernel call: first call, and bounds of the adaptive size
_FIRST_CHUNK = 4
_MIN_CHUNK = 2
_MAX_CHUNK = 32
#: changes used to fit the decay rate
_RATE_WINDOW = 16


@dataclass
class SteadyState:
    """Periodic steady state reached by time integration.

    Attributes
    ----------
    omega : float
        Forcing pulsation Ω, rad/s.
    force : float
        Forcing amplitude, N.
    harmonic_numbers : ndarray of int, shape (H + 1,)
        ``0, 1, …, H``.
    coefficients : ndarray, shape (n_dof, 2 H + 1)
        Fourier coefficients of the last period, per DOF, m, in the layout
        ``[X0, Xc1, Xs1, …, XcH, XsH]`` with
        ``x(t) = X0 + Σ Xc_k cos kΩt + Xs_k sin kΩt``.
    samples : ndarray, shape (n_dof, steps_per_period)
        Displacements at the step instants ``t_k = k T / N`` of the last
        period (``T = 2π/Ω``, ``t = 0`` a forcing-phase origin), m.
    contact_force : ndarray, shape (steps_per_period,)
        Contact force at the same instants, N (zeros without contact).
    periods : int
        Periods integrated (the recorded last one included).
    steps : int
        Time steps integrated, ``periods * steps_per_period``.
    newton_iterations : int
        Iterations of the scalar contact update, summed over all steps.
    converged : bool
        The period-to-period change fell below ``tol`` (and no kernel
        failure).
    change : float
        Period-to-period change over the recorded last period: the largest
        of ``max|Δx| / max|x|``, ``max|Δv| / max|v|`` and ``|Δf| / max|f|``
        between its start and end states.
    steps_per_period : int
        ``N``.
    error_estimate : float
        From step halving (``check_halving=True``): change of the
        first-harmonic amplitude when the step is halved, relative to the
        largest first-harmonic amplitude of all DOFs (for one DOF simply
        ``|a₁(N) / a₁(2N) - 1|``). For the second-order scheme the error of
        this result is about 4/3 of it. NaN if not computed.
    halving_periods : int
        Periods integrated with the halved step (0 if not computed).
    elapsed : float
        Wall time, s.
    status : int
        Kernel status code (0 = ok).
    message : str
        Why the integration stopped.
    dof_names : dict
        Named DOFs of the system (e.g. ``"tip"``, ``"contact"``) → index, as
        on :class:`~hbmfric.PeriodicSolution` and :class:`~hbmfric.Branch`.
    final_state : tuple of ndarray or None
        ``(x, v, law_state)`` at the end of the last period (m, m/s and the
        contact laws' state, ``law_state[0]`` a force in N): where
        :func:`~hbmfric.validation.monodromy` starts.
    """

    omega: float
    force: float
    harmonic_numbers: np.ndarray = field(repr=False)
    coefficients: np.ndarray = field(repr=False)
    samples: np.ndarray = field(repr=False)
    contact_force: np.ndarray = field(repr=False)
    periods: int
    steps: int
    newton_iterations: int
    converged: bool
    change: float
    steps_per_period: int
    error_estimate: float
    halving_periods: int
    elapsed: float
    status: int
    message: str
    dof_names: dict = field(default_factory=dict)
    final_state: tuple | None = field(default=None, repr=False)

    @property
    def n_dof(self) -> int:
        """Number of DOFs."""
        return self.samples.shape[0]

    @property
    def period(self) -> float:
        """Forcing period ``2π/Ω``, s."""
        return 2.0 * np.pi / self.omega

    def amplitude(self, harmonic: int | None = None, dof=None) -> float:
        """Amplitude of the displacement of ``dof``, m.

        Parameters
        ----------
        harmonic : int or None
            ``k >= 1``: ``sqrt(Xc_k² + Xs_k²)``; ``0``: ``|X0|``; ``None``:
            half the peak-to-peak value of ``x(t)`` over the last period,
            from the step samples (each extreme refined by the parabola
            through its sample and the two neighbours).
        dof : int, str or None
            DOF index, a name of ``dof_names`` (``"tip"``, ``"force"`` on the
            beam) or None: the DOF named ``"contact"`` (the contact DOF of
            the built-in systems), else 0 -- the same default as
            :meth:`PeriodicSolution.amplitude`, so that
            ``sol.amplitude(1)`` and ``ref.amplitude(1)`` compare one DOF.
        """
        d = _resolve_dof(dof, self.dof_names, self.n_dof)
        if harmonic is None:
            return 0.5 * sampled_peak_to_peak(self.samples[d])
        return float(
            harmonic_amplitude(self.harmonic_numbers, self.coefficients[d], harmonic)
        )

    def time_response(self, n: int = 256, dof=None) -> tuple[np.ndarray, np.ndarray]:
        """Displacement over one period at ``n`` equidistant instants.

        Evaluated from the trigonometric interpolant of the step samples
        (all harmonics up to ``n/2`` that the samples resolve), so that
        ``n = steps_per_period`` returns the samples themselves.

        Parameters
        ----------
        n : int
            Number of instants (>= 2).
        dof : int, str or None
            As in :meth:`amplitude`.

        Returns
        -------
        t : ndarray, shape (n,)
            ``k T / n``, s.
        x : ndarray, shape (n,)
            Displacement, m.
        """
        n = positive_int("n", n, low=2)
        samples = self.samples[_resolve_dof(dof, self.dof_names, self.n_dof)]
        t = self.period * np.arange(n) / n
        return t, _resample(samples, n)

    def __repr__(self) -> str:
        return (
            f"SteadyState(omega={self.omega:g}, force={self.force:g}, "
            f"n_dof={self.n_dof}, amplitude={self.amplitude():.6g}, "
            f"periods={self.periods}, converged={self.converged}, "
            f"change={self.change:.2e}, error_estimate={self.error_estimate:.2e}, "
            f"elapsed={self.elapsed:.3g} s, message={self.message!r})"
        )


def steady_state(
    system: Oscillator,
    force: float,
    omega: float,
    *,
    harmonics: int = 15,
    steps_per_period: int = 2048,
    tol: float = 1e-10,
    max_periods: int = 20000,
    initial_state: tuple | str | None = None,
    check_halving: bool = False,
    on_failure: str = "warn",
) -> SteadyState:
    """Periodic steady state under ``force cos(Ω t)`` by time integration.

    Integrates ``M ẍ + C ẋ + K x + e_c f_c(x_c) = p cos(Ω t)`` with Newmark's
    average-acceleration rule (fixed step ``h = T/N``, contact force updated
    implicitly and exactly through the law kernel), whole period by whole
    period, until the change of displacement, velocity and contact force
    between successive period starts is below ``tol`` relative to their
    peaks over the period; then takes the harmonics of the last period by a
    DFT of its ``N`` step samples (the trapezoidal rule over one period,
    spectrally accurate for a smooth periodic signal).

    Parameters
    ----------
    system : Oscillator or compatible
        A built-in system or any object following the system protocol
        (:mod:`hbmfric.systems.protocol`: ``n_dof``, ``contact_dof``,
        ``contact``, ``matrices() -> (M, C, K)``, ``load_vector(force)``).
    force : float
        Forcing amplitude, N.
    omega : float
        Forcing pulsation Ω, rad/s, > 0.
    harmonics : int
        Highest harmonic ``H`` kept in ``coefficients`` (>= 1).
    steps_per_period : int
        Time steps per period ``N`` (>= 16 and > 2 H).
    tol : float
        Steady-state tolerance (relative), > 0.
    max_periods : int
        Upper limit on the periods integrated; if reached, the last period
        is analysed all the same and ``converged`` is False.
    initial_state : (x0, v0), "linear" or None
        Where the integration starts (it chooses the basin where several
        steady states coexist, as on a Duffing fold):

        * None (default): rest, ``x = v = 0``, contact force 0.
        * ``(x0, v0)``: displacement (m) and velocity (m/s), scalars for one
          DOF (or broadcast to all DOFs), else arrays of shape (n_dof,).
        * ``"linear"``: the periodic solution of the stuck linearisation
          (stiffness ``K + k_t e_c e_cᵀ``, ``k_t`` the law's stiffness at
          rest, 0 for a cubic spring) under the Newmark scheme itself, in
          closed form: ``(K + k_t e_c e_cᵀ - Ω̃² M + iΩ̃ C) X = p`` with
          ``Ω̃ = (2/h) tan(Ω h / 2)``. When the contact sticks this is the
          steady state to rounding (a few periods instead of hundreds);
          otherwise it shortens the transient. It is independent of the
          harmonic balance.

        The contact starts from its virgin state at 0 moved to ``x0[c]``
        (``law_init(code, params, x0[c], state)``).
    check_halving : bool
        Also integrate with the step halved (``2 N`` steps per period) from
        the converged state, to the same ``tol``, and report
        ``error_estimate``.
    on_failure : {"warn", "raise"}
        What to do when the steady state is not reached (``max_periods``
        used up, or a kernel failure such as a contact update that did not
        converge or a response escaping to infinity): ``"warn"`` (default)
        issues a :class:`~hbmfric.ConvergenceWarning` naming the cause and
        returns the last period with ``converged=False``; ``"raise"``
        raises :class:`~hbmfric.ConvergenceError` instead.

    Returns
    -------
    SteadyState
        The last period and its harmonics, the work done and whether the
        steady state was reached (``converged``, ``message``).

    Raises
    ------
    ValueError
        On invalid input, naming the parameter.
    ConvergenceError
        With ``on_failure="raise"``, when the steady state is not reached.
    """
    start = time.perf_counter()
    if on_failure not in ("warn", "raise"):
        raise ValueError(f"on_failure must be 'warn' or 'raise', got {on_failure!r}")
    force = finite_float("force", force)
    omega = finite_float("omega", omega, low=0.0, low_open=True)
    harmonics = positive_int("harmonics", harmonics, low=1)
    steps_per_period = positive_int("steps_per_period", steps_per_period, low=16)
    if steps_per_period <= 2 * harmonics:
        raise ValueError(
            f"steps_per_period must be > 2 * harmonics = {2 * harmonics} "
            f"(the DFT of N samples resolves harmonics below N/2), "
            f"got {steps_per_period}"
        )
    tol = finite_float("tol", tol, low=0.0, low_open=True)
    max_periods = positive_int("max_periods", max_periods)
    if not isinstance(check_halving, bool | np.bool_):
        raise ValueError(f"check_halving must be True or False, got {check_halving!r}")
    problem = _Problem.build(system, force)
    x, v = problem.initial_state(initial_state, omega, steps_per_period)
    f = problem.initial_law_state(x)

    run = problem.integrate(omega, steps_per_period, tol, max_periods, x, v, f)
    coefficients = _fourier_coefficients(run.samples, harmonics)
    final_state = (x.copy(), v.copy(), f.copy())

    error_estimate = math.nan
    halving_periods = 0
    if check_halving and run.status == OK:
        fine = problem.integrate(omega, 2 * steps_per_period, tol, max_periods, x, v, f)
        halving_periods = fine.periods
        if fine.status == OK:
            a_coarse = np.hypot(coefficients[:, 1], coefficients[:, 2])
            fine_coefficients = _fourier_coefficients(fine.samples, 1)
            a_fine = np.hypot(fine_coefficients[:, 1], fine_coefficients[:, 2])
            scale = float(np.max(a_fine))
            error_estimate = (
                float(np.max(np.abs(a_coarse - a_fine)) / scale) if scale > 0 else 0.0
            )

    result = SteadyState(
        omega=omega,
        force=force,
        harmonic_numbers=np.arange(harmonics + 1),
        coefficients=coefficients,
        samples=run.samples,
        contact_force=run.contact_force,
        periods=run.periods,
        steps=run.periods * steps_per_period,
        newton_iterations=run.newton_iterations,
        converged=run.converged,
        change=run.change,
        steps_per_period=steps_per_period,
        error_estimate=error_estimate,
        halving_periods=halving_periods,
        elapsed=time.perf_counter() - start,
        status=run.status,
        message=_message(run, tol),
        dof_names=dict(getattr(system, "dof_names", {})),
        final_state=final_state,
    )
    if not result.converged:
        text = (
            f"time integration at Ω = {omega:.6g} rad/s did not reach the steady "
            f"state after {result.periods} periods: {result.message}"
        )
        if on_failure == "raise":
            raise ConvergenceError(text)
        warnings.warn(text, ConvergenceWarning, stacklevel=2)
    return result


def _message(run: _Run, tol: float) -> str:
    if run.status != OK:
        return MESSAGES.get(run.status, f"kernel status {run.status}")
    if not run.converged:
        return f"max_periods reached, period-to-period change {run.change:.2e} > tol"
    return MESSAGES[OK]


@dataclass(frozen=True)
class _Run:
    """Outcome of one integration to the steady state."""

    status: int
    periods: int
    newton_iterations: int
    converged: bool
    change: float
    samples: np.ndarray
    contact_force: np.ndarray


@dataclass(frozen=True)
class _Problem:
    """The system as flat float64 arrays, ready for the kernels."""

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    load: np.ndarray
    contact_dof: int
    law_code: int
    law_params: np.ndarray
    stuck_stiffness: float
    #: constant load ``p₀`` (system hook ``static_load()``), N, and the phase
    #: φ of the forcing ``p cos(Ωt − φ)`` (system attribute ``load_phase``),
    #: already applied to ``load``, the complex amplitude ``q`` of the forcing
    #: ``Re(q e^{iΩt})``
    static_load: np.ndarray | None = None
    load_phase: float = 0.0

    @classmethod
    def build(cls, system, force) -> _Problem | _MultiProblem:
        data = check_system(system)
        force = finite_float("force", force)
        law = data.contact
        load = check_load(system, force, data.n_dof, data.load_phase)
        if len(data.contacts) > 1 or any(max(c[2:]) >= 0 for c in data.contacts):
            return _MultiProblem.build(data, load)
        if law is None:
            code, params, k_stuck = NO_CONTACT, np.zeros(1), 0.0
        elif law.code == COULOMB:
            raise ValueError(
                "the time-integration reference has no rigid Coulomb contact "
                "(hf.Coulomb is solved by harmonic balance only); use a stiff "
                "hf.Jenkins element here, e.g. stiffness = 1e3-1e4 times the "
                "structure's stiffness at the contact, with the same slip force"
            )
        else:
            code = int(law.code)
            params = np.ascontiguousarray(law.params, dtype=np.float64)
            if params.ndim != 1 or not np.all(np.isfinite(params)):
                raise ValueError("system.contact.params must be a finite 1-d array")
            k_stuck = float(law.stuck_stiffness)
        return cls(
            data.mass,
            data.damping,
            data.stiffness,
            load,
            data.contact_dof,
            code,
            params,
            k_stuck,
            data.static_load,
            data.load_phase,
        )

    @property
    def n_dof(self) -> int:
        return self.load.size

    def initial_state(
        self, state, omega: float, steps: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(x0, v0)`` as fresh float64 arrays of shape (n_dof,)."""
        n = self.n_dof
        if state is None:
            return np.zeros(n), np.zeros(n)
        if isinstance(state, str):
            if state != "linear":
                raise ValueError(
                    f"initial_state must be None, 'linear' or a pair (x0, v0), "
                    f"got {state!r}"
                )
            return self.linear_steady_state(omega, steps)
        try:
            x0, v0 = state
        except (TypeError, ValueError):
            raise ValueError(
                f"initial_state must be None, 'linear' or a pair (x0, v0), "
                f"got {state!r}"
            ) from None
        out = []
        for name, value in (("x0", x0), ("v0", v0)):
            try:
                a = np.broadcast_to(np.asarray(value, dtype=np.float64), (n,))
            except (TypeError, ValueError):
                raise ValueError(
                    f"initial_state {name} must be a scalar or an array of shape "
                    f"({n},), got {value!r}"
                ) from None
            if not np.all(np.isfinite(a)):
                raise ValueError(f"initial_state {name} must be finite, got {value!r}")
            out.append(np.array(a))
        return out[0], out[1]

    def linear_steady_state(
        self, omega: float, steps: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """Periodic Newmark solution of the stuck linearisation at ``t = 0``.

        The trapezoidal rule maps ``x_k = Re(X e^{iΩ t_k})`` to
        ``v_k = Re(iΩ̃ X e^{iΩ t_k})`` with ``Ω̃ = (2/h) tan(Ωh/2)``, so its
        periodic response is the linear FRF at the modified pulsation.
        """
        h = 2.0 * np.pi / (omega * steps)
        omega_h = (2.0 / h) * np.tan(0.5 * omega * h)
        k = self.stiffness.astype(complex)
        c = self.contact_dof
        k[c, c] += self.stuck_stiffness
        dynamic = k - omega_h**2 * self.mass + 1j * omega_h * self.damping
        try:
            X = np.linalg.solve(dynamic, self.load)
        except np.linalg.LinAlgError:
            raise ValueError(
                "initial_state='linear': the stuck linearisation is singular at "
                f"omega={omega} (undamped resonance); give (x0, v0) instead"
            ) from None
        return np.ascontiguousarray(X.real), np.ascontiguousarray(-omega_h * X.imag)

    def initial_law_state(self, x: np.ndarray) -> np.ndarray:
        """Virgin contact-law state at 0 moved to ``x[c]`` (``[0]`` the
        force, N)."""
        if self.law_code == NO_CONTACT:
            return np.zeros(1)
        code = np.int64(self.law_code)
        state = np.empty(int(state_size(code, self.law_params)))
        law_init(code, self.law_params, float(x[self.contact_dof]), state)
        return state

    def operators(self, omega: float, steps: int):
        """Newmark operators ``(Aᵀ, Bᵀ, q, q₀, g, cos_sum, 2/h)`` for ``h = T/N``
        (see :mod:`hbmfric.validation.integrator`)."""
        n = self.n_dof
        h = 2.0 * np.pi / (omega * steps)
        k_eff = (4.0 / h**2) * self.mass + (2.0 / h) * self.damping + self.stiffness
        unit = np.zeros(n)
        unit[self.contact_dof] = 1.0
        static = np.zeros(n) if self.static_load is None else self.static_load
        rhs = np.column_stack(
            (self.stiffness, self.mass, self.load.real, -self.load.imag, unit, static)
        )
        try:
            solved = np.linalg.solve(k_eff, rhs)
        except np.linalg.LinAlgError:
            raise ValueError(
                "the effective stiffness (4/h²) M + (2/h) C + K is singular; "
                "check the system matrices"
            ) from None
        # the kernels take the transposes (column-wise products)
        A_t = np.ascontiguousarray(-2.0 * solved[:, :n].T)
        B_t = np.ascontiguousarray((4.0 / h) * solved[:, n : 2 * n].T)
        q = np.ascontiguousarray(solved[:, 2 * n : 2 * n + 2].T)
        g = np.ascontiguousarray(solved[:, 2 * n + 2])
        q0 = np.ascontiguousarray(2.0 * solved[:, 2 * n + 3])
        if self.law_code != NO_CONTACT and not g[self.contact_dof] > 0.0:
            raise ValueError(
                "the effective stiffness must be positive definite at the contact "
                "DOF; check the system matrices"
            )
        phase = 2.0 * np.pi * np.arange(steps + 1) / steps
        samples = np.stack((np.cos(phase), np.sin(phase)))
        cos_sum = np.ascontiguousarray(samples[:, :-1] + samples[:, 1:])
        return A_t, B_t, q, q0, g, cos_sum, 2.0 / h

    def kernel_system(self, omega: float, steps: int) -> tuple:
        """The kernels' ``system`` tuple for ``h = T/N``
        (:func:`hbmfric.validation.integrator.newmark_periods`)."""
        A_t, B_t, q, q0, g, cos_sum, two_over_h = self.operators(omega, steps)
        return (
            A_t,
            B_t,
            q,
            q0,
            g,
            cos_sum,
            np.int64(self.contact_dof),
            np.int64(self.law_code),
            self.law_params,
            two_over_h,
        )

    def kernels(self):
        """The period and recording kernels."""
        return newmark_periods, record_period

    def integrate(self, omega, steps, tol, max_periods, x, v, f) -> _Run:
        """Integrate from ``(x, v, f)`` (advanced in place) until the change
        over a period is below ``tol`` or ``max_periods`` are done.

        Python checks the convergence: the kernel returns the state at every
        period start, and the number of periods of the next kernel call is
        predicted from the decay rate of the last changes. The last period
        of every call is recorded at the step instants, so the period that
        passes the test is the one analysed.
        """
        system = self.kernel_system(omega, steps)
        periods_kernel, record_kernel = self.kernels()
        n = self.n_dof
        work = np.empty(n)
        samples = np.empty((n, steps))
        contact_force = np.empty(steps)
        record_peaks = np.empty((1, 3))
        periods = 0
        iterations = 0
        converged = False
        change = math.inf
        chunk = _FIRST_CHUNK
        history: list[float] = []
        while True:
            # a chunk: (chunk - 1) plain periods, then one recorded period whose
            # change decides convergence
            chunk = min(chunk, max_periods - periods)
            if chunk > 1:
                starts = np.empty((chunk, 2 * n + 1))
                peaks = np.empty((chunk - 1, 3))
                status, done, its = periods_kernel(system, x, v, f, work, starts, peaks)
                periods += int(done)
                iterations += int(its)
                if status != OK:
                    return self._failed(status, periods, iterations, steps)
                history.extend(_period_changes(starts, peaks, n).tolist())
            before = np.concatenate((x, v, f[:1]))
            status, its = record_kernel(
                system, x, v, f, work, record_peaks[0], samples, contact_force
            )
            periods += 1
            iterations += int(its)
            if status != OK:
                return self._failed(status, periods, iterations, steps)
            after = np.concatenate((x, v, f[:1]))
            change = float(
                _period_changes(np.vstack((before, after)), record_peaks, n)[0]
            )
            history.append(change)
            if change <= tol:
                converged = True
                break
            if periods >= max_periods:
                break
            chunk = _next_chunk(history, tol)
        return _Run(OK, periods, iterations, converged, change, samples, contact_force)

    def _failed(self, status, periods, iterations, steps) -> _Run:
        nan = np.full((self.n_dof, steps), np.nan)
        return _Run(status, periods, iterations, False, math.nan, nan, nan[0].copy())


class _MultiProblem(_Problem):
    """Several contacts (to ground or between two DOFs, any law but the
    rigid Coulomb, and 2D elements) for
    :mod:`hbmfric.validation.multi_integrator`: the contact coordinates'
    rows, the laws' codes, parameters and state layout. Same interface as
    :class:`_Problem` (whose single-contact fields it leaves at "no
    contact")."""

    @classmethod
    def build(cls, data, load) -> _MultiProblem:
        rows, kinds, codes, first, stiff = [], [], [], [], []
        params, param_at, state_at, sizes = [], [0], [], []
        n_coord = sum(2 if c[3] >= 0 else 1 for c in data.contacts)
        offset = n_coord
        for law, a, b, a_n, b_n in data.contacts:
            if law.code == COULOMB:
                raise ValueError(
                    "the time-integration reference has no rigid Coulomb contact "
                    "(hf.Coulomb is solved by harmonic balance only); use a stiff "
                    "hf.Jenkins element here"
                )
            p = np.ascontiguousarray(law.params, dtype=np.float64)
            if p.ndim != 1 or not np.all(np.isfinite(p)):
                raise ValueError("every contact law's params must be finite 1-d")
            first.append(len(rows))
            rows.append((a, b))
            if a_n >= 0:  # the 2D element: tangential and normal coordinates
                kinds.append(ELEMENT_2D)
                rows.append((a_n, b_n))
                closed = law.preload > 0.0
                kt, kn = law.tangential_stiffness, law.normal_stiffness
                stiff += [kt, kn] if closed else [0.0, 0.0]
                size = 1
            else:
                kinds.append(LAW_1D)
                stiff.append(float(law.stuck_stiffness))
                size = int(state_size(np.int64(law.code), p))
            codes.append(int(law.code))
            params.append(p)
            param_at.append(param_at[-1] + p.size)
            state_at.append(offset)
            sizes.append(size)
            offset += size
        self = cls(
            data.mass,
            data.damping,
            data.stiffness,
            load,
            0,
            NO_CONTACT,
            np.zeros(1),
            0.0,
            data.static_load,
            data.load_phase,
        )
        object.__setattr__(self, "rows", np.array(rows, dtype=np.int64))
        extra = {
            "kinds": np.array(kinds, dtype=np.int64),
            "codes": np.array(codes, dtype=np.int64),
            "params": np.concatenate(params),
            "param_at": np.array(param_at, dtype=np.int64),
            "first": np.array(first, dtype=np.int64),
            "state_at": np.array(state_at, dtype=np.int64),
            "sizes": np.array(sizes, dtype=np.int64),
            "coordinate_stiffness": np.array(stiff),
            "state_length": offset,
        }
        for key, value in extra.items():
            object.__setattr__(self, key, value)
        return self

    def reader(self) -> np.ndarray:
        """``Bc``, shape (m, n_dof): the coordinates from ``x``."""
        B = np.zeros((self.rows.shape[0], self.n_dof))
        for i, (a, b) in enumerate(self.rows):
            B[i, a] += 1.0
            if b >= 0:
                B[i, b] -= 1.0
        return B

    def linear_steady_state(self, omega: float, steps: int):
        """As :meth:`_Problem.linear_steady_state` with every coordinate
        held by its law's stuck stiffness (a 2D element's tangential and
        normal stiffness when preloaded, none when open at rest)."""
        h = 2.0 * np.pi / (omega * steps)
        omega_h = (2.0 / h) * np.tan(0.5 * omega * h)
        B = self.reader()
        k = self.stiffness + B.T @ (self.coordinate_stiffness[:, None] * B)
        dynamic = k - omega_h**2 * self.mass + 1j * omega_h * self.damping
        try:
            X = np.linalg.solve(dynamic, self.load)
        except np.linalg.LinAlgError:
            raise ValueError(
                "initial_state='linear': the stuck linearisation is singular at "
                f"omega={omega} (undamped resonance); give (x0, v0) instead"
            ) from None
        x0 = np.ascontiguousarray(X.real)
        v0 = np.ascontiguousarray(-omega_h * X.imag)
        if self.static_load is not None:
            x0 = x0 + np.linalg.solve(
                self.stiffness + B.T @ (self.coordinate_stiffness[:, None] * B),
                self.static_load - B.T @ self._rest_forces(),
            )
        return x0, v0

    def _rest_forces(self) -> np.ndarray:
        """Coordinate forces at ``x = 0`` (a 2D element's preload)."""
        f = np.zeros(self.rows.shape[0])
        for k, kind in enumerate(self.kinds):
            if kind == ELEMENT_2D:
                a = self.param_at[k]
                f[self.first[k] + 1] = max(self.params[a + 3], 0.0)
        return f

    def initial_law_state(self, x: np.ndarray) -> np.ndarray:
        """Every law virgin at 0 moved to its coordinate at ``x`` (a 2D
        element's slider at its tangential coordinate); the coordinate
        forces first."""
        c = self.reader() @ x
        state = np.zeros(self.state_length)
        for k, kind in enumerate(self.kinds):
            j, s = self.first[k], self.state_at[k]
            p = self.params[self.param_at[k] : self.param_at[k + 1]]
            if kind == LAW_1D:
                block = state[s : s + self.sizes[k]]
                law_init(np.int64(self.codes[k]), p, float(c[j]), block)
                state[j] = block[0]
            else:
                state[s] = c[j]
                t, n, _, _ = contact2d_step(
                    p[0], p[1], p[2], p[3], c[j], c[j], c[j + 1]
                )
                state[j], state[j + 1] = t, n
        return state

    def kernel_system(self, omega: float, steps: int) -> tuple:
        n = self.n_dof
        h = 2.0 * np.pi / (omega * steps)
        k_eff = (4.0 / h**2) * self.mass + (2.0 / h) * self.damping + self.stiffness
        B = self.reader()
        static = np.zeros(n) if self.static_load is None else self.static_load
        rhs = np.column_stack(
            (self.stiffness, self.mass, self.load.real, -self.load.imag, static, B.T)
        )
        try:
            solved = np.linalg.solve(k_eff, rhs)
        except np.linalg.LinAlgError:
            raise ValueError(
                "the effective stiffness (4/h²) M + (2/h) C + K is singular; "
                "check the system matrices"
            ) from None
        A_t = np.ascontiguousarray(-2.0 * solved[:, :n].T)
        B_t = np.ascontiguousarray((4.0 / h) * solved[:, n : 2 * n].T)
        q = np.ascontiguousarray(solved[:, 2 * n : 2 * n + 2].T)
        q0 = np.ascontiguousarray(2.0 * solved[:, 2 * n + 2])
        G = np.ascontiguousarray(solved[:, 2 * n + 3 :])
        Gc = np.ascontiguousarray(B @ G)
        phase = 2.0 * np.pi * np.arange(steps + 1) / steps
        samples = np.stack((np.cos(phase), np.sin(phase)))
        cos_sum = np.ascontiguousarray(samples[:, :-1] + samples[:, 1:])
        return (
            A_t,
            B_t,
            q,
            q0,
            G,
            cos_sum,
            Gc,
            self.kinds,
            self.codes,
            self.params,
            self.first,
            self.state_at,
            np.zeros(self.rows.shape[0]),
            self.sizes,
            self.rows,
            2.0 / h,
            self.param_at,
            np.zeros((self.rows.shape[0], self.rows.shape[0])),
            np.zeros((self.rows.shape[0], self.rows.shape[0])),
        )

    def kernels(self):
        return newmark_periods_multi, record_period_multi


def _period_changes(starts: np.ndarray, peaks: np.ndarray, n: int) -> np.ndarray:
    """Relative change of ``[x, v, f]`` over each period, shape (n_periods,).

    ``starts`` has shape (n_periods + 1, 2 n + 1), ``peaks`` (n_periods, 3).
    Each part is measured against its own peak over the period; a part that
    is zero throughout counts as unchanged.
    """
    diff = np.abs(np.diff(starts, axis=0))
    parts = np.column_stack(
        (diff[:, :n].max(axis=1), diff[:, n : 2 * n].max(axis=1), diff[:, 2 * n])
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(parts == 0.0, 0.0, parts / peaks)
    return ratio.max(axis=1)


def _next_chunk(history: list[float], tol: float) -> int:
    """Periods for the next kernel call.

    The decay rate of the changes, fitted (least squares on their logarithm,
    which smooths the ripple of a transient seen once per period) over the
    last periods, predicts how many periods remain, so that little is
    integrated past convergence.
    """
    recent = np.asarray(history[-_RATE_WINDOW:])
    recent = recent[recent > 0]
    if recent.size < 3:
        return _FIRST_CHUNK
    slope = np.polyfit(np.arange(recent.size), np.log(recent), 1)[0]
    if not slope < 0.0:
        return _MAX_CHUNK
    remaining = math.log(tol / recent[-1]) / slope
    if not remaining < _MAX_CHUNK:
        return _MAX_CHUNK
    return min(_MAX_CHUNK, max(_MIN_CHUNK, math.ceil(remaining) + 1))


def _fourier_coefficients(samples: np.ndarray, harmonics: int) -> np.ndarray:
    """Coefficients ``[X0, Xc1, Xs1, …, XcH, XsH]`` of sampled periods.

    Parameters
    ----------
    samples : ndarray, shape (n_dof, N)
        One period at ``t_k = k T / N``.
    harmonics : int
        ``H < N / 2``.

    Returns
    -------
    ndarray, shape (n_dof, 2 H + 1)
    """
    spectrum = np.fft.rfft(samples, axis=1) / samples.shape[1]
    out = np.empty((samples.shape[0], 2 * harmonics + 1))
    out[:, 0] = spectrum[:, 0].real
    out[:, 1::2] = 2.0 * spectrum[:, 1 : harmonics + 1].real
    out[:, 2::2] = -2.0 * spectrum[:, 1 : harmonics + 1].imag
    return out


def _resample(samples: np.ndarray, n: int) -> np.ndarray:
    """Trigonometric interpolant of one sampled period, at ``n`` instants.

    Harmonics ``k < n/2`` are kept whole; the harmonic ``n/2`` (``n`` even)
    contributes what sampling it at ``n`` points gives; the Nyquist term of
    the input (``N`` even) is the usual split ``c cos(N θ / 2)``.
    """
    m = samples.size
    spectrum = np.fft.rfft(samples) / m  # c_k, x = Σ c_k e^{ikθ} + c.c.
    top = min(m // 2, n // 2)
    # one-sided cosine/sine amplitudes a_k - i b_k
    one_sided = 2.0 * spectrum[: top + 1]
    one_sided[0] = spectrum[0]
    if m % 2 == 0 and top == m // 2:
        one_sided[top] = spectrum[top].real  # input Nyquist: c cos(m θ / 2)
    out = np.zeros(n // 2 + 1, dtype=complex)
    out[: top + 1] = 0.5 * one_sided
    out[0] = one_sided[0]
    if n % 2 == 0 and top == n // 2:
        out[top] = one_sided[top].real  # sampled at n points: a cos(n θ / 2)
    return np.fft.irfft(out * n, n)
