"""Iwan's model: Jenkins elements in parallel."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._validate import finite_float, positive_int
from ..kernels.laws import updates as _k
from .base import ContactLaw, energy_masing


def _positive_tuple(name: str, values, *, allow_zero: bool) -> tuple[float, ...]:
    try:
        a = np.asarray(values, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        raise ValueError(
            f"{name} must be a sequence of numbers, got {values!r}"
        ) from None
    if a.size == 0:
        raise ValueError(f"{name} must hold at least one element")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite")
    if np.any(a < 0.0) or (not allow_zero and np.any(a == 0.0)):
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must all be {bound}")
    return tuple(float(x) for x in a)


@dataclass(frozen=True)
class Iwan(ContactLaw):
    """Iwan's model: Jenkins elements (stiffness ``k_e``, slip force
    ``f_e``) in parallel, all closed at ``u = 0``.

    It is a Masing law with the virgin curve
    ``F_load(δ) = Σ_e min(k_e δ, f_e)`` and Madelung's memory, and is marched
    as such (cost independent of the number of elements, up to a binary
    search); one element is the Jenkins element.

    Give the slip forces directly, or friction coefficients and one normal
    load (``f_e = μ_e F_n``); only the latter can be moved with
    :meth:`with_normal_load`. :meth:`segalman` builds the elements from the
    4-parameter distribution of Segalman.

    Parameters
    ----------
    stiffnesses : sequence of float, shape (n,)
        ``k_e``, N/m, > 0.
    slip_forces : sequence of float, shape (n,), optional
        ``f_e``, N, >= 0.
    friction_coefficients : sequence of float, shape (n,), optional
        ``μ_e >= 0`` (with ``normal_load``).
    normal_load : float, optional
        ``F_n >= 0``, N (with ``friction_coefficients``).
    """

    stiffnesses: tuple
    slip_forces: tuple | None = None
    friction_coefficients: tuple | None = None
    normal_load: float | None = None
    code: ClassVar[int] = _k.IWAN

    def __post_init__(self) -> None:
        k = _positive_tuple("stiffnesses", self.stiffnesses, allow_zero=False)
        object.__setattr__(self, "stiffnesses", k)
        by_load = self.friction_coefficients is not None or self.normal_load is not None
        if by_load:
            if self.friction_coefficients is None or self.normal_load is None:
                raise ValueError(
                    "give both friction_coefficients and normal_load (or slip_forces)"
                )
            if self.slip_forces is not None:
                raise ValueError(
                    "give either slip_forces or friction_coefficients with "
                    "normal_load, not both"
                )
            mu = _positive_tuple(
                "friction_coefficients", self.friction_coefficients, allow_zero=True
            )
            fn = finite_float("normal_load", self.normal_load, low=0.0)
            object.__setattr__(self, "friction_coefficients", mu)
            object.__setattr__(self, "normal_load", fn)
            forces = tuple(m * fn for m in mu)
        elif self.slip_forces is None:
            raise ValueError(
                "give slip_forces, or friction_coefficients and normal_load"
            )
        else:
            forces = _positive_tuple("slip_forces", self.slip_forces, allow_zero=True)
        if len(forces) != len(k):
            raise ValueError(
                f"slip_forces (or friction_coefficients) must have the length of "
                f"stiffnesses ({len(k)}), got {len(forces)}"
            )
        object.__setattr__(self, "slip_forces", forces)

    @classmethod
    def segalman(
        cls,
        slip_force: float,
        stiffness: float,
        chi: float,
        beta: float,
        n_elements: int = 50,
        normal_load: float | None = None,
    ) -> Iwan:
        """Elements from Segalman's 4-parameter density of slip displacements.

        The density ``ρ(φ) = R φ^χ`` on ``(0, φ_max)`` plus ``S δ(φ - φ_max)``
        (``ρ(φ) dφ`` the stiffness of the elements slipping at ``φ``) with
        ``∫ρ = K_T`` and ``∫φρ = F_S``:
        ``φ_max = F_S (1 + β) / (K_T (β + (χ+1)/(χ+2)))``,
        ``R = F_S (χ+1) / (φ_max^{χ+2} (β + (χ+1)/(χ+2)))``,
        ``S = β F_S / (φ_max (β + (χ+1)/(χ+2)))``.
        The power-law part is cut into cells of equal stiffness, each
        element keeping its cell's exact stiffness and slip force (so the
        totals ``K_T`` and ``F_S`` are exact); the delta is one more
        element (none if ``β = 0``).

        Parameters
        ----------
        slip_force : float
            ``F_S``, the force at macroslip, N, > 0.
        stiffness : float
            ``K_T``, the stuck stiffness, N/m, > 0.
        chi : float
            ``χ > -1``: exponent of the power law (about -0.5 … 0 for
            lap joints; energy per cycle ∝ amplitude^(3+χ) at small
            amplitude).
        beta : float
            ``β >= 0``: weight of the delta at ``φ_max``.
        n_elements : int
            Number of elements (>= 2 when ``β > 0``).
        normal_load : float, optional
            If given, the law is defined by friction coefficients
            ``f_e / F_n`` so that :meth:`with_normal_load` works.
        """
        fs = finite_float("slip_force", slip_force, low=0.0, low_open=True)
        kt = finite_float("stiffness", stiffness, low=0.0, low_open=True)
        chi = finite_float("chi", chi, low=-1.0, low_open=True)
        beta = finite_float("beta", beta, low=0.0)
        n = positive_int("n_elements", n_elements, low=2 if beta > 0.0 else 1)
        c = (chi + 1.0) / (chi + 2.0)
        phi_max = fs * (1.0 + beta) / (kt * (beta + c))
        s = beta * fs / (phi_max * (beta + c))
        m = n - 1 if beta > 0.0 else n
        # cell nodes φ_i with φ_i^(χ+1) = φ_max^(χ+1) i/m (equal stiffness);
        # with u = i/m, ∫ρ over a cell is (K_T − S) Δu and ∫φρ is
        # (F_S − S φ_max) Δ(u^p), p = (χ+2)/(χ+1), free of powers of φ_max
        # and φ_i: as χ → -1 those underflow (φ_1 = φ_max (1/m)^(1/(χ+1)))
        # and the stiffnesses came out 0; now the first cells get slip
        # forces that round to 0 (exact to double precision: they slip at
        # once), and Σ k = K_T, Σ f = F_S hold for every χ > -1
        p = (chi + 2.0) / (chi + 1.0)
        u = np.arange(m + 1) / m
        k = (kt - s) * np.diff(u)
        f = (fs - s * phi_max) * np.diff(u**p)
        if beta > 0.0:
            k = np.append(k, s)
            f = np.append(f, s * phi_max)
        if normal_load is not None:
            fn = finite_float("normal_load", normal_load, low=0.0, low_open=True)
            return cls(tuple(k), friction_coefficients=tuple(f / fn), normal_load=fn)
        return cls(tuple(k), tuple(f))

    @property
    def n_elements(self) -> int:
        """Number of Jenkins elements."""
        return len(self.stiffnesses)

    @property
    def stiffness(self) -> float:
        """Stuck stiffness ``Σ k_e``, N/m."""
        return float(np.sum(self.stiffnesses))

    @property
    def slip_force(self) -> float:
        """Gross-slip force ``Σ f_e``, N."""
        return float(np.sum(self.slip_forces))

    @property
    def params(self) -> np.ndarray:
        k = np.asarray(self.stiffnesses)
        f = np.asarray(self.slip_forces)
        phi = f / k
        order = np.argsort(phi, kind="stable")
        k, f, phi = k[order], f[order], phi[order]
        n = k.size
        slipped = np.concatenate(([0.0], np.cumsum(f)))
        stuck = np.concatenate((np.cumsum(k[::-1])[::-1], [0.0]))
        return np.concatenate(([float(n)], phi, slipped, stuck))

    def with_normal_load(self, normal_load: float) -> Iwan:
        """The same elements at another normal load, N (``f_e = μ_e F_n``)."""
        if self.friction_coefficients is None:
            raise ValueError(
                "this law was given slip_forces; define it by "
                "friction_coefficients and normal_load to change the normal load"
            )
        return Iwan(
            self.stiffnesses,
            friction_coefficients=self.friction_coefficients,
            normal_load=normal_load,
        )

    @property
    def adherent_stiffness(self) -> float:
        """The stiffness a roughness law acts on: ``Σ k_e``, N/m."""
        return self.stiffness

    def with_adherent_stiffness(self, stiffness: float) -> Iwan:
        """All element stiffnesses scaled to the total ``stiffness``, N/m
        (slip forces unchanged)."""
        scale = stiffness / self.stiffness
        k = tuple(x * scale for x in self.stiffnesses)
        if self.friction_coefficients is not None:
            return Iwan(
                k,
                friction_coefficients=self.friction_coefficients,
                normal_load=self.normal_load,
            )
        return Iwan(k, self.slip_forces)

    def virgin_curve(self, delta) -> np.ndarray:
        """``F_load(δ) = Σ_e min(k_e δ, f_e)`` (odd in δ), N."""
        d = np.asarray(delta, dtype=float)
        k = np.asarray(self.stiffnesses)
        f = np.asarray(self.slip_forces)
        out = np.minimum(np.abs(d)[..., None] * k, f).sum(axis=-1)
        return np.sign(d) * out

    def energy_per_cycle(self, amplitude: float) -> float:
        """Energy dissipated per cycle under ``u = a cos θ``: the sum of the
        elements' ``4 f_e (a - f_e/k_e)`` over the slipping ones, J."""
        a = finite_float("amplitude", amplitude, low=0.0)
        k = np.asarray(self.stiffnesses)
        f = np.asarray(self.slip_forces)
        stuck = k * a <= f
        integral = float(
            np.sum(np.where(stuck, 0.5 * k * a * a, f * (a - 0.5 * f / k)))
        )
        return energy_masing(integral, a, float(self.virgin_curve(a)))
