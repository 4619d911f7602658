"""Friction contacts of a structure: which law acts between which DOFs.

A structure from matrices (:class:`~hbmfric.LinearStructure`) may carry
any number of contacts, each a law (:class:`~hbmfric.Jenkins`,
:class:`~hbmfric.Menq`, :class:`~hbmfric.Iwan`, ...) acting on one DOF
against ground or on the relative displacement of two DOFs (the two sides
of a joint). The engine solves them all in one harmonic balance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kernels.dlft.coulomb import COULOMB
from ..laws import Contact2D, ContactLaw


@dataclass(frozen=True)
class Contact:
    """A contact law acting at one DOF or between two DOFs.

    Parameters
    ----------
    law : ContactLaw or Contact2D
        The friction law, e.g. ``hf.Jenkins(stiffness=..., slip_force=...)``,
        or the 2D element :class:`~hbmfric.Contact2D` (friction under a
        varying normal load that may open).
    dof : int or str
        The DOF ``a`` the law acts on (index, or a name of the structure's
        ``dof_names``); the tangential DOF of a 2D element.
    other : int or str or None
        The DOF ``b`` on the other side of the joint: the law acts on the
        relative displacement ``x_a - x_b``, with the force ``+f`` on ``a``
        and ``-f`` on ``b``. None (default): against ground, on ``x_a``.
    normal : int or str or None
        The normal DOF of a 2D element (its displacement positive closing
        the contact); required for :class:`~hbmfric.Contact2D`, refused for
        the other laws.
    normal_other : int or str or None
        The normal DOF on the other side of the joint (relative normal
        displacement ``x_normal - x_normal_other``); None: against ground.

    Examples
    --------
    >>> import hbmfric as hf
    >>> joint = hf.Contact(hf.Jenkins(stiffness=3.0, slip_force=1.0), 4, other=9)
    >>> joint.dof, joint.other
    (4, 9)
    """

    law: ContactLaw | Contact2D
    dof: int | str
    other: int | str | None = None
    normal: int | str | None = None
    normal_other: int | str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.law, ContactLaw | Contact2D):
            raise TypeError(
                "Contact.law must be a contact law such as hf.Jenkins or "
                f"hf.Contact2D, got {type(self.law).__name__}"
            )
        for label in ("dof", "other", "normal", "normal_other"):
            v = getattr(self, label)
            if v is None and label != "dof":
                continue
            if isinstance(v, bool) or not isinstance(v, int | np.integer | str):
                raise TypeError(
                    f"Contact.{label} must be a DOF index or name, got {v!r}"
                )
        two_d = isinstance(self.law, Contact2D)
        if two_d and self.normal is None:
            raise ValueError("a Contact2D element needs its normal DOF (normal=...)")
        if not two_d and (self.normal is not None or self.normal_other is not None):
            raise ValueError(
                f"normal DOFs are for hf.Contact2D only, not {type(self.law).__name__}"
            )


def shared_directions(a, b, a_n, b_n) -> list:
    """DOFs that a 2D element would use both as a tangential DOF (``a``,
    ``b``) and as a normal DOF (``a_n``, ``b_n``); ground (None or -1) is
    not a DOF. One scalar DOF has one direction, so it cannot be both."""
    ground = (None, -1)
    tangential = {d for d in (a, b) if d not in ground}
    return sorted(d for d in (a_n, b_n) if d not in ground and d in tangential)


def check_contacts(system, n_dof: int) -> tuple[tuple[ContactLaw, int, int], ...]:
    """The contacts of ``system`` as ``(law, a, b, a_n, b_n)`` tuples
    (``-1``: ground, or no normal DOF for the 1D laws), checked.

    A system lists them in ``contacts`` (a sequence of objects with
    ``law``, ``dof`` and ``other`` as integer indices); without that
    attribute its single ``contact`` law acts on ``contact_dof``.

    Raises
    ------
    TypeError
        A contact that is not a law.
    ValueError
        A DOF out of range, a contact between a DOF and itself, or a rigid
        :class:`~hbmfric.Coulomb` law that is not the only contact or acts
        between two DOFs (the DLFT of this release solves one rigid
        contact to ground).
    """
    listed = getattr(system, "contacts", None)
    if listed is None:
        law = system.contact
        if law is None:
            return ()
        return ((law, int(system.contact_dof), -1, -1, -1),)
    out = []
    for i, c in enumerate(listed):
        law = getattr(c, "law", None)
        if not isinstance(law, ContactLaw | Contact2D):
            raise TypeError(
                f"system.contacts[{i}].law must be a contact law such as "
                f"hf.Jenkins, got {type(law).__name__}"
            )
        dofs = []
        for label, low in (
            ("dof", 0),
            ("other", -1),
            ("normal", -1),
            ("normal_other", -1),
        ):
            v = getattr(c, label, None)
            v = -1 if v is None else v
            if (
                isinstance(v, bool)
                or not isinstance(v, int | np.integer)
                or not low <= v < n_dof
            ):
                raise ValueError(
                    f"system.contacts[{i}].{label} must be a DOF index in "
                    f"[0, {n_dof - 1}] (n_dof = {n_dof}), got {v!r}"
                )
            dofs.append(int(v))
        a, b, a_n, b_n = dofs
        if a == b or (a_n >= 0 and a_n == b_n):
            raise ValueError(f"system.contacts[{i}] acts between a DOF and itself")
        shared = shared_directions(a, b, a_n, b_n)
        if shared:
            raise ValueError(
                f"system.contacts[{i}] uses DOF {shared[0]} both tangentially and "
                "normally: a 2D element needs distinct tangential and normal DOFs"
            )
        if isinstance(law, Contact2D) and a_n < 0:
            raise ValueError(
                f"system.contacts[{i}] is a Contact2D element without its normal DOF"
            )
        out.append((law, a, b, a_n, b_n))
    for i, (law, _, b, _, _) in enumerate(out):
        if law.code == COULOMB and (len(out) > 1 or b >= 0):
            raise ValueError(
                f"system.contacts[{i}] is a rigid hf.Coulomb law: it must be the "
                "only contact and act against ground (other=None); use "
                "hf.Jenkins with a large stiffness for rigid contacts among "
                "several"
            )
    return tuple(out)


def contact_arrays(
    contacts, params: list[np.ndarray] | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kernel arrays of ``contacts`` (``(law, a, b)`` triples).

    Parameters
    ----------
    contacts : sequence of (law, a, b, a_n, b_n)
    params : list of ndarray, optional
        Parameters per contact replacing the laws' own (the rigid Coulomb
        contact's DLFT parameters).

    Returns
    -------
    pairs : ndarray of int64, shape (n_contacts, 4)
    codes : ndarray of int64, shape (n_contacts,)
    law_params : ndarray, shape (n_contacts, n_params)
        Rows padded with zeros to the longest (at least one column).
    """
    n = len(contacts)
    rows = [
        np.asarray(p if params is not None else law.params, dtype=np.float64)
        for (law, *_), p in zip(contacts, params or [None] * n, strict=True)
    ]
    width = max([1] + [r.size for r in rows])
    law_params = np.zeros((n, width))
    for i, r in enumerate(rows):
        law_params[i, : r.size] = r
    pairs = np.array([c[1:] for c in contacts], dtype=np.int64).reshape(n, 4)
    codes = np.array([c[0].code for c in contacts], dtype=np.int64)
    return np.ascontiguousarray(pairs), codes, law_params


__all__ = ["Contact", "check_contacts", "contact_arrays"]
