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


#: cases known to cover only part of their range (issue 14): the up sweep
#: turns at a fold near 0.314 and leaves at 0.3 (reported as "end of
#: frequency range reached" before), and the retrace finds no starting
#: point at 3 rad/s (Newton stalls at |R| = 8e-4 from the linear guesses
#: between three coexisting solutions). The same case twice: F = 10, k3 = 1
#: and F = 1, k3 = 100 differ by an amplitude scale.
INCOMPLETE = {"cubic ratio=10 stiffness_ratio=1", "cubic ratio=1 stiffness_ratio=100"}


def _marked(case):
    if case.name in INCOMPLETE:
        reason = "covers [0.3, 0.314] only; no start at 3 rad/s"
        return pytest.param(case, marks=pytest.mark.xfail(reason=reason, strict=True))
    return case


@pytest.mark.stress
@pytest.mark.parametrize(
    "case", [_marked(c) for c in matrix() if c not in FAST], ids=lambda c: c.name
)
def test_stress_matrix(case):
    out = run_case(case)
    assert out["known_stop"]
    assert not failures(out), failures(out)
