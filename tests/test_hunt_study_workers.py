"""Parameter sets on workers (stop 29): warnings of sets traced in threads
of one process, and a worker process that dies.

A Dask worker with ``threads_per_worker > 1`` runs several sets of
:func:`hbmfric.study` at once in one process; ``warnings.catch_warnings``
is process-wide, so a set's warnings went to another set's list, or were
lost when the other set's exit restored the filters (a LocalCluster with
two threads: the set at 0.5 N listed clean, a stuck set at 1e-4 N with
its AccuracyWarning). The same two-thread schedule is reproduced here with
a thread pool calling the worker function directly.

A worker process that dies (os._exit here; a crash in native code or the
out-of-memory killer alike) broke the process pool and ``study`` raised
``BrokenProcessPool``, returning none of the sets already traced.
"""

from __future__ import annotations

import os
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


def build_or_die(p):
    if p["die"]:
        os._exit(3)
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def test_a_dead_worker_fails_the_unfinished_sets_and_keeps_the_rest():
    sets = [{"force": 1e-4, "die": False}, {"force": 1e-4, "die": True}]
    sets += [{"force": 1e-4, "die": False}] * 2
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = hf.study(
            build_or_die, sets, (0.5, 2.0), workers=2, harmonics=1, progress=False
        )
    assert [r.index for r in result.runs] == [0, 1, 2, 3]
    broken = "BrokenProcessPool: a worker process ended abruptly"
    assert result.runs[1].error.startswith(broken)
    assert all(r.ok or r.error.startswith(broken) for r in result.runs)
    assert any(issubclass(w.category, hf.StudyWarning) for w in caught)
    # what was traced before the pool broke is returned
    for r in result.runs:
        if r.ok:
            assert r.branch.complete
