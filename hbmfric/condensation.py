"""Harmonic balance condensed onto the contacts: the plain-Python layer
that builds the data of :mod:`hbmfric.kernels.residuals.condensed` (modal or direct
receptance) and recovers the response of every DOF afterwards.

One contact to ground is condensed onto its DOF; several contacts (or one
between two DOFs) onto their contact coordinates ``q = B x``, one per 1D
contact (its relative displacement, or its DOF against ground) and two per
2D element (:class:`~hbmfric.Contact2D`: its tangential, then its normal
relative displacement)."""

from __future__ import annotations

import math

import numpy as np

from .hbm import HBMProblem, _stuck_stiffnesses
from .kernels.aft.contact2d import CONTACT2D
from .kernels.dlft.coulomb import COULOMB
from .kernels.linalg.krylov import N_REUSE, REUSE_MODE_BLOCKS, REUSE_MODE_FACTORS
from .kernels.linalg.krylov import REUSE_BLOCKS_KEEP as REUSE_BLOCKS_KEEP_INDEX
from .kernels.linalg.krylov import (
    REUSE_CAPACITANCE_EVERY as REUSE_CAPACITANCE_EVERY_INDEX,
)
from .kernels.linalg.krylov import REUSE_MODE as REUSE_MODE_INDEX
from .kernels.linalg.krylov import REUSE_REFRESH as REUSE_REFRESH_INDEX
from .kernels.linalg.krylov import REUSE_TOL as REUSE_TOL_INDEX
from .kernels.linalg.pattern import pattern_size
from .kernels.residuals.condensed import (
    AFT_EVENTS,
    AFT_SAMPLES,
    CONDENSED_FAMILY_TYPES,
    CONDENSED_SINGLE_TYPES,
    CONTACT2D_NORMAL,
    DIRECT,
    MODAL,
    STATE,
    CondensedCoulombProblem,
    CondensedProblem,
    condensed_contact_forces,
    condensed_modal_recover,
    condensed_residual,
    state_magnitudes,
)
from .kernels.residuals.hbm import aft_family
from .laws import Contact2D
from .signals import coefficient_columns
from .state_series import plan_state_series
from .systems.contacts import check_contacts, contact_arrays

#: largest off-diagonal term of Φᵀ C Φ, relative to its diagonal, accepted
#: as classical (modal) damping
_CLASSICAL_TOL = 1e-8

RECEPTANCE_METHODS = ("auto", "modal", "state", "direct")

#: largest error of the receptance from complex modes against direct solves
#: (relative to the largest receptance term, at the test pulsations of
#: :func:`state_space_modes`) accepted; beyond it the direct solve is used
STATE_TOL = 1e-10

#: relative distance ``|ω_r² - (kΩ)² + i kΩ c_r| / ω_r²`` of a harmonic
#: ``kΩ`` to a natural pulsation ``ω_r`` of the structure without its
#: contacts (a pole of the receptance, modal damping ``c_r``) below which
#: a solve from a standing start is not condensed
#: (:meth:`CondensedHBMProblem.pole_distance`): the recovered DOFs lose
#: about 6e-17 / distance (relative) there, measured on an undamped 2-DOF
#: chain with a Jenkins contact (stop 31: 7e-2 at 1e-15, 2.6e-4 at 1e-13,
#: 5.3e-6 at 1e-11, 2e-9 at 1e-9), and at 0 the receptance is infinite
POLE_DISTANCE = 1e-8
#: the series of the high poles (:meth:`CondensedHBMProblem.plan_band`) is
#: planned for pulsations up to this factor above the band's top harmonic
SERIES_MARGIN = 1.1

#: a condensed problem on several contacts with at least this many
#: unknowns solves its corrector's bordered systems by GMRES
#: (:func:`hbmfric.kernels.steps.newton.bordered_solve`), and the probe
#: solves of its truncation estimate too
#: (:func:`hbmfric.kernels.steps.truncation.probe_solve`); smaller ones
#: factor every iteration (their LU costs about as much as a few GMRES
#: iterations). The lap joint at ``N = 10``, ``H = 15`` (128 unknowns)
#: traces its branch in 0.62 s CPU with the harmonic blocks against
#: 0.79 s with an LU every iteration, the same 587 points.
REUSE_MIN_UNKNOWNS = 100
#: the corrector's preconditioner: ``"blocks"``, the harmonic blocks of the
#: current matrix (:func:`hbmfric.kernels.linalg.blocks.block_solve`), or
#: ``"factors"``, the kept LU factors of an earlier one
#: (:func:`hbmfric.kernels.linalg.krylov.reuse_solve`, stop 25)
REUSE_PRECONDITIONER = "blocks"
#: GMRES iterations at most per solve (the Krylov basis, order ``k + 1``)
REUSE_KRYLOV = 40
#: relative residual (2-norm) at which GMRES stops
REUSE_TOL = 1e-10
#: kept factors: a solve that took more matrix products than this makes
#: the next one factor afresh
REUSE_REFRESH = 12
#: the corrector on the harmonic blocks keeps the blocks factored for an
#: earlier matrix while its GMRES needs at most this many products more
#: than on fresh blocks (:func:`hbmfric.kernels.linalg.blocks.block_solve`);
#: negative: the blocks of every matrix are factored. Off at stop 27 (with
#: 3 the lap joint's N = 40 branch took 10.8 against 10.2 s CPU, its
#: Newton updates then solved to 1e-10); on since stop 29, with the updates
#: solved to 1e-6 (:data:`hbmfric.kernels.steps.newton.NEWTON_KRYLOV_TOL`):
#: N = 40 factors its blocks 44 times instead of 871 for 12 % more GMRES
#: products (bench/README.md "Issue 15, stop 29"). 5 since stop 30: with
#: the blocks corrected for the slipping coordinates a fresh preconditioner
#: solves in one iteration (two products with the check), and at N = 40
#: 1, 3, 5, 8 gave 411, 292, 98, 30 builds for 4513, 5387, 8107, 11207
#: products (bench/README.md "Issue 15, stop 30")
REUSE_KEEP_BLOCKS = 5
#: the harmonic blocks are corrected for at most this many slipping
#: coordinates (:mod:`hbmfric.kernels.linalg.capacitance`: a capacitance
#: matrix of order ``n_coef`` times as many, one dense LU per correction);
#: beyond it, for those with the largest coupling of harmonics; 0: no
#: correction (bench/README.md "Issue 15, stop 30")
REUSE_SLIP_MAX = 12
#: the correction is built for every matrix, also on kept blocks (True),
#: or only with freshly factored blocks (False, the default: at N = 40 a
#: correction for 10 coordinates costs 1.5 ms, twice the blocks' 0.7 ms,
#: and built for all 872 matrices it costs more than the GMRES products
#: it saves)
REUSE_CAPACITANCE_EVERY = False


def solver_arrays(
    n_unknowns: int,
    enabled: bool = True,
    n_dof: int = 1,
    n_coef: int = 0,
    first: int = 0,
) -> tuple:
    """Work arrays of the corrector's iterative solve for a bordered system
    of order ``n_unknowns + 1`` (``n_dof`` coordinates of ``n_coef``
    coefficients, ``first`` 1 when column 0 is the constant): dense factors,
    pivots, Krylov basis, state (:mod:`hbmfric.kernels.linalg.krylov`) and
    the harmonic blocks' factors, pivots, border and work
    (:func:`hbmfric.kernels.linalg.blocks.block_work`), their correction
    for at most :data:`REUSE_SLIP_MAX` slipping coordinates
    (:func:`hbmfric.kernels.linalg.capacitance.capacitance_work`) and room
    for the bordered matrix's nonzeros built on the Jacobian's pattern
    (CSR starts, columns, values;
    :func:`hbmfric.kernels.linalg.pattern.pattern_size` entries); of order 0 (plain LU
    every iteration) when not ``enabled`` or below
    :data:`REUSE_MIN_UNKNOWNS`. Without a layout (``n_coef = 0``) the kept
    factors precondition."""
    m = n_unknowns + 1 if enabled and n_unknowns >= REUSE_MIN_UNKNOWNS else 0
    if REUSE_PRECONDITIONER not in ("blocks", "factors"):
        raise ValueError(
            "REUSE_PRECONDITIONER must be 'blocks' or 'factors', "
            f"not {REUSE_PRECONDITIONER!r}"
        )
    blocks = (
        REUSE_PRECONDITIONER == "blocks"
        and m > 0
        and n_coef > 0
        and n_dof * n_coef == n_unknowns
    )
    state = np.zeros(N_REUSE)
    state[REUSE_TOL_INDEX] = REUSE_TOL
    state[REUSE_REFRESH_INDEX] = REUSE_REFRESH
    state[REUSE_BLOCKS_KEEP_INDEX] = REUSE_KEEP_BLOCKS
    state[REUSE_MODE_INDEX] = REUSE_MODE_BLOCKS if blocks else REUSE_MODE_FACTORS
    state[REUSE_CAPACITANCE_EVERY_INDEX] = 1.0 if REUSE_CAPACITANCE_EVERY else 0.0
    groups = first + (n_coef - first) // 2 if blocks else 0
    size = 2 * n_dof if blocks else 0
    n_slip = min(max(int(REUSE_SLIP_MAX), 0), n_dof) if blocks else 0
    k = n_slip * n_coef
    room = int(pattern_size(n_dof, n_coef, first)) if blocks else 0
    return (
        np.zeros((m, m)),
        np.zeros(m, dtype=np.int64),
        np.zeros((REUSE_KRYLOV + 1 if m else 0, m)),
        state,
        np.zeros((groups, size, size)),
        np.zeros((groups, size), dtype=np.int64),
        np.zeros(m),
        np.zeros(size),
        (
            np.zeros(1, dtype=np.int64),
            np.zeros(n_slip, dtype=np.int64),
            np.zeros((groups, size, 2 * n_slip)),
            np.zeros((n_slip, n_coef if blocks else 0, n_coef if blocks else 0)),
            np.zeros(k * k),
            np.zeros(k, dtype=np.int64),
            np.zeros(k),
        ),
        (
            np.zeros(m + 1 if blocks else 1, dtype=np.int64),
            np.zeros(room, dtype=np.int64),
            np.zeros(room),
        ),
    )


#: complex modes per system matrices (:func:`state_space_modes`)
_STATE_CACHE: dict = {}


def system_modes(system) -> tuple[np.ndarray, np.ndarray]:
    """Natural pulsations (rad/s) and mass-normalised mode shapes (columns)
    of the system without contact: ``system.modes()`` when it has one, else
    the generalised eigenproblem ``K φ = ω² M φ``."""
    if hasattr(system, "modes"):
        return system.modes()
    M, _, K = system.matrices()
    from scipy.linalg import eigh  # lazy: keeps import hbmfric light

    w2, shapes = eigh(K, M)
    return np.sqrt(np.maximum(w2, 0.0)), shapes


def can_condense(system) -> bool:
    """True when condensation pays and applies: a contact, fewer contact
    coordinates than DOFs, symmetric matrices and a regular stiffness
    matrix (a structure held only by its contact, such as the
    belt-tensioner rig, has no static receptance: harmonic 0 cannot be
    condensed).

    One contact to ground may have any law, a rigid Coulomb contact
    included (the condensed residual runs the same DLFT scheme as the full
    one). Several contacts, or one between two DOFs, are condensed onto
    their contact coordinates (one per 1D law, two per
    :class:`~hbmfric.Contact2D` element) when there are fewer of them than
    DOFs and they are independent (``B`` of full row rank: no two
    coordinates on the same pair of DOFs, no closed loop of contacts).
    """
    if system.contact is None or int(system.n_dof) < 2:
        return False
    n_dof = int(system.n_dof)
    contacts = check_contacts(system, n_dof)
    if not _single(contacts) and (
        len(coordinate_rows(contacts)) >= n_dof
        or _coordinate_problem(contacts, n_dof) is not None
    ):
        return False
    matrices = system.matrices()
    if not _symmetric(matrices):
        return False
    return coordinate_shift(contacts, np.asarray(matrices[2], dtype=float)) is not None


def condensed_by_default(system) -> bool:
    """What ``condense=None`` chooses: :func:`can_condense`, with the
    receptance from modal sums (classical damping) or complex modes
    (:func:`state_space_modes`) for several contacts.

    Several contacts are condensed by default since stop 24: the condensed
    curve rule draws the contact DOF recovered from the coordinates
    (:func:`hbmfric.kernels.residuals.condensed.coordinates_drawn`), the DOF a
    branch reports and checks, so the chords keep the curve tolerance as
    in full (the lap joint, N = 10, H = 15: ``Branch.curve_errors`` at
    most 1e-4 condensed and full). When neither receptance applies (the
    complex modes fail their check; the direct solve remains, whose curve
    rule watches the first coordinate) several contacts are solved in
    full."""
    if not can_condense(system):
        return False
    contacts = check_contacts(system, int(system.n_dof))
    if _single(contacts):
        return True
    matrices = system.matrices()
    shift = coordinate_shift(contacts, np.asarray(matrices[2], dtype=float))
    if np.any(shift):
        shifted = receptance_matrices(contacts, matrices, shift)
        return (
            _modal_damping_of(*shifted) is not None
            or state_space_modes(*shifted) is not None
        )
    if modal_damping(system) is not None:
        return True
    return state_space_modes(*system.matrices()) is not None


def _single(contacts) -> bool:
    """One contact, to ground, on one DOF: the single-DOF condensation."""
    return len(contacts) == 1 and max(contacts[0][2:]) < 0


def coordinate_rows(contacts) -> list[tuple[int, int, int, int]]:
    """The contact coordinates of ``contacts`` (``(law, a, b, a_n, b_n)``
    tuples), in order: ``(contact, direction, i, j)`` per coordinate
    ``q = x_i - x_j`` (``j = -1``: against ground), ``direction`` 0 for a
    1D law and for a 2D element's tangential coordinate, 1 for its normal
    one (the coordinate right after its tangential one)."""
    rows = []
    for c, (law, a, b, a_n, b_n) in enumerate(contacts):
        rows.append((c, 0, a, b))
        if isinstance(law, Contact2D):
            rows.append((c, 1, a_n, b_n))
    return rows


def coordinate_arrays(contacts) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The kernel arrays of the contact coordinates (:func:`coordinate_rows`):
    ``(i, j)`` pairs (int64, shape (n_c, 2)), law codes (int64, shape
    (n_c,); a 2D element's normal coordinate ``CONTACT2D_NORMAL``, its
    tangential one ``CONTACT2D``) and parameters per coordinate (shape
    (n_c, n_params), rows padded; a 2D element's on both its rows)."""
    _, codes, law_rows = contact_arrays(contacts)
    rows = coordinate_rows(contacts)
    pairs = np.array([(i, j) for _, _, i, j in rows], dtype=np.int64).reshape(-1, 2)
    out_codes = np.array(
        [CONTACT2D_NORMAL if d == 1 else int(codes[c]) for c, d, _, _ in rows],
        dtype=np.int64,
    )
    out_rows = np.ascontiguousarray(law_rows[[c for c, *_ in rows]])
    return np.ascontiguousarray(pairs), out_codes, out_rows


def selection_matrix(contacts, n_dof: int) -> np.ndarray:
    """``B`` of the contact coordinates ``q = B x`` (:func:`coordinate_rows`),
    shape (n_c, n_dof): row ``a`` has +1 at the DOF of coordinate ``a``
    and -1 at its other DOF (none against ground)."""
    rows = coordinate_rows(contacts)
    B = np.zeros((len(rows), n_dof))
    for a, (_, _, i, j) in enumerate(rows):
        B[a, i] = 1.0
        if j >= 0:
            B[a, j] = -1.0
    return B


def _coordinate_problem(contacts, n_dof: int) -> str | None:
    """Why ``contacts`` cannot be condensed onto their coordinates, or
    None."""
    for i, (law, _a, _b, a_n, _b_n) in enumerate(contacts):
        if isinstance(law, Contact2D):
            if law.code != CONTACT2D or a_n < 0:
                return (
                    f"contacts[{i}] is a 2D element (hf.Contact2D) without its "
                    "normal DOF: it has no normal contact coordinate"
                )
            continue
        if law.code == COULOMB and len(contacts) > 1:
            return "a rigid hf.Coulomb contact is condensed only alone, to ground"
    B = selection_matrix(contacts, n_dof)
    if np.linalg.matrix_rank(B) < B.shape[0]:
        return (
            "the contact coordinates are not independent (two contacts, or "
            "the two directions of 2D elements, on the same pair of DOFs, or "
            "a closed loop of contacts): their receptance matrix is singular"
        )
    return None


def _modal_damping_of(M, C, K):
    """:func:`modal_damping` of the matrices (modes by ``eigh``)."""
    from scipy.linalg import eigh  # lazy: keeps import hbmfric light

    w2, shapes = eigh(K, M)
    if not np.all(w2 > 0.0):
        return None
    return _classical(np.sqrt(w2), shapes, C)


def _classical(omega, shapes, C):
    """``(ω_r, Φ, c_r)`` when ``Φᵀ C Φ`` is diagonal (to ``_CLASSICAL_TOL``
    of its largest diagonal entry), else None."""
    modal_c = shapes.T @ C @ shapes
    diag = np.diag(modal_c).copy()
    off = modal_c - np.diag(diag)
    scale = max(float(np.max(np.abs(diag))), 1e-300)
    if float(np.max(np.abs(off))) > _CLASSICAL_TOL * scale:
        return None
    return omega, shapes, diag


def modal_damping(system) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """``(ω_r, Φ, c_r)`` when the damping is classical (``Φᵀ C Φ`` diagonal)
    and the stiffness positive definite, else None."""
    M, C, K = (np.asarray(a, dtype=float) for a in system.matrices())
    omega, shapes = system_modes(system)
    if not np.all(omega > 0.0):
        return None
    return _classical(omega, shapes, C)


def state_space_modes(mass, damping, stiffness):
    """Complex modes of ``M ẍ + C ẋ + K x = f`` (any damping matrix), such
    that ``Z(ω)⁻¹ = (K - ω² M + iω C)⁻¹ = X diag(1/(iω - λ_r)) Y``.

    The first-order form is scaled by the Cholesky factors ``K = L_K L_Kᵀ``
    and ``M = L_M L_Mᵀ``: with the state ``z = [L_Kᵀ x; L_Mᵀ ẋ]``,
    ``ż = A z + [0; L_M⁻¹ f]``, ``A = [[0, Sᵀ], [-S, -L_M⁻¹ C L_M⁻ᵀ]]`` and
    ``S = L_M⁻¹ L_K`` (its singular values are the undamped natural
    pulsations, so ``A`` is nearly normal for light damping and its
    eigenvectors well conditioned). With ``A = V diag(λ) V⁻¹``:
    ``X = L_K⁻ᵀ V[:n]`` and ``Y = V⁻¹[:, n:] L_M⁻¹``. (Balancing by the
    undamped modes instead loses ``eps ω_max²/ω_min²`` relative on the
    low modes, 2e-6 on the lap joint.)

    The decomposition is checked against direct solves of ``Z(ω)`` at the
    pulsation 0 and at (up to 24) geometric midpoints between consecutive
    natural pulsations; it is returned only when the error at each is
    below :data:`STATE_TOL` relative to the largest term of ``Z⁻¹``, plus
    ``16 eps κ₁(Z)`` (the direct solve's own error where ``Z`` is
    ill-conditioned: 1e-8 at the lap joint's suspension modes, 1e-12 in
    its bending range). Defective or nearly repeated modes make ``V``
    ill-conditioned and fail this check. Cached per matrices.

    Parameters
    ----------
    mass, damping, stiffness : ndarray, shape (n_dof, n_dof)
        Symmetric; ``M`` and ``K`` positive definite (no rigid-body mode).

    Returns
    -------
    tuple or None
        ``(poles, X, Y, error)``: ``λ_r`` (rad/s, shape (2 n_dof,)), ``X``
        (shape (n_dof, 2 n_dof)), ``Y`` (shape (2 n_dof, n_dof)), complex,
        and the largest relative error measured; None when ``M`` or ``K``
        is not positive definite, the eigenproblem fails or the check
        fails (the caller then solves directly).
    """
    M, C, K = (np.ascontiguousarray(a, dtype=float) for a in (mass, damping, stiffness))
    key = (M.tobytes(), C.tobytes(), K.tobytes())
    if key in _STATE_CACHE:
        return _STATE_CACHE[key]
    out = _state_space_modes(M, C, K)
    if len(_STATE_CACHE) >= 8:
        _STATE_CACHE.pop(next(iter(_STATE_CACHE)))
    _STATE_CACHE[key] = out
    return out


def _state_space_modes(M, C, K):
    from scipy.linalg import LinAlgError, cholesky, eig, solve_triangular  # lazy

    n = M.shape[0]
    try:
        L_k = cholesky(K, lower=True)
        L_m = cholesky(M, lower=True)
    except LinAlgError:
        return None
    S = solve_triangular(L_m, L_k, lower=True)
    C_s = solve_triangular(L_m, solve_triangular(L_m, C, lower=True).T, lower=True)
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = S.T
    A[n:, :n] = -S
    A[n:, n:] = -C_s
    try:
        poles, V = eig(A)
        V_inv = np.linalg.inv(V)
    except (LinAlgError, np.linalg.LinAlgError, ValueError):
        return None
    if not (np.all(np.isfinite(poles)) and np.all(np.isfinite(V_inv))):
        return None
    X = solve_triangular(L_k.T, V[:n], lower=False)
    Y = solve_triangular(L_m.T, V_inv[:, n:].T, lower=False).T
    # test pulsations: 0 and geometric midpoints between consecutive
    # natural pulsations (at most 24)
    omega = np.unique(np.abs(poles.imag))
    omega = omega[omega > 0.0]
    mids = np.sqrt(omega[1:] * omega[:-1])
    mids = mids[np.diff(omega) > 1e-3 * omega[1:]]
    if mids.size > 24:
        mids = mids[np.unique(np.linspace(0, mids.size - 1, 24).astype(int))]
    error = 0.0
    for w in np.concatenate([[0.0], mids]):
        Z = K - w * w * M + 1j * w * C
        exact = np.linalg.inv(Z)
        approx = (X / (1j * w - poles)) @ Y
        scale = float(np.max(np.abs(exact)))
        kappa = np.linalg.norm(Z, 1) * np.linalg.norm(exact, 1)
        err = float(np.max(np.abs(approx - exact))) / scale
        if not err <= STATE_TOL + 16.0 * np.finfo(float).eps * kappa:
            return None
        error = max(error, err)
    return poles, X, Y, error


def _singular(stiffness) -> bool:
    """True when ``stiffness`` (shape (n, n), N/m) is singular to rounding:
    a rigid-body mode of the structure without its contact.

    Judged on the matrix scaled to a unit diagonal (where the diagonal is
    positive), whose singular values do not depend on the units of the
    DOFs: a clamped beam of 50 elements of 0.2 mm in SI units (translations
    and rotations: entries from EI/L³ to EI L) has singular values down to
    8e-13 of its largest, and was taken for a free-floating structure
    (stop 35); scaled, 3e-8. A rigid-body mode stays one when scaled."""
    k = np.asarray(stiffness, dtype=float)
    diag = np.diag(k)
    if k.ndim == 2 and diag.size and np.all(diag > 0.0):
        d = 1.0 / np.sqrt(diag)
        k = k * d[:, None] * d[None, :]
    sv = np.linalg.svd(k, compute_uv=False)
    return not sv[-1] > 1e-12 * max(float(sv[0]), 1e-300)


def _symmetric(matrices) -> bool:
    for a in matrices:
        a = np.asarray(a, dtype=float)
        if np.max(np.abs(a - a.T)) > 1e-12 * max(float(np.max(np.abs(a))), 1e-300):
            return False
    return True


#: the static receptance of several contact coordinates is used as it is
#: while its rounding level (:func:`static_rounding`) stays below this
#: fraction of the largest load term; above it the contacts' stiffnesses
#: are moved into the structure (:func:`coordinate_shift` with
#: ``soft=True``). A 6-DOF chain held by a soft spring ``s`` (relative to
#: its others) and a 2D element, with a static load: rounding level / load
#: 2.5e-12, 2.5e-8, 2.5e-4, 2.5 at s = 1e-3, 1e-5, 1e-7, 1e-9, and the
#: condensed solution's relative error against the full solve 8e-12,
#: 6e-8, 4e-4, 4.8 (stop 34; the corrector accepts a residual at the
#: rounding level as converged, so the answer was quietly wrong)
STATIC_ROUNDING = 1e-11


def static_rounding(contacts, stiffness, load, shift=None, forces=None) -> float:
    """Rounding level (N) of the condensed residual's static (harmonic 0)
    linear part on several contact coordinates, ``eps κ(G₀) max_a Σ_b
    |D₀,ab| |p_b|`` with ``G₀ = B K⁻¹ Bᵀ``, ``D₀ = G₀⁻¹`` and ``p = B K⁻¹
    P₀`` the static response of the coordinates to the constant load
    ``load`` (shape (n_dof,), N): the kernel's
    :func:`~hbmfric.kernels.residuals.condensed._rounding_level` at ``q =
    0``, in plain NumPy. ``shift``: with ``K + Bᵀ K_s B``. ``forces``
    (N, shape (n_c,)): contact forces at rest (a 2D element's preload on
    its normal coordinate), whose static response ``G₀ f`` adds to ``p``
    (``q - p = -G f`` at a solution). inf when ``K`` (shifted) is
    singular."""
    K = np.asarray(stiffness, dtype=float)
    B = selection_matrix(contacts, K.shape[0])
    if shift is not None and np.any(shift):
        K = K + B.T @ (np.asarray(shift, dtype=float)[:, None] * B)
    try:
        sol = np.linalg.solve(K, np.column_stack([B.T, load]))
        G = B @ sol[:, :-1]
        p = B @ sol[:, -1]
        D = np.linalg.inv(G)
    except np.linalg.LinAlgError:
        return math.inf
    e = np.abs(p)
    if forces is not None:
        e = e + np.abs(G @ np.asarray(forces, dtype=float))
    kappa = np.linalg.norm(G, np.inf) * np.linalg.norm(D, np.inf)
    level = np.finfo(float).eps * kappa * float(np.max(np.abs(D) @ e))
    return level if np.isfinite(level) else math.inf


def coordinate_shift(contacts, stiffness, soft: bool = False) -> np.ndarray | None:
    """Stiffnesses ``K_s`` (N/m, shape (n_c,)) added to the structure on
    its contact coordinates, ``K + Bᵀ K_s B``, when ``stiffness`` is
    singular and a 2D element is among several ``contacts``; zeros when
    ``K`` is regular; None when no shift applies (no 2D element) or the
    shifted stiffness stays singular.

    A structure held by its 2D elements (the lap joint's Contact2D variant:
    the beams' axial rigid-body modes) has no static receptance, and a 2D
    element solves the mean (its preload). The shift moves the elements'
    stiffnesses (tangential and normal) into the linear structure, whose
    receptance then exists at harmonic 0, and out of the contact force
    (``f - K_s q``): the same equations. Each 1D contact's coordinate is
    shifted by its stuck stiffness too.

    ``soft=True``: the shift of a regular ``K`` whose static receptance
    rounds too coarsely (:data:`STATIC_ROUNDING`; a structure held by a
    soft spring), for any laws on several coordinates; None when the
    shifted stiffness is no better (the contacts carry no stiffness)."""
    if not soft and not _singular(stiffness):
        return np.zeros(len(coordinate_rows(contacts)))
    if _single(contacts) or (
        not soft and not any(isinstance(c[0], Contact2D) for c in contacts)
    ):
        return None
    shift = []
    for c, d, _, _ in coordinate_rows(contacts):
        law = contacts[c][0]
        if isinstance(law, Contact2D):
            shift.append(law.normal_stiffness if d else law.tangential_stiffness)
        else:
            shift.append(float(getattr(law, "stuck_stiffness", 0.0)))
    shift = np.array(shift, dtype=float)
    B = selection_matrix(contacts, np.asarray(stiffness).shape[0])
    if not np.any(shift) or _singular(stiffness + B.T @ (shift[:, None] * B)):
        return None
    return shift


def receptance_matrices(contacts, matrices, shift) -> tuple:
    """``(M, C, K + Bᵀ K_s B)``: the structure whose receptance a problem
    condensed onto ``contacts`` uses (:func:`coordinate_shift`)."""
    M, C, K = (np.asarray(a, dtype=float) for a in matrices)
    if shift is None or not np.any(shift):
        return M, C, K
    B = selection_matrix(contacts, K.shape[0])
    return M, C, K + B.T @ (shift[:, None] * B)


#: bytes of the stacked dynamic stiffness matrices ``Z(ω)`` a direct
#: recovery or receptance holds at once (:func:`direct_solves`)
DIRECT_CHUNK_BYTES = 1 << 25


def direct_solves(matrices, omega, rhs) -> np.ndarray:
    """``Z(ω_i)⁻¹ rhs_i`` with ``Z(ω) = K - ω² M + iω C`` for pulsations
    ``omega`` (rad/s, shape (m,)) and right-hand sides ``rhs`` (shape (m,
    n_dof, r)), complex, shape (m, n_dof, r).

    The pulsations are solved in chunks whose stacked ``Z`` (``16 n_dof²``
    bytes each) stay under :data:`DIRECT_CHUNK_BYTES`. Stacked over every
    point at once (before stop 34) the recovery of a condensed branch with
    direct receptances held ``n_points × n_dof²`` complex terms, twice
    (the solve copies them): 472 MB for 500 points of a 200-DOF chain, 32
    GB for 2000 points of 1000 DOFs, which the memory guard
    (:mod:`hbmfric._memory`, condensed unknowns only) did not count: the
    process killed after the whole trace."""
    M, C, K = matrices
    omega = np.asarray(omega, dtype=float)
    n = K.shape[0]
    out = np.empty(np.shape(rhs), dtype=complex)
    step = max(1, int(DIRECT_CHUNK_BYTES // (16 * n * n)))
    for a in range(0, omega.size, step):
        w = omega[a : a + step, None, None]
        Z = K - w**2 * M + 1j * w * C
        out[a : a + step] = np.linalg.solve(Z, rhs[a : a + step])
    return out


class CondensedHBMProblem(HBMProblem):
    """HBM with the unknowns at the contact DOF only.

    Same parameters and interface as :class:`~hbmfric.hbm.HBMProblem`
    (``n_unknowns``, ``kernel_problem``, ``residual``, ``linear_response``,
    ``amplitude_scale``, ``initial_guesses``); the unknowns are the
    ``n_coef`` coefficients of the contact DOF. The linear DOFs are
    eliminated per harmonic through the dynamic receptance at the contact;
    :meth:`full_coefficients` recovers every DOF.

    Several contacts (or one between two DOFs): the unknowns are the
    ``n_c * n_coef`` coefficients of the contact coordinates ``q = B x``
    (:func:`selection_matrix`), coordinate by coordinate, in the order of
    ``system.contacts``; the residual uses the receptance matrix
    ``B Z(kΩ)⁻¹ Bᵀ`` per harmonic (:mod:`hbmfric.kernels.residuals.condensed`).
    ``problem.system`` is then a view of the system in coordinates
    (``n_dof`` the number of coordinates, ``contact_dof`` 0: the
    continuation's accuracy rules watch the first coordinate; its curve
    rule draws the contact DOF recovered from the coordinates with modal
    sums or complex modes, the first coordinate with direct solves);
    ``problem.structure`` is the system itself.

    Parameters
    ----------
    system, force, harmonics, n_time, symmetry, aft, subharmonic
        As :class:`~hbmfric.hbm.HBMProblem` (a rigid :class:`~hbmfric.Coulomb`
        contact is solved by DLFT on the condensed residual).
    receptance : {"auto", "modal", "state", "direct"}
        ``"modal"``: modal superposition with all modes (exact for
        classical damping, the fast path); ``"state"`` (several contacts):
        the complex modes of the first-order form (any damping,
        :func:`state_space_modes`, ``O(n_states n_c²)`` per harmonic, no
        factorisation); ``"direct"``: a complex solve of ``K - ω² M + iω
        C`` per harmonic and residual evaluation (any damping); ``"auto"``:
        modal when the damping is classical, else complex modes for
        several contacts when they pass their check, else direct.
    """

    condensed = True

    def __init__(
        self,
        system,
        force: float,
        harmonics: int = 15,
        n_time: int | None = None,
        symmetry: bool | None = None,
        aft: str = "auto",
        receptance: str = "auto",
        subharmonic: int = 1,
        _checked=None,
    ) -> None:
        super().__init__(
            system,
            force,
            harmonics,
            n_time,
            symmetry,
            aft,
            subharmonic=subharmonic,
            _checked=_checked,
        )
        if system.contact is None:
            raise ValueError("condensation needs a contact law on the system")
        self.multi = not _single(self._contacts)
        if self.multi:
            why = _coordinate_problem(self._contacts, self.n_dof)
            if why is not None:
                raise ValueError(f"{why}; use condense=False for this system")
        if receptance not in RECEPTANCE_METHODS:
            raise ValueError(
                f"receptance must be one of {RECEPTANCE_METHODS}, got {receptance!r}"
            )
        if not _symmetric(system.matrices()):
            raise ValueError(
                "condensation needs symmetric mass, damping and stiffness "
                "matrices; use condense=False for this system"
            )
        n_c = len(coordinate_rows(self._contacts)) if self.multi else 1
        shift = np.zeros(n_c)
        if self.harmonic_numbers[0] == 0 and _singular(self._matrices[2]):
            shift = coordinate_shift(self._contacts, self._matrices[2])
            if shift is None:
                raise ValueError(
                    "condensation needs a regular stiffness matrix when harmonic "
                    "0 is solved (the structure without its contact has a "
                    "rigid-body mode, so no static receptance; with a 2D "
                    "element, also once the contacts' stiffnesses are added); "
                    "use condense=False for this system"
                )
        elif self.harmonic_numbers[0] == 0 and self.multi:
            shift = self._soft_shift(shift)
        #: stiffnesses (N/m) per contact coordinate moved from the contact
        #: forces into the linear structure (:func:`coordinate_shift`;
        #: zeros unless ``K`` is singular with a 2D element, or its static
        #: receptance rounds too coarsely: :meth:`_soft_shift`)
        self.shift = shift
        #: (M, C, K + Bᵀ K_s B): the structure of the receptance
        self._receptance_matrices = receptance_matrices(
            self._contacts, self._matrices, shift
        )
        shifted = bool(np.any(shift))
        modal = _modal_damping_of(*self._receptance_matrices) if shifted else None
        if not shifted:
            modal = modal_damping(system)
        #: (ω_r, Φ, c_r) of the structure without contacts (classical
        #: damping; shifted, :attr:`shift`), whatever the receptance:
        #: :meth:`pole_distance`
        self._free_modes = modal
        if receptance == "modal" and modal is None:
            why = (
                " (here the contacts' stiffnesses are moved into a structure "
                "held by its contacts or by a soft spring, which breaks its "
                "classical damping: CondensedHBMProblem.shift)"
                if shifted
                else ""
            )
            raise ValueError(
                "receptance='modal' needs classical (modal or Rayleigh) damping and "
                f"no rigid-body mode{why}; use condense='direct' (or 'state') in "
                "hf.frf (receptance='direct' or 'state' here)"
            )
        state = None
        if receptance == "state" or (
            receptance == "auto" and modal is None and self.multi
        ):
            if not self.multi:
                raise ValueError(
                    "receptance='state' is for several contacts (or one between "
                    "two DOFs); use condense='direct' in hf.frf "
                    "(receptance='direct' here)"
                )
            state = state_space_modes(*self._receptance_matrices)
            if state is None and receptance == "state":
                raise ValueError(
                    "the complex modes do not reproduce the direct receptance "
                    f"to {STATE_TOL:g} (defective or nearly repeated modes, or "
                    "a rigid-body mode); use condense='direct' in hf.frf "
                    "(receptance='direct' here)"
                )
            receptance = "direct" if state is None else "state"
        if receptance == "auto":
            receptance = "direct" if modal is None else "modal"

        #: "modal", "state" or "direct"; "auto" chose "direct" for several
        #: contacts only when the complex modes failed their check
        self.receptance_method = receptance
        self._state = state
        self.contact_dof = int(system.contact_dof)
        self._modal = modal if receptance == "modal" else None
        self.shapes = None if self._modal is None else np.ascontiguousarray(modal[1])
        self.structure = system
        self.n_coordinates = len(coordinate_rows(self._contacts)) if self.multi else 1
        #: a 2D element among the contacts: its two coordinates are coupled
        #: in the contact Jacobian, which the corrector's harmonic-block
        #: preconditioner does not model (it corrects 1D slipping
        #: coordinates): such a problem factors every iteration
        self.has_contact2d = any(isinstance(c[0], Contact2D) for c in self._contacts)
        self.selection = selection_matrix(self._contacts, self.n_dof)
        if self.multi:
            self.system = _CoordinateView(system, self.n_coordinates)
        self._condense()

    def _soft_shift(self, zeros: np.ndarray) -> np.ndarray:
        """The shift of a structure whose static receptance on the contact
        coordinates rounds above :data:`STATIC_ROUNDING` of the load
        (:func:`static_rounding`: a soft spring holding it, the static load
        driving a nearly rigid mode), when the shifted one rounds less;
        ``zeros`` otherwise (an :class:`~hbmfric.errors.AccuracyWarning`
        when the level is beyond ``1e-8`` of the load: the condensed
        solution is then only as good as it)."""
        K = self._matrices[2]
        scale = float(np.max(np.abs(self.load)))
        if not scale > 0.0:
            return zeros
        static = self.load.reshape(self.n_dof, self.n_coef)[:, 0]
        rest = np.array(
            [
                max(self._contacts[c][0].preload, 0.0)
                if d == 1 and isinstance(self._contacts[c][0], Contact2D)
                else 0.0
                for c, d, _, _ in coordinate_rows(self._contacts)
            ]
        )
        scale = max(scale, float(np.max(rest)))
        level = static_rounding(self._contacts, K, static, forces=rest)
        if level <= STATIC_ROUNDING * scale:
            return zeros
        shift = coordinate_shift(self._contacts, K, soft=True)
        if shift is not None:
            shifted = static_rounding(self._contacts, K, static, shift, rest)
            if shifted < level:
                return shift
        if level > 1e-8 * scale:
            import warnings

            from .errors import AccuracyWarning

            warnings.warn(
                "the static receptance of the contact coordinates rounds at "
                f"{level:.2g} N against loads of {scale:.2g} N (a structure "
                "held by a soft spring) and the contacts' stiffnesses cannot "
                "regularise it: the condensed solution is only that "
                "accurate; use condense=False",
                AccuracyWarning,
                stacklevel=4,
            )
        return zeros

    def pole_distance(
        self, omega: float, top: int | None = None
    ) -> tuple[float, int, float]:
        """How close a harmonic of ``omega`` comes to a pole of the receptance.

        Parameters
        ----------
        omega : float
            Forcing pulsation Ω, rad/s.
        top : int, optional
            Highest harmonic to check (the top of a ladder of levels);
            default: the harmonics of this problem.

        Returns
        -------
        (float, int, float)
            The smallest ``|ω_r² - (kΩ)² + i kΩ c_r| / ω_r²`` over the
            harmonics ``k > 0`` (of the subharmonic's base pulsation) and
            the natural pulsations ``ω_r`` (rad/s) of the structure without
            its contacts, the harmonic ``k`` and ``ω_r`` where it is
            reached; ``(inf, 0, nan)`` without classical modal data (the
            receptance then comes from complex modes or direct solves of a
            non-classically damped structure).
        """
        if self._free_modes is None:
            return math.inf, 0, math.nan
        if top is None:
            k = self.harmonic_numbers[self.harmonic_numbers > 0].astype(float)
        else:
            k = np.arange(1, int(top) + 1, 2 if self.odd else 1, dtype=float)
        omega_r, _, modal_c = self._free_modes
        w = k[:, None] * float(omega) / self.subharmonic
        d = np.abs(omega_r**2 - w**2 + 1j * w * modal_c) / omega_r**2
        i, r = np.unravel_index(int(np.argmin(d)), d.shape)
        return float(d[i, r]), int(k[i]), float(omega_r[r])

    def with_harmonics(self, harmonics: int) -> CondensedHBMProblem:
        """As :meth:`HBMProblem.with_harmonics`; the modal data are shared."""
        new = super().with_harmonics(harmonics)
        new._condense()
        return new

    def _condense(self) -> None:
        """The condensed kernel problem from the full one of the current
        harmonics."""
        self.full_kernel_problem = full = self.kernel_problem
        hn = full[0]
        mass, damping, stiffness = self._receptance_matrices
        codes, rows, aft_code = full[6:9]
        # one contact to ground: its code and parameters
        law_code = int(codes[0])
        law_params = np.ascontiguousarray(rows[0])
        if self.multi:
            pairs, law_codes, law_rows = coordinate_arrays(self._contacts)
        else:
            pairs = np.zeros((0, 2), dtype=np.int64)
            law_codes = np.zeros(0, dtype=np.int64)
            law_rows = np.zeros((0, 1))
        inverse, forward, derivative = full[9:12]
        load = np.ascontiguousarray(self.load.reshape(self.n_dof, self.n_coef))
        empty = np.zeros((0, 0))
        modal = self._modal
        coordinate_shapes = np.zeros((law_codes.size, 0))
        n_c = law_codes.size
        state_parts = (
            np.zeros((n_c, 0), dtype=complex),
            np.zeros((0, n_c), dtype=complex),
            np.zeros(0, dtype=complex),
            np.zeros((0, self.n_coef), dtype=complex),
            np.zeros(0, dtype=complex),
            np.zeros(0, dtype=np.int64),
            np.zeros((n_c, n_c, 0)),
            0.0,
        )
        # Lᵀ, Rᵀ, |L|ᵀ and the row sums of |R| (complex modes only)
        magnitude_parts = (
            np.zeros((0, n_c), dtype=complex),
            np.zeros((n_c, 0), dtype=complex),
            np.zeros((0, n_c)),
            np.zeros(0),
        )
        method = MODAL if modal is not None else DIRECT
        if self._state is not None:
            poles, X, Y, _ = self._state
            B = self.selection
            left = np.ascontiguousarray(B @ X)
            right = np.ascontiguousarray(Y @ B.T)
            state_parts = (
                left,
                right,
                np.ascontiguousarray(poles),
                np.ascontiguousarray(Y @ load),
                np.ascontiguousarray(X[self.contact_dof]),
                *self._series_parts(B @ X, Y @ B.T, poles),
            )
            magnitude_parts = state_magnitudes(left, right)
            method = STATE
        if modal is not None:
            omega, shapes, modal_c = modal
            if self.multi:
                coordinate_shapes = np.ascontiguousarray(self.selection @ shapes)
            modal_parts = (
                np.ascontiguousarray(shapes[self.contact_dof]),
                np.ascontiguousarray(omega**2),
                np.ascontiguousarray(modal_c),
                np.ascontiguousarray(shapes.T @ load),
            )
            direct_parts = (empty, empty, empty, empty)
        elif method == STATE:
            modal_parts = (np.zeros(0), np.zeros(0), np.zeros(0), empty)
            direct_parts = (empty, empty, empty, empty)
        else:
            modal_parts = (np.zeros(0), np.zeros(0), np.zeros(0), empty)
            direct_parts = (mass, damping, stiffness, load)
        # a rigid Coulomb contact gets its own type (its residual alone
        # compiles the DLFT kernels), contacts of one AFT family that
        # family's type (its residual compiles that AFT alone), one contact
        # to ground of such a family its one-contact type (its kernels do
        # not compile the several-contact path)
        if law_code == COULOMB:
            kind = CondensedCoulombProblem
        else:
            family = aft_family(codes, aft_code)
            if self.multi:
                kind = CONDENSED_FAMILY_TYPES.get(family, CondensedProblem)
            else:
                kind = CONDENSED_SINGLE_TYPES.get(family, CondensedProblem)
        self.kernel_problem = kind(
            hn,
            *modal_parts,
            np.int64(law_code),
            law_params,
            np.int64(AFT_EVENTS if aft_code == AFT_EVENTS else AFT_SAMPLES),
            inverse,
            forward,
            derivative,
            np.int64(method),
            np.int64(self.contact_dof),
            *direct_parts,
            float(mass[self.contact_dof, self.contact_dof]),
            pairs,
            law_codes,
            np.ascontiguousarray(law_rows),
            coordinate_shapes,
            *state_parts,
            # the curve rule draws the contact DOF, recovered (not for the
            # direct receptance: it watches coordinate 0 there)
            np.int64(self.contact_dof if self.multi else -1),
            self._drawn_cache(n_c),
            np.zeros(1),
            solver_arrays(
                self.n_coordinates * self.n_coef,
                self.multi and not self.has_contact2d,
                self.n_coordinates,
                self.n_coef,
                int(hn.size > 0 and hn[0] == 0),
            ),
            self._kept_inverse(n_c, method),
            np.ascontiguousarray(self.shift if self.multi else np.zeros(0)),
            *magnitude_parts,
        )
        self.n_unknowns = self.n_coordinates * self.n_coef

    def plan_band(self, omega_high: float) -> None:
        """Plan the complex-mode receptance for fundamentals up to
        ``omega_high`` (rad/s): the poles far above ``H × omega_high`` are
        summed once as a series (:mod:`hbmfric.state_series`). Kept by
        :meth:`with_harmonics`. The residual stays exact to rounding at any
        Ω: above the planned band the kernel sums every pole. No effect
        without complex modes."""
        self._omega_high = float(omega_high)
        if self._state is None:
            return
        kp = self.kernel_problem
        low, series, split = self._series_parts(
            kp.state_left, kp.state_right, kp.state_poles
        )
        self.kernel_problem = kp._replace(
            state_low=low,
            state_series=series,
            state_split=split,
            drawn_cache=self._drawn_cache(kp.law_codes.size),
            kept_inverse=self._kept_inverse(kp.law_codes.size, int(kp.method)),
        )

    def _drawn_cache(self, n_c: int) -> np.ndarray:
        """Empty cache of the drawn output (``drawn_cache`` of the kernel
        problem)."""
        m = n_c * self.n_coef + 1
        return np.zeros((2, 3 * m + 9 + self.n_coef if self.multi else 0))

    def _kept_inverse(self, n_c: int, method: int) -> np.ndarray:
        """Empty store of the inverse receptance per harmonic
        (``kept_inverse`` of the kernel problem): complex modes on several
        coordinates only."""
        if not (self.multi and method == STATE):
            return np.zeros((0, 0, 0), dtype=np.complex128)
        store = np.zeros((self.harmonic_numbers.size + 1, n_c, n_c), dtype=complex)
        store[-1, 0, 0] = np.nan
        return store

    def _series_parts(self, left, right, poles):
        """``(state_low, state_series, state_split)`` for the planned band
        (every pole summed when none is planned)."""
        n_c = left.shape[0]
        omega_high = getattr(self, "_omega_high", None)
        if omega_high is None:
            return np.zeros(0, dtype=np.int64), np.zeros((n_c, n_c, 0)), 0.0
        w_max = SERIES_MARGIN * omega_high * float(np.max(self.harmonic_numbers))
        return plan_state_series(poles, left, right, w_max)

    # ------------------------------------------------------------------
    def residual(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
        """Condensed residual (N) and Jacobian at ``y = [X_c, Ω]``."""
        y = np.ascontiguousarray(y, dtype=np.float64)
        R = np.empty(self.n_unknowns)
        J = np.empty((self.n_unknowns, self.n_unknowns + 1))
        state = condensed_residual(y, self.kernel_problem, R, J)
        return R, J, int(state)

    def rounding_level(self) -> float:
        """Rounding level (N) of the last residual evaluated: on several
        contact coordinates that of ``D = G⁻¹`` (the condition number of
        the receptance matrix times eps times the terms ``|D| |q - p|``,
        :func:`hbmfric.kernels.residuals.condensed._rounding_level`), which the
        corrector accepts as converged; 0 for one contact to ground."""
        return float(self.kernel_problem.rounding[0])

    def _complex_load(self) -> np.ndarray:
        """Complex load ``P̂_k`` per harmonic, shape (n_harmonics, n_dof)."""
        load = self.load.reshape(self.n_dof, self.n_coef)
        cols = coefficient_columns(self.harmonic_numbers)
        out = np.empty((self.harmonic_numbers.size, self.n_dof), dtype=complex)
        for h, k in enumerate(self.harmonic_numbers):
            c = cols[int(k)]
            out[h] = load[:, c] if k == 0 else load[:, c] - 1j * load[:, c + 1]
        return out

    def _direct_response(self, omega: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        """``Z(ω)⁻¹ rhs`` for pulsations ``omega`` (shape (m,)) and right-hand
        sides ``rhs`` (shape (m, n_dof) or (m, n_dof, r)), complex, shaped
        as ``rhs``; solved in chunks of pulsations (:func:`direct_solves`)."""
        rhs = np.asarray(rhs)
        if rhs.ndim == 2:
            return direct_solves(self._receptance_matrices, omega, rhs[..., None])[
                ..., 0
            ]
        return direct_solves(self._receptance_matrices, omega, rhs)

    def receptance(self, omega) -> tuple[np.ndarray, np.ndarray]:
        """Contact receptance ``G_cc(ω)`` (m/N) and the contact response to
        the harmonic load (complex amplitude, m), at pulsation(s) ``omega``
        of that harmonic."""
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        forced = list(self.harmonic_numbers).index(self.subharmonic)
        load = self._complex_load()[forced]
        if self.receptance_method == "modal":
            p = self.kernel_problem
            q = load @ self.shapes
            d = p.omega_squared - w[:, None] ** 2 + 1j * w[:, None] * p.modal_damping
            g = np.sum(p.contact_shapes**2 / d, axis=1)
            x = np.sum(p.contact_shapes * q / d, axis=1)
            return g, x
        unit = np.zeros((w.size, self.n_dof))
        unit[:, self.contact_dof] = 1.0
        rhs = np.broadcast_to(load, (w.size, self.n_dof))
        g = self._direct_response(w, unit)[:, self.contact_dof]
        x = self._direct_response(w, rhs)[:, self.contact_dof]
        return g, x

    def coordinate_receptance(self, omega, harmonic: int | None = None):
        """Receptance matrix ``G = B Z(ω)⁻¹ Bᵀ`` of the contact coordinates
        (m/N, complex, shape (m, n_c, n_c)) and their response ``B Z(ω)⁻¹
        P̂`` to the load of ``harmonic`` (default the forced one; complex,
        m, shape (m, n_c)), at the pulsations ``omega`` (shape (m,), rad/s).
        Plain NumPy, independent of the kernels."""
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        h = self.subharmonic if harmonic is None else int(harmonic)
        load = self._complex_load()[list(self.harmonic_numbers).index(h)]
        B = self.selection
        if self.receptance_method == "modal":
            omega_r, shapes, modal_c = self._modal
            psi = B @ shapes
            d = omega_r**2 - w[:, None] ** 2 + 1j * w[:, None] * modal_c
            G = (psi[None, :, :] / d[:, None, :]) @ psi.T
            x = (psi[None, :, :] / d[:, None, :]) @ (shapes.T @ load)
            return G, x
        rhs = np.concatenate([B.T, load[:, None]], axis=1)
        sol = B @ self._direct_response(w, np.broadcast_to(rhs, (w.size,) + rhs.shape))
        return sol[:, :, :-1], sol[:, :, -1]

    def linear_response(self, omega, contact: str = "stuck") -> np.ndarray:
        """Response of the contact DOF (several contacts: of the contact
        coordinates) of the linearised system at the forced harmonic (see
        :meth:`HBMProblem.linear_response`), shape (n_unknowns,) or
        (n_omega, n_unknowns); a stuck rigid Coulomb contact holds it at
        0."""
        w = self.subharmonic * np.atleast_1d(np.asarray(omega, dtype=float))
        if self.multi:
            return self._coordinate_linear_response(omega, w, contact)
        with np.errstate(divide="ignore", invalid="ignore"):
            # an undamped structure exactly at a natural pulsation (of the
            # free or the stuck structure) divides by zero
            g, x = self.receptance(w)
            law = self.system.contact
            if contact == "stuck":
                if law.code == COULOMB:
                    x = np.zeros_like(x)
                else:
                    x = x / (1.0 + law.stuck_stiffness * g)
        # zero where the linearisation is singular, as
        # :func:`~hbmfric.kernels.linalg.linear_response.first_harmonic_response`
        x = np.where(np.isfinite(x), x, 0.0)
        col = coefficient_columns(self.harmonic_numbers)[self.subharmonic]
        X = np.zeros((x.size, self.n_coef))
        X[:, col] = x.real
        X[:, col + 1] = -x.imag
        return X[0] if np.ndim(omega) == 0 else X

    def _coordinate_linear_response(self, omega, w, contact: str) -> np.ndarray:
        """:meth:`linear_response` on the contact coordinates: ``q = p``
        free, ``q = (I + G K_s)⁻¹ p`` stuck (``K_s`` the stuck stiffnesses of
        the laws)."""

        def solve(w):
            with np.errstate(divide="ignore", invalid="ignore"):
                G, x = self.coordinate_receptance(w)
                if contact == "stuck":
                    ks = np.array(
                        [
                            _stuck_stiffnesses(self._contacts[c][0])[d]
                            for c, d, _, _ in coordinate_rows(self._contacts)
                        ]
                    )
                    ks = ks - self.shift  # the shift is in G already
                    eye = np.eye(self.n_coordinates)
                    A = eye + G * ks[None, None, :]
                    x = np.linalg.solve(A, x[..., None])[..., 0]
            return x

        try:
            x = solve(w)
        except np.linalg.LinAlgError:
            # an undamped structure exactly at a natural pulsation: zero
            # there, as the full kernel, the other pulsations solved
            x = np.zeros((w.size, self.n_coordinates), dtype=complex)
            for i in range(w.size):
                try:
                    x[i] = solve(w[i : i + 1])[0]
                except np.linalg.LinAlgError:
                    pass
        x = np.where(np.isfinite(x), x, 0.0)
        col = coefficient_columns(self.harmonic_numbers)[self.subharmonic]
        X = np.zeros((w.size, self.n_coordinates, self.n_coef))
        X[:, :, col] = x.real
        X[:, :, col + 1] = -x.imag
        X = X.reshape(w.size, -1)
        return X[0] if np.ndim(omega) == 0 else X

    def _add_static(self, y: np.ndarray, static: np.ndarray) -> None:
        """Starting points (:meth:`~hbmfric.hbm.HBMProblem.initial_guesses`,
        rigid-contact presolve included) carry the static solution at the
        contact DOF (the contact coordinates) only."""
        if self.multi:
            y[: self.n_unknowns : self.n_coef] += self.selection @ static
            return
        y[0] += float(static[self.contact_dof])

    def contact_forces(self, points: np.ndarray) -> np.ndarray:
        """Contact-force coefficients (N) at condensed solutions ``points``
        (shape (n_points, n_unknowns + 1)), shape (n_points, n_coef);
        several contacts: shape (n_points, n_c, n_coef), the force ``f_a``
        on each contact coordinate (``+f_a`` on its DOF, ``-f_a`` on its
        other; a 2D element's tangential and normal forces on its two)."""
        points = np.ascontiguousarray(np.atleast_2d(points), dtype=np.float64)
        F = self._shifted_forces(points)
        if self.multi:
            F = F.reshape(points.shape[0], self.n_coordinates, self.n_coef)
            q = points[:, : self.n_unknowns].reshape(F.shape)
            return F + self.shift[None, :, None] * q
        return F

    def _shifted_forces(self, points: np.ndarray) -> np.ndarray:
        """The kernel's contact forces ``f - K_s q`` (:attr:`shift`), shape
        (n_points, n_unknowns)."""
        F = np.empty((points.shape[0], self.n_unknowns))
        condensed_contact_forces(points, self.kernel_problem, F)
        return F

    def full_coefficients(self, points: np.ndarray) -> np.ndarray:
        """Coefficients of every DOF at condensed solutions:
        ``x̂_k = Z(kΩ)⁻¹ (P̂_k - e_c F̂_k)`` with ``F`` the AFT contact force.

        Parameters
        ----------
        points : ndarray, shape (n_points, n_coef + 1)
            ``[X_c, Ω]`` per point.

        Returns
        -------
        ndarray, shape (n_points, n_dof, n_coef), m
        """
        points = np.ascontiguousarray(np.atleast_2d(points), dtype=np.float64)
        if self.multi:
            # the receptance's structure carries the shift: its forces too
            F = self._shifted_forces(points)
            F = F.reshape(points.shape[0], self.n_coordinates, self.n_coef)
            return self._coordinate_recover(points, F)
        F = self.contact_forces(points)
        out = np.empty((points.shape[0], self.n_dof, self.n_coef))
        if self.receptance_method == "modal":
            condensed_modal_recover(points, F, self.kernel_problem, self.shapes, out)
            return out
        omega = points[:, -1]
        loads = self._complex_load()
        cols = coefficient_columns(self.harmonic_numbers)
        for h, k in enumerate(self.harmonic_numbers):
            c = cols[int(k)]
            f = F[:, c] if k == 0 else F[:, c] - 1j * F[:, c + 1]
            rhs = np.broadcast_to(loads[h], (omega.size, self.n_dof)).copy()
            rhs[:, self.contact_dof] -= f
            x = self._direct_response(k * omega, rhs)
            out[:, :, c] = x.real
            if k != 0:
                out[:, :, c + 1] = -x.imag
        return out

    def _coordinate_recover(self, points: np.ndarray, F: np.ndarray) -> np.ndarray:
        """:meth:`full_coefficients` for several contacts:
        ``x̂_k = Z(kΩ)⁻¹ (P̂_k - Bᵀ f̂_k)`` per harmonic, by modal sums,
        complex modes or direct solves (plain NumPy); ``F`` of shape
        (n_points, n_c, n_coef)."""
        omega = points[:, -1]
        loads = self._complex_load()
        cols = coefficient_columns(self.harmonic_numbers)
        out = np.empty((points.shape[0], self.n_dof, self.n_coef))
        B = self.selection
        for h, k in enumerate(self.harmonic_numbers):
            c = cols[int(k)]
            f = F[:, :, c] if k == 0 else F[:, :, c] - 1j * F[:, :, c + 1]
            rhs = loads[h][None, :] - f @ B
            w = k * omega
            if self.receptance_method == "modal":
                omega_r, shapes, modal_c = self._modal
                d = omega_r**2 - w[:, None] ** 2 + 1j * w[:, None] * modal_c
                x = ((rhs @ shapes) / d) @ shapes.T
            elif self.receptance_method == "state":
                poles, X, Y, _ = self._state
                x = ((rhs @ Y.T) / (1j * w[:, None] - poles)) @ X.T
            else:
                x = self._direct_response(w, rhs)
            out[:, :, c] = x.real
            if k != 0:
                out[:, :, c + 1] = -x.imag
        return out

    def unknowns_from_full(self, X: np.ndarray) -> np.ndarray:
        """The unknowns (contact-DOF coefficients; several contacts: the
        coordinates ``B X``, flat) of full coefficients ``X`` of shape
        (n_dof, n_coef)."""
        if self.multi:
            q = self.selection @ np.asarray(X, dtype=np.float64)
            return np.ascontiguousarray(q.reshape(-1))
        return np.ascontiguousarray(X[self.contact_dof], dtype=np.float64)


class _CoordinateView:
    """The system as the continuation of a problem condensed onto several
    contact coordinates sees it: every attribute of the system, except
    ``n_dof`` (the number of coordinates, the blocks of the unknowns),
    ``contact_dof`` = 0 (the first coordinate, the one the accuracy rules
    watch; the curve rule draws the recovered contact DOF, see
    :class:`CondensedHBMProblem`) and no ``output_weights`` (they weigh
    DOFs, not coordinates)."""

    contact_dof = 0
    output_weights = None

    def __init__(self, system, n_coordinates: int) -> None:
        self._system = system
        self.n_dof = int(n_coordinates)

    def __getattr__(self, name):
        if name.startswith("__") or name == "_system":
            # not set yet (copy, pickle): no recursion through the view
            raise AttributeError(name)
        return getattr(self._system, name)

    def __repr__(self) -> str:
        return f"contact coordinates of {self._system!r}"
