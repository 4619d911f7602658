"""Plane Euler–Bernoulli frame elements: element matrices and the assembly
of a straight beam clamped at its first node.

Each node carries three DOFs, ``(u, w, θ)``: axial displacement (m),
transverse displacement (m) and rotation of the cross-section (rad). The
element is the classical two-node element with linear axial shape functions
and cubic Hermite bending shape functions; the mass matrix is the consistent
one (same shape functions). For a straight beam the axial and bending parts
do not couple.
"""

from __future__ import annotations

import numpy as np

#: DOFs per node: axial, transverse, rotation
DOFS_PER_NODE = 3
AXIAL, TRANSVERSE, ROTATION = 0, 1, 2


def element_matrices(
    length: float, ea: float, ei: float, rho_a: float
) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and consistent mass of one frame element.

    Parameters
    ----------
    length : float
        Element length ``Le``, m.
    ea : float
        Axial rigidity ``E A``, N.
    ei : float
        Bending rigidity ``E I``, N m².
    rho_a : float
        Mass per unit length ``ρ A``, kg/m.

    Returns
    -------
    stiffness, mass : ndarray, shape (6, 6)
        In the DOF order ``(u1, w1, θ1, u2, w2, θ2)``; N/m (N, N m/rad for
        the rotations) and kg (kg m, kg m² for the rotations).
    """
    L = length
    k = np.zeros((6, 6))
    m = np.zeros((6, 6))
    ax = [0, 3]
    k[np.ix_(ax, ax)] = ea / L * np.array([[1.0, -1.0], [-1.0, 1.0]])
    m[np.ix_(ax, ax)] = rho_a * L / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    bend = [1, 2, 4, 5]
    k[np.ix_(bend, bend)] = (
        ei
        / L**3
        * np.array(
            [
                [12.0, 6.0 * L, -12.0, 6.0 * L],
                [6.0 * L, 4.0 * L * L, -6.0 * L, 2.0 * L * L],
                [-12.0, -6.0 * L, 12.0, -6.0 * L],
                [6.0 * L, 2.0 * L * L, -6.0 * L, 4.0 * L * L],
            ]
        )
    )
    m[np.ix_(bend, bend)] = (
        rho_a
        * L
        / 420.0
        * np.array(
            [
                [156.0, 22.0 * L, 54.0, -13.0 * L],
                [22.0 * L, 4.0 * L * L, 13.0 * L, -3.0 * L * L],
                [54.0, 13.0 * L, 156.0, -22.0 * L],
                [-13.0 * L, -3.0 * L * L, -22.0 * L, 4.0 * L * L],
            ]
        )
    )
    return k, m


def clamped_beam_matrices(
    length: float, n_elements: int, ea: float, ei: float, rho_a: float
) -> tuple[np.ndarray, np.ndarray]:
    """Assembled stiffness and mass of a uniform beam clamped at ``x = 0``.

    Nodes ``0 … n_elements`` are equally spaced; node 0 is clamped and
    removed, so node ``i >= 1`` owns DOFs ``3 (i - 1) + (0, 1, 2)``.

    Returns
    -------
    stiffness, mass : ndarray, shape (3 n_elements, 3 n_elements)
    """
    n_full = DOFS_PER_NODE * (n_elements + 1)
    K = np.zeros((n_full, n_full))
    M = np.zeros((n_full, n_full))
    ke, me = element_matrices(length / n_elements, ea, ei, rho_a)
    for e in range(n_elements):
        s = slice(DOFS_PER_NODE * e, DOFS_PER_NODE * (e + 2))
        K[s, s] += ke
        M[s, s] += me
    free = slice(DOFS_PER_NODE, n_full)
    return np.ascontiguousarray(K[free, free]), np.ascontiguousarray(M[free, free])


def node_dof(node: int, kind: int) -> int:
    """Index of DOF ``kind`` (``AXIAL``, ``TRANSVERSE``, ``ROTATION``) of
    node ``node >= 1`` in the clamped numbering."""
    return DOFS_PER_NODE * (node - 1) + kind
