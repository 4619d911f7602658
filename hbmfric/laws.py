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
        by_load = self.friction_coefficient is not None or self.normal_load is not None
        if by_load:
            if self.friction_coefficient is None or self.normal_load is None:
                raise ValueError(
                    "give both friction_coefficient and normal_load (or slip_force)"
                )
            mu = finite_float(
                "friction_coefficient", self.friction_coefficient, low=0.0
            )
            fn = finite_float("normal_load", self.normal_load, low=0.0)
            if self.slip_force is not None and not np.isclose(
                float(self.slip_force), mu * fn, rtol=1e-12, atol=0.0
            ):
                raise ValueError(
                    "give either slip_force or friction_coefficient with normal_load, "
                    f"not both (slip_force={self.slip_force}, μ F_n={mu * fn})"
                )
            object.__setattr__(self, "friction_coefficient", mu)
            object.__setattr__(self, "normal_load", fn)
            object.__setattr__(self, "slip_force", mu * fn)
        elif self.slip_force is None:
            raise ValueError("give slip_force, or friction_coefficient and normal_load")
        object.__setattr__(
            self, "slip_force", finite_float("slip_force", self.slip_force, low=0.0)
        )

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


def hertz_mindlin_stiffness(
    asymptotic_stiffness: float, normal_load: float, limit_load: float
) -> float:
    """Default roughness law: ``kt = kt_∞ (F_n / F_lim)^(1/3)`` below the
    limit load, ``kt_∞`` above (asperities crushed), N/m."""
    if normal_load >= limit_load:
        return asymptotic_stiffness
    return asymptotic_stiffness * (normal_load / limit_load) ** (1.0 / 3.0)


@dataclass(frozen=True)
class Roughness(ContactLaw):
    """A friction law whose tangential stiffness depends on the normal load.

    Below the limit load the surfaces are not fully adherent and the
    stiffness is ``stiffness_law(kt_∞, F_n, F_lim)`` (default
    :func:`hertz_mindlin_stiffness`); above it, the wrapped law's own
    stiffness ``kt_∞``. The wrapped law must be defined by a friction
    coefficient and a normal load, so that :meth:`with_normal_load` can move
    both the slip force and the stiffness.

    Parameters
    ----------
    law : Jenkins
        The law at full adherence (its stiffness is ``kt_∞``).
    limit_load : float
        ``F_lim``, N, > 0 (300 N in the paper).
    stiffness_law : callable, optional
        ``(kt_inf, normal_load, limit_load) -> kt`` in N/m; must return a
        positive finite value.
    """

    law: ContactLaw
    limit_load: float = 300.0
    stiffness_law: object = None

    def __post_init__(self) -> None:
        if not isinstance(self.law, Jenkins):
            raise ValueError(
                f"law must be a Jenkins element, got {type(self.law).__name__}"
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
        """Stiffness at the current normal load, N/m."""
        rule = self.stiffness_law or hertz_mindlin_stiffness
        kt = rule(self.law.stiffness, self.law.normal_load, self.limit_load)
        return finite_float("stiffness_law(...)", kt, low=0.0, low_open=True)

    @property
    def effective(self) -> Jenkins:
        """The plain law with the load-dependent stiffness."""
        return Jenkins(
            stiffness=self.tangential_stiffness,
            friction_coefficient=self.law.friction_coefficient,
            normal_load=self.law.normal_load,
        )

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
        """Closed-form first harmonic under ``u = a cos θ`` (see Jenkins)."""
        return self.effective.first_harmonic(amplitude)

    def energy_per_cycle(self, amplitude: float) -> float:
        """Energy dissipated per cycle under ``u = a cos θ``, J."""
        return self.effective.energy_per_cycle(amplitude)
