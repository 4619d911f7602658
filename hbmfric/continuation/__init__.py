"""Pseudo-arclength continuation: options, step control, the iterator."""

from .adaptive import AdaptiveContinuation
from .options import ContinuationOptions
from .palc import Continuation, ContinuationState
from .step_control import StepController

__all__ = [
    "AdaptiveContinuation",
    "Continuation",
    "ContinuationOptions",
    "ContinuationState",
    "StepController",
]
