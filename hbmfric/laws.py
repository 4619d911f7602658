"""Contact laws: frozen dataclasses that describe a law and hand its flat
parameter array to the kernels (``hbmfric.kernels.laws``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ._validate import finite_array, finite_float
from .kernels import laws as _k


@dataclass(frozen=True)
class ContactLaw:
    """Base class of contact laws.

    Every law has an integer kernel ``code`` and a flat ``params`` array; the
    AFT march (harmonic balance) and the time-integration reference both
    evaluate the law through :func:`hbmfric.kernels.laws.law_update` with
    them, so the two paths cannot disagree on the law.
    """

    code: ClassVar[int] = -1

    @property
    def params(self) -> np.ndarray:
        """Flat float64 parameter array passed to the kernels."""
        raise NotImplementedError

    @property
    def odd(self) -> bool:
        """True if ``f(-u) = -f(u)`` for the steady-state loop, so that a
        symmetric system responds with odd harmonics only."""
        return True

    @property
    def stuck_stiffness(self) -> float:
        """Tangent stiffness of the law at rest (fully stuck), N/m."""
        return float(_k.linear_stiffness(self.code, self.params))

    def hysteresis(self, u) -> np.ndarray:
        """Steady-state periodic force over one sampled period of ``u``.

        Parameters
        ----------
        u : array_like, shape (n_time,)
            Relative displacement at equidistant instants of one period, m;
            the signal is taken as periodic (sample ``n_time`` = sample 0).

        Returns
        -------
        ndarray, shape (n_time,)
            Contact force, N, on the closed steady-state loop. For a stuck
            contact the slider sits at the reference position 0
            (``f = kt u``), shifted just enough to keep ``|f| <= f_s``.
        """
        from .kernels.aft import periodic_force

        u = finite_array("u", u)
        if u.size < 2:
            raise ValueError(f"u must hold at least 2 samples, got {u.size}")
        force = np.empty_like(u)
        periodic_force(self.code, self.params, u, force)
        return force


@dataclass(frozen=True)
class Jenkins(ContactLaw):
    """Jenkins element (Masing macroslip): a spring in series with a slider.

    Parameters
    ----------
    stiffness : float
        Tangential (stuck) stiffness ``kt``, N/m, > 0.
    slip_force : float
        Slip force ``f_s = μ F_n``, N, >= 0.
    """

    stiffness: float
    slip_force: float
    code: ClassVar[int] = _k.JENKINS

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "stiffness",
            finite_float("stiffness", self.stiffness, low=0.0, low_open=True),
        )
        object.__setattr__(
            self, "slip_force", finite_float("slip_force", self.slip_force, low=0.0)
        )

    @property
    def params(self) -> np.ndarray:
        return np.array([self.stiffness, self.slip_force])

    @property
    def slip_displacement(self) -> float:
        """Displacement amplitude at which gross slip starts, ``f_s / kt``, m."""
        return self.slip_force / self.stiffness

    def first_harmonic(self, amplitude: float) -> tuple[float, float]:
        """Closed-form first harmonic of the steady force under ``u = a cos θ``.

        Returns ``(C1, S1)`` with ``f ≈ C1 cos θ + S1 sin θ`` (SPEC §4).
        """
        a = finite_float("amplitude", amplitude, low=0.0)
        kt, fs = self.stiffness, self.slip_force
        if kt * a <= fs:
            return kt * a, 0.0
        r = fs / (kt * a)
        beta = np.arccos(1.0 - 2.0 * r)
        c1 = kt * a / np.pi * (beta - 0.5 * np.sin(2.0 * beta))
        s1 = -4.0 * fs / np.pi * (1.0 - r)
        return float(c1), float(s1)

    def energy_per_cycle(self, amplitude: float) -> float:
        """Energy dissipated per cycle under ``u = a cos θ``, J."""
        a = finite_float("amplitude", amplitude, low=0.0)
        if self.stiffness * a <= self.slip_force:
            return 0.0
        return 4.0 * self.slip_force * (a - self.slip_force / self.stiffness)


@dataclass(frozen=True)
class Cubic(ContactLaw):
    """Cubic spring ``f = k3 u**3`` (Duffing): smooth, memoryless.

    Parameters
    ----------
    coefficient : float
        ``k3``, N/m^3 (any sign: negative softens).
    """

    coefficient: float
    code: ClassVar[int] = _k.CUBIC

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "coefficient", finite_float("coefficient", self.coefficient)
        )

    @property
    def params(self) -> np.ndarray:
        return np.array([self.coefficient])
