"""Contact laws: frozen dataclasses that describe a law and hand its flat
parameter array to the kernels (:mod:`hbmfric.kernels.laws.updates`).

* :class:`Jenkins` — Masing macroslip (spring + Coulomb slider);
* :class:`Menq` — microslip of an elastic bar on an elastic shear layer;
* :class:`Iwan` — Jenkins elements in parallel (Segalman's distribution);
* :class:`Roughness` — any of them with a normal-load-dependent stiffness;
* :class:`Cubic` — a smooth, memoryless cubic spring;
* :class:`Contact2D` — a 2D element: Jenkins friction under a unilateral
  normal contact with preload, whose slip force follows the normal force;
* :class:`ModifiedDahl` — a smooth hysteretic restoring force (belt
  tensioner);
* :class:`Coulomb` — the rigid Coulomb contact (no tangential compliance),
  solved by DLFT instead of AFT.
"""

from .base import ContactLaw
from .contact2d import Contact2D, Contact2DForces
from .coulomb import Coulomb
from .dahl import ModifiedDahl
from .iwan import Iwan
from .jenkins import Cubic, Jenkins
from .menq import Menq
from .roughness import Roughness, hertz_mindlin_stiffness

__all__ = [
    "Contact2D",
    "Contact2DForces",
    "ContactLaw",
    "Coulomb",
    "Cubic",
    "Iwan",
    "Jenkins",
    "Menq",
    "ModifiedDahl",
    "Roughness",
    "hertz_mindlin_stiffness",
]
