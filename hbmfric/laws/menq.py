"""Menq microslip: an elastic bar on an elastic shear layer (docs/laws.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._validate import finite_float
from ..kernels.laws import updates as _k
from .base import ContactLaw, energy_masing, slip_force_from

#: Gauss–Legendre rule for the virgin-curve integral in the slip length
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(64)


def _lambda_from_onset(ratio: float) -> float:
    """``λ > 0`` with ``tanh(λ)/λ = ratio`` (``0 < ratio < 1``), by
    bisection (the left side decreases from 1 to 0)."""
    lo, hi = 0.0, 2.0 / ratio + 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if math.tanh(mid) / mid > ratio:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15 * hi:
            break
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class Menq(ContactLaw):
    """Menq's microslip model: an elastic bar of axial rigidity ``EA`` and
    length ``L`` on an elastic shear layer (stiffness ``k_s`` per unit
    length) with a uniform friction limit ``q`` per unit length, loaded at
    one end.

    Virgin curve (``α = √(k_s/EA)``, ``λ = αL``): stuck ``F = K0 δ`` with
    ``K0 = √(k_s EA) tanh λ`` up to ``δ1 = q/k_s``; microslip over a slip
    length ``l = x/α``: ``F = (q/α)(x + tanh(λ - x))``,
    ``δ = δ1 (1 + x²/2 + x tanh(λ - x))``; gross slip ``F* = qL`` from
    ``δ_gs = δ1 (1 + λ²/2)``. Cycles follow Masing's rule with Madelung's
    memory (exact inner loops). The loop's mean force follows the contact
    closed at ``u = 0``: the vertex with the largest ``|u|`` lies on the
    virgin curve.

    Give the friction limit ``q`` directly, or a friction coefficient and a
    normal load spread uniformly over the bar (``q = μ F_n / L``); only the
    latter can be moved with :meth:`with_normal_load`. For the terms an
    engineer measures use :meth:`from_stiffness`.

    Parameters
    ----------
    axial_rigidity : float
        ``EA``, N, > 0.
    length : float
        ``L``, m, > 0.
    shear_stiffness : float
        ``k_s``, N/m per m of bar (N/m²), > 0.
    friction_limit : float, optional
        ``q``, N/m, >= 0.
    friction_coefficient : float, optional
        ``μ >= 0`` (with ``normal_load``).
    normal_load : float, optional
        ``F_n >= 0``, N (with ``friction_coefficient``).
    """

    axial_rigidity: float
    length: float
    shear_stiffness: float
    friction_limit: float | None = None
    friction_coefficient: float | None = None
    normal_load: float | None = None
    code: ClassVar[int] = _k.MENQ

    def __post_init__(self) -> None:
        for name in ("axial_rigidity", "length", "shear_stiffness"):
            value = finite_float(name, getattr(self, name), low=0.0, low_open=True)
            object.__setattr__(self, name, value)
        by_load = self.friction_coefficient is not None or self.normal_load is not None
        given_q = None if by_load else self.friction_limit
        force, mu, fn = slip_force_from(
            given_q, self.friction_coefficient, self.normal_load, "friction_limit"
        )
        q = force / self.length if mu is not None else force
        if by_load and self.friction_limit is not None:
            given = finite_float("friction_limit", self.friction_limit, low=0.0)
            if not np.isclose(given, q, rtol=1e-12, atol=0.0):
                raise ValueError(
                    "give either friction_limit or friction_coefficient with "
                    f"normal_load, not both (friction_limit={given}, "
                    f"μ F_n / L={q})"
                )
        object.__setattr__(self, "friction_limit", q)
        object.__setattr__(self, "friction_coefficient", mu)
        object.__setattr__(self, "normal_load", fn)

    @classmethod
    def from_stiffness(
        cls,
        stiffness: float,
        slip_force: float | None = None,
        microslip_onset: float = 0.5,
        *,
        friction_coefficient: float | None = None,
        normal_load: float | None = None,
        length: float = 1.0,
    ) -> Menq:
        """Menq law from its stuck stiffness, gross-slip force and the force
        ratio at which microslip starts.

        Parameters
        ----------
        stiffness : float
            Stuck stiffness ``K0``, N/m, > 0.
        slip_force : float, optional
            Gross-slip force ``F*``, N, >= 0 (or give ``friction_coefficient``
            and ``normal_load``, ``F* = μ F_n``).
        microslip_onset : float
            ``F1/F*`` in (0, 1): the force at the end of the linear range
            over the gross-slip force (``tanh λ / λ``); close to 1 the law
            approaches Jenkins, small values spread microslip wide.
        friction_coefficient, normal_load : float, optional
            See above.
        length : float
            Bar length ``L``, m (> 0); it only fixes the units of the
            physical parameters, not the force–displacement law.
        """
        k0 = finite_float("stiffness", stiffness, low=0.0, low_open=True)
        ratio = finite_float("microslip_onset", microslip_onset, low=0.0, low_open=True)
        if not ratio < 1.0:
            raise ValueError(f"microslip_onset must be < 1, got {ratio}")
        length = finite_float("length", length, low=0.0, low_open=True)
        force, mu, fn = slip_force_from(slip_force, friction_coefficient, normal_load)
        lam = _lambda_from_onset(ratio)
        alpha = lam / length
        shear = alpha * k0 / math.tanh(lam)
        rigidity = shear / alpha**2
        if mu is not None:
            return cls(
                rigidity,
                length,
                shear,
                friction_coefficient=mu,
                normal_load=fn,
            )
        return cls(rigidity, length, shear, friction_limit=force / length)

    # --- derived quantities ------------------------------------------------
    @property
    def alpha(self) -> float:
        """``α = √(k_s/EA)``, 1/m."""
        return math.sqrt(self.shear_stiffness / self.axial_rigidity)

    @property
    def bar_number(self) -> float:
        """``λ = αL`` (dimensionless): the bar's compliance relative to the
        shear layer; small λ is nearly Jenkins."""
        return self.alpha * self.length

    @property
    def stiffness(self) -> float:
        """Stuck stiffness ``K0 = √(k_s EA) tanh λ``, N/m."""
        return math.sqrt(self.shear_stiffness * self.axial_rigidity) * math.tanh(
            self.bar_number
        )

    @property
    def slip_force(self) -> float:
        """Gross-slip force ``F* = qL``, N."""
        return self.friction_limit * self.length

    @property
    def slip_displacement(self) -> float:
        """End of the stuck range ``δ1 = q/k_s``, m."""
        return self.friction_limit / self.shear_stiffness

    @property
    def gross_slip_displacement(self) -> float:
        """Start of gross slip ``δ_gs = δ1 (1 + λ²/2)``, m."""
        return self.slip_displacement * (1.0 + 0.5 * self.bar_number**2)

    @property
    def microslip_onset(self) -> float:
        """``F1/F* = tanh λ / λ``."""
        lam = self.bar_number
        return math.tanh(lam) / lam

    @property
    def params(self) -> np.ndarray:
        lam = self.bar_number
        d1 = self.slip_displacement
        return np.array(
            [
                d1,
                lam,
                self.friction_limit / self.alpha,
                self.stiffness,
                d1 * (1.0 + 0.5 * lam * lam),
                self.slip_force,
            ]
        )

    # --- variants ------------------------------------------------------------
    def with_normal_load(self, normal_load: float) -> Menq:
        """The same contact at another normal load, N (same μ, ``EA``, ``L``,
        ``k_s``: the friction limit scales with ``F_n``)."""
        if self.friction_coefficient is None:
            raise ValueError(
                "this law was given a friction_limit; define it by "
                "friction_coefficient and normal_load to change the normal load"
            )
        return Menq(
            self.axial_rigidity,
            self.length,
            self.shear_stiffness,
            friction_coefficient=self.friction_coefficient,
            normal_load=normal_load,
        )

    @property
    def adherent_stiffness(self) -> float:
        """The stiffness a roughness law acts on: ``k_s``, N/m²."""
        return self.shear_stiffness

    def with_adherent_stiffness(self, shear_stiffness: float) -> Menq:
        """The same contact with another shear-layer stiffness, N/m²."""
        by_load = self.friction_coefficient is not None
        return Menq(
            self.axial_rigidity,
            self.length,
            shear_stiffness,
            friction_limit=None if by_load else self.friction_limit,
            friction_coefficient=self.friction_coefficient,
            normal_load=self.normal_load,
        )

    # --- closed forms --------------------------------------------------------
    def virgin_curve(self, delta) -> np.ndarray:
        """Virgin loading force ``F_load(δ)`` (odd in δ), N.

        Parameters
        ----------
        delta : array_like
            Displacement from the virgin state, m.
        """
        d = np.asarray(delta, dtype=float)
        params = self.params
        flat = np.array(
            [_k.menq_virgin(params, abs(x), -1.0, 0.0, 0.0)[0] for x in d.ravel()]
        )
        return (np.sign(d.ravel()) * flat).reshape(d.shape)

    def virgin_integral(self, amplitude: float) -> float:
        """``∫₀^a F_load(s) ds``, J: closed form in the stuck and gross-slip
        parts; in microslip ``∫ F dδ`` over the slip length by 64-point
        Gauss–Legendre (smooth integrand: exact to rounding)."""
        a = finite_float("amplitude", amplitude, low=0.0)
        d1, lam, fq, k0, d_gs, f_star = self.params
        if a <= d1:
            return 0.5 * k0 * a * a
        total = 0.5 * k0 * d1 * d1
        x_end = lam
        if a < d_gs:
            x_end = _k.menq_slip_length(self.params, a)
        x = 0.5 * x_end * (_GAUSS_X + 1.0)
        t = np.tanh(lam - x)
        integrand = fq * (x + t) * d1 * t * (1.0 + x * t)
        total += 0.5 * x_end * float(np.dot(_GAUSS_W, integrand))
        if a > d_gs:
            total += f_star * (a - d_gs)
        return total

    def energy_per_cycle(self, amplitude: float) -> float:
        """Energy dissipated per cycle under ``u = a cos θ``,
        ``W = 8 ∫₀^a F_load ds − 4 a F_load(a)``, J."""
        a = finite_float("amplitude", amplitude, low=0.0)
        return energy_masing(self.virgin_integral(a), a, float(self.virgin_curve(a)))
