"""The built-in paper scenes (docs/paper.md).

The paper gives only the ratios ``Fex/Fn`` for its single-DOF study; the
numbers below are the project's choice: the full-slip resonance sits at
``sqrt(k/m) = 100`` rad/s and the stuck one at ``sqrt((k + kt)/m) = 200``
rad/s.
"""

from __future__ import annotations

import math

from ..laws import Jenkins
from ..systems import Oscillator

#: single-DOF paper scene: SI units
PAPER_SDOF = {
    "mass": 1.0,  # kg
    "stiffness": 1.0e4,  # N/m
    "damping_ratio": 0.02,  # of the free (slipping) oscillator
    "tangential_stiffness": 3.0e4,  # N/m, kt_inf
    "friction_coefficient": 1.0,
    "omega": (50.0, 300.0),  # rad/s
    "ratios": (10.0, 0.5, 0.2, 0.1, 0.001),  # Fex/Fn of Fig. 8
}


def paper_oscillator(normal_load: float, **overrides) -> Oscillator:
    """The SDOF paper oscillator with a Jenkins contact at ``normal_load`` (N).

    Slip force ``μ Fn``, damping ``c = 2 ζ sqrt(k m)``.
    """
    p = {**PAPER_SDOF, **overrides}
    damping = 2.0 * p["damping_ratio"] * math.sqrt(p["stiffness"] * p["mass"])
    law = Jenkins(
        stiffness=p["tangential_stiffness"],
        slip_force=p["friction_coefficient"] * normal_load,
    )
    return Oscillator(p["mass"], damping, p["stiffness"], law)
