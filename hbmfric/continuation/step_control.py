"""Arc-length step control."""

from __future__ import annotations

import math

import numpy as np

from .options import ContinuationOptions


class StepController:
    """Adapts the arc-length step to the corrector's effort.

    Contract: :meth:`accept` returns the next step after a converged,
    accepted corrector run; :meth:`reject` returns the shrunk step after a
    failed or rejected one. Neither clips below ``min_step``: the caller
    stops when the step falls under it.
    """

    def __init__(self, options: ContinuationOptions) -> None:
        self.options = options

    def accept(self, step: float, iterations: int, angle: float) -> float:
        """Next step after success with ``iterations`` Newton iterations and a
        tangent turn of ``angle`` rad."""
        o = self.options
        factor = min(o.growth, o.target_newton / max(iterations, 1))
        if angle > 0.0:
            factor = min(factor, 0.8 * o.max_angle / angle)
        factor = max(factor, o.shrink)
        return min(step * factor, o.max_step)

    def reject(self, step: float) -> float:
        """Step after a rejection."""
        return step * self.options.shrink

    @staticmethod
    def angle(t1, t2) -> float:
        """Angle between two unit tangents, rad."""
        c = float(np.dot(t1, t2))
        return math.acos(max(-1.0, min(1.0, c)))
