"""The contact-law base class and the checks shared by the laws."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._validate import finite_array, finite_float, positive_int
from ..kernels.laws import updates as _k


@dataclass(frozen=True)
class ContactLaw:
    """Base class of contact laws.

    Every law has an integer kernel ``code`` and a flat ``params`` array; the
    AFT march (harmonic balance) and the time-integration reference both
    evaluate the law through :func:`hbmfric.kernels.laws.updates.law_step` with
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
            Contact force, N, on the closed steady-state loop. Mean-force
            convention: the contact closed at ``u = 0`` in its virgin state.
            For Jenkins the slider sits at 0 (``f = kt u``) shifted just
            enough to keep ``|f| <= f_s``; for the Masing laws (Menq, Iwan)
            the loop vertex of largest ``|u|`` lies on the virgin curve.
        """
        from ..kernels.aft.schemes import periodic_force

        u = finite_array("u", u)
        if u.size < 2:
            raise ValueError(f"u must hold at least 2 samples, got {u.size}")
        force = np.empty_like(u)
        periodic_force(np.int64(self.code), self.params, u, force)
        return force

    def energy_per_cycle(self, amplitude: float) -> float:
        """Energy dissipated per cycle under ``u = a cos θ``, J.

        Base version: the area of the loop sampled at 8192 instants
        (trapezoidal rule); laws with a closed form override it.
        """
        a = finite_float("amplitude", amplitude, low=0.0)
        theta = 2.0 * np.pi * np.arange(8192) / 8192
        u = a * np.cos(theta)
        f = self.hysteresis(u)
        du = np.roll(u, -1) - u
        return float(np.sum(0.5 * (f + np.roll(f, -1)) * du))

    def plot_loop(self, amplitude: float, n_samples: int = 512, ax=None, **kwargs):
        """Plot the steady-state loop under ``u = a cos θ``.

        Parameters
        ----------
        amplitude : float
            ``a``, m, >= 0.
        n_samples : int
            Samples per period (>= 8).
        ax : matplotlib Axes, optional
            Where to draw; a new figure if None.
        **kwargs
            Passed to ``ax.plot``.

        Returns
        -------
        matplotlib Axes
        """
        a = finite_float("amplitude", amplitude, low=0.0)
        n = positive_int("n_samples", n_samples, low=8)
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        u = a * np.cos(2.0 * np.pi * np.arange(n + 1) / n)
        f = self.hysteresis(u[:-1])
        kwargs.setdefault("label", type(self).__name__)
        ax.plot(u, np.append(f, f[0]), **kwargs)
        ax.set_xlabel("relative displacement u (m)")
        ax.set_ylabel("contact force f (N)")
        return ax


def slip_force_from(
    slip_force, friction_coefficient, normal_load, name: str = "slip_force"
) -> tuple[float, float | None, float | None]:
    """Resolve ``slip_force`` or ``(friction_coefficient, normal_load)``.

    Returns ``(slip_force, μ, F_n)`` with ``μ, F_n = None`` when the slip
    force was given directly; ``name`` is the name of the direct parameter
    in error messages.
    """
    by_load = friction_coefficient is not None or normal_load is not None
    if by_load:
        if friction_coefficient is None or normal_load is None:
            raise ValueError(
                f"give both friction_coefficient and normal_load (or {name})"
            )
        mu = finite_float("friction_coefficient", friction_coefficient, low=0.0)
        fn = finite_float("normal_load", normal_load, low=0.0)
        if slip_force is not None and not np.isclose(
            float(slip_force), mu * fn, rtol=1e-12, atol=0.0
        ):
            raise ValueError(
                f"give either {name} or friction_coefficient with normal_load, "
                f"not both ({name}={slip_force}, μ F_n={mu * fn})"
            )
        return mu * fn, mu, fn
    if slip_force is None:
        raise ValueError(f"give {name}, or friction_coefficient and normal_load")
    return finite_float(name, slip_force, low=0.0), None, None


def energy_masing(virgin_integral: float, amplitude: float, vertex: float) -> float:
    """Energy per cycle of a symmetric Masing loop between ``±(a, F_a)``:
    ``W = 8 ∫₀^a F_load ds − 4 a F_a``, J."""
    return 8.0 * virgin_integral - 4.0 * amplitude * vertex
