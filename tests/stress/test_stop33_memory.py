"""Stress rows for stop 33: the memory a solve plans against its budget.

Each row takes a system solved in full (a one-DOF oscillator, a three-DOF
chain and the paper beam with ``condense=False``), a fixed ``H`` or
``harmonics="auto"``, and a budget just below or just above the dense
matrices the solve needs (``hbmfric._memory``, counted from the problem's
own unknowns): below, ``frf`` raises ``MemoryError`` before any work (an
``auto`` run below its first level too) or stops its ladder where the
budget ends; above, it runs as before. Before stop 33 nothing was checked:
a model too large for the machine was killed by the operating system.

Run with ``python -m pytest -m stress tests/stress/test_stop33_memory.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric import _memory
from hbmfric.api import _problem
from hbmfric.continuation.adaptive import LADDER, START, probe_level

pytestmark = pytest.mark.stress


def _system(name: str):
    if name == "p1":
        law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
        return hf.Oscillator(1.0, 0.02, 1.0, law), 0.5, (0.5, 3.0)
    if name == "chain":
        k = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]])
        law = hf.Jenkins(stiffness=2.0, slip_force=0.3)
        chain = hf.LinearStructure(
            mass=np.eye(3),
            stiffness=k,
            damping=0.02 * k,
            contacts=[hf.Contact(law, 1)],
            load={2: 1.0},
        )
        return chain, 1.0, (0.5, 2.5)
    from hbmfric.paper.beam import HZ, paper_beam, paper_calibration

    return paper_beam(1.0, paper_calibration()), 2.0, (60.0 * HZ, 100.0 * HZ)


def _need(problem, rungs) -> float:
    rungs = tuple(rungs)
    per = problem.n_unknowns // problem.n_coef
    return _memory.level_plan_bytes(
        per, problem.odd, rungs, [probe_level(h, rungs) for h in rungs]
    )


ROWS = [(name, h) for name in ("p1", "chain", "beam") for h in (7, 15, 31, "auto")]


@pytest.mark.parametrize("name, harmonics", ROWS, ids=str)
def test_budget_below_the_need_is_said(name, harmonics, monkeypatch):
    system, force, omega = _system(name)
    condense = None if name == "p1" else False
    first = LADDER[START] if harmonics == "auto" else harmonics
    problem = _problem(system, force, first, None, None, "auto", condense)
    rungs = LADDER[: START + 1] if harmonics == "auto" else (harmonics,)
    need = _need(problem, rungs)
    monkeypatch.setattr(_memory, "budget", lambda: 0.5 * need)
    with pytest.raises(MemoryError, match="unknowns"):
        hf.frf(system, force, omega, harmonics=harmonics, condense=condense)
    if harmonics == "auto":
        return  # the ladder's stop: tests/test_memory_guard.py
    monkeypatch.setattr(_memory, "budget", lambda: 1.01 * need)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, force, omega, harmonics=harmonics, condense=condense)
    assert branch.n_points > 10
