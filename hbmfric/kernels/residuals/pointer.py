"""The residual called through its address, so that the continuation kernels
do not compile it again.

Numba compiles each kernel into its own LLVM module and links into it the
modules of every kernel it calls, then optimises and emits the whole linked
tree again. Called directly, the HBM residual (with its contact laws' AFT)
was thereby compiled once more in every kernel of the continuation chain
(:func:`~hbmfric.kernels.steps.newton.correct`,
:func:`~hbmfric.kernels.steps.truncation.truncation_change`,
:func:`~hbmfric.kernels.steps.truncation.branch_truncation`,
:func:`~hbmfric.kernels.steps.arclength.trace`). Those kernels instead take
the address of the residual's compiled code (an integer,
:func:`residual_address`, resolved in Python once per problem type and
process) and call it with :func:`call_residual`: the call follows Numba's own
calling convention (the same as a first-class function's ``jit_addr``), so
an exception in the residual propagates as from a direct call, and nothing
of the residual is linked into the caller.

The address is only valid in the process that resolved it: never store it
in anything that is pickled or cached.

Since the continuation kernels reach the residual only through its address,
nothing else in them depends on which law family a problem's type stands
for: they receive the problem as :func:`chain_problem`, so that they are
compiled once for every law family instead of once per problem type: a full
problem and a problem condensed onto one contact to ground (both solved
with dense factors) in one type,
:class:`~hbmfric.kernels.residuals.dispatch.DenseChainProblem`, which holds
both layouts and says at run time which one is the problem; any other
condensed problem in
:class:`~hbmfric.kernels.residuals.condensed.CondensedChainProblem`. The call
passes the problem by Numba's calling convention, which lays a named tuple
out by its field types alone; :func:`chain_problem` checks that those are
the problem's own (the residual's) field types.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import types
from numba.core import cgutils, errors
from numba.extending import intrinsic

from .condensed import (
    CONDENSED_TYPES,
    SINGLE_CONTACT_TYPES,
    CondensedChainProblem,
    CondensedSingleChainProblem,
    condensed_residual,
)
from .dispatch import DenseChainProblem, _is_condensed, is_dense_chain
from .hbm import ChainProblem, hbm_residual

#: the types the residual is compiled for: ``y``, ``R`` (float64, 1D,
#: C-contiguous), ``J`` (float64, 2D, C-contiguous); the problem's type is
#: the fourth
VECTOR = types.Array(types.float64, 1, "C")
MATRIX = types.Array(types.float64, 2, "C")
#: the residual's return type (the contact-state code)
STATE = types.int64


def residual_signature(problem_type):
    """Numba signature of the residual compiled for a problem of
    ``problem_type``: ``int64(y, problem, R, J)``."""
    return STATE(VECTOR, problem_type, VECTOR, MATRIX)


def residual_dispatcher(problem_type):
    """The residual kernel for problems of ``problem_type``:
    :func:`~hbmfric.kernels.residuals.condensed.condensed_residual` for a
    condensed problem, :func:`~hbmfric.kernels.residuals.hbm.hbm_residual`
    for any other (the dispatch of
    :func:`hbmfric.kernels.residuals.dispatch.residual`)."""
    if _is_condensed(problem_type):
        return condensed_residual
    return hbm_residual


#: address of the compiled residual per problem type, keyed by Numba's
#: fingerprint of the problem (its dispatcher's own key for argument types);
#: process-local
_ADDRESSES: dict = {}


def _key(problem):
    try:
        return numba._dispatcher.compute_fingerprint(problem)
    except Exception:  # a value Numba fingerprints only through typeof
        return numba.typeof(problem)


def residual_address(problem) -> int:
    """Address of the residual compiled for the type of the kernel
    ``problem``, compiling (or loading from the cache) the residual kernel
    on the first call for that type in this process.

    Parameters
    ----------
    problem : tuple
        A kernel problem (``kernel_problem`` of
        :class:`~hbmfric.hbm.HBMProblem` or
        :class:`~hbmfric.condensation.CondensedHBMProblem`).

    Returns
    -------
    int
        Address of the residual's compiled function (Numba's calling
        convention), for :func:`call_residual` with this ``problem``.
    """
    key = _key(problem)
    address = _ADDRESSES.get(key)
    if address is None:
        if type(problem) in _NOT_A_PROBLEM:
            raise TypeError(
                "residual_address takes the kernel problem itself, not its "
                "chain_problem (whose type does not name the law family)"
            )
        problem_type = numba.typeof(problem)
        dispatcher = residual_dispatcher(problem_type)
        # compiled (or loaded) for the argument types alone, the key of a
        # call from Python too: a signature with its return type would be
        # another key in Numba's cache index
        args = tuple(residual_signature(problem_type).args)
        dispatcher.compile(args)
        cres = dispatcher.overloads[args]
        if cres.signature.return_type != STATE:
            raise TypeError(
                f"the residual for {problem_type} returns "
                f"{cres.signature.return_type}, not {STATE}"
            )
        address = cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name)
        if not address:
            raise RuntimeError(f"no compiled residual found for {problem_type}")
        _ADDRESSES[key] = address
    return address


@intrinsic
def call_residual(typingctx, address, y, problem, R, J):
    """``residual(y, problem, R, J)`` through the ``address`` of its compiled
    code (:func:`residual_address` of a problem of the same type). Callable
    from jitted code only; ``y``, ``R`` must be C-contiguous float64
    vectors and ``J`` a C-contiguous float64 matrix (anything else is a
    typing error at compile time)."""
    if not isinstance(address, types.Integer):
        raise errors.TypingError(f"residual address must be an integer: {address}")
    for name, got, want in (("y", y, VECTOR), ("R", R, VECTOR), ("J", J, MATRIX)):
        if got != want:
            raise errors.TypingError(f"call_residual: {name} is {got}, not {want}")
    sig = STATE(address, y, problem, R, J)

    def call(context, builder, address, argtys, args):
        fnty = context.call_conv.get_function_type(STATE, argtys)
        fn = builder.inttoptr(address, fnty.as_pointer())
        status, out = context.call_conv.call_function(builder, fn, STATE, argtys, args)
        with cgutils.if_unlikely(builder, status.is_error):
            context.call_conv.return_status_propagate(builder, status)
        return out

    if not is_dense_chain(problem):

        def codegen(context, builder, signature, args):
            return call(context, builder, args[0], signature.args[1:], args[1:])

        return sig, codegen

    def dense(context, builder, signature, args):
        # the residual takes the member that is the problem: the condensed
        # one of one contact to ground, or the full one
        address, y, problem, R, J = args
        condensed = builder.extract_value(problem, 0)
        out = cgutils.alloca_once(builder, context.get_value_type(STATE))
        is_condensed = builder.icmp_signed("!=", condensed, condensed.type(0))
        with builder.if_else(is_condensed) as (single, full):
            for member, block in ((2, single), (1, full)):
                with block:
                    argtys = (VECTOR, signature.args[2].types[member], VECTOR, MATRIX)
                    value = builder.extract_value(problem, member)
                    builder.store(
                        call(context, builder, address, argtys, (y, value, R, J)),
                        out,
                    )
        return builder.load(out)

    return sig, dense


#: the types of :func:`chain_problem`, and of its members
_CHAIN_TYPES = (DenseChainProblem, CondensedChainProblem)
_NOT_A_PROBLEM = (*_CHAIN_TYPES, ChainProblem, CondensedSingleChainProblem)


def _empty_members() -> tuple:
    """The members of a :class:`DenseChainProblem` that are not the problem:
    a :class:`ChainProblem` and a :class:`CondensedSingleChainProblem` of
    empty arrays (one row for ``rounding``) and zero scalars, with the
    field types of the problems' own (checked by :func:`chain_problem`).
    Never read: the kernels read the member the problem is in."""
    i1, f1, c1 = np.zeros(0, np.int64), np.zeros(0), np.zeros(0, np.complex128)
    i2, f2, c2 = (np.zeros((0, 0), t) for t in (np.int64, float, np.complex128))
    f3, c3 = np.zeros((0, 0, 0)), np.zeros((0, 0, 0), np.complex128)
    full = ChainProblem(i1, f2, f2, f2, f1, i2, i1, f2, 0, f2, f2, f2)
    single = CondensedSingleChainProblem(
        harmonic_numbers=i1,
        contact_shapes=f1,
        omega_squared=f1,
        modal_damping=f1,
        modal_load=f2,
        law_code=0,
        law_params=f1,
        aft_scheme=0,
        inverse=f2,
        forward=f2,
        derivative=f2,
        method=0,
        contact_dof=0,
        mass=f2,
        damping=f2,
        stiffness=f2,
        load=f2,
        contact_mass=0.0,
        coordinate_pairs=i2,
        law_codes=i1,
        law_rows=f2,
        coordinate_shapes=f2,
        state_left=c2,
        state_right=c2,
        state_poles=c1,
        state_load=c2,
        state_output=c1,
        state_low=i1,
        state_series=f3,
        state_split=0.0,
        output_dof=0,
        drawn_cache=f2,
        rounding=np.zeros(1),
        solver=(f2, i1, f2, f1, f3, i2, f1, f1),
        kept_inverse=c3,
    )
    return full, single


#: :func:`_empty_members` and their Numba types, made on first use
_EMPTY: list = []

#: problem keys (as :data:`_ADDRESSES`) whose :func:`chain_problem` has
#: the problem's own field types; process-local
_CHAIN_CHECKED: set = set()


def chain_problem(problem):
    """The kernel ``problem`` as the continuation kernels take it, one type
    for every law family, so that those kernels compile once for all of
    them: a :class:`~hbmfric.kernels.residuals.dispatch.DenseChainProblem`
    holding its fields for a full problem or one condensed onto one contact
    to ground (:data:`~hbmfric.kernels.residuals.condensed.
    SINGLE_CONTACT_TYPES`), whose corrector solves with dense factors; its
    fields in :class:`~hbmfric.kernels.residuals.condensed.
    CondensedChainProblem` for any other condensed one. They call the
    residual through :func:`residual_address` of ``problem`` itself (its
    own type's residual).

    Parameters
    ----------
    problem : tuple
        A kernel problem (``kernel_problem`` of
        :class:`~hbmfric.hbm.HBMProblem` or
        :class:`~hbmfric.condensation.CondensedHBMProblem`), or a chain
        problem (returned as it is).

    Returns
    -------
    DenseChainProblem or CondensedChainProblem
        The same field values (in the member of a ``DenseChainProblem``
        its ``condensed`` flag names).

    Raises
    ------
    TypeError
        If the chain type's fields would not have the problem's own Numba
        types (the residual called through its address would then read
        them wrongly), or the ``DenseChainProblem`` not the one Numba type
        of every other (it would compile the continuation again); checked
        once per problem type and process.
    """
    kind = type(problem)
    if kind in _CHAIN_TYPES:
        return problem
    if not _EMPTY:
        full, single = _empty_members()
        _EMPTY.extend((full, single, numba.typeof(full), numba.typeof(single)))
    if kind in SINGLE_CONTACT_TYPES:
        own = CondensedSingleChainProblem(*problem)
        view = DenseChainProblem(1, _EMPTY[0], own)
        empty = _EMPTY[3]
    elif kind in CONDENSED_TYPES:
        own = view = CondensedChainProblem(*problem)
        empty = None
    else:
        own = ChainProblem(*problem)
        view = DenseChainProblem(0, own, _EMPTY[1])
        empty = _EMPTY[2]
    key = _key(problem)
    if key not in _CHAIN_CHECKED:
        mine, chain = numba.typeof(problem), numba.typeof(own)
        if tuple(mine.types) != tuple(chain.types):
            raise TypeError(
                f"the continuation's problem type {chain} does not have the "
                f"field types of {mine}"
            )
        if empty is not None and chain != empty:
            raise TypeError(
                f"the dense chain's member {chain} does not have the field "
                f"types of its empty member {empty} (another compilation of "
                "the continuation kernels)"
            )
        _CHAIN_CHECKED.add(key)
    return view
