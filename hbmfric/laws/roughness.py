"""Roughness: a friction law whose tangential stiffness depends on the normal
load."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import finite_float
from .base import ContactLaw


def hertz_mindlin_stiffness(
    asymptotic_stiffness: float, normal_load: float, limit_load: float
) -> float:
    """Default roughness law: ``kt = kt_∞ (F_n / F_lim)^(1/3)`` below the
    limit load, ``kt_∞`` above (asperities crushed), N/m.

    Parameters
    ----------
    asymptotic_stiffness : float
        ``kt_∞``, N/m (or the unit of the law's adherent stiffness), >= 0.
    normal_load : float
        ``F_n``, N, >= 0.
    limit_load : float
        ``F_lim``, N, > 0.

    Returns
    -------
    float
        ``kt``, in the unit of ``asymptotic_stiffness``.
    """
    asymptotic_stiffness = finite_float(
        "asymptotic_stiffness", asymptotic_stiffness, low=0.0
    )
    normal_load = finite_float("normal_load", normal_load, low=0.0)
    limit_load = finite_float("limit_load", limit_load, low=0.0, low_open=True)
    if normal_load >= limit_load:
        return asymptotic_stiffness
    return asymptotic_stiffness * (normal_load / limit_load) ** (1.0 / 3.0)


@dataclass(frozen=True)
class Roughness(ContactLaw):
    """A friction law whose tangential stiffness depends on the normal load.

    Below the limit load the surfaces are not fully adherent and the
    stiffness is ``stiffness_law(kt_∞, F_n, F_lim)`` (default
    :func:`hertz_mindlin_stiffness`); above it, the wrapped law's own
    stiffness ``kt_∞``. Which stiffness that is depends on the law
    (its ``adherent_stiffness``): ``kt`` for Jenkins, the shear-layer
    stiffness ``k_s`` for Menq, the total ``Σ k_e`` for Iwan (all elements
    scaled alike). The wrapped law must be defined by a friction
    coefficient and a normal load, so that :meth:`with_normal_load` can move
    both the slip force and the stiffness.

    Parameters
    ----------
    law : Jenkins, Menq or Iwan
        The law at full adherence.
    limit_load : float
        ``F_lim``, N, > 0 (300 N in the paper).
    stiffness_law : callable, optional
        ``(kt_inf, normal_load, limit_load) -> kt`` in the units of the
        law's adherent stiffness; must return a positive finite value.
    """

    law: ContactLaw
    limit_load: float = 300.0
    stiffness_law: object = None

    def __post_init__(self) -> None:
        if not hasattr(self.law, "with_adherent_stiffness"):
            raise ValueError(
                "law must be a Jenkins, Menq or Iwan law, got "
                f"{type(self.law).__name__}"
            )
        if self.law.normal_load is None:
            raise ValueError(
                "the wrapped law needs friction_coefficient and normal_load "
                "(the roughness stiffness depends on the normal load)"
            )
        object.__setattr__(
            self,
            "limit_load",
            finite_float("limit_load", self.limit_load, low=0.0, low_open=True),
        )
        if self.stiffness_law is not None and not callable(self.stiffness_law):
            raise ValueError(
                "stiffness_law must be callable (kt_inf, Fn, Fn_lim) -> kt"
            )
        self.effective  # validates the stiffness law's value  # noqa: B018

    @property
    def code(self) -> int:  # type: ignore[override]
        return self.law.code

    @property
    def normal_load(self) -> float:
        """Normal load, N."""
        return self.law.normal_load

    @property
    def tangential_stiffness(self) -> float:
        """Adherent stiffness at the current normal load (units of the
        wrapped law's ``adherent_stiffness``)."""
        rule = self.stiffness_law or hertz_mindlin_stiffness
        kt = rule(self.law.adherent_stiffness, self.law.normal_load, self.limit_load)
        return finite_float("stiffness_law(...)", kt, low=0.0, low_open=True)

    @property
    def effective(self) -> ContactLaw:
        """The plain law with the load-dependent stiffness."""
        return self.law.with_adherent_stiffness(self.tangential_stiffness)

    @property
    def params(self) -> np.ndarray:
        return self.effective.params

    @property
    def odd(self) -> bool:
        return self.law.odd

    def with_normal_load(self, normal_load: float) -> Roughness:
        """The same contact at another normal load, N."""
        return Roughness(
            self.law.with_normal_load(normal_load), self.limit_load, self.stiffness_law
        )

    def first_harmonic(self, amplitude: float) -> tuple[float, float]:
        """Closed-form first harmonic under ``u = a cos θ`` (Jenkins only)."""
        if not hasattr(self.law, "first_harmonic"):
            raise ValueError(
                f"first_harmonic has no closed form for {type(self.law).__name__}"
            )
        return self.effective.first_harmonic(amplitude)

    def energy_per_cycle(self, amplitude: float) -> float:
        """Energy dissipated per cycle under ``u = a cos θ``, J."""
        return self.effective.energy_per_cycle(amplitude)
