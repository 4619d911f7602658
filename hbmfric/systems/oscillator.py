"""The single-DOF friction oscillator ``m ẍ + c ẋ + k x + f_c(x) = F cos Ωt``."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import finite_float
from ..laws import ContactLaw


@dataclass(frozen=True)
class Oscillator:
    """Single-DOF oscillator with a contact to ground parallel to its spring.

    Parameters
    ----------
    mass : float
        ``m``, kg, > 0.
    damping : float
        Viscous damping ``c``, N s/m, >= 0.
    stiffness : float
        Spring ``k``, N/m, >= 0.
    contact : ContactLaw or None
        Law of the contact force ``f_c(x)``; None for a linear oscillator.
    """

    mass: float
    damping: float
    stiffness: float
    contact: ContactLaw | None = None

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "mass", finite_float("mass", self.mass, low=0.0, low_open=True)
        )
        object.__setattr__(
            self, "damping", finite_float("damping", self.damping, low=0.0)
        )
        object.__setattr__(
            self, "stiffness", finite_float("stiffness", self.stiffness, low=0.0)
        )
        if self.contact is not None and not isinstance(self.contact, ContactLaw):
            raise ValueError(
                f"contact must be a contact law such as hf.Jenkins, got "
                f"{type(self.contact).__name__}"
            )

    n_dof = 1
    contact_dof = 0

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass, damping and stiffness matrices, each shape (1, 1)."""
        return (
            np.array([[self.mass]]),
            np.array([[self.damping]]),
            np.array([[self.stiffness]]),
        )

    def load_vector(self, force: float) -> np.ndarray:
        """Cosine forcing amplitude per DOF, shape (1,), N."""
        return np.array([force])

    @property
    def symmetric(self) -> bool:
        """True when the response to ``F cos Ωt`` has odd harmonics only."""
        return self.contact is None or self.contact.odd

    def with_contact(self, contact: ContactLaw | None) -> Oscillator:
        """The same oscillator with another contact law."""
        return Oscillator(self.mass, self.damping, self.stiffness, contact)
