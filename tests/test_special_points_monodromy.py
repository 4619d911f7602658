"""Stability changes located on the time-domain monodromy (issue 16).

A branch whose stability comes from the monodromy (a contact with memory
on several DOFs, ``Stability.criterion == "monodromy"``) used to have its
changes located with Hill's exponents, which disagree with the monodromy
there and keep one sign over the interval: "not located". They are now
located on the monodromy's largest multiplier. The period-doubling and
Neimark–Sacker kinds of that location are checked on the preloaded Duffing
and the two-DOF energy sink, with their stability forced to the monodromy,
and on a two-DOF preloaded Duffing with a Jenkins contact (the monodromy
under ``method="auto"``), against Hill's located points (exact there up to
the truncation: memoryless laws, a stuck contact).
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
    # between the two points along the branch: across the fold the branch
    # reaches beyond both points' Ω, up to the fold's
    lo, hi = sorted(branch.omega[i - 1 : i + 1])
    lo, hi = min(lo, fold.omega), max(hi, fold.omega)
    slack = 5e-5 * fold.omega  # the monodromy's error near a fold
    assert lo - slack <= point.omega <= hi + slack
    assert abs(point.omega - fold.omega) <= 5e-5 * fold.omega
    assert abs(point.multiplier.imag) <= 1e-3
    assert abs(abs(point.multiplier) - (1.0 + NEUTRAL_TOLERANCE)) <= 1e-6
    assert point.multiplier.real > 0.0


def _monodromy_changes(system, force, branch, harmonics, around, width=3):
    """Intervals where the monodromy's verdict changes, searched in a
    window of ``width`` points on each side of each interval of
    ``around`` (the whole branch's monodromy would take minutes)."""
    h = np.full(len(branch), harmonics)
    common = dict(n_time=branch.info["n_time"], aft=branch.info["aft"])
    found = []
    for i in around:
        idx = np.arange(max(int(i) - width, 0), min(int(i) + width, len(branch)))
        raw = stability_of_points(
            system,
            force,
            branch.omega[idx],
            branch.harmonic_numbers,
            branch.coefficients[idx],
            h[idx],
            method="monodromy",
            **common,
        )
        assert raw.criterion == "monodromy"
        found.extend(int(j) for j in idx[raw.changes()])
    return np.array(found, dtype=np.int64), h, common


def test_period_doublings_located_on_the_monodromy():
    """The preloaded Duffing (``tests/test_period_doubling.py``) with its
    stability from the time-domain monodromy: both changes are located as
    period doublings, the crossing multiplier real and negative with
    ``|μ| = 1 + NEUTRAL_TOLERANCE`` (to 1e-5, Brent's tolerance), inside
    their intervals and at Hill's located period doublings (an
    independent route, exact for this memoryless law up to the
    truncation) to 1e-5 relative (measured 1.8e-6 and 2.8e-7 rad/s)."""
    from stability_cases import preloaded_duffing

    from hbmfric.bifurcation import PERIOD_DOUBLING

    system = preloaded_duffing()
    branch = hf.frf(system, 0.5, (2.5, 3.6), harmonics=9)
    hill_points = branch.special_points()
    assert [p.kind for p in hill_points] == [PERIOD_DOUBLING] * 2
    changes, h, common = _monodromy_changes(
        system, 0.5, branch, 9, [p.index for p in hill_points]
    )
    assert changes.size == 2
    points = locate_special_points(
        system,
        0.5,
        branch.omega,
        branch.harmonic_numbers,
        branch.coefficients,
        h,
        np.zeros(0, dtype=np.int64),
        changes,
        stability_method="monodromy",
        **common,
    )
    assert [p.kind for p in points] == [PERIOD_DOUBLING] * 2
    for p, ref in zip(points, hill_points, strict=True):
        lo, hi = sorted(branch.omega[p.index - 1 : p.index + 1])
        assert lo <= p.omega <= hi
        assert p.multiplier.real < 0.0 and p.multiplier.imag == 0.0
        assert abs(abs(p.multiplier) - (1.0 + NEUTRAL_TOLERANCE)) <= 1e-5
        assert abs(p.omega - ref.omega) <= 1e-5 * ref.omega


def test_neimark_sacker_located_on_the_monodromy():
    """The two-DOF energy sink (``tests/test_neimark_sacker.py``) with its
    stability from the time-domain monodromy: the change away from the
    folds is located as a Neimark–Sacker point, a complex pair with
    ``|μ| = 1 + NEUTRAL_TOLERANCE`` (to 1e-5) and ``|Im μ| > 0.1``, inside
    its interval and at Hill's located point (exact for the cubic law up
    to the truncation) to 1e-5 relative (measured 1.6e-6 rad/s)."""
    from test_neimark_sacker import FORCE, OMEGA_RANGE, energy_sink

    from hbmfric.bifurcation import NEIMARK_SACKER

    system = energy_sink()
    branch = hf.frf(system, FORCE, OMEGA_RANGE, harmonics=5)
    hill_points = [p for p in branch.special_points() if p.kind == NEIMARK_SACKER]
    assert len(hill_points) == 1
    ref = hill_points[0]
    changes, h, common = _monodromy_changes(system, FORCE, branch, 5, [ref.index])
    assert changes.tolist() == [ref.index]
    (point,) = locate_special_points(
        system,
        FORCE,
        branch.omega,
        branch.harmonic_numbers,
        branch.coefficients,
        h,
        np.zeros(0, dtype=np.int64),
        changes,
        stability_method="monodromy",
        **common,
    )
    assert point.kind == NEIMARK_SACKER
    lo, hi = sorted(branch.omega[point.index - 1 : point.index + 1])
    assert lo <= point.omega <= hi
    assert abs(point.multiplier.imag) > 0.1
    assert abs(abs(point.multiplier) - (1.0 + NEUTRAL_TOLERANCE)) <= 1e-5
    assert abs(point.omega - ref.omega) <= 1e-5 * ref.omega


def preloaded_friction_pair():
    """Two DOFs: the preloaded Duffing of ``tests/test_period_doubling.py``
    (cubic spring and static load on DOF 0) with a light second mass
    (0.1, stiffness 2) and a Jenkins contact (kt = 0.1, f_s = 0.2) on
    DOF 0: a contact with memory on several DOFs, so ``method="auto"``
    takes the monodromy; near twice the linearised frequency the period
    doubles."""
    return hf.LinearStructure(
        np.diag([1.0, 0.1]),
        np.array([[3.0, -2.0], [-2.0, 2.0]]),
        np.diag([0.02, 0.01]),
        load={0: 1.0},
        static_load={0: 1.0},
        contacts=[
            hf.Contact(hf.Cubic(1.0), 0),
            hf.Contact(hf.Jenkins(stiffness=0.1, slip_force=0.2), 0),
        ],
    )


@pytest.mark.slow
def test_period_doublings_of_a_friction_pair_under_auto():
    """A friction branch of two DOFs whose stability ``method="auto"``
    takes from the monodromy: its two changes are located on it as period
    doublings (real negative multiplier, ``|μ| = 1 + NEUTRAL_TOLERANCE``
    to 1e-5), inside their intervals and at Hill's located period
    doublings to 1e-5 relative (measured 5e-7 and 7e-7 rad/s: the
    contact sticks there, where Hill's linearisation is exact)."""
    from hbmfric.bifurcation import PERIOD_DOUBLING

    system = preloaded_friction_pair()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, 0.5, (2.0, 4.0), harmonics=9)
        hill = branch.stability(method="hill")
    h = np.full(len(branch), 9)
    common = dict(n_time=branch.info["n_time"], aft=branch.info["aft"])
    args = (system, 0.5, branch.omega, branch.harmonic_numbers, branch.coefficients, h)
    no_fold = np.zeros(0, dtype=np.int64)
    hill_points = locate_special_points(*args, no_fold, hill.changes(), **common)
    assert [p.kind for p in hill_points] == [PERIOD_DOUBLING] * 2
    found = []
    for ref in hill_points:
        idx = np.arange(ref.index - 3, ref.index + 3)
        raw = stability_of_points(
            system,
            0.5,
            branch.omega[idx],
            branch.harmonic_numbers,
            branch.coefficients[idx],
            h[idx],
            **common,
        )
        assert raw.criterion == "monodromy"
        found.extend(int(j) for j in idx[raw.changes()])
    assert len(found) == 2
    points = locate_special_points(
        *args, no_fold, np.array(found), stability_method="monodromy", **common
    )
    assert [p.kind for p in points] == [PERIOD_DOUBLING] * 2
    for p, ref in zip(points, hill_points, strict=True):
        lo, hi = sorted(branch.omega[p.index - 1 : p.index + 1])
        assert lo <= p.omega <= hi
        assert p.multiplier.real < 0.0 and p.multiplier.imag == 0.0
        assert abs(abs(p.multiplier) - (1.0 + NEUTRAL_TOLERANCE)) <= 1e-5
        assert abs(p.omega - ref.omega) <= 1e-5 * ref.omega
