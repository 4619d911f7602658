"""Stress rows for stop 28: how a traced piece ends
(``hbmfric.continuation.ends``), on the paths the default tests do not take:
the uncondensed solve through the undamped chain's singular point, and the
unbounded undamped resonance with ``harmonics="auto"`` and a Menq contact.

Run with ``python -m pytest -m stress tests/stress/test_stop28_ends.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_piece_ends import undamped_contact_chain

import hbmfric as hf

pytestmark = pytest.mark.stress


def test_undamped_chain_uncondensed_meets_the_same_singular_point():
    """``condense=False``: the same singular point, no folds, and the two
    pieces on the condensed branch (amplitudes at 6 Ω within the dense
    outputs' estimates)."""
    system = undamped_contact_chain()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        with pytest.warns(hf.SingularPointWarning):
            full = hf.frf(system, 0.5, (0.02, 0.8), harmonics=15, condense=False)
        with pytest.warns(hf.SingularPointWarning):
            condensed = hf.frf(system, 0.5, (0.02, 0.8), harmonics=15)
    assert full.folds.size == 0 and full.complete
    w_s = condensed.info["singular_points"][0]
    np.testing.assert_allclose(full.info["singular_points"], w_s, rtol=1e-9)
    # the two branches have different points (the condensed one steps with
    # the second-order predictor): their dense outputs agree within the sum
    # of their own estimates (about 1e-6 to 1e-5 here)
    omegas = [0.1, 0.3, 0.6, 0.74, 0.76, 0.79]
    a_full, e_full = full.amplitude_at(omegas, 1, 9, return_error=True)
    a_cond, e_cond = condensed.amplitude_at(omegas, 1, 9, return_error=True)
    assert a_full.shape == a_cond.shape == (6, 1)
    assert np.all(np.abs(a_full / a_cond - 1.0) <= e_full + e_cond + 1e-8)


@pytest.mark.parametrize(
    "law",
    [
        hf.Jenkins(stiffness=3.0, slip_force=1.0),
        hf.Menq.from_stiffness(3.0, slip_force=1.0),
    ],
    ids=["jenkins", "menq"],
)
def test_unbounded_undamped_resonance_warns_with_auto_harmonics(law):
    """No damping, F = 2 > 4 f_s/π: unbounded at Ω = 1; the adaptive run
    must say so too (a CoverageWarning naming the step budget)."""
    osc = hf.Oscillator(1.0, 0.0, 1.0, law)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        with pytest.warns(hf.CoverageWarning, match="step budget"):
            branch = hf.frf(osc, 2.0, (0.5, 3.0), max_steps=1500)
    assert np.nanmax(branch.amplitude(harmonic=1)) > 1e2


def test_undamped_chain_at_h7_stalls_from_both_sides_at_the_singular_point():
    """H = 7: both sweeps stall (step below min_step) at the singular point
    instead of returning; before stop 28 the complete branch listed 17
    folds there and said nothing. Now: a SingularPointWarning, no folds,
    3Ω at a natural frequency of the stuck chain."""
    system = undamped_contact_chain()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        with pytest.warns(hf.SingularPointWarning):
            branch = hf.frf(system, 0.5, (0.02, 0.8), harmonics=7)
    assert branch.folds.size == 0 and branch.complete
    (w_s,) = set(branch.info["singular_points"])
    stuck = 2.0 * np.eye(10) - np.eye(10, k=1) - np.eye(10, k=-1)
    stuck[-1, -1] = 1.0
    stuck[np.arange(8), np.arange(8)] += np.logspace(-1.0, 1.0, 8)
    natural = np.sqrt(np.linalg.eigvalsh(stuck))
    assert np.min(np.abs(natural - 3.0 * w_s)) < 1e-6 * natural.max()
