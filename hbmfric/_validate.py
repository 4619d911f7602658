"""Input checks for the public edge: clear messages that name the parameter,
``TypeError`` for a wrong type (a string or a bool where a number belongs),
``ValueError`` for a wrong value with the allowed range. Kernels trust their
input."""

import math
import numbers

import numpy as np


def real_number(name: str, value) -> float:
    """Return ``value`` as a float if it is a real number.

    Numbers are ``int``, ``float``, NumPy integer and floating scalars and
    0-d arrays of those; ``bool``, strings, complex numbers and sequences
    are not (``TypeError`` naming ``name``).
    """
    if isinstance(value, np.ndarray) and value.ndim == 0:
        ok = value.dtype.kind in "iuf"
    else:
        ok = isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)
    if not ok:
        raise TypeError(
            f"{name} must be a real number (int or float), got "
            f"{type(value).__name__} {value!r}"
        )
    return float(value)


def finite_float(name: str, value, *, low=None, high=None, low_open=False) -> float:
    """Return ``value`` as a finite float, checking ``low <= value <= high``.

    With ``low_open=True`` the lower bound is strict (``value > low``).

    Raises
    ------
    TypeError
        If ``value`` is not a real number (:func:`real_number`).
    ValueError
        If it is NaN, infinite or out of range.
    """
    x = real_number(name, value)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {x}")
    if low is not None:
        if low_open and not x > low:
            raise ValueError(f"{name} must be > {low}, got {x}")
        if not low_open and not x >= low:
            raise ValueError(f"{name} must be >= {low}, got {x}")
    if high is not None and not x <= high:
        raise ValueError(f"{name} must be <= {high}, got {x}")
    return x


def positive_int(name: str, value, *, low: int = 1) -> int:
    """Return ``value`` as an int ``>= low``."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} must be an integer >= {low}, got {value!r}")
    if value < low:
        raise ValueError(f"{name} must be an integer >= {low}, got {value}")
    return int(value)


def finite_array(name: str, value, *, ndim: int = 1) -> np.ndarray:
    """Return ``value`` as a C-contiguous float64 array with no NaN or inf."""
    a = np.ascontiguousarray(value, dtype=np.float64)
    if a.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-d array, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must contain only finite values (no NaN or inf)")
    return a


def dof_index(dof, n_dof: int) -> int:
    """Return ``dof`` as an int in ``[0, n_dof)``."""
    if isinstance(dof, bool) or not isinstance(dof, int | np.integer):
        raise ValueError(f"dof must be an integer in [0, {n_dof - 1}], got {dof!r}")
    if not 0 <= dof < n_dof:
        raise ValueError(f"dof must be in [0, {n_dof - 1}], got {dof}")
    return int(dof)
