"""At H = 1 (or H = 2 of an odd-symmetric system) no truncation estimate is
formed (there is no smaller level to compare with): the warning says that
nothing vouches for the solution instead of "estimated truncation error
inf" (stop 31)."""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf


def _osc():
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


@pytest.mark.parametrize("harmonics", [1, 2])
def test_one_frequency_without_an_estimate_says_so(harmonics):
    with pytest.warns(hf.AccuracyWarning, match="could not be estimated") as record:
        sol = hf.periodic_solution(_osc(), 0.5, 1.2, harmonics=harmonics)
    assert sol.converged
    assert not any("error inf" in str(w.message) for w in record)


def test_branch_without_estimates_says_how_many():
    with pytest.warns(hf.AccuracyWarning, match="without an estimate") as record:
        branch = hf.frf(_osc(), 0.5, (0.5, 3.0), harmonics=1)
    n = int(np.count_nonzero(np.isinf(branch.truncation_error)))
    assert n == branch.n_points
    assert any(f"{n} of them without an estimate" in str(w.message) for w in record)
