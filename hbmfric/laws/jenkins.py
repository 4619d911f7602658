"""Jenkins (Masing macroslip) and the cubic spring."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._validate import finite_float
from ..kernels.laws import updates as _k
from .base import ContactLaw, slip_force_from


@dataclass(frozen=True)
class Jenkins(ContactLaw):
    """Jenkins element (Masing macroslip): a spring in series with a slider.

    Give the slip force directly, or a friction coefficient and a normal
    load (``f_s = μ F_n``); only the latter can be moved to another normal
    load with :meth:`with_normal_load`.

    Parameters
    ----------
    stiffness : float
        Tangential (stuck) stiffness ``kt``, N/m, > 0.
    slip_force : float, optional
        Slip force ``f_s``, N, >= 0.
    friction_coefficient : float, optional
        ``μ >= 0`` (with ``normal_load``).
    normal_load : float, optional
        ``F_n >= 0``, N (with ``friction_coefficient``).
    """

    stiffness: float
    slip_force: float | None = None
    friction_coefficient: float | None = None
    normal_load: float | None = None
    code: ClassVar[int] = _k.JENKINS

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "stiffness",
            finite_float("stiffness", self.stiffness, low=0.0, low_open=True),
        )
        fs, mu, fn = slip_force_from(
            self.slip_force, self.friction_coefficient, self.normal_load
        )
        object.__setattr__(self, "slip_force", fs)
        object.__setattr__(self, "friction_coefficient", mu)
        object.__setattr__(self, "normal_load", fn)

    def with_normal_load(self, normal_load: float) -> Jenkins:
        """The same element at another normal load, N (same μ and kt)."""
        if self.friction_coefficient is None:
            raise ValueError(
                "this law was given a slip_force; define it by friction_coefficient "
                "and normal_load to change the normal load"
            )
        return Jenkins(
            stiffness=self.stiffness,
            friction_coefficient=self.friction_coefficient,
            normal_load=normal_load,
        )

    @property
    def params(self) -> np.ndarray:
        return np.array([self.stiffness, self.slip_force])

    @property
    def adherent_stiffness(self) -> float:
        """The stiffness a roughness law acts on: ``kt``, N/m."""
        return self.stiffness

    def with_adherent_stiffness(self, stiffness: float) -> Jenkins:
        """The same element with another tangential stiffness, N/m."""
        return Jenkins(
            stiffness=stiffness,
            slip_force=None if self.normal_load is not None else self.slip_force,
            friction_coefficient=self.friction_coefficient,
            normal_load=self.normal_load,
        )

    @property
    def slip_displacement(self) -> float:
        """Displacement amplitude at which gross slip starts, ``f_s / kt``, m."""
        return self.slip_force / self.stiffness

    def first_harmonic(self, amplitude: float) -> tuple[float, float]:
        """Closed-form first harmonic of the steady force under ``u = a cos θ``.

        Returns ``(C1, S1)`` with ``f ≈ C1 cos θ + S1 sin θ`` (docs/laws.md).
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

    def energy_per_cycle(self, amplitude: float) -> float:
        """Energy dissipated per cycle: 0 (elastic), J."""
        finite_float("amplitude", amplitude, low=0.0)
        return 0.0
