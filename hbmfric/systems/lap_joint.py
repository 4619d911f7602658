"""A bolted lap joint of two beams (Brake–Reuss-like), with one friction
contact per node pair along the interface.

Geometry (the Brake–Reuss beam, BRB; see ``docs/lap-joint.md`` for the
sources and for which numbers are the project's own choices): two straight
beams of square section ``width × thickness`` overlap over the joint length
``joint_length``; inside the overlap each beam is cut to half its thickness,
so that the assembly has the full section everywhere and the interface is
the mid-plane ``y = 0``. Beam A spans ``x ∈ [0, half_length]`` (the
excitation end is ``x = 0``), beam B ``x ∈ [half_length − joint_length,
2 half_length − joint_length]``. Bolts at ``bolt_positions`` (measured from
the start of the overlap) clamp the two halves with ``bolt_preload`` each.
The assembly hangs free–free on soft suspension springs (the BRB is tested
hung on bungee cords), here springs to ground at both free ends, axial and
transverse, tuned to the rigid-body frequency ``suspension_frequency``.

Finite elements: plane Euler–Bernoulli frame elements
(:func:`hbmfric.systems.frame.element_matrices`, consistent mass, plus the
rotary inertia ``ρ I`` of the section, which keeps the mass matrix well
conditioned when the overlap is meshed finely), three DOFs per node
``(u, w, θ)``. Every node of both beams lies on the interface
plane ``y = 0``; the overlap elements, whose centroid axis lies at
``y_c = +t/2`` (beam A, upper half) or ``y_c = −t/2`` (beam B, lower half)
with ``t = thickness / 2`` their own thickness, are *eccentric*: with plane
sections, the axial displacement at height ``y`` is ``u(y) = u_c − (y − y_c)
θ``, so the element's centroid DOFs follow from the node DOFs by the linear
change of coordinates

    u_c = u − y_c θ,   w_c = w,   θ_c = θ,

and its matrices are ``Eᵀ k E``, ``Eᵀ m E`` with ``E`` that map. The node
DOF ``u`` of an overlap node is therefore the axial displacement of the beam
*surface* in contact, ``u_c ± (t/2) θ`` (beam A: plus, beam B: minus), and
the tangential slip of node pair ``i`` is the difference of two DOFs,
``u_A,i − u_B,i``: a :class:`~hbmfric.Contact` between them. The full-section
elements outside the overlap have ``y_c = 0``.

The overlap is meshed with ``n_pairs − 1`` equal elements per beam, so that
the ``n_pairs`` nodes of beam A and of beam B face each other at the pair
positions ``x_i``; outside it each beam has ``n_elements`` equal elements.
The normal pressure of the bolts (:meth:`LapJoint.pressure`) gives each pair
its normal load ``N_i`` (tributary length ``ℓ_i`` of node ``i``, the nodal
loads of each bolt scaled so that they sum to its preload exactly); a pair
with ``N_i > 0`` carries

* a Jenkins element on ``u_A,i − u_B,i`` with slip force ``μ N_i`` and
  stiffness ``k_t'' × width × ℓ_i`` (``k_t''``: tangential contact stiffness
  per unit area, N/m³), the normal load held constant over the cycle;
* a linear spring on ``w_A,i − w_B,i`` of stiffness ``k_n'' × width × ℓ_i``
  (the interface held closed by the preload; ``k_n'' = k_t'' (2 − ν) /
  (2 (1 − ν))``, Mindlin's ratio of normal to tangential compliance).

Pairs with ``N_i = 0`` (outside the pressure cones) are open and carry
nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .._validate import finite_float, positive_int
from ..laws import Contact2D, Jenkins
from .contacts import Contact
from .frame import AXIAL, DOFS_PER_NODE, ROTATION, TRANSVERSE, element_matrices
from .structure import LinearStructure

#: the Brake–Reuss beam as modelled here (SI units); sources in
#: docs/lap-joint.md
BRAKE_REUSS = {
    "half_length": 0.422,  # m, each beam (assembly 0.724 m)
    "joint_length": 0.120,  # m, overlap
    "width": 0.0254,  # m, 1 in
    "thickness": 0.0254,  # m, 1 in (each beam is 12.7 mm thick in the overlap)
    "youngs_modulus": 192.31e9,  # Pa, stainless steel 304
    "poisson_ratio": 0.3,
    "density": 8000.0,  # kg/m³
    "bolt_positions": (0.030, 0.060, 0.090),  # m from the overlap's start
    "bolt_preload": 12.0e3,  # N per bolt
    "pressure_radius": 0.0214,  # m, washer radius + plate thickness (45° cone)
    "friction_coefficient": 0.6,
    "contact_stiffness": 1.0e12,  # N/m³, tangential, per unit area
    "damping_ratio": 0.002,  # modal, of the structure without friction
    "suspension_frequency": 2.0,  # Hz, rigid-body modes on the bungees
}


def _rotary_inertia(length: float, rho_i: float) -> np.ndarray:
    """Rotary inertia of a frame element (cubic Hermite shape functions),
    ``ρ I ∫ N'ᵀ N' dx`` in the DOF order ``(u1, w1, θ1, u2, w2, θ2)``, kg
    (kg m, kg m² for the rotations); ``rho_i`` = ``ρ I``, kg m."""
    L = length
    m = np.zeros((6, 6))
    bend = [1, 2, 4, 5]
    m[np.ix_(bend, bend)] = (
        rho_i
        / (30.0 * L)
        * np.array(
            [
                [36.0, 3.0 * L, -36.0, 3.0 * L],
                [3.0 * L, 4.0 * L * L, -3.0 * L, -L * L],
                [-36.0, -3.0 * L, 36.0, -3.0 * L],
                [3.0 * L, -L * L, -3.0 * L, 4.0 * L * L],
            ]
        )
    )
    return m


def _positive(name: str, value) -> float:
    return finite_float(name, value, low=0.0, low_open=True)


@dataclass(frozen=True, eq=False)
class LapJoint:
    """Two beams bolted by a lap joint, with ``n_pairs`` contact node pairs.

    See the module notes for the model; defaults are the Brake–Reuss beam
    (:data:`BRAKE_REUSS`).

    Parameters
    ----------
    n_pairs : int
        Contact node pairs along the overlap, >= 2 (default 10).
    n_elements : int
        Elements of each beam outside the overlap, >= 1 (default 12).
    bolt_preload : float or sequence of float
        Preload of each bolt, N, >= 0 (one value for all, or one per bolt).
    friction_coefficient : float
        ``μ``, >= 0.
    contact_stiffness : float
        Tangential contact stiffness per unit area ``k_t''``, N/m³, > 0.
    damping_ratio : float
        Modal damping ratio of every mode of the structure without the
        tangential contacts (normal springs and suspension included), >= 0.
    suspension_frequency : float
        Frequency of the rigid-body modes on the suspension, Hz, > 0.
    half_length, joint_length, width, thickness : float
        Geometry, m (``joint_length < half_length``).
    youngs_modulus : float
        ``E``, Pa.
    poisson_ratio : float
        ``ν`` (normal-to-tangential contact stiffness ratio only).
    density : float
        ``ρ``, kg/m³.
    bolt_positions : sequence of float
        Bolt axes, m from the start of the overlap, inside it.
    pressure_radius : float
        Half-width ``a`` of each bolt's pressure zone along the beam, m.

    Examples
    --------
    >>> import hbmfric as hf
    >>> joint = hf.LapJoint(n_pairs=10)
    >>> s = joint.structure()
    >>> len(s.contacts) <= 10
    True
    """

    n_pairs: int = 10
    n_elements: int = 12
    bolt_preload: float | tuple = BRAKE_REUSS["bolt_preload"]
    friction_coefficient: float = BRAKE_REUSS["friction_coefficient"]
    contact_stiffness: float = BRAKE_REUSS["contact_stiffness"]
    damping_ratio: float = BRAKE_REUSS["damping_ratio"]
    suspension_frequency: float = BRAKE_REUSS["suspension_frequency"]
    half_length: float = BRAKE_REUSS["half_length"]
    joint_length: float = BRAKE_REUSS["joint_length"]
    width: float = BRAKE_REUSS["width"]
    thickness: float = BRAKE_REUSS["thickness"]
    youngs_modulus: float = BRAKE_REUSS["youngs_modulus"]
    poisson_ratio: float = BRAKE_REUSS["poisson_ratio"]
    density: float = BRAKE_REUSS["density"]
    bolt_positions: tuple = field(default=BRAKE_REUSS["bolt_positions"])
    pressure_radius: float = BRAKE_REUSS["pressure_radius"]

    def __post_init__(self) -> None:
        s = object.__setattr__
        s(self, "n_pairs", positive_int("n_pairs", self.n_pairs, low=2))
        s(self, "n_elements", positive_int("n_elements", self.n_elements, low=1))
        for name in (
            "contact_stiffness",
            "suspension_frequency",
            "half_length",
            "joint_length",
            "width",
            "thickness",
            "youngs_modulus",
            "density",
            "pressure_radius",
        ):
            s(self, name, _positive(name, getattr(self, name)))
        for name in ("friction_coefficient", "damping_ratio"):
            s(self, name, finite_float(name, getattr(self, name), low=0.0))
        s(
            self,
            "poisson_ratio",
            finite_float("poisson_ratio", self.poisson_ratio, low=0.0, high=0.5),
        )
        if not self.joint_length < self.half_length:
            raise ValueError(
                f"joint_length ({self.joint_length} m) must be shorter than "
                f"half_length ({self.half_length} m)"
            )
        try:
            positions = tuple(float(x) for x in self.bolt_positions)
        except (TypeError, ValueError):
            raise ValueError(
                f"bolt_positions must be a sequence of floats, got "
                f"{self.bolt_positions!r}"
            ) from None
        if not positions or not all(
            math.isfinite(x) and 0.0 <= x <= self.joint_length for x in positions
        ):
            raise ValueError(
                f"bolt_positions must be one or more positions in [0, "
                f"{self.joint_length}] m (the overlap), got {self.bolt_positions!r}"
            )
        s(self, "bolt_positions", positions)
        if np.ndim(self.bolt_preload) == 0:
            loads = (finite_float("bolt_preload", self.bolt_preload, low=0.0),) * len(
                positions
            )
        else:
            loads = tuple(
                finite_float(f"bolt_preload[{k}]", v, low=0.0)
                for k, v in enumerate(self.bolt_preload)
            )
            if len(loads) != len(positions):
                raise ValueError(
                    f"bolt_preload has {len(loads)} values for {len(positions)} bolts"
                )
        s(self, "bolt_preload", loads)

    # -- mesh --------------------------------------------------------------
    @property
    def nodes_per_beam(self) -> int:
        """Nodes of each beam, ``n_elements + n_pairs``."""
        return self.n_elements + self.n_pairs

    @property
    def n_dof(self) -> int:
        """DOFs of the full model, ``6 (n_elements + n_pairs)``."""
        return 2 * DOFS_PER_NODE * self.nodes_per_beam

    @property
    def total_length(self) -> float:
        """Length of the assembly, ``2 half_length − joint_length``, m."""
        return 2.0 * self.half_length - self.joint_length

    @property
    def pair_positions(self) -> np.ndarray:
        """``x_i`` of the node pairs from the start of the overlap, m,
        shape (n_pairs,)."""
        return np.linspace(0.0, self.joint_length, self.n_pairs)

    @property
    def tributary_lengths(self) -> np.ndarray:
        """Length of interface each pair stands for (half an element at the
        ends), m, shape (n_pairs,); they sum to ``joint_length``."""
        le = self.joint_length / (self.n_pairs - 1)
        ell = np.full(self.n_pairs, le)
        ell[[0, -1]] = 0.5 * le
        return ell

    def node_positions(self, beam: str) -> np.ndarray:
        """Axial positions of the nodes of beam ``"A"`` or ``"B"`` (global
        ``x``, m), in the node order of the DOF numbering."""
        x0 = self.half_length - self.joint_length
        outside = np.linspace(0.0, x0, self.n_elements + 1)
        if beam == "A":
            return np.concatenate([outside, x0 + self.pair_positions[1:]])
        if beam == "B":
            return np.concatenate(
                [x0 + self.pair_positions, x0 + self.joint_length + outside[1:]]
            )
        raise ValueError(f"beam must be 'A' or 'B', got {beam!r}")

    def node_dof(self, beam: str, node: int, kind: int) -> int:
        """DOF index of ``kind`` (``AXIAL``, ``TRANSVERSE``, ``ROTATION``)
        at node ``node`` (0-based, in the order of :meth:`node_positions`)
        of beam ``"A"`` or ``"B"``."""
        offset = {"A": 0, "B": self.nodes_per_beam}[beam]
        return DOFS_PER_NODE * (offset + node) + kind

    def pair_dofs(self, kind: int = AXIAL) -> tuple[np.ndarray, np.ndarray]:
        """DOFs ``kind`` of the pairs on beam A and on beam B, each shape
        (n_pairs,); with ``AXIAL`` (default) the surface axial
        displacements the contacts act on."""
        a = [self.node_dof("A", self.n_elements + i, kind) for i in range(self.n_pairs)]
        b = [self.node_dof("B", i, kind) for i in range(self.n_pairs)]
        return np.array(a), np.array(b)

    @property
    def dof_names(self) -> dict[str, int]:
        """``"drive"`` (transverse DOF of beam A's free end, the forced
        DOF), ``"tip"`` (beam B's free end, transverse), ``"pair:<i>:a"``
        and ``"pair:<i>:b"`` (surface axial DOFs of pair ``i``)."""
        names = {
            "drive": self.node_dof("A", 0, TRANSVERSE),
            "tip": self.node_dof("B", self.nodes_per_beam - 1, TRANSVERSE),
            "drive:axial": self.node_dof("A", 0, AXIAL),
            "tip:axial": self.node_dof("B", self.nodes_per_beam - 1, AXIAL),
        }
        a, b = self.pair_dofs()
        for i in range(self.n_pairs):
            names[f"pair:{i}:a"] = int(a[i])
            names[f"pair:{i}:b"] = int(b[i])
        return names

    # -- interface loads ----------------------------------------------------
    def pressure(self, x) -> np.ndarray:
        """Normal pressure ``p(x)`` on the interface, Pa, at positions ``x``
        (m from the start of the overlap).

        Each bolt presses a zone ``|x − x_k| < a`` (``a`` =
        ``pressure_radius``) with a parabolic profile across the width,
        ``p_k(x) = 3 P_k / (4 a b) (1 − ((x − x_k)/a)²)``, whose integral
        over the zone is the bolt preload ``P_k``; zones add up.
        """
        x = np.asarray(x, dtype=float)
        a, b = self.pressure_radius, self.width
        p = np.zeros_like(x)
        for xk, pk in zip(self.bolt_positions, self.bolt_preload, strict=True):
            r = (x - xk) / a
            p += np.where(np.abs(r) < 1.0, 0.75 * pk / (a * b) * (1.0 - r * r), 0.0)
        return p

    def normal_loads(self) -> np.ndarray:
        """Normal load ``N_i`` of each pair, N, shape (n_pairs,).

        Per bolt, the pressure at the pair times its tributary area
        ``width × ℓ_i``, scaled so that the pairs carry exactly the bolt's
        preload (the nodal rule is exact only as the mesh is refined); a
        bolt whose zone holds no pair puts its preload on the nearest pair.
        """
        x, ell = self.pair_positions, self.tributary_lengths
        a, b = self.pressure_radius, self.width
        loads = np.zeros(self.n_pairs)
        for xk, pk in zip(self.bolt_positions, self.bolt_preload, strict=True):
            r = (x - xk) / a
            q = np.where(np.abs(r) < 1.0, (1.0 - r * r), 0.0) * ell * b
            if q.sum() > 0.0:
                loads += pk * q / q.sum()
            else:
                loads[int(np.argmin(np.abs(x - xk)))] += pk
        return loads

    def slip_forces(self) -> np.ndarray:
        """Slip force ``μ N_i`` of each pair, N, shape (n_pairs,)."""
        return self.friction_coefficient * self.normal_loads()

    @property
    def total_preload(self) -> float:
        """Sum of the bolt preloads, N."""
        return float(sum(self.bolt_preload))

    def tangential_stiffnesses(self) -> np.ndarray:
        """Stuck stiffness of each pair's Jenkins element,
        ``k_t'' width ℓ_i``, N/m, shape (n_pairs,) (zero for open pairs)."""
        k = self.contact_stiffness * self.width * self.tributary_lengths
        return np.where(self.normal_loads() > 0.0, k, 0.0)

    def normal_stiffnesses(self) -> np.ndarray:
        """Normal spring of each closed pair, ``k_n'' width ℓ_i`` with
        Mindlin's ``k_n'' / k_t'' = (2 − ν) / (2 (1 − ν))``, N/m, shape
        (n_pairs,)."""
        nu = self.poisson_ratio
        return self.tangential_stiffnesses() * (2.0 - nu) / (2.0 * (1.0 - nu))

    @property
    def closed_pairs(self) -> np.ndarray:
        """Indices of the pairs with a normal load (they carry contacts)."""
        return np.nonzero(self.normal_loads() > 0.0)[0]

    # -- matrices ------------------------------------------------------------
    @cached_property
    def _matrices(self) -> tuple[np.ndarray, np.ndarray]:
        n = self.n_dof
        K = np.zeros((n, n))
        M = np.zeros((n, n))
        E = self.youngs_modulus
        b, h = self.width, self.thickness
        full = (E * b * h, E * b * h**3 / 12.0, self.density * b * h)
        t = 0.5 * h
        half = (E * b * t, E * b * t**3 / 12.0, self.density * b * t)
        x0 = self.half_length - self.joint_length
        le_out = x0 / self.n_elements
        le_joint = self.joint_length / (self.n_pairs - 1)
        for beam, sign in (("A", 1.0), ("B", -1.0)):
            kinds = (
                ["out"] * self.n_elements + ["joint"] * (self.n_pairs - 1)
                if beam == "A"
                else ["joint"] * (self.n_pairs - 1) + ["out"] * self.n_elements
            )
            for e, kind in enumerate(kinds):
                if kind == "out":
                    ke, me = element_matrices(le_out, *full)
                    me = me + _rotary_inertia(le_out, self.density * b * h**3 / 12)
                else:
                    ke, me = element_matrices(le_joint, *half)
                    me = me + _rotary_inertia(le_joint, self.density * b * t**3 / 12)
                    # eccentric element: centroid at y_c = ±t/2 above the
                    # node line (the interface); u_c = u − y_c θ
                    y_c = sign * 0.5 * t
                    T = np.eye(6)
                    T[AXIAL, ROTATION] = -y_c
                    T[3 + AXIAL, 3 + ROTATION] = -y_c
                    ke, me = T.T @ ke @ T, T.T @ me @ T
                first = self.node_dof(beam, e, 0)
                s = slice(first, first + 2 * DOFS_PER_NODE)
                K[s, s] += ke
                M[s, s] += me
        # normal springs of the closed pairs
        wa, wb = self.pair_dofs(TRANSVERSE)
        for i, kn in enumerate(self.normal_stiffnesses()):
            if kn > 0.0:
                for p, q, sgn in ((wa[i], wa[i], 1), (wb[i], wb[i], 1)):
                    K[p, q] += sgn * kn
                K[wa[i], wb[i]] -= kn
                K[wb[i], wa[i]] -= kn
        # suspension: springs to ground at both free ends, axial and
        # transverse, each k = m_total (2π f_s)² / 2
        ks = self.mass * (2.0 * math.pi * self.suspension_frequency) ** 2 / 2.0
        names = self.dof_names
        for d in ("drive", "tip", "drive:axial", "tip:axial"):
            K[names[d], names[d]] += ks
        return M, K

    @property
    def mass(self) -> float:
        """Mass of the assembly, kg."""
        return self.density * self.width * self.thickness * self.total_length

    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """Mass (kg) and stiffness (N/m) of the full model without the
        tangential contacts (normal springs and suspension included), each
        shape (n_dof, n_dof)."""
        M, K = self._matrices
        return M.copy(), K.copy()

    def contact_stiffness_matrix(self) -> np.ndarray:
        """The stuck tangential springs ``Σ k_t,i (e_a − e_b)(e_a − e_b)ᵀ``,
        N/m, shape (n_dof, n_dof)."""
        n = self.n_dof
        Kc = np.zeros((n, n))
        a, b = self.pair_dofs()
        for i, kt in enumerate(self.tangential_stiffnesses()):
            Kc[a[i], a[i]] += kt
            Kc[b[i], b[i]] += kt
            Kc[a[i], b[i]] -= kt
            Kc[b[i], a[i]] -= kt
        return Kc

    # -- structures ------------------------------------------------------------
    def structure(self, contact: str = "jenkins") -> LinearStructure:
        """The lap joint as a :class:`~hbmfric.LinearStructure`.

        Parameters
        ----------
        contact : {"jenkins", "contact2d", "stuck", "free"}
            ``"jenkins"``: one Jenkins contact per closed pair (the friction
            model, normal load constant); ``"contact2d"``: one
            :class:`~hbmfric.Contact2D` element per closed pair (normal load
            varying over the cycle, see :meth:`_contact2d_structure`);
            ``"stuck"``: linear, the contacts replaced by their stuck
            springs; ``"free"``: linear, without tangential contacts (the
            full-slip limit at zero slip force).

        Returns
        -------
        LinearStructure
            Load: unit cosine force on ``"drive"``; modal damping
            ``damping_ratio`` on the modes of the structure without the
            tangential contacts (the same damping matrix in all three
            variants).
        """
        M, K = self._matrices
        free = LinearStructure(
            M,
            K,
            modal_damping=self.damping_ratio,
            load={"drive": 1.0},
            dof_names=self.dof_names,
        )
        if contact == "free":
            return free
        _, C, _ = free.matrices()
        if contact == "stuck":
            return LinearStructure(
                M,
                K + self.contact_stiffness_matrix(),
                C,
                load={"drive": 1.0},
                dof_names=self.dof_names,
            )
        if contact == "contact2d":
            return self._contact2d_structure(M, K, C)
        if contact != "jenkins":
            raise ValueError(
                "contact must be 'jenkins', 'contact2d', 'stuck' or 'free', got "
                f"{contact!r}"
            )
        a, b = self.pair_dofs()
        kt, fs = self.tangential_stiffnesses(), self.slip_forces()
        contacts = [
            Contact(
                Jenkins(stiffness=float(kt[i]), slip_force=float(fs[i])),
                int(a[i]),
                other=int(b[i]),
            )
            for i in self.closed_pairs
        ]
        return LinearStructure(
            M,
            K,
            C,
            load={"drive": 1.0},
            dof_names=self.dof_names,
            contacts=contacts,
        )

    def _contact2d_structure(self, M, K, C) -> LinearStructure:
        """The ``"contact2d"`` variant: per closed pair a
        :class:`~hbmfric.Contact2D` element (Jenkins whose slip force follows
        the normal force ``N_i + k_n,i v``, ``v = w_B − w_A`` positive
        closing, open when it reaches zero) instead of the Jenkins element
        and the linear normal spring; the bolts' clamping enters as the
        static load ``−N_i`` on ``w_A,i`` and ``+N_i`` on ``w_B,i``, so that
        at rest every pair carries ``N_i``."""
        a, b = self.pair_dofs()
        wa, wb = self.pair_dofs(TRANSVERSE)
        kt, kn = self.tangential_stiffnesses(), self.normal_stiffnesses()
        loads = self.normal_loads()
        K = K.copy()
        static = {}
        contacts = []
        for i in self.closed_pairs:
            for p, q, v in ((wa, wa, 1.0), (wb, wb, 1.0), (wa, wb, -1.0)):
                K[p[i], q[i]] -= v * kn[i]
                if p is not q:
                    K[q[i], p[i]] -= v * kn[i]
            element = Contact2D(
                tangential_stiffness=float(kt[i]),
                normal_stiffness=float(kn[i]),
                friction_coefficient=self.friction_coefficient,
                preload=float(loads[i]),
            )
            contacts.append(
                Contact(
                    element,
                    int(a[i]),
                    other=int(b[i]),
                    normal=int(wb[i]),
                    normal_other=int(wa[i]),
                )
            )
            static[int(wa[i])] = -float(loads[i])
            static[int(wb[i])] = float(loads[i])
        return LinearStructure(
            M,
            K,
            C,
            load={"drive": 1.0},
            dof_names=self.dof_names,
            contacts=contacts,
            static_load=static,
        )

    def reduced(self, n_modes: int = 8, contact: str = "jenkins", extra=()):
        """Craig–Bampton reduction of :meth:`structure` onto the surface
        axial DOFs of the closed pairs (with ``contact="contact2d"`` also
        their transverse DOFs), ``"drive"`` and ``"tip"`` (and ``extra``
        DOFs), plus ``n_modes`` fixed-interface modes
        (:func:`hbmfric.craig_bampton`)."""
        from .craig_bampton import craig_bampton

        a, b = self.pair_dofs()
        closed = self.closed_pairs
        boundary = ["drive", "tip", *extra]
        boundary += [int(d) for i in closed for d in (a[i], b[i])]
        if contact == "contact2d":
            wa, wb = self.pair_dofs(TRANSVERSE)
            boundary += [int(d) for i in closed for d in (wa[i], wb[i])]
        return craig_bampton(self.structure(contact), boundary, n_modes)

    def natural_frequencies(self, contact: str = "stuck", n: int = 10) -> np.ndarray:
        """The first ``n`` undamped natural frequencies of the full model,
        Hz, ``contact`` as in :meth:`structure` (``"stuck"`` or
        ``"free"``)."""
        if contact not in ("stuck", "free"):
            raise ValueError(f"contact must be 'stuck' or 'free', got {contact!r}")
        from scipy.linalg import eigh

        M, K = self._matrices
        if contact == "stuck":
            K = K + self.contact_stiffness_matrix()
        n = positive_int("n", n)
        lam = eigh(K, M, eigvals_only=True, subset_by_index=(0, min(n, len(M)) - 1))
        return np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * math.pi)


def lap_joint(
    n_pairs: int = 10,
    bolt_preload=BRAKE_REUSS["bolt_preload"],
    n_modes: int | None = 8,
    **parameters,
) -> LinearStructure:
    """The Brake–Reuss-like lap joint with ``n_pairs`` Jenkins contacts.

    Parameters
    ----------
    n_pairs : int
        Contact node pairs along the overlap (default 10).
    bolt_preload : float or sequence of float
        Preload per bolt, N (default 12 kN).
    n_modes : int or None
        Fixed-interface modes of the Craig–Bampton reduction onto the
        contact DOFs, ``"drive"`` and ``"tip"`` (default 8); None: the full
        finite-element model.
    **parameters
        The other fields of :class:`LapJoint`.

    Returns
    -------
    LinearStructure
        A :class:`~hbmfric.ReducedStructure` unless ``n_modes`` is None;
        forced by a unit cosine load at ``"drive"``.

    Examples
    --------
    >>> import hbmfric as hf
    >>> s = hf.lap_joint(n_pairs=10)
    >>> s.dof("drive"), s.dof("tip")
    (0, 1)
    """
    joint = LapJoint(n_pairs=n_pairs, bolt_preload=bolt_preload, **parameters)
    if n_modes is None:
        return joint.structure()
    return joint.reduced(n_modes)


__all__ = ["BRAKE_REUSS", "LapJoint", "lap_joint"]
