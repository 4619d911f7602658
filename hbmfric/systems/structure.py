"""A linear structure given by its matrices, with friction contacts.

This is how a structure from a finite-element code enters hbmfric: mass and
stiffness matrices (full or reduced, e.g. by :func:`craig_bampton`), a
damping model, named DOFs, loads on any DOFs with any phase, and contact
laws acting on one DOF each or between two DOFs (:class:`Contact`).
:class:`LinearStructure` follows the system protocol
(:mod:`hbmfric.systems.protocol`), so :func:`hbmfric.frf`,
:func:`hbmfric.periodic_solution` and the time-integration reference accept
it like the built-in systems.

Forcing convention: with the load vector ``p`` (complex, N, per unit of the
forcing amplitude) and the amplitude ``F`` passed to :func:`hbmfric.frf`,
the force on the structure is ``F Re(p e^{iΩt})``: a real ``p_j`` is a
cosine load, ``p_j = |p_j| e^{-iφ_j}`` the load ``|p_j| cos(Ωt − φ_j)``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from .._validate import finite_float
from ..laws import ContactLaw
from .contacts import Contact, shared_directions

#: relative tolerance of the symmetry checks of M, C and K
SYMMETRY_TOL = 1e-10
#: eigenvalues of K above ``-NEGATIVE_TOL * max|eig|`` count as >= 0
NEGATIVE_TOL = 1e-9
#: natural pulsations closer than this (relative) are one repeated frequency
#: for ``modal_damping`` (eigensolver rounding splits an exact pair by about
#: 1e-15; a real structure's distinct modes lie further apart)
REPEATED_TOL = 1e-8


def _square(label: str, value, n: int | None = None) -> np.ndarray:
    """``value`` as a finite, symmetric float64 matrix (dense)."""
    if hasattr(value, "toarray"):  # scipy.sparse
        value = value.toarray()
    try:
        a = np.asarray(value)
    except (TypeError, ValueError):
        a = None
    # complex (a structural-damping K(1 + iη)) would lose its imaginary part
    # in the cast without a word; strings and objects are no matrices either
    if a is None or a.dtype.kind not in "biuf":
        kind = "" if a is None else f" of dtype {a.dtype}"
        raise ValueError(
            f"{label} must be a real square matrix, got {type(value).__name__}{kind}"
        )
    a = np.array(a, dtype=np.float64)
    if a.ndim != 2 or a.shape[0] != a.shape[1] or a.shape[0] == 0:
        raise ValueError(f"{label} must be a non-empty square matrix, got {a.shape}")
    if n is not None and a.shape[0] != n:
        raise ValueError(
            f"{label} has shape {a.shape}, but the mass matrix has {n} DOFs"
        )
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{label} must contain only finite values (no NaN or inf)")
    scale = float(np.max(np.abs(a)))
    asym = float(np.max(np.abs(a - a.T)))
    if asym > SYMMETRY_TOL * max(scale, 1e-300):
        raise ValueError(
            f"{label} must be symmetric; max |A - Aᵀ| = {asym:.3g} "
            f"(max |A| = {scale:.3g}){_asymmetry_hint(a, asym, scale)}"
        )
    return np.ascontiguousarray(0.5 * (a + a.T))


def _positive_definite(label: str, a: np.ndarray) -> None:
    """ValueError unless ``a`` (a mass matrix) is positive definite.

    Tested on the matrix scaled to a unit diagonal, ``D^-1/2 A D^-1/2``
    with ``D = diag(A)``, whose eigenvalues do not depend on the units of
    the DOFs. The eigenvalues of ``A`` itself do: a beam or shell model
    mixes translations (entries ~ m) with rotations (~ m L²), and with
    elements of 0.2 mm in SI units the consistent mass of a 1 cm beam has
    eigenvalues 4.9e-11 of its largest (stop 35: refused as "not positive
    definite", while in mm its ratio is 1e3 times larger; the same matrix
    scaled has 0.034)."""
    diag = np.diag(a)
    if not np.all(diag > 0.0):
        j = int(np.argmin(diag))
        raise ValueError(
            f"{label} must be positive definite (every DOF needs mass): DOF {j} "
            f"has {label}[{j}, {j}] = {diag[j]:.3g}"
            + (
                " (a massless DOF, such as the rotations of a lumped mass "
                "matrix: condense it out statically before, e.g. in the FE "
                "code)"
                if diag[j] == 0.0
                else ""
            )
        )
    d = 1.0 / np.sqrt(diag)
    eig = np.linalg.eigvalsh(a * d[:, None] * d[None, :])
    if not eig[0] > NEGATIVE_TOL * float(eig[-1]):
        raise ValueError(
            f"{label} must be positive definite (every DOF needs mass); scaled "
            "to a unit diagonal its smallest eigenvalue is "
            f"{eig[0]:.3g} (largest {eig[-1]:.3g})"
        )


def _asymmetry_hint(a: np.ndarray, asym: float, scale: float) -> str:
    """What a non-symmetric matrix from a file most often is: one triangle
    of a symmetric matrix (FE codes store one; a dense copy of it has zeros
    in the other), or a symmetric matrix with rounding."""
    lower, upper = np.tril(a, -1), np.triu(a, 1)
    for held, empty in (("upper", lower), ("lower", upper)):
        if not np.any(empty) and np.any(a - np.diag(np.diag(a))):
            return (
                f": it holds only its {held} triangle (the storage of a "
                "symmetric matrix by FE codes); expand it first, A + Aᵀ - "
                "diag(diag(A))"
            )
    if asym <= 1e-6 * scale:
        return (
            ": nearly symmetric; if that is rounding (a matrix computed in "
            "single precision, or printed with few digits), pass (A + Aᵀ) / 2"
        )
    return ""


def _semidefinite(label: str, a: np.ndarray, strict: bool) -> np.ndarray:
    """Eigenvalues of ``a``; ValueError if it is indefinite (or not
    positive definite with ``strict``: :func:`_positive_definite`)."""
    if strict:
        _positive_definite(label, a)
    eig = np.linalg.eigvalsh(a)
    top = max(float(np.max(np.abs(eig))), 1e-300)
    if eig[0] < -NEGATIVE_TOL * top:
        raise ValueError(
            f"{label} must be positive semi-definite; it has the negative "
            f"eigenvalue {eig[0]:.3g} (largest {eig[-1]:.3g})"
        )
    return eig


def _check_repeated_ratios(omega: np.ndarray, zeta: np.ndarray, given: int) -> None:
    """Refuse different damping ratios on modes of one repeated natural
    frequency (within :data:`REPEATED_TOL`, relative).

    The mode shapes of a repeated frequency (a symmetric structure: a ring,
    a disc, a square plate) are any basis of their space, the one the
    eigensolver returns by rounding; ``M Φ diag(2 ζ ω) Φᵀ M`` with
    different ``ζ`` on them depends on that basis. On a ring of three
    masses a perturbation of 1e-9 of one stiffness entry moves the
    driving-point receptance at the repeated resonance from 2.39 to 0.96
    m/N, and the damping matrix breaks the ring's symmetry."""
    rigid = NEGATIVE_TOL * float(omega[-1]) ** 2  # 2 ζ ω = 0 there: no damping
    for j in range(omega.size - 1):
        top = float(omega[j + 1])
        if top - omega[j] > REPEATED_TOL * top or not top * top > rigid:
            continue
        if zeta[j] != zeta[j + 1]:
            rest = " (the rest undamped)" if given <= j + 1 else ""
            raise ValueError(
                f"modal_damping gives modes {j + 1} and {j + 2} different ratios "
                f"({zeta[j]:g} and {zeta[j + 1]:g}{rest}), but they share the "
                f"natural pulsation {omega[j]:.6g} rad/s (repeated: a symmetric "
                "structure): their mode shapes are any basis of that pair, so "
                "the damping matrix would depend on rounding; give them the "
                "same ratio, or pass the damping matrix as damping="
            )


class LinearStructure:
    """A linear structure from its matrices, with friction contacts.

    Parameters
    ----------
    mass : array_like or sparse, shape (n, n)
        Mass matrix ``M``, kg; symmetric positive definite.
    stiffness : array_like or sparse, shape (n, n)
        Stiffness matrix ``K``, N/m; symmetric positive semi-definite (a
        free-floating structure has rigid-body modes).
    damping : array_like, shape (n, n), optional
        Viscous damping matrix ``C``, N s/m, symmetric. At most one of
        ``damping``, ``rayleigh`` and ``modal_damping``; none of them means
        no viscous damping.
    rayleigh : (float, float), optional
        ``(α, β)`` of Rayleigh damping ``C = α M + β K`` (``K`` the
        structure's, without the contacts), ``α`` in 1/s, ``β`` in s; mode
        ``j`` gets the damping ratio ``α / (2 ω_j) + β ω_j / 2``.
    modal_damping : float or array_like, optional
        Damping ratio of every mode (one value) or of the first modes (one
        per mode, the rest undamped), a fraction of critical damping in
        ``[0, 1)`` (0.02 for 2 %; 1 or more is refused as a likely
        percentage): ``C = M Φ diag(2 ζ_j ω_j) Φᵀ M`` with the
        mass-normalised modes ``Φ``. Modes of one repeated frequency (a
        symmetric structure) must have equal ratios (their shapes are any
        basis of their space; different ratios are refused).
    load : array_like or mapping, optional
        Load per unit forcing amplitude: a vector of shape (n,), real or
        complex (see the module notes for the phase), or a mapping
        ``{dof: value}`` with DOF indices or names. Default: a unit cosine
        load on the contact DOF.
    contact : ContactLaw, optional
        The friction law; None for a linear structure.
    contact_dof : int or str, optional
        The DOF the contact acts on (index or name); required with a
        contact.
    contacts : sequence of Contact, optional
        Several contacts instead of ``contact``/``contact_dof``: each a law
        on one DOF or between two DOFs (:class:`~hbmfric.Contact`, DOFs by
        index or name). ``contact`` and ``contact_dof`` then name the first
        one. Several contacts are condensed onto their contact coordinates
        when that applies (:func:`hbmfric.condensation.condensed_by_default`).
    dof_names : mapping of str to int, optional
        Names of DOFs, accepted wherever a DOF is asked for. ``"contact"``
        is added for the contact DOF.
    static_load : array_like or mapping, optional
        A constant load (N), shape (n,) or ``{dof: value}``, e.g. the
        preload that holds a :class:`~hbmfric.Contact2D` element closed; a
        structure with one is solved with every harmonic (no odd-only
        symmetry).

    Raises
    ------
    ValueError
        Mismatched shapes, non-finite entries, a non-symmetric or
        indefinite matrix, a DOF that does not exist, an unknown name, or
        more than one damping model; the message names the argument.

    Examples
    --------
    >>> import numpy as np, hbmfric as hf
    >>> s = hf.LinearStructure(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]],
    ...                        modal_damping=0.01, contact=hf.Jenkins(3.0, 1.0),
    ...                        contact_dof=1, load={0: 1.0})
    >>> s.n_dof, s.contact_dof
    (2, 1)
    """

    def __init__(
        self,
        mass,
        stiffness,
        damping=None,
        *,
        rayleigh: tuple[float, float] | None = None,
        modal_damping=None,
        load=None,
        contact: ContactLaw | None = None,
        contact_dof: int | str | None = None,
        contacts: Sequence[Contact] | None = None,
        dof_names: Mapping[str, int] | None = None,
        static_load=None,
    ) -> None:
        M = _square("mass", mass)
        n = M.shape[0]
        _semidefinite("mass", M, strict=True)
        K = _square("stiffness", stiffness, n)
        _semidefinite("stiffness", K, strict=False)
        self._mass, self._stiffness = M, K
        self.n_dof = n
        self._names = self._check_names(dof_names)
        given = [
            name
            for name, v in (
                ("damping", damping),
                ("rayleigh", rayleigh),
                ("modal_damping", modal_damping),
            )
            if v is not None
        ]
        if len(given) > 1:
            raise ValueError(
                f"give at most one damping model, got {' and '.join(given)}"
            )
        self._modes = None
        if damping is not None:
            C = _square("damping", damping, n)
            _semidefinite("damping", C, strict=False)
        elif rayleigh is not None:
            try:
                alpha, beta = rayleigh
            except (TypeError, ValueError):
                raise ValueError(
                    f"rayleigh must be a pair (alpha, beta), got {rayleigh!r}"
                ) from None
            alpha = finite_float("rayleigh alpha", alpha, low=0.0)
            beta = finite_float("rayleigh beta", beta, low=0.0)
            C = alpha * M + beta * K
        elif modal_damping is not None:
            C = self._modal_damping(modal_damping)
        else:
            C = np.zeros((n, n))
        self._damping = np.ascontiguousarray(C)
        if contact is not None and not isinstance(contact, ContactLaw):
            raise ValueError(
                "contact must be a contact law such as hf.Jenkins, or None, got "
                f"{type(contact).__name__}"
            )
        self.contacts = None
        if contacts is not None:
            if contact is not None or contact_dof is not None:
                raise ValueError(
                    "give either contacts or contact/contact_dof, not both"
                )
            self.contacts = self._check_contacts(contacts)
            if self.contacts:
                contact = self.contacts[0].law
                contact_dof = self.contacts[0].dof
        self.contact = contact
        if contact_dof is None:
            if contact is not None:
                raise ValueError("contact_dof is required with a contact")
            self.contact_dof = 0
        else:
            self.contact_dof = self.dof(contact_dof, "contact_dof")
        if contact is not None or contact_dof is not None:
            self._names.setdefault("contact", self.contact_dof)
        self._load = self._check_load(load)
        self._static = np.zeros(n)
        if static_load is not None:
            p0 = self._check_load(static_load, "static_load")
            if np.any(p0.imag):
                raise ValueError("static_load must be real (a constant load), N")
            self._static = p0.real.copy()

    @classmethod
    def from_files(cls, mass, stiffness, damping=None, **kwargs) -> LinearStructure:
        """A structure from matrix files, one per matrix.

        Parameters
        ----------
        mass, stiffness : str or Path
            Files of ``M`` and ``K`` (``.mtx``, ``.npy``, or ``.mat`` /
            ``.npz`` holding one array; ``"file.mat:Kff"`` picks the array
            ``Kff`` of a file with several).
        damping : str or Path, optional
            File of ``C``.
        **kwargs
            The other arguments of :class:`LinearStructure` (``rayleigh``,
            ``modal_damping``, ``load``, ``contact``, ``contact_dof``,
            ``dof_names``).
        """
        from .matrix_files import read_matrix

        def read(spec):
            text = str(spec)
            head, sep, name = text.rpartition(":")
            if sep and head.lower().endswith((".mat", ".npz")):
                return read_matrix(head, name)
            return read_matrix(text)

        c = None if damping is None else read(damping)
        return cls(read(mass), read(stiffness), c, **kwargs)

    @classmethod
    def from_file(cls, path, names: dict | None = None, **kwargs) -> LinearStructure:
        """A structure from one ``.mat`` or ``.npz`` file holding ``M``,
        ``K`` and optionally ``C`` (names found as in
        :func:`hbmfric.systems.matrix_files.read_matrices`, or given by
        ``names={"mass": ..., "stiffness": ..., "damping": ...}``);
        ``**kwargs`` as for :class:`LinearStructure`. A damping matrix in
        the file is used unless another damping model is given."""
        from .matrix_files import read_matrices

        found = read_matrices(path, names)
        damping = found.get("damping")
        if any(kwargs.get(k) is not None for k in ("rayleigh", "modal_damping")):
            damping = None
        return cls(found["mass"], found["stiffness"], damping, **kwargs)

    # -- checks ----------------------------------------------------------------
    def _check_names(self, names) -> dict[str, int]:
        if names is None:
            return {}
        if not isinstance(names, Mapping):
            raise ValueError(
                f"dof_names must be a mapping of names to DOF indices, got "
                f"{type(names).__name__}"
            )
        out = {}
        for name, index in names.items():
            if not isinstance(name, str):
                raise ValueError(f"dof_names keys must be strings, got {name!r}")
            out[name] = self._index(index, f"dof_names[{name!r}]")
        return out

    def _index(self, index, label: str) -> int:
        n = self.n_dof
        if isinstance(index, bool) or not isinstance(index, int | np.integer):
            raise ValueError(
                f"{label} must be a DOF index in [0, {n - 1}], got {index!r}"
            )
        if not 0 <= index < n:
            raise ValueError(
                f"{label} = {index} does not exist: the structure has {n} DOFs "
                f"(0 to {n - 1})"
            )
        return int(index)

    def dof(self, which: int | str, label: str = "dof") -> int:
        """Index of a DOF given by index or name (ValueError if unknown)."""
        if isinstance(which, str):
            if which not in self._names:
                known = ", ".join(sorted(self._names)) or "none"
                raise ValueError(
                    f"{label}: unknown DOF name {which!r} (known: {known})"
                )
            return self._names[which]
        return self._index(which, label)

    def _check_contacts(self, contacts) -> tuple[Contact, ...]:
        """``contacts`` with DOF names resolved to indices."""
        if isinstance(contacts, Contact) or not isinstance(contacts, Sequence):
            raise ValueError(
                "contacts must be a list of hf.Contact(law, dof, other=None), got "
                f"{type(contacts).__name__}"
            )
        out = []
        for i, c in enumerate(contacts):
            if not isinstance(c, Contact):
                raise ValueError(
                    f"contacts[{i}] must be an hf.Contact(law, dof, other=None), "
                    f"got {type(c).__name__}"
                )
            a = self.dof(c.dof, f"contacts[{i}].dof")
            rest = [
                None if v is None else self.dof(v, f"contacts[{i}].{label}")
                for label, v in (
                    ("other", c.other),
                    ("normal", c.normal),
                    ("normal_other", c.normal_other),
                )
            ]
            if a == rest[0] or (rest[1] is not None and rest[1] == rest[2]):
                raise ValueError(f"contacts[{i}] acts between a DOF and itself")
            shared = shared_directions(a, *rest)
            if shared:
                raise ValueError(
                    f"contacts[{i}] uses DOF {shared[0]} both tangentially and "
                    "normally: a 2D element needs distinct tangential and normal "
                    "DOFs"
                )
            out.append(Contact(c.law, a, *rest))
        return tuple(out)

    def _check_load(self, load, label: str = "load") -> np.ndarray:
        n = self.n_dof
        p = np.zeros(n, dtype=complex)
        if load is None:
            p[self.contact_dof] = 1.0
            return p
        if isinstance(load, Mapping):
            for key, value in load.items():
                j = self.dof(key, f"{label} key")
                v = complex(value)
                if not (math.isfinite(v.real) and math.isfinite(v.imag)):
                    raise ValueError(f"{label}[{key!r}] must be finite, got {value!r}")
                p[j] += v
            return p
        try:
            a = np.array(load, dtype=complex)
        except (TypeError, ValueError):
            raise ValueError(
                f"{label} must be a vector of shape ({n},) or a mapping "
                "{dof: value}, "
                f"got {type(load).__name__}"
            ) from None
        if a.ndim == 0:
            # a newcomer's `load=1.0`: the amplitude belongs to frf's force
            raise ValueError(
                f"{label} must be a vector of shape ({n},) (one entry per DOF) or "
                f"a mapping {{dof: value}}, got the number {load!r}: for a unit "
                f"load at DOF j give {label}={{j: 1.0}} (or a DOF name); the "
                "forcing amplitude itself is the force of hf.frf"
            )
        if a.shape != (n,):
            raise ValueError(
                f"{label} must have shape ({n},) (n_dof) or be a mapping "
                f"{{dof: value}}, got shape {a.shape}"
            )
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{label} must contain only finite values (no NaN or inf)")
        return a

    def _modal_damping(self, ratios) -> np.ndarray:
        omega, phi = self.modes()
        z = np.atleast_1d(np.asarray(ratios, dtype=float))
        if z.ndim != 1 or not np.all(np.isfinite(z)) or np.any(z < 0.0):
            raise ValueError(
                "modal_damping must be a ratio >= 0 or a 1-d array of ratios >= 0, "
                f"got {ratios!r}"
            )
        if np.any(z >= 1.0):
            raise ValueError(
                "modal_damping takes ratios of critical damping (0.02 for 2 %), "
                f"got {ratios!r}: a ratio >= 1 is critical or over-critical "
                "damping, most often a percentage given by mistake; for "
                "over-critical modes on purpose pass the matrix as damping="
            )
        if z.size > omega.size:
            raise ValueError(
                f"modal_damping has {z.size} ratios but the structure has "
                f"{omega.size} modes"
            )
        zeta = np.full(omega.size, z[0]) if z.size == 1 else np.zeros(omega.size)
        if z.size > 1:
            zeta[: z.size] = z
        _check_repeated_ratios(omega, zeta, z.size)
        mphi = self._mass @ phi
        return (mphi * (2.0 * zeta * omega)) @ mphi.T

    # -- the system protocol -----------------------------------------------------
    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass (kg), damping (N s/m) and stiffness (N/m), each (n, n)."""
        return self._mass.copy(), self._damping.copy(), self._stiffness.copy()

    def load_vector(self, force: float) -> np.ndarray:
        """Load amplitudes per DOF for the forcing amplitude ``force``,
        shape (n,): real for cosine loads, complex when some load has a
        phase (force ``Re(p e^{iΩt})``), N."""
        p = force * self._load
        return p.real.copy() if not np.any(self._load.imag) else p

    def static_load(self) -> np.ndarray:
        """Constant load per DOF (e.g. a bolt preload), shape (n,), N."""
        return self._static.copy()

    @property
    def load(self) -> np.ndarray:
        """Load per unit forcing amplitude, complex, shape (n,)."""
        return self._load.copy()

    @property
    def symmetric(self) -> bool:
        """True when the response has odd harmonics only (odd law)."""
        if self.contacts is not None:
            return all(c.law.odd for c in self.contacts)
        return self.contact is None or self.contact.odd

    @property
    def dof_names(self) -> dict[str, int]:
        """Named DOFs → index."""
        return dict(self._names)

    def modes(self) -> tuple[np.ndarray, np.ndarray]:
        """Natural pulsations (rad/s, ascending) and mass-normalised mode
        shapes (columns) of the structure without the contact."""
        if self._modes is None:
            from scipy.linalg import eigh

            lam, phi = eigh(self._stiffness, self._mass)
            self._modes = (np.sqrt(np.clip(lam, 0.0, None)), phi)
        omega, phi = self._modes
        return omega.copy(), phi.copy()

    def natural_frequencies(self, n: int | None = None) -> np.ndarray:
        """The first ``n`` natural frequencies (all by default), Hz, of the
        linear structure alone: without the contacts (their stiffness not
        added; ``CantileverBeam.natural_frequencies`` defaults to the same,
        ``contact="free"``, while ``LapJoint.natural_frequencies`` defaults
        to the joint stuck)."""
        omega = self.modes()[0] / (2.0 * math.pi)
        return omega if n is None else omega[:n]

    def with_contact(
        self, contact: ContactLaw | None, contact_dof: int | str | None = None
    ) -> LinearStructure:
        """The same structure with another contact law (on the same DOF, or
        between the same DOFs, unless ``contact_dof`` is given; a
        :class:`~hbmfric.ReducedStructure` stays one, with its
        transformation and valid range). ``None``: the linear structure,
        without any contact.

        Raises
        ------
        ValueError
            ``contact`` is not a contact law, or the structure has several
            contacts (``contacts=``: say which law goes where by building
            it again), or ``contact_dof`` is given for a contact between
            two DOFs or a 2D element.
        """
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new._names = dict(self._names)
        if contact is not None and not isinstance(contact, ContactLaw):
            raise ValueError(
                "contact must be a contact law such as hf.Jenkins, or None, got "
                f"{type(contact).__name__}"
            )
        placed = self.contacts or ()
        if contact is not None and len(placed) > 1:
            # the others were dropped without a word (stop 35)
            raise ValueError(
                f"the structure has {len(placed)} contacts: with_contact replaces "
                "the law of one; build it again with contacts=[hf.Contact(law, "
                "dof, other=...), ...] (or with_contact(None) for the linear "
                "structure)"
            )
        if contact is not None and len(placed) == 1:
            c = placed[0]
            joined = (c.other, c.normal, c.normal_other) != (None, None, None)
            if contact_dof is None:
                # keep where it acts: a contact between two DOFs became one
                # to ground on the first of them (stop 35)
                try:
                    one = Contact(contact, c.dof, c.other, c.normal, c.normal_other)
                except (TypeError, ValueError) as exc:
                    raise ValueError(f"with_contact: {exc}") from None
                new.contact, new.contacts = contact, (one,)
                return new
            if joined:
                raise ValueError(
                    "contact_dof moves a contact to ground; this structure's "
                    "contact acts between DOFs (or is a 2D element): build it "
                    "again with contacts=[hf.Contact(law, dof, other=...)]"
                )
        new.contact = contact
        new.contacts = None
        if contact_dof is not None:
            new.contact_dof = self.dof(contact_dof, "contact_dof")
            new._names["contact"] = new.contact_dof
        return new

    def __repr__(self) -> str:
        if self.contacts is not None and len(self.contacts) != 1:
            return f"LinearStructure(n_dof={self.n_dof}, contacts={len(self.contacts)})"
        law = type(self.contact).__name__ if self.contact is not None else None
        return (
            f"LinearStructure(n_dof={self.n_dof}, contact={law}, "
            f"contact_dof={self.contact_dof})"
        )
