"""The rigid Coulomb contact: stick/slip without tangential compliance.

Harmonic balance solves it by the dynamic Lagrangian frequency–time method
(:mod:`hbmfric.kernels.dlft.coulomb`), not by an AFT law march: in stick its force is
not a function of the displacement but whatever the dynamics need.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._validate import finite_array, finite_float
from ..kernels.dlft.coulomb import COULOMB
from .base import ContactLaw


@dataclass(frozen=True)
class Coulomb(ContactLaw):
    """Rigid Coulomb friction: the exact stick/slip limit.

    The contact sticks (zero relative motion) while the force it must carry
    stays within ``±f_s``, and slips with ``f = f_s sgn(u̇)`` otherwise. It is
    the limit of a Jenkins element whose stiffness tends to infinity, without
    the stick-phase ringing at ``sqrt(kt/m)`` that a stiff element brings.

    Give the slip force directly, or a friction coefficient and a normal load
    (``f_s = μ F_n``); only the latter can be moved to another normal load
    with :meth:`with_normal_load`.

    Parameters
    ----------
    slip_force : float, optional
        Slip force ``f_s``, N, > 0.
    friction_coefficient : float, optional
        ``μ > 0`` (with ``normal_load``).
    normal_load : float, optional
        ``F_n > 0``, N (with ``friction_coefficient``).
    penalty : float, optional
        DLFT penalty ``ε``, N/m, > 0: a numerical parameter of the harmonic
        balance, not of the physics (the converged solution does not depend
        on it beyond the harmonic truncation error; without stick phases
        not at all). Default (None): the static stiffness of the structure
        at the contact DOF, ``1 / (K⁻¹)_cc`` (the other DOFs free to
        follow; for the oscillator ``m ẍ + c ẋ + k x``: ``k``), the
        smallest dynamic stiffness of the contact below its first
        resonance; Newton fails at some stick/slip points from about ten
        times that on (on the 39-DOF beam the diagonal entry ``K[c, c]``
        is 8800 times larger and stalled every branch).
    linear_tail : bool, optional
        Locate the stick/slip switches on the relative velocity including
        the harmonics above ``H``, which the linear structure slaves to the
        contact force (:mod:`hbmfric.kernels.dlft.tail`). Default True:
        third order in ``H`` in the non-stop regime (at H = 31 the first
        harmonic is 1e-7 off Den Hartog, the peak 2e-4), 2e-4 to 5e-4 off
        an event-driven integration in the stop regime (F_s/P = 0.3).
        False: the located DLFT on the truncated velocity
        (:func:`hbmfric.kernels.dlft.coulomb.dlft_located`), first order in ``H``
        (3e-3 to 1e-2 at H = 31), about twice as fast on a branch. Not used with
        ``aft="samples"`` nor for a singular mass matrix; far from a
        solution (more than ``max(8, H/2)`` velocity events per period)
        the located scheme stands in for the tail.

    Notes
    -----
    Harmonic balance only. The time-integration reference
    (:func:`hbmfric.validation.steady_state`) has no rigid-contact
    integrator; use a stiff :class:`~hbmfric.Jenkins` element there.
    """

    slip_force: float | None = None
    friction_coefficient: float | None = None
    normal_load: float | None = None
    penalty: float | None = None
    linear_tail: bool = True
    code: ClassVar[int] = COULOMB

    def __post_init__(self) -> None:
        by_load = self.friction_coefficient is not None or self.normal_load is not None
        if by_load:
            if self.friction_coefficient is None or self.normal_load is None:
                raise ValueError(
                    "give both friction_coefficient and normal_load (or slip_force)"
                )
            mu = finite_float(
                "friction_coefficient",
                self.friction_coefficient,
                low=0.0,
                low_open=True,
            )
            fn = finite_float("normal_load", self.normal_load, low=0.0, low_open=True)
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
            self,
            "slip_force",
            finite_float("slip_force", self.slip_force, low=0.0, low_open=True),
        )
        if not isinstance(self.linear_tail, (bool, np.bool_)):
            raise ValueError(
                f"linear_tail must be True or False, got {self.linear_tail!r}"
            )
        object.__setattr__(self, "linear_tail", bool(self.linear_tail))
        if self.penalty is not None:
            object.__setattr__(
                self,
                "penalty",
                finite_float("penalty", self.penalty, low=0.0, low_open=True),
            )

    def with_normal_load(self, normal_load: float) -> Coulomb:
        """The same contact at another normal load, N (same μ and penalty)."""
        if self.friction_coefficient is None:
            raise ValueError(
                "this law was given a slip_force; define it by friction_coefficient "
                "and normal_load to change the normal load"
            )
        return Coulomb(
            friction_coefficient=self.friction_coefficient,
            normal_load=normal_load,
            penalty=self.penalty,
            linear_tail=self.linear_tail,
        )

    @property
    def params(self) -> np.ndarray:
        """``[slip_force]``; the harmonic balance appends the penalty."""
        return np.array([self.slip_force])

    @property
    def stuck_stiffness(self) -> float:
        """Infinite: a stuck rigid contact does not move."""
        return math.inf

    def hysteresis(self, u) -> np.ndarray:
        """Steady-state periodic force over one sampled period of ``u``.

        The rigid limit of the Jenkins loop: ``f_i = f_s sgn(u_i - u_{i-1})``
        where the displacement moves, the previous force where it does not.

        Parameters
        ----------
        u : array_like, shape (n_time,)
            Relative displacement over one period, m (periodic).

        Returns
        -------
        ndarray, shape (n_time,)
            Contact force, N; zeros if ``u`` never moves (the force of a
            stuck rigid contact is set by the dynamics, not by ``u``).
        """
        u = finite_array("u", u)
        if u.size < 2:
            raise ValueError(f"u must hold at least 2 samples, got {u.size}")
        step = np.diff(u, append=u[0])  # step[i] = u[i+1] - u[i]
        moving = np.flatnonzero(step != 0.0)
        force = np.zeros_like(u)
        if moving.size == 0:
            return force
        f = self.slip_force * np.sign(step[moving[-1]])
        for j in range(1, u.size + 1):
            i = (moving[-1] + j) % u.size  # start just after the last move
            if step[i - 1] != 0.0:
                f = self.slip_force * np.sign(step[i - 1])
            force[i] = f
        return force

    def first_harmonic(self, amplitude: float) -> tuple[float, float]:
        """First harmonic ``(C1, S1)`` of the force under ``u = a cos θ``:
        ``f = -f_s sgn(sin θ)`` gives ``(0, -4 f_s / π)`` for ``a > 0``."""
        a = finite_float("amplitude", amplitude, low=0.0)
        if a == 0.0:
            return 0.0, 0.0
        return 0.0, -4.0 * self.slip_force / math.pi

    def energy_per_cycle(self, amplitude: float) -> float:
        """Energy dissipated per cycle under ``u = a cos θ``: ``4 f_s a``, J."""
        a = finite_float("amplitude", amplitude, low=0.0)
        return 4.0 * self.slip_force * a
