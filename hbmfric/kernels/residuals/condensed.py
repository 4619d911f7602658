"""Harmonic balance condensed onto the contact DOF.

Only the contact is nonlinear, so the linear DOFs are eliminated harmonic by
harmonic. With the modes of the structure (``K φ_r = ω_r² M φ_r``,
mass-normalised, classical damping ``φ_rᵀ C φ_s = c_r δ_rs``) and all modes
kept, the dynamic receptance at pulsation ``ω`` is exact:

    G_ij(ω) = Σ_r φ_ir φ_jr / d_r(ω),   d_r(ω) = ω_r² - ω² + i ω c_r.

Complex amplitudes follow ``x(t) = Re(x̂ e^{iωt})``, i.e. ``x̂ = Xc - i Xs``
for the real coefficients ``[Xc, Xs]`` of one harmonic. For harmonic ``k``
(``ω = kΩ``), with ``g = G_cc(ω)`` the receptance at the contact DOF ``c``
and ``p = Σ_r φ_cr q̂_r / d_r`` the response of the contact DOF to the
external load (modal load ``q̂_r = φ_rᵀ P̂_k``), the contact DOF obeys
``x̂ = p - g F̂``: the condensed residual, in the dynamic-stiffness form

    r̂_k = (x̂_k - p_k) / g_k + F̂_k,       R_c = Re r̂,  R_s = -Im r̂,

is the Schur complement of the full HBM residual on the contact row (units
N, so tolerances mean the same as for the full problem). ``dR/dΩ`` is
analytic: ``d(1/g)/dΩ = -k g'/g²``, ``d(1/d_r)/dω = (2ω - i c_r)/d_r²``.
The mean (harmonic 0, when present) uses ``ω = 0``.

Two ways to evaluate ``g`` and ``p`` (``method``):

``MODAL``
    the modal sums above (all modes: exact for classical damping);
``DIRECT``
    a direct solve per harmonic, for any damping: ``Z(ω) = K - ω² M + iω C``
    (symmetric), ``z = Z⁻¹ e_c`` gives ``g = z_c``, ``x_p = Z⁻¹ P̂`` gives
    ``p = (x_p)_c``; with ``Z' = dZ/dΩ = k (-2ω M + i C)``,
    ``dg/dΩ = -zᵀ Z' z`` and ``dp/dΩ = -zᵀ Z' x_p``. The complex systems
    are solved in real form (``2 n_dof`` unknowns) by
    :func:`hbmfric.kernels.linalg.lu.solve_inplace`.

The contact force comes from the same AFT kernels as in the full residual
(:func:`_contact_force`). A rigid Coulomb contact is handled by the same DLFT
scheme as in the full residual (:func:`_coulomb`): located reversals
(:func:`hbmfric.kernels.dlft.coulomb.dlft_located`, the default), with the linear
tail (:func:`hbmfric.kernels.dlft.tail.dlft_tail`) when the law asks for it,
or the classic one (:func:`hbmfric.kernels.dlft.coulomb.dlft_contact`) for
``aft="samples"``. DLFT reads only the contact rows of the linear residual,
and the condensed residual is their Schur complement: at any point where the
eliminated rows hold (every condensed point, by construction) the force
``λ_X = -R_lin`` that the linear dynamics ask of the contact, hence the
holding force ``h = λ_X + M_cc ü`` of the located scheme, are those of the
full residual, so both paths have the same solutions. The tail needs the
receptance at the contact DOF for the harmonics beyond the balance,
``G(kΩ)`` for ``k <= K``: a modal sum (:func:`_modal_tail_receptance`) or
the direct solves of :func:`hbmfric.kernels.dlft.tail.contact_receptance`.

Several contacts (:func:`_coordinates_residual`)
-------------------------------------------------
With ``n_c`` one-dimensional contacts, contact ``a`` acting on the relative
displacement ``q_a = x_{i_a} - x_{j_a}`` (or on ``x_{i_a}`` against ground),
the unknowns are the coefficients of the contact coordinates ``q = B x``
(``B`` of shape (n_c, n_dof), entries +1 and -1), stored coordinate by
coordinate (``y[a * n_coef + j]``, the layout of the full residual). The
contact forces act on the structure as ``Bᵀ f``, so per harmonic

    q̂_k = p_k - G_k f̂_k,    G_k = B Z(kΩ)⁻¹ Bᵀ,    p_k = B Z(kΩ)⁻¹ P̂_k,

and the residual, in the dynamic-stiffness form of the single contact
(units N), is

    r̂_k = D_k (q̂_k - p_k) + f̂_k,     D_k = G_k⁻¹   (n_c x n_c, complex),

with ``dD/dΩ = -D (dG/dΩ) D``, so ``d(D (q̂ - p))/dΩ = -D (dG/dΩ D (q̂ -
p) + dp/dΩ)``: two matrix-vector products per harmonic, ``dD`` is not
formed. ``G`` is complex symmetric (``Z`` is) and
regular when ``B`` has full row rank (checked at the edge). Modal:
``G_ab = Σ_r ψ_ar ψ_br / d_r`` with ``ψ = B Φ`` (``coordinate_shapes``);
direct: one LU of ``Z`` per harmonic, ``Z_c = Z⁻¹ Bᵀ`` (``n_c`` solves),
``G = B Z_c``, ``dG/dΩ = -Z_cᵀ Z' Z_c``, ``dp/dΩ = -Z_cᵀ Z' Z⁻¹ P̂``. Every
contact's force is the AFT of its law on its own coordinate (the dispatch
of the full residual, :func:`hbmfric.kernels.residuals.hbm.contact_aft`), so
``df/dq`` is block diagonal; a 2D element (:class:`~hbmfric.Contact2D`)
has two coordinates, its tangential one (code ``CONTACT2D``) and right
after it its normal one (``CONTACT2D_NORMAL``), and its AFT
(:func:`hbmfric.kernels.aft.contact2d.aft_contact2d`) on the pair gives a
2x2 block of ``n_coef`` blocks (compiled into the general type only,
:func:`coordinate_contact2d`). Its preload acts on the mean: harmonic 0 is
solved through the static receptance ``B K⁻¹ Bᵀ``. The single contact to
ground keeps the path above (``law_codes`` empty); any other set of
contacts fills ``law_codes``.

Complex modes (``method == STATE``, any damping): with the decomposition
``Z(ω)⁻¹ = X diag(1/(iω - λ_r)) Y`` of
:func:`hbmfric.condensation.state_space_modes` (``2 n_dof`` poles), ``G =
L diag(c) R`` with ``L = B X``, ``R = Y Bᵀ``, ``c_r = 1/(ikΩ - λ_r)``: one
complex matrix product per harmonic, ``O(n_states n_c²)``, and no
factorisation (:func:`_state_coordinate_receptance`). ``dG/dΩ`` is never
formed: the Ω column needs only ``dG r̂ + dp = L (dc ⊙ (R r̂ + ρ))``
(:func:`_state_derivative`, ``O(n_states n_c)``). Its rounding scales with
the sum of the absolute terms (:func:`_state_sum_norm`).

The curve rule of the continuation draws the contact DOF recovered from the
coordinates (:func:`coordinates_drawn`; modal sums and complex modes).

The problem travels as a :class:`CondensedProblem` named tuple; the residual
dispatcher :func:`hbmfric.kernels.residuals.dispatch.residual` recognises its type.
"""

from collections import namedtuple

import numpy as np
from numba import types
from numba.extending import overload

from ..._jit import jit, jit_inline
from ..aft.contact2d import CONTACT2D, MAX_PASSES, aft_contact2d
from ..aft.schemes import GROSS_SLIP, STUCK
from ..dlft.coulomb import COULOMB, dlft_contact, dlft_located
from ..dlft.tail import contact_receptance, dlft_tail
from ..linalg.lu import lu_factor, lu_solve, solve_inplace
from ..linalg.products import matvec, symmetric_matmul
from .hbm import (
    COULOMB_TYPES,
    DAHL_FAMILY,
    JENKINS_FAMILY,
    JIT_OPTIONS,
    MASING_FAMILY,
    NOT_A_COULOMB_PROBLEM,
    NOT_COMPILED_FOR_LAW,
    _combined_state,
    contact_aft,
    is_coulomb_problem,
    problem_family,
)

#: AFT scheme codes (same values as :mod:`hbmfric.kernels.residuals.hbm`)
AFT_SAMPLES = 0
AFT_EVENTS = 1
#: receptance methods
MODAL = 0
DIRECT = 1
#: complex modes of the first-order form (several contacts only)
STATE = 2
#: status returned when a direct solve meets a singular dynamic stiffness
SINGULAR_RECEPTANCE = -100
#: code in ``law_codes`` of the normal coordinate of a 2D element
#: (:class:`~hbmfric.Contact2D`): its element is the ``CONTACT2D`` entry of
#: the coordinate just before (its tangential one), which carries the
#: parameters; the residual evaluates the element's AFT once on the pair
CONTACT2D_NORMAL = 201

CondensedProblem = namedtuple(
    "CondensedProblem",
    [
        "harmonic_numbers",  # int64 (n_harmonics,)
        "contact_shapes",  # float64 (n_modes,): φ_cr
        "omega_squared",  # float64 (n_modes,): ω_r², rad²/s²
        "modal_damping",  # float64 (n_modes,): c_r = φ_rᵀ C φ_r, 1/s
        "modal_load",  # float64 (n_modes, n_coef): Φᵀ P per coefficient, N
        "law_code",  # int64
        "law_params",  # float64 (n_params,)
        "aft_scheme",  # int64
        "inverse",  # float64 (n_time, n_coef)
        "forward",  # float64 (n_coef, n_time)
        "derivative",  # float64 (n_time, n_coef)
        "method",  # int64: MODAL or DIRECT
        "contact_dof",  # int64 (DIRECT)
        "mass",  # float64 (n_dof, n_dof) (DIRECT; (0, 0) for MODAL)
        "damping",  # float64 (n_dof, n_dof) (DIRECT)
        "stiffness",  # float64 (n_dof, n_dof) (DIRECT)
        "load",  # float64 (n_dof, n_coef): P per coefficient, N (DIRECT)
        "contact_mass",  # float64: M_cc, kg (located DLFT of a rigid Coulomb)
        # several contacts (empty arrays for the single contact to ground)
        "coordinate_pairs",  # int64 (n_c, 2): (i_a, j_a), j_a = -1 for ground
        "law_codes",  # int64 (n_c,)
        "law_rows",  # float64 (n_c, n_params): parameters per contact, padded
        "coordinate_shapes",  # float64 (n_c, n_modes): ψ = B Φ (MODAL)
        # complex modes of the first-order form (STATE; empty otherwise)
        "state_left",  # complex128 (n_c, n_states): L = B X
        "state_right",  # complex128 (n_states, n_c): R = Y Bᵀ
        "state_poles",  # complex128 (n_states,): λ_r, rad/s
        "state_load",  # complex128 (n_states, n_coef): Y P per coefficient
        "state_output",  # complex128 (n_states,): row of X at output_dof
        # the poles far above the band summed once as a series in ikΩ
        # (:func:`state_matrix`; empty series: every pole summed)
        "state_low",  # int64 (n_low,): the poles summed term by term
        "state_series",  # float64 (n_c, n_c, n_terms): M_j λ_s^j, m/N
        "state_split",  # float64: λ_s, the least |λ_r| in the series, rad/s
        # several contacts: the DOF whose first harmonic the curve rule
        # draws (recovered, :func:`coordinates_drawn`); -1: coordinate 0
        "output_dof",  # int64
        # work: the last two results of :func:`coordinates_drawn` with their
        # arguments, float64 (2, 3 m + 9 + n_coef), m = n_c n_coef + 1
        # ((2, 0) for the single contact to ground)
        "drawn_cache",
        # output, shape (1,): rounding level (N) of the last residual on
        # several coordinates (:func:`_coordinates_linear`), 0 otherwise
        "rounding",
        # work arrays kept between corrector solves (factors, pivots,
        # Krylov basis, state) of hbmfric.kernels.linalg.krylov.reuse_solve,
        # used by hbmfric.kernels.steps.newton.bordered_solve when the
        # factors have the order of the bordered matrix (n_unknowns + 1);
        # empty (order 0) for small problems
        "solver",
        # work, complex128 (n_harmonics + 1, n_c, n_c) with complex modes on
        # several coordinates, (0, 0, 0) otherwise: D_k = G_k⁻¹ of every
        # harmonic at the Ω of the last residual (:func:`_coordinates_linear`),
        # entry [n_harmonics, 0, 0] = Ω + 1j while they are valid, for the
        # recovery of the drawn DOF at the same Ω (:func:`_drawn_harmonic`)
        "kept_inverse",
        # several contacts: stiffness K_s per coordinate, N/m, float64
        # (n_c,), in the receptance's structure K + Bᵀ K_s B and taken off
        # the contact forces (f - K_s q); zeros unless K is singular
        # (hbmfric.condensation.coordinate_shift); (0,) for one contact
        "coordinate_shift",
        # constant parts of the complex modes' sums, from state_left and
        # state_right (:func:`state_magnitudes`, once per problem; empty
        # without complex modes): Lᵀ complex128 (n_states, n_c), Rᵀ
        # complex128 (n_c, n_states), |L|ᵀ float64 (n_states, n_c), the row
        # sums of |R| float64 (n_states,)
        "state_left_t",
        "state_right_t",
        "state_left_abs_t",
        "state_right_sums",
    ],
)
CondensedProblem.__doc__ = """Flat data of the condensed HBM residual (see the
module docstring); built by :class:`hbmfric.condensation.CondensedHBMProblem`."""

CondensedCoulombProblem = namedtuple(
    "CondensedCoulombProblem", CondensedProblem._fields
)
CondensedCoulombProblem.__doc__ = """A :class:`CondensedProblem` of a rigid
Coulomb contact (``law_code = COULOMB``): the same fields in their own type,
so that the DLFT kernels are compiled only into the residual of this type
(see :class:`hbmfric.kernels.residuals.hbm.CoulombProblem`)."""
COULOMB_TYPES.append(CondensedCoulombProblem)


def _family_type(name, family):
    kind = namedtuple(name, CondensedProblem._fields)
    kind.__doc__ = f"""A :class:`CondensedProblem` whose contacts are all of
the {family!r} AFT family (:func:`hbmfric.kernels.residuals.hbm.aft_family`):
the same fields in their own type, whose residual compiles that family's
AFT only (see :class:`hbmfric.kernels.residuals.hbm.JenkinsProblem`)."""
    kind.aft_family = family
    return kind


CondensedJenkinsProblem = _family_type("CondensedJenkinsProblem", JENKINS_FAMILY)
CondensedMasingProblem = _family_type("CondensedMasingProblem", MASING_FAMILY)
CondensedDahlProblem = _family_type("CondensedDahlProblem", DAHL_FAMILY)

#: problem class of each AFT family for the condensed residual
CONDENSED_FAMILY_TYPES = {
    JENKINS_FAMILY: CondensedJenkinsProblem,
    MASING_FAMILY: CondensedMasingProblem,
    DAHL_FAMILY: CondensedDahlProblem,
}


def _single_type(name, family):
    kind = namedtuple(name, CondensedProblem._fields)
    kind.__doc__ = f"""A :class:`CondensedProblem` of one contact to ground of
the {family!r} AFT family (empty ``law_codes``): the same fields in their
own type, whose residual compiles that family's AFT and the single
contact's path alone, not the several-contact one
(:func:`_coordinates_residual`); the continuation kernels take it as a
:class:`CondensedSingleChainProblem`, which solves with dense factors
only."""
    kind.aft_family = family
    return kind


CondensedSingleJenkinsProblem = _single_type(
    "CondensedSingleJenkinsProblem", JENKINS_FAMILY
)
CondensedSingleMasingProblem = _single_type(
    "CondensedSingleMasingProblem", MASING_FAMILY
)
CondensedSingleDahlProblem = _single_type("CondensedSingleDahlProblem", DAHL_FAMILY)

#: problem class of each AFT family for one condensed contact to ground
CONDENSED_SINGLE_TYPES = {
    JENKINS_FAMILY: CondensedSingleJenkinsProblem,
    MASING_FAMILY: CondensedSingleMasingProblem,
    DAHL_FAMILY: CondensedSingleDahlProblem,
}

CondensedChainProblem = namedtuple("CondensedChainProblem", CondensedProblem._fields)
CondensedChainProblem.__doc__ = """A condensed kernel problem as the
continuation kernels receive it (:func:`hbmfric.kernels.residuals.pointer.
chain_problem`): the :class:`CondensedProblem` fields in one type for every
condensed problem type but those of one contact to ground (see
:class:`hbmfric.kernels.residuals.hbm.ChainProblem`). Never passed to
:func:`condensed_residual` itself."""

CondensedSingleChainProblem = namedtuple(
    "CondensedSingleChainProblem", CondensedProblem._fields
)
CondensedSingleChainProblem.__doc__ = """A condensed kernel problem of one
contact to ground (:data:`CONDENSED_SINGLE_TYPES`) as the continuation
kernels receive it: they compile for it without the solvers and the drawn
output of several contact coordinates. Never passed to
:func:`condensed_residual` itself."""

#: the condensed problem classes of one contact to ground, whose kernels
#: do not compile the several-contact path
SINGLE_CONTACT_TYPES = (*CONDENSED_SINGLE_TYPES.values(), CondensedSingleChainProblem)

#: every condensed problem class (the residual dispatch sends them here)
CONDENSED_TYPES = (
    CondensedProblem,
    CondensedCoulombProblem,
    *CONDENSED_FAMILY_TYPES.values(),
    *SINGLE_CONTACT_TYPES,
    CondensedChainProblem,
)

#: status of the residual of a one-contact type
#: (:data:`SINGLE_CONTACT_TYPES`) whose ``law_codes`` are not empty (its
#: several-contact path is not compiled)
NOT_ONE_CONTACT = -104


def is_single_contact(problem) -> bool:
    """Is the Numba type ``problem`` a condensed problem of one contact to
    ground (:data:`SINGLE_CONTACT_TYPES`)? For compile-time dispatch."""
    return (
        isinstance(problem, types.BaseNamedTuple)
        and problem.instance_class in SINGLE_CONTACT_TYPES
    )


@jit
def _harmonic_receptance(k, omega, col, problem):
    """Receptance ``g``, load response ``p`` and their Ω-derivatives for one
    harmonic (complex; derivatives are ``d/dΩ`` at ``ω = kΩ``)."""
    phi = problem.contact_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    q = problem.modal_load
    w = k * omega
    g = 0.0j
    p = 0.0j
    dg = 0.0j
    dp = 0.0j
    for r in range(phi.size):
        if k == 0:
            qr = q[r, col] + 0.0j
        else:
            qr = q[r, col] - 1j * q[r, col + 1]
        inv_d = 1.0 / (w2[r] - w * w + 1j * w * c[r])
        # d(1/d_r)/dΩ = k (2ω - i c_r) / d_r²
        dinv = k * (2.0 * w - 1j * c[r]) * inv_d * inv_d
        g += phi[r] * phi[r] * inv_d
        dg += phi[r] * phi[r] * dinv
        p += phi[r] * qr * inv_d
        dp += phi[r] * qr * dinv
    return g, p, dg, dp


@jit
def _dynamic_stiffness(problem, w, A):
    """Real form ``[[Kd, -ωC], [ωC, Kd]]`` of ``Z(ω)`` into ``A``."""
    n = problem.mass.shape[0]
    for i in range(n):
        for j in range(n):
            kd = problem.stiffness[i, j] - w * w * problem.mass[i, j]
            wc = w * problem.damping[i, j]
            A[i, j] = kd
            A[i, n + j] = -wc
            A[n + i, j] = wc
            A[n + i, n + j] = kd


@jit
def _solve_complex(problem, w, rhs_re, rhs_im, A, b, out):
    """``out = Z(ω)⁻¹ (rhs_re + i rhs_im)``; False if singular."""
    n = rhs_re.size
    _dynamic_stiffness(problem, w, A)
    for i in range(n):
        b[i] = rhs_re[i]
        b[n + i] = rhs_im[i]
    if not solve_inplace(A, b):
        return False
    for i in range(n):
        out[i] = b[i] + 1j * b[n + i]
    return True


@jit
def _harmonic_receptance_direct(k, omega, col, problem, work):
    """As :func:`_harmonic_receptance` by direct solves; the last value is
    False when ``Z(kΩ)`` is singular."""
    n = problem.mass.shape[0]
    A, b, re, im, z, xp = work
    w = k * omega
    c = problem.contact_dof
    re[:] = 0.0
    im[:] = 0.0
    re[c] = 1.0
    if not _solve_complex(problem, w, re, im, A, b, z):
        return 0.0j, 0.0j, 0.0j, 0.0j, False
    load = problem.load
    forced = False
    for i in range(n):
        re[i] = load[i, col]
        im[i] = 0.0 if k == 0 else -load[i, col + 1]
        if re[i] != 0.0 or im[i] != 0.0:
            forced = True
    if forced:
        if not _solve_complex(problem, w, re, im, A, b, xp):
            return 0.0j, 0.0j, 0.0j, 0.0j, False
    else:
        xp[:] = 0.0
    g = z[c]
    p = xp[c]
    dg = 0.0j
    dp = 0.0j
    if k != 0:
        for i in range(n):
            zi = z[i]
            for j in range(n):
                dz = k * (-2.0 * w * problem.mass[i, j] + 1j * problem.damping[i, j])
                dg -= zi * dz * z[j]
                dp -= zi * dz * xp[j]
    return g, p, dg, dp, True


@jit
def _direct_work(problem):
    n = problem.mass.shape[0]
    return (
        np.empty((2 * n, 2 * n)),
        np.empty(2 * n),
        np.empty(n),
        np.empty(n),
        np.empty(n, dtype=np.complex128),
        np.empty(n, dtype=np.complex128),
    )


@jit
def condensed_residual(y, problem, R, J):
    """Condensed residual ``R(X_c, Ω)`` and Jacobian ``[dR/dX_c, dR/dΩ]``.

    Parameters
    ----------
    y : ndarray, shape (n_coef + 1,)
        Coefficients of the contact DOF (m), then Ω (rad/s).
    problem : CondensedProblem
    R : ndarray, shape (n_coef,)
        Output: residual, N.
    J : ndarray, shape (n_coef, n_coef + 1)
        Output: Jacobian; last column ``dR/dΩ``.

    Returns
    -------
    int
        Contact-state code of the AFT (negative on failure).
    """
    if problem.law_codes.size > 0:
        return coordinates_residual(y, problem, R, J)
    status = _condensed_linear(y, problem, R, J)
    if status < 0:
        return status
    n = problem.inverse.shape[1]
    if problem.law_code == COULOMB:
        # DLFT on the condensed linear residual: it is the Schur complement
        # of the full one on the contact rows, which is all DLFT reads
        # (compiled for a CondensedCoulombProblem only)
        return condensed_rigid_coulomb(y, problem, R, J)
    F = np.empty(n)
    dF = np.empty((n, n))
    status = _contact_force(y[:n].copy(), problem, F, dF)
    for i in range(n):
        R[i] += F[i]
        for j in range(n):
            J[i, j] += dF[i, j]
    return status


def condensed_rigid_coulomb(y, problem, R, J):
    """:func:`_coulomb` for a :class:`CondensedCoulombProblem`; for any other
    problem type it compiles to ``return NOT_A_COULOMB_PROBLEM`` (see
    :func:`hbmfric.kernels.residuals.hbm.rigid_coulomb`). Callable from jitted code
    only."""
    raise NotImplementedError("condensed_rigid_coulomb is for jit code")


def _refuse(y, problem, R, J):
    return NOT_A_COULOMB_PROBLEM


@overload(
    condensed_rigid_coulomb,
    jit_options=JIT_OPTIONS,
)
def _condensed_rigid_coulomb(y, problem, R, J):
    # the body of _coulomb itself, compiled for this type only
    return _coulomb if is_coulomb_problem(problem) else _refuse


def coulomb_contact_force(y, problem, R, R_lin, J, f):
    """DLFT force of the rigid Coulomb contact of a
    :class:`CondensedCoulombProblem` at ``y`` into ``f``: what the residual
    adds to its linear part; its status. For any other problem type it
    compiles to ``return NOT_A_COULOMB_PROBLEM`` without compiling the
    residual. Callable from jitted code only."""
    raise NotImplementedError("coulomb_contact_force is for jit code")


def _refuse_force(y, problem, R, R_lin, J, f):
    return NOT_A_COULOMB_PROBLEM


def _coulomb_force(y, problem, R, R_lin, J, f):
    # the implementation of ``coulomb_contact_force`` for a Coulomb problem
    status = condensed_residual(y, problem, R, J)
    _condensed_linear(y, problem, R_lin, J)
    for r in range(f.size):
        f[r] = R[r] - R_lin[r]
    return status


@overload(
    coulomb_contact_force,
    jit_options=JIT_OPTIONS,
)
def _coulomb_contact_force(y, problem, R, R_lin, J, f):
    return _coulomb_force if is_coulomb_problem(problem) else _refuse_force


def _coulomb(y, problem, R, J):
    """Add a rigid Coulomb contact to the condensed linear residual, by the
    DLFT scheme the full residual uses
    (:func:`hbmfric.kernels.residuals.hbm.hbm_residual`): located, with the linear
    tail when ``law_params[4] = K > 0``, classic for ``AFT_SAMPLES``."""
    # the contact's first coefficient: row 0, not a literal 0 (the DLFT
    # kernels would compile once more for it beside the full residual's)
    BASE = np.int64(0)
    params = problem.law_params
    if problem.aft_scheme != AFT_EVENTS:
        return dlft_contact(params, BASE, y, problem.inverse, problem.forward, R, J)
    hn = problem.harmonic_numbers
    m_cc = problem.contact_mass
    if params[4] > 0.0:
        n_coef = problem.inverse.shape[1]
        omega = y[n_coef]
        q = np.zeros(int(params[4]) + 1, dtype=np.complex128)
        dq = np.zeros(int(params[4]) + 1, dtype=np.complex128)
        if problem.method == DIRECT:
            a2, da2, ok = contact_receptance(
                problem.mass,
                problem.damping,
                problem.stiffness,
                problem.contact_dof,
                omega,
                hn,
                params[3],
                q,
                dq,
            )
        else:
            a2, da2, ok = _modal_tail_receptance(problem, omega, params[3], q, dq)
        if not ok:
            return SINGULAR_RECEPTANCE
        return dlft_tail(
            params,
            hn,
            BASE,
            m_cc,
            q,
            dq,
            a2,
            da2,
            y,
            problem.inverse,
            problem.forward,
            problem.derivative,
            R,
            J,
        )
    return dlft_located(
        params,
        hn,
        BASE,
        m_cc,
        y,
        problem.inverse,
        problem.forward,
        problem.derivative,
        R,
        J,
    )


@jit
def _modal_tail_receptance(problem, omega, mu, q, dq):
    """Tail coefficients of the contact receptance by modal sums: as
    :func:`hbmfric.kernels.dlft.tail.contact_receptance` (same outputs and
    conventions: ``q_k = G(kΩ) [k ∉ S] - a₂/k²``, ``a₂ = -μ/Ω²``, ``q[0]``
    flags odd harmonics only), with ``G(kΩ) = Σ_r φ_cr² / d_r(kΩ)``.

    Returns
    -------
    tuple of (float, float, bool)
        ``a₂``, ``da₂/dΩ`` and False if some ``d_r(kΩ)`` is zero.
    """
    n_k = q.size
    hn = problem.harmonic_numbers
    kept = np.zeros(n_k, dtype=np.bool_)
    odd = True
    for k in hn:
        if k % 2 == 0:
            odd = False
        if k < n_k:
            kept[k] = True
    q[0] = 1.0 if odd else 0.0
    dq[0] = 0.0
    a2 = -mu / (omega * omega)
    da2 = 2.0 * mu / (omega * omega * omega)
    phi = problem.contact_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    for k in range(1, n_k):
        if odd and k % 2 == 0:
            q[k] = 0.0
            dq[k] = 0.0
            continue
        g = 0.0j
        dg = 0.0j
        if not kept[k]:
            w = k * omega
            for r in range(phi.size):
                d = w2[r] - w * w + 1j * w * c[r]
                if d == 0.0:
                    return a2, da2, False
                inv_d = 1.0 / d
                g += phi[r] * phi[r] * inv_d
                dg += phi[r] * phi[r] * k * (2.0 * w - 1j * c[r]) * inv_d * inv_d
        q[k] = g - a2 / (k * k)
        dq[k] = dg - da2 / (k * k)
    return a2, da2, True


@jit
def _condensed_linear(y, problem, R, J):
    """Linear part ``D (x̂ - p)`` of the condensed residual and its Jacobian
    (``J`` overwritten); 0, or ``SINGULAR_RECEPTANCE``."""
    hn = problem.harmonic_numbers
    n = problem.inverse.shape[1]
    omega = y[n]
    J[:, :] = 0.0
    work = _direct_work(problem)
    col = np.int64(0)  # not a literal 0: one signature of the callee
    for k in hn:
        if problem.method == DIRECT:
            g, p, dg, dp, ok = _harmonic_receptance_direct(k, omega, col, problem, work)
            if not ok:
                return SINGULAR_RECEPTANCE
        else:
            g, p, dg, dp = _harmonic_receptance(k, omega, col, problem)
        D = 1.0 / g
        dD = -dg * D * D
        if k == 0:
            x = y[col] + 0.0j
        else:
            x = y[col] - 1j * y[col + 1]
        r = D * (x - p)
        dr = dD * (x - p) - D * dp
        R[col] = r.real
        J[col, col] = D.real
        J[col, n] = dr.real
        if k != 0:
            R[col + 1] = -r.imag
            J[col, col + 1] = D.imag
            J[col + 1, col] = -D.imag
            J[col + 1, col + 1] = D.real
            J[col + 1, n] = -dr.imag
        col += 1 if k == 0 else 2
    return 0


@jit
def _contact_force(x, problem, F, dF):
    """AFT of the contact law at the contact coefficients ``x`` (the same
    dispatch as :func:`hbmfric.kernels.residuals.hbm.hbm_residual`)."""
    return contact_aft(
        problem,
        problem.law_code,
        problem.law_params,
        problem.aft_scheme,
        problem.harmonic_numbers,
        x,
        problem.inverse,
        problem.forward,
        problem.derivative,
        F,
        dF,
    )


@jit
def condensed_contact_forces(points, problem, F):
    """Contact-force coefficients at condensed solutions (AFT at each; for
    a rigid Coulomb contact the DLFT force).

    Parameters
    ----------
    points : ndarray, shape (n_points, n_unknowns + 1)
        ``[X_c, Ω]`` per point (``[q, Ω]`` for several contacts).
    problem : CondensedProblem
    F : ndarray, shape (n_points, n_coef)
        Output: force coefficients, N; for several contacts shape
        (n_points, n_c * n_coef), contact by contact (the force ``f_a`` on
        coordinate ``a``).

    Returns
    -------
    int
        Lowest AFT status met (negative on a failure).
    """
    if problem.law_codes.size > 0:
        return coordinate_forces(points, problem, F)
    n = problem.inverse.shape[1]
    dF = np.empty((n, n))
    f = np.empty(n)
    R = np.empty(n)
    R_lin = np.empty(n)
    J = np.empty((n, n + 1))
    worst = 1 << 30
    for i in range(points.shape[0]):
        y = points[i].copy()
        if problem.law_code == COULOMB:
            # the DLFT force is what the residual adds to its linear part
            status = coulomb_contact_force(y, problem, R, R_lin, J, f)
        else:
            status = _contact_force(y[:n].copy(), problem, f, dF)
        if status < worst:
            worst = status
        F[i, :] = f
    return worst


@jit
def condensed_modal_recover(points, F, problem, shapes, X):
    """Response of every DOF at condensed solutions, modal receptance:
    ``x̂_j = Σ_r φ_jr η̂_r`` with ``η̂_r = (q̂_r - φ_cr F̂) / d_r(kΩ)``.

    Parameters
    ----------
    points : ndarray, shape (n_points, n_coef + 1)
        ``[X_c, Ω]`` per point.
    F : ndarray, shape (n_points, n_coef)
        Contact-force coefficients at the points, N.
    problem : CondensedProblem
        With ``method == MODAL``.
    shapes : ndarray, shape (n_dof, n_modes)
        Mass-normalised mode shapes.
    X : ndarray, shape (n_points, n_dof, n_coef)
        Output: coefficients of every DOF, m.
    """
    n = problem.inverse.shape[1]
    phi = problem.contact_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    q = problem.modal_load
    n_dof, n_modes = shapes.shape
    # the modal sum as one update of every DOF per mode (contiguous rows
    # of the transposed shapes, real and imaginary parts apart), which
    # the compiler vectorises; the sum over modes in the same order
    modes = np.ascontiguousarray(shapes.T)
    eta_re = np.empty(n_modes)
    eta_im = np.empty(n_modes)
    s_re = np.empty(n_dof)
    s_im = np.empty(n_dof)
    for i in range(points.shape[0]):
        omega = points[i, n]
        col = 0
        for k in problem.harmonic_numbers:
            w = k * omega
            if k == 0:
                f = F[i, col] + 0.0j
            else:
                f = F[i, col] - 1j * F[i, col + 1]
            for r in range(n_modes):
                if k == 0:
                    qr = q[r, col] + 0.0j
                else:
                    qr = q[r, col] - 1j * q[r, col + 1]
                eta = (qr - phi[r] * f) / (w2[r] - w * w + 1j * w * c[r])
                eta_re[r] = eta.real
                eta_im[r] = eta.imag
            s_re[:] = 0.0
            s_im[:] = 0.0
            for r in range(n_modes):
                a = eta_re[r]
                b = eta_im[r]
                for j in range(n_dof):
                    s_re[j] += modes[r, j] * a
                    s_im[j] += modes[r, j] * b
            for j in range(n_dof):
                X[i, j, col] = s_re[j]
                if k != 0:
                    X[i, j, col + 1] = -s_im[j]
            col += 1 if k == 0 else 2


# ----------------------------------------------------------------------
# several contacts: unknowns on the contact coordinates q = B x


@jit
def _modal_coordinate_receptance(k, omega, col, problem, G, dG, p, dp, inv_d, dinv):
    """``G_k``, ``p_k`` and their Ω-derivatives by modal sums (see the
    module docstring) into ``G``, ``dG`` (shape (n_c, n_c)), ``p``, ``dp``
    (shape (n_c,)), all complex; ``inv_d``, ``dinv``: work, (n_modes,)."""
    psi = problem.coordinate_shapes
    w2 = problem.omega_squared
    c = problem.modal_damping
    q = problem.modal_load
    n_c, n_modes = psi.shape
    w = k * omega
    for r in range(n_modes):
        d = 1.0 / (w2[r] - w * w + 1j * w * c[r])
        inv_d[r] = d
        dinv[r] = k * (2.0 * w - 1j * c[r]) * d * d
    for a in range(n_c):
        for b in range(a, n_c):
            g = 0.0j
            dg = 0.0j
            for r in range(n_modes):
                s = psi[a, r] * psi[b, r]
                g += s * inv_d[r]
                dg += s * dinv[r]
            G[a, b] = g
            G[b, a] = g
            dG[a, b] = dg
            dG[b, a] = dg
        pa = 0.0j
        dpa = 0.0j
        for r in range(n_modes):
            if k == 0:
                qr = q[r, col] + 0.0j
            else:
                qr = q[r, col] - 1j * q[r, col + 1]
            s = psi[a, r] * qr
            pa += s * inv_d[r]
            dpa += s * dinv[r]
        p[a] = pa
        dp[a] = dpa


@jit
def _direct_coordinate_receptance(k, omega, col, problem, G, dG, p, dp, work):
    """As :func:`_modal_coordinate_receptance` by one LU of the real form
    of ``Z(kΩ)`` and ``n_c + 1`` solves; False if ``Z`` is singular."""
    A, piv, b, Zc, xp, tmp = work
    pairs = problem.coordinate_pairs
    n = problem.mass.shape[0]
    n_c = pairs.shape[0]
    w = k * omega
    _dynamic_stiffness(problem, w, A)
    if not lu_factor(A, piv):
        return False
    for a in range(n_c):
        b[:] = 0.0
        b[pairs[a, 0]] = 1.0
        if pairs[a, 1] >= 0:
            b[pairs[a, 1]] = -1.0
        lu_solve(A, piv, b)
        for i in range(n):
            Zc[i, a] = b[i] + 1j * b[n + i]
    load = problem.load
    for i in range(n):
        b[i] = load[i, col]
        b[n + i] = 0.0 if k == 0 else -load[i, col + 1]
    lu_solve(A, piv, b)
    for i in range(n):
        xp[i] = b[i] + 1j * b[n + i]
    if not (np.isfinite(b).all() and np.isfinite(A).all()):
        return False
    for a in range(n_c):
        i_a = pairs[a, 0]
        j_a = pairs[a, 1]
        for c in range(n_c):
            G[a, c] = Zc[i_a, c] - (Zc[j_a, c] if j_a >= 0 else 0.0)
        p[a] = xp[i_a] - (xp[j_a] if j_a >= 0 else 0.0)
    dG[:, :] = 0.0
    dp[:] = 0.0
    if k == 0:
        return True
    # Z' = k (-2ω M + i C); tmp = Z' [Z_c, x_p]
    mass = problem.mass
    damping = problem.damping
    for i in range(n):
        for c in range(n_c + 1):
            tmp[i, c] = 0.0
        for j in range(n):
            dz = k * (-2.0 * w * mass[i, j] + 1j * damping[i, j])
            if dz == 0.0:
                continue
            for c in range(n_c):
                tmp[i, c] += dz * Zc[j, c]
            tmp[i, n_c] += dz * xp[j]
    for a in range(n_c):
        for c in range(n_c + 1):
            s = 0.0j
            for i in range(n):
                s += Zc[i, a] * tmp[i, c]
            if c < n_c:
                dG[a, c] = -s
            else:
                dp[a] = -s
    return True


@jit
def _state_coordinate_receptance(k, omega, col, problem, G, p, c, dc, rho, left_t):
    """``G_k`` and ``p_k`` from the complex modes of the first-order form
    (``method == STATE``): ``G = L diag(c) R``, ``p = L (c ⊙ ρ)`` with
    ``c_r = 1/(ikΩ - λ_r)``, ``ρ`` the modal load of harmonic ``k``. Fills
    ``c``, ``dc = dc/dΩ = -ik c²`` and ``ρ`` (shape (n_states,)) for
    :func:`_state_derivative`; ``G`` (n_c, n_c), ``p`` (n_c,) complex.
    ``left_t``: ``Lᵀ`` (shape (n_states, n_c), :func:`state_magnitudes`),
    so that ``p`` is summed pole by pole over contiguous rows (a loop the
    compiler vectorises; each ``p_a`` is the same sum in the same order as
    the row-by-row dot product, bit for bit).
    Cost ``O(n_states n_c²)``: one complex matrix product (fewer poles with
    a series, :func:`state_matrix`), no factorisation."""
    poles = problem.state_poles
    load = problem.state_load
    n_s, n_c = left_t.shape
    s = 1j * (k * omega)
    for r in range(n_s):
        cr = 1.0 / (s - poles[r])
        c[r] = cr
        dc[r] = -1j * k * cr * cr
        if k == 0:
            rho[r] = load[r, col]
        else:
            rho[r] = load[r, col] - 1j * load[r, col + 1]
    for a in range(n_c):
        p[a] = 0.0j
    for r in range(n_s):
        cr = c[r]
        rr = rho[r]
        for a in range(n_c):
            p[a] += left_t[r, a] * cr * rr
    state_matrix(problem, k * omega, c, G)


#: relative truncation of the series of :func:`state_matrix` (below the
#: rounding of the sum it replaces)
SERIES_TOL = 2.0**-55


@jit
def series_terms(w, split, n_terms):
    """How many terms of the series of :func:`state_matrix` reach
    :data:`SERIES_TOL` at the pulsation ``w`` (rad/s) for poles of modulus
    at least ``split``: the least ``J`` with ``ρ^J / (1 - ρ) <= SERIES_TOL``,
    ``ρ = w / split``; 0 when that needs more than the ``n_terms`` stored
    (or there is no series): then every pole is summed."""
    if n_terms == 0 or not split > 0.0:
        return 0
    rho = abs(w) / split
    if rho == 0.0:
        return 1
    if not rho < 1.0:
        return 0
    need = np.log(SERIES_TOL * (1.0 - rho)) / np.log(rho)
    if not need <= n_terms:
        return 0
    return max(1, int(np.ceil(need)))


@jit
def state_matrix(problem, w, c, G):
    """``G = L diag(c) R`` of the complex modes at the pulsation ``w = kΩ``
    (rad/s) with ``c_r = 1/(iw - λ_r)`` given (shape (n_states,)), into
    ``G`` (complex, shape (n_c, n_c)).

    The poles of ``problem.state_low`` are summed term by term
    (:func:`hbmfric.kernels.linalg.products.symmetric_matmul`); the others,
    at least ``λ_s = problem.state_split`` in modulus, enter by the series
    ``Σ_r L_r R_r / (iw - λ_r) = Σ_j (iw/λ_s)^j M̃_j`` with ``M̃_j = -λ_s^j
    Σ_r L_r R_r / λ_r^{j+1}`` (``problem.state_series``, real: the poles
    come in conjugate pairs), truncated where ``(w/λ_s)^J`` is below
    :data:`SERIES_TOL` (:func:`series_terms`). A real term costs a quarter
    of a complex one; on the lap joint at H = 15 the series replaces 124 of
    156 poles (N = 40) with about 20 terms. Where the series would need
    more terms than stored (a pulsation above the planned band) every pole
    is summed, as without a series."""
    left = problem.state_left
    right = problem.state_right
    series = problem.state_series
    n_c, n_s = left.shape
    terms = series_terms(w, problem.state_split, series.shape[2])
    if terms == 0:
        scaled = np.empty((n_c, n_s), dtype=np.complex128)
        for a in range(n_c):
            for r in range(n_s):
                scaled[a, r] = left[a, r] * c[r]
        symmetric_matmul(scaled, right, G)
        return
    low = problem.state_low
    n_low = low.size
    scaled = np.empty((n_c, n_low), dtype=np.complex128)
    right_low = np.empty((n_low, n_c), dtype=np.complex128)
    for i in range(n_low):
        r = low[i]
        for a in range(n_c):
            scaled[a, i] = left[a, r] * c[r]
            right_low[i, a] = right[r, a]
    symmetric_matmul(scaled, right_low, G)
    # (iw/λ_s)^j = i^j ρ^j: even j real, odd j imaginary
    rho = w / problem.state_split
    n_even = (terms + 1) // 2
    n_odd = terms // 2
    even = np.empty(n_even)
    odd = np.empty(n_odd)
    power = 1.0
    for j in range(terms):
        sign = 1.0 if (j // 2) % 2 == 0 else -1.0
        if j % 2 == 0:
            even[j // 2] = sign * power
        else:
            odd[j // 2] = sign * power
        power *= rho
    for a in range(n_c):
        b = a
        # four entries at a time: four independent sums per loop (each the
        # same sum in the same order as alone, bit for bit)
        while b + 3 < n_c:
            r0 = 0.0
            r1 = 0.0
            r2 = 0.0
            r3 = 0.0
            for j in range(n_even):
                f = even[j]
                r0 += f * series[a, b, 2 * j]
                r1 += f * series[a, b + 1, 2 * j]
                r2 += f * series[a, b + 2, 2 * j]
                r3 += f * series[a, b + 3, 2 * j]
            i0 = 0.0
            i1 = 0.0
            i2 = 0.0
            i3 = 0.0
            for j in range(n_odd):
                f = odd[j]
                i0 += f * series[a, b, 2 * j + 1]
                i1 += f * series[a, b + 1, 2 * j + 1]
                i2 += f * series[a, b + 2, 2 * j + 1]
                i3 += f * series[a, b + 3, 2 * j + 1]
            _add_mirrored(G, a, b, r0, i0)
            _add_mirrored(G, a, b + 1, r1, i1)
            _add_mirrored(G, a, b + 2, r2, i2)
            _add_mirrored(G, a, b + 3, r3, i3)
            b += 4
        while b < n_c:
            re = 0.0
            im = 0.0
            for j in range(n_even):
                re += even[j] * series[a, b, 2 * j]
            for j in range(n_odd):
                im += odd[j] * series[a, b, 2 * j + 1]
            _add_mirrored(G, a, b, re, im)
            b += 1


@jit_inline
def _add_mirrored(G, a, b, re, im):
    """``G[a, b] += re + i im`` and ``G[b, a]`` the same value."""
    g = G[a, b] + (re + 1j * im)
    G[a, b] = g
    G[b, a] = g


@jit
def _state_derivative(left_t, right_t, r_lin, dc, rho, out, tmp):
    """``(dG/dΩ) r + dp/dΩ = L (dc ⊙ (R r + ρ))`` for the complex modes
    (``O(n_states n_c)``, ``dG/dΩ`` never formed) into ``out`` (n_c,);
    ``left_t``, ``right_t``: ``Lᵀ`` (n_states, n_c) and ``Rᵀ`` (n_c,
    n_states) (:func:`state_magnitudes`): both products run over
    contiguous rows, one column of the sum at a time (loops the compiler
    vectorises), every entry the same sum in the same order as the dot
    products of rows, bit for bit; ``tmp``: work, (n_states,)."""
    n_s, n_c = left_t.shape
    for r in range(n_s):
        tmp[r] = rho[r]
    for b in range(n_c):
        x = r_lin[b]
        for r in range(n_s):
            tmp[r] += right_t[b, r] * x
    for r in range(n_s):
        tmp[r] = dc[r] * tmp[r]
    for a in range(n_c):
        out[a] = 0.0j
    for r in range(n_s):
        t = tmp[r]
        for a in range(n_c):
            out[a] += left_t[r, a] * t


@jit
def _invert(G, D, A):
    """``D = G⁻¹`` (complex, shape (m, m)) by Gauss-Jordan elimination
    in place with partial pivoting; ``A`` (complex, C-contiguous, shape
    (m, m)) is work. False if a pivot is zero or not finite.

    The elimination runs on the real and imaginary parts in separate
    float64 rows (``A`` viewed as float64 of shape (m, 2m): row ``i``
    holds the real parts of the eliminated row in its first ``m`` entries,
    the imaginary parts in the last ``m``), with the scaled pivot rows
    copied apart, so that each row's update is one contiguous loop of
    real products that the compiler vectorises (about 3 times faster at
    order 84 than the loop on complex entries). In place: the column of
    each pivot receives the inverse's column (``-f/p``), the rows swapped
    for the pivots are undone as column swaps at the end. The pivot is the
    entry of largest ``|Re| + |Im|`` (as BLAS's ``izamax``).

    Pivots are taken two at a time (stop 34): the second pivot is chosen
    on its column as the first one's update leaves it, its row updated
    and scaled, and every other row then updated by both pivot rows in
    one pass (:func:`_eliminate_two`), each entry by the same two
    operations in the same order as two passes: the result is that of
    one pivot at a time bit for bit, with half the passes over the rows
    (order 84: 0.135 against 0.198 ms)."""
    m = G.shape[0]
    V = A.view(np.float64)
    big_all = 0.0
    for i in range(m):
        for j in range(m):
            g = G[i, j]
            V[i, j] = g.real
            V[i, m + j] = g.imag
            a = abs(g.real) + abs(g.imag)
            if not a <= big_all:
                big_all = a
    if not np.isfinite(big_all):
        return False
    tiny = 1e-300 + big_all * 1e-15
    piv = np.empty(m, dtype=np.int64)
    r1_re = np.empty(m)
    r1_im = np.empty(m)
    r2_re = np.empty(m)
    r2_im = np.empty(m)
    c_re = np.empty(m)
    c_im = np.empty(m)
    k = 0
    while k < m:
        # first pivot: column k
        p = k
        big = abs(V[k, k]) + abs(V[k, m + k])
        for i in range(k + 1, m):
            a = abs(V[i, k]) + abs(V[i, m + k])
            if a > big:
                big = a
                p = i
        if not big > tiny:
            return False
        piv[k] = p
        if p != k:
            for j in range(2 * m):
                V[k, j], V[p, j] = V[p, j], V[k, j]
        _scale_pivot_row(V, k, r1_re, r1_im)
        if k + 1 == m:
            for i in range(m - 1):
                f_re = V[i, k]
                f_im = V[i, m + k]
                if f_re == 0.0 and f_im == 0.0:
                    continue
                V[i, k] = 0.0
                V[i, m + k] = 0.0
                _eliminate_one(V, i, f_re, f_im, r1_re, r1_im)
            break
        # second pivot: column q as the first pivot's update leaves it
        q = k + 1
        a1 = r1_re[q]
        b1 = r1_im[q]
        for i in range(q, m):
            f_re = V[i, k]
            f_im = V[i, m + k]
            x = V[i, q]
            y = V[i, m + q]
            if not (f_re == 0.0 and f_im == 0.0):
                x -= f_re * a1 - f_im * b1
                y -= f_re * b1 + f_im * a1
            c_re[i] = x
            c_im[i] = y
        p = q
        big = abs(c_re[q]) + abs(c_im[q])
        for i in range(q + 1, m):
            a = abs(c_re[i]) + abs(c_im[i])
            if a > big:
                big = a
                p = i
        if not big > tiny:
            return False
        piv[q] = p
        if p != q:
            for j in range(2 * m):
                V[q, j], V[p, j] = V[p, j], V[q, j]
        # row q: the first pivot's update, then its own scaling
        f_re = V[q, k]
        f_im = V[q, m + k]
        if not (f_re == 0.0 and f_im == 0.0):
            V[q, k] = 0.0
            V[q, m + k] = 0.0
            _eliminate_one(V, q, f_re, f_im, r1_re, r1_im)
        _scale_pivot_row(V, q, r2_re, r2_im)
        # row k: the second pivot's update
        f_re = V[k, q]
        f_im = V[k, m + q]
        if not (f_re == 0.0 and f_im == 0.0):
            V[k, q] = 0.0
            V[k, m + q] = 0.0
            _eliminate_one(V, k, f_re, f_im, r2_re, r2_im)
        # every other row: both updates, in one pass where both apply
        for i in range(m):
            if i == k or i == q:
                continue
            f1_re = V[i, k]
            f1_im = V[i, m + k]
            one = not (f1_re == 0.0 and f1_im == 0.0)
            f2_re = V[i, q]
            f2_im = V[i, m + q]
            if one:
                f2_re -= f1_re * a1 - f1_im * b1
                f2_im -= f1_re * b1 + f1_im * a1
            two = not (f2_re == 0.0 and f2_im == 0.0)
            if one and two:
                V[i, k] = 0.0
                V[i, m + k] = 0.0
                _eliminate_two(
                    V, i, f1_re, f1_im, r1_re, r1_im, f2_re, f2_im, r2_re, r2_im
                )
                # column q was zeroed for the second pivot: its update only
                c = r2_re[q]
                d = r2_im[q]
                V[i, q] = 0.0 - (f2_re * c - f2_im * d)
                V[i, m + q] = 0.0 - (f2_re * d + f2_im * c)
            elif one:
                V[i, k] = 0.0
                V[i, m + k] = 0.0
                _eliminate_one(V, i, f1_re, f1_im, r1_re, r1_im)
            elif two:
                V[i, q] = 0.0
                V[i, m + q] = 0.0
                _eliminate_one(V, i, f2_re, f2_im, r2_re, r2_im)
        k += 2
    for i in range(m):
        for j in range(m):
            D[i, j] = complex(V[i, j], V[i, m + j])
    for k in range(m - 1, -1, -1):
        p = piv[k]
        if p != k:
            for i in range(m):
                D[i, k], D[i, p] = D[i, p], D[i, k]
    return True


@jit_inline
def _scale_pivot_row(V, k, row_re, row_im):
    """Row ``k`` of the split work array ``V`` (float64, shape (m, 2m),
    :func:`_invert`) divided by its pivot ``V[k, k]`` (its own entry set to
    1 first: it receives the pivot's inverse), into ``row_re``,
    ``row_im`` (shape (m,)) and back into ``V``."""
    m = row_re.size
    inv = 1.0 / complex(V[k, k], V[k, m + k])
    inv_re = inv.real
    inv_im = inv.imag
    V[k, k] = 1.0
    V[k, m + k] = 0.0
    for j in range(m):
        a = V[k, j]
        b = V[k, m + j]
        row_re[j] = a * inv_re - b * inv_im
        row_im[j] = a * inv_im + b * inv_re
    for j in range(m):
        V[k, j] = row_re[j]
        V[k, m + j] = row_im[j]


@jit_inline
def _eliminate_one(V, i, f_re, f_im, r_re, r_im):
    """Row ``i`` of the split work array ``V`` (:func:`_invert`) minus
    ``f`` times the scaled pivot row ``r``."""
    m = r_re.size
    for j in range(m):
        a = r_re[j]
        b = r_im[j]
        V[i, j] -= f_re * a - f_im * b
        V[i, m + j] -= f_re * b + f_im * a


@jit_inline
def _eliminate_two(V, i, f1_re, f1_im, r1_re, r1_im, f2_re, f2_im, r2_re, r2_im):
    """Row ``i`` of the split work array ``V`` (:func:`_invert`) minus
    ``f1 r1``, then minus ``f2 r2``, in one pass: each entry the same two
    operations in the same order as :func:`_eliminate_one` twice."""
    m = r1_re.size
    for j in range(m):
        a = r1_re[j]
        b = r1_im[j]
        c = r2_re[j]
        d = r2_im[j]
        x = V[i, j] - (f1_re * a - f1_im * b)
        y = V[i, m + j] - (f1_re * b + f1_im * a)
        V[i, j] = x - (f2_re * c - f2_im * d)
        V[i, m + j] = y - (f2_re * d + f2_im * c)


@jit
def _coordinate_work(problem):
    """Work arrays of :func:`_coordinates_residual`."""
    n_c = problem.law_codes.size
    n_modes = problem.coordinate_shapes.shape[1]
    n_s = problem.state_poles.size
    n = problem.mass.shape[0]
    complex_square = np.empty((n_c, n_c), dtype=np.complex128)
    direct = (
        np.empty((2 * n, 2 * n)),
        np.empty(2 * n, dtype=np.int64),
        np.empty(2 * n),
        np.empty((n, n_c), dtype=np.complex128),
        np.empty(n, dtype=np.complex128),
        np.empty((n, n_c + 1), dtype=np.complex128),
    )
    state = (
        np.empty(n_s, dtype=np.complex128),
        np.empty(n_s, dtype=np.complex128),
        np.empty(n_s, dtype=np.complex128),
        np.empty(n_s, dtype=np.complex128),
    )
    return (
        complex_square,
        complex_square.copy(),
        complex_square.copy(),
        complex_square.copy(),
        np.empty(n_c, dtype=np.complex128),
        np.empty(n_c, dtype=np.complex128),
        np.empty(n_modes, dtype=np.complex128),
        np.empty(n_modes, dtype=np.complex128),
        direct,
        state,
    )


@jit
def _coordinates_linear(y, problem, R, J):
    """Linear part ``r̂_k = D_k (q̂_k - p_k)`` of the residual on the contact
    coordinates and its Jacobian (``J`` overwritten); 0, or
    ``SINGULAR_RECEPTANCE``.

    ``dr̂/dΩ = dD e - D dp = -D (dG r̂ + dp)`` (from ``dD = -D dG D``), so
    ``dD`` is never formed: two matrix-vector products per harmonic."""
    hn = problem.harmonic_numbers
    n_coef = problem.inverse.shape[1]
    n_c = problem.law_codes.size
    n = n_c * n_coef
    omega = y[n]
    J[:, :] = 0.0
    G, dG, D, work, p, dp, inv_d, dinv, direct, state = _coordinate_work(problem)
    c, dc, rho, tmp = state
    e = np.empty(n_c, dtype=np.complex128)
    r_lin = np.empty(n_c, dtype=np.complex128)
    v = np.empty(n_c, dtype=np.complex128)
    level = 0.0
    left_t = problem.state_left_t
    right_t = problem.state_right_t
    left_abs_t = problem.state_left_abs_t
    right_sums = problem.state_right_sums
    rows = np.empty(n_c)
    kept = problem.kept_inverse
    keep = problem.method == STATE and kept.shape[0] == hn.size + 1
    if keep:
        kept[hn.size, 0, 0] = np.nan  # invalid until every harmonic is in
    col = np.int64(0)  # not a literal 0: one signature of the callee
    for h, k in enumerate(hn):
        if problem.method == DIRECT:
            if not _direct_coordinate_receptance(
                k, omega, col, problem, G, dG, p, dp, direct
            ):
                return SINGULAR_RECEPTANCE
        elif problem.method == STATE:
            _state_coordinate_receptance(
                k, omega, col, problem, G, p, c, dc, rho, left_t
            )
        else:
            _modal_coordinate_receptance(
                k, omega, col, problem, G, dG, p, dp, inv_d, dinv
            )
        if not _invert(G, D, work):
            return SINGULAR_RECEPTANCE
        if keep:
            kept[h, :, :] = D
        for a in range(n_c):
            i = a * n_coef + col
            e[a] = (y[i] + 0.0j if k == 0 else y[i] - 1j * y[i + 1]) - p[a]
        g_scale = 0.0
        if problem.method == STATE:
            g_scale = _state_sum_norm(left_abs_t, right_sums, c, rows)
        level = max(level, _rounding_level(G, D, e, g_scale))
        for a in range(n_c):
            s = 0.0j
            for b in range(n_c):
                s += D[a, b] * e[b]
            r_lin[a] = s
        # v = dG r + dp
        if problem.method == STATE:
            _state_derivative(left_t, right_t, r_lin, dc, rho, v, tmp)
        else:
            for a in range(n_c):
                s = dp[a]
                for b in range(n_c):
                    s += dG[a, b] * r_lin[b]
                v[a] = s
        for a in range(n_c):
            r = r_lin[a]
            dr = 0.0j
            for b in range(n_c):
                dr -= D[a, b] * v[b]
            ra = a * n_coef + col
            R[ra] = r.real
            J[ra, n] = dr.real
            if k != 0:
                R[ra + 1] = -r.imag
                J[ra + 1, n] = -dr.imag
            for b in range(n_c):
                cb = b * n_coef + col
                d = D[a, b]
                J[ra, cb] = d.real
                if k != 0:
                    J[ra, cb + 1] = d.imag
                    J[ra + 1, cb] = -d.imag
                    J[ra + 1, cb + 1] = d.real
        col += 1 if k == 0 else 2
    problem.rounding[0] = level
    if keep:
        kept[hn.size, 0, 0] = omega + 1j
    return 0


@jit
def state_magnitudes(left, right):
    """The constant parts of the complex modes' sums, once per problem
    (:class:`hbmfric.condensation.CondensedHBMProblem` stores them in the
    kernel problem's ``state_*_t`` fields), from ``L`` (complex, shape
    (n_c, n_states)) and ``R`` (complex, shape (n_states, n_c)):
    ``Lᵀ`` (n_states, n_c) and ``Rᵀ`` (n_c, n_states) for
    :func:`_state_coordinate_receptance` and :func:`_state_derivative`
    (their sums then run over contiguous rows), ``|L|ᵀ`` (n_states, n_c)
    and the row sums of ``|R|`` (n_states,) for :func:`_state_sum_norm`
    (each complex magnitude a square root: 0.28 ms per residual at
    ``N = 100`` when they were taken at every residual)."""
    n_c, n_s = left.shape
    left_abs_t = np.empty((n_s, n_c))
    left_t = np.empty((n_s, n_c), dtype=np.complex128)
    right_t = np.empty((n_c, n_s), dtype=np.complex128)
    right_sums = np.empty(n_s)
    for r in range(n_s):
        s = 0.0
        for b in range(n_c):
            s += abs(right[r, b])
        right_sums[r] = s
    for a in range(n_c):
        for r in range(n_s):
            v = left[a, r]
            left_t[r, a] = v
            left_abs_t[r, a] = abs(v)
    for r in range(n_s):
        for b in range(n_c):
            right_t[b, r] = right[r, b]
    return left_t, right_t, left_abs_t, right_sums


@jit
def _state_sum_norm(left_abs_t, right_sums, c, rows):
    """``‖ |L| diag|c| |R| ‖∞``: the ∞-norm of the sum of the absolute
    terms of ``G = L diag(c) R`` (complex modes), the scale of its
    rounding, from :func:`state_magnitudes` (``left_abs_t = |L|ᵀ``, the
    row sums summed pole by pole over contiguous rows of it into ``rows``,
    shape (n_c,): each the same sum in the same order as a row's dot
    product, bit for bit). On the lap joint 80 times ``‖G‖∞`` (its
    relative coordinates are small differences of the modes' terms)."""
    n_s, n_c = left_abs_t.shape
    for a in range(n_c):
        rows[a] = 0.0
    for r in range(n_s):
        w = abs(c[r]) * right_sums[r]
        for a in range(n_c):
            rows[a] += left_abs_t[r, a] * w
    worst = 0.0
    for a in range(n_c):
        worst = max(worst, rows[a])
    return worst


@jit
def _rounding_level(G, D, e, g_scale=0.0):
    """Rounding level (N) of ``D e`` with ``D = G⁻¹`` computed from ``G``
    (complex, shapes (m, m), (m, m), (m,)): ``eps κ max_a Σ_b |D_ab| |e_b|``
    with ``κ = ‖G‖∞ ‖D‖∞`` the condition number of ``G``; ``‖G‖∞`` is
    replaced by ``g_scale`` when larger (the sum of the absolute terms of a
    sum that computes ``G``, :func:`_state_sum_norm`).

    The rounding of ``G`` (a modal sum or a direct solve) reaches ``D`` as
    ``κ eps`` relative, so the linear part of the residual on several
    contact coordinates jitters at about this level as Ω changes (the lap
    joint, ``hf.lap_joint(10)``: κ ≈ 1.7e4, jitter 2e-10 to 1e-9 N against
    the tolerance 7e-11 N of Fex = 0.72 N; the level is 1 to 30 times the
    jitter measured there). Below it the corrector cannot reduce ``max |R|``
    and the continuation's steps collapsed (issue 15).

    The moduli are ``sqrt(re² + im²)``, which vectorises (``abs`` of a
    complex is ``hypot``: 6 times slower at order 84); should a square
    overflow (entries beyond 1e154: then the level is not finite), the
    level is taken again with ``hypot`` (:func:`_rounding_level_hypot`).
    A square that underflows (an entry below 1e-154) leaves out of its
    row's sum an entry below 1e-154 of the matrix's largest (else the
    inverse overflows, caught as above)."""
    m = G.shape[0]
    g_norm = 0.0
    d_norm = 0.0
    worst = 0.0
    e_abs = np.empty(m)
    for b in range(m):
        e_abs[b] = abs(e[b])
    for a in range(m):
        sg = 0.0
        sd = 0.0
        se = 0.0
        for b in range(m):
            g = G[a, b]
            d = D[a, b]
            sg += np.sqrt(g.real * g.real + g.imag * g.imag)
            d_abs = np.sqrt(d.real * d.real + d.imag * d.imag)
            sd += d_abs
            se += d_abs * e_abs[b]
        g_norm = max(g_norm, sg, g_scale)
        d_norm = max(d_norm, sd)
        worst = max(worst, se)
    level = 2.220446049250313e-16 * g_norm * d_norm * worst
    if np.isfinite(level):
        return level
    return _rounding_level_hypot(G, D, e_abs, g_scale)


@jit
def _rounding_level_hypot(G, D, e_abs, g_scale):
    """:func:`_rounding_level` with the moduli by ``hypot`` (no overflow
    of the squares), ``e_abs`` the moduli of ``e``."""
    m = G.shape[0]
    g_norm = 0.0
    d_norm = 0.0
    worst = 0.0
    for a in range(m):
        sg = 0.0
        sd = 0.0
        se = 0.0
        for b in range(m):
            sg += abs(G[a, b])
            d = abs(D[a, b])
            sd += d
            se += d * e_abs[b]
        g_norm = max(g_norm, sg, g_scale)
        d_norm = max(d_norm, sd)
        worst = max(worst, se)
    return 2.220446049250313e-16 * g_norm * d_norm * worst


@jit
def _coordinates_residual(y, problem, R, J):
    """The condensed residual on several contact coordinates (module
    docstring): linear part plus every contact's AFT force on its own
    coordinate (a 2D element's on its pair of coordinates, tangential then
    normal: :func:`coordinate_contact2d`). Same contract as
    :func:`condensed_residual` with ``y`` of shape (n_c * n_coef + 1,)."""
    status = _coordinates_linear(y, problem, R, J)
    if status < 0:
        return status
    n_coef = problem.inverse.shape[1]
    F = np.empty(n_coef)
    dF = np.empty((n_coef, n_coef))
    x = np.empty(n_coef)
    F2 = np.empty((2, n_coef))
    dF2 = np.empty((2 * n_coef, 2 * n_coef))
    X2 = np.empty((2, n_coef))
    for a in range(problem.law_codes.size):
        code = problem.law_codes[a]
        if code == CONTACT2D_NORMAL:
            continue  # evaluated with its tangential coordinate, a - 1
        base = a * n_coef
        if code == CONTACT2D:
            for j in range(n_coef):
                X2[0, j] = y[base + j]
                X2[1, j] = y[base + n_coef + j]
            s_a = coordinate_contact2d(
                problem,
                problem.law_rows[a],
                X2,
                problem.inverse,
                problem.forward,
                F2,
                dF2,
            )
            if s_a < 0:
                return s_a
            status = s_a if a == 0 else _combined_state(status, s_a)
            for row in range(2):
                for i in range(n_coef):
                    R[base + row * n_coef + i] += F2[row, i]
                    for col in range(2):
                        for j in range(n_coef):
                            J[base + row * n_coef + i, base + col * n_coef + j] += dF2[
                                row * n_coef + i, col * n_coef + j
                            ]
            continue
        for j in range(n_coef):
            x[j] = y[base + j]
        s_a = contact_aft(
            problem,
            code,
            problem.law_rows[a],
            problem.aft_scheme,
            problem.harmonic_numbers,
            x,
            problem.inverse,
            problem.forward,
            problem.derivative,
            F,
            dF,
        )
        if s_a < 0:
            return s_a
        status = s_a if a == 0 else _combined_state(status, s_a)
        for i in range(n_coef):
            R[base + i] += F[i]
            for j in range(n_coef):
                J[base + i, base + j] += dF[i, j]
    _unshift(y, problem, R, J)
    return status


@jit
def _unshift(y, problem, R, J):
    """Take the shift ``K_s q`` (``problem.coordinate_shift``) off the
    contact forces in ``R`` and ``J``."""
    n_coef = problem.inverse.shape[1]
    shift = problem.coordinate_shift
    for a in range(shift.size):
        s = shift[a]
        if s == 0.0:
            continue
        base = a * n_coef
        for j in range(n_coef):
            R[base + j] -= s * y[base + j]
            J[base + j, base + j] -= s


@jit
def _coordinate_forces(points, problem, F):
    """Contact forces of :func:`condensed_contact_forces` for several
    contacts: ``F[i, a * n_coef + j]``, the AFT of contact ``a`` at its
    coordinate (of a 2D element: its tangential force on its tangential
    coordinate, its normal force on its normal one)."""
    n_coef = problem.inverse.shape[1]
    f = np.empty(n_coef)
    dF = np.empty((n_coef, n_coef))
    x = np.empty(n_coef)
    F2 = np.empty((2, n_coef))
    dF2 = np.empty((2 * n_coef, 2 * n_coef))
    X2 = np.empty((2, n_coef))
    worst = 1 << 30
    for i in range(points.shape[0]):
        for a in range(problem.law_codes.size):
            code = problem.law_codes[a]
            if code == CONTACT2D_NORMAL:
                continue
            base = a * n_coef
            if code == CONTACT2D:
                for j in range(n_coef):
                    X2[0, j] = points[i, base + j]
                    X2[1, j] = points[i, base + n_coef + j]
                status = coordinate_contact2d(
                    problem,
                    problem.law_rows[a],
                    X2,
                    problem.inverse,
                    problem.forward,
                    F2,
                    dF2,
                )
                if status < worst:
                    worst = status
                for row in range(2):
                    for j in range(n_coef):
                        F[i, base + row * n_coef + j] = F2[row, j]
                continue
            for j in range(n_coef):
                x[j] = points[i, base + j]
            status = contact_aft(
                problem,
                code,
                problem.law_rows[a],
                problem.aft_scheme,
                problem.harmonic_numbers,
                x,
                problem.inverse,
                problem.forward,
                problem.derivative,
                f,
                dF,
            )
            if status < worst:
                worst = status
            for j in range(n_coef):
                F[i, base + j] = f[j]
        shift = problem.coordinate_shift
        for a in range(shift.size):
            base = a * n_coef
            for j in range(n_coef):
                F[i, base + j] -= shift[a] * points[i, base + j]
    return worst


def coordinate_contact2d(problem, params, X, inverse, forward, F, dF):
    """The 2D element's AFT (:func:`hbmfric.kernels.aft.contact2d.
    aft_contact2d`) on its coordinates ``X`` (shape (2, n_coef): tangential,
    normal) into ``F`` (2, n_coef) and ``dF`` (2 n_coef, 2 n_coef); its
    state code as the full residual counts it (``STUCK`` or
    ``GROSS_SLIP``: an element that opens counts as slipping), negative on
    failure. Compiled only into the general condensed type
    (:class:`CondensedProblem`): in the types of an AFT family or of a
    rigid Coulomb contact it is ``return NOT_COMPILED_FOR_LAW``. Inlined;
    callable from jitted code only."""
    raise NotImplementedError("coordinate_contact2d is for jit code")


def _with_coordinate_contact2d(problem, params, X, inverse, forward, F, dF):
    status = aft_contact2d(params, X, inverse, forward, F, dF, MAX_PASSES)
    if status < 0:
        return status
    return np.int64(STUCK) if status == STUCK else np.int64(GROSS_SLIP)


def _without_coordinate_contact2d(problem, params, X, inverse, forward, F, dF):
    # not the bare constant (a literal type would compile the caller's
    # _combined_state once more)
    return np.int64(NOT_COMPILED_FOR_LAW)


@overload(coordinate_contact2d, jit_options=JIT_OPTIONS, inline="always")
def _coordinate_contact2d_overload(problem, params, X, inverse, forward, F, dF):
    if problem_family(problem) is None and not is_coulomb_problem(problem):
        return _with_coordinate_contact2d
    return _without_coordinate_contact2d


def coordinates_residual(y, problem, R, J):
    """:func:`_coordinates_residual`; for a problem of one contact to
    ground (:func:`is_single_contact`) it compiles to ``return
    NOT_ONE_CONTACT`` without compiling the several-contact path. Callable
    from jitted code only."""
    raise NotImplementedError("coordinates_residual is for jit code")


def _several_residual(y, problem, R, J):
    return _coordinates_residual(y, problem, R, J)


def _one_contact_residual(y, problem, R, J):
    return NOT_ONE_CONTACT


@overload(coordinates_residual, jit_options=JIT_OPTIONS)
def _coordinates_residual_entry(y, problem, R, J):
    return _one_contact_residual if is_single_contact(problem) else _several_residual


def coordinate_forces(points, problem, F):
    """:func:`_coordinate_forces`; for a problem of one contact to ground
    it compiles to ``return NOT_ONE_CONTACT``. Callable from jitted code
    only."""
    raise NotImplementedError("coordinate_forces is for jit code")


def _several_forces(points, problem, F):
    return _coordinate_forces(points, problem, F)


def _one_contact_forces(points, problem, F):
    return NOT_ONE_CONTACT


@overload(coordinate_forces, jit_options=JIT_OPTIONS)
def _coordinate_forces_entry(points, problem, F):
    return _one_contact_forces if is_single_contact(problem) else _several_forces


# ----------------------------------------------------------------------
# the drawn DOF of a problem condensed onto several contact coordinates


@jit
def coordinates_drawn(problem, y, t, scale, column, coefficients):
    """Ω, the amplitude ``a`` of the forced harmonic of the output DOF
    (``problem.output_dof``) recovered from the contact coordinates, and
    their derivatives along the continuation's scaled arc length, at a
    solution ``y`` with unit tangent ``t`` (scaled): what the curve rule
    draws (:func:`hbmfric.kernels.steps.arclength.chord_error`); also the
    output's coefficients of every harmonic and the squared norm of their
    derivatives (the metric of ``Branch.curve_errors``).

    At a solution the contact forces are ``f̂ = -r̂`` with ``r̂ = D (q̂ -
    p)`` the linear part of the residual, so the output is linear in the
    coordinates of the harmonic: ``x̂ = x_p + g_cᵀ r̂`` with ``x_p = e_cᵀ
    Z⁻¹ P̂`` and ``g_c = B Z⁻¹ e_c``. Along the arc ``dr̂ = D (dq̂ - dΩ (dG
    r̂ + dp))``. Modal sums (classical damping) or complex modes only.

    Parameters
    ----------
    problem : CondensedProblem
    y : ndarray, shape (n_c * n_coef + 1,)
        ``[q, Ω]``, m and rad/s.
    t : ndarray, shape (n_c * n_coef + 1,)
        Unit tangent in the scaled variables.
    scale : ndarray, shape (n_c * n_coef + 1,)
        Scales of the variables.
    column : int
        Column of the forced harmonic's cosine coefficient (of coordinate
        0, or within any coordinate's block).
    coefficients : ndarray, shape (>= n_coef,)
        Output: the output DOF's coefficients (m), first ``n_coef``.

    Returns
    -------
    tuple of (bool, float, float, float, float, float, int)
        False when not applicable (one contact to ground, the direct
        receptance, no output DOF, a singular ``G``; then the coordinate at
        ``column`` is drawn); Ω, dΩ/ds, ``a`` (m; NaN at rest), da/ds, the
        sum of the squared derivatives of the coefficients (m²) and the
        number of coefficients (``n_coef``).
    """
    n_c = problem.law_codes.size
    if n_c == 0 or problem.output_dof < 0 or problem.method == DIRECT:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0
    cache = problem.drawn_cache
    slot = _drawn_lookup(cache, y, t, scale, column)
    if slot >= 0:
        return _drawn_cached(cache, slot, y.size, coefficients)
    out = _coordinates_drawn(problem, y, t, scale, column, coefficients)
    if out[0]:
        _drawn_store(cache, y, t, scale, column, out, coefficients)
    return out


@jit
def _drawn_lookup(cache, y, t, scale, column):
    """The slot of ``problem.drawn_cache`` that holds the result for these
    arguments (equal to the bit), or -1. The continuation asks for the
    start of every step, which the step before drew as its end."""
    m = y.size
    if cache.shape[1] < 3 * m + 8:
        return -1
    for slot in range(2):
        row = cache[slot]
        if row[0] != 1.0 or row[1] != column:
            continue
        same = True
        for i in range(m):
            if (
                row[2 + i] != y[i]
                or row[2 + m + i] != t[i]
                or row[2 + 2 * m + i] != scale[i]
            ):
                same = False
                break
        if same:
            return slot
    return -1


@jit
def _drawn_cached(cache, slot, m, coefficients):
    """The result of :func:`coordinates_drawn` kept in ``slot``."""
    row = cache[slot]
    base = 2 + 3 * m
    n_coef = int(row[base + 5])
    for i in range(n_coef):
        coefficients[i] = row[base + 6 + i]
    return (
        True,
        row[base],
        row[base + 1],
        row[base + 2],
        row[base + 3],
        row[base + 4],
        n_coef,
    )


@jit
def _drawn_store(cache, y, t, scale, column, out, coefficients):
    """Keep a result of :func:`coordinates_drawn` in the older slot."""
    m = y.size
    n_coef = out[6]
    if cache.shape[1] < 3 * m + 9 + n_coef:
        return
    last = cache.shape[1] - 1
    slot = 1 if cache[0, last] == 0.0 else 0
    cache[0, last] = float(slot)
    row = cache[slot]
    row[0] = 0.0
    row[1] = column
    for i in range(m):
        row[2 + i] = y[i]
        row[2 + m + i] = t[i]
        row[2 + 2 * m + i] = scale[i]
    base = 2 + 3 * m
    row[base] = out[1]
    row[base + 1] = out[2]
    row[base + 2] = out[3]
    row[base + 3] = out[4]
    row[base + 4] = out[5]
    row[base + 5] = n_coef
    for i in range(n_coef):
        row[base + 6 + i] = coefficients[i]
    row[0] = 1.0


@jit
def _coordinates_drawn(problem, y, t, scale, column, coefficients):
    """:func:`coordinates_drawn` computed (no cache)."""
    n_c = problem.law_codes.size
    hn = problem.harmonic_numbers
    n_coef = problem.inverse.shape[1]
    col_forced = column % n_coef
    a = np.nan
    da = np.nan
    speed2 = 0.0
    found = False
    col = np.int64(0)  # not a literal 0: one signature of the callee
    for h, k in enumerate(hn):
        ok, x, dx = _drawn_harmonic(problem, y, t, scale, h, k, col)
        if not ok:
            return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0
        coefficients[col] = x.real
        speed2 += dx.real * dx.real
        if k != 0:
            coefficients[col + 1] = -x.imag
            speed2 += dx.imag * dx.imag
            if col == col_forced:
                found = True
                amp = abs(x)
                if amp > 0.0:
                    a = amp
                    da = (x.real * dx.real + x.imag * dx.imag) / amp
        col += 1 if k == 0 else 2
    if not found:  # not the cosine of a harmonic above the mean
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0
    n = n_c * n_coef
    return True, y[n], t[n] * scale[n], a, da, speed2, n_coef


@jit
def _drawn_harmonic(problem, y, t, scale, h, k, col):
    """Complex amplitude ``x̂`` of harmonic ``k`` (the ``h``-th, columns
    from ``col``) of the output DOF at ``y`` and its derivative along ``t``
    (see :func:`coordinates_drawn`); False if ``G`` is singular.

    With complex modes ``D = G⁻¹`` is taken from ``problem.kept_inverse``
    when the last residual was evaluated at this very Ω (compared bit for
    bit; the corrector's last residual is at the point it returns): the
    same ``G`` from the same sums, the same ``D`` to the bit, without the
    ``O(n_c³)`` inversion."""
    n_c = problem.law_codes.size
    n_coef = problem.inverse.shape[1]
    n = n_c * n_coef
    omega = y[n]
    d_omega = t[n] * scale[n]
    state = problem.method == STATE
    n_m = problem.state_poles.size if state else problem.omega_squared.size
    c = np.empty(n_m, dtype=np.complex128)
    dc = np.empty(n_m, dtype=np.complex128)
    rho = np.empty(n_m, dtype=np.complex128)
    h_out = np.empty(n_m, dtype=np.complex128)
    left = np.empty((n_c, n_m), dtype=np.complex128)
    w = k * omega
    for r in range(n_m):
        if state:
            cr = 1.0 / (1j * w - problem.state_poles[r])
            dc[r] = -1j * k * cr * cr
            h_out[r] = problem.state_output[r]
            q_c = problem.state_load[r, col]
            q_s = problem.state_load[r, col + 1] if k != 0 else 0.0j
        else:
            damping = problem.modal_damping[r]
            cr = 1.0 / (problem.omega_squared[r] - w * w + 1j * w * damping)
            dc[r] = k * (2.0 * w - 1j * damping) * cr * cr
            h_out[r] = problem.contact_shapes[r]
            q_c = problem.modal_load[r, col] + 0.0j
            q_s = problem.modal_load[r, col + 1] + 0.0j if k != 0 else 0.0j
        c[r] = cr
        rho[r] = q_c - 1j * q_s
        for a in range(n_c):
            if state:
                left[a, r] = problem.state_left[a, r]
            else:
                left[a, r] = problem.coordinate_shapes[a, r]
    # right factor: R = Y Bᵀ (complex modes) or Ψᵀ (modal)
    right = np.empty((n_m, n_c), dtype=np.complex128)
    for r in range(n_m):
        for a in range(n_c):
            right[r, a] = problem.state_right[r, a] if state else left[a, r]
    scaled = np.empty((n_c, n_m), dtype=np.complex128)
    p = np.empty(n_c, dtype=np.complex128)
    for a in range(n_c):
        s = 0.0j
        for r in range(n_m):
            scaled[a, r] = left[a, r] * c[r]
            s += scaled[a, r] * rho[r]
        p[a] = s
    kept = problem.kept_inverse
    n_h = problem.harmonic_numbers.size
    if state and kept.shape[0] == n_h + 1 and kept[n_h, 0, 0] == omega + 1j:
        D = kept[h]
    else:
        G = np.empty((n_c, n_c), dtype=np.complex128)
        if state:
            state_matrix(problem, w, c, G)
        else:
            symmetric_matmul(scaled, right, G)
        D = np.empty((n_c, n_c), dtype=np.complex128)
        work = np.empty((n_c, n_c), dtype=np.complex128)
        if not _invert(G, D, work):
            return False, 0.0j, 0.0j
    e = np.empty(n_c, dtype=np.complex128)
    dq = np.empty(n_c, dtype=np.complex128)
    for a in range(n_c):
        i = a * n_coef + col
        if k == 0:
            e[a] = y[i] - p[a]
            dq[a] = t[i] * scale[i]
        else:
            e[a] = y[i] - 1j * y[i + 1] - p[a]
            dq[a] = t[i] * scale[i] - 1j * t[i + 1] * scale[i + 1]
    r_lin = matvec(D, e)
    # v = dG r + dp = L (dc ⊙ (R r + ρ))
    rr = matvec(right, r_lin)
    tmp = np.empty(n_m, dtype=np.complex128)
    for r in range(n_m):
        tmp[r] = dc[r] * (rr[r] + rho[r])
    v = matvec(left, tmp)
    dr = matvec(D, dq - d_omega * v)
    drr = matvec(right, dr)
    x = 0.0j
    dx = 0.0j
    for r in range(n_m):
        x += h_out[r] * c[r] * (rho[r] + rr[r])
        dx += h_out[r] * (d_omega * dc[r] * (rho[r] + rr[r]) + c[r] * drr[r])
    return True, x, dx
