"""Craig–Bampton reduction onto boundary (contact) DOFs plus fixed-interface
modes.

The DOFs are split into boundary DOFs ``b`` (kept physically: the contact
DOFs, the forced DOFs, any DOF to be read out exactly) and interior DOFs
``i``. The interior motion is represented by the static constraint modes
``Ψ = -K_ii⁻¹ K_ib`` (the interior's static response to a unit motion of
each boundary DOF) plus the first ``n_modes`` fixed-interface modes ``Φ_i``
(the interior's modes with every boundary DOF clamped):

    x = T [x_b; η],   T = [[I, 0], [Ψ, Φ_i]],

and the reduced matrices are ``Tᵀ M T``, ``Tᵀ C T``, ``Tᵀ K T``, the reduced
load ``Tᵀ p``. Friction acts on boundary DOFs only, so the reduced model
carries the contact exactly; the reduction is accurate for responses well
below the highest kept fixed-interface frequency (:attr:`ReducedStructure.
cutoff_frequency`).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import AccuracyWarning
from .contacts import Contact
from .structure import LinearStructure


class ReducedStructure(LinearStructure):
    """A :class:`LinearStructure` reduced by :func:`craig_bampton`.

    Its first ``n_boundary`` DOFs are the kept boundary DOFs (with their
    names), the rest the modal coordinates of the fixed-interface modes
    (named ``"mode:1"``, ``"mode:2"``, ...).

    Attributes
    ----------
    full : LinearStructure
        The structure that was reduced.
    boundary : ndarray of int, shape (n_boundary,)
        Indices of the kept DOFs in the full structure.
    transformation : ndarray, shape (n_full, n_boundary + n_modes)
        ``T``: full displacements ``x = T x_reduced``.
    cutoff_frequency : float
        Highest kept fixed-interface frequency, Hz; the reduced model is
        accurate well below it. ``inf`` when every DOF is a boundary DOF
        (nothing reduced), 0 for an interior without modes (a Guyan
        reduction: static accuracy only).
    valid_below : float
        Pulsation (rad/s) above which a response of the reduced model is
        not trusted: ``2π cutoff_frequency``, or for a Guyan reduction the
        lowest fixed-interface pulsation (none of those modes is kept);
        ``inf`` when nothing is reduced. :func:`hbmfric.frf`,
        :func:`hbmfric.periodic_solution` and :func:`hbmfric.nonlinear_mode`
        warn (:class:`~hbmfric.AccuracyWarning`) above it
        (:func:`warn_above_cutoff`).
    """

    def expand(self, coefficients: np.ndarray) -> np.ndarray:
        """Displacements (or Fourier coefficients) of every DOF of the full
        structure from those of the reduced one.

        Parameters
        ----------
        coefficients : ndarray, shape (n_reduced, ...) or (..., n_reduced, n_coef)
            Reduced coordinates along axis 0, or a branch's coefficients
            ``(n_points, n_reduced, n_coef)``.

        Returns
        -------
        ndarray
            The same shape with ``n_reduced`` replaced by ``n_full``.
        """
        c = np.asarray(coefficients, dtype=float)
        n = self.transformation.shape[1]
        if c.ndim == 3 and c.shape[1] == n:
            return np.einsum("fr,prc->pfc", self.transformation, c)
        if c.shape[0] != n:
            raise ValueError(
                f"coefficients must have {n} reduced coordinates along axis 0 "
                f"(or axis 1 of a branch's coefficients), got shape {c.shape}"
            )
        return np.tensordot(self.transformation, c, axes=(1, 0))


def craig_bampton(
    structure: LinearStructure, boundary, n_modes: int
) -> ReducedStructure:
    """Reduce a structure onto boundary DOFs plus fixed-interface modes.

    Parameters
    ----------
    structure : LinearStructure
        The full model (its contact DOF must be a boundary DOF).
    boundary : sequence of int or str
        The DOFs kept physically (indices or names), e.g. the contact DOFs
        and the forced DOF.
    n_modes : int
        Number of fixed-interface modes kept (0 gives the Guyan reduction).

    Returns
    -------
    ReducedStructure
        Same contact law, load ``Tᵀ p``, damping ``Tᵀ C T``; DOF names of
        the boundary DOFs carried over.

    Raises
    ------
    ValueError
        Empty or repeated boundary, the contact DOF not in it, ``n_modes``
        out of range (0 to the number of interior DOFs), or an interior
        that is not held by the boundary (singular ``K_ii``: rigid-body
        motion of the interior).
    """
    if not isinstance(structure, LinearStructure):
        raise ValueError(
            "craig_bampton reduces a hf.LinearStructure, got "
            f"{type(structure).__name__}"
        )
    try:
        items = list(boundary)
    except TypeError:
        raise ValueError(
            f"boundary must be a sequence of DOFs, got {boundary!r}"
        ) from None
    b = np.array([structure.dof(d, "boundary") for d in items], dtype=int)
    n = structure.n_dof
    if b.size == 0:
        raise ValueError("boundary must hold at least one DOF")
    if np.unique(b).size != b.size:
        raise ValueError(f"boundary has repeated DOFs: {items!r}")
    contacts = structure.contacts
    contact_dofs = (
        [
            d
            for c in contacts
            for d in (c.dof, c.other, c.normal, c.normal_other)
            if d is not None
        ]
        if contacts is not None
        else ([structure.contact_dof] if structure.contact is not None else [])
    )
    for d in contact_dofs:
        if d not in b:
            named = [
                k for k, i in structure.dof_names.items() if i == d and k != "contact"
            ]
            label = f"{d} ({', '.join(map(repr, named))})" if named else f"{d}"
            raise ValueError(
                f"the contact DOF {label} must be a boundary DOF "
                "(friction acts on physical DOFs only): add it to boundary"
            )
    interior = np.setdiff1d(np.arange(n), b)
    if isinstance(n_modes, bool) or not isinstance(n_modes, int | np.integer):
        raise ValueError(f"n_modes must be an integer, got {n_modes!r}")
    if not 0 <= n_modes <= interior.size:
        raise ValueError(
            f"n_modes must be in [0, {interior.size}] (the interior DOFs), got "
            f"{n_modes}"
        )
    M, C, K = structure.matrices()
    T = np.zeros((n, b.size + n_modes))
    T[b, np.arange(b.size)] = 1.0
    # no interior: the reduction is exact; an interior without modes (a
    # Guyan reduction) keeps its statics only, exact at Ω = 0 alone
    cutoff = math.inf if not interior.size else 0.0
    if interior.size:
        from scipy.linalg import cho_factor, cho_solve, eigh

        K_ii = K[np.ix_(interior, interior)]
        try:
            factor = cho_factor(K_ii)
        except np.linalg.LinAlgError:
            raise ValueError(
                "the interior stiffness K_ii is singular: the boundary DOFs do not "
                "hold the interior (add DOFs to the boundary)"
            ) from None
        T[np.ix_(interior, np.arange(b.size))] = -cho_solve(
            factor, K[np.ix_(interior, b)]
        )
        if n_modes:
            lam, phi = eigh(
                K_ii, M[np.ix_(interior, interior)], subset_by_index=(0, n_modes - 1)
            )
            T[np.ix_(interior, b.size + np.arange(n_modes))] = phi
            cutoff = math.sqrt(max(float(lam[-1]), 0.0)) / (2.0 * math.pi)
            valid_below = 2.0 * math.pi * cutoff
        else:
            # Guyan: no fixed-interface mode kept; the lowest one bounds
            # the pulsations its statics can stand for
            lam = eigh(
                K_ii,
                M[np.ix_(interior, interior)],
                eigvals_only=True,
                subset_by_index=(0, 0),
            )
            valid_below = math.sqrt(max(float(lam[0]), 0.0))
    else:
        valid_below = math.inf

    def reduce(a):
        r = T.T @ a @ T
        return 0.5 * (r + r.T)

    position = {int(d): k for k, d in enumerate(b)}
    names = {
        name: position[i]
        for name, i in structure.dof_names.items()
        if i in position and name != "contact"
    }
    names.update({f"mode:{j + 1}": b.size + j for j in range(n_modes)})
    load = T.T @ structure.load
    reduced = ReducedStructure(
        reduce(M),
        reduce(K),
        reduce(C) if np.any(C) else None,
        load=load,
        static_load=T.T @ structure.static_load(),
        dof_names=names,
        **_reduced_contacts(structure, position),
    )
    reduced.full = structure
    reduced.boundary = b
    reduced.transformation = T
    reduced.cutoff_frequency = cutoff
    reduced.valid_below = valid_below
    return reduced


def warn_above_cutoff(system, omega_high: float, what: str, stacklevel: int) -> None:
    """Warn when a Craig–Bampton reduced structure is asked for a response
    at a pulsation above the range it stands for.

    Above the highest kept fixed-interface mode the reduced model's own
    modes are those of a different structure: on a 40-DOF chain the
    reduced natural frequencies below :attr:`ReducedStructure.valid_below`
    are within 1.5 % of the full model's, those above it 4 to 18 % off
    (``bench/README.md``, stop 28); its FRF there is the reduced model's,
    not the structure's, and no other check would say so.

    Parameters
    ----------
    system : object
        Any system; only a :class:`ReducedStructure` is checked.
    omega_high : float
        Highest fundamental pulsation asked for, rad/s.
    what : str
        What was asked (for the message), e.g. ``"the FRF band"``.
    stacklevel : int
        Passed to :func:`warnings.warn` (the user's line).
    """
    if not isinstance(system, ReducedStructure):
        return
    limit = float(getattr(system, "valid_below", math.inf))
    if not omega_high > limit:
        return
    kept = system.transformation.shape[1] - system.boundary.size
    warnings.warn(
        f"{what} reaches {omega_high:.6g} rad/s, above the {limit:.6g} rad/s "
        f"({limit / (2.0 * math.pi):.6g} Hz) that the Craig–Bampton reduction "
        f"with n_modes={kept} stands for (its highest kept fixed-interface "
        "mode, or the lowest one for a Guyan reduction): the response there "
        "is the reduced model's, not the structure's; keep more modes "
        "(hf.craig_bampton(..., n_modes=...)) so that the cutoff lies above "
        "the band",
        AccuracyWarning,
        stacklevel=stacklevel + 1,
    )


def _reduced_contacts(structure, position: dict[int, int]) -> dict:
    """The contact arguments of the reduced structure (DOFs renumbered by
    ``position``)."""
    if structure.contacts is not None:
        return {
            "contacts": [
                Contact(
                    c.law,
                    *(
                        None if d is None else position[d]
                        for d in (c.dof, c.other, c.normal, c.normal_other)
                    ),
                )
                for c in structure.contacts
            ]
        }
    if structure.contact is None:
        return {}
    return {
        "contact": structure.contact,
        "contact_dof": position[structure.contact_dof],
    }
