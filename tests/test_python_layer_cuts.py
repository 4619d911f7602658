"""The Python layer's shortcuts of stop 34 (issue 18, branch p1f7) give the
values of the long way.

- ``HBMProblem.with_harmonics`` copies the problem without ``copy.copy``
  and shares the law arrays between levels: each level's kernel problem
  equals, field by field, that of a problem built at that ``H`` from the
  system (several contacts, a 2D element with a static load, a rigid
  Coulomb contact whose law parameters depend on the level).
- ``accuracy._confirm`` skips its ratio to the rest floor where no point is
  near rest: its estimates equal the ratio's formula computed in plain
  NumPy, with points near rest and without, non-finite estimates among
  them.
"""

from __future__ import annotations

import warnings
from types import SimpleNamespace

import numpy as np
import pytest
from test_hunt_contact2d_normal import _rig

import hbmfric as hf
from hbmfric.api import _problem
from hbmfric.continuation.accuracy import _confirm
from hbmfric.results import CURVE_REST
from hbmfric.signals import half_peak_to_peak


def _build(system, force, h):
    return _problem(system, force, h, None, None, "auto", None)


def _chain():
    k = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    return hf.LinearStructure(
        np.eye(3),
        k,
        0.02 * k,
        load={0: 1.0},
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=3.0, slip_force=0.4), 1),
            hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.3), 2, 0),
        ],
    )


SYSTEMS = {
    "P1": (hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 1.0)), 0.5),
    "two Jenkins on a chain": (_chain(), 0.5),
    "2D element, static load": (_rig(), 1.0),
    "rigid Coulomb": (hf.Oscillator(1.0, 0.05, 1.0, hf.Coulomb(1.0)), 2.0),
}


def _equal(a, b) -> bool:
    if isinstance(a, tuple) or isinstance(b, tuple):
        return (
            type(a) is type(b)
            and len(a) == len(b)
            and all(_equal(x, y) for x, y in zip(a, b, strict=True))
        )
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b)
    return a == b


@pytest.mark.parametrize("name", list(SYSTEMS))
def test_levels_equal_problems_built_at_their_harmonics(name):
    system, force = SYSTEMS[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        base = _build(system, force, 7)
        for h in (3, 11, 21, 45):
            level, fresh = base.with_harmonics(h), _build(system, force, h)
            assert type(level) is type(fresh)
            assert type(level.kernel_problem) is type(fresh.kernel_problem)
            assert _equal(level.kernel_problem, fresh.kernel_problem), (name, h)
            assert np.array_equal(level.load, fresh.load)
            assert level.n_time == fresh.n_time and level.n_coef == fresh.n_coef
    # the copy keeps the base problem as it was
    again = _build(system, force, 7)
    assert _equal(base.kernel_problem, again.kernel_problem)


def _level(n_coef=8, first=0):
    rates = np.zeros(n_coef)
    rates[first::2] = np.arange(1, (n_coef - first) // 2 + 1)
    rates[first + 1 :: 2] = rates[first::2]
    hn = np.arange(0 if first else 1, (n_coef - first) // 2 + (0 if first else 1))
    if first:
        hn = np.arange(0, (n_coef - 1) // 2 + 1)
    output = np.zeros((2, 1))
    output[0, 0] = 1.0
    return SimpleNamespace(
        n_coef=n_coef,
        output=output,
        first_column=first,
        rates=rates,
        problem=SimpleNamespace(harmonic_numbers=hn),
    )


def _reference(level, points, errors, scale):
    """The ratio of ``_confirm`` (estimates relative to max(measure, rest
    floor)) in plain NumPy, every point's peak-to-peak value computed."""
    z = points[:, :-1]
    f = level.first_column
    a1 = np.hypot(z[:, f], z[:, f + 1])
    hpp = half_peak_to_peak(level.problem.harmonic_numbers, z)
    rest = CURVE_REST * scale
    m = np.where(a1 < rest, np.maximum(a1, hpp), a1)
    with np.errstate(divide="ignore", invalid="ignore"):
        factor = np.where(m > 0.0, m / np.maximum(m, rest), 1.0)
    return np.where(np.isfinite(errors), errors * factor, errors)


@pytest.mark.parametrize("first", [0, 1])
@pytest.mark.parametrize("near_rest", [False, True])
def test_confirm_ratio_equals_its_formula(first, near_rest):
    rng = np.random.default_rng(3 + first + 2 * near_rest)
    level = _level(8 + first, first)
    n = 40
    points = np.empty((n, level.n_coef + 1))
    points[:, :-1] = rng.normal(size=(n, level.n_coef))
    points[:, -1] = rng.uniform(0.5, 3.0, n)
    scale = 1.0
    if near_rest:
        points[::5, :-1] *= 1e-9  # first harmonic under CURVE_REST
    points[7, :-1] = 0.0  # at rest
    errors = rng.uniform(0.0, 0.15, n)  # none confirmed (all <= 0.2)
    errors[[3, 11]] = np.inf
    errors[13] = np.nan
    got = _confirm(None, level, None, points, errors, scale)
    want = _reference(level, points, errors, scale)
    assert np.array_equal(got, want, equal_nan=True)
    assert got is not errors
