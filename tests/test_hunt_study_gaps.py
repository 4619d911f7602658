"""A study whose branches did not cover the band, read back by the
criterion (stop 35, hunt37).

``StudyResult.to_csv`` wrote the points of an incomplete branch as a curve
(nothing in the file said it had a gap), ``read_frfs`` sorted them and the
criterion joined them across the gap by a straight line: on the docs'
Jenkins family traced with ``max_steps=60`` every branch missed its
resonance and the verdict was "undecided: no mostly stuck curve ... add
values of Fex/Fn", a reason about the chord. ``FRFRecord.from_branch`` did
the same. Reference: the complete branches, whose peaks lie in the gaps.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.criterion import FRFRecord, choose_contact_model, read_frfs

BAND = (0.5, 3.0)


def build(p):
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 0.3 * p["normal_load"]))


GRID = hf.grid(force=[0.02, 0.2], normal_load=[1.0, 10.0])


def _study(**options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return hf.study(build, GRID, BAND, executor="serial", **options)


@pytest.fixture(scope="module")
def studies():
    return _study(max_steps=60), _study()


def test_partial_sets_written_beside_the_csv_and_read_back(studies, tmp_path):
    short, complete = studies
    path = short.to_csv(tmp_path / "family.csv")
    side = tmp_path / "family.partial.csv"
    assert side.is_file()
    records = read_frfs(path)
    for r, run, ref in zip(records, short.runs, complete.runs, strict=True):
        assert r.gaps, run.index
        (lo, hi), peak = r.gaps[0], ref.branch.omega[np.argmax(ref.branch.amplitude())]
        # the complete branch peaks inside the gap: no sample of it there
        assert lo < peak < hi
        assert not np.any((r.omega > lo) & (r.omega < hi))
    with pytest.warns(hf.CoverageWarning, match="records have gaps"):
        choose_contact_model(records)
    with pytest.warns(hf.CoverageWarning, match="records have gaps"):
        choose_contact_model(short.records())
    # a complete study written to the same path removes the stale list
    complete.to_csv(path)
    assert not side.exists()
    assert all(not r.gaps for r in read_frfs(path))
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        choose_contact_model(read_frfs(path))


def test_record_gaps_checked():
    w, a = np.linspace(1.0, 2.0, 6), np.ones(6)
    assert FRFRecord(1.0, 1.0, w, a, gaps=[(1.5, 1.7)]).gaps == ((1.5, 1.7),)
    with pytest.raises(ValueError, match="low < high"):
        FRFRecord(1.0, 1.0, w, a, gaps=[(1.7, 1.5)])
