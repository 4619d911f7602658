"""Warning and exception classes of hbmfric.

A public call either returns a right answer or says loudly that it could
not: by one of these warnings (which a user can turn into errors with
``warnings.simplefilter("error", hf.HbmfricWarning)``) or by an exception.
A flag on a result (``converged``, ``stop_reason``, ``coverage``) is never
the only signal.
"""

from __future__ import annotations


class HbmfricWarning(UserWarning):
    """Base class of every warning hbmfric issues."""


class ConvergenceWarning(HbmfricWarning):
    """A solve did not meet its tolerances; the result is not a solution."""


class CoverageWarning(HbmfricWarning):
    """A branch covers only part of the requested frequency range."""


class AccuracyWarning(HbmfricWarning):
    """A result is a solution, but its estimated error exceeds the tolerance
    asked for (truncation in harmonics, curve between points, sampling)."""


class SingularPointWarning(HbmfricWarning):
    """A branch met a singular point of the HBM equations that is not a fold
    (the path turned back onto itself) and was traced up to it from both
    ends of the range; the points are solutions, the point itself is not
    passed (``Branch.info["singular_points"]``)."""


class CacheWarning(HbmfricWarning):
    """The Numba cache cannot be used (no writable location); kernels are
    compiled in every process."""


class StudyWarning(HbmfricWarning):
    """Some parameter sets of a study failed or warned; the others are
    kept (:attr:`hbmfric.study.StudyResult.failures` and ``.warned``)."""


class DataWarning(HbmfricWarning):
    """Input data read from a file look misread (for example decimal commas
    in a comma-separated file); the values returned are what the file says
    under the documented format, which may not be what was meant."""


class CostWarning(HbmfricWarning):
    """A call is about to take long (minutes): issued before the work, with
    the estimated time and a cheaper way, so that a long computation is not
    mistaken for a hang."""


class ConvergenceError(RuntimeError):
    """Raised instead of :class:`ConvergenceWarning` where the user asked
    for an exception (``on_failure="raise"``)."""


__all__ = [
    "AccuracyWarning",
    "CacheWarning",
    "CostWarning",
    "ConvergenceError",
    "ConvergenceWarning",
    "CoverageWarning",
    "DataWarning",
    "HbmfricWarning",
    "StudyWarning",
]
