"""The calibration's extremes of the padded output (issue 18, stop 35).

``truncation_change`` locates the extremes of the zero-padded point's
output on the synthesis samples (:func:`_sample_extremes`, four rows'
sums side by side) and refines them on the series of its nonzero columns
only. Both must give what the plain row-by-row loop over every column gave,
bit for bit: the tests compare with that loop written in plain Python
(IEEE doubles, each row summed in column order) and with the series over
every column, on P1's own padded points.
"""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.kernels.steps.truncation import _extreme, _sample_extremes, series_at


def _loop(synthesis, z):
    """The selection as the calibration made it before: every row summed
    over every column in order, the first largest and first smallest."""
    best = (-np.inf, np.inf)
    s_max = s_min = 0
    for s in range(synthesis.shape[0]):
        xs = 0.0
        for k in range(z.size):
            xs += float(synthesis[s, k]) * float(z[k])
        if xs > best[0]:
            best = (xs, best[1])
            s_max = s
        if xs < best[1]:
            best = (best[0], xs)
            s_min = s
    return s_max, s_min


@pytest.mark.parametrize("rows", [1, 2, 3, 4, 5, 6, 7, 64, 65, 66, 67, 252])
def test_rows_against_the_plain_loop(rows):
    """Every count of rows (remainders of 0-3 after the blocks of four) and
    trailing zero columns skipped: the same rows as the loop over all."""
    rng = np.random.default_rng(rows)
    n_coef = 32
    theta = np.linspace(0.0, 2.0 * np.pi, rows, endpoint=False)
    synthesis = np.empty((rows, n_coef))
    for j in range(n_coef // 2):
        synthesis[:, 2 * j] = np.cos((2 * j + 1) * theta)
        synthesis[:, 2 * j + 1] = np.sin((2 * j + 1) * theta)
    for _trial in range(20):
        z = np.zeros(n_coef)
        n_small = 2 * int(rng.integers(1, n_coef // 2 + 1))
        z[:n_small] = rng.standard_normal(n_small) / (1.0 + np.arange(n_small)) ** 2
        expected = _loop(synthesis, z)
        assert _sample_extremes(synthesis, z) == expected
        assert _sample_extremes(synthesis, z[:n_small]) == expected


def test_ties_keep_the_first_row():
    """Equal sums: the first row of each extreme, as the loop."""
    synthesis = np.array([[1.0, 0.0], [2.0, 0.0], [2.0, 0.0], [-1.0, 0.0], [-1.0, 0.0]])
    z = np.array([1.0, 0.0])
    assert _sample_extremes(synthesis, z) == (1, 3) == _loop(synthesis, z)


def test_padded_series_on_its_nonzero_columns_is_the_whole_series():
    """On P1's points zero-padded from H = 7 to the probe level 15: the
    extremes' instants and values of the series over the nonzero columns
    equal those over every column bit for bit."""
    from hbmfric.api import _problem
    from hbmfric.continuation.adaptive import _Level
    from hbmfric.continuation.palc import Continuation

    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    p = _problem(osc, 2.0, 7, None, None, "auto", None)
    state, _ = Continuation(p, (0.5, 3.0)).run()
    probe = _Level(p.with_harmonics(15), None)
    kp, residual_at, synthesis, weights, rates, y, R, J, A, dX = probe.work()
    first = probe.first_column
    spacing = 2.0 * np.pi / synthesis.shape[0]
    checked = 0
    for x in np.array(state.points)[::10]:
        n_small = x.size - 1
        z = np.zeros(probe.n)
        z[:n_small] = x[:-1]
        s_max, s_min = _sample_extremes(synthesis, z[:n_small])
        assert (s_max, s_min) == _loop(synthesis, z)
        for s, sign in ((s_max, 1.0), (s_min, -1.0)):
            t0 = np.arctan2(synthesis[s, first + 1], synthesis[s, first])
            t_all = _extreme(z, rates, first, t0, spacing, sign)
            t_own = _extreme(z[:n_small], rates, first, t0, spacing, sign)
            assert t_own == t_all
            assert series_at(z[:n_small], rates, first, t_own) == series_at(
                z, rates, first, t_all
            )
        checked += 1
    assert checked >= 10
