"""Trust hunt, stop 35: what the user draws, exports and reads off a Branch.

* A period-doubled branch (:func:`hbmfric.period_doubled_branch`) has
  ``omega`` = Ω/2 but recorded the *forcing* range as ``omega_range``:
  ``gaps`` named the whole asked range a gap while 725 points lay in it,
  and ``plot`` drew it at half the forcing frequency under the label Ω
  (beside its parent, away from where it was born).
* ``to_csv`` wrote the rows of two pieces one after the other (a line drawn
  through them crossed the jump) and neither it nor ``plot`` said that the
  branch did not cover its asked range (a loaded branch: nothing said so).
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from stability_cases import preloaded_duffing

import hbmfric as hf

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


@pytest.fixture(scope="module")
def doubled():
    """The preloaded Duffing of docs/stability.md: its period-T branch, the
    two period doublings on it, and the period-2T branch between them."""
    branch = hf.frf(preloaded_duffing(1.0), 0.5, (2.5, 3.6), harmonics=9)
    points = [p for p in branch.special_points() if p.kind == "period doubling"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        b2 = hf.period_doubled_branch(branch, points[0])
    return branch, points, b2


def test_period_doubled_range_is_in_the_units_of_omega(doubled):
    """Every point lies in the recorded range, no gap holds a point, and
    the range is half the forcing range asked for (the parent's)."""
    branch, _, b2 = doubled
    lo, hi = b2.omega_range
    assert lo <= b2.omega.min() and b2.omega.max() <= hi
    assert (2.0 * lo, 2.0 * hi) == branch.omega_range
    assert tuple(b2.info["forcing_omega_range"]) == branch.omega_range
    for a, b in b2.gaps:
        assert not np.any((b2.omega > a) & (b2.omega < b)), (a, b)
    # what it does not cover: before the first and after the last doubling
    covered = sum(b - a for a, b in b2.gaps)
    assert covered == pytest.approx(
        (hi - lo) - (b2.omega.max() - b2.omega.min()), rel=1e-12
    )


def test_period_doubled_branch_is_drawn_where_it_was_born(doubled):
    """Drawn over its parent, the period-2T branch starts at the forcing Ω
    of the period doubling it was born at (2.9965 rad/s) and ends at the
    other one (3.1782 rad/s), where it returns: not at half of them."""
    branch, points, b2 = doubled
    ax = branch.plot(harmonic=None)
    n_parent = len(ax.lines)
    b2.plot(ax=ax, harmonic=None)
    curves = [
        line.get_xdata() for line in ax.lines[n_parent:] if line.get_marker() != "x"
    ]
    born = sorted(p.omega for p in points)
    assert curves[0][0] == pytest.approx(born[0], rel=1e-4)
    assert curves[-1][-1] == pytest.approx(born[-1], rel=1e-4)
    x = np.concatenate(curves)
    lo, hi = branch.omega_range
    assert lo < x.min() and x.max() < hi


def test_period_doubled_file_of_the_old_layout(doubled, tmp_path):
    """A period-doubled branch saved with the forcing range as
    ``omega_range`` loads with the range of its omega."""
    _, _, b2 = doubled
    path = b2.save(tmp_path / "pd.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(str(arrays["meta"]))
    meta["info"]["omega_range"] = meta["info"].pop("forcing_omega_range")
    arrays["meta"] = np.array(json.dumps(meta))
    np.savez(path, **arrays)
    back = hf.Branch.load(path)
    assert back.omega_range == b2.omega_range
    assert back.gaps == b2.gaps


@pytest.fixture(scope="module")
def two_pieces():
    """A step budget too small: the run is retraced from the far end, two
    pieces with a gap between them."""
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 1.0))
    with pytest.warns(hf.CoverageWarning):
        return hf.frf(osc, 0.5, (0.5, 3.0), 15, max_steps=5, retrace=True)


def test_csv_rows_break_between_pieces_and_say_the_gap(two_pieces, tmp_path):
    b = two_pieces
    (first, second) = b.piece_slices()
    with pytest.warns(hf.CoverageWarning, match=r"CSV.*gaps: \[0\.56"):
        path = b.to_csv(tmp_path / "frf.csv")
    rows = np.genfromtxt(path, delimiter=",", names=True)
    assert rows.size == len(b) + 1
    gap = first.stop
    assert np.all(np.isnan([rows[n][gap] for n in rows.dtype.names]))
    np.testing.assert_allclose(rows["omega"][:gap], b.omega[first], rtol=1e-11)
    np.testing.assert_allclose(rows["omega"][gap + 1 :], b.omega[second], rtol=1e-11)
    # a line through the rows never spans the gap
    w = rows["omega"]
    a, c = b.gaps[0]
    joins = np.column_stack((w[:-1], w[1:]))
    spans = np.all(np.isfinite(joins), axis=1) & (
        (joins.min(axis=1) <= a) & (joins.max(axis=1) >= c)
    )
    assert not spans.any()


def test_plot_of_a_loaded_incomplete_branch_warns(two_pieces, tmp_path):
    back = hf.Branch.load(two_pieces.save(tmp_path / "b.npz"))
    with pytest.warns(hf.CoverageWarning, match="plot.*asked range"):
        back.plot()


def test_complete_branches_say_nothing(doubled, tmp_path):
    """No false alarm: a complete FRF, and a period-doubled branch that
    returned to its parent (it exists only between the doublings)."""
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 1.0))
    b = hf.frf(osc, 0.5, (0.5, 3.0), 15)
    _, _, b2 = doubled
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        for branch in (b, b2):
            branch.to_csv(tmp_path / "x.csv")
            branch.plot()
    rows = np.genfromtxt(tmp_path / "x.csv", delimiter=",", names=True)
    assert rows.size == len(b2) and np.all(np.isfinite(rows["omega"]))


def test_record_of_a_folded_branch_is_a_sweep():
    """A criterion record is one amplitude per frequency: sorted by Ω, the
    samples of a Duffing branch through its two folds interleaved the three
    sheets (1-term harmonic balance: three amplitudes at Ω = 1.2, 0.046,
    0.756, 0.774), which the criterion would join by straight lines. The
    record keeps what a sweep along the branch measures (hunt37's rule,
    merged over this test's first form, a warning): one jump, at the fold."""
    from hbmfric.criterion import FRFRecord

    duf = hf.Oscillator(1.0, 0.02, 1.0, hf.Cubic(1.0))
    b = hf.frf(duf, 0.02, (0.5, 2.0))
    assert b.folds.size == 2
    record = FRFRecord.from_branch(b, 1.0)
    assert np.all(np.diff(record.omega) > 0.0)
    steps = np.diff(np.log(record.amplitude))
    assert np.count_nonzero(np.abs(steps) > 1.0) == 1  # the jump at the fold
    # no sheet-to-sheet zigzag: the slope turns at the peak and the jump only
    signs = np.sign(steps[steps != 0.0])
    assert np.count_nonzero(signs[1:] != signs[:-1]) <= 3


def test_record_of_a_branch_with_a_gap_keeps_it(two_pieces):
    from hbmfric.criterion import FRFRecord

    record = FRFRecord.from_branch(two_pieces, 1.0)
    inner = [
        (lo, hi)
        for lo, hi in two_pieces.gaps
        if lo > two_pieces.omega.min() and hi < two_pieces.omega.max()
    ]
    assert inner and record.gaps == tuple(inner)


def test_record_of_a_plain_branch_is_quiet():
    from hbmfric.criterion import FRFRecord

    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 1.0))
    for sweep in ("up", "down"):
        b = hf.frf(osc, 0.5, (0.5, 3.0), sweep=sweep)
        with warnings.catch_warnings():
            warnings.simplefilter("error", hf.AccuracyWarning)
            FRFRecord.from_branch(b, 1.0)
            FRFRecord.from_branch(b, 1.0, resample=None)
