"""Stress rows for stop 33: loops the modified Dahl law does or does not
describe, with 0-5 % force noise.

Before stop 33 ``hf.identify.modified_dahl`` fitted every record quietly:
a Jenkins loop came back with negative envelope slopes (-2e4 N/m where the
slip plateaus are flat) and a residual a thousand times the record's noise.
Each row builds a loop by plain NumPy (``tests/naive.py``'s Jenkins march;
the exact exponential branches of the Dahl law), adds noise and checks
that the fit warns exactly when the record is not a Dahl loop (a loop too
noisy for the fit may be refused instead, as documented).

Run with ``python -m pytest -m stress tests/stress/test_stop33_identify.py``.
"""

from __future__ import annotations

import warnings

import pytest

import hbmfric as hf
from tests.naive import jenkins_march
from tests.test_identify import TRUE, _exact_loop, _noisy, _record

pytestmark = pytest.mark.stress

NOISES = [0.0, 0.01, 0.03, 0.05]


def _said(u, f):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            hf.identify.modified_dahl(u, f)
        except ValueError as exc:
            assert "too noisy" in str(exc)
            return None
    return any(issubclass(w.category, hf.AccuracyWarning) for w in caught)


@pytest.mark.parametrize("kt, fs", [(2e4, 60.0), (1e5, 150.0), (1e6, 150.0)])
@pytest.mark.parametrize("noise", NOISES)
def test_jenkins_loops_are_said(kt, fs, noise):
    u = _record(4.3)
    f = jenkins_march(u - 2e-3, kt, fs)[0]
    assert _said(*_noisy(u, f, noise, 0.005 if noise else 0.0, 3)) is True


@pytest.mark.parametrize("amplitude", [3e-4, 1e-3, 4e-3, 2e-2])
@pytest.mark.parametrize("noise", NOISES)
@pytest.mark.parametrize("seed", [0, 1])
def test_dahl_loops_are_not(amplitude, noise, seed):
    u = _record(4.3, amplitude=amplitude)
    f = _exact_loop(u, **TRUE)
    assert _said(*_noisy(u, f, noise, 0.005 if noise else 0.0, seed)) is not True
