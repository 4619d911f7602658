"""The probe solve's LU (:func:`hbmfric.kernels.steps.truncation.probe_factor`):
the factors of :func:`hbmfric.kernels.linalg.lu.lu_factor` to the last bit
(the truncation estimates, on which ``SAFETY`` was calibrated, must not
move), and a solution that LAPACK confirms."""

from __future__ import annotations

import numpy as np
import pytest

from hbmfric.kernels.linalg.lu import lu_factor, lu_solve
from hbmfric.kernels.steps.truncation import (
    PANEL,
    probe_dense_solve,
    probe_factor,
)


def _matrices(n: int, rng: np.random.Generator):
    """Dense, with exact zeros (zero multipliers skip their updates), over
    16 decades of scale, diagonally dominant, and pivots all on one row
    order reversed."""
    a = rng.standard_normal((n, n))
    yield a
    b = a.copy()
    b[rng.random((n, n)) < 0.4] = 0.0
    yield b
    yield a * 10.0 ** rng.integers(-8, 8, size=(n, n))
    yield a + n * np.eye(n)
    yield np.flipud(np.triu(a) + n * np.eye(n))


@pytest.mark.parametrize(
    "n", [1, 2, 3, 4, 5, 7, 8, 9, 16, 22, 33, 46, 63, 64, 65, 90, 101]
)
def test_factors_are_lu_factor_bit_for_bit(n):
    rng = np.random.default_rng(n)
    for a in _matrices(n, rng):
        ref, mine = a.copy(), a.copy()
        p_ref = np.empty(n, dtype=np.int64)
        p_mine = np.empty(n, dtype=np.int64)
        ok_ref = lu_factor(ref, p_ref)
        ok_mine = probe_factor(mine, p_mine)
        assert ok_mine == ok_ref
        if ok_ref:
            assert np.array_equal(p_mine, p_ref)
            # the same bits, signed zeros included
            assert ref.tobytes() == mine.tobytes()


@pytest.mark.parametrize("n", [5, 46, 90])
def test_solution_against_lapack(n):
    rng = np.random.default_rng(100 + n)
    for a in _matrices(n, rng):
        b = rng.standard_normal(n)
        x = b.copy()
        assert probe_dense_solve(a.copy(), x)
        ref = np.linalg.solve(a, b)
        cond = np.linalg.cond(a)
        assert np.linalg.norm(x - ref) <= 1e-15 * cond * np.linalg.norm(ref) * n
        # the residual of the computed x, as a backward error
        r = a @ x - b
        assert np.linalg.norm(r) <= 1e-13 * np.linalg.norm(a) * np.linalg.norm(x)


def test_singular_and_non_finite_are_refused_as_lu_factor_does():
    n = 3 * PANEL + 1
    rng = np.random.default_rng(7)
    a = rng.standard_normal((n, n))
    singular = a.copy()
    singular[:, 5] = singular[:, 2]  # a pivot vanishes inside a panel
    late = a.copy()
    late[-1] = late[0] + late[1]  # the last pivot vanishes
    nan = a.copy()
    nan[3, 4] = np.nan
    inf = a.copy()
    inf[0, 0] = np.inf
    for m in (singular, late, nan, inf):
        piv = np.empty(n, dtype=np.int64)
        assert not probe_factor(m.copy(), piv)
        assert not lu_factor(m.copy(), piv)
        assert not probe_dense_solve(m.copy(), np.ones(n))


def test_fortran_order_falls_back_to_the_plain_factors():
    n = 20
    a = np.random.default_rng(3).standard_normal((n, n))
    ref = a.copy()
    p_ref = np.empty(n, dtype=np.int64)
    assert lu_factor(ref, p_ref)
    f = np.asfortranarray(a)
    p = np.empty(n, dtype=np.int64)
    assert probe_factor(f, p)
    assert np.array_equal(p, p_ref)
    assert np.array_equal(f, ref)
    b = np.arange(n, dtype=float)
    x1, x2 = b.copy(), b.copy()
    lu_solve(ref, p_ref, x1)
    lu_solve(np.ascontiguousarray(f), p, x2)
    assert np.array_equal(x1, x2)


def test_probe_systems_of_p1_factor_as_lu_factor():
    """The matrices the probe solve meets (P1 at F = 2, H = 21 points,
    probe level 45: order 46) factor to the same bits."""
    import hbmfric as hf
    from hbmfric.api import _problem
    from hbmfric.continuation.adaptive import _Level
    from hbmfric.continuation.palc import Continuation
    from hbmfric.kernels.steps.truncation import truncation_change

    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    p = _problem(osc, 2.0, 21, None, None, "auto", None)
    state, _ = Continuation(p, (0.5, 3.0)).run()
    points = np.array(state.points)
    probe = _Level(p.with_harmonics(45), None)
    kp, residual_at, synthesis, weights, rates, y, R, J, A, dX = probe.work()
    n = A.shape[0]
    assert n == 46
    changes = []
    for i in np.linspace(0, len(points) - 1, 12).astype(int):
        changes.append(
            truncation_change(
                points[i],
                kp,
                residual_at,
                weights,
                rates,
                probe.first_column,
                synthesis,
                y,
                R,
                J,
                A,
                dX,
            )
        )
        ref, mine = np.ascontiguousarray(J[:, :n]), np.ascontiguousarray(J[:, :n])
        p_ref = np.empty(n, dtype=np.int64)
        p_mine = np.empty(n, dtype=np.int64)
        assert lu_factor(ref, p_ref) and probe_factor(mine, p_mine)
        assert np.array_equal(p_mine, p_ref)
        assert ref.tobytes() == mine.tobytes()
        # and the probe's update is the LAPACK solution of that system
        np.testing.assert_allclose(
            dX, np.linalg.solve(J[:, :n], -R), rtol=0, atol=1e-9 * np.abs(dX).max()
        )
    assert max(changes) > 0.0
