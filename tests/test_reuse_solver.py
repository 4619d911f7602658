"""Corrector solves with kept LU factors (issue 15): GMRES preconditioned by
the factors of an earlier matrix (``kernels/linalg/krylov.py``), used by the
Newton kernels for large condensed problems (``kernels/steps/newton.py:
bordered_solve``). Checked against NumPy's dense solve, against the plain
path (a fresh LU every iteration) on the lap joint, and for loud failure."""

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
import hbmfric.condensation as hc
from hbmfric.condensation import CondensedHBMProblem, solver_arrays
from hbmfric.kernels.linalg import krylov
from hbmfric.kernels.linalg.lu import lu_factor
from hbmfric.kernels.residuals.pointer import residual_address
from hbmfric.kernels.steps import newton

HZ = 2.0 * math.pi


def _state(tol=1e-10, refresh=12):
    s = np.zeros(krylov.N_REUSE)
    s[krylov.REUSE_TOL] = tol
    s[krylov.REUSE_REFRESH] = refresh
    return s


def _near_pair(m, size, seed=0):
    """A well-conditioned matrix and a nearby one (rank-2 change plus a
    small dense perturbation of relative size ``size``)."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((m, m)) + m * np.eye(m)
    u = rng.standard_normal((m, 2))
    v = rng.standard_normal((2, m))
    B = A + u @ v + size * np.abs(A).max() * rng.standard_normal((m, m))
    return A, B


@pytest.mark.parametrize("size", [0.0, 1e-3])
def test_gmres_with_nearby_factors_matches_numpy(size):
    A, B = _near_pair(60, size)
    F = A.copy()
    piv = np.empty(60, dtype=np.int64)
    assert lu_factor(F, piv)
    b = np.random.default_rng(1).standard_normal(60)
    x = np.empty(60)
    V = np.empty((31, 60))
    status, products = krylov.gmres_lu(B, F, piv, b, x, V, 1e-12)
    assert status == krylov.GMRES_CONVERGED
    # a rank-2 change takes at most 3 iterations (plus the check)
    assert products <= (4 if size == 0.0 else 30)
    ref = np.linalg.solve(B, b)
    assert np.max(np.abs(x - ref)) <= 1e-10 * np.max(np.abs(ref))
    assert np.linalg.norm(B @ x - b) <= 1e-12 * np.linalg.norm(b)


@pytest.mark.parametrize("m", [1, 2, 5, 33])
def test_apply_factors_matches_numpy(m):
    A = np.random.default_rng(m).standard_normal((m, m)) + 0.1 * np.eye(m)
    F = A.copy()
    piv = np.empty(m, dtype=np.int64)
    assert lu_factor(F, piv)
    b = np.arange(1.0, m + 1.0)
    x = b.copy()
    krylov.apply_factors(F, piv, x)
    assert np.allclose(x, np.linalg.solve(A, b), rtol=1e-11, atol=1e-12)


def test_gmres_reports_what_it_cannot_do():
    A, B = _near_pair(40, 0.0)
    F = np.eye(40)  # a useless preconditioner, too few iterations
    piv = np.arange(40, dtype=np.int64)
    b = np.ones(40)
    x = np.empty(40)
    status, products = krylov.gmres_lu(B, F, piv, b, x, np.empty((4, 40)), 1e-12)
    assert status == krylov.GMRES_NOT_CONVERGED and products == 3
    b[3] = np.nan
    status, _ = krylov.gmres_lu(B, F, piv, b, x, np.empty((4, 40)), 1e-12)
    assert status == krylov.GMRES_NOT_FINITE


def test_reuse_solve_factors_when_the_kept_factors_do_not_serve():
    """No factors yet: factor; nearby matrix: GMRES; far matrix (GMRES
    fails within the basis): factor afresh, and the solve is still exact;
    a singular matrix fails and leaves no usable factors."""
    m = 50
    A, B = _near_pair(m, 0.0, seed=2)
    far = np.random.default_rng(3).standard_normal((m, m)) + 2.0 * np.eye(m)
    F = np.zeros((m, m))
    piv = np.zeros(m, dtype=np.int64)
    V = np.empty((6, m))
    state = _state()
    b0 = np.random.default_rng(4).standard_normal(m)
    for M, factored, solves, fallbacks in [
        (A, 1, 0, 0),
        (B, 1, 1, 0),
        (far, 2, 1, 1),
    ]:
        b = b0.copy()
        assert krylov.reuse_solve(M, b, F, piv, V, state)
        assert np.max(np.abs(b - np.linalg.solve(M, b0))) <= 1e-9 * np.max(np.abs(b))
        assert state[krylov.REUSE_FACTORISATIONS] == factored
        assert state[krylov.REUSE_SOLVES] == solves
        assert state[krylov.REUSE_FALLBACKS] == fallbacks
        assert state[krylov.REUSE_VALID] == 1.0
    singular = A.copy()
    singular[7] = 0.0
    state[krylov.REUSE_VALID] = 0.0
    assert not krylov.reuse_solve(singular, b0.copy(), F, piv, V, state)
    assert state[krylov.REUSE_VALID] == 0.0


def test_a_stale_preconditioner_past_the_refresh_limit_is_replaced():
    m = 50
    A, B = _near_pair(m, 1e-3, seed=5)
    F = np.zeros((m, m))
    piv = np.zeros(m, dtype=np.int64)
    V = np.empty((31, m))
    state = _state(refresh=2)
    b = np.ones(m)
    assert krylov.reuse_solve(A, b.copy(), F, piv, V, state)
    assert krylov.reuse_solve(B, b.copy(), F, piv, V, state)
    assert state[krylov.REUSE_SOLVES] == 1 and state[krylov.REUSE_VALID] == 0.0
    x = b.copy()
    assert krylov.reuse_solve(B, x, F, piv, V, state)
    assert state[krylov.REUSE_FACTORISATIONS] == 2
    assert np.allclose(B @ x, b, rtol=0, atol=1e-12)


def test_small_problems_keep_the_plain_lu():
    joint = hf.lap_joint(10)
    p = CondensedHBMProblem(joint, 36.0, 7)  # 64 unknowns
    assert p.n_unknowns < hc.REUSE_MIN_UNKNOWNS
    assert p.kernel_problem.solver[0].shape == (0, 0)
    F, piv, V, state, *_ = solver_arrays(300)
    assert F.shape == (301, 301) and V.shape == (hc.REUSE_KRYLOV + 1, 301)
    assert state[krylov.REUSE_TOL] == hc.REUSE_TOL
    assert solver_arrays(300, enabled=False)[0].shape == (0, 0)


@pytest.fixture(params=["blocks", "factors"])
def reuse_everywhere(monkeypatch, request):
    """The iterative corrector solve on every condensed problem, with each
    preconditioner (harmonic blocks, the default; kept factors)."""
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 0)
    monkeypatch.setattr(hc, "REUSE_PRECONDITIONER", request.param)
    return request.param


def _corrector_run(problem, y0, constraint, y_pred):
    n = problem.n_unknowns
    y = y0.copy()
    scale = np.full(n + 1, 1e-6)
    scale[n] = 2.0 * HZ * 60.0
    R = np.empty(n)
    J = np.empty((n, n + 1))
    A = np.empty((n + 1, n + 1))
    piv = np.empty(n + 1, dtype=np.int64)
    status, evaluations, _ = newton.correct(
        problem.kernel_problem,
        residual_address(problem.kernel_problem),
        y,
        y_pred,
        constraint,
        scale,
        1e-10 * 36.0,
        1e-8,
        20,
        R,
        J,
        A,
        piv,
    )
    return status, y, evaluations


def test_lap_joint_corrector_with_kept_factors_matches_the_plain_path(
    reuse_everywhere,
):
    """Newton at fixed Ω on the condensed lap joint in microslip from the
    linear response, then at a nearby Ω from that solution (the kept
    factors precondition): the same solution and the same number of
    evaluations as with a fresh LU every iteration (a plain problem)."""
    joint = hf.lap_joint(10)
    reuse = CondensedHBMProblem(joint, 36.0, 15)
    plain = CondensedHBMProblem(joint, 36.0, 15)
    plain.kernel_problem = plain.kernel_problem._replace(
        solver=solver_arrays(plain.n_unknowns, enabled=False)
    )
    assert reuse.kernel_problem.solver[0].shape[0] == reuse.n_unknowns + 1
    n = reuse.n_unknowns
    e = np.zeros(n + 1)
    e[n] = 1.0
    start = None
    for hz in (162.0, 162.3):
        omega = HZ * hz
        y0 = np.append(reuse.linear_response(omega, "free"), omega)
        if start is not None:
            y0[:n] = start
        out = [_corrector_run(p, y0, e, y0) for p in (reuse, plain)]
        (s1, y1, ev1), (s2, y2, ev2) = out
        assert s1 == s2 == newton.CONVERGED
        assert ev1 == ev2
        # the corrector's tolerance: scaled update below tol_step (1e-8 of
        # the 1e-6 m scale)
        assert np.max(np.abs(y1 - y2)) <= 1e-14 + 1e-8 * 1e-6
        start = y1[:n]
    state = reuse.kernel_problem.solver[3]
    if reuse_everywhere == "factors":
        assert state[krylov.REUSE_SOLVES] > state[krylov.REUSE_FACTORISATIONS] >= 1
    else:  # no dense factorisation at all
        assert state[krylov.REUSE_MODE] == krylov.REUSE_MODE_BLOCKS
        assert state[krylov.REUSE_SOLVES] >= ev1 - 1
        assert state[krylov.REUSE_FACTORISATIONS] == 0


def test_reuse_path_reports_a_singular_bordered_matrix(reuse_everywhere):
    """A zero constraint row makes the bordered matrix singular: the fresh
    factorisation of the reuse path says so (status SINGULAR), as the plain
    path does; a non-finite constraint too."""
    joint = hf.lap_joint(10)
    p = CondensedHBMProblem(joint, 36.0, 15)
    n = p.n_unknowns
    omega = HZ * 162.0
    y0 = np.append(p.linear_response(omega, "free"), omega)
    status, _, _ = _corrector_run(p, y0, np.zeros(n + 1), y0)
    assert status == newton.SINGULAR
    assert p.kernel_problem.solver[3][krylov.REUSE_VALID] == 0.0
    bad = np.zeros(n + 1)
    bad[n] = np.nan
    status, _, _ = _corrector_run(p, y0, bad, y0)
    assert status in (newton.SINGULAR, newton.NOT_FINITE)


@pytest.mark.parametrize("preconditioner", ["blocks", "factors"])
def test_lap_joint_branch_with_kept_factors_matches_the_plain_path(
    monkeypatch, preconditioner
):
    """A stretch of the condensed lap joint's branch through the onset of
    microslip (Fex/P = 1e-3, 161–163 Hz, H = 15): with kept factors the
    same points (count, Ω, amplitude within the corrector's tolerance) as
    with a fresh LU every iteration, and the curve rule's bound holds."""
    joint = hf.lap_joint(10)
    band = (HZ * 161.0, HZ * 163.0)
    branches = []
    monkeypatch.setattr(hc, "REUSE_PRECONDITIONER", preconditioner)
    for threshold in (10**9, 0):
        monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", threshold)
        with warnings.catch_warnings():
            # H = 15 is short of the harmonic tolerance here; not the point
            warnings.simplefilter("ignore", hf.AccuracyWarning)
            branches.append(hf.frf(joint, 36.0, band, 15, max_step=0.05))
    plain, reuse = branches
    assert len(reuse.omega) == len(plain.omega)
    assert np.max(np.abs(reuse.omega - plain.omega)) <= 1e-9 * band[1]
    a1 = reuse.amplitude(harmonic=1, dof="drive")
    a2 = plain.amplitude(harmonic=1, dof="drive")
    assert np.max(np.abs(a1 - a2)) <= 1e-8 * np.max(a2)
    assert np.max(reuse.curve_errors) <= 1e-4
