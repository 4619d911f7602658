"""``branch_side="below"`` just short of the fold of a hardening resonance
(issue 14). Within about 1e-6 (relative) of the fold the continuation from
below turned back between two points that both lie short of the target, so
no sign change showed the crossing, and the first crossing found was the
one on the lower branch: 0.28 m instead of about 3.05 m."""

import pytest

import hbmfric as hf

DUFFING = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
FORCE = 0.2


@pytest.fixture(scope="module")
def fold():
    branch = hf.frf(DUFFING, FORCE, (0.5, 2.0), harmonics=9)
    return max(p.omega for p in branch.special_points() if p.kind == "fold")


@pytest.mark.parametrize("distance", [1e-3, 1e-6, 1e-8])
def test_below_just_short_of_the_fold_is_the_resonant_solution(fold, distance):
    """At the peak of a lightly damped resonance the response is in phase
    quadrature: amplitude F / (c Ω) (3.06 m here; the lower branch has
    0.28 m). Within 2 %."""
    omega = fold * (1.0 - distance)
    solution = hf.periodic_solution(
        DUFFING, FORCE, omega, harmonics=9, branch_side="below"
    )
    assert solution.converged
    quadrature = FORCE / (0.05 * omega)
    assert abs(solution.amplitude(harmonic=1) / quadrature - 1.0) < 2e-2
