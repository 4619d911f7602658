"""The system protocol: what hbmfric needs from a mechanical system.

:func:`hbmfric.frf`, :func:`hbmfric.periodic_solution` and
:func:`hbmfric.validation.steady_state` accept the built-in systems
(:class:`~hbmfric.Oscillator`, :class:`~hbmfric.CantileverBeam`,
:class:`~hbmfric.BeltTensioner`) and any object of your own that provides

``n_dof`` : int
    Number of degrees of freedom ``n`` (>= 1).
``matrices()`` -> (M, C, K)
    Mass (kg), viscous damping (N s/m) and stiffness (N/m) matrices of the
    structure without the contact, each of shape (n, n), finite. ``M`` must
    be symmetric positive definite (every DOF carries mass). ``C`` and ``K``
    may be non-symmetric (gyroscopic or circulatory terms): the full HBM
    solves such systems; the condensation onto the contact DOF, the
    default for several DOFs, needs all three symmetric and ``K`` regular
    (a structure held only by its contact, like the belt tensioner, has no
    static receptance) and is skipped otherwise.
``load_vector(force)`` -> p
    Amplitude per DOF of the forcing ``p cos Ωt`` for the forcing amplitude
    ``force`` (N), shape (n,), finite; complex for loads with their own
    phases, the forcing then being ``Re(p e^{iΩt})``.
``contact`` : ContactLaw or None
    The friction law (such as :class:`~hbmfric.Jenkins`), or None for a
    linear system.
``contact_dof`` : int
    The DOF the contact acts on, ``0 <= contact_dof < n``.

and optionally

``contacts`` : sequence of :class:`~hbmfric.Contact`
    Several contacts (each a law on one DOF or between two DOFs, integer
    indices); ``contact`` and ``contact_dof`` then name the first (the DOF
    that results report by default).
``symmetric`` : bool, default False
    True if the response to ``F cos Ωt`` has odd harmonics only (a contact
    law that is odd and no constant load); halves the unknowns.
``dof_names`` : dict
    Names of DOFs (``{"tip": 7, "contact": 7}``), accepted wherever a ``dof``
    is asked for; ``"contact"`` is the default DOF of results.
``static_load()`` -> p0
    A constant load, shape (n,), N.
``load_phase`` : float
    Phase ``φ`` of the forcing ``p cos(Ωt − φ)``, rad.
``static_solution()`` -> x0
    Rest position added to the linear starting guesses, shape (n,), m.
``modes()`` -> (ω, Φ)
    Natural pulsations and mass-normalised mode shapes, if known in closed
    form (else computed from ``M`` and ``K``).
``output_weights`` -> (a, b)
    The output whose truncation error ``harmonics="auto"`` and the
    per-point estimate (``Branch.truncation_error``) watch: ``sum_d a_d
    x_d + b_d ẋ_d``, ``a`` (output unit per m) and ``b`` (per m/s) each
    of shape (n,), finite, not both zero (default: the contact DOF's displacement,
    where the higher harmonics are made; the belt tensioner names its
    belt tension). A constant added to the output changes nothing (the
    estimate is relative to the first harmonic and to half the
    peak-to-peak value). A problem condensed onto the contact DOF watches
    that DOF.

:func:`check_system` checks all of this on entry and raises ``TypeError``
or ``ValueError`` naming the offending attribute, instead of an error from
deep inside the solver.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validate import finite_float, positive_int
from ..laws import Contact2D, ContactLaw
from .contacts import check_contacts

REQUIRED = ("n_dof", "matrices", "load_vector", "contact", "contact_dof")
"""Attributes every system must have."""

#: relative tolerance of the symmetry check of M and K
SYMMETRY_TOL = 1e-10


@dataclass(frozen=True)
class SystemData:
    """A checked system, as float64 arrays.

    Attributes
    ----------
    n_dof : int
    contact : ContactLaw or None
    contact_dof : int
    mass, damping, stiffness : ndarray, shape (n_dof, n_dof)
        kg, N s/m, N/m; C-contiguous copies.
    static_load : ndarray, shape (n_dof,), or None
        N; None without the hook.
    load_phase : float
        rad.
    contacts : tuple of (ContactLaw, int, int)
        Every contact as ``(law, a, b)``, ``b = -1`` against ground
        (:func:`hbmfric.systems.contacts.check_contacts`).
    """

    n_dof: int
    contact: ContactLaw | None
    contact_dof: int
    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    static_load: np.ndarray | None
    load_phase: float
    contacts: tuple = ()


def _vector(label: str, value, n: int) -> np.ndarray:
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(
            f"{label} must be a real array of shape ({n},), got {value!r}"
        ) from None
    if a.shape != (n,):
        raise ValueError(f"{label} must have shape ({n},) (n_dof), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{label} must contain only finite values (no NaN or inf)")
    return a


def _matrix(label: str, value, n: int) -> np.ndarray:
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(
            f"{label} must be a real array of shape ({n}, {n}), got {value!r}"
        ) from None
    if a.shape != (n, n):
        raise ValueError(f"{label} must have shape ({n}, {n}) (n_dof), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{label} must contain only finite values (no NaN or inf)")
    return np.ascontiguousarray(a)


def _check_symmetric(label: str, a: np.ndarray) -> None:
    scale = float(np.max(np.abs(a)))
    asym = float(np.max(np.abs(a - a.T)))
    if asym > SYMMETRY_TOL * scale:
        raise ValueError(
            f"{label} must be symmetric; max |A - Aᵀ| = {asym:.3g} "
            f"(max |A| = {scale:.3g})"
        )


def check_system(system) -> SystemData:
    """Check ``system`` against the protocol of this module.

    Parameters
    ----------
    system : object
        A built-in system or an object following the protocol.

    Returns
    -------
    SystemData
        The checked attributes and matrices.

    Raises
    ------
    TypeError
        If ``system`` lacks a required attribute or ``contact`` is not a
        contact law.
    ValueError
        If a matrix or vector has the wrong shape or non-finite entries,
        ``M`` is not symmetric positive definite, or ``contact_dof`` is out
        of range; the message names the field.
    """
    missing = [a for a in REQUIRED if not hasattr(system, a)]
    if missing:
        raise TypeError(
            "system must be an hbmfric system (hf.Oscillator, hf.CantileverBeam, "
            "hf.BeltTensioner, or your own object with "
            f"{', '.join(REQUIRED)}: see hbmfric.systems.protocol), got "
            f"{type(system).__name__} without {', '.join(missing)}"
        )
    n = positive_int("system.n_dof", system.n_dof, low=1)
    law = system.contact
    if law is not None and not isinstance(law, ContactLaw | Contact2D):
        raise TypeError(
            f"system.contact must be a contact law such as hf.Jenkins, or None, "
            f"got {type(law).__name__}"
        )
    c = system.contact_dof
    if isinstance(c, bool) or not isinstance(c, int | np.integer) or not 0 <= c < n:
        raise ValueError(
            f"system.contact_dof must be an integer in [0, {n - 1}] (n_dof = {n}), "
            f"got {c!r}"
        )
    matrices = system.matrices()
    try:
        m, d, k = matrices
    except (TypeError, ValueError):
        raise ValueError(
            "system.matrices() must return the three matrices (M, C, K), got "
            f"{type(matrices).__name__}"
        ) from None
    mass = _matrix("system.mass (M of system.matrices())", m, n)
    damping = _matrix("system.damping (C of system.matrices())", d, n)
    stiffness = _matrix("system.stiffness (K of system.matrices())", k, n)
    if n == 1:
        # one DOF (the common SDOF case): symmetric, and positive definite
        # iff the mass is positive (a tenth of the cost of the general test)
        positive = bool(mass[0, 0] > 0.0)
    else:
        _check_symmetric("system.mass (M of system.matrices())", mass)
        try:
            np.linalg.cholesky(mass)
            positive = True
        except np.linalg.LinAlgError:
            positive = False
    if not positive:
        low = float(np.linalg.eigvalsh(mass)[0])
        raise ValueError(
            "system.mass (M of system.matrices()) must be positive definite "
            f"(every DOF needs mass); its smallest eigenvalue is {low:.3g}"
        ) from None
    static = getattr(system, "static_load", None)
    if static is not None:
        static = _vector("system.static_load()", static(), n)
    phase = finite_float("system.load_phase", getattr(system, "load_phase", 0.0))
    contacts = check_contacts(system, n)
    output_weights(system, n, int(c))
    return SystemData(n, law, int(c), mass, damping, stiffness, static, phase, contacts)


def output_weights(system, n_dof: int, contact_dof: int) -> np.ndarray:
    """The watched output of ``system`` (its ``output_weights``, see the
    module docstring), checked.

    Parameters
    ----------
    system : object
        A system following the protocol.
    n_dof : int
        Its number of DOFs.
    contact_dof : int
        Its contact DOF (the default output).

    Returns
    -------
    ndarray, shape (2, n_dof)
        Displacement weights (row 0, output unit per m) and velocity
        weights (row 1, per m/s).

    Raises
    ------
    ValueError
        If the weights are not a pair of finite vectors of shape (n_dof,)
        or are all zero.
    """
    label = "system.output_weights"
    value = getattr(system, "output_weights", None)
    out = np.zeros((2, n_dof))
    if value is None:
        out[0, contact_dof] = 1.0
        return out
    try:
        a, b = value
    except (TypeError, ValueError):
        raise ValueError(
            f"{label} must be a pair (displacement weights, velocity weights), "
            f"got {value!r}"
        ) from None
    out[0] = _vector(f"{label}[0] (displacement weights)", a, n_dof)
    out[1] = _vector(f"{label}[1] (velocity weights)", b, n_dof)
    if not np.any(out):
        raise ValueError(f"{label} must not be all zero (no output to watch)")
    return out


def check_load(system, force: float, n_dof: int, phase: float = 0.0) -> np.ndarray:
    """The forcing as a complex amplitude per DOF, shape (n_dof,), N.

    ``system.load_vector(force)`` may be real (the load ``p cos(Ωt − φ)``
    with ``φ`` the system's ``load_phase``, passed as ``phase``) or complex
    (the load ``Re(p e^{iΩt})``, each DOF with its own phase, which
    ``load_phase`` shifts too). The result ``q`` is in the second form:
    the load is ``Re(q e^{iΩt}) = Re(q) cos Ωt − Im(q) sin Ωt``.

    Raises
    ------
    ValueError
        If the vector has the wrong shape or non-finite entries (named).
    """
    label = "system.load_vector(force)"
    value = system.load_vector(force)
    if np.iscomplexobj(value):
        a = np.asarray(value, dtype=np.complex128)
        if a.shape != (n_dof,):
            raise ValueError(
                f"{label} must have shape ({n_dof},) (n_dof), got {a.shape}"
            )
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{label} must contain only finite values (no NaN or inf)")
    else:
        a = _vector(label, value, n_dof).astype(np.complex128)
    return a * np.exp(-1j * phase) if phase else a


__all__ = ["REQUIRED", "SystemData", "check_load", "check_system", "output_weights"]
