"""Calibration of the rubbing beam on two measured resonances (docs/paper.md).

In full slip the contact adds no stiffness: the first resonance is that of
the cantilever with its tip mass, a function of the tip mass alone. Stuck,
the contact adds its tangential stiffness at the tip. So the tip mass is
found first from the slipping resonance, then the contact stiffness from
the stuck one, each by a bracketed scalar root (Brent) on the first
natural frequency of the finite-element model.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._validate import finite_float

if TYPE_CHECKING:  # the beam imports this module, not the other way round
    from .beam import CantileverBeam


@dataclass(frozen=True)
class BeamCalibration:
    """Result of :meth:`CantileverBeam.calibrate`.

    Attributes
    ----------
    tip_mass : float
        kg.
    contact_stiffness : float
        Stuck tangential stiffness of the tip contact, N/m.
    residual : float
        Largest mismatch between the model's first frequencies (slipping,
        stuck) and the targets, Hz.
    beam : CantileverBeam
        The calibrated model (tip mass included, no contact law).
    slip_frequency, stuck_frequency : float
        The targets, Hz.
    """

    tip_mass: float
    contact_stiffness: float
    residual: float
    beam: CantileverBeam
    slip_frequency: float
    stuck_frequency: float

    def contact(self, normal_load: float, friction_coefficient: float):
        """A Jenkins law with the calibrated stiffness, ``f_s = μ F_n``."""
        from ..laws import Jenkins

        return Jenkins(
            stiffness=self.contact_stiffness,
            friction_coefficient=friction_coefficient,
            normal_load=normal_load,
        )


def _first_frequency(M: np.ndarray, K: np.ndarray) -> float:
    from scipy.linalg import eigh  # lazy: keeps import hbmfric light

    w2 = eigh(K, M, eigvals_only=True, subset_by_index=(0, 0))[0]
    return float(np.sqrt(max(w2, 0.0)) / (2.0 * np.pi))


def calibrate_beam(
    base: CantileverBeam,
    slip_frequency: float = 24.0,
    stuck_frequency: float = 87.0,
) -> BeamCalibration:
    """Tip mass and stuck contact stiffness that reproduce two resonances.

    Parameters
    ----------
    base : CantileverBeam
        The beam whose ``tip_mass`` is sought (its own ``tip_mass`` and
        ``contact`` are ignored); :meth:`CantileverBeam.calibrate` builds it
        from the other fields.
    slip_frequency : float
        First resonance in full slip (no contact stiffness), Hz; must lie
        below the first frequency of the beam without tip mass.
    stuck_frequency : float
        First resonance with the contact stuck, Hz; above the slipping one
        and below the clamped–pinned limit (infinitely stiff contact).

    Returns
    -------
    BeamCalibration
    """
    import scipy.optimize  # lazy: keeps ``import hbmfric`` light

    f_slip = finite_float("slip_frequency", slip_frequency, low=0.0, low_open=True)
    f_stuck = finite_float("stuck_frequency", stuck_frequency, low=0.0, low_open=True)
    base = dataclasses.replace(base, tip_mass=0.0, contact=None)
    M0, K = base._structure
    tip = base.contact_dof
    axial = tip - 1

    def with_mass(m: float) -> np.ndarray:
        M = M0.copy()
        M[tip, tip] += m
        M[axial, axial] += m
        return M

    f_bare = _first_frequency(M0, K)
    if not f_slip < f_bare:
        raise ValueError(
            f"slip_frequency must be below {f_bare:.6g} Hz (the beam without tip "
            f"mass), got {f_slip}"
        )
    beam_mass = base.mass_per_length * base.length
    hi = beam_mass
    while _first_frequency(with_mass(hi), K) > f_slip:
        hi *= 4.0
    tip_mass = scipy.optimize.brentq(
        lambda m: _first_frequency(with_mass(m), K) - f_slip,
        0.0,
        hi,
        xtol=1e-14,
        rtol=1e-13,
    )
    M = with_mass(tip_mass)

    def stuck(k: float) -> float:
        Kc = K.copy()
        Kc[tip, tip] += k
        return _first_frequency(M, Kc)

    # the clamped-pinned limit bounds what a tip spring can reach
    f_pinned = stuck(1e6 * K[tip, tip])
    if not f_slip < f_stuck < f_pinned:
        raise ValueError(
            f"stuck_frequency must lie between slip_frequency ({f_slip} Hz) and "
            f"the clamped-pinned limit ({f_pinned:.6g} Hz), got {f_stuck}"
        )
    hi = K[tip, tip]
    while stuck(hi) < f_stuck:
        hi *= 4.0
    stiffness = scipy.optimize.brentq(
        lambda k: stuck(k) - f_stuck, 0.0, hi, xtol=1e-10, rtol=1e-13
    )
    residual = max(
        abs(_first_frequency(M, K) - f_slip), abs(stuck(stiffness) - f_stuck)
    )
    beam = dataclasses.replace(base, tip_mass=float(tip_mass))
    return BeamCalibration(
        tip_mass=float(tip_mass),
        contact_stiffness=float(stiffness),
        residual=float(residual),
        beam=beam,
        slip_frequency=f_slip,
        stuck_frequency=f_stuck,
    )
