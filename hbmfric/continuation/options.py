"""Options of the Newton corrector and of pseudo-arclength continuation."""

from __future__ import annotations

from dataclasses import dataclass

from .._validate import finite_float, positive_int


@dataclass(frozen=True)
class ContinuationOptions:
    """Settings of a continuation run (arc lengths in scaled variables).

    Scaled variables divide Ω by the width of the frequency range and every
    displacement coefficient by the peak linear response over the range, so
    that a whole FRF has an arc length of a few units.

    Parameters
    ----------
    initial_step, min_step, max_step : float
        Arc-length step: first, smallest allowed (below it the run stops),
        largest.
    max_steps : int
        Limit on accepted plus rejected steps.
    tol_residual : float
        Newton convergence: ``max |R| <= tol_residual * max(|F|, 1e-300)``.
    tol_step : float
        Newton convergence: scaled update below this.
    max_newton : int
        Newton iterations per corrector call.
    target_newton : int
        Iteration count the step controller aims at: fewer → longer steps.
    max_angle : float
        Largest angle (rad) between successive tangents; a larger turn
        rejects the step.
    max_correction : float
        Largest scaled distance between predictor and corrected point,
        relative to the step; a larger one is suspect (branch jumping) and
        the step is rejected.
    corner_step : float
        Contact transitions (stick to slip) put corners into FRF branches:
        the tangent turns by a finite angle. A converged step no longer than
        this is accepted whatever the turn (and recorded as a corner) if the
        corrected point lies within ``2 * step`` of the predictor, or (a
        sharp corner, where the new piece leaves at nearly a right angle)
        within ``corner_step`` of the current point along the new tangent.
    growth, shrink : float
        Largest step growth factor after success; factor after rejection.
    curve_tolerance : float or None
        Largest estimated distance between the branch and the straight
        line joining two consecutive points, in the plane of Ω and the
        first-harmonic amplitude of the contact DOF (linear axes; measured
        relative to the amplitude, as read off a log axis; a segment drawn
        on log-log axes is straight in the logarithms and can be several
        times further off: :attr:`hbmfric.Branch.curve_errors`), from the
        points' tangents
        (:func:`hbmfric.kernels.steps.arclength.chord_error`); a longer step is
        rejected and the next step is sized to keep below it. With
        ``harmonics="auto"`` the points' own estimated truncation error is
        charged against it: the chord gets the tolerance less the point's
        estimate, at least a quarter of it
        (:func:`hbmfric.kernels.steps.arclength.chord_target`), so that chord
        and points together stay within it. The first step of a run is an
        eighth of ``initial_step``. None or 0: off (steps from the
        corrector's effort and the tangent turn alone).
    """

    initial_step: float = 0.02
    min_step: float = 1e-7
    max_step: float = 0.08
    max_steps: int = 5000
    tol_residual: float = 1e-10
    tol_step: float = 1e-9
    max_newton: int = 12
    target_newton: int = 4
    max_angle: float = 0.3
    max_correction: float = 0.5
    corner_step: float = 1e-3
    growth: float = 2.0
    shrink: float = 0.5
    curve_tolerance: float | None = 1e-4

    def __post_init__(self) -> None:
        for name in ("initial_step", "min_step", "max_step", "tol_residual"):
            finite_float(name, getattr(self, name), low=0.0, low_open=True)
        finite_float("tol_step", self.tol_step, low=0.0, low_open=True)
        if not self.min_step <= self.initial_step <= self.max_step:
            raise ValueError(
                "steps must satisfy min_step <= initial_step <= max_step, got "
                f"{self.min_step}, {self.initial_step}, {self.max_step}"
            )
        positive_int("max_steps", self.max_steps)
        positive_int("max_newton", self.max_newton, low=2)
        positive_int("target_newton", self.target_newton)
        finite_float("max_angle", self.max_angle, low=0.0, low_open=True, high=3.14)
        finite_float("max_correction", self.max_correction, low=0.0, low_open=True)
        finite_float("corner_step", self.corner_step, low=0.0)
        finite_float("growth", self.growth, low=1.0)
        finite_float("shrink", self.shrink, low=0.0, low_open=True, high=0.99)
        if self.curve_tolerance is not None:
            finite_float("curve_tolerance", self.curve_tolerance, low=0.0)
