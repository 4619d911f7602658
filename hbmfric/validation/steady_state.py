"""The time-integration reference: periodic steady state reached by fixed-step
integration, analysed into harmonics.

Independent of the harmonic-balance path except for the contact-law kernels
(:func:`hbmfric.kernels.laws.updates.law_step` and ``law_init``), which both evaluate
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
from ..errors import AccuracyWarning, ConvergenceError, ConvergenceWarning
from ..results import CURVE_REST, _resolve_dof
from ..signals import harmonic_amplitude, sampled_peak_to_peak
from .integrator import MESSAGES, OK
from .problems import SingleContact, _Run

if TYPE_CHECKING:
    from ..systems import Oscillator


#: largest a priori scheme error (:attr:`SteadyState.scheme_error`) that
#: passes without an :class:`~hbmfric.AccuracyWarning`: at 2048 steps per
#: period a stuck structure with 1 % damping stays below it (4e-5 on the
#: flanks of its resonance), one with 0.1 % does not (3.9e-4, stop 34)
SCHEME_TOLERANCE = 1e-4


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
        Contact force at the same instants, N (zeros without contact; with
        several contacts the first contact's, on its first coordinate).
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
        From step halving (``check_halving=True``): the largest change of
        a DOF's first-harmonic amplitude when the step is halved, relative
        to that DOF's own amplitude (``max_d |a₁d(N) / a₁d(2N) - 1|``; a DOF
        below ``CURVE_REST`` = 1e-4 of the largest amplitude relative to
        that floor), so that it bounds what ``amplitude(1, dof=d)`` reads
        for any ``d``. For the second-order scheme the error of this result
        is about 4/3 of it. NaN if not computed. Before stop 34 it was
        relative to the largest amplitude of all DOFs: on a 3-DOF chain
        whose contact DOF moved 10 times less than the forced one it read
        7.1e-5 where the contact DOF's amplitude was 9.5e-4 off.
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
    scheme_error : float
        Error of the scheme where the motion is the stuck structure's: the
        largest relative change of a DOF's first harmonic when the stuck
        structure is forced at the scheme's pulsation ``Ω̃ = (2/h)
        tan(Ωh/2)`` instead of ``Ω`` (the trapezoidal rule's periodic
        response is the exact one at ``Ω̃``); it grows as ``1/ζ`` on the
        flanks of a lightly damped resonance. Above ``SCHEME_TOLERANCE`` =
        1e-4 the call warns (``hf.AccuracyWarning``). NaN where the motion
        is not the stuck structure's (its first harmonic more than 5 % off
        it: a contact slips), with a modified Dahl law (no stuck state) or
        after a failed integration; ``check_halving=True`` measures the
        errors of slip phases and stick onsets.
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
    scheme_error: float = math.nan

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
    problem = SingleContact.build(system, force)
    x, v = problem.initial_state(initial_state, omega, steps_per_period)
    f = problem.initial_law_state(x)

    run = problem.integrate(omega, steps_per_period, tol, max_periods, x, v, f)
    coefficients = _fourier_coefficients(run.samples, harmonics)
    scheme_error, scheme_dof = problem.scheme_error(
        omega, steps_per_period, coefficients[:, 1] - 1j * coefficients[:, 2]
    )
    if run.status == OK and scheme_error > SCHEME_TOLERANCE:
        # the error goes as h²: the steps that bring it to half the tolerance
        needed = steps_per_period * math.sqrt(2.0 * scheme_error / SCHEME_TOLERANCE)
        warnings.warn(
            f"time integration at Ω = {omega:.6g} rad/s: the motion is the "
            f"stuck structure's, and the trapezoidal rule's pulsation "
            f"(2/h) tan(Ωh/2) moves its first harmonic (amplitude and phase) "
            f"by {scheme_error:.2g} "
            f"(relative, DOF {scheme_dof}) at "
            f"{steps_per_period} steps per period (too coarse for a lightly "
            f"damped resonance nearby); the result carries an error of that order. "
            f"steps_per_period >= {int(math.ceil(needed / 256.0)) * 256} brings "
            f"it below {SCHEME_TOLERANCE:g}",
            AccuracyWarning,
            stacklevel=2,
        )
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
            error_estimate = halving_change(a_coarse, a_fine)

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
        message=_message(run, tol, max_periods),
        dof_names=dict(getattr(system, "dof_names", {})),
        final_state=final_state,
        scheme_error=scheme_error,
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


def halving_change(a_coarse: np.ndarray, a_fine: np.ndarray) -> float:
    """Largest relative change of the DOFs' amplitudes between two step
    sizes (:attr:`SteadyState.error_estimate`).

    Parameters
    ----------
    a_coarse, a_fine : ndarray, shape (n_dof,)
        First-harmonic amplitudes with ``N`` and ``2 N`` steps per period, m.

    Returns
    -------
    float
        ``max_d |a_coarse[d] - a_fine[d]| / max(a_fine[d], floor)`` with the
        floor ``CURVE_REST`` times the largest ``a_fine`` (0 when all are 0).
    """
    scale = float(np.max(a_fine))
    if not scale > 0.0:
        return 0.0
    own = np.maximum(a_fine, CURVE_REST * scale)
    return float(np.max(np.abs(a_coarse - a_fine) / own))


def _message(run: _Run, tol: float, max_periods: int | None = None) -> str:
    if run.status != OK:
        return MESSAGES.get(run.status, f"kernel status {run.status}")
    if not run.converged:
        # what to do: a lightly damped structure, or a stuck contact whose
        # slider offset decays only through the structure's damping, needs
        # more periods than the default (stop 33: 20000 periods of an
        # 81-DOF beam, 234 s CPU, ended 3.3e-10 from tol = 1e-10)
        limit = f"max_periods = {max_periods}" if max_periods else "max_periods"
        return (
            f"{limit} reached, period-to-period change {run.change:.2e} > "
            f"tol = {tol:.2g}; raise max_periods or tol, or start nearer the "
            "steady state (initial_state='linear' or (x0, v0))"
        )
    return MESSAGES[OK]


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
