"""The criterion on families sampled at few uneven frequencies per curve
(stop 34): the chords between the samples cut the resonance peaks
differently on every curve, and that error was not in the noise unit.

Families of known law by the describing function (plain NumPy,
``tests/test_criterion.py``): Jenkins is macroslip, Menq microslip, both
without roughness. On main (88bbbff) the rows below read microslip with
roughness (Jenkins, 15 samples, envelope margin +32), macroslip with
roughness (Jenkins, 25 samples, ratio-spread margin +51) and macroslip
without roughness (Menq, 40 samples, margin -25): confident and wrong.
"""

from __future__ import annotations

import numpy as np
import pytest

from hbmfric.criterion import choose_contact_model
from hbmfric.criterion.smoothing import interp_log, interpolation_error
from tests.stress.test_stop34_criterion_sampling import TRUTH, family, sampled


@pytest.mark.parametrize(
    ("law", "n", "seed"), [("jenkins", 15, 3), ("jenkins", 25, 1), ("menq", 40, 1)]
)
def test_sparse_uneven_family_gets_no_wrong_verdict(law, n, seed):
    res = choose_contact_model(sampled(family(law), seed, n))
    assert res.model in (TRUTH[law], "undecided"), res.explanation
    assert res.model == "undecided" or not res.roughness, res.explanation


def test_the_families_at_full_resolution_still_decide():
    for law, model in TRUTH.items():
        res = choose_contact_model(family(law))
        assert res.verdict == f"{model} without roughness", res.explanation


def test_interpolation_error_covers_a_straddled_peak():
    """A Lorentzian peak (half width 1) sampled every 2.5 around it: the
    estimate reaches the true chord error at the peak within a factor 2 (the
    change to half the samples), and is tiny where 0.05 sampling resolves it."""
    grid = np.linspace(-20.0, 20.0, 801)

    def y(w):
        return -0.5 * np.log1p(w**2)

    for spacing, low, high in ((2.5, 0.5, 2.0), (0.05, 0.0, 1e-2)):
        w = np.arange(-20.0, 20.0 + 1e-9, spacing) + 0.3 * spacing
        w = w[(w >= -20.0) & (w <= 20.0)]
        true = np.abs(interp_log(w, y(w), grid) - y(grid))
        est = interpolation_error(w, y(w), grid, 0.0)
        ok = np.isfinite(true) & np.isfinite(est)
        worst = np.max(true[ok])
        if spacing > 1:
            assert low * worst <= np.max(est[ok]) <= high * worst
        else:
            assert np.max(est[ok]) < high
