"""Stability of the stress matrix's single-DOF rows (issue 16): the
verdicts of ``exponents="auto"`` (eigenvalues at a few points) equal
those of Hill's eigenvalues at every point, point by point, for every
law of the matrix (the rigid Coulomb contact is refused by stability),
at the base case and at a stronger forcing."""

import warnings

import numpy as np
import pytest

import hbmfric as hf

from .cases import Case, build

LAWS = ("jenkins", "cubic", "menq", "iwan", "dahl", "roughness")
ROWS = [Case(law=law) for law in LAWS] + [Case(law=law, ratio=0.9) for law in LAWS]


@pytest.mark.slow
@pytest.mark.parametrize("case", ROWS, ids=lambda c: c.name)
def test_stress_row_sparse_verdicts_equal_every_point(case):
    system, force, omega = build(case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, force, omega, case.harmonics)
    assert branch.info["odd_only"]
    # Hill's scheme (a Dahl branch's own default is the monodromy since
    # stop 33, tests/test_dahl_stability.py)
    auto = branch.stability(method="hill")
    computed = auto.computed.copy()
    stable = auto.stable.copy()
    branch._stability = None
    full = branch.stability(exponents="all", method="hill")
    np.testing.assert_array_equal(stable, full.stable)
    assert computed.sum() <= max(8, len(branch) // 8)
    for i in full.changes():
        assert computed[i - 1] and computed[i]
