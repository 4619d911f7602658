"""The watched output's coefficients of many points at once
(``continuation.accuracy._output_series``) equal the compiled per-point
kernel's (``kernels.steps.truncation.output_coefficients``) bit for bit, and
its first-harmonic columns alone (``_output_first``, what the final pass
reads at every point) equal both."""

from types import SimpleNamespace

import numpy as np
import pytest

from hbmfric.continuation.accuracy import _output_first, _output_series
from hbmfric.kernels.steps.truncation import output_coefficients


@pytest.mark.parametrize("first", [0, 1])
@pytest.mark.parametrize("velocity", [False, True])
def test_output_series_equals_the_kernel(first, velocity):
    rng = np.random.default_rng(7 + first + 2 * velocity)
    n_dof, harmonics, n_points = 5, 7, 11
    n_coef = first + 2 * harmonics
    rates = np.zeros(n_coef)
    rates[first::2] = np.arange(1, harmonics + 1)
    rates[first + 1 :: 2] = np.arange(1, harmonics + 1)
    weights = np.zeros((2, n_dof))
    weights[0, [0, 2, 3]] = rng.normal(size=3)  # several DOFs, one left out
    if velocity:
        weights[1, [2, 4]] = rng.normal(size=2)
    points = rng.normal(size=(n_points, n_dof * n_coef + 1))
    points[:, -1] = rng.uniform(0.5, 50.0, n_points)  # Ω, rad/s
    level = SimpleNamespace(
        n_coef=n_coef, output=weights, first_column=first, rates=rates
    )
    expected = np.empty((n_points, n_coef))
    for i in range(n_points):
        output_coefficients(
            points[i], n_coef, weights, rates, points[i, -1], first, expected[i]
        )
    assert np.array_equal(_output_series(level, points), expected)
    c, s = _output_first(level, points)
    assert np.array_equal(c, expected[:, first])
    assert np.array_equal(s, expected[:, first + 1])
