"""Arc-length step control."""

from __future__ import annotations

import math

import numpy as np

from ..kernels.steps import arclength as _arclength
from .options import ContinuationOptions


class StepController:
    """Adapts the arc-length step to the corrector's effort.

    Contract: :meth:`accept` returns the next step after a converged,
    accepted corrector run; :meth:`reject` returns the shrunk step after a
    failed or rejected one. Neither clips below ``min_step``: the caller
    stops when the step falls under it. The rule itself is the compiled
    :func:`hbmfric.kernels.steps.arclength.next_step`, which the continuation
    kernels use.
    """

    def __init__(self, options: ContinuationOptions) -> None:
        self.options = options
        o = options
        self._settings = np.zeros(_arclength.N_SETTINGS)
        self._settings[_arclength.MAX_STEP] = o.max_step
        self._settings[_arclength.MAX_ANGLE] = o.max_angle
        self._settings[_arclength.GROWTH] = o.growth
        self._settings[_arclength.SHRINK] = o.shrink
        self._settings[_arclength.TARGET_NEWTON] = o.target_newton

    def accept(self, step: float, iterations: int, angle: float) -> float:
        """Next step after success with ``iterations`` Newton iterations and a
        tangent turn of ``angle`` rad."""
        new = _arclength.next_step(
            float(step), int(iterations), float(angle), 0.0, self._settings
        )
        return float(new)

    def reject(self, step: float) -> float:
        """Step after a rejection."""
        return step * self.options.shrink

    @staticmethod
    def angle(t1, t2) -> float:
        """Angle between two unit tangents, rad."""
        c = float(np.dot(t1, t2))
        return math.acos(max(-1.0, min(1.0, c)))
