"""References for validating HBM results: time integration, and exact
event-driven periodic solutions for one Jenkins contact."""

from .curve import (
    CurveError,
    branch_curve_error,
    chord_midpoints,
    curve_references,
    polyline_error,
    reference_omegas,
)
from .exact import (
    BranchErrors,
    ExactSolution,
    branch_errors,
    exact_branch,
    exact_periodic_solution,
)
from .period_map import Monodromy, monodromy
from .steady_state import SteadyState, steady_state

__all__ = [
    "BranchErrors",
    "CurveError",
    "branch_curve_error",
    "chord_midpoints",
    "curve_references",
    "polyline_error",
    "reference_omegas",
    "ExactSolution",
    "Monodromy",
    "monodromy",
    "branch_errors",
    "SteadyState",
    "exact_branch",
    "exact_periodic_solution",
    "steady_state",
]
