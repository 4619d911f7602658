"""Numerical stress tests: extreme parameters, unit scales, harmonic counts
and sweep directions (case matrix in ``tests/stress/cases.py``).

Default run: the extremes of each axis (``FAST``). Full matrix:
``python -m pytest -m stress tests/stress``.
"""

import pytest

from .cases import FAST, failures, matrix, run_case


@pytest.mark.parametrize("case", FAST, ids=lambda c: c.name)
def test_stress_fast(case):
    out = run_case(case)
    assert not failures(out), failures(out)
    assert out["spot"]  # the time-integration check ran


@pytest.mark.stress
@pytest.mark.parametrize(
    "case", [c for c in matrix() if c not in FAST], ids=lambda c: c.name
)
def test_stress_matrix(case):
    out = run_case(case)
    assert out["known_stop"]
    assert not failures(out), failures(out)
