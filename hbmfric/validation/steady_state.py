"""The time-integration reference: periodic steady state by fixed-step
integration, analysed into harmonics."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._validate import dof_index, finite_float, positive_int
from ..kernels.hbm import NO_CONTACT
from ..signals import half_peak_to_peak, harmonic_amplitude
from .integrator import MESSAGES, OK, initial_acceleration, newmark_periods


@dataclass
class SteadyState:
    """Periodic steady state reached by time integration.

    Attributes
    ----------
    omega : float
        Forcing pulsation, rad/s.
    force : float
        Forcing amplitude, N.
    harmonic_numbers : ndarray of int, shape (H + 1,)
        ``0, 1, …, H``.
    coefficients : ndarray, shape (n_dof, 2 H + 1)
        Fourier coefficients of the last period per DOF, m (layout
        ``[X0, Xc1, Xs1, …]``).
    samples : ndarray, shape (n_dof, steps_per_period)
        Displacements at the step instants of the last period, m.
    contact_force : ndarray, shape (steps_per_period,)
        Contact force over the last period, N.
    periods : int
        Periods integrated.
    converged : bool
        The period-to-period change fell below ``tol``.
    change : float
        Last period-to-period relative change.
    steps_per_period : int
    error_estimate : float
        From step halving: relative change of the first-harmonic amplitude
        (of ``dof`` 0) when the step is halved; NaN if not computed. For a
        second-order scheme the error of this result is about that much and
        the error of the halved run a quarter of it.
    elapsed : float
        Wall time, s.
    message : str
    """

    omega: float
    force: float
    harmonic_numbers: np.ndarray
    coefficients: np.ndarray
    samples: np.ndarray
    contact_force: np.ndarray
    periods: int
    converged: bool
    change: float
    steps_per_period: int
    error_estimate: float
    elapsed: float
    message: str

    def amplitude(self, harmonic: int | None = None, dof: int = 0) -> float:
        """Amplitude of harmonic ``k`` (``sqrt(Xc² + Xs²)``), or with
        ``harmonic=None`` half the peak-to-peak of ``x(t)``, m."""
        X = self.coefficients[dof_index(dof, self.coefficients.shape[0])]
        if harmonic is None:
            # all harmonics the sampling resolves, extremes refined on the series
            return float(half_peak_to_peak(*_spectrum(self.samples[dof])))
        return float(harmonic_amplitude(self.harmonic_numbers, X, harmonic))

    def time_response(
        self, n: int = 256, dof: int = 0
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(t, x)`` at ``n`` equidistant instants of the last period, from
        the Fourier series of the samples (s, m)."""
        n = positive_int("n", n, low=2)
        x = self.samples[dof_index(dof, self.samples.shape[0])]
        m = x.size
        spec = np.fft.rfft(x) / m
        out = np.zeros(n // 2 + 1, dtype=complex)
        keep = min(spec.size, out.size)
        out[:keep] = spec[:keep]
        if n % 2 == 0 and keep == out.size:
            out[-1] = out[-1].real  # Nyquist term of a real signal
        t = 2.0 * np.pi / self.omega * np.arange(n) / n
        return t, np.fft.irfft(out * n, n)


def _spectrum(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Harmonics ``0 … m/2 - 1`` of one sampled period in the HBM layout."""
    m = x.size
    h_max = m // 2 - 1
    c = np.fft.rfft(x) / m
    coef = np.empty(2 * h_max + 1)
    coef[0] = c[0].real
    coef[1::2] = 2.0 * c[1 : h_max + 1].real
    coef[2::2] = -2.0 * c[1 : h_max + 1].imag
    return np.arange(h_max + 1), coef


def _run(system, force, omega, steps, max_periods, tol, x, v, f):
    mass, damping, stiffness = (
        np.ascontiguousarray(m, dtype=np.float64) for m in system.matrices()
    )
    load = np.ascontiguousarray(system.load_vector(force), dtype=np.float64)
    law = system.contact
    code = NO_CONTACT if law is None else law.code
    params = np.zeros(1) if law is None else law.params
    samples = np.empty((system.n_dof + 1, steps))
    a = initial_acceleration(
        mass, damping, stiffness, load, system.contact_dof, code, params, x, v, f[0]
    )
    status, periods, change = newmark_periods(
        mass,
        damping,
        stiffness,
        load,
        np.int64(system.contact_dof),
        np.int64(code),
        params,
        omega,
        np.int64(steps),
        np.int64(max_periods),
        tol,
        x,
        v,
        a,
        f,
        samples,
    )
    return int(status), int(periods), float(change), samples


def steady_state(
    system,
    force: float,
    omega: float,
    *,
    harmonics: int = 15,
    steps_per_period: int = 2048,
    tol: float = 1e-10,
    max_periods: int = 20000,
    initial_state=None,
    check_halving: bool = False,
) -> SteadyState:
    """Periodic steady state of ``system`` under ``force cos(Ω t)`` by time
    integration (Newmark average acceleration, exact contact update).

    Independent of the HBM path except for the contact-law kernel they
    share. Integrates whole periods from ``initial_state`` until the
    period-to-period change of displacement, velocity and contact force is
    below ``tol``, then takes the harmonics of the last period.

    Parameters
    ----------
    system : Oscillator or compatible
    force : float
        Forcing amplitude, N.
    omega : float
        Forcing pulsation, rad/s (> 0).
    harmonics : int
        Harmonics ``0 … H`` kept in ``coefficients``.
    steps_per_period : int
        Time steps per period (>= 16, and > 2 H).
    tol : float
        Steady-state tolerance (relative).
    max_periods : int
        Limit; if reached, ``converged`` is False.
    initial_state : (x0, v0), optional
        Initial displacement and velocity (scalars for one DOF, else arrays
        of shape (n_dof,)); the contact starts from its virgin state at 0
        moved to ``x0``. Default: rest. Chooses the basin where several
        steady states coexist.
    check_halving : bool
        Also integrate with half the step (from the converged state) and
        report ``error_estimate``.

    Returns
    -------
    SteadyState
    """
    start = time.perf_counter()
    force = finite_float("force", force)
    omega = finite_float("omega", omega, low=0.0, low_open=True)
    harmonics = positive_int("harmonics", harmonics, low=1)
    steps_per_period = positive_int("steps_per_period", steps_per_period, low=16)
    if steps_per_period <= 2 * harmonics:
        raise ValueError(
            f"steps_per_period must be > 2 * harmonics = {2 * harmonics}, "
            f"got {steps_per_period}"
        )
    tol = finite_float("tol", tol, low=0.0, low_open=True)
    max_periods = positive_int("max_periods", max_periods)
    n_dof = system.n_dof
    x = np.zeros(n_dof)
    v = np.zeros(n_dof)
    if initial_state is not None:
        try:
            x0, v0 = initial_state
        except (TypeError, ValueError):
            raise ValueError("initial_state must be a pair (x0, v0)") from None
        x[:] = np.broadcast_to(np.asarray(x0, dtype=float), (n_dof,))
        v[:] = np.broadcast_to(np.asarray(v0, dtype=float), (n_dof,))
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
            raise ValueError("initial_state must be finite")
    law = system.contact
    f = np.zeros(1)
    if law is not None:
        from ..kernels.laws import law_update

        f[0] = law_update(law.code, law.params, 0.0, 0.0, x[system.contact_dof])[0]
    status, periods, change, samples = _run(
        system, force, omega, steps_per_period, max_periods, tol, x, v, f
    )
    converged = status == OK and change <= tol
    error_estimate = float("nan")
    coefficients = _coefficients(samples[:n_dof], harmonics)
    if check_halving and status == OK:
        x2, v2, f2 = x.copy(), v.copy(), f.copy()
        status2, periods2, change2, samples2 = _run(
            system, force, omega, 2 * steps_per_period, max_periods, tol, x2, v2, f2
        )
        if status2 == OK:
            fine = _coefficients(samples2[:n_dof], harmonics)
            h = np.arange(harmonics + 1)
            a_coarse = harmonic_amplitude(h, coefficients[0], 1)
            a_fine = harmonic_amplitude(h, fine[0], 1)
            error_estimate = float(abs(a_coarse - a_fine) / max(abs(a_fine), 1e-300))
    return SteadyState(
        omega=omega,
        force=force,
        harmonic_numbers=np.arange(harmonics + 1),
        coefficients=coefficients,
        samples=samples[:n_dof].copy(),
        contact_force=samples[n_dof].copy(),
        periods=periods,
        converged=converged,
        change=change,
        steps_per_period=steps_per_period,
        error_estimate=error_estimate,
        elapsed=time.perf_counter() - start,
        message=MESSAGES.get(status, str(status)),
    )


def _coefficients(samples: np.ndarray, harmonics: int) -> np.ndarray:
    """Fourier coefficients ``[X0, Xc1, Xs1, …]`` of sampled periods,
    shape (n_dof, 2 H + 1)."""
    m = samples.shape[1]
    c = np.fft.rfft(samples, axis=1) / m
    out = np.empty((samples.shape[0], 2 * harmonics + 1))
    out[:, 0] = c[:, 0].real
    out[:, 1::2] = 2.0 * c[:, 1 : harmonics + 1].real
    out[:, 2::2] = -2.0 * c[:, 1 : harmonics + 1].imag
    return out
