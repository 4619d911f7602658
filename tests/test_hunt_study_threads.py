"""Warnings of parameter sets traced in threads of one process (stop 29).

A Dask worker with ``threads_per_worker > 1`` runs several sets of
:func:`hbmfric.study` at once in one process; ``warnings.catch_warnings``
is process-wide, so a set's warnings went to another set's list, or were
lost when the other set's exit restored the filters (a LocalCluster with
two threads: the set at 0.5 N listed clean, a stuck set at 1e-4 N with
its AccuracyWarning). The same two-thread schedule is reproduced here with
a thread pool calling the worker function directly.
"""

from __future__ import annotations

import time
import warnings
from concurrent.futures import ThreadPoolExecutor

import hbmfric as hf
from hbmfric.study import _run_one


def build(p):
    # the set that warns enters second and warns after the first has left
    time.sleep(p["delay"])
    if p["warn"]:
        warnings.warn(f"set {p['name']} warns", UserWarning, stacklevel=1)
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def test_each_set_keeps_its_own_warnings_in_threads():
    options = {"omega": (0.5, 2.0), "harmonics": 1}
    # warm: the first set's branch then takes milliseconds, not the
    # seconds of loading the compiled kernels
    _run_one(build, "force", options, (0, {"force": 1e-4, "warn": False, "delay": 0}))
    quiet = {"force": 1e-4, "name": "quiet", "warn": False, "delay": 0.1}
    loud = {"force": 1e-4, "name": "loud", "warn": True, "delay": 1.0}
    with ThreadPoolExecutor(2) as pool:
        first = pool.submit(_run_one, build, "force", options, (0, quiet))
        time.sleep(0.05)
        second = pool.submit(_run_one, build, "force", options, (1, loud))
        runs = [first.result(), second.result()]
    assert all(r.ok for r in runs), [r.error for r in runs]
    assert not any("warns" in w for w in runs[0].warnings), runs[0].warnings
    assert any("set loud warns" in w for w in runs[1].warnings), runs[1].warnings
