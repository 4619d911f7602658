"""Pseudo-arclength continuation: options, step control, the iterator."""

from .options import ContinuationOptions
from .palc import Continuation, ContinuationState
from .step_control import StepController

__all__ = ["Continuation", "ContinuationOptions", "ContinuationState", "StepController"]
