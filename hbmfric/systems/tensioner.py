"""The 2-DOF belt-tensioner rig of the paper (Sec. 2.2, eqs. 4–6; docs/paper.md).

Shaker-side mass ``m1`` and idler pulley ``m2`` joined by the belt (spring
``K``, damper ``C``, pre-tension ``T0``); the tensioner (modified Dahl force
``F(u2)``) holds the pulley to the frame. Displacements are positive
downwards (along gravity):

    T = K (u1 − u2) + C (u̇1 − u̇2) + T0,
    m2 ü2 = T − F(u2) + m2 g,
    m1 ü1 = −T + f(t) + m1 g,     f = f0 + f1 sin Ωt.

In matrix form ``M ü + C_b u̇ + K_b u + e_2 F(u2) = p0 + e_1 f1 sin Ωt`` with
the constant load ``p0 = [f0 + m1 g − T0, T0 + m2 g]``; the forcing is
``f1 cos(Ωt − π/2)`` (``load_phase = π/2``).

Default parameters (the paper gives none; chosen here, SI units) make the
regimes of the paper's Fig. 5 fall in 5–100 Hz: a tensioner with parallel
envelopes ``h_u = 1.5e4 u + 300``, ``h_l = 1.5e4 u + 150`` and ``β = 900
1/m`` (small-loop stiffness ``β (b − e)/2 = 6.75e4 N/m``), a belt of
``K = 1e5 N/m``, ``m1 = 0.5 kg``, ``m2 = 0.2 kg``: the stuck resonance (small
loops) is at about 45 Hz, the slipping one (tensioner stiffness near its
envelope slope) near 25 Hz, and the third-harmonic ("subharmonic" in the
paper) resonance at one third of the stuck one, about 15 Hz.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._validate import finite_float
from ..laws import ModifiedDahl

GRAVITY = 9.81


def default_tensioner() -> ModifiedDahl:
    """The rig's default tensioner law (see the module docstring)."""
    return ModifiedDahl(
        beta=900.0, exponent=1.0, upper=(1.5e4, 300.0), lower=(1.5e4, 150.0)
    )


@dataclass(frozen=True)
class BeltTensioner:
    """2-DOF belt-tensioner rig (DOF 0: ``u1``, shaker mass; DOF 1: ``u2``,
    idler pulley, where the tensioner acts).

    Parameters
    ----------
    mass_shaker : float
        ``m1``, kg.
    mass_pulley : float
        ``m2``, kg.
    belt_stiffness : float
        ``K``, N/m.
    belt_damping : float
        ``C``, N s/m.
    pretension : float
        ``T0``, N.
    static_force : float
        ``f0``, N (the shaker's constant force).
    tensioner : ModifiedDahl
        The tensioner's restoring-force law ``F(u2)``.
    gravity : float
        ``g``, m/s².
    """

    mass_shaker: float = 0.5
    mass_pulley: float = 0.2
    belt_stiffness: float = 1.0e5
    belt_damping: float = 6.0
    pretension: float = 205.0
    static_force: float = 200.0
    tensioner: ModifiedDahl = field(default_factory=default_tensioner)
    gravity: float = GRAVITY

    n_dof = 2
    contact_dof = 1
    symmetric = False
    #: the forcing is ``f1 sin Ωt = f1 cos(Ωt − π/2)``
    load_phase = 0.5 * math.pi

    def __post_init__(self) -> None:
        for name in ("mass_shaker", "mass_pulley", "belt_stiffness"):
            value = finite_float(name, getattr(self, name), low=0.0, low_open=True)
            object.__setattr__(self, name, value)
        for name in ("belt_damping",):
            object.__setattr__(
                self, name, finite_float(name, getattr(self, name), low=0.0)
            )
        for name in ("pretension", "static_force", "gravity"):
            object.__setattr__(self, name, finite_float(name, getattr(self, name)))
        if not isinstance(self.tensioner, ModifiedDahl):
            raise ValueError(
                f"tensioner must be a hf.ModifiedDahl law, got "
                f"{type(self.tensioner).__name__}"
            )

    @property
    def dof_names(self) -> dict[str, int]:
        """Named DOFs: ``"shaker"`` (``u1``), ``"pulley"`` and ``"contact"``
        (``u2``, where the tensioner acts)."""
        return {"shaker": 0, "pulley": 1, "contact": 1}

    @property
    def contact(self) -> ModifiedDahl:
        """The tensioner law (the contact of the generic system interface)."""
        return self.tensioner

    @property
    def output_weights(self) -> tuple[np.ndarray, np.ndarray]:
        """The watched output of the truncation estimate: the belt tension
        without ``T0`` (:meth:`tension`), displacement weights ``(K, −K)``
        (N/m) and velocity weights ``(C, −C)`` (N s/m), each shape (2,).
        The users read the tension; its relative truncation error exceeds
        the pulley displacement's (above both resonances ``u1 − u2`` is
        small against ``u2``)."""
        k, c = self.belt_stiffness, self.belt_damping
        return np.array([k, -k]), np.array([c, -c])

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass, damping and stiffness matrices, each shape (2, 2)."""
        mass = np.diag([self.mass_shaker, self.mass_pulley])
        coupling = np.array([[1.0, -1.0], [-1.0, 1.0]])
        return mass, self.belt_damping * coupling, self.belt_stiffness * coupling

    def load_vector(self, force: float) -> np.ndarray:
        """Amplitude of the forcing ``f1 sin Ωt`` per DOF, shape (2,), N."""
        return np.array([force, 0.0])

    def static_load(self) -> np.ndarray:
        """Constant load ``[f0 + m1 g − T0, T0 + m2 g]``, shape (2,), N."""
        g = self.gravity
        return np.array(
            [
                self.static_force + self.mass_shaker * g - self.pretension,
                self.pretension + self.mass_pulley * g,
            ]
        )

    @property
    def tensioner_static_force(self) -> float:
        """Force the tensioner carries at rest, ``f0 + (m1 + m2) g``, N."""
        return self.static_force + (self.mass_shaker + self.mass_pulley) * self.gravity

    def static_solution(self) -> np.ndarray:
        """Rest position ``[u1, u2]``, m: the tensioner at its mid-envelope
        force (the limit of vanishing loops)."""
        u2 = self.tensioner.static_displacement(self.tensioner_static_force)
        p0 = self.static_load()
        return np.array([u2 + p0[0] / self.belt_stiffness, u2])

    def small_loop_stiffness(self) -> float:
        """Tensioner stiffness of small loops at rest, N/m."""
        return self.tensioner.small_loop_stiffness(self.static_solution()[1])

    def resonances(self, tensioner_stiffness: float | None = None) -> np.ndarray:
        """Undamped resonances of the linearised rig, Hz, shape (2,).

        ``tensioner_stiffness`` (N/m) defaults to the small-loop stiffness
        (the stuck rig); the envelope slope ``(a + d)/2`` gives the slipping
        limit.
        """
        k_t = (
            self.small_loop_stiffness()
            if tensioner_stiffness is None
            else float(tensioner_stiffness)
        )
        mass, _, stiffness = self.matrices()
        stiffness = stiffness.copy()
        stiffness[1, 1] += k_t
        eig = np.linalg.eigvals(np.linalg.solve(mass, stiffness))
        return np.sort(np.sqrt(np.abs(eig.real))) / (2.0 * math.pi)

    def tension(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Belt tension ``K (u1 − u2) + C (u̇1 − u̇2) + T0``, N.

        ``x``, ``v`` of shape (2, ...): displacements (m), velocities (m/s).
        """
        return (
            self.belt_stiffness * (x[0] - x[1])
            + self.belt_damping * (v[0] - v[1])
            + self.pretension
        )


def tension_coefficients(
    rig: BeltTensioner,
    harmonic_numbers: np.ndarray,
    coefficients: np.ndarray,
    omega: float,
) -> np.ndarray:
    """Fourier coefficients of the belt tension, N.

    Parameters
    ----------
    rig : BeltTensioner
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (2, n_coef)
        Displacement coefficients (layout ``[X0, Xc1, Xs1, …]``), m.
    omega : float
        Fundamental pulsation, rad/s.

    Returns
    -------
    ndarray, shape (n_coef,)
    """
    rel = coefficients[0] - coefficients[1]
    out = rig.belt_stiffness * rel
    col = 0
    for k in harmonic_numbers:
        if k == 0:
            out[col] += rig.pretension
            col += 1
            continue
        w = k * omega
        c, s = rel[col], rel[col + 1]
        # d/dt (c cos + s sin) = w (s cos − c sin)
        out[col] += rig.belt_damping * w * s
        out[col + 1] -= rig.belt_damping * w * c
        col += 2
    return out
