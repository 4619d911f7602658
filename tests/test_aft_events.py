"""The event-located Jenkins AFT on hard inputs: reversal pairs closer than
a sample interval (stick arcs shorter than one interval), stiff contacts
whose stick arcs are 1e-4 of the amplitude, and the Jacobian there.

References: :func:`naive.jenkins_exact_coefficients` (reversals on a grid
300 times finer, bisection, Gauss quadrature of the force itself; plain
NumPy) and central finite differences of the kernel.
"""

import numpy as np
import pytest
from naive import (
    analyse,
    jenkins_coefficients_cos,
    jenkins_exact_coefficients,
    jenkins_march,
    n_coefficients,
    sample_angles,
    synthesize,
    synthesize_derivative,
)

from hbmfric.kernels.aft.schemes import GROSS_SLIP, aft_jenkins_events
from hbmfric.kernels.fourier.dft import fourier_matrices

H15 = np.arange(0, 16, dtype=np.int64)


def _events(harmonics, X, kt, fs, n_time):
    inverse, _, derivative = fourier_matrices(harmonics, n_time)
    F = np.empty(X.size)
    dF = np.empty((X.size, X.size))
    state = aft_jenkins_events(
        np.array([kt, fs]), harmonics, X, inverse, derivative, F, dF
    )
    return F, dF, state


def _random_motion(rng, harmonics, amplitude, decay):
    X = np.zeros(n_coefficients(harmonics))
    col = 0
    for k in harmonics:
        if k == 0:
            X[col] = 0.1 * amplitude * rng.normal()
            col += 1
        else:
            X[col : col + 2] = amplitude * rng.normal(size=2) / k**decay
            col += 2
    return X


def _closest_reversal_pair(harmonics, X, n_fine=200_000):
    """Smallest angle between successive reversals of ``u`` (dense grid)."""
    theta = 2.0 * np.pi * np.arange(n_fine) / n_fine
    slope = synthesize_derivative(harmonics, X, theta)
    idx = np.nonzero(np.diff(np.sign(slope)))[0]
    if idx.size < 2:
        return np.inf
    return float(np.min(np.diff(theta[idx])))


def test_exact_reference_matches_the_closed_form_loop():
    """The naive event reference against the SPEC closed form (a pure
    harmonic)."""
    harmonics = np.arange(0, 8)
    a, kt, fs = 0.7, 3.0, 1.0
    X = np.zeros(n_coefficients(harmonics))
    X[1] = a
    ref = jenkins_coefficients_cos(harmonics, a, kt, fs)
    got = jenkins_exact_coefficients(harmonics, X, kt, fs)
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-13 * fs)


def test_reversal_pairs_inside_one_sample_interval():
    """Random motions with two reversals closer than the sample interval
    ``2π / n_time``: the sampled slope has no sign change there, yet the
    kernel finds the pair and agrees with the exact reference."""
    rng = np.random.default_rng(7)
    n_time = 8 * 15
    h = 2.0 * np.pi / n_time
    checked = 0
    for _ in range(400):
        X = _random_motion(rng, H15, 1.0, 1.2)
        gap = _closest_reversal_pair(H15, X)
        if not (2e-3 < gap < 0.8 * h):
            continue
        kt, fs = 1e3, 1e-3  # stick range 2e-6: every wiggle is a stick arc
        F, _, state = _events(H15, X, kt, fs, n_time)
        assert state == GROSS_SLIP
        ref = jenkins_exact_coefficients(H15, X, kt, fs)
        np.testing.assert_allclose(F, ref, rtol=0, atol=1e-11 * fs)
        checked += 1
        if checked == 4:
            break
    assert checked == 4


def _stiff_motion(amplitude):
    """First harmonic ``amplitude`` with small higher harmonics (a branch
    point of the kt/k = 1e4, Fex/Fn = 10 case)."""
    X = np.zeros(n_coefficients(H15))
    X[1], X[2] = 0.95 * amplitude, 0.3 * amplitude
    X[5], X[6] = 4e-2, -3e-2
    X[9], X[10] = 1e-2, 7e-3
    X[29], X[30] = -2e-4, 1e-4
    return X


@pytest.mark.parametrize("amplitude", [10.0, 8500.0])
def test_stiff_contact_short_stick_arcs_are_exact(amplitude):
    """kt = 1e4, fs = 1: stick arcs span 2e-4 against amplitudes up to
    8500 (kt |u| / fs ≈ 1e8). The closed-form integrals of kt u and kt z
    over such an arc cancel to 1e-9 N; the kernel's F must match the exact
    reference to 1e-11 N, and not depend on n_time."""
    kt, fs = 1e4, 1.0
    X = _stiff_motion(amplitude)
    ref = jenkins_exact_coefficients(H15, X, kt, fs)
    for n_time in (32, 120, 960):
        F, _, state = _events(H15, X, kt, fs, n_time)
        assert state == GROSS_SLIP
        np.testing.assert_allclose(F, ref, rtol=0, atol=1e-11 * fs)


@pytest.mark.parametrize("amplitude", [10.0, 8500.0])
def test_stiff_contact_jacobian_matches_central_differences(amplitude):
    kt, fs = 1e4, 1.0
    X = _stiff_motion(amplitude)
    F, dF, _ = _events(H15, X, kt, fs, 120)
    eps = 1e-7 * amplitude
    J = np.empty_like(dF)
    for c in range(X.size):
        d = np.zeros_like(X)
        d[c] = eps
        J[:, c] = (
            _events(H15, X + d, kt, fs, 120)[0] - _events(H15, X - d, kt, fs, 120)[0]
        ) / (2.0 * eps)
    scale = np.abs(dF).max()
    assert np.abs(J - dF).max() <= 1e-4 * scale


def test_stiff_contact_matches_a_finely_sampled_march():
    """The sampled march (plain NumPy, tests/naive.py) approaches the event
    result once its samples resolve the stick arcs (about 6e-3 rad here):
    within 2e-6 f_s from 2**14 samples on, 3e-7 f_s at 2**16 (the march's
    error is not monotone in n: it depends on where the samples fall in
    the arcs)."""
    kt, fs = 1e4, 1.0
    X = _stiff_motion(10.0)
    F, _, _ = _events(H15, X, kt, fs, 120)
    errors = []
    for n in (2**14, 2**15, 2**16):
        u = synthesize(H15, X, sample_angles(n))
        errors.append(np.abs(analyse(H15, jenkins_march(u, kt, fs)[0]) - F).max())
    assert max(errors) < 2e-6 * fs
    assert errors[-1] < 3e-7 * fs
