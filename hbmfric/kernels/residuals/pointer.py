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
for: they receive the problem as :func:`chain_problem` (the same fields in
one type per residual, full or condensed), so that they are compiled once
for every law family instead of once per problem type. The call passes the
problem by Numba's calling convention, which lays a named tuple out by its
field types alone; :func:`chain_problem` checks that those are the problem's
own (the residual's) field types.
"""

from __future__ import annotations

import numba
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
from .dispatch import _is_condensed
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
        if type(problem) in _CHAIN_TYPES:
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

    def codegen(context, builder, signature, args):
        argtys = signature.args[1:]
        fnty = context.call_conv.get_function_type(STATE, argtys)
        fn = builder.inttoptr(args[0], fnty.as_pointer())
        status, out = context.call_conv.call_function(
            builder, fn, STATE, argtys, args[1:]
        )
        with cgutils.if_unlikely(builder, status.is_error):
            context.call_conv.return_status_propagate(builder, status)
        return out

    return sig, codegen


#: the types of :func:`chain_problem`
_CHAIN_TYPES = (ChainProblem, CondensedChainProblem, CondensedSingleChainProblem)

#: problem keys (as :data:`_ADDRESSES`) whose :func:`chain_problem` has
#: the problem's own field types; process-local
_CHAIN_CHECKED: set = set()


def chain_problem(problem):
    """The kernel ``problem`` as the continuation kernels take it: its
    fields in :class:`~hbmfric.kernels.residuals.hbm.ChainProblem` (a full
    problem) or :class:`~hbmfric.kernels.residuals.condensed.
    CondensedChainProblem` (a condensed one;
    :class:`~hbmfric.kernels.residuals.condensed.CondensedSingleChainProblem`
    for one contact to ground), one type for every law family, so that
    those kernels compile once for all of them. They call the
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
    ChainProblem, CondensedChainProblem or CondensedSingleChainProblem
        The same field values.

    Raises
    ------
    TypeError
        If the chain type's fields would not have the problem's own Numba
        types (the residual called through its address would then read
        them wrongly; cannot happen for the same values, checked once per
        problem type and process).
    """
    kind = type(problem)
    if kind in _CHAIN_TYPES:
        return problem
    if kind in SINGLE_CONTACT_TYPES:
        view = CondensedSingleChainProblem(*problem)
    elif kind in CONDENSED_TYPES:
        view = CondensedChainProblem(*problem)
    else:
        view = ChainProblem(*problem)
    key = _key(problem)
    if key not in _CHAIN_CHECKED:
        own, chain = numba.typeof(problem), numba.typeof(view)
        if tuple(own.types) != tuple(chain.types):
            raise TypeError(
                f"the continuation's problem type {chain} does not have the "
                f"field types of {own}"
            )
        _CHAIN_CHECKED.add(key)
    return view
