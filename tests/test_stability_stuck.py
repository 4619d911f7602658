"""Stuck points of a Jenkins branch in Hill's stability at a few points
(issue 16: the cost of ``Branch.stability()`` on P1).

Where every Jenkins contact of a one-DOF branch provably sticks over the
whole period (``kt A <= f_s``, ``A`` a bound of ``|u|`` from the
coefficients), the HBM Jacobian is the linear one with the contact
stiffnesses added: every block's determinant sign is +1 and every
eigenvalue of Hill's pencil has the real part ``-c/2m``
(``hbmfric.stability._stuck_everywhere``). The stability then runs the AFT
and the LU signs at the other points only, and computes no eigenvalues at
the stuck ones. Checked against the AFT's own Jacobians, NumPy's
determinants, Hill's eigenvalues at every point and the closed form of the
linear oscillator.
"""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric import stability as stab_module
from hbmfric.kernels.aft.schemes import STUCK
from hbmfric.kernels.stability.hill import hill_jacobians
from hbmfric.stability import (
    _parity_blocks,
    _stability_problem,
    _stuck_everywhere,
    _to_full_basis,
)

C, M = 0.02, 1.0


def _p1():
    return hf.Oscillator(M, C, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def _two_sliders():
    return hf.LinearStructure(
        M * np.eye(1),
        np.eye(1),
        C * np.eye(1),
        load={0: 1.0},
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=3.0, slip_force=1.0), 0),
            hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.6), 0),
        ],
    )


@pytest.fixture(scope="module")
def p1_branch():
    return hf.frf(_p1(), 0.5, (0.5, 3.0), harmonics=15)


def _full_points(branch, h):
    n = len(branch)
    pts = np.empty((n, 2 * h + 2))
    pts[:, :-1] = _to_full_basis(branch.harmonic_numbers, branch.coefficients, h)[:, 0]
    pts[:, -1] = branch.omega
    return pts


def _aft_jacobians(problem, pts):
    n = problem.n_unknowns
    J = np.empty((pts.shape[0], n, n))
    status = np.empty(pts.shape[0], dtype=np.int64)
    none = np.zeros((0, 0), dtype=np.int64)
    hill_jacobians(
        pts,
        problem.kernel_problem,
        J,
        status,
        none,
        np.zeros(0, dtype=np.int64),
        np.zeros((pts.shape[0], 0), dtype=np.int64),
        np.zeros(0, dtype=np.int64),
        np.zeros(0),
        np.zeros((0, 0)),
        1e-10,
        np.zeros(3),
    )
    return J, status


@pytest.mark.parametrize("system", [_p1, _two_sliders], ids=["p1", "two-sliders"])
def test_stuck_points_against_the_aft_and_numpy(system):
    """Every point taken as stuck: the AFT says stuck, its Jacobian is
    block diagonal by harmonic (the linear one plus the contact
    stiffnesses, to rounding) and NumPy's determinants of the odd and even
    blocks are positive; the stuck stretch is a real part of the branch
    (measured: 139 of P1's 316 points)."""
    osc = system()
    branch = hf.frf(osc, 0.5, (0.5, 3.0), harmonics=15)
    problem = _stability_problem(osc, 0.5, 15, None, "auto", 1)
    pts = _full_points(branch, 15)
    mask, largest, proven = _stuck_everywhere(problem, pts, None, len(branch))
    assert 0.2 * len(branch) < mask.sum() < len(branch)
    assert np.array_equal(proven, mask)
    J, status = _aft_jacobians(problem, pts[mask])
    assert np.all(status == STUCK)
    hn = np.arange(16)
    kt = 3.0 if system is _p1 else 4.0
    for Jp, w in zip(J, branch.omega[mask], strict=True):
        linear = np.zeros((31, 31))
        linear[0, 0] = 1.0 + kt
        for k in hn[1:]:
            a = 1.0 - M * (k * w) ** 2 + kt
            linear[2 * k - 1 : 2 * k + 1, 2 * k - 1 : 2 * k + 1] = [
                [a, C * k * w],
                [-C * k * w, a],
            ]
        np.testing.assert_allclose(Jp, linear, rtol=0, atol=1e-12 * np.abs(Jp).max())
        for block in _parity_blocks(hn, 1):
            assert np.linalg.det(Jp[np.ix_(block, block)]) > 0.0
    np.testing.assert_allclose(largest, np.abs(J).max(axis=(1, 2)), rtol=1e-12)


def test_stuck_points_need_no_aft_and_no_eigenvalues(p1_branch, monkeypatch):
    """P1: the determinant signs need no AFT at all (every block's sign is
    +1 by proof on a Jenkins branch, ``_passive``; stop 25: the AFT at the
    177 points that slip, before it at all 316), no eigenvalues are computed
    (the first point sticks; no anchors, by the energy proof; stop 25: at
    the two of six anchors that slip), and the verdicts equal Hill's
    eigenvalues at every point. The exponents of the stuck points,
    computed when read, are those of the linear oscillator: real part
    ``-c/2m`` to 1e-9."""
    evaluated = []
    original = stab_module._Level._evaluate

    def counting(self, local, groups=None, coupling=False, **kw):
        if groups is not None:
            evaluated.append(local.size)
        return original(self, local, groups, coupling, **kw)

    monkeypatch.setattr(stab_module._Level, "_evaluate", counting)
    p1_branch._stability = None
    stab = p1_branch.stability()
    problem = _stability_problem(_p1(), 0.5, 15, None, "auto", 1)
    mask = _stuck_everywhere(problem, _full_points(p1_branch, 15), None, 10**6)[0]
    assert sum(evaluated) == 0 < np.count_nonzero(~mask)
    # no anchors on a passive Jenkins branch (the energy proof: no exponent
    # can cross), one computed verdict at the first point, which sticks:
    # no eigenvalues at all
    assert mask[0] and not stab.computed.any()
    p1_branch._stability = None
    ref = p1_branch.stability(exponents="all")
    assert np.array_equal(stab.stable, ref.stable)
    lam = stab.exponents[mask]  # computed now
    np.testing.assert_allclose(lam.real, -C / (2 * M), rtol=0, atol=1e-9)
    np.testing.assert_allclose(lam, ref.exponents[mask], rtol=0, atol=1e-9)
