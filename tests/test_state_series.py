"""The high poles of the complex-mode receptance summed once as a series
(:mod:`hbmfric.state_series`, :func:`hbmfric.kernels.residuals.condensed.
state_matrix`), against a plain-NumPy sum over every pole in extended
precision and against the condensed residual without the series."""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.kernels.residuals.condensed import (
    SERIES_TOL,
    series_terms,
    state_matrix,
)
from hbmfric.state_series import plan_state_series

HZ = 2.0 * np.pi
EPS = np.finfo(float).eps


@pytest.fixture(scope="module", params=[10, 40])
def joint(request):
    """The lap joint at H = 15 condensed by complex modes, without and with
    the series planned for 185 Hz."""
    s = hf.lap_joint(request.param)
    exact = CondensedHBMProblem(s, 36.0, 15, receptance="state")
    planned = exact.with_harmonics(15)
    planned.plan_band(HZ * 185.0)
    return exact, planned


def _reference(L, R, poles, w):
    """``L diag(1/(iw - λ)) R`` summed over every pole in extended
    precision, and the scale of its rounding in double (the row sums of
    the absolute terms)."""
    c = 1.0 / (np.clongdouble(1j * w) - poles.astype(np.clongdouble))
    ref = np.einsum(
        "ar,r,rb->ab", L.astype(np.clongdouble), c, R.astype(np.clongdouble)
    )
    scale = np.max((np.abs(L) * np.abs(1.0 / (1j * w - poles))) @ np.abs(R))
    return ref, float(scale)


def test_plan_splits_the_high_poles(joint):
    exact, planned = joint
    kp = planned.kernel_problem
    moduli = np.abs(kp.state_poles)
    assert exact.kernel_problem.state_series.shape[2] == 0
    n_c = kp.state_left.shape[0]
    assert kp.state_series.shape[:2] == (n_c, n_c)
    assert kp.state_series.shape[2] > 0
    low = np.zeros(moduli.size, dtype=bool)
    low[kp.state_low] = True
    # the series takes the poles at and above the split, whole pairs
    assert np.all(moduli[~low] >= kp.state_split)
    assert np.all(moduli[low] < kp.state_split)
    assert np.count_nonzero(~low) >= moduli.size // 2
    # the top harmonic of the band is served by the stored terms
    w_top = 15 * HZ * 185.0
    assert 0 < series_terms(w_top, kp.state_split, kp.state_series.shape[2])
    assert (w_top / kp.state_split) < 1.0


@pytest.mark.parametrize(
    "f_hz",
    [0.0, 125.0, 7 * 162.0, 15 * 185.0, 16.5 * 185.0, 40 * 185.0],
)
def test_series_against_every_pole(joint, f_hz):
    """Inside the band, at its top, just above (still the series) and far
    above (every pole summed): as close to the extended-precision sum as the
    double sum over every pole."""
    exact, planned = joint
    kp = planned.kernel_problem
    L, R, poles = kp.state_left, kp.state_right, kp.state_poles
    w = HZ * f_hz
    c = 1.0 / (1j * w - poles)
    ref, scale = _reference(L, R, poles, w)
    errors = []
    for p in (exact.kernel_problem, kp):
        G = np.empty((L.shape[0], L.shape[0]), dtype=complex)
        state_matrix(p, w, c, G)
        errors.append(float(np.max(np.abs(G - ref))))
    assert errors[1] <= 1.1 * errors[0] + 8.0 * EPS * scale


def test_series_terms_truncation():
    # ρ = 1/8: 2^-3J / (7/8) <= 2^-55 needs J = 19
    assert series_terms(1.0, 8.0, 40) == 19
    assert (1 / 8) ** 19 / (7 / 8) <= SERIES_TOL < (1 / 8) ** 18 / (7 / 8)
    assert series_terms(0.0, 8.0, 40) == 1
    assert series_terms(1.0, 8.0, 18) == 0  # too few stored: every pole
    assert series_terms(8.0, 8.0, 40) == 0  # at the split: every pole
    assert series_terms(1.0, 8.0, 0) == 0  # no series


def test_no_series_without_conjugate_pairs():
    """A pole without its conjugate makes the series complex: every pole is
    summed."""
    rng = np.random.default_rng(3)
    n_c, n_s = 3, 8
    poles = -1.0 - 1j * np.array([1, 2, 3, 4, 50, 60, 70, 80.0]) * 1e3
    L = rng.standard_normal((n_c, n_s)) + 1j * rng.standard_normal((n_c, n_s))
    low, series, split = plan_state_series(poles, L, L.T.copy(), 100.0)
    assert series.shape[2] == 0 and split == 0.0 and low.size == n_s
    # with the conjugates the high ones form a real series
    poles2 = np.concatenate([poles, poles.conj()])
    L2 = np.concatenate([L, L.conj()], axis=1)
    low, series, split = plan_state_series(poles2, L2, L2.T.copy(), 100.0)
    assert series.shape[2] > 0
    moduli = np.abs(poles2)
    assert split in moduli
    np.testing.assert_array_equal(low, np.flatnonzero(moduli < split))
    # the series against the sum over the high poles, plain NumPy
    high = moduli >= split
    for w in (0.0, 30.0, 100.0):
        want = (L2[:, high] / (1j * w - poles2[high])) @ L2.T[high]
        rho = 1j * w / split
        got = sum(rho**j * series[:, :, j] for j in range(series.shape[2]))
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-14 * np.abs(want).max())


def test_residual_with_series_matches_exact(joint):
    """The condensed residual and Jacobian with the series against those
    summing every pole, at three times the free linear response: within
    the residual's own rounding level."""
    exact, planned = joint
    for f_hz in (130.0, 162.0, 184.0):
        omega = HZ * f_hz
        y = np.append(3.0 * exact.linear_response(omega, "free"), omega)
        R0, J0, s0 = exact.residual(y)
        level = exact.rounding_level()
        R1, J1, s1 = planned.residual(y)
        assert s0 == s1
        assert level > 0.0
        assert np.max(np.abs(R1 - R0)) <= level
        scale = np.max(np.abs(J0), axis=1, keepdims=True)
        assert np.max(np.abs(J1 - J0) / scale) <= 1e-9


def test_drawn_output_cache_returns_the_computed_values(joint):
    """The curve rule draws the start of every step as the end of the step
    before: :func:`coordinates_drawn` keeps its last two results, and one
    read back equals the value computed afresh, bit for bit; other
    arguments are computed."""
    from hbmfric.kernels.residuals.condensed import (
        _coordinates_drawn,
        coordinates_drawn,
    )

    _, planned = joint
    kp = planned.kernel_problem
    omega = HZ * 150.0
    y = np.append(planned.linear_response(omega, "free"), omega)
    rng = np.random.default_rng(0)
    t = rng.standard_normal(y.size)
    t /= np.linalg.norm(t)
    scale = np.ones_like(y)
    col = 0
    points = [(y, t), (1.01 * y, t), (y, -t)]
    fresh = []
    for yi, ti in points:
        X = np.zeros(planned.n_coef)
        fresh.append((_coordinates_drawn(kp, yi, ti, scale, col, X), X))
    for _ in range(2):
        for (yi, ti), (want, X_want) in zip(points[:2], fresh[:2], strict=True):
            X = np.zeros(planned.n_coef)
            got = coordinates_drawn(kp, yi, ti, scale, col, X)
            assert got == want
            assert np.array_equal(X, X_want)
    # a third point pushes out the older one; all still exact
    for (yi, ti), (want, X_want) in zip(points, fresh, strict=True):
        X = np.zeros(planned.n_coef)
        assert coordinates_drawn(kp, yi, ti, scale, col, X) == want
        assert np.array_equal(X, X_want)
        assert coordinates_drawn(kp, yi, ti, 2.0 * scale, col, X) != want


def test_drawn_output_reads_the_inverse_of_the_last_residual(joint):
    """The residual keeps ``D_k = G_k⁻¹`` of every harmonic with its Ω
    (``kept_inverse``); the recovery of the drawn DOF at that very Ω reads
    them instead of inverting ``G`` again: the same values, bit for bit,
    as the recovery that inverts; at another Ω it inverts."""
    from hbmfric.kernels.residuals.condensed import _coordinates_drawn

    _, planned = joint
    kp = planned.kernel_problem
    hn = kp.harmonic_numbers
    n_h, n_c = hn.size, kp.state_left.shape[0]
    assert kp.kept_inverse.shape == (n_h + 1, n_c, n_c)
    omega = HZ * 162.0
    y = np.append(3.0 * planned.linear_response(omega, "free"), omega)
    rng = np.random.default_rng(1)
    t = rng.standard_normal(y.size)
    t /= np.linalg.norm(t)
    scale = np.ones_like(y)

    def drawn():
        X = np.zeros(planned.n_coef)
        return _coordinates_drawn(kp, y, t, scale, 0, X), X

    kp.kept_inverse[n_h, 0, 0] = np.nan  # nothing kept: inverts G
    want, X_want = drawn()
    planned.residual(y)
    assert kp.kept_inverse[n_h, 0, 0] == omega + 1j
    # what is kept is G⁻¹ of every harmonic (against NumPy's inverse)
    for h, k in enumerate(hn):
        c = 1.0 / (1j * (k * omega) - kp.state_poles)
        G = np.empty((n_c, n_c), dtype=complex)
        state_matrix(kp, k * omega, c, G)
        D = np.linalg.inv(G)
        assert np.max(np.abs(kp.kept_inverse[h] - D)) <= 1e-9 * np.max(np.abs(D))
    got, X = drawn()
    assert got == want
    assert np.array_equal(X, X_want)
    # it is read: a spoilt store changes the recovery
    kept = kp.kept_inverse.copy()
    kp.kept_inverse[:n_h] *= 2.0
    assert drawn()[0] != want
    kp.kept_inverse[:] = kept
    # a residual at another Ω: the recovery at this one inverts again
    planned.residual(np.append(y[:-1], 1.001 * omega))
    kp.kept_inverse[:n_h] = 0.0
    got, X = drawn()
    assert got == want
    assert np.array_equal(X, X_want)
