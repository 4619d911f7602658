"""Harmonic-balance residual and Jacobian of a linear structure with
friction contacts.

System: ``M ẍ + C ẋ + K x + Σ_i (e_a - e_b) f_i(x_a - x_b) = p(t)``, with
``f_i`` the law of contact ``i`` acting between DOFs ``a`` and ``b`` (or
on ``a`` against ground). Unknowns ``y = [X, Ω]`` with ``X`` stored DOF by DOF,
``X[d * n_coef:(d + 1) * n_coef]`` the coefficients of DOF ``d`` (layout of
:mod:`hbmfric.kernels.fourier.dft`).

The problem travels to the kernels as one flat tuple (see
:func:`hbm_residual`); the Newton corrector passes it through untouched.
"""

from collections import namedtuple

import numpy as np
from numba import types
from numba.extending import overload

from ..._jit import CACHE, jit
from ..aft.contact2d import CONTACT2D, MAX_PASSES, aft_contact2d
from ..aft.dahl import aft_dahl
from ..aft.masing import aft_masing
from ..aft.schemes import (
    GROSS_SLIP,
    MARCHED,
    MICROSLIP,
    STUCK,
    aft_jenkins_events,
    aft_samples,
)
from ..dlft.coulomb import COULOMB, dlft_contact, dlft_located
from ..dlft.tail import SINGULAR_RECEPTANCE, contact_receptance, dlft_tail
from ..laws.updates import DAHL, JENKINS, MASING, is_masing

NO_CONTACT = -1
#: AFT scheme codes
AFT_SAMPLES = 0
AFT_EVENTS = 1
#: status of :func:`hbm_residual` for a rigid Coulomb contact in a problem
#: that is not a :class:`CoulombProblem` (the DLFT is not compiled for it)
NOT_A_COULOMB_PROBLEM = -102

#: field names of the kernel problem tuple of :func:`hbm_residual`
FIELDS = (
    "harmonic_numbers",
    "mass",
    "damping",
    "stiffness",
    "load",
    "contact_pairs",
    "law_codes",
    "law_params",
    "aft_scheme",
    "inverse",
    "forward",
    "derivative",
)

CoulombProblem = namedtuple("CoulombProblem", FIELDS)
CoulombProblem.__doc__ = """The kernel problem of :func:`hbm_residual` for a
rigid Coulomb contact (``law_codes[0] = COULOMB``): the same fields as the
plain tuple, in its own type, so that the DLFT kernels are compiled only
into the residual of this type and not into every residual (the plain tuple
of the other laws compiles without them). Built by
:class:`hbmfric.hbm.HBMProblem`."""


ChainProblem = namedtuple("ChainProblem", FIELDS)
ChainProblem.__doc__ = """The kernel problem of :func:`hbm_residual` as the
continuation kernels receive it (:func:`hbmfric.kernels.residuals.pointer.
chain_problem`): the same fields, in one type for every full problem type
(plain tuple, :class:`CoulombProblem` and the AFT families' types). Those
kernels call the residual only through its address, which is resolved for
the problem's own type, and dispatch on nothing else of the type, so one
compilation of the continuation serves every law family."""


#: options of the overloads' implementations: those of the project
#: decorator (:data:`hbmfric._jit.jit`)
JIT_OPTIONS = {"cache": CACHE, "nogil": True, "error_model": "numpy"}


def is_coulomb_problem(problem) -> bool:
    """Whether the Numba type ``problem`` is a :class:`CoulombProblem` (or
    the condensed one, :class:`hbmfric.kernels.residuals.condensed.
    CondensedCoulombProblem`); for compile-time dispatch."""
    return isinstance(problem, types.BaseNamedTuple) and problem.instance_class in (
        COULOMB_TYPES
    )


#: the problem classes whose residual compiles the rigid Coulomb DLFT
#: (the condensed one registers itself)
COULOMB_TYPES = [CoulombProblem]

#: status of the residual of a one-law problem type (:class:`JenkinsProblem`,
#: :class:`MasingProblem`, :class:`DahlProblem`) for a contact its family
#: does not cover (its AFT is not compiled into that type)
NOT_COMPILED_FOR_LAW = -103

#: AFT families: a problem whose contacts all go through one AFT kernel
#: gets a problem type of that family, whose residual compiles that kernel
#: only (the plain tuple compiles every law's AFT and the 2D element)
JENKINS_FAMILY = "jenkins"
MASING_FAMILY = "masing"
DAHL_FAMILY = "dahl"

JenkinsProblem = namedtuple("JenkinsProblem", FIELDS)
JenkinsProblem.__doc__ = """The kernel problem of :func:`hbm_residual` when
every contact is ``JENKINS`` with ``aft_scheme = AFT_EVENTS``: the fields of
the plain tuple, in a type whose residual compiles only the event-located
Jenkins AFT (:func:`hbmfric.kernels.aft.schemes.aft_jenkins_events`), not the
AFT of every law. Built by :class:`hbmfric.hbm.HBMProblem`
(:func:`aft_family`)."""
JenkinsProblem.aft_family = JENKINS_FAMILY

MasingProblem = namedtuple("MasingProblem", FIELDS)
MasingProblem.__doc__ = """As :class:`JenkinsProblem` for contacts that are
all Masing laws (``MENQ``, ``IWAN``) with ``aft_scheme = AFT_EVENTS``: only
:func:`hbmfric.kernels.aft.masing.aft_masing` is compiled."""
MasingProblem.aft_family = MASING_FAMILY

DahlProblem = namedtuple("DahlProblem", FIELDS)
DahlProblem.__doc__ = """As :class:`JenkinsProblem` for contacts that are
all ``DAHL`` (either scheme): only :func:`hbmfric.kernels.aft.dahl.aft_dahl`
is compiled."""
DahlProblem.aft_family = DAHL_FAMILY

#: problem class of each family for the full residual (the condensed ones
#: are in :data:`hbmfric.kernels.residuals.condensed.CONDENSED_FAMILY_TYPES`)
FAMILY_TYPES = {
    JENKINS_FAMILY: JenkinsProblem,
    MASING_FAMILY: MasingProblem,
    DAHL_FAMILY: DahlProblem,
}


def aft_family(law_codes, aft_scheme) -> str | None:
    """The AFT family that serves every contact of a problem, or None.

    Python side, when a problem is built: the family names the one AFT
    kernel that :func:`contact_aft` calls for each of these contacts (the
    same kernel the general dispatch picks), so that the problem's type can
    compile that kernel alone.

    Parameters
    ----------
    law_codes : array_like of int, shape (n_contacts,)
        Law codes of the contacts.
    aft_scheme : int
        ``AFT_EVENTS`` or ``AFT_SAMPLES``.

    Returns
    -------
    str or None
        ``JENKINS_FAMILY``, ``MASING_FAMILY``, ``DAHL_FAMILY``, or None
        (no contact, mixed families, another law, or a law on the sampled
        scheme: the general type).
    """
    codes = {int(c) for c in law_codes}
    if not codes:
        return None
    events = int(aft_scheme) == AFT_EVENTS
    if codes == {JENKINS} and events:
        return JENKINS_FAMILY
    if codes <= set(MASING) and events:
        return MASING_FAMILY
    if codes == {DAHL}:
        return DAHL_FAMILY
    return None


def problem_family(problem) -> str | None:
    """The AFT family of the Numba type ``problem`` (its class's
    ``aft_family``), None for the general types; for compile-time
    dispatch."""
    if not isinstance(problem, types.BaseNamedTuple):
        return None
    return getattr(problem.instance_class, "aft_family", None)


@jit
def hbm_residual(y, problem, R, J):
    """Residual ``R(X, Ω)`` and Jacobian ``[dR/dX, dR/dΩ]``.

    Parameters
    ----------
    y : ndarray, shape (n_dof * n_coef + 1,)
        Coefficients of all DOFs (m), then Ω (rad/s).
    problem : tuple
        ``(harmonic_numbers, mass, damping, stiffness, load, contact_pairs,
        law_codes, law_params, aft_scheme, inverse, forward, derivative)``
        with ``mass``, ``damping``, ``stiffness`` of shape (n_dof, n_dof),
        ``load`` of shape (n_dof * n_coef,) (coefficients of ``p(t)``, N),
        and per contact ``i`` (``n_contacts >= 0`` of them):
        ``contact_pairs[i] = (a, b, a_n, b_n)`` (int64, shape
        (n_contacts, 4)), the law acting on ``x_a - x_b`` (on ``x_a``
        against ground for ``b = -1``, the force ``+f`` on ``a`` and ``-f``
        on ``b``); the 2D element (``CONTACT2D``) also on the normal pair
        ``x_{a_n} - x_{b_n}`` (``-1`` for the 1D laws),
        ``law_codes[i]`` (int64, shape (n_contacts,)) and its parameters
        ``law_params[i]`` (float64, shape (n_contacts, n_params), rows
        padded). ``law_codes[0] = COULOMB`` (rigid Coulomb, the only
        contact, on ``a`` to ground, ``law_params[0] = [slip_force,
        penalty, penalty_damping, (M⁻¹)_cc, K]``) is solved by DLFT
        (:mod:`hbmfric.kernels.dlft.coulomb`)
        instead of an AFT: for ``aft_scheme = AFT_EVENTS`` with located
        reversals, plus the linear tail of the response summed to ``K``
        when ``K > 0`` (:mod:`hbmfric.kernels.dlft.tail`); the classic
        sampled scheme otherwise. Such a problem must come as a
        :class:`CoulombProblem` (the same fields), the only type for which
        the DLFT kernels are compiled; in a plain tuple the residual
        returns ``NOT_A_COULOMB_PROBLEM``. Contacts of one AFT family
        (:func:`aft_family`) may come as that family's type
        (:class:`JenkinsProblem`, :class:`MasingProblem`,
        :class:`DahlProblem`, the same fields), which compiles that
        family's AFT alone and returns ``NOT_COMPILED_FOR_LAW`` for any
        other law.
    R : ndarray, shape (n_dof * n_coef,)
        Output: residual, N.
    J : ndarray, shape (n_dof * n_coef, n_dof * n_coef + 1)
        Output: Jacobian; last column ``dR/dΩ``.

    Returns
    -------
    int
        Contact-state code of the AFT (negative on failure).
    """
    (
        harmonic_numbers,
        mass,
        damping,
        stiffness,
        load,
        contact_pairs,
        law_codes,
        law_params,
        aft_scheme,
        inverse,
        forward,
        derivative,
    ) = problem
    n_dof = mass.shape[0]
    n_coef = inverse.shape[1]
    n = n_dof * n_coef
    omega = y[n]
    J[:, :] = 0.0
    for r in range(n):
        R[r] = -load[r]
    col = 0
    for k in harmonic_numbers:
        w = k * omega
        for p in range(n_dof):
            for q in range(n_dof):
                kpq = stiffness[p, q]
                mpq = mass[p, q]
                cpq = damping[p, q]
                rp = p * n_coef + col
                cq = q * n_coef + col
                if k == 0:
                    J[rp, cq] += kpq
                    R[rp] += kpq * y[cq]
                else:
                    diag = kpq - mpq * w * w
                    xc = y[cq]
                    xs = y[cq + 1]
                    J[rp, cq] += diag
                    J[rp, cq + 1] += cpq * w
                    J[rp + 1, cq] -= cpq * w
                    J[rp + 1, cq + 1] += diag
                    R[rp] += diag * xc + cpq * w * xs
                    R[rp + 1] += diag * xs - cpq * w * xc
                    ddiag = -2.0 * mpq * k * w
                    J[rp, n] += ddiag * xc + cpq * k * xs
                    J[rp + 1, n] += ddiag * xs - cpq * k * xc
        col += 1 if k == 0 else 2
    n_contacts = law_codes.size
    if n_contacts == 0:
        return 0
    if law_codes[0] == COULOMB:
        # a rigid Coulomb contact is solved alone (checked at the edge), in a
        # CoulombProblem only
        return rigid_coulomb(y, problem, R, J)
    F = np.empty(n_coef)
    dF = np.empty((n_coef, n_coef))
    x_c = np.empty(n_coef)
    status = np.int64(0)  # not a literal 0: one signature of _combined_state
    for i in range(n_contacts):
        if law_codes[i] == CONTACT2D:
            s_i = contact2d(
                problem,
                y,
                contact_pairs[i],
                law_params[i],
                inverse,
                forward,
                n_coef,
                R,
                J,
            )
            if s_i < 0:
                return s_i
            status = s_i if i == 0 else _combined_state(status, s_i)
            continue
        a = contact_pairs[i, 0]
        b = contact_pairs[i, 1]
        base_a = a * n_coef
        base_b = b * n_coef
        # relative displacement of the contact (to ground when b < 0)
        for r in range(n_coef):
            x_c[r] = y[base_a + r] - (y[base_b + r] if b >= 0 else 0.0)
        s_i = contact_aft(
            problem,
            law_codes[i],
            law_params[i],
            aft_scheme,
            harmonic_numbers,
            x_c,
            inverse,
            forward,
            derivative,
            F,
            dF,
        )
        if s_i < 0:
            return s_i
        status = s_i if i == 0 else _combined_state(status, s_i)
        for r in range(n_coef):
            R[base_a + r] += F[r]
            for c in range(n_coef):
                J[base_a + r, base_a + c] += dF[r, c]
            if b >= 0:
                R[base_b + r] -= F[r]
                for c in range(n_coef):
                    J[base_a + r, base_b + c] -= dF[r, c]
                    J[base_b + r, base_a + c] -= dF[r, c]
                    J[base_b + r, base_b + c] += dF[r, c]
    return status


@jit
def _contact2d(y, dofs, params, inverse, forward, n_coef, R, J):
    """The 2D element (:mod:`hbmfric.kernels.aft.contact2d`) on the tangential
    pair ``dofs[0] - dofs[1]`` and the normal pair ``dofs[2] - dofs[3]``
    (``-1``: ground), added to ``R`` and ``J``; its state code."""
    X = np.empty((2, n_coef))
    for r in range(n_coef):
        for row in range(2):
            a = dofs[2 * row]
            b = dofs[2 * row + 1]
            X[row, r] = y[a * n_coef + r] - (y[b * n_coef + r] if b >= 0 else 0.0)
    F = np.empty((2, n_coef))
    dF = np.empty((2 * n_coef, 2 * n_coef))
    status = aft_contact2d(params, X, inverse, forward, F, dF, MAX_PASSES)
    if status < 0:
        return status
    for row in range(2):
        for side in range(2):
            d = dofs[2 * row + side]
            if d < 0:
                continue
            sign = 1.0 if side == 0 else -1.0
            for r in range(n_coef):
                R[d * n_coef + r] += sign * F[row, r]
            for col in range(2):
                for side2 in range(2):
                    e = dofs[2 * col + side2]
                    if e < 0:
                        continue
                    s2 = sign * (1.0 if side2 == 0 else -1.0)
                    for r in range(n_coef):
                        for c in range(n_coef):
                            J[d * n_coef + r, e * n_coef + c] += (
                                s2 * dF[row * n_coef + r, col * n_coef + c]
                            )
    # the element's own codes: a contact that opens counts as slipping
    return STUCK if status == STUCK else GROSS_SLIP


@jit
def _combined_state(a, b):
    """Contact-state code of two contacts together: the more slipping one
    (gross slip, then microslip, then a marched law, then stuck)."""
    for code in (GROSS_SLIP, MICROSLIP, MARCHED, STUCK):
        if a == code or b == code:
            return code
    return a


def contact_aft(
    problem,
    law_code,
    law_params,
    aft_scheme,
    harmonic_numbers,
    x_c,
    inverse,
    forward,
    derivative,
    F,
    dF,
):
    """Force coefficients ``F`` and ``dF/dx_c`` of one contact law at the
    displacement coefficients ``x_c``; the AFT's contact-state code.

    Dispatched at compile time on the type of ``problem``: a problem type
    of an AFT family (:func:`aft_family`) compiles that family's AFT kernel
    only and returns ``NOT_COMPILED_FOR_LAW`` for any other law or scheme;
    the general types compile every law's AFT. Inlined into the caller (no
    kernel of its own). Callable from jitted code only."""
    raise NotImplementedError(
        "hbmfric.kernels.residuals.hbm.contact_aft is for jit code"
    )


def _jenkins_aft(
    problem,
    law_code,
    law_params,
    aft_scheme,
    harmonic_numbers,
    x_c,
    inverse,
    forward,
    derivative,
    F,
    dF,
):
    if law_code != JENKINS or aft_scheme != AFT_EVENTS:
        return np.int64(NOT_COMPILED_FOR_LAW)
    return aft_jenkins_events(
        law_params, harmonic_numbers, x_c, inverse, derivative, F, dF
    )


def _masing_aft(
    problem,
    law_code,
    law_params,
    aft_scheme,
    harmonic_numbers,
    x_c,
    inverse,
    forward,
    derivative,
    F,
    dF,
):
    if not is_masing(law_code) or aft_scheme != AFT_EVENTS:
        return np.int64(NOT_COMPILED_FOR_LAW)
    return aft_masing(
        law_code,
        law_params,
        harmonic_numbers,
        x_c,
        inverse,
        forward,
        derivative,
        F,
        dF,
    )


def _dahl_aft(
    problem,
    law_code,
    law_params,
    aft_scheme,
    harmonic_numbers,
    x_c,
    inverse,
    forward,
    derivative,
    F,
    dF,
):
    if law_code != DAHL:
        return np.int64(NOT_COMPILED_FOR_LAW)
    return aft_dahl(
        law_params, harmonic_numbers, x_c, inverse, forward, derivative, F, dF
    )


def _any_aft(
    problem,
    law_code,
    law_params,
    aft_scheme,
    harmonic_numbers,
    x_c,
    inverse,
    forward,
    derivative,
    F,
    dF,
):
    if law_code == JENKINS and aft_scheme == AFT_EVENTS:
        return aft_jenkins_events(
            law_params, harmonic_numbers, x_c, inverse, derivative, F, dF
        )
    if is_masing(law_code) and aft_scheme == AFT_EVENTS:
        return aft_masing(
            law_code,
            law_params,
            harmonic_numbers,
            x_c,
            inverse,
            forward,
            derivative,
            F,
            dF,
        )
    if law_code == DAHL:
        return aft_dahl(
            law_params, harmonic_numbers, x_c, inverse, forward, derivative, F, dF
        )
    return aft_samples(law_code, law_params, x_c, inverse, forward, F, dF)


_FAMILY_AFT = {
    JENKINS_FAMILY: _jenkins_aft,
    MASING_FAMILY: _masing_aft,
    DAHL_FAMILY: _dahl_aft,
}


@overload(contact_aft, jit_options=JIT_OPTIONS, inline="always")
def _contact_aft(
    problem,
    law_code,
    law_params,
    aft_scheme,
    harmonic_numbers,
    x_c,
    inverse,
    forward,
    derivative,
    F,
    dF,
):
    return _FAMILY_AFT.get(problem_family(problem), _any_aft)


def contact2d(problem, y, dofs, params, inverse, forward, n_coef, R, J):
    """:func:`_contact2d` in a general problem type; ``NOT_COMPILED_FOR_LAW``
    in a problem type of an AFT family (the 2D element is not compiled
    into it). Inlined; callable from jitted code only."""
    raise NotImplementedError("hbmfric.kernels.residuals.hbm.contact2d is for jit code")


def _with_contact2d(problem, y, dofs, params, inverse, forward, n_coef, R, J):
    return _contact2d(y, dofs, params, inverse, forward, n_coef, R, J)


def _without_contact2d(problem, y, dofs, params, inverse, forward, n_coef, R, J):
    # not the bare constant: an inlined function would return it as a
    # literal type, and the caller would compile _combined_state once more
    # for that literal
    return np.int64(NOT_COMPILED_FOR_LAW)


@overload(contact2d, jit_options=JIT_OPTIONS, inline="always")
def _contact2d_overload(problem, y, dofs, params, inverse, forward, n_coef, R, J):
    if problem_family(problem) is None:
        return _with_contact2d
    return _without_contact2d


def rigid_coulomb(y, problem, R, J):
    """Add the rigid Coulomb contact of a :class:`CoulombProblem` to ``R``
    and ``J`` by DLFT (:func:`_coulomb`); its status. For any other problem
    type it compiles to ``return NOT_A_COULOMB_PROBLEM``: the DLFT kernels
    are compiled only for the problems that use them. Callable from jitted
    code only."""
    raise NotImplementedError(
        "hbmfric.kernels.residuals.hbm.rigid_coulomb is for jit code"
    )


def _refuse(y, problem, R, J):
    return NOT_A_COULOMB_PROBLEM


@overload(rigid_coulomb, jit_options=JIT_OPTIONS)
def _rigid_coulomb(y, problem, R, J):
    # the body of _coulomb itself, compiled for this type only (a wrapper
    # calling a _coulomb kernel would emit the DLFT kernels once more)
    return _coulomb if is_coulomb_problem(problem) else _refuse


def _coulomb(y, problem, R, J):
    """The rigid Coulomb contact of a :class:`CoulombProblem` (on
    ``contact_pairs[0, 0]``, parameters ``law_params[0]``) by DLFT, added to
    ``R`` and ``J``: with located reversals (``AFT_EVENTS``), plus the
    linear tail of the response when ``law_params[4] = K > 0``; the classic
    sampled DLFT otherwise."""
    harmonic_numbers = problem[0]
    mass = problem[1]
    damping = problem[2]
    stiffness = problem[3]
    contact_dof = problem[5][0, 0]
    law_params = problem[7][0]
    aft_scheme = problem[8]
    inverse = problem[9]
    forward = problem[10]
    derivative = problem[11]
    n_coef = inverse.shape[1]
    omega = y[y.size - 1]
    if aft_scheme == AFT_EVENTS and law_params[4] > 0.0:
        n_tail = int(law_params[4])
        q = np.zeros(n_tail + 1, dtype=np.complex128)
        dq = np.zeros(n_tail + 1, dtype=np.complex128)
        a2, da2, ok = contact_receptance(
            mass,
            damping,
            stiffness,
            contact_dof,
            omega,
            harmonic_numbers,
            law_params[3],
            q,
            dq,
        )
        if not ok:
            return SINGULAR_RECEPTANCE
        return dlft_tail(
            law_params,
            harmonic_numbers,
            contact_dof * n_coef,
            mass[contact_dof, contact_dof],
            q,
            dq,
            a2,
            da2,
            y,
            inverse,
            forward,
            derivative,
            R,
            J,
        )
    if aft_scheme == AFT_EVENTS:
        return dlft_located(
            law_params,
            harmonic_numbers,
            contact_dof * n_coef,
            mass[contact_dof, contact_dof],
            y,
            inverse,
            forward,
            derivative,
            R,
            J,
        )
    return dlft_contact(law_params, contact_dof * n_coef, y, inverse, forward, R, J)
