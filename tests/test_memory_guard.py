"""A solve whose dense matrices do not fit in memory says so before any
work (stop 33).

A model solved in full keeps dense matrices of order ``n_dof × n_coef``
per harmonic level; on an 81-DOF beam with a 2D contact element
``harmonics="auto"`` held about 5 GB at H = 31, and a larger model would
be killed by the operating system without a word (the allocation succeeds;
the pages fail when touched). The budget is replaced here by a small one so
that the guard acts on models that fit anyway; the reference for the
sizes is the problem's own count of unknowns.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric import _memory
from hbmfric.api import _problem
from hbmfric.continuation.adaptive import LADDER, START, probe_level


def _p1():
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def _chain():
    """Three DOFs, a Jenkins contact at the middle one: solved in full with
    ``condense=False``."""
    k = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]])
    return hf.LinearStructure(
        mass=np.eye(3),
        stiffness=k,
        damping=0.02 * k,
        contacts=[hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.3), 1)],
        load={2: 1.0},
    )


def _plan(problem, rungs):
    rungs = tuple(rungs)
    per = problem.n_unknowns // problem.n_coef
    return _memory.level_plan_bytes(
        per, problem.odd, rungs, [probe_level(h, rungs) for h in rungs]
    )


@pytest.mark.parametrize("odd", [True, False])
@pytest.mark.parametrize("harmonics", [1, 3, 7, 15, 31])
def test_unknowns_are_the_problems_own(odd, harmonics):
    for system, condense in ((_p1(), None), (_chain(), False), (_chain(), None)):
        problem = _problem(system, 0.5, harmonics, None, odd, "auto", condense)
        per = problem.n_unknowns // problem.n_coef
        assert _memory.unknowns(per, harmonics, odd) == problem.n_unknowns


def test_fixed_harmonics_too_large_raise_before_any_work(monkeypatch):
    system = _chain()
    problem = _problem(system, 0.5, 15, None, None, "auto", False)
    need = _plan(problem, [15])
    monkeypatch.setattr(_memory, "budget", lambda: 0.5 * need)
    with pytest.raises(MemoryError, match="craig_bampton"):
        hf.frf(system, 0.5, (0.5, 2.5), harmonics=15, condense=False)
    with pytest.raises(MemoryError, match="unknowns at H = 15"):
        hf.periodic_solution(system, 0.5, 1.0, harmonics=15, condense=False)
    # room for it: traced as before
    monkeypatch.setattr(_memory, "budget", lambda: 1.01 * need)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(system, 0.5, (0.5, 2.5), harmonics=15, condense=False)
    assert branch.complete


def test_auto_ladder_stops_where_memory_ends_and_says_so(monkeypatch):
    """P1 at F = 2 climbs to H = 31-45 unhindered; with room for the rungs
    up to 15 only, every point stays at or below 15, the branch records
    the limit, and the points that needed more are warned about with the
    reason."""
    system = _p1()
    problem = _problem(system, 2.0, LADDER[START], None, None, "auto", None)
    top = LADDER.index(15) + 1
    room = _plan(problem, LADDER[:top])
    assert room < _plan(problem, LADDER[: top + 1])
    free = hf.frf(system, 2.0, (0.5, 3.0))
    assert free.point_harmonics.max() > 15  # the unhindered run goes higher
    assert "memory_limit" not in free.info
    monkeypatch.setattr(_memory, "budget", lambda: room)
    with pytest.warns(hf.AccuracyWarning, match="ladder stopped at H=15"):
        capped = hf.frf(system, 2.0, (0.5, 3.0))
    assert capped.point_harmonics.max() == 15
    assert capped.info["memory_limit"]["harmonics"] == 15
    assert capped.info["memory_limit"]["next_level_bytes"] > room
    assert np.max(capped.truncation_error) > capped.info["harmonic_tolerance"]
    # the auto periodic solution climbs the same rungs only
    with pytest.warns(hf.AccuracyWarning, match="ladder stopped at H = 15"):
        sol = hf.periodic_solution(system, 2.0, 1.2)
    assert sol.harmonic_numbers[-1] <= 15


def test_auto_without_room_for_its_first_level_raises(monkeypatch):
    system = _p1()
    problem = _problem(system, 0.5, LADDER[START], None, None, "auto", None)
    monkeypatch.setattr(
        _memory, "budget", lambda: 0.5 * _plan(problem, LADDER[: START + 1])
    )
    with pytest.raises(MemoryError, match="harmonics='auto'"):
        hf.frf(system, 0.5, (0.5, 3.0))


def test_available_memory_is_read():
    available = _memory.available_memory()
    assert available is None or available > 0
    assert _memory.budget() > 0.0


def test_mem_available_reads_its_line_wherever_it_is():
    # /proc/meminfo's text: the line first, inside, last without a newline
    rest = b"MemTotal:       32000000 kB\nMemFree:         1000 kB\n"
    line = b"MemAvailable:   21400432 kB"
    for text in (line + b"\n" + rest, rest + line + b"\nCached: 5 kB\n", rest + line):
        assert _memory.mem_available(text) == 21400432 * 1024
    assert _memory.mem_available(rest) is None
    assert _memory.mem_available(b"MemAvailable: many kB\n") is None
    assert _memory.mem_available(b"MemAvailable:\n") is None


def test_unknowns_follow_the_layout_of_the_harmonics():
    from hbmfric.hbm import select_harmonics

    for odd in (True, False):
        for h in range(1, 130):
            hn = select_harmonics(h, odd)
            n_coef = 2 * hn.size - (1 if hn[0] == 0 else 0)
            assert _memory.unknowns(3, h, odd) == 3 * n_coef
    with pytest.raises(ValueError, match="harmonics"):
        _memory.unknowns(1, 0, True)
