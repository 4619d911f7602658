"""Hill's stability with eigenvalues at a few points (issue 16:
``exponents="auto"`` of :func:`hbmfric.stability.stability_of_points`).

The verdicts of the sparse scheme are compared with Hill's eigenvalues at
every point (``exponents="all"``) on branches with folds, with adaptive
harmonics and with friction; the determinant-sign identity it relies on
is checked against the eigenvalues themselves, and the schedule against
synthetic verdicts.
"""

import pickle

import numpy as np
import pytest
from stability_cases import friction_duffing, preloaded_duffing

import hbmfric as hf
from hbmfric.stability import (
    ANCHOR_SPACING,
    _sparse_schedule,
    _stability_problem,
    _to_full_basis,
    hill_matrices,
)


def _duffing():
    return hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))


def _p1():
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def _p1_with(law):
    return hf.Oscillator(1.0, 0.02, 1.0, law)


BRANCHES = {
    # two folds, unstable middle stretch
    "duffing": lambda: hf.frf(_duffing(), 0.2, (0.5, 2.0), harmonics=9),
    # the whole basis (no odd/even split): eigenvalues at every point
    "duffing-whole": lambda: hf.frf(
        _duffing(), 0.2, (0.5, 2.0), harmonics=5, symmetry=False
    ),
    # no symmetry, a period-doubling stretch: eigenvalues at every point
    "preloaded-duffing": lambda: hf.frf(
        preloaded_duffing(), 0.5, (2.5, 3.6), harmonics=9
    ),
    # softening: folds on the other side
    "softening": lambda: hf.frf(
        hf.Oscillator(1.0, 0.02, 1.0, hf.Cubic(-0.05)), 0.05, (0.5, 1.5), harmonics=9
    ),
    # the bench case (all stable)
    "p1": lambda: hf.frf(_p1(), 0.5, (0.5, 3.0), harmonics=15),
    # adaptive harmonics: several levels along the branch
    "p1-adaptive": lambda: hf.frf(_p1(), 1.5, (0.5, 3.0)),
    # friction and folds
    "friction-duffing": lambda: hf.frf(
        friction_duffing(), 0.2, (0.5, 2.5), harmonics=15
    ),
    # the other hysteretic laws on P1's oscillator (anchors: their Hill
    # pencils are not reflection-symmetric)
    "menq": lambda: hf.frf(
        _p1_with(hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0)),
        0.5,
        (0.5, 3.0),
        harmonics=15,
    ),
    "iwan": lambda: hf.frf(
        _p1_with(hf.Iwan(stiffnesses=(1.5, 1.5), slip_forces=(0.5, 1.0))),
        0.5,
        (0.5, 3.0),
        harmonics=15,
    ),
    "dahl": lambda: hf.frf(
        _p1_with(hf.ModifiedDahl(beta=3.0, upper=(0.0, 1.0), lower=(0.0, -1.0))),
        0.5,
        (0.5, 3.0),
        harmonics=15,
    ),
}


@pytest.mark.filterwarnings("ignore::hbmfric.errors.AccuracyWarning")
@pytest.mark.parametrize("name", sorted(BRANCHES))
def test_sparse_verdicts_equal_every_point_hill(name):
    """``exponents="auto"`` gives the stability of Hill's eigenvalues at
    every point, point by point, with eigenvalues at a small share of the
    points; the exponents it computed, and those it computes on demand,
    are the full computation's."""
    branch = BRANCHES[name]()
    if branch.point_harmonics is not None:
        assert np.unique(branch.point_harmonics).size > 1
    assert branch.info["odd_only"] == (
        name not in ("duffing-whole", "preloaded-duffing")
    )
    # Hill's scheme (a Dahl branch's own default is the monodromy since
    # stop 33, tests/test_dahl_stability.py)
    auto = branch.stability(method="hill")
    computed = auto.computed.copy()
    branch._stability = None
    full = branch.stability(exponents="all", method="hill")
    assert full.computed.all()
    np.testing.assert_array_equal(auto.stable, full.stable)
    if name in ("duffing-whole", "preloaded-duffing"):
        # no symmetry: a period doubling is possible, every point solved
        assert computed.all()
    else:
        assert computed.sum() <= len(branch) // 8
    for i in full.changes():
        assert computed[i - 1] and computed[i]
    np.testing.assert_allclose(auto.exponents, full.exponents, atol=1e-12)
    assert auto.computed.all()


def test_duffing_changes_are_the_folds_and_the_stretch_is_unstable():
    """Against the continuation's own fold detection (the Ω tangent's sign
    change): the sparse verdicts change exactly at the folds of the
    hardening Duffing branch, unstable between them."""
    branch = BRANCHES["duffing"]()
    stab = branch.stability()
    np.testing.assert_array_equal(stab.changes(), branch.folds)
    f0, f1 = branch.folds
    assert stab.stable[:f0].all() and stab.stable[f1:].all()
    assert not stab.stable[f0:f1].any()


def test_determinant_sign_counts_positive_real_exponents():
    """``sign det Δ0 = sign det Δ2 · (-1)^m`` with ``m`` the positive real
    eigenvalues of Hill's pencil (computed here by NumPy on the companion
    matrix): the identity the sparse scheme tracks."""
    branch = BRANCHES["duffing"]()
    osc = _duffing()
    problem = _stability_problem(osc, 0.2, 9, None, branch.info["aft"], 1)
    n = problem.n_unknowns
    M, C = problem.kernel_problem[1], problem.kernel_problem[2]
    f0, f1 = branch.folds
    counts = set()
    for i in (5, f0 - 1, f0 + 3, (f0 + f1) // 2, f1 + 3, len(branch) - 2):
        X = _to_full_basis(branch.harmonic_numbers, branch.coefficients[i], 9)
        _, J, _ = problem.residual(np.append(X.ravel(), branch.omega[i]))
        d0, d1, d2 = hill_matrices(
            J[:, :n], M, C, problem.harmonic_numbers, float(branch.omega[i])
        )
        A = np.block(
            [
                [np.zeros((n, n)), np.eye(n)],
                [-np.linalg.solve(d2, d0), -np.linalg.solve(d2, d1)],
            ]
        )
        lam = np.linalg.eigvals(A)
        real = lam[np.abs(lam.imag) <= 1e-9 * np.abs(lam).max()].real
        m = int(np.count_nonzero(real > 0.0))
        counts.add(m)
        sign = np.sign(np.linalg.det(d0)) * np.sign(np.linalg.det(d2))
        assert sign == (-1) ** m, (i, m)
    assert counts == {0, 1}


def test_schedule_locates_a_change_without_indicator_flip():
    """A change of verdict that no determinant sees (a complex crossing)
    between two anchors is bisected down to the two points around it; a
    change at a flip is computed on both sides; nothing else is."""
    n = 200
    truth = np.ones(n, dtype=bool)
    truth[77:] = False  # complex crossing between 76 and 77
    truth[150:160] = True  # folds at 150 and 160 (flips)
    flips = np.zeros(n, dtype=bool)
    flips[[150, 160]] = True
    asked = []

    def verdict(where):
        asked.extend(where.tolist())
        return truth[where]

    computed, stable = _sparse_schedule(n, flips, verdict, ANCHOR_SPACING)
    np.testing.assert_array_equal(stable, truth)
    assert len(asked) == len(set(asked)) == computed.sum()
    assert computed[[76, 77, 149, 150, 159, 160, 0, n - 1]].all()
    assert computed.sum() < 30


def test_lazy_exponents_survive_pickling_and_all_is_validated():
    """The exponents not computed yet are computed before pickling (the
    callable that computes them is not pickled); ``exponents`` takes
    "auto" or "all" only."""
    branch = BRANCHES["p1"]()
    stab = branch.stability()
    assert not stab.computed.all()
    back = pickle.loads(pickle.dumps(stab))
    assert back.computed.all() and np.isfinite(back.exponents).all()
    branch._stability = None
    np.testing.assert_allclose(
        back.exponents, branch.stability(exponents="all").exponents, atol=1e-12
    )
    with pytest.raises(ValueError, match="exponents"):
        branch.stability(exponents="some")


@pytest.mark.parametrize("hp", [None, 5])
def test_block_signs_against_numpy_determinants(hp):
    """The signs tracked at every point (computed with the Jacobians in one
    compiled pass; with ``perturbation_harmonics`` on the kept rows and
    columns) are those of NumPy's determinants of the same blocks, and
    the verdicts with a smaller perturbation basis equal its eigenvalues
    at every point."""
    from hbmfric.stability import _Level, _parity_blocks

    branch = BRANCHES["duffing"]()
    problem = _stability_problem(_duffing(), 0.2, 9, None, branch.info["aft"], 1)
    n = len(branch)
    points = np.empty((n, problem.n_unknowns + 1))
    points[:, :-1] = _to_full_basis(
        branch.harmonic_numbers, branch.coefficients, 9
    ).reshape(n, -1)
    points[:, -1] = branch.omega
    hn, keep = problem.harmonic_numbers, None
    if hp is not None:
        hn = hn[hn <= hp]
        keep = np.arange(2 * hp + 1)
    level = _Level(problem, np.arange(n), points, hn, keep, True, True)
    signs = level.determinant_signs()
    J = level.jacobians(np.arange(n))
    odd, even = _parity_blocks(hn, 1)
    assert [g.size for g in level.groups] == [odd.size, even.size]
    for b, g in enumerate((odd, even)):
        ref = np.sign(np.linalg.det(J[:, g][:, :, g]))
        np.testing.assert_array_equal(signs[:, b], ref)
    assert {tuple(r) for r in signs} == {(1, 1), (-1, 1)}  # the folds
    if hp is not None:
        auto = branch.stability(perturbation_harmonics=hp)
        assert not auto.computed.all()
        stable = auto.stable.copy()
        branch._stability = None
        full = branch.stability(perturbation_harmonics=hp, exponents="all")
        np.testing.assert_array_equal(stable, full.stable)


def test_period_doubling_changes_no_determinant_sign():
    """Why a branch without the symmetry solves every point: across the
    period-doubling stretch of the preloaded Duffing branch (unstable
    points by Hill's eigenvalues at every point) the determinant of the
    HBM Jacobian keeps its sign, so tracking it would see nothing."""
    from hbmfric.stability import _Level

    branch = BRANCHES["preloaded-duffing"]()
    stab = branch.stability()
    assert stab.computed.all()
    assert branch.folds.size == 0
    changes = stab.changes()
    assert changes.size == 2 and not stab.stable[changes[0] : changes[1]].any()
    problem = _stability_problem(
        preloaded_duffing(), 0.5, 9, None, branch.info["aft"], 1
    )
    n = len(branch)
    points = np.empty((n, problem.n_unknowns + 1))
    points[:, :-1] = _to_full_basis(
        branch.harmonic_numbers, branch.coefficients, 9
    ).reshape(n, -1)
    points[:, -1] = branch.omega
    level = _Level(
        problem, np.arange(n), points, problem.harmonic_numbers, None, False, True
    )
    signs = level.determinant_signs()
    assert np.unique(signs[:, 0]).size == 1
