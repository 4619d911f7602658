"""Stability without anchors on reflection-symmetric branches (issue 16,
``exponents="auto"``).

For one DOF and a memoryless law, Hill's pencil is similar to
``m (μ + Ω D₁)² + S`` with ``S`` symmetric and ``μ = λ + c/(2m)``, so its
eigenvalues pair as ``λ`` and ``-c/m - λ``: the two exponents of a
symmetric branch are a real pair or a complex pair on ``Re λ = -c/(2m)``
and the verdict can change only where a determinant changes sign. These
tests check the pairing with NumPy's eigenvalues of the whole pencil (not
the code's selection), that the symmetry measured in the Jacobian loop is
NumPy's, that such a branch computes eigenvalues at the two ends of each
sign change only, and that a failed pairing check brings the anchors back.
"""

import numpy as np
import pytest

import hbmfric as hf
import hbmfric.stability as stab_mod
from hbmfric.stability import (
    ANCHOR_SPACING,
    _Level,
    _stability_problem,
    _to_full_basis,
    derivative_operator,
    hill_matrices,
)


def _duffing():
    return hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))


def _p1():
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


@pytest.fixture(scope="module")
def duffing_branch():
    return hf.frf(_duffing(), 0.2, (0.5, 2.0), harmonics=9)


@pytest.fixture(scope="module")
def p1_branch():
    return hf.frf(_p1(), 0.5, (0.5, 3.0), harmonics=15)


def _pencil_eigenvalues(system, force, branch, i, harmonics):
    """All eigenvalues of Hill's pencil of branch point ``i`` in the full
    basis, by NumPy on the companion matrix."""
    problem = _stability_problem(system, force, harmonics, None, branch.info["aft"], 1)
    n = problem.n_unknowns
    X = _to_full_basis(branch.harmonic_numbers, branch.coefficients[i], harmonics)
    _, J, _ = problem.residual(np.append(X.ravel(), branch.omega[i]))
    M, C = problem.kernel_problem[1], problem.kernel_problem[2]
    d0, d1, d2 = hill_matrices(
        J[:, :n], M, C, problem.harmonic_numbers, float(branch.omega[i])
    )
    A = np.block(
        [
            [np.zeros((n, n)), np.eye(n)],
            [-np.linalg.solve(d2, d0), -np.linalg.solve(d2, d1)],
        ]
    )
    return np.linalg.eigvals(A), problem, J[:, :n]


def _reflection_mismatch(lam, c_over_m):
    """Largest distance from each eigenvalue's reflection ``-c/m - λ`` to
    the nearest eigenvalue, relative to the spectrum's size."""
    mirror = -c_over_m - lam
    d = np.abs(mirror[:, None] - lam[None, :]).min(axis=1)
    return float(d.max() / np.abs(lam).max())


def test_memoryless_pencil_eigenvalues_pair_about_minus_c_over_2m(
    duffing_branch, p1_branch
):
    """Duffing (memoryless): every eigenvalue of the whole pencil has its
    reflection ``-c/m - λ`` in the spectrum, at stable and unstable points;
    P1's Jenkins contact (memory) breaks the pairing at a slipping point,
    which is why it keeps the anchors."""
    f0, f1 = duffing_branch.folds
    for i in (3, f0 - 2, (f0 + f1) // 2, f1 + 2, len(duffing_branch) - 3):
        lam, _, _ = _pencil_eigenvalues(_duffing(), 0.2, duffing_branch, i, 9)
        assert _reflection_mismatch(lam, 0.05) < 1e-9, i
    peak = int(np.argmax(p1_branch.amplitude(harmonic=1)))
    lam, _, _ = _pencil_eigenvalues(_p1(), 0.5, p1_branch, peak, 15)
    assert _reflection_mismatch(lam, 0.02) > 1e-3


def _level(system, force, branch, harmonics):
    problem = _stability_problem(system, force, harmonics, None, branch.info["aft"], 1)
    n = len(branch)
    points = np.empty((n, problem.n_unknowns + 1))
    points[:, :-1] = _to_full_basis(
        branch.harmonic_numbers, branch.coefficients, harmonics
    ).reshape(n, -1)
    points[:, -1] = branch.omega
    level = _Level(
        problem,
        np.arange(n),
        points,
        problem.harmonic_numbers,
        None,
        True,
        True,
        reflect=True,
    )
    return level, problem


def test_measured_symmetry_against_numpy(duffing_branch, p1_branch, monkeypatch):
    """The asymmetry measured in the compiled Jacobian loop is NumPy's
    ``max |W J - (W J)ᵀ - 2 Ω W C ⊗ D₁|`` relative to each point's
    largest entry (``W``: 2 on the rows of harmonic 0, 1 elsewhere):
    rounding on the Duffing, of the order of the entries on P1 (the
    Duffing's Jacobians from the AFT here, not from the spectrum)."""
    monkeypatch.setattr(stab_mod, "_memoryless", lambda problem, keep: False)
    # P1's signs come by proof, without the measurement: the measured route
    monkeypatch.setattr(stab_mod, "_passive", lambda problem, points: False)
    for system, force, branch, h, memoryless in (
        (_duffing(), 0.2, duffing_branch, 9, True),
        (_p1(), 0.5, p1_branch, 15, False),
    ):
        level, problem = _level(system, force, branch, h)
        J = level.jacobians(np.arange(len(branch)))
        hn = problem.harmonic_numbers
        per = np.repeat(hn, np.where(hn == 0, 1, 2))
        W = np.where(per == 0, 2.0, 1.0)
        c = problem.kernel_problem[2][0, 0]
        WJ = W[None, :, None] * J
        skew = 2.0 * c * derivative_operator(hn, 1.0)
        ref = np.abs(
            WJ
            - WJ.transpose(0, 2, 1)
            - branch.omega[:, None, None] * (W[:, None] * skew)[None]
        ).max(axis=(1, 2)) / np.abs(J).max(axis=(1, 2))
        assert level.reflection_symmetric() == memoryless
        if memoryless:
            # every point tested: the largest ratio
            np.testing.assert_allclose(level._asymmetry, ref.max(), rtol=1e-12)
            assert level._asymmetry <= 1e-13
        else:
            # the test stops at the first point above the tolerance
            first = int(np.argmax(ref > stab_mod.SPLIT_TOLERANCE))
            np.testing.assert_allclose(
                level._asymmetry, ref[: first + 1].max(), rtol=1e-12
            )
            assert ref.max() >= 1e-4


@pytest.mark.parametrize(
    "damping, cubic, force, omega_range",
    [(0.05, 0.1, 0.2, (0.5, 2.0)), (0.02, -0.05, 0.05, (0.5, 1.5))],
    ids=["hardening", "softening"],
)
def test_reflection_symmetric_branch_computes_the_sign_changes_only(
    damping, cubic, force, omega_range
):
    """A memoryless one-DOF branch: Hill's eigenvalues at the two ends of
    each fold only (no anchors, no first and last points), the verdicts
    those of the eigenvalues at every point."""
    osc = hf.Oscillator(1.0, damping, 1.0, hf.Cubic(cubic))
    branch = hf.frf(osc, force, omega_range, harmonics=9)
    auto = branch.stability()
    computed = np.flatnonzero(auto.computed)
    f0, f1 = branch.folds
    np.testing.assert_array_equal(computed, [f0 - 1, f0, f1 - 1, f1])
    branch._stability = None
    full = branch.stability(exponents="all")
    np.testing.assert_array_equal(auto.stable, full.stable)
    np.testing.assert_array_equal(full.changes(), [f0, f1])
    # the pairing the scheme relies on, on the exponents of every point
    total = full.exponents.real.sum(axis=1)
    np.testing.assert_allclose(total, -damping, atol=1e-10)


def test_failed_pairing_brings_the_anchors_back(duffing_branch, monkeypatch):
    """Where the computed exponents do not pair (forced here by a negative
    tolerance), the schedule runs again with anchors every
    ``ANCHOR_SPACING`` points; the verdicts stay those of every point."""
    monkeypatch.setattr(stab_mod, "REFLECTION_TOLERANCE", -1.0)
    duffing_branch._stability = None
    auto = duffing_branch.stability()
    assert auto.computed[::ANCHOR_SPACING].all()
    assert auto.computed[[0, len(duffing_branch) - 1]].all()
    stable = auto.stable.copy()
    duffing_branch._stability = None
    monkeypatch.undo()
    full = duffing_branch.stability(exponents="all")
    np.testing.assert_array_equal(stable, full.stable)
    duffing_branch._stability = None


def test_spectral_jacobians_and_signs_against_the_aft(duffing_branch):
    """The Jacobians a memoryless one-DOF branch takes from the spectrum
    of its tangent stiffness equal the AFT's (``HBMProblem.residual``) to
    rounding, and the signs of their odd and even blocks at every point
    of the Duffing branch equal those of NumPy's determinants of the AFT
    Jacobians' blocks (both signs of the odd block occur: the folds)."""
    from hbmfric.kernels.stability.hill import memoryless_jacobians
    from hbmfric.stability import SIGN_GUARD, _memoryless, _parity_blocks

    level, problem = _level(_duffing(), 0.2, duffing_branch, 9)
    assert _memoryless(problem, None) and level._all is None
    n = problem.n_unknowns
    J = level.jacobians(np.arange(len(duffing_branch)))  # the AFT's
    kp = problem.kernel_problem
    hn = problem.harmonic_numbers
    theta = 2.0 * np.pi * np.arange(kp[9].shape[0]) / kp[9].shape[0]
    m = np.arange(2 * hn[-1] + 1)[:, None]
    jac = np.empty((n, n))
    # half a period (the odd solution of an odd law) and the whole one
    cases = [(i, True) for i in (0, 150, duffing_branch.folds[0], 300)]
    cases += [(i, False) for i in (150, len(duffing_branch) - 1)]
    for i, odd_law in cases:
        memoryless_jacobians(
            level.points[i : i + 1],
            hn,
            np.array([1.0, 0.05, 1.0]),
            np.asarray(kp[6]),
            kp[7],
            np.cos(m * theta),
            np.sin(m * theta),
            jac,
            np.zeros((0, 1), dtype=np.int64),
            np.zeros(0, dtype=np.int64),
            np.empty((1, 0), dtype=np.int64),
            np.zeros(n, dtype=np.int64),
            SIGN_GUARD,
            odd_law,
            np.zeros(2),
        )
        np.testing.assert_allclose(jac, J[i], rtol=0, atol=1e-13 * np.abs(J[i]).max())
    signs = level.determinant_signs()
    for b, g in enumerate(_parity_blocks(hn, 1)):
        ref = np.sign(np.linalg.det(J[:, g][:, :, g]))
        np.testing.assert_array_equal(signs[:, b], ref)
    assert set(signs[:, 0]) == {-1, 1}
