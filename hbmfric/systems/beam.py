"""The clamped beam with a rubbing tip (paper Sec. 3.2): a finite-element
Euler–Bernoulli cantilever with a tip mass, modal damping, a harmonic force at
any DOF and a contact law on the tip's transverse DOF."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .._validate import finite_float, positive_int
from ..laws import ContactLaw
from .calibration import BeamCalibration, calibrate_beam
from .frame import AXIAL, DOFS_PER_NODE, ROTATION, TRANSVERSE, clamped_beam_matrices

#: the paper's steel beam (docs/paper.md)
PAPER_BEAM = {
    "length": 0.50,  # m
    "width": 0.04,  # m
    "thickness": 0.008,  # m, in the bending direction
    "n_elements": 13,
    "youngs_modulus": 210e9,  # Pa
    "density": 7800.0,  # kg/m³
}

#: default forcing position, fraction of the length (node 11 of 13)
FORCE_POSITION = 11.0 / 13.0

_KINDS = {"axial": AXIAL, "transverse": TRANSVERSE, "rotation": ROTATION}


@dataclass(frozen=True, eq=False)
class CantileverBeam:
    """Steel cantilever, clamped at ``x = 0``, rubbing at its free end.

    Finite elements: ``n_elements`` two-node Euler–Bernoulli frame elements
    with 3 DOFs per node (axial ``u``, transverse ``w``, rotation ``θ``) and
    consistent mass; node 0 is clamped, so the model has ``3 n_elements``
    DOFs, numbered node by node: node ``i >= 1`` owns DOFs
    ``3 (i - 1) + (0, 1, 2)``. Bending is about the weak axis
    (``I = width thickness³ / 12``). The contact acts on the tip's transverse
    DOF (``contact_dof``) to ground, parallel to the structure.

    Damping is modal: every mode of the structure without contact (tip mass
    included) gets the damping ratio ``damping_ratio``,
    ``C = M Φ diag(2 ζ ω_r) Φᵀ M`` with ``Φ`` mass-normalised.

    Parameters
    ----------
    length, width, thickness : float
        Beam dimensions, m (defaults: the paper's 0.50 × 0.04 × 0.008 m).
    n_elements : int
        Number of elements (default 13: 39 DOFs).
    youngs_modulus : float
        ``E``, Pa (default 210 GPa).
    density : float
        ``ρ``, kg/m³ (default 7800).
    tip_mass : float
        Point mass at the free end (both translations), kg, >= 0.
    damping_ratio : float
        Modal damping ratio ``ζ`` of every mode, >= 0 (default 0.05; the
        paper does not give one).
    contact : ContactLaw or None
        Law of the tip contact; None for the linear beam.
    force_dof : int, str or None
        DOF of the harmonic force ``F cos Ωt``: an index, ``"tip"`` (the tip
        transverse DOF) or ``"node:<i>"`` (transverse DOF of node i). None
        (default): the transverse DOF of the node nearest
        ``x = FORCE_POSITION L`` (node 11 of 13, x = 0.423 m, for the paper
        mesh); see :mod:`hbmfric.paper.beam` for why.
    """

    length: float = PAPER_BEAM["length"]
    width: float = PAPER_BEAM["width"]
    thickness: float = PAPER_BEAM["thickness"]
    n_elements: int = PAPER_BEAM["n_elements"]
    youngs_modulus: float = PAPER_BEAM["youngs_modulus"]
    density: float = PAPER_BEAM["density"]
    tip_mass: float = 0.0
    damping_ratio: float = 0.05
    contact: ContactLaw | None = None
    force_dof: int | str | None = None

    def __post_init__(self) -> None:
        for name in ("length", "width", "thickness", "youngs_modulus", "density"):
            value = finite_float(name, getattr(self, name), low=0.0, low_open=True)
            object.__setattr__(self, name, value)
        object.__setattr__(
            self, "n_elements", positive_int("n_elements", self.n_elements, low=1)
        )
        object.__setattr__(
            self, "tip_mass", finite_float("tip_mass", self.tip_mass, low=0.0)
        )
        object.__setattr__(
            self,
            "damping_ratio",
            finite_float("damping_ratio", self.damping_ratio, low=0.0),
        )
        if self.contact is not None and not isinstance(self.contact, ContactLaw):
            raise ValueError(
                f"contact must be a contact law such as hf.Jenkins, got "
                f"{type(self.contact).__name__}"
            )
        self.dof(self.force_dof)  # validates

    # -- the system protocol ------------------------------------------------
    @property
    def n_dof(self) -> int:
        """Number of DOFs, ``3 n_elements``."""
        return DOFS_PER_NODE * self.n_elements

    @property
    def contact_dof(self) -> int:
        """The tip's transverse DOF."""
        return self.n_dof - DOFS_PER_NODE + TRANSVERSE

    @property
    def symmetric(self) -> bool:
        """True when the response to ``F cos Ωt`` has odd harmonics only."""
        return self.contact is None or self.contact.odd

    @property
    def dof_names(self) -> dict[str, int]:
        """Named DOFs: ``"tip"`` and ``"contact"`` (the tip transverse DOF),
        ``"force"`` (the forced DOF)."""
        return {
            "tip": self.contact_dof,
            "contact": self.contact_dof,
            "force": self.dof(self.force_dof),
        }

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass (kg), damping (N s/m) and stiffness (N/m) matrices without
        the contact, each shape (n_dof, n_dof)."""
        M, C, K = self._matrices
        return M.copy(), C.copy(), K.copy()

    def load_vector(self, force: float) -> np.ndarray:
        """Cosine forcing amplitude per DOF, shape (n_dof,), N."""
        p = np.zeros(self.n_dof)
        p[self.dof(self.force_dof)] = force
        return p

    # -- helpers ---------------------------------------------------------------
    def dof(self, which: int | str | None) -> int:
        """DOF index of ``which``: an index, ``"tip"``, ``"force"``,
        ``"contact"`` or ``"node:<i>"`` / ``"node:<i>:<kind>"`` with kind
        ``axial``, ``transverse`` (default) or ``rotation``; None is the
        default forcing DOF."""
        n = DOFS_PER_NODE * self.n_elements
        if which is None:
            which = "default-force"
        if isinstance(which, str):
            if which in ("tip", "contact"):
                return n - DOFS_PER_NODE + TRANSVERSE
            if which == "force":
                return self.dof(self.force_dof)
            if which == "default-force":
                node = min(max(round(FORCE_POSITION * self.n_elements), 1), n // 3)
                return DOFS_PER_NODE * (node - 1) + TRANSVERSE
            parts = which.split(":")
            if parts[0] == "node" and len(parts) in (2, 3):
                try:
                    node = int(parts[1])
                except ValueError:
                    node = -1
                kind = _KINDS.get(parts[2] if len(parts) == 3 else "transverse")
                if 1 <= node <= self.n_elements and kind is not None:
                    return DOFS_PER_NODE * (node - 1) + kind
            raise ValueError(
                f"DOF name must be 'tip', 'force', 'contact' or 'node:<i>[:kind]' "
                f"with 1 <= i <= {self.n_elements} and kind in {tuple(_KINDS)}, "
                f"got {which!r}"
            )
        if isinstance(which, bool) or not isinstance(which, int | np.integer):
            raise ValueError(f"DOF must be an index or a name, got {which!r}")
        if not 0 <= which < n:
            raise ValueError(f"DOF index must be in [0, {n - 1}], got {which}")
        return int(which)

    @property
    def mass_per_length(self) -> float:
        """``ρ A``, kg/m."""
        return self.density * self.width * self.thickness

    @property
    def bending_rigidity(self) -> float:
        """``E I`` about the weak axis, N m²."""
        return self.youngs_modulus * self.width * self.thickness**3 / 12.0

    def modes(self) -> tuple[np.ndarray, np.ndarray]:
        """Modes of the structure without contact (tip mass included).

        Returns
        -------
        omega : ndarray, shape (n_dof,)
            Natural pulsations, increasing, rad/s.
        shapes : ndarray, shape (n_dof, n_dof)
            Mass-normalised mode shapes in columns (``Φᵀ M Φ = I``).
        """
        omega, shapes = self._modes
        return omega.copy(), shapes.copy()

    def natural_frequencies(
        self, contact: str = "free", n_modes: int | None = None
    ) -> np.ndarray:
        """Undamped natural frequencies, Hz, increasing.

        Parameters
        ----------
        contact : {"free", "stuck"}
            ``"free"``: without contact (the full-slip limit); ``"stuck"``:
            with the contact law's stuck stiffness as a tip spring.
        n_modes : int, optional
            How many to return (default: all).
        """
        M, _, K = self._matrices
        if contact == "stuck":
            if self.contact is None:
                raise ValueError("contact='stuck' needs a contact law")
            K = K.copy()
            K[self.contact_dof, self.contact_dof] += self.contact.stuck_stiffness
        elif contact != "free":
            raise ValueError(f"contact must be 'free' or 'stuck', got {contact!r}")
        from scipy.linalg import eigh  # lazy: keeps import hbmfric light

        w2 = eigh(K, M, eigvals_only=True)
        f = np.sqrt(np.maximum(w2, 0.0)) / (2.0 * np.pi)
        return f if n_modes is None else f[: positive_int("n_modes", n_modes)]

    def with_contact(self, contact: ContactLaw | None) -> CantileverBeam:
        """The same beam with another contact law."""
        return dataclasses.replace(self, contact=contact)

    @classmethod
    def calibrate(
        cls,
        slip_frequency: float = 24.0,
        stuck_frequency: float = 87.0,
        **beam_parameters,
    ) -> BeamCalibration:
        """Tip mass and stuck contact stiffness from two measured resonances.

        ``**beam_parameters`` are the other fields of the beam (geometry,
        material, mesh, damping, force DOF); ``tip_mass`` and ``contact``
        are found here. See
        :func:`hbmfric.systems.calibration.calibrate_beam`.
        """
        for name in ("tip_mass", "contact"):
            if name in beam_parameters:
                raise ValueError(f"{name} is found by the calibration; do not pass it")
        return calibrate_beam(cls(**beam_parameters), slip_frequency, stuck_frequency)

    # -- cached linear algebra ----------------------------------------------------
    @cached_property
    def _structure(self) -> tuple[np.ndarray, np.ndarray]:
        ea = self.youngs_modulus * self.width * self.thickness
        K, M = clamped_beam_matrices(
            self.length,
            self.n_elements,
            ea,
            self.bending_rigidity,
            self.mass_per_length,
        )
        tip = self.n_dof - DOFS_PER_NODE
        M[tip + AXIAL, tip + AXIAL] += self.tip_mass
        M[tip + TRANSVERSE, tip + TRANSVERSE] += self.tip_mass
        return M, K

    @cached_property
    def _modes(self) -> tuple[np.ndarray, np.ndarray]:
        M, K = self._structure
        from scipy.linalg import eigh  # lazy: keeps import hbmfric light

        w2, shapes = eigh(K, M)
        return np.sqrt(np.maximum(w2, 0.0)), shapes

    @cached_property
    def _matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        M, K = self._structure
        omega, shapes = self._modes
        MP = M @ shapes
        C = (MP * (2.0 * self.damping_ratio * omega)) @ MP.T
        C = 0.5 * (C + C.T)
        return M, C, K
