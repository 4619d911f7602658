"""The time-domain monodromy at a few points (issue 16, stop 26:
``exponents="auto"`` with ``method="monodromy"``).

A system of Jenkins contacts with symmetric definite matrices is stable at
every point by proof (``hbmfric.stability._incrementally_passive``: the
energy of the difference of two motions never grows), and the monodromy
is computed at anchors only, as a check; any other monodromy branch is
scheduled on Hill's determinant signs and verdicts
(``hbmfric.stability._hill_flips``) with anchors and a bisection. The
verdicts are compared with the monodromy of every point.
"""

import warnings

import numpy as np
import pytest
from stability_cases import friction_duffing

import hbmfric as hf
import hbmfric.stability as stab_module
from hbmfric.stability import (
    PASSIVE_SPACING,
    _incrementally_passive,
    stability_of_points,
)

CHAIN_K = np.array(
    [[2000.0, -1000.0, 0.0], [-1000.0, 2000.0, -1000.0], [0.0, -1000.0, 1000.0]]
)


def _chain(stiffness=CHAIN_K, law=None, damping=None):
    """The user's three-DOF chain, a Jenkins contact between DOFs 1 and 2."""
    law = law or hf.Jenkins(stiffness=2000.0, slip_force=1.0)
    kwargs = {"modal_damping": 0.01} if damping is None else {"damping": damping}
    return hf.LinearStructure(
        np.eye(3),
        stiffness,
        load={0: 1.0},
        contacts=[hf.Contact(law, 1, other=2)],
        **kwargs,
    )


def test_which_systems_are_passive():
    assert _incrementally_passive(_chain())
    # a ground contact as well, and no damping at all: still non-expansive
    two = hf.LinearStructure(
        np.eye(2),
        np.array([[2.0, -1.0], [-1.0, 2.0]]),
        np.zeros((2, 2)),
        load={0: 1.0},
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=3.0, slip_force=1.0), 0),
            hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.2), 0, other=1),
        ],
    )
    assert _incrementally_passive(two)
    # a cubic spring: its work on a difference is no energy
    assert not _incrementally_passive(friction_duffing(second_mass=0.1))
    # a Dahl law
    dahl = hf.ModifiedDahl(beta=3.0, upper=(0.0, 1.0), lower=(0.0, -1.0))
    assert not _incrementally_passive(_chain(law=dahl))
    # K singular (a free chain held by the contact: E is no norm)
    free = CHAIN_K.copy()
    free[0, 0] = 1000.0
    assert abs(np.linalg.det(free)) < 1e-6 * 1000.0**3
    assert not _incrementally_passive(_chain(stiffness=free))


def _small_branch():
    """A 2-DOF Jenkins branch of a few dozen points (passive)."""
    system = hf.LinearStructure(
        np.eye(2),
        np.array([[2.0, -1.0], [-1.0, 2.0]]),
        0.02 * np.eye(2),
        load={0: 1.0},
        contacts=[hf.Contact(hf.Jenkins(stiffness=3.0, slip_force=0.3), 0, other=1)],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, 0.5, (0.5, 2.5), harmonics=5)
    return system, branch


def test_passive_route_falls_back_when_an_anchor_reads_unstable(monkeypatch):
    """The anchors check the proof against the numerics: where one reads
    unstable (a synthetic multiplier 1.1 here), every point is computed and
    its own verdict kept; otherwise only the anchors are computed."""
    system, branch = _small_branch()
    n = len(branch)
    assert n > PASSIVE_SPACING + 2
    calls = []
    bad = float(branch.omega[PASSIVE_SPACING])

    def fake(system, force, hn, coefficients, omega, subharmonic=1):
        calls.append(omega)
        return np.array([1.1 if omega == bad else 0.5, 0.2, 0.0], dtype=complex)

    monkeypatch.setattr(stab_module, "monodromy_multipliers", fake)
    args = (
        system,
        0.5,
        branch.omega,
        branch.harmonic_numbers,
        branch.coefficients,
        np.full(n, 5),
    )
    stab = stability_of_points(*args, method="monodromy", symmetric=True)
    assert len(calls) == n and stab.computed.all()
    assert np.count_nonzero(~stab.stable) == 1 and not stab.stable[PASSIVE_SPACING]
    calls.clear()
    bad = -1.0
    stab = stability_of_points(*args, method="monodromy", symmetric=True)
    anchors = np.unique(np.r_[np.arange(0, n, PASSIVE_SPACING), n - 1])
    assert len(calls) == anchors.size
    assert np.array_equal(np.flatnonzero(stab.computed), anchors)
    assert stab.stable.all()
    np.testing.assert_allclose(np.abs(stab.multipliers).max(axis=1), 0.5)  # lazily
    assert len(calls) == n


@pytest.mark.slow
def test_chain_monodromy_at_a_few_points():
    """The user's chain (945 points, every point's monodromy 270 s at load
    5, all stable, largest |μ| 1 + 5e-9): its stability by the monodromy
    computes 16 points (main: 945), all stable; 24 other points, computed
    one by one, are stable too, and their exponents read lazily equal
    those of the direct computation."""
    system = _chain()
    branch = hf.frf(system, 5.0, (8.0, 25.0))
    assert len(branch) > 500
    stab = branch.stability()
    assert stab.criterion == "monodromy"
    n = len(branch)
    assert stab.computed.sum() <= n // PASSIVE_SPACING + 2
    assert stab.stable.all()
    rng = np.random.default_rng(1)
    pick = np.sort(rng.choice(np.flatnonzero(~stab.computed), 24, replace=False))
    ref = stability_of_points(
        system,
        branch.force,
        branch.omega[pick],
        branch.harmonic_numbers,
        branch.coefficients[pick],
        branch.point_harmonics[pick],
        symmetric=bool(branch.info["odd_only"]),
        method="monodromy",
        exponents="all",
    )
    assert ref.stable.all()
    np.testing.assert_allclose(stab.multipliers[pick], ref.multipliers, atol=1e-12)
    assert stab.computed.all()


@pytest.mark.slow
def test_friction_duffing_monodromy_at_a_few_points_equals_every_point():
    """A branch no proof covers (a cubic spring and a Jenkins contact on
    two DOFs, two folds, an unstable middle stretch): every 3rd point of
    the stretch around the folds, the verdicts scheduled on Hill's signs
    and verdicts equal the monodromy at every one of these points, with a
    fraction of the monodromies (whole branch: 47 of 603 points, 19 s
    against 144 s at load 5)."""
    system = friction_duffing(second_mass=0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, 0.2, (0.5, 2.5), harmonics=15)
    f0, f1 = int(branch.folds[0]), int(branch.folds[-1])
    idx = np.arange(max(f0 - 60, 0), min(f1 + 60, len(branch)), 3)
    args = (
        system,
        0.2,
        branch.omega[idx],
        branch.harmonic_numbers,
        branch.coefficients[idx],
        np.full(idx.size, 15),
    )
    common = dict(n_time=branch.info["n_time"], aft=branch.info["aft"], symmetric=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        auto = stability_of_points(*args, method="monodromy", **common)
        full = stability_of_points(*args, method="monodromy", exponents="all", **common)
    assert full.changes().size >= 2
    np.testing.assert_array_equal(auto.stable, full.stable)
    assert auto.computed.sum() <= idx.size // 2
    for i in full.changes():
        assert auto.computed[i - 1] and auto.computed[i]


def two_contact_pair(damping_second: float = 0.0) -> hf.LinearStructure:
    """Two DOFs, a grounded and a between-DOF Jenkins contact, the second
    DOF undamped by default (also used by the stress rows of stop 30)."""
    return hf.LinearStructure(
        np.eye(2),
        np.array([[2.0, -1.0], [-1.0, 2.0]]),
        np.diag([0.03, damping_second]),
        load={0: 1.0},
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=3.0, slip_force=0.2), 0),
            hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.1), 0, other=1),
        ],
    )


@pytest.mark.slow
@pytest.mark.parametrize("which", ["between", "ground-and-between-undamped"])
def test_passive_systems_every_point_monodromy_is_stable(which):
    """The proof's claim against the numerics on two more passive systems:
    the monodromy of every 3rd point (the route the proof replaces; all
    points of both branches: 407 s at load 12, all stable) reads every one
    stable, as the route by proof says (one of them with no
    damping at all on its second DOF and a second, grounded contact)."""
    if which == "between":
        system, branch = _small_branch()
    else:
        system = two_contact_pair()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            branch = hf.frf(system, 0.5, (0.5, 2.5), harmonics=5)
    assert _incrementally_passive(system)
    idx = np.arange(0, len(branch), 3)  # every 3rd point: 7 min for all of them
    args = (
        system,
        branch.force,
        branch.omega[idx],
        branch.harmonic_numbers,
        branch.coefficients[idx],
        np.full(idx.size, 5),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        auto = stability_of_points(*args, method="monodromy", symmetric=True)
        full = stability_of_points(
            *args, method="monodromy", symmetric=True, exponents="all"
        )
    assert auto.stable.all() and auto.computed.sum() < idx.size
    np.testing.assert_array_equal(auto.stable, full.stable)


def test_a_zero_multiplier_has_the_exponent_minus_infinity():
    """A slipping Jenkins element forgets its state over the period: a
    Floquet multiplier exactly 0, whose exponent is -inf + 0j (the complex
    division gave -inf + nan j with a RuntimeWarning). The other exponents
    are log(mu) / T folded into the band of half the forcing frequency
    (checked from the multipliers with NumPy)."""
    system = two_contact_pair()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, 0.5, (0.5, 2.5), harmonics=5)
    # near the resonance, where the multiplier 0 appears (Ω 1.03-1.12)
    idx = np.flatnonzero((branch.omega > 1.05) & (branch.omega < 1.07))[:8]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        warnings.simplefilter("error", RuntimeWarning)
        r = stability_of_points(
            system,
            branch.force,
            branch.omega[idx],
            branch.harmonic_numbers,
            branch.coefficients[idx],
            np.full(idx.size, 5),
            method="monodromy",
            symmetric=True,
            exponents="all",
        )
    zero = r.multipliers == 0
    assert zero.any()
    assert not np.isnan(r.exponents).any()
    assert np.all(r.exponents[zero] == -np.inf)
    w = branch.omega[idx][:, None] * np.ones(zero.shape)
    mu = r.multipliers[~zero]
    lam = np.log(mu) * w[~zero] / (2 * np.pi)
    lam = lam.real + 1j * (lam.imag - w[~zero] * np.round(lam.imag / w[~zero]))
    np.testing.assert_allclose(r.exponents[~zero], lam, rtol=1e-12, atol=1e-12)
