"""The complex modes' sums of the residual on several contact coordinates
(issue 15, stop 34: ``kernels/residuals/condensed.py``) run over
contiguous rows of ``Lᵀ`` and ``Rᵀ`` stored once per problem
(``state_magnitudes``): each against a plain-NumPy formula, and the whole
residual against the same residual with the constant parts taken afresh
from ``state_left`` and ``state_right`` (bit for bit: the same sums in the
same order)."""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.kernels.residuals.condensed import (
    _state_coordinate_receptance,
    _state_derivative,
    _state_sum_norm,
    condensed_residual,
    state_magnitudes,
    state_matrix,
)

HZ = 2.0 * np.pi
EPS = np.finfo(float).eps


def _random_modes(n_c, n_s, seed):
    rng = np.random.default_rng(seed)
    L = rng.standard_normal((n_c, n_s)) + 1j * rng.standard_normal((n_c, n_s))
    R = rng.standard_normal((n_s, n_c)) + 1j * rng.standard_normal((n_s, n_c))
    # entries over six decades, one exact zero
    L *= 10.0 ** rng.uniform(-3, 3, (n_c, 1))
    R *= 10.0 ** rng.uniform(-3, 3, (1, n_c))
    L[0, -1] = 0.0
    return rng, L, R


@pytest.mark.parametrize("n_c, n_s", [(1, 1), (3, 7), (10, 26)])
def test_magnitudes_and_sums_against_numpy(n_c, n_s):
    rng, L, R = _random_modes(n_c, n_s, n_c + n_s)
    left_t, right_t, left_abs_t, right_sums = state_magnitudes(L, R)
    assert np.array_equal(left_t, L.T) and left_t.flags.c_contiguous
    assert np.array_equal(right_t, R.T) and right_t.flags.c_contiguous
    assert np.allclose(left_abs_t, np.abs(L).T, rtol=2 * EPS, atol=0)
    assert np.allclose(right_sums, np.abs(R).sum(axis=1), rtol=n_c * EPS, atol=0)
    c = rng.standard_normal(n_s) + 1j * rng.standard_normal(n_s)
    dc = rng.standard_normal(n_s) + 1j * rng.standard_normal(n_s)
    rho = rng.standard_normal(n_s) + 1j * rng.standard_normal(n_s)
    r_lin = rng.standard_normal(n_c) + 1j * rng.standard_normal(n_c)
    # the rounding scale ‖ |L| diag|c| |R| ‖∞
    rows = np.empty(n_c)
    ref = np.max((np.abs(L) * np.abs(c)) @ np.abs(R).sum(axis=1))
    got = _state_sum_norm(left_abs_t, right_sums, c, rows)
    assert abs(got - ref) <= 4 * n_s * EPS * ref
    # the Ω column L (dc ⊙ (R r + ρ)): the terms' size bounds the rounding
    out = np.empty(n_c, dtype=complex)
    tmp = np.empty(n_s, dtype=complex)
    _state_derivative(left_t, right_t, r_lin, dc, rho, out, tmp)
    inner = R @ r_lin + rho
    ref = L @ (dc * inner)
    size = np.abs(L) @ (np.abs(dc) * (np.abs(R) @ np.abs(r_lin) + np.abs(rho)))
    assert np.all(np.abs(out - ref) <= 8 * (n_c + n_s) * EPS * size)


@pytest.fixture(scope="module")
def joint():
    """The lap joint at N = 10, H = 15, complex modes with the series
    planned for 185 Hz."""
    c = CondensedHBMProblem(hf.lap_joint(10), 36.0, 15, receptance="state")
    c = c.with_harmonics(15)
    c.plan_band(HZ * 185.0)
    return c


def test_problem_fields_are_the_magnitudes_of_its_modes(joint):
    kp = joint.kernel_problem
    fresh = state_magnitudes(kp.state_left, kp.state_right)
    stored = (
        kp.state_left_t,
        kp.state_right_t,
        kp.state_left_abs_t,
        kp.state_right_sums,
    )
    for a, b in zip(stored, fresh, strict=True):
        assert np.array_equal(a, b)


@pytest.mark.parametrize("k, col", [(0, 0), (1, 0), (15, 14)])
def test_receptance_and_load_against_numpy(joint, k, col):
    """``G_k`` and ``p_k = L (c ⊙ ρ)`` with ``c``, ``dc``, ``ρ`` against
    NumPy at 162 Hz (the joint's odd harmonics: the first in columns 0-1,
    the top one in 14-15; and the constant's formula on column 0)."""
    kp = joint.kernel_problem
    L, poles, load = kp.state_left, kp.state_poles, kp.state_load
    n_c, n_s = L.shape
    omega = HZ * 162.0
    G = np.empty((n_c, n_c), dtype=complex)
    p = np.empty(n_c, dtype=complex)
    c = np.empty(n_s, dtype=complex)
    dc = np.empty(n_s, dtype=complex)
    rho = np.empty(n_s, dtype=complex)
    _state_coordinate_receptance(k, omega, col, kp, G, p, c, dc, rho, kp.state_left_t)
    c_ref = 1.0 / (1j * k * omega - poles)
    assert np.allclose(c, c_ref, rtol=4 * EPS, atol=0)
    assert np.allclose(dc, -1j * k * c_ref**2, rtol=8 * EPS, atol=0)
    rho_ref = load[:, col] if k == 0 else load[:, col] - 1j * load[:, col + 1]
    assert np.array_equal(rho, rho_ref)
    p_ref = L @ (c_ref * rho_ref)
    size = np.abs(L) @ np.abs(c_ref * rho_ref)
    assert np.all(np.abs(p - p_ref) <= 8 * n_s * EPS * size)
    G_ref = np.empty_like(G)
    state_matrix(kp, k * omega, c, G_ref)
    assert np.array_equal(G, G_ref)


@pytest.mark.parametrize("f_hz, factor", [(125.0, 3.0), (162.0, 30.0), (185.0, 3.0)])
def test_residual_with_the_stored_parts_is_bit_for_bit(joint, f_hz, factor):
    """The residual and Jacobian with the stored ``Lᵀ``, ``Rᵀ``, ``|L|ᵀ``
    and row sums equal those with the parts taken afresh from the modes,
    bit for bit, and their rounding level too (a stale or misaligned field
    would not)."""
    kp = joint.kernel_problem
    omega = HZ * f_hz
    y = np.append(factor * joint.linear_response(omega, "free"), omega)
    n = joint.n_unknowns
    out = []
    for p in (kp, kp._replace(**_fresh(kp))):
        R = np.empty(n)
        J = np.zeros((n, n + 1))
        status = condensed_residual(y, p, R, J)
        out.append((status, R, J, p.rounding[0]))
    (s1, R1, J1, l1), (s2, R2, J2, l2) = out
    assert s1 == s2 and s1 >= 0
    assert np.array_equal(R1, R2) and np.array_equal(J1, J2) and l1 == l2
    assert np.all(np.isfinite(R1)) and l1 > 0.0


def _fresh(kp):
    left_t, right_t, left_abs_t, right_sums = state_magnitudes(
        kp.state_left.copy(), kp.state_right.copy()
    )
    return {
        "state_left_t": left_t,
        "state_right_t": right_t,
        "state_left_abs_t": left_abs_t,
        "state_right_sums": right_sums,
        "rounding": np.zeros(1),
    }
