"""Stress row for stop 34 (hunt35): the memory a full solve with 2D
elements actually holds, against what the memory guard plans for it.

In a fresh process (the kernels loaded from the cache by a small warm-up
solve first), ``periodic_solution`` of a 60-DOF chain with four 2D
elements at ``H = 15``, ``condense=False``: the peak resident memory
above the warm process must stay within the guard's plan
(:func:`hbmfric._memory.level_plan_bytes` of the level and its probe,
340 MB). On main every element's normal output built a probe level of
its own: 1.17 GB (3.4 times the plan; eight elements 2.0 GB, 6 times),
so a run the guard let through could be killed by the operating system.
Now 0.29 GB.

Run with ``python -m pytest -m stress tests/stress/test_stop34_probe_memory.py``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

pytestmark = pytest.mark.stress

SCRIPT = textwrap.dedent(
    """
    import resource, warnings
    import numpy as np
    import hbmfric as hf
    from hbmfric import _memory
    from hbmfric.api import _problem
    from hbmfric.continuation.adaptive import LADDER, probe_level

    warnings.simplefilter("ignore")

    def chain(n, n_elements):
        K = np.zeros((n, n))
        for i in range(n):
            K[i, i] += 1.0
            if i + 1 < n:
                K[i, i] += 1.0
                K[i, i + 1] = K[i + 1, i] = -1.0
        el = hf.Contact2D(
            tangential_stiffness=1.0, normal_stiffness=2.0,
            friction_coefficient=0.3, preload=0.05,
        )
        contacts = [hf.Contact(el, 2 * i + 1, normal=2 * i + 2)
                    for i in range(n_elements)]
        return hf.LinearStructure(np.eye(n), K, rayleigh=(0.01, 0.02),
                                  contacts=contacts, load={n - 1: 0.1})

    hf.periodic_solution(chain(12, 4), 0.1, 0.4, harmonics=3, condense=False)
    s = chain(60, 4)
    problem = _problem(s, 0.1, 15, None, None, "auto", False)
    plan = _memory.level_plan_bytes(60, problem.odd, [15], [probe_level(15, LADDER)])
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0
    hf.periodic_solution(s, 0.1, 0.4, harmonics=15, condense=False)
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0
    print(after - before, plan)
    """
)


def test_full_solve_with_elements_stays_within_the_plan():
    # this checkout's package first, as the tests import it
    root = str(Path(__file__).resolve().parents[2])
    path = os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH")) if p)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=path)
    out = subprocess.run(
        [sys.executable, "-c", SCRIPT],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=True,
    )
    used, plan = (float(v) for v in out.stdout.split()[-2:])
    assert used <= plan, (used / 1e6, plan / 1e6)
