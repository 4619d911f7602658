"""One residual entry point for the Newton kernels, dispatched at compile
time on the type of the problem: a :class:`~hbmfric.kernels.condensed.
CondensedProblem` goes to the condensed residual, any other problem tuple
to the full HBM residual :func:`hbmfric.kernels.hbm.hbm_residual`.

Numba compiles the caller once per problem type, so the dispatch costs
nothing at run time.
"""

from numba import types
from numba.extending import overload

from .._jit import CACHE
from .condensed import CondensedProblem, condensed_residual
from .hbm import hbm_residual


def residual(y, problem, R, J):
    """Residual and Jacobian of ``problem`` at ``y = [X, Ω]`` into ``R``,
    ``J``; returns the AFT contact-state code. Callable from jitted code
    only (see :func:`hbmfric.kernels.hbm.hbm_residual` for the contract)."""
    raise NotImplementedError("hbmfric.kernels.residual.residual is for jit code")


def _is_condensed(problem) -> bool:
    return (
        isinstance(problem, types.BaseNamedTuple)
        and problem.instance_class is CondensedProblem
    )


@overload(residual, jit_options={"cache": CACHE, "nogil": True})
def _residual(y, problem, R, J):
    if _is_condensed(problem):

        def condensed(y, problem, R, J):
            return condensed_residual(y, problem, R, J)

        return condensed

    def full(y, problem, R, J):
        return hbm_residual(y, problem, R, J)

    return full


def rounding_level(problem):
    """Rounding level (N) of the last residual of ``problem`` beyond the
    generic :func:`hbmfric.kernels.newton.rounding_floor`: the level a
    condensed problem on several contact coordinates reports (its ``D =
    G⁻¹`` carries the condition number of ``G``), 0 for any other problem.
    Callable from jitted code only."""
    raise NotImplementedError("hbmfric.kernels.residual.rounding_level is for jit code")


@overload(rounding_level, jit_options={"cache": CACHE, "nogil": True})
def _rounding_level(problem):
    if _is_condensed(problem):

        def condensed(problem):
            return problem.rounding[0]

        return condensed

    def full(problem):
        return 0.0

    return full
