"""Belt-tension FRF of the tensioner rig, ``|max T − min T|`` against the
forcing frequency, by three routes:

* ``time_domain_frf(..., method="bdf")``: the paper's route — at every
  frequency, integrate the first-order system ``[u1, u2, u̇1, u̇2, F]`` (the
  Dahl force as a state, ``dF/dt = β σ(h − F sgn u̇2) u̇2``) with scipy's
  ``solve_ivp(method="BDF")`` period after period until the state at the
  period start repeats to ``tol``;
* ``time_domain_frf(..., method="jit")``: the project's fixed-step Newmark
  integrator (:func:`hbmfric.validation.steady_state`), the Dahl force
  updated exactly per step through the law kernel;
* ``hbm_frf``: harmonic balance through the engine's one path,
  :func:`hbmfric.frf` (defaults: ``harmonics="auto"``, coverage,
  retrace, warnings), in hertz, with the tension range of every point;
  optionally subharmonic (fundamental ``Ω/ν``, fixed ``H``).

The independent reference of both is the shooting solution of
:mod:`hbmfric.systems.tensioner_shooting` (``bench/tensioner_reference.py``).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from .._validate import finite_float, positive_int
from ..continuation import ContinuationOptions
from ..errors import ConvergenceWarning
from ..signals import sampled_peak_to_peak, synthesis_matrix
from ..validation import steady_state
from .tensioner import BeltTensioner, tension_coefficients


@dataclass
class TensionFRF:
    """Tension variation against forcing frequency.

    Attributes
    ----------
    frequency : ndarray, shape (n,)
        Forcing frequency ``Ω/2π``, Hz (path order for HBM).
    tension_range : ndarray, shape (n,)
        ``max T − min T`` over the steady state, N.
    force : float
        Forcing amplitude ``f1``, N.
    method : str
        ``"bdf"``, ``"jit"`` or ``"hbm"`` (``"hbm/3"`` for a subharmonic run).
    elapsed : float
        Wall time, s.
    converged : ndarray of bool, shape (n,)
        Time domain: steady state reached; HBM: all True (only converged
        points are stored).
    work : dict
        Work counters: periods and steps (time domain), or continuation
        steps, rejections and Newton iterations (HBM).
    info : dict
        Stop reason (HBM), settings.
    """

    frequency: np.ndarray
    tension_range: np.ndarray
    force: float
    method: str
    elapsed: float
    converged: np.ndarray
    work: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    def plot(self, ax=None, **kwargs):
        """Plot ``|max T − min T|`` against frequency (lazy matplotlib)."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        style = "-" if self.method.startswith("hbm") else "o"
        kwargs.setdefault("label", f"{self.method}, f1 = {self.force:g} N")
        ax.plot(self.frequency, self.tension_range, style, ms=3, **kwargs)
        ax.set_xlabel("forcing frequency (Hz)")
        ax.set_ylabel("|max T − min T| (N)")
        return ax

    def at(self, frequency) -> np.ndarray:
        """Tension range interpolated at ``frequency`` (Hz) along the path;
        for a folded HBM branch, the first crossing."""
        f = np.asarray(frequency, dtype=float)
        order = np.argsort(self.frequency, kind="stable")
        return np.interp(f, self.frequency[order], self.tension_range[order])


def branch_tension_range(rig: BeltTensioner, branch) -> np.ndarray:
    """``max T − min T`` (N) at every point of an HBM branch of the rig.

    Parameters
    ----------
    rig : BeltTensioner
    branch : Branch
        From :func:`hbmfric.frf` (or a subharmonic run, whose ``omega`` is
        the fundamental ``Ω/ν``), coefficients of shape (n, 2, n_coef), m.

    Returns
    -------
    ndarray, shape (n,)

    Notes
    -----
    The tension is synthesised on ``64 H`` samples per period of the
    fundamental and each extreme refined by a parabola (error of the order
    of the cube of the step: below 1e-7 relative); vectorised, since a
    per-point Newton refinement would cost more than the continuation.
    """
    hn = branch.harmonic_numbers
    n_theta = 64 * max(int(hn[-1]), 1)
    theta = 2.0 * math.pi * np.arange(n_theta) / n_theta
    basis = synthesis_matrix(hn, theta)
    tension = np.array(
        [
            tension_coefficients(rig, hn, c, w)
            for c, w in zip(branch.coefficients, branch.omega, strict=True)
        ]
    ).reshape(len(branch), -1)
    return np.array([sampled_peak_to_peak(row) for row in tension @ basis.T])


def _frequencies(frequencies) -> np.ndarray:
    f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    if f.ndim != 1 or f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ValueError("frequencies must be a non-empty 1-d array of values > 0 Hz")
    return f


def time_domain_frf(
    rig: BeltTensioner,
    force: float,
    frequencies,
    method: str = "jit",
    *,
    steps_per_period: int = 512,
    tol: float | None = None,
    max_periods: int = 20000,
    rtol: float = 1e-7,
) -> TensionFRF:
    """Tension FRF by time integration to the steady state at each frequency.

    Parameters
    ----------
    rig : BeltTensioner
    force : float
        Forcing amplitude ``f1``, N.
    frequencies : array_like, shape (n,)
        Forcing frequencies, Hz.
    method : {"jit", "bdf"}
        The project's Newmark integrator, or scipy's BDF.
    steps_per_period : int
        ``jit``: fixed steps per period; ``bdf``: output samples per period
        (the tension extremes are refined by a parabola through the samples).
    tol : float, optional
        Steady state: relative change of the state over one period; default
        1e-6 for ``jit`` and 1e-5 for ``bdf`` (whose variable-step error,
        ``rtol``, puts a noise floor under the period-to-period change).
    max_periods : int
        Per frequency.
    rtol : float
        ``bdf``: relative tolerance of ``solve_ivp`` (``atol`` scaled from
        it and the static state).

    Returns
    -------
    TensionFRF
    """
    if method not in ("jit", "bdf"):
        raise ValueError(f"method must be 'jit' or 'bdf', got {method!r}")
    force = finite_float("force", force)
    freqs = _frequencies(frequencies)
    steps_per_period = positive_int("steps_per_period", steps_per_period, low=16)
    if tol is None:
        tol = 1e-6 if method == "jit" else 1e-5
    tol = finite_float("tol", tol, low=0.0, low_open=True)
    max_periods = positive_int("max_periods", max_periods)
    start = time.perf_counter()
    ranges = np.empty(freqs.size)
    converged = np.zeros(freqs.size, dtype=bool)
    periods = 0
    steps = 0
    x0 = rig.static_solution()
    for i, fhz in enumerate(freqs):
        omega = 2.0 * math.pi * fhz
        if method == "jit":
            with warnings.catch_warnings():
                # one summary warning below instead of one per frequency
                warnings.simplefilter("ignore", ConvergenceWarning)
                ss = steady_state(
                    rig,
                    force,
                    omega,
                    harmonics=1,
                    steps_per_period=steps_per_period,
                    tol=tol,
                    max_periods=max_periods,
                    initial_state=(x0, 0.0),
                )
            x = ss.samples
            spectrum = np.fft.rfft(x, axis=1)
            k = np.arange(spectrum.shape[1])
            v = np.fft.irfft(1j * k * omega * spectrum, x.shape[1], axis=1)
            tension = rig.tension(x, v)
            ranges[i] = sampled_peak_to_peak(tension)
            converged[i] = ss.converged
            periods += ss.periods
            steps += ss.steps
        else:
            rng, ok, p, n_steps = _bdf_steady_state(
                rig, force, omega, steps_per_period, tol, max_periods, rtol
            )
            ranges[i] = rng
            converged[i] = ok
            periods += p
            steps += n_steps
    if not converged.all():
        missed = freqs[~converged]
        warnings.warn(
            f"the time integration did not reach the steady state at "
            f"{missed.size} of {freqs.size} frequencies ({missed[0]:.4g} Hz "
            f"first); their tension ranges are from the last period integrated "
            f"(TensionFRF.converged)",
            ConvergenceWarning,
            stacklevel=2,
        )
    return TensionFRF(
        frequency=freqs,
        tension_range=ranges,
        force=force,
        method=method,
        elapsed=time.perf_counter() - start,
        converged=converged,
        work={"periods": periods, "steps": steps},
        info={"steps_per_period": steps_per_period, "tol": tol},
    )


def _bdf_rhs(rig: BeltTensioner, force: float, omega: float):
    """Right-hand side and Jacobian of ``[u1, u2, v1, v2, F]``."""
    m1, m2 = rig.mass_shaker, rig.mass_pulley
    K, C, T0, g = rig.belt_stiffness, rig.belt_damping, rig.pretension, rig.gravity
    f0 = rig.static_force
    beta, mu, a, b, d, e = rig.tensioner.params

    def dahl_rate(u2, v2, F):
        """dF/dt and its partials in (u2, v2, F)."""
        if v2 >= 0.0:
            x = a * u2 + b - F
            s, slope = 1.0, a
        else:
            x = F - d * u2 - e
            s, slope = -1.0, d
        p = abs(x) ** (mu - 1.0) if mu != 1.0 else 1.0
        sigma = x * p
        dsigma = mu * p
        rate = beta * sigma * v2
        return (
            rate,
            beta * dsigma * s * slope * v2,
            beta * sigma,
            -beta * dsigma * s * v2,
        )

    def rhs(t, y):
        u1, u2, v1, v2, F = y
        T = K * (u1 - u2) + C * (v1 - v2) + T0
        dF = dahl_rate(u2, v2, F)[0]
        return np.array(
            [
                v1,
                v2,
                (-T + f0 + force * math.sin(omega * t) + m1 * g) / m1,
                (T - F + m2 * g) / m2,
                dF,
            ]
        )

    def jac(t, y):
        u1, u2, v1, v2, F = y
        _, r_u2, r_v2, r_F = dahl_rate(u2, v2, F)
        J = np.zeros((5, 5))
        J[0, 2] = 1.0
        J[1, 3] = 1.0
        J[2, :4] = np.array([-K, K, -C, C]) / m1
        J[3, :4] = np.array([K, -K, C, -C]) / m2
        J[3, 4] = -1.0 / m2
        J[4, 1] = r_u2
        J[4, 3] = r_v2
        J[4, 4] = r_F
        return J

    return rhs, jac


def _bdf_steady_state(rig, force, omega, samples, tol, max_periods, rtol):
    from scipy.integrate import solve_ivp

    rhs, jac = _bdf_rhs(rig, force, omega)
    period = 2.0 * math.pi / omega
    x0 = rig.static_solution()
    y = np.array([x0[0], x0[1], 0.0, 0.0, rig.tensioner_static_force])
    atol = rtol * np.array(
        [1e-3, 1e-3, 1e-3 * omega, 1e-3 * omega, rig.tensioner_static_force]
    )
    t_eval = np.arange(samples + 1) * period / samples
    steps = 0
    for p in range(1, max_periods + 1):
        t0 = (p - 1) * period
        sol = solve_ivp(
            rhs,
            (t0, t0 + period),
            y,
            method="BDF",
            jac=jac,
            rtol=rtol,
            atol=atol,
            t_eval=t0 + t_eval,
            # from rest the forcing starts at sin 0 = 0: without a bound the
            # first step would skip the whole period
            max_step=period / 20.0,
        )
        steps += sol.t.size if sol.nfev == 0 else int(sol.nfev)
        if not sol.success:
            return math.nan, False, p, steps
        y_new = sol.y[:, -1]
        # changes relative to the oscillation of each state, not its offset
        osc = np.ptp(sol.y, axis=1)
        change = max(
            float(np.max(np.abs(y_new[:4] - y[:4]) / np.maximum(osc[:4], 1e-300))),
            float(abs(y_new[4] - y[4]) / max(osc[4], 1e-300)),
        )
        y = y_new
        if change <= tol:
            u1, u2, v1, v2, _ = sol.y[:, :-1]
            tension = rig.tension(np.array([u1, u2]), np.array([v1, v2]))
            return sampled_peak_to_peak(tension), True, p, steps
    u1, u2, v1, v2, _ = sol.y[:, :-1]
    tension = rig.tension(np.array([u1, u2]), np.array([v1, v2]))
    return sampled_peak_to_peak(tension), False, max_periods, steps


def hbm_frf(
    rig: BeltTensioner,
    force: float,
    frequency_range: tuple[float, float],
    harmonics: int | str = "auto",
    *,
    subharmonic: int = 1,
    n_time: int | None = None,
    options: ContinuationOptions | None = None,
    sweep: str = "up",
    harmonic_tolerance: float = 1e-4,
) -> TensionFRF:
    """Tension FRF by harmonic balance: :func:`hbmfric.frf` in hertz, with
    the tension range of every point.

    Parameters
    ----------
    rig : BeltTensioner
    force : float
        Forcing amplitude ``f1``, N.
    frequency_range : (float, float)
        Forcing frequencies ``(low, high)``, Hz.
    harmonics : int or "auto", default "auto"
        Highest harmonic of the fundamental ``Ω/ν``; ``"auto"`` as in
        :func:`hbmfric.frf` (``ν = 1`` only).
    subharmonic : int
        ``ν``: solve for responses of period ``ν T`` (fixed ``harmonics``
        only; such a branch carries no truncation estimate).
    n_time : int, optional
        AFT samples per period (fixed ``harmonics`` only; default from
        :class:`~hbmfric.hbm.HBMProblem`).
    options : ContinuationOptions, optional
    sweep : {"up", "down"}
    harmonic_tolerance : float
        As in :func:`hbmfric.frf`.

    Returns
    -------
    TensionFRF
        Points in path order; ``info["branch"]`` holds the
        :class:`~hbmfric.Branch` (its ``omega`` is the fundamental
        ``Ω/ν``, rad/s), ``info["coefficients"]`` the coefficients
        ``(n, 2, n_coef)``, ``info["harmonic_numbers"]`` and
        ``info["stop_reason"]``.

    Warns
    -----
    CoverageWarning, AccuracyWarning
        As :func:`hbmfric.frf`.
    """
    from ..api import _frf_fixed, _problem
    from ..api import frf as _frf

    try:
        lo, hi = (
            finite_float("frequency_range", f, low=0.0, low_open=True)
            for f in frequency_range
        )
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f"frequency_range must be a pair (low, high) in Hz, > 0: {exc}"
        ) from None
    if not hi > lo:
        raise ValueError(f"frequency_range must be increasing, got ({lo}, {hi})")
    nu = positive_int("subharmonic", subharmonic, low=1)
    if sweep not in ("up", "down"):
        raise ValueError(f"sweep must be 'up' or 'down', got {sweep!r}")
    start = time.perf_counter()
    omega_range = (2.0 * math.pi * lo / nu, 2.0 * math.pi * hi / nu)
    if nu == 1:
        branch = _frf(
            rig,
            force,
            omega_range,
            harmonics,
            n_time=n_time,
            sweep=sweep,
            options=options,
            harmonic_tolerance=harmonic_tolerance,
        )
    else:
        if isinstance(harmonics, str):
            raise ValueError(
                f"subharmonic = {nu} needs a fixed number of harmonics, got "
                f"{harmonics!r}"
            )
        if not isinstance(options, ContinuationOptions | None):
            raise TypeError(
                f"options must be a ContinuationOptions, got {type(options).__name__}"
            )
        problem = _problem(rig, force, harmonics, n_time, False, "auto", None, nu)
        branch = _frf_fixed(
            rig,
            problem,
            omega_range,
            sweep,
            harmonic_tolerance,
            options or ContinuationOptions(),
            None,
            True,
        )
    return TensionFRF(
        frequency=nu * branch.omega / (2.0 * math.pi),
        tension_range=branch_tension_range(rig, branch),
        force=float(force),
        method="hbm" if nu == 1 else f"hbm/{nu}",
        elapsed=time.perf_counter() - start,
        converged=np.ones(len(branch), dtype=bool),
        work={
            "steps": branch.n_steps,
            "rejected": branch.n_rejected,
            "newton_iterations": branch.newton_iterations,
        },
        info={
            "stop_reason": branch.stop_reason,
            "harmonics": branch.info["harmonics"],
            "n_time": branch.info["n_time"],
            "subharmonic": nu,
            "harmonic_numbers": branch.harmonic_numbers.copy(),
            "coefficients": branch.coefficients.copy(),
            "folds": [int(f) for f in branch.folds],
            "branch": branch,
        },
    )
