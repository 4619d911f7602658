"""The 2D friction contact element: Jenkins friction under a varying normal load."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from .._validate import finite_array, finite_float, positive_int
from ..kernels.aft import contact2d as _k
from .jenkins import Jenkins


class Contact2DForces(NamedTuple):
    """Harmonic forces of a :class:`Contact2D` (:meth:`Contact2D.harmonic_forces`).

    Attributes
    ----------
    force : ndarray, shape (2, n_coef)
        Fourier coefficients of the tangential (row 0) and normal (row 1)
        contact forces, N.
    jacobian : ndarray, shape (2 n_coef, 2 n_coef)
        ``d force / d displacement`` (tangential block first), N/m.
    state : int
        Contact-state code (:data:`hbmfric.kernels.aft.contact2d.STATE_NAMES`).
    message : str
        What ``state`` means.
    """

    force: np.ndarray
    jacobian: np.ndarray
    state: int
    message: str


#: passes of the steady-state march allowed (two are always enough in exact
#: arithmetic, see :mod:`hbmfric.kernels.aft.contact2d`)
MAX_PASSES = 4


@dataclass(frozen=True)
class Contact2D:
    """2D contact element: Jenkins friction coupled to a unilateral normal contact.

    Two relative displacements of a contact point pair: ``u`` tangential and
    ``v`` normal, **positive closing** (``v > 0`` presses the surfaces
    together; ``v = 0`` is the preloaded reference). The normal force is a
    penalty spring on top of the preload,

        ``N(t) = max(0, N0 + kn v(t))``,

    and the tangential force a Jenkins element whose slip limit follows it,
    ``T = kt (u - w)`` with ``|T| <= μ N(t)`` (``w`` the slider). Within a
    period the contact may stick, slip, separate (``N = 0``: ``T = 0`` and the
    slider follows ``u``, so that the contact sticks where it closes again)
    and re-close. Both forces enter an equation of motion like spring
    forces: ``+T`` on the tangential DOF, ``+N`` on the normal one.

    Steady state convention: the contact closed at ``u = 0`` with the slider
    there; a stuck slider stays at 0 unless the motion forces it to shift
    (as for :class:`Jenkins`). With a constant normal load (no separation,
    ``v = 0``) the element is :meth:`tangential_law`.

    In a structure: ``hf.Contact(element, dof=tangential, normal=normal)``
    in :class:`~hbmfric.LinearStructure` ``contacts`` (or a system of your
    own listing it in ``contacts``); :meth:`harmonic_forces` is the AFT
    building block alone.

    Parameters
    ----------
    tangential_stiffness : float
        ``kt``, N/m, > 0.
    normal_stiffness : float
        Penalty stiffness ``kn``, N/m, > 0.
    friction_coefficient : float
        ``μ >= 0``.
    preload : float
        ``N0``, N: the normal force at ``v = 0``. Negative values are an
        initial gap ``-N0 / kn`` (the contact closes at ``v = -N0 / kn``).
    """

    tangential_stiffness: float
    normal_stiffness: float
    friction_coefficient: float
    preload: float
    #: law code in the HBM kernels' contact arrays
    code: ClassVar[int] = _k.CONTACT2D

    @property
    def odd(self) -> bool:
        """False: the preload makes the response carry a mean (harmonic 0)."""
        return False

    @property
    def stuck_stiffness(self) -> float:
        """Tangential stiffness of the stuck, closed contact, N/m."""
        return self.tangential_stiffness

    def __post_init__(self) -> None:
        for name in ("tangential_stiffness", "normal_stiffness"):
            value = finite_float(name, getattr(self, name), low=0.0, low_open=True)
            object.__setattr__(self, name, value)
        object.__setattr__(
            self,
            "friction_coefficient",
            finite_float("friction_coefficient", self.friction_coefficient, low=0.0),
        )
        object.__setattr__(self, "preload", finite_float("preload", self.preload))

    @property
    def params(self) -> np.ndarray:
        """``[kt, kn, μ, N0]``, the flat array the kernels take."""
        return np.array(
            [
                self.tangential_stiffness,
                self.normal_stiffness,
                self.friction_coefficient,
                self.preload,
            ]
        )

    @property
    def opening_displacement(self) -> float:
        """Normal displacement at which the contact opens, ``-N0 / kn``, m."""
        return -self.preload / self.normal_stiffness

    def tangential_law(self) -> Jenkins:
        """The constant-load limit: Jenkins with ``f_s = μ N0`` (needs N0 >= 0)."""
        if self.preload < 0.0:
            raise ValueError(
                f"the contact is open at v = 0 (preload={self.preload} < 0); "
                "it has no constant-load Jenkins limit"
            )
        return Jenkins(
            stiffness=self.tangential_stiffness,
            friction_coefficient=self.friction_coefficient,
            normal_load=self.preload,
        )

    def with_preload(self, preload: float) -> Contact2D:
        """The same element under another preload, N."""
        return Contact2D(
            tangential_stiffness=self.tangential_stiffness,
            normal_stiffness=self.normal_stiffness,
            friction_coefficient=self.friction_coefficient,
            preload=preload,
        )

    def periodic_forces(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        """Steady-state periodic forces over one sampled period.

        Parameters
        ----------
        u, v : array_like, shape (n_time,)
            Tangential and normal (positive closing) relative displacements
            at equidistant instants of one period, m; periodic (sample
            ``n_time`` = sample 0).

        Returns
        -------
        tangential_force, normal_force : ndarray, shape (n_time,)
            ``T`` and ``N``, N.
        """
        u = finite_array("u", u)
        v = finite_array("v", v)
        if u.size < 2:
            raise ValueError(f"u must hold at least 2 samples, got {u.size}")
        if v.shape != u.shape:
            raise ValueError(
                f"u and v must have the same shape, got {u.shape}, {v.shape}"
            )
        t = np.empty_like(u)
        n = np.empty_like(u)
        empty = np.empty((0, 0))
        status = _k.contact2d_march(
            self.params, u, v, t, n, empty, empty, False, np.int64(MAX_PASSES)
        )
        _check_status(status)
        return t, n

    def harmonic_forces(self, X, harmonics, n_time: int) -> Contact2DForces:
        """AFT: force coefficients and their Jacobian for given displacements.

        Parameters
        ----------
        X : array_like, shape (2, n_coef)
            Coefficients of ``u`` (row 0) and ``v`` (row 1), m, in the layout
            of :mod:`hbmfric.kernels.fourier.dft` (``[X0, Xc1, Xs1, …]``).
        harmonics : array_like of int, shape (n_harmonics,)
            Distinct non-negative harmonic numbers, increasing. Include 0:
            the preload gives the normal force a mean.
        n_time : int
            Samples per period, ``> 2 max(harmonics)``.

        Returns
        -------
        Contact2DForces
        """
        from ..kernels.fourier.dft import fourier_matrices, n_coefficients

        h = np.ascontiguousarray(harmonics, dtype=np.int64)
        if h.ndim != 1 or h.size == 0:
            raise ValueError("harmonics must be a non-empty 1-d sequence of integers")
        if h[0] < 0 or np.any(np.diff(h) <= 0):
            raise ValueError(
                f"harmonics must be distinct, non-negative and increasing, got {h}"
            )
        n = positive_int("n_time", n_time, low=2 * int(h[-1]) + 1)
        X = finite_array("X", X, ndim=2)
        n_coef = int(n_coefficients(h))
        if X.shape != (2, n_coef):
            raise ValueError(f"X must have shape (2, {n_coef}), got {X.shape}")
        inverse, forward, _ = fourier_matrices(h, np.int64(n))
        F = np.empty((2, n_coef))
        dF = np.empty((2 * n_coef, 2 * n_coef))
        status = _k.aft_contact2d(
            self.params, X, inverse, forward, F, dF, np.int64(MAX_PASSES)
        )
        _check_status(status)
        return Contact2DForces(F, dF, int(status), _k.STATE_NAMES[int(status)])


def _check_status(status: int) -> None:
    if status < 0:
        from ..errors import ConvergenceError

        raise ConvergenceError(f"Contact2D: {_k.STATE_NAMES[int(status)]}")
