"""Independent time-domain reference for the belt-tensioner rig: the
periodic steady state by shooting on the equations of motion.

The first-order system ``y = [u1, u2, u̇1, u̇2, F]`` (the Dahl force as a
state, ``dF/dt = β σ(h − F sgn u̇2) u̇2``, docs/laws.md) is integrated with
scipy's ``DOP853`` at tight tolerances, one monotone stretch of ``u2`` at a
time: every sign change of ``u̇2`` is located as an event, so the
integrator only ever sees one smooth branch of the law. The right-hand
side is continuous across the switch (``dF/dt = 0`` at ``u̇2 = 0`` on both
sides), so the flow is differentiable and the monodromy matrix follows
from the variational equations of the active branch, with no jump at the
events. Newton's method on ``y(T) − y(0) = 0`` then converges to a period-T
orbit; its Floquet multipliers tell whether a time integration would
settle there.

Nothing here uses the harmonic balance: the HBM solution may serve as the
starting state (to pick the branch at a fold), never as data.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import finite_float, positive_int
from .tensioner import BeltTensioner

#: samples per period of the dense output (tension extremes and Fourier
#: coefficients)
N_SAMPLES = 4096


@dataclass
class ShootingSolution:
    """A period-T orbit of the rig.

    Attributes
    ----------
    frequency : float
        Forcing frequency ``Ω/2π``, Hz.
    force : float
        Forcing amplitude ``f1``, N.
    state : ndarray, shape (5,)
        ``[u1, u2, u̇1, u̇2, F]`` at ``t = 0`` (phase of ``f1 sin Ωt``); m, m/s, N.
    samples : ndarray, shape (5, n_samples)
        The state at ``t_k = k T / n_samples``.
    tension_range : float
        ``max T − min T``, N (extremes refined by parabolas).
    first_harmonic : ndarray, shape (2,)
        First-harmonic amplitude of ``u1`` and ``u2``, m.
    mean : ndarray, shape (2,)
        Mean of ``u1`` and ``u2``, m.
    residual : float
        ``max |y(T) − y(0)| / scale`` at the solution (scale: each state's
        range over the period).
    multipliers : ndarray, shape (5,)
        Floquet multipliers (eigenvalues of the monodromy matrix).
    newton_iterations : int
    converged : bool
        ``residual`` below the tolerance.
    """

    frequency: float
    force: float
    state: np.ndarray
    samples: np.ndarray
    tension_range: float
    first_harmonic: np.ndarray
    mean: np.ndarray
    residual: float
    multipliers: np.ndarray
    newton_iterations: int
    converged: bool

    @property
    def stable(self) -> bool:
        """All Floquet multipliers inside the unit circle."""
        return bool(np.max(np.abs(self.multipliers)) < 1.0)


class _Rig:
    """Right-hand sides of the rig and of its variational equations."""

    def __init__(self, rig: BeltTensioner, force: float, omega: float) -> None:
        self.m1, self.m2 = rig.mass_shaker, rig.mass_pulley
        self.K, self.C = rig.belt_stiffness, rig.belt_damping
        self.T0, self.g, self.f0 = rig.pretension, rig.gravity, rig.static_force
        self.beta, self.mu, self.a, self.b, self.d, self.e = rig.tensioner.params
        self.force, self.omega = force, omega

    def _law(self, s: float, u2: float, F: float):
        """``x``, ``σ(x)``, ``σ'(x)`` and the envelope slope of branch ``s``."""
        if s > 0.0:
            x, slope = self.a * u2 + self.b - F, self.a
        else:
            x, slope = F - self.d * u2 - self.e, self.d
        if self.mu == 1.0:
            return x, x, 1.0, slope
        p = abs(x) ** (self.mu - 1.0)
        return x, x * p, self.mu * p, slope

    def field(self, t: float, y: np.ndarray, s: float) -> np.ndarray:
        u1, u2, v1, v2, F = y[:5]
        T = self.K * (u1 - u2) + self.C * (v1 - v2) + self.T0
        _, sigma, _, _ = self._law(s, u2, F)
        return np.array(
            [
                v1,
                v2,
                (
                    -T
                    + self.f0
                    + self.force * math.sin(self.omega * t)
                    + self.m1 * self.g
                )
                / self.m1,
                (T - F + self.m2 * self.g) / self.m2,
                self.beta * sigma * v2,
            ]
        )

    def jacobian(self, y: np.ndarray, s: float) -> np.ndarray:
        u1, u2, v1, v2, F = y[:5]
        _, sigma, dsigma, slope = self._law(s, u2, F)
        K, C = self.K, self.C
        J = np.zeros((5, 5))
        J[0, 2] = J[1, 3] = 1.0
        J[2, :4] = np.array([-K, K, -C, C]) / self.m1
        J[3, :4] = np.array([K, -K, C, -C]) / self.m2
        J[3, 4] = -1.0 / self.m2
        J[4, 1] = self.beta * dsigma * s * slope * v2
        J[4, 3] = self.beta * sigma
        J[4, 4] = -self.beta * dsigma * s * v2
        return J

    def augmented(self, t: float, z: np.ndarray, s: float) -> np.ndarray:
        out = np.empty_like(z)
        out[:5] = self.field(t, z, s)
        out[5:] = (self.jacobian(z, s) @ z[5:].reshape(5, 5)).reshape(-1)
        return out


def _branch_sign(rig: _Rig, t: float, y: np.ndarray) -> float:
    """Active branch at ``(t, y)``: the sign of ``u̇2``, else of ``ü2``."""
    if y[3] != 0.0:
        return 1.0 if y[3] > 0.0 else -1.0
    acc = rig.field(t, y, 1.0)[3]
    return 1.0 if acc >= 0.0 else -1.0


def _period(rig: _Rig, y0, period, rtol, atol, variational, times=None):
    """Integrate one period from ``y0``; returns ``(y(T), Φ, samples)``."""
    from scipy.integrate import solve_ivp

    n = 30 if variational else 5
    z = np.empty(n)
    z[:5] = y0
    if variational:
        z[5:] = np.eye(5).reshape(-1)
    tol = np.empty(n)
    tol[:5] = atol
    if variational:
        tol[5:] = 1e-3 * rtol
    t = 0.0
    samples = None if times is None else np.empty((5, times.size))
    s = _branch_sign(rig, t, z)
    for _ in range(10000):
        fun = rig.augmented if variational else rig.field

        def event(t, z, s=s):
            return z[3]

        event.terminal = True
        event.direction = -s
        sol = solve_ivp(
            fun,
            (t, period),
            z,
            method="DOP853",
            rtol=rtol,
            atol=tol,
            args=(s,),
            events=event,
            dense_output=times is not None,
            # the forcing starts at sin 0 = 0: bound the first step
            max_step=period / 16.0,
        )
        if sol.status == -1:
            raise RuntimeError(f"integration failed: {sol.message}")
        t_end = float(sol.t[-1])
        if times is not None:
            inside = (times >= t) & (times <= t_end)
            if np.any(inside):
                samples[:, inside] = sol.sol(times[inside])[:5]
        z = sol.y[:, -1].copy()
        if sol.status == 0:
            break
        # event: u̇2 = 0 exactly, switch branch
        z[3] = 0.0
        t = t_end
        s = -s
    else:
        raise RuntimeError("more than 10000 reversals in one period")
    phi = z[5:].reshape(5, 5) if variational else None
    return z[:5], phi, samples


def shooting_steady_state(
    rig: BeltTensioner,
    force: float,
    frequency: float,
    initial_state=None,
    *,
    transient_periods: int = 0,
    rtol: float = 1e-11,
    tol: float = 1e-9,
    max_newton: int = 30,
    n_samples: int = N_SAMPLES,
) -> ShootingSolution:
    """Period-T steady state of the rig by shooting (see the module docstring).

    Parameters
    ----------
    rig : BeltTensioner
    force : float
        Forcing amplitude ``f1`` of ``f1 sin Ωt``, N.
    frequency : float
        ``Ω/2π``, Hz.
    initial_state : array_like, shape (5,), optional
        ``[u1, u2, u̇1, u̇2, F]`` at ``t = 0`` (m, m/s, N); default: the rest
        position with the mid-envelope force.
    transient_periods : int
        Periods integrated from ``initial_state`` before Newton starts.
    rtol : float
        Relative tolerance of ``DOP853`` (the absolute one is ``rtol`` times
        each state's scale).
    tol : float
        Newton: ``max |y(T) − y(0)|`` relative to each state's range.
    max_newton : int
    n_samples : int
        Samples per period of the returned orbit.

    Returns
    -------
    ShootingSolution
    """
    force = finite_float("force", force)
    frequency = finite_float("frequency", frequency, low=0.0, low_open=True)
    n_samples = positive_int("n_samples", n_samples, low=16)
    omega = 2.0 * math.pi * frequency
    period = 1.0 / frequency
    model = _Rig(rig, force, omega)
    if initial_state is None:
        x0 = rig.static_solution()
        y = np.array([x0[0], x0[1], 0.0, 0.0, rig.tensioner_static_force])
    else:
        y = np.array(initial_state, dtype=float).reshape(5)
    u_scale = max(abs(force) / (rig.mass_shaker * omega**2), 1e-9)
    scale0 = np.array(
        [u_scale, u_scale, omega * u_scale, omega * u_scale, rig.tensioner_static_force]
    )
    atol = rtol * scale0
    for _ in range(transient_periods):
        y, _, _ = _period(model, y, period, rtol, atol, False)
    residual = math.inf
    iterations = 0
    phi = np.eye(5)
    scale = scale0
    for iterations in range(1, max_newton + 1):  # noqa: B007
        yT, phi, _ = _period(model, y, period, rtol, atol, True)
        g = yT - y
        residual = float(np.max(np.abs(g) / scale))
        if residual <= tol:
            break
        dy = np.linalg.solve(phi - np.eye(5), -g)
        # damped step: at most the state's scale at once
        ratio = float(np.max(np.abs(dy) / scale))
        y = y + (dy if ratio <= 1.0 else dy / ratio)
        # scales from the orbit once it oscillates
        _, _, samples = _period(
            model, y, period, rtol, atol, False, np.arange(64) * period / 64
        )
        osc = np.ptp(samples, axis=1)
        scale = np.maximum(osc, 1e-6 * scale0)
        atol = rtol * scale
    times = np.arange(n_samples) * period / n_samples
    _, _, samples = _period(model, y, period, rtol, atol, False, times)
    x, v = samples[:2], samples[2:4]
    tension = rig.tension(x, v)
    from ..signals import sampled_peak_to_peak

    spectrum = np.fft.rfft(samples[:2], axis=1) / n_samples
    return ShootingSolution(
        frequency=frequency,
        force=force,
        state=y,
        samples=samples,
        tension_range=sampled_peak_to_peak(tension),
        first_harmonic=2.0 * np.abs(spectrum[:, 1]),
        mean=spectrum[:, 0].real.copy(),
        residual=residual,
        multipliers=np.linalg.eigvals(phi),
        newton_iterations=iterations,
        converged=residual <= tol,
    )


def state_at_zero(
    rig: BeltTensioner,
    harmonic_numbers: np.ndarray,
    coefficients: np.ndarray,
    omega: float,
    n_samples: int = 1024,
) -> np.ndarray:
    """``[u1, u2, u̇1, u̇2, F]`` at ``t = 0`` of a harmonic-balance point, to
    start the shooting on the same branch (m, m/s, N).

    Parameters
    ----------
    rig : BeltTensioner
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (2, n_coef)
        Layout ``[X0, Xc1, Xs1, …]``, m.
    omega : float
        Fundamental pulsation, rad/s.
    n_samples : int
        Samples of ``u2`` over the period for the Dahl force's loop.

    Returns
    -------
    ndarray, shape (5,)
    """
    from .. import signals

    X = np.asarray(coefficients, dtype=float)
    u, v = signals.state_at_zero(harmonic_numbers, X, omega)
    theta = 2.0 * math.pi * np.arange(n_samples) / n_samples
    u2 = X[1] @ signals.synthesis_matrix(harmonic_numbers, theta).T
    force = float(rig.tensioner.hysteresis(u2)[0])
    return np.array([u[0], u[1], v[0], v[1], force])


__all__ = ["ShootingSolution", "shooting_steady_state", "state_at_zero"]
