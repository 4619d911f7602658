"""A stability change located on the time-domain monodromy a few points
past a fold is that fold's change, not a separate branch point (issue 16,
stop 27: once the fold snap stopped overriding computed verdicts, the
two-DOF friction Duffing at H = 15 reported its fold at point 288 without
a change and a "branch point" at 292, 3.6e-6 rad/s past it)."""

import numpy as np

from hbmfric.bifurcation import (
    BRANCH_POINT,
    FOLD,
    FOLD_REACH,
    PERIOD_DOUBLING,
    SpecialPoint,
    _fold_changes_on_monodromy,
)


def _point(kind, index, omega, multiplier=None, stability_omega=None):
    return SpecialPoint(
        kind,
        index,
        omega,
        np.arange(3),
        np.zeros((1, 5)),
        multiplier=multiplier,
        stability_omega=stability_omega,
    )


def test_branch_point_next_to_a_fold_becomes_its_change():
    fold = _point(FOLD, 288, 1.2345)
    bp = _point(BRANCH_POINT, 292, 1.2345036, multiplier=1.000001 + 0j)
    out = _fold_changes_on_monodromy([fold, bp])
    assert [p.kind for p in out] == [FOLD]
    assert out[0].stability_omega == 1.2345036
    assert out[0].multiplier == 1.000001 + 0j
    assert out[0].omega == 1.2345  # the fold's own Ω is kept


def test_far_or_other_kinds_or_claimed_folds_are_left_alone():
    far = [
        _point(FOLD, 100, 1.0),
        _point(BRANCH_POINT, 100 + FOLD_REACH + 1, 1.1, multiplier=1.0 + 0j),
    ]
    assert [p.kind for p in _fold_changes_on_monodromy(far)] == [FOLD, BRANCH_POINT]
    doubling = [
        _point(FOLD, 100, 1.0),
        _point(PERIOD_DOUBLING, 102, 1.01, multiplier=-1.0 + 0j),
    ]
    out = _fold_changes_on_monodromy(doubling)
    assert [p.kind for p in out] == [FOLD, PERIOD_DOUBLING]
    assert out[0].stability_omega is None
    claimed = [
        _point(FOLD, 100, 1.0, multiplier=1.0 + 0j, stability_omega=1.0),
        _point(BRANCH_POINT, 103, 1.02, multiplier=1.0 + 0j),
    ]
    out = _fold_changes_on_monodromy(claimed)
    assert [p.kind for p in out] == [FOLD, BRANCH_POINT]
    assert out[0].stability_omega == 1.0


def test_another_change_in_between_keeps_the_branch_point():
    points = [
        _point(FOLD, 100, 1.0),
        _point(PERIOD_DOUBLING, 102, 1.01, multiplier=-1.0 + 0j),
        _point(BRANCH_POINT, 104, 1.02, multiplier=1.0 + 0j),
    ]
    out = _fold_changes_on_monodromy(points)
    assert [p.kind for p in out] == [FOLD, PERIOD_DOUBLING, BRANCH_POINT]


def test_the_nearest_free_fold_takes_the_change():
    points = [
        _point(FOLD, 100, 1.0),
        _point(FOLD, 106, 1.05),
        _point(BRANCH_POINT, 108, 1.06, multiplier=1.0 + 0j),
    ]
    out = _fold_changes_on_monodromy(points)
    assert [p.kind for p in out] == [FOLD, FOLD]
    assert out[0].stability_omega is None
    assert out[1].stability_omega == 1.06
