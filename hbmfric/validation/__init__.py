"""Time-integration reference for validating HBM results."""

from .steady_state import SteadyState, steady_state

__all__ = ["SteadyState", "steady_state"]
