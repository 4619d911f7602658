"""Stability changes located on the time-domain monodromy (issue 16).

A branch whose stability comes from the monodromy (a contact with memory
on several DOFs, ``Stability.criterion == "monodromy"``) used to have its
changes located with Hill's exponents, which disagree with the monodromy
there and keep one sign over the interval: "not located". They are now
located on the monodromy's largest multiplier.
"""

import warnings

import numpy as np
import pytest
from stability_cases import friction_duffing

import hbmfric as hf
from hbmfric.bifurcation import BRANCH_POINT, FOLD, locate_special_points
from hbmfric.stability import NEUTRAL_TOLERANCE, stability_of_points


@pytest.mark.slow
def test_raw_monodromy_change_located_next_to_the_fold():
    """Two-DOF friction Duffing: the monodromy's own verdict changes at the
    first fold (between its point and the one before; with a virgin slider
    at the start, before the contact law was put on the orbit's loop, four
    points after it, and the verdicts were snapped onto the fold). Located
    on the monodromy, the change is a branch point (a real multiplier
    through +1, ``|μ| = 1 + NEUTRAL_TOLERANCE``), within the interval, and
    at the fold located independently (the Ω tangent's zero) up to the
    monodromy's error near a fold (2e-5 relative, docs/stability.md)."""
    system = friction_duffing(second_mass=0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(system, 0.2, (0.5, 2.5), harmonics=15)
    f0 = int(branch.folds[0])
    idx = np.arange(f0 - 4, f0 + 11)
    common = dict(n_time=branch.info["n_time"], aft=branch.info["aft"], symmetric=True)
    h = np.full(len(branch), 15)
    raw = stability_of_points(
        system,
        0.2,
        branch.omega[idx],
        branch.harmonic_numbers,
        branch.coefficients[idx],
        h[idx],
        method="monodromy",
        **common,
    )
    changes = idx[raw.changes()]
    assert changes.size == 1 and changes[0] == f0  # at the fold
    args = (system, 0.2, branch.omega, branch.harmonic_numbers, branch.coefficients, h)
    no_fold = np.zeros(0, dtype=np.int64)
    (point,) = locate_special_points(
        *args, no_fold, changes, stability_method="monodromy", **common
    )
    (fold,) = locate_special_points(*args, branch.folds[:1], None, **common)
    assert point.kind == BRANCH_POINT and fold.kind == FOLD
    i = int(changes[0])
    assert point.index == i
    lo, hi = sorted(branch.omega[i - 1 : i + 1])
    assert lo <= point.omega <= hi
    assert abs(point.omega - fold.omega) <= 5e-5 * fold.omega
    assert abs(point.multiplier.imag) <= 1e-3
    assert abs(abs(point.multiplier) - (1.0 + NEUTRAL_TOLERANCE)) <= 1e-6
    assert point.multiplier.real > 0.0
