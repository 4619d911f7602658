"""Stress rows for stop 35: what the user draws, exports and reads off a Branch.

* The exact Jenkins reference at a stiff contact's resonance: a stick phase
  shorter than one grid step of the scan was missed and the contact stayed
  stuck beyond its slip force (kt 1e6 at the peak: 72 f_s, 3 % off, residual
  7e-16). Rows: kt 1e5 / 1e6 / 1e7 × Ω at and beside the resonance × F 2 / 5,
  the friction bound |f| ≤ f_s and time integration (16384 steps per
  period) within 2e-4.
* Incomplete branches: ``to_csv`` and ``plot`` say which part of the range
  is covered (``CoverageWarning``) and the CSV breaks between pieces (a row
  of nan). Rows: step budgets × retrace × sweep × H.
* ``FRFRecord.from_branch`` of a branch through folds interleaved the
  sheets (one amplitude per Ω, sorted); it now keeps what a sweep along the
  branch measures (hunt37's rule): Ω increasing, one jump at the fold, no
  zigzag. Rows: Duffing forces × H; Jenkins branches that must stay quiet.
* Period-doubled branches: ``omega_range`` in the units of ``omega`` (no gap
  holds a point) and ``plot`` at the forcing Ω (the curve starts at the
  period doubling it was born at). Rows: two preloads × the two doublings.

Run with ``python -m pytest -m stress tests/stress/test_stop35_outputs.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from stability_cases import preloaded_duffing

import hbmfric as hf

pytestmark = pytest.mark.stress

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


@pytest.mark.parametrize("force", [2.0, 5.0])
@pytest.mark.parametrize("omega", [0.97, 0.9944446725110113, 1.01])
@pytest.mark.parametrize("kt", [1e5, 1e6, 1e7])
def test_exact_reference_at_a_stiff_resonance(kt, omega, force):
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(kt, 1.0))
    exact = hf.validation.exact_periodic_solution(osc, force, omega, on_failure="raise")
    _, f = exact.contact_force(n=50000)
    assert np.max(np.abs(f)) <= 1.0 + 1e-9
    ref = hf.validation.steady_state(
        osc, force, omega, steps_per_period=2**14, max_periods=600, tol=1e-9
    )
    assert ref.converged
    a, b = exact.amplitude(harmonic=1), ref.amplitude(harmonic=1)
    assert abs(a - b) <= 2e-4 * b, (a, b)


@pytest.mark.parametrize("harmonics", [15, "auto"])
@pytest.mark.parametrize("sweep", ["up", "down"])
@pytest.mark.parametrize("retrace", [False, True])
@pytest.mark.parametrize("max_steps", [5, 40])
def test_incomplete_branch_outputs_say_so(
    max_steps, retrace, sweep, harmonics, tmp_path
):
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 1.0))
    with pytest.warns(hf.CoverageWarning):
        b = hf.frf(
            osc,
            0.5,
            (0.5, 3.0),
            harmonics,
            sweep=sweep,
            max_steps=max_steps,
            retrace=retrace,
        )
    assert not b.complete
    with pytest.warns(hf.CoverageWarning, match="CSV"):
        path = b.to_csv(tmp_path / "b.csv")
    with pytest.warns(hf.CoverageWarning, match="plot"):
        b.plot()
    rows = np.genfromtxt(path, delimiter=",", names=True)
    pieces = b.piece_slices()
    assert rows.size == len(b) + len(pieces) - 1
    w = rows["omega"]
    breaks = np.flatnonzero(np.isnan(w))
    assert breaks.tolist() == [p.start + k for k, p in enumerate(pieces[1:])]
    finite = np.isfinite(w[:-1]) & np.isfinite(w[1:])
    lo, hi = np.minimum(w[:-1], w[1:]), np.maximum(w[:-1], w[1:])
    for a, c in b.gaps:
        assert not np.any(finite & (lo <= a) & (hi >= c))


@pytest.mark.parametrize("which", [0, -1])
@pytest.mark.parametrize("preload", [1.0, 1.1])
def test_period_doubled_branch_range_and_plot(preload, which):
    branch = hf.frf(preloaded_duffing(preload), 0.5, (2.5, 3.6), harmonics=9)
    points = [p for p in branch.special_points() if p.kind == "period doubling"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.CoverageWarning)
        b2 = hf.period_doubled_branch(branch, points[which])
    lo, hi = b2.omega_range
    assert (2 * lo, 2 * hi) == branch.omega_range
    assert lo <= b2.omega.min() and b2.omega.max() <= hi
    for a, c in b2.gaps:
        assert not np.any((b2.omega > a) & (b2.omega < c))
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)  # no false alarm
        ax = b2.plot(harmonic=1, curve="polyline")
    curves = [line.get_xdata() for line in ax.lines if line.get_marker() != "x"]
    assert curves[0][0] == pytest.approx(points[which].omega, rel=1e-4)


@pytest.mark.parametrize("harmonics", [5, "auto"])
@pytest.mark.parametrize("force", [0.01, 0.02, 0.04])
def test_record_of_a_folded_branch_is_a_sweep(force, harmonics):
    from hbmfric.criterion import FRFRecord

    duf = hf.Oscillator(1.0, 0.02, 1.0, hf.Cubic(1.0))
    b = hf.frf(duf, force, (0.5, 2.5), harmonics)
    assert b.folds.size == 2
    record = FRFRecord.from_branch(b, 1.0)
    assert np.all(np.diff(record.omega) > 0.0)
    steps = np.diff(np.log(record.amplitude))
    signs = np.sign(steps[steps != 0.0])
    assert np.count_nonzero(signs[1:] != signs[:-1]) <= 3


@pytest.mark.parametrize("sweep", ["up", "down"])
@pytest.mark.parametrize("force", [0.3, 2.0])
@pytest.mark.parametrize("damping", [0.02, 0.002])
def test_record_of_a_jenkins_branch_is_quiet(damping, force, sweep):
    from hbmfric.criterion import FRFRecord

    osc = hf.Oscillator(1.0, damping, 1.0, hf.Jenkins(3.0, 1.0))
    b = hf.frf(osc, force, (0.5, 3.0), sweep=sweep)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.AccuracyWarning)
        FRFRecord.from_branch(b, 1.0)
