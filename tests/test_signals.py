"""Amplitude measures of sampled periods against extremes located exactly."""

import numpy as np
import pytest

from hbmfric.signals import half_peak_to_peak, sampled_peak_to_peak, synthesis_matrix

HARMONICS = np.array([0, 1, 2, 3])
#: x(θ) = 3 + 0.7 cos(θ - 0.3) + 0.2 cos(2θ + 1) - 0.05 sin 3θ
COEFFICIENTS = np.array(
    [3.0, 0.7 * np.cos(0.3), 0.7 * np.sin(0.3), 0.2 * np.cos(1.0), -0.2 * np.sin(1.0)]
    + [0.0, -0.05]
)


@pytest.mark.parametrize("n", [16, 32, 64, 128, 256, 512])
def test_sampled_peak_to_peak_refines_the_sampled_extremes(n):
    exact = 2.0 * half_peak_to_peak(HARMONICS, COEFFICIENTS)
    theta = 2.0 * np.pi * np.arange(n) / n
    x = synthesis_matrix(HARMONICS, theta) @ COEFFICIENTS
    error = abs(sampled_peak_to_peak(x) - exact)
    plain = abs(np.ptp(x) - exact)
    # parabola through three samples: third order in the step at worst
    h = 2.0 * np.pi / n
    third_derivative = 0.7 + 8 * 0.2 + 27 * 0.05
    assert error <= h**3 * third_derivative / 24.0
    assert error <= plain / 5.0


def test_sampled_peak_to_peak_of_a_sampled_parabola_is_exact():
    # the refinement is exact where the signal is a parabola near its extremes
    n = 40
    i = np.arange(n)
    x = np.where(i < n // 2, -((i - 7.3) ** 2), (i - 30.6) ** 2 - 300.0)
    expected = 0.0 - (-300.0)
    assert sampled_peak_to_peak(x) == pytest.approx(expected, rel=1e-12)
