"""One residual entry point for jitted code, dispatched at compile
time on the type of the problem: a :class:`~hbmfric.kernels.residuals.condensed.
CondensedProblem` (or another of :data:`~hbmfric.kernels.residuals.condensed.
CONDENSED_TYPES`) goes to the condensed residual, any other problem
tuple to the full HBM residual :func:`hbmfric.kernels.residuals.hbm.hbm_residual`;
and the other problem-dependent pieces of the Newton kernels
(:func:`rounding_level`, :func:`drawn_output`).

The continuation kernels do not call :func:`residual`: they call the
residual through its address (:mod:`hbmfric.kernels.residuals.pointer`), so
that they do not link in, optimise and emit the whole residual once more
each (each compiled kernel emits machine code for all it calls).
"""

from numba import types
from numba.extending import overload

from .condensed import (
    CONDENSED_TYPES,
    condensed_residual,
    coordinates_drawn,
    is_single_contact,
)
from .hbm import JIT_OPTIONS, hbm_residual


def residual(y, problem, R, J):
    """Residual and Jacobian of ``problem`` at ``y = [X, Ω]`` into ``R``,
    ``J``; returns the AFT contact-state code. Callable from jitted code
    only (see :func:`hbmfric.kernels.residuals.hbm.hbm_residual` for the contract)."""
    raise NotImplementedError(
        "hbmfric.kernels.residuals.dispatch.residual is for jit code"
    )


def _is_condensed(problem) -> bool:
    return (
        isinstance(problem, types.BaseNamedTuple)
        and problem.instance_class in CONDENSED_TYPES
    )


def _on_coordinates(problem) -> bool:
    """Is the Numba type ``problem`` a condensed problem that may stand on
    several contact coordinates (every condensed type but those of one
    contact to ground, :func:`~hbmfric.kernels.residuals.condensed.
    is_single_contact`)? Their continuation kernels compile the iterative
    solvers and the drawn output of several coordinates; for one contact
    to ground those are the full problem's."""
    return _is_condensed(problem) and not is_single_contact(problem)


@overload(residual, jit_options=JIT_OPTIONS)
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
    generic :func:`hbmfric.kernels.steps.newton.rounding_floor`: the level a
    condensed problem on several contact coordinates reports (its ``D =
    G⁻¹`` carries the condition number of ``G``), 0 for any other problem.
    Callable from jitted code only."""
    raise NotImplementedError(
        "hbmfric.kernels.residuals.dispatch.rounding_level is for jit code"
    )


@overload(rounding_level, jit_options=JIT_OPTIONS)
def _rounding_level(problem):
    if _is_condensed(problem):

        def condensed(problem):
            return problem.rounding[0]

        return condensed

    def full(problem):
        return 0.0

    return full


def drawn_output(problem, y, t, scale, column, coefficients):
    """What the curve rule draws at a solution ``y`` with unit tangent
    ``t`` when it is not the unknown at ``column``: ``(True, Ω, dΩ/ds, a,
    da/ds, |dX/ds|², n_coef)`` of the output DOF recovered from the contact
    coordinates of a condensed problem, its coefficients into
    ``coefficients``
    (:func:`hbmfric.kernels.residuals.condensed.coordinates_drawn`),
    ``(False, 0, 0, 0, 0, 0, 0)`` for any other problem. Callable from jitted
    code only."""
    raise NotImplementedError("drawn_output is for jit code")


@overload(drawn_output, jit_options=JIT_OPTIONS)
def _drawn_output(problem, y, t, scale, column, coefficients):
    # one contact to ground: coordinates_drawn returns False at run time
    if _on_coordinates(problem):

        def condensed(problem, y, t, scale, column, coefficients):
            return coordinates_drawn(problem, y, t, scale, column, coefficients)

        return condensed

    def full(problem, y, t, scale, column, coefficients):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0

    return full
