"""``hf.periodic_solution`` with its default ``harmonics="auto"`` on a
structure with a 2D element condensed by default (hunt35, stop 34).

The ladder's measures read each element's normal displacement with the
weights of :func:`~hbmfric.continuation.accuracy.normal_outputs`, which
for a condensed problem are over the contact coordinates, applied to the
coefficients of every DOF: on main the default call raised ``ValueError:
matmul ... mismatch`` for any such structure. Reference: the full
(uncondensed) auto solve, whose measures read the DOFs: the same top
harmonic and every coefficient to 1e-8.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf


def _structure():
    M = np.diag([1.0, 1.1, 1.2, 1.3])
    K = np.array(
        [
            [2.0, -1.0, 0.0, 0.0],
            [-1.0, 2.0, -1.0, 0.0],
            [0.0, -1.0, 2.0, -1.0],
            [0.0, 0.0, -1.0, 1.0],
        ]
    )
    element = hf.Contact2D(
        tangential_stiffness=1.0,
        normal_stiffness=2.0,
        friction_coefficient=0.3,
        preload=0.05,
    )
    return hf.LinearStructure(
        M,
        K,
        rayleigh=(0.01, 0.02),
        contacts=[hf.Contact(element, 1, normal=2)],
        load={3: 1.0},
    )


@pytest.mark.parametrize("omega", [0.5, 0.8])
def test_default_call_matches_the_full_auto_solve(omega):
    s = _structure()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        a = hf.periodic_solution(s, 0.1, omega)
        b = hf.periodic_solution(s, 0.1, omega, condense=False)
    assert a.converged and b.converged
    assert a.harmonic_numbers[-1] == b.harmonic_numbers[-1] > 7
    scale = np.max(np.abs(b.coefficients))
    assert np.max(np.abs(a.coefficients - b.coefficients)) < 1e-8 * scale
