"""Monodromy verdicts in a cluster of folds (issue 16, stop 27: item 4 of
the trust hunt).

A verdict never contradicts the multipliers computed at its point: the
fold snap (``results._snap_to_folds``) moves a change only across points
whose multipliers were not computed, each change at most once and never
off a fold it is on; the schedule computes every point between two
indicator flips at most ``FOLD_CLUSTER`` points apart; and a filled point
whose own multipliers, computed on reading, give the other verdict takes
theirs with an ``AccuracyWarning``.
"""

import warnings

import numpy as np
import pytest
from stability_cases import fold_cluster_chain

import hbmfric as hf
import hbmfric.stability as stab_module
from hbmfric.results import FOLD_SNAP, _snap_to_folds
from hbmfric.stability import (
    FOLD_CLUSTER,
    MONODROMY_SPACING,
    NEUTRAL_TOLERANCE,
    Stability,
    _monodromy_stability,
)


def test_a_change_on_a_fold_stays_there():
    """The verdicts of stop 27's scene before the snap: the change at 575,
    on a fold of a cluster of seven (557 … 592). The folds used to pass it
    from one to the next, to 592, across the computed unstable points
    575 … 591."""
    folds = np.array([557, 563, 570, 575, 583, 588, 592])
    stable = np.arange(700) < 575
    _snap_to_folds(stable, folds)
    np.testing.assert_array_equal(stable, np.arange(700) < 575)


def test_a_change_moves_at_most_once_onto_its_nearest_fold():
    stable = np.array([True] * 16 + [False] * 24)
    _snap_to_folds(stable, np.array([10, 19]))  # nearest to 16: 19
    np.testing.assert_array_equal(stable, [True] * 19 + [False] * 21)


def test_the_snap_never_crosses_a_computed_point():
    stable = np.array([True] * 10 + [False] * 10)
    computed = np.zeros(20, dtype=bool)
    computed[[0, 9, 10, 19]] = True
    before = stable.copy()
    _snap_to_folds(stable, np.array([7]), computed)  # would flip 7 … 9
    np.testing.assert_array_equal(stable, before)
    computed[9] = False  # 7 … 9 filled: moved
    _snap_to_folds(stable, np.array([7]), computed)
    np.testing.assert_array_equal(stable, [True] * 7 + [False] * 13)
    assert FOLD_SNAP == FOLD_CLUSTER


def test_a_filled_verdict_follows_its_own_multipliers():
    """Two computed stable ends, a middle point filled stable whose
    multipliers (computed on reading) are unstable: it becomes unstable,
    loudly."""
    n = 3
    mu = np.full((n, 2), np.nan + 0j)
    lam = np.full((n, 2), np.nan + 0j)
    mu[[0, 2]] = [0.9, 0.5]
    lam[[0, 2]] = np.log(mu[[0, 2]])

    def fill(where):
        m = np.tile(np.array([1.05, 0.5], dtype=complex), (where.size, 1))
        return np.log(m), m

    stab = Stability(
        exponents=lam,
        multipliers=mu,
        stable=np.ones(n, dtype=bool),
        max_real=lam.real.max(axis=1),
        omega=np.full(n, 2.0 * np.pi),
        harmonics=np.full(n, 5),
        elapsed=0.0,
        criterion="monodromy",
        computed=np.array([True, False, True]),
        fill=fill,
    )
    with pytest.warns(hf.AccuracyWarning, match="other verdict"):
        stab.multipliers  # noqa: B018
    np.testing.assert_array_equal(stab.stable, [True, False, True])


def test_the_schedule_computes_every_point_of_a_cluster_of_flips(monkeypatch):
    """Flips (folds) at 40, 44 and 50; the synthetic monodromy is unstable
    at 42 only (it leaves and re-enters the unit circle between two flips
    with no indicator of its own): only a point between the flips sees it."""
    n = 100
    omega = np.linspace(1.0, 2.0, n)
    bad = float(omega[42])

    def fake(system, force, hn, coefficients, w, subharmonic=1):
        return np.array([1.02 if w == bad else 0.9, 0.3], dtype=complex)

    monkeypatch.setattr(stab_module, "monodromy_multipliers", fake)
    monkeypatch.setattr(stab_module, "_incrementally_passive", lambda s: False)
    flips = np.zeros(n, dtype=bool)
    flips[[40, 44, 50]] = True
    assert 44 - 40 <= FOLD_CLUSTER and 40 % MONODROMY_SPACING != 0
    stab = _monodromy_stability(
        None,
        1.0,
        omega,
        np.arange(6),
        np.zeros((n, 2, 11)),
        np.full(n, 5),
        1,
        exponents="auto",
        flips=lambda: flips,
    )
    assert stab.computed[39:51].all()
    assert np.flatnonzero(~stab.stable).tolist() == [42]
    assert stab.computed.sum() < n // 3


@pytest.mark.slow
def test_verdicts_in_a_cluster_of_seven_folds_are_their_multipliers():
    """The scene of stop 27's item 4 (about 1400 points, seven folds within
    0.9805-0.9830 rad/s): every computed point's verdict is its own
    multipliers' (|μ| <= 1 + NEUTRAL_TOLERANCE), and the stretch from the
    fourth fold of the cluster to its seventh, where the monodromy reads
    |μ| 1.001 ... 1.065, is computed and unstable (before stop 27: stable,
    the verdict carried from fold to fold; 40 s CPU at load 2). The cluster
    is found by Ω, not by point index: the points move with the step
    control (stop 29: folds 564 ... 600 instead of 557 ... 592)."""
    system = fold_cluster_chain()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, 0.3, (0.3, 2.2), harmonics=5)
        stab = branch.stability()
    assert stab.criterion == "monodromy"
    folds = branch.folds
    w = branch.omega[folds]
    cluster = folds[(w > 0.9805) & (w < 0.9830)]
    assert cluster.size == 7
    done = np.flatnonzero(stab.computed)
    assert done.size < len(branch) // 4
    own = np.abs(stab._multipliers[done]).max(axis=1) <= 1.0 + NEUTRAL_TOLERANCE
    np.testing.assert_array_equal(stab.stable[done], own)
    unstable = np.arange(cluster[3], cluster[6] + 1)
    assert stab.computed[unstable].all()
    assert (
        np.abs(stab._multipliers[unstable]).max(axis=1).min() > 1.0 + NEUTRAL_TOLERANCE
    )
    assert not stab.stable[unstable].any()
