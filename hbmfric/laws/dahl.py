"""The modified Dahl restoring-force model as a contact law (docs/laws.md)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._validate import finite_array, finite_float
from ..errors import AccuracyWarning
from ..kernels.aft.dahl import DAHL_NOT_CONVERGED, dahl_periodic
from ..kernels.laws import updates as _k
from .base import ContactLaw


def _pair(name: str, value) -> tuple[float, float]:
    try:
        slope, offset = value
    except (TypeError, ValueError):
        raise ValueError(
            f"{name} must be a pair (slope N/m, offset N), got {value!r}"
        ) from None
    return finite_float(f"{name}[0]", slope), finite_float(f"{name}[1]", offset)


@dataclass(frozen=True)
class ModifiedDahl(ContactLaw):
    """Modified Dahl model: a rate-independent hysteretic restoring force.

    ``dF/dt = β (h − F sgn u̇)^μ u̇`` with ``h = h_u`` on loading and
    ``h = −h_l`` on unloading: the force relaxes towards the upper envelope
    ``h_u = a u + b`` while ``u`` increases and towards the lower one
    ``h_l = d u + e`` while it decreases, at a rate set by ``β``. For
    ``μ = 1`` the branches tend to ``h_u − a/β`` and ``h_l + d/β``.

    Parameters
    ----------
    beta : float
        ``β > 0``; 1/m for ``μ = 1`` (in general N^(1-μ)/m).
    exponent : float
        ``μ >= 1`` (1 gives exact exponential branches).
    upper : (float, float)
        ``(a, b)`` of ``h_u = a u + b``: N/m, N.
    lower : (float, float)
        ``(d, e)`` of ``h_l = d u + e``: N/m, N; the envelopes must be
        apart, ``b > e``.

    Notes
    -----
    A constant displacement carries the mid-envelope force
    ``½(h_u + h_l)``, the limit of a vanishing loop; small loops around it
    have the stiffness ``β ((h_u − h_l)/2)^μ`` (:attr:`stuck_stiffness` at
    ``u = 0``).
    """

    beta: float
    exponent: float = 1.0
    upper: tuple[float, float] = (0.0, 1.0)
    lower: tuple[float, float] = (0.0, -1.0)
    code: ClassVar[int] = _k.DAHL

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "beta", finite_float("beta", self.beta, low=0.0, low_open=True)
        )
        object.__setattr__(
            self, "exponent", finite_float("exponent", self.exponent, low=1.0)
        )
        upper = _pair("upper", self.upper)
        lower = _pair("lower", self.lower)
        if not upper[1] > lower[1]:
            raise ValueError(
                f"upper offset b must exceed lower offset e (the envelopes must be "
                f"apart), got b={upper[1]}, e={lower[1]}"
            )
        object.__setattr__(self, "upper", upper)
        object.__setattr__(self, "lower", lower)
        reason = self.active_reason()
        if reason is not None:
            warnings.warn(
                f"ModifiedDahl(beta={self.beta}, exponent={self.exponent}, "
                f"upper={upper}, lower={lower}): {reason}, so the law gives "
                "energy instead of dissipating it. Its steady responses can "
                "be computed; Branch.stability() decides their stability by "
                "the time-domain monodromy (Hill's verdicts leave out the "
                "law's memory and can call an unstable orbit stable), and "
                "where the monodromy cannot be formed (the law between two "
                "DOFs) check them by time integration (docs/laws.md)",
                AccuracyWarning,
                stacklevel=3,
            )

    def active_reason(self) -> str | None:
        """Why the law's loops give energy instead of dissipating it, or
        None where that is not known to happen.

        ``μ = 1``: the energy per cycle of a loop ``u = X cos θ`` is
        ``2 (b − e − (a + d)/β)(X − tanh(βX)/β)``
        (:meth:`energy_per_cycle`), of the sign of ``b − e − (a + d)/β`` at
        every amplitude. ``μ > 1`` with slopes ``a, d ≥ 0``: large
        loops follow the asymptotes ``h_u − (a/β)^(1/μ)`` and
        ``h_l + (d/β)^(1/μ)`` (where ``df/du`` equals the envelope's
        slope), so their energy per cycle tends to
        ``2 X (b − e − (a/β)^(1/μ) − (d/β)^(1/μ))``: negative for large
        ``X`` when ``b − e ≤ (a/β)^(1/μ) + (d/β)^(1/μ)`` (small loops may
        still dissipate). Negative slopes at ``μ > 1`` are not checked.
        Stop 32: the law ``β = 1``, ``(5, 1)``, ``(5, −1)`` on one DOF was
        called stable above 4.27 rad/s where the monodromy reads
        multipliers 1.08-1.14 and time integration from the orbit grows to
        140-197 times its amplitude; the stability of such laws is now
        decided by the monodromy
        (:func:`hbmfric.stability.stability_of_points`).
        """
        a, b = self.upper
        d, e = self.lower
        if self.exponent == 1.0:
            limit = (a + d) / self.beta
            if b - e <= limit:
                return (
                    f"b - e = {b - e:g} <= (a + d)/beta = {limit:g}: every loop "
                    "has a negative energy per cycle"
                )
            return None
        if a >= 0.0 and d >= 0.0:
            root = 1.0 / self.exponent
            limit = (a / self.beta) ** root + (d / self.beta) ** root
            if b - e <= limit:
                return (
                    f"b - e = {b - e:g} <= (a/beta)^(1/exponent) + "
                    f"(d/beta)^(1/exponent) = {limit:g}: large loops have a "
                    "negative energy per cycle"
                )
        return None

    @property
    def params(self) -> np.ndarray:
        a, b = self.upper
        d, e = self.lower
        return np.array([self.beta, self.exponent, a, b, d, e])

    @property
    def odd(self) -> bool:
        a, b = self.upper
        d, e = self.lower
        return a == d and b == -e

    def small_loop_stiffness(self, u: float = 0.0) -> float:
        """Stiffness of vanishing loops around ``u``, ``β ((h_u − h_l)/2)^μ``,
        N/m."""
        u = finite_float("u", u)
        a, b = self.upper
        d, e = self.lower
        width = max(0.5 * ((a - d) * u + b - e), 0.0)
        return float(self.beta * width**self.exponent)

    def static_force(self, u):
        """Force held at a constant displacement (mid-envelope), N."""
        a, b = self.upper
        d, e = self.lower
        return 0.5 * ((a + d) * np.asarray(u, dtype=float) + b + e)

    def static_displacement(self, force: float) -> float:
        """Displacement at which the mid-envelope force equals ``force``, m."""
        a, b = self.upper
        d, e = self.lower
        if a + d == 0.0:
            raise ValueError("the mid-envelope is flat (a + d = 0): no unique u")
        return float((2.0 * finite_float("force", force) - b - e) / (a + d))

    def hysteresis(self, u) -> np.ndarray:
        """Steady-state periodic force over one sampled period of ``u``.

        Parameters
        ----------
        u : array_like, shape (n_time,)
            Displacement at equidistant instants of one period, m (periodic:
            sample ``n_time`` = sample 0). The law is rate independent, so
            only the path matters.

        Returns
        -------
        ndarray, shape (n_time,)
            Force on the closed loop, N (the periodic fixed point of the
            march, not a transient).
        """
        u = finite_array("u", u)
        if u.size < 2:
            raise ValueError(f"u must hold at least 2 samples, got {u.size}")
        force = np.empty_like(u)
        status = dahl_periodic(self.params, u, force)
        if status == DAHL_NOT_CONVERGED:
            raise ValueError("the periodic Dahl force did not converge for this u")
        return force

    def energy_per_cycle(self, amplitude: float, n_time: int = 4096) -> float:
        """Energy dissipated per cycle under ``u = X cos θ``, J.

        ``μ = 1``: the closed form (docs/laws.md)
        ``W = 2 (b − e − (a + d)/β)(X − tanh(βX)/β)``; otherwise the loop
        area ``∮ F du`` of :meth:`hysteresis` on ``n_time`` samples
        (trapezoidal rule).
        """
        x = finite_float("amplitude", amplitude, low=0.0)
        a, b = self.upper
        d, e = self.lower
        if self.exponent == 1.0:
            beta = self.beta
            return float(
                2.0 * (b - e - (a + d) / beta) * (x - np.tanh(beta * x) / beta)
            )
        return loop_area(self, x, n_time)


def loop_area(law: ContactLaw, amplitude: float, n_time: int = 4096) -> float:
    """``∮ F du`` over the steady loop under ``u = X cos θ`` (trapezoidal
    rule on ``n_time`` samples), J."""
    theta = 2.0 * np.pi * np.arange(n_time) / n_time
    u = amplitude * np.cos(theta)
    f = law.hysteresis(u)
    du = np.roll(u, -1) - u
    return float(np.sum(0.5 * (f + np.roll(f, -1)) * du))
