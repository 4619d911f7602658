"""A new user's first day (stop 33): the mistakes a newcomer makes at the
public edge are refused or warned about with what to do."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf


def _chain(n: int = 3):
    k = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    return np.eye(n), k


def test_scalar_load_says_what_to_give():
    m, k = _chain()
    with pytest.raises(ValueError, match=r"mapping \{dof: value\}.*load=\{j: 1.0\}"):
        hf.LinearStructure(m, k, load=1.0)


def test_wrong_length_load_mentions_the_mapping():
    m, k = _chain()
    with pytest.raises(ValueError, match=r"shape \(3,\).*mapping"):
        hf.LinearStructure(m, k, load=[1.0, 0.0])


def _build(p):  # reads only force-independent "slip_force"
    return hf.Oscillator(1.0, 0.05, 1.0, hf.Jenkins(3.0, p["slip_force"]))


def _study(params):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = hf.study(_build, params, (0.8, 1.2), executor="serial", harmonics=3)
    return result, [str(w.message) for w in caught if w.category is hf.StudyWarning]


def test_study_warns_about_a_parameter_build_never_reads():
    # a misspelt axis ("slip_forse") is never read: both sets are the same
    # system, which the study used to trace twice without a word
    params = hf.grid(force=[0.1], slip_force=[1.0], slip_forse=[0.5, 2.0])
    result, messages = _study(params)
    assert any("'slip_forse'" in m and "never read" in m for m in messages)
    assert all(r.unread == ("slip_forse",) for r in result.runs)


def test_study_is_quiet_when_every_parameter_is_read():
    params = hf.grid(force=[0.1], slip_force=[0.5, 1.0], normal_load=[1.0])
    result, messages = _study(params)
    assert not messages  # normal_load: a tag for the criterion, not warned
    assert all(r.unread == ("normal_load",) for r in result.runs)


def test_read_tracker_counts_bulk_reads():
    from hbmfric.study import _ReadTracker

    for read in (dict, lambda p: {**p}, lambda p: list(p.items()), list):
        p = _ReadTracker({"a": 1, "b": 2})
        read(p)
        assert p.read == {"a", "b"}
    p = _ReadTracker({"a": 1, "b": 2})
    p.get("a")
    assert p.read == {"a"}
