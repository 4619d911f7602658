"""Fourier integrals over pieces of the period (kernels/fourier/segments.py) against
Gauss–Legendre quadrature and plain NumPy sums."""

import numpy as np
import pytest

from hbmfric.kernels.fourier.dft import fourier_matrices
from hbmfric.kernels.fourier.segments import (
    add_segment_integrals,
    basis_integrals,
    product_integrals,
    project_samples,
    trig_series,
)

HARMONIC_SETS = [np.array([0, 1, 2, 3]), np.array([1, 3, 5]), np.array([0, 2, 5])]
SEGMENTS = [(0.3, 1.7), (-2.0, 0.5), (5.9, 7.1), (1.0, 1.0), (2.0, -1.0)]


def _basis(harmonic_numbers, theta):
    """Basis functions ``ψ_r(θ)`` and normalisations ``c_r``."""
    rows, norms = [], []
    for k in harmonic_numbers:
        if k == 0:
            rows.append(1.0)
            norms.append(1.0 / (2.0 * np.pi))
        else:
            rows += [np.cos(k * theta), np.sin(k * theta)]
            norms += [1.0 / np.pi, 1.0 / np.pi]
    return np.array(rows), np.array(norms)


#: 80-point Gauss–Legendre rule: exact to rounding for the trigonometric
#: integrands here (degree <= 10 over at most a period)
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(80)


def segment_integrals(m_max, *ends):
    """``C, S`` summed over the segments ``ends[0:2], ends[2:4], …``."""
    C = np.zeros(m_max + 1)
    S = np.zeros(m_max + 1)
    ca, sa, cb, sb = (np.empty(m_max + 1) for _ in range(4))
    for a, b in zip(ends[::2], ends[1::2], strict=True):
        trig_series(a, ca, sa)
        trig_series(b, cb, sb)
        add_segment_integrals(a, b, ca, sa, cb, sb, C, S)
    return C, S


def _quad(fn, a, b):
    half = 0.5 * (b - a)
    theta = 0.5 * (a + b) + half * _NODES
    return half * sum(w * fn(t) for t, w in zip(theta, _WEIGHTS, strict=True))


@pytest.mark.parametrize(("a", "b"), SEGMENTS)
def test_segment_integrals_match_quadrature(a, b):
    m_max = 12
    cos_int, sin_int = segment_integrals(m_max, a, b)
    for m in range(m_max + 1):
        assert cos_int[m] == pytest.approx(
            _quad(lambda t, m=m: np.cos(m * t), a, b), abs=1e-13
        )
        assert sin_int[m] == pytest.approx(
            _quad(lambda t, m=m: np.sin(m * t), a, b), abs=1e-13
        )


@pytest.mark.parametrize("harmonic_numbers", HARMONIC_SETS)
@pytest.mark.parametrize(("a", "b"), SEGMENTS[:3])
def test_basis_and_product_integrals_match_quadrature(harmonic_numbers, a, b):
    hn = harmonic_numbers.astype(np.int64)
    cos_int, sin_int = segment_integrals(2 * int(hn[-1]), a, b)
    n_coef = _basis(hn, 0.0)[0].size
    q = np.empty(n_coef)
    basis_integrals(hn, cos_int, sin_int, q)
    stiffness = 2.5
    P = np.full((n_coef, n_coef), np.nan)  # overwritten
    product_integrals(hn, cos_int, sin_int, stiffness, P)
    _, norms = _basis(hn, 0.0)
    for r in range(n_coef):
        expected = norms[r] * _quad(lambda t, r=r: _basis(hn, t)[0][r], a, b)
        assert q[r] == pytest.approx(expected, abs=1e-13)
        for j in range(n_coef):
            product = _quad(
                lambda t, r=r, j=j: _basis(hn, t)[0][r] * _basis(hn, t)[0][j], a, b
            )
            assert P[r, j] == pytest.approx(stiffness * norms[r] * product, abs=1e-12)


def test_segments_of_a_period_give_the_fourier_coefficients_of_a_stuck_spring():
    # f = kt (u - z) on [0, 2.1), f = f_s after: the pieces sum to the exact
    # coefficients, checked against a fine quadrature of the whole period
    hn = np.array([0, 1, 2, 3], dtype=np.int64)
    X = np.array([0.1, 1.0, -0.4, 0.3, 0.2, -0.1, 0.05])
    kt, z, f_s, cut = 3.0, 0.2, 0.7, 2.1
    q = np.empty(7)
    P = np.empty((7, 7))
    # stick on two segments [0, 0.9) and [0.9, cut): the sums serve both
    C, S = segment_integrals(6, 0.0, 0.9, 0.9, cut)
    basis_integrals(hn, C, S, q)
    product_integrals(hn, C, S, kt, P)
    F = P @ X - kt * z * q
    C, S = segment_integrals(6, cut, 2.0 * np.pi)
    basis_integrals(hn, C, S, q)
    F += f_s * q

    def force(t):
        return kt * (_basis(hn, t)[0] @ X - z) if t < cut else f_s

    _, norms = _basis(hn, 0.0)
    for r in range(7):
        expected = norms[r] * (
            _quad(lambda t, r=r: force(t) * _basis(hn, t)[0][r], 0.0, cut)
            + _quad(lambda t, r=r: force(t) * _basis(hn, t)[0][r], cut, 2 * np.pi)
        )
        assert F[r] == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize(
    ("start", "count", "weight"), [(0, 32, 1.0), (21, 32, 1.0), (27, 16, 2.0)]
)
def test_project_samples_is_the_weighted_forward_dft(start, count, weight):
    hn = np.array([0, 1, 2, 3], dtype=np.int64)
    n_time = 32
    _, forward, _ = fourier_matrices(hn, n_time)
    rng = np.random.default_rng(start)
    force = rng.standard_normal(n_time)
    grad = rng.standard_normal((n_time, 5))
    F = np.full(7, 0.5)
    dF = np.full((7, 5), -0.5)
    project_samples(forward, force, grad, start, count, weight, F, dF)
    pick = (start + np.arange(count)) % n_time
    W = weight * forward[:, pick]
    np.testing.assert_allclose(F, 0.5 + W @ force[pick], rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(dF, -0.5 + W @ grad[pick], rtol=1e-13, atol=1e-14)


def test_project_samples_of_a_smooth_force_matches_the_fourier_integrals():
    # the trapezoidal rule is spectrally accurate for a smooth periodic force
    hn = np.array([0, 1, 2, 3], dtype=np.int64)
    n_time = 64
    _, forward, _ = fourier_matrices(hn, n_time)
    theta = 2.0 * np.pi * np.arange(n_time) / n_time

    def force(t):
        return np.exp(np.cos(t) + 0.3 * np.sin(2 * t))

    F = np.zeros(7)
    project_samples(
        forward,
        force(theta),
        np.zeros((n_time, 1)),
        0,
        n_time,
        1.0,
        F,
        np.zeros((7, 1)),
    )
    _, norms = _basis(hn, 0.0)
    for r in range(7):
        expected = norms[r] * _quad(
            lambda t, r=r: force(t) * _basis(hn, t)[0][r], 0.0, 2 * np.pi
        )
        assert F[r] == pytest.approx(expected, abs=1e-13)
