"""harmonics="auto": the harmonic count chosen along the branch."""

import warnings

import numpy as np
import pytest
from test_condensed_coulomb import Chain

import hbmfric as hf
from hbmfric.api import _problem
from hbmfric.continuation import adaptive
from hbmfric.continuation.palc import Continuation
from hbmfric.kernels.steps import arclength

OSC = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


@pytest.fixture(scope="module")
def branches():
    return {
        tol: hf.frf(OSC, 0.5, (0.5, 3.0), "auto", harmonic_tolerance=tol)
        for tol in (1e-3, 1e-4)
    }


SLOW = pytest.mark.slow


@pytest.mark.parametrize(
    "force, tol",
    [
        (0.5, 1e-3),
        (2.0, 1e-4),
        pytest.param(0.1, 1e-3, marks=SLOW),
        pytest.param(0.1, 1e-4, marks=SLOW),
        pytest.param(0.5, 1e-4, marks=SLOW),
        pytest.param(2.0, 1e-3, marks=SLOW),
    ],
)
def test_auto_reaches_tolerance_against_high_h(force, tol):
    """At 20 points spread over the branch, the first-harmonic amplitude and
    half the peak-to-peak of the adaptive branch agree with an H = 63
    solution to the tolerance (F = 2 slips over the whole range; F = 0.1
    mostly sticks)."""
    b = hf.frf(OSC, force, (0.5, 3.0), "auto", harmonic_tolerance=tol)
    assert b.stop_reason == "end of frequency range reached"
    worst = 0.0
    for i in np.unique(np.linspace(0, len(b) - 1, 20).astype(int)):
        ref = hf.periodic_solution(
            OSC, force, float(b.omega[i]), 63, initial_guess=b.point(i)
        )
        assert ref.converged
        for harmonic in (1, None):
            a = b.amplitude(harmonic=harmonic)[i]
            r = ref.amplitude(harmonic=harmonic)
            worst = max(worst, abs(a - r) / r)
    assert worst <= tol, worst
    assert worst > 0.0  # the check can fail: slipping points carry an error


def test_auto_reaches_tolerance_against_time_integration():
    """Gross slip over the whole range (F = 2): at the branch points nearest
    to four frequencies, the first harmonic and half the peak-to-peak agree
    with the time-integration steady state (Newmark, 2048 steps per period,
    its own error about 3e-6) to the tolerance, while H = 3 everywhere would
    not."""
    tol = 1e-3
    b = hf.frf(OSC, 2.0, (0.5, 3.0), "auto", harmonic_tolerance=tol)
    worst = 0.0
    worst_h3 = 0.0
    for w in (0.6, 0.95, 1.5, 2.5):
        i = int(np.argmin(np.abs(b.omega - w)))
        omega = float(b.omega[i])
        ref = hf.validation.steady_state(OSC, 2.0, omega, initial_state="linear")
        assert ref.converged
        low = hf.periodic_solution(OSC, 2.0, omega, 3, initial_guess=b.point(i))
        for harmonic in (1, None):
            r = ref.amplitude(harmonic=harmonic)
            worst = max(worst, abs(b.amplitude(harmonic=harmonic)[i] - r) / r)
            worst_h3 = max(worst_h3, abs(low.amplitude(harmonic=harmonic) - r) / r)
    assert worst <= tol, worst
    assert worst_h3 > 3 * tol, worst_h3


def test_auto_low_h_when_stuck_high_h_at_the_peak(branches):
    b = branches[1e-4]
    h = b.point_harmonics
    amp = b.amplitude(harmonic=1)
    lowest = adaptive.LADDER[0]
    assert h[0] == lowest and h[-1] == lowest  # both ends stuck: linear
    peak = int(np.argmax(amp))
    assert h[peak] >= 11
    assert h[peak] > 2 * lowest
    assert b.harmonic_numbers[-1] == h.max()
    # the truncated coefficients of a low-level point are exactly zero
    low = np.flatnonzero(h == lowest)[0]
    assert np.all(b.coefficients[low, 0, (lowest + 1) :] == 0.0)
    # on the slipping stretch H follows the error: less where it is smaller
    # (F = 2 slips everywhere; the low-frequency end needs the most)
    b2 = hf.frf(OSC, 2.0, (0.5, 3.0), "auto", harmonic_tolerance=1e-4)
    h2 = b2.point_harmonics
    assert h2[b2.omega < 0.7].min() > h2[b2.omega > 2.0].max()


def test_auto_few_changes_no_flapping(branches):
    """H changes at a few points only, and never goes back to the level it
    just left within ``LOWER_PATIENCE`` points."""
    for b in branches.values():
        h = b.point_harmonics
        changes = np.flatnonzero(np.diff(h)) + 1
        # F = 0.5, tol 1e-4: 8 changes before the curve rule budgeted the
        # points' error (at this bound), 10 after (shorter steps on the
        # slipping stretch reach the lowering patience sooner: 11 -> 7 ->
        # 11 -> 7 -> 3 near Ω = 2.3, each move at least LOWER_PATIENCE apart)
        assert 1 <= changes.size <= 10, h
        for a, c in zip(changes[:-1], changes[1:], strict=True):
            if h[c] == h[a - 1]:
                assert c - a >= adaptive.LOWER_PATIENCE
        assert b.info["harmonic_switches"] >= changes.size


def test_auto_cubic_spring_no_flapping():
    """A cubic spring's harmonics decay geometrically, not like a power of
    their order: at its 3rd superharmonic resonance the top harmonic of
    H = 21 vanishes while harmonic 3 is large. The run must neither take
    that for a linear response nor flap between levels (it once went back
    and forth between H = 21 and 3 for 5000 steps), and it meets the
    tolerance against H = 63."""
    duffing = hf.Oscillator(1.0, 0.02, 1.0, hf.Cubic(0.5))
    tol = 1e-3
    # the level logic on the points of the step control alone (the curve
    # rule adds points, and with them level decisions, but no flapping)
    b = hf.frf(
        duffing, 0.5, (0.3, 3.0), "auto", harmonic_tolerance=tol, curve_tolerance=None
    )
    assert b.stop_reason == "end of frequency range reached"
    fixed = hf.frf(duffing, 0.5, (0.3, 3.0), 15, curve_tolerance=None)
    assert len(b) <= 1.2 * len(fixed)
    assert b.info["harmonic_switches"] <= 12
    for i in np.linspace(0, len(b) - 1, 8).astype(int):
        ref = hf.periodic_solution(
            duffing, 0.5, float(b.omega[i]), 63, initial_guess=b.point(i)
        )
        for harmonic in (1, None):
            r = ref.amplitude(harmonic=harmonic)
            assert abs(b.amplitude(harmonic=harmonic)[i] - r) <= tol * r


def test_auto_branch_continuous_across_changes(branches):
    """Where H changes, successive points stay as close as elsewhere on the
    branch (in the scaled norm of the continuation), and the point after the
    change is the fixed-H solution of its level (no branch jump)."""
    b = branches[1e-4]
    h = b.point_harmonics
    changes = np.flatnonzero(np.diff(h)) + 1
    assert changes.size >= 2
    X = b.coefficients[:, 0]
    scale = np.max(np.abs(X))
    d = np.hypot(
        np.diff(b.omega) / 2.5, np.max(np.abs(np.diff(X, axis=0)), axis=1) / scale
    )
    assert np.max(d[changes - 1]) <= 1.5 * np.max(np.delete(d, changes - 1))
    for i in changes:
        fixed = hf.periodic_solution(
            OSC, 0.5, float(b.omega[i]), int(h[i]), initial_guess=b.point(i)
        )
        a = b.amplitude(harmonic=1)[i]
        assert abs(fixed.amplitude(harmonic=1) - a) <= 1e-8 * a


def test_change_estimate_matches_solved_change():
    """The compiled first-order change (one Newton step in the next level's
    basis) against the change actually found by solving both levels, at
    slipping points of the F = 2 branch: the same to 25 %."""
    h, h_up = 7, 11
    p, p_up = (_problem(OSC, 2.0, k, None, None, "auto", None) for k in (h, h_up))
    cont = Continuation(p, (0.5, 3.0))
    cont_up = Continuation(p_up, (0.5, 3.0))
    run = adaptive.AdaptiveContinuation(
        lambda k: {h: p, h_up: p_up}[k], (0.5, 3.0), 1, cont.options, 1.0, 1e-3
    )
    level = run._level(h_up)
    for w in (0.7, 1.0, 2.0):
        y, status, _ = cont.solve_at(w, p.initial_guesses(w)[0][:-1])
        assert status == 0
        y_up, status, _ = cont_up.solve_at(w, run.pad(y, h, h_up)[:-1])
        assert status == 0
        change = level.change(y)
        a1 = np.hypot(y[0], y[1])
        a1_up = np.hypot(y_up[0], y_up[1])
        t = np.linspace(0.0, 2 * np.pi, 4096, endpoint=False)
        hpp, hpp_up = (
            0.5 * np.ptp(hf.signals.synthesis_matrix(q.harmonic_numbers, t) @ v[:-1])
            for q, v in ((p, y), (p_up, y_up))
        )
        solved = max(abs(a1_up - a1) / a1, abs(hpp_up - hpp) / hpp)
        assert solved > 1e-6  # slipping: there is a change to measure
        assert change == pytest.approx(solved, rel=0.25)


@pytest.mark.parametrize(
    ("system", "force", "tol"),
    [
        ("jenkins", 0.1, 1e-3),
        ("jenkins", 0.5, 1e-4),
        ("jenkins", 2.0, 1e-4),
        ("cubic", 0.3, 1e-3),
    ],
)
def test_compiled_stretches_decide_as_python(monkeypatch, system, force, tol):
    """Between decisions the adaptive run stays at its level inside the
    compiled trace (``kernels.steps.arclength.stays``, due calibrations
    included); with that rule switched off every point goes through
    ``AdaptiveContinuation._adapt`` in Python. Both must give the same
    branch bit for bit: same points, levels and counters, calibrations
    included (the cubic spring exercises the flap cooldown)."""
    if system == "jenkins":
        law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    else:
        law = hf.Cubic(0.5)
    osc = hf.Oscillator(1.0, 0.02 if system == "jenkins" else 0.05, 1.0, law)

    def run():
        return hf.frf(osc, force, (0.3, 3.0), "auto", harmonic_tolerance=tol)

    compiled = run()
    make_watch = adaptive.AdaptiveContinuation._watch

    def python_only(self, h, levels):
        w = make_watch(self, h, levels)
        w[arclength.W_RECALIBRATE] = -1.0  # never fresh: no stay
        w[arclength.W_LOWEST] = 0.0  # no linear stay either
        w[arclength.W_CALIBRATE] = 0.0  # calibrations in Python too
        return w

    monkeypatch.setattr(adaptive.AdaptiveContinuation, "_watch", python_only)
    stepped = run()
    np.testing.assert_array_equal(stepped.point_harmonics, compiled.point_harmonics)
    np.testing.assert_array_equal(stepped.omega, compiled.omega)
    np.testing.assert_array_equal(stepped.coefficients, compiled.coefficients)
    counters = ("harmonic_calibrations", "harmonic_switches", "harmonic_resolves")
    assert (stepped.n_steps, stepped.n_rejected, stepped.newton_iterations) == (
        compiled.n_steps,
        compiled.n_rejected,
        compiled.newton_iterations,
    )
    assert [stepped.info[k] for k in counters] == [compiled.info[k] for k in counters]
    assert len(set(compiled.point_harmonics)) >= 2


def test_compiled_stretches_return_only_to_act(monkeypatch):
    """The compiled stretch takes every decision of ``_adapt`` that keeps
    the level (the carried estimate right after a calibration, the count
    of points below the lower threshold, due calibrations): each return to
    Python for a decision changes the level or solves the point again (P1
    at F = 0.1 / 0.5 / 2 before: 16 / 13 / 24 of 21 / 21 / 41 returns
    kept the level; the same branch bit for bit is
    ``test_compiled_stretches_decide_as_python``'s)."""
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    decide = adaptive.AdaptiveContinuation._adapt
    calls = []

    def logged(self, state, h, levels):
        resolves = self.n_resolves
        h_new = decide(self, state, h, levels)
        calls.append((len(levels), h, h_new, self.n_resolves - resolves))
        return h_new

    monkeypatch.setattr(adaptive.AdaptiveContinuation, "_adapt", logged)
    for force in (0.1, 0.5, 2.0):
        calls.clear()
        hf.frf(osc, force, (0.5, 3.0), "auto")
        assert len(calls) >= 3  # the level moves: there are decisions
        idle = [c for c in calls if c[1] == c[2] and c[3] == 0]
        assert idle == [], (force, idle)


@pytest.mark.parametrize(
    "law, condense, aft",
    [
        (hf.Jenkins(stiffness=3.0, slip_force=1.0), False, "auto"),
        (hf.Menq.from_stiffness(3.0, 1.0, microslip_onset=0.5), False, "auto"),
        (hf.Coulomb(slip_force=1.0, linear_tail=True), True, "auto"),
        (hf.Jenkins(stiffness=3.0, slip_force=1.0), True, "samples"),
        (hf.Jenkins(stiffness=3.0, slip_force=1.0), "direct", "auto"),
    ],
)
def test_level_problem_equals_a_fresh_build(law, condense, aft):
    """A level problem derived from another level (``with_harmonics``,
    sharing the system's data) has the residual, Jacobian and kernel data
    of the problem built from scratch at that ``H`` (full and condensed
    HBM, the rigid Coulomb tail whose length depends on ``H``)."""
    if condense is False:
        system = hf.Oscillator(1.0, 0.02, 1.0, law)
    else:
        system = Chain(law)
    base = _problem(system, 0.7, 7, None, None, aft, condense)
    rng = np.random.default_rng(3)
    for h in (3, 15):
        derived = base.with_harmonics(h)
        fresh = _problem(system, 0.7, h, None, None, aft, condense)
        assert type(derived) is type(fresh)
        assert (derived.n_time, derived.n_unknowns, derived.aft) == (
            fresh.n_time,
            fresh.n_unknowns,
            fresh.aft,
        )
        _same_data(derived.kernel_problem, fresh.kernel_problem)
        y = np.append(0.3 * rng.standard_normal(fresh.n_unknowns), 1.1)
        R1, J1, s1 = derived.residual(y)
        R2, J2, s2 = fresh.residual(y)
        np.testing.assert_array_equal(R1, R2)
        np.testing.assert_array_equal(J1, J2)
        assert s1 == s2
        pts = y[None, :]
        np.testing.assert_array_equal(
            derived.full_coefficients(pts), fresh.full_coefficients(pts)
        )
    # the base is untouched
    again = _problem(system, 0.7, 7, None, None, aft, condense)
    _same_data(base.kernel_problem, again.kernel_problem)


def _same_data(first, second):
    """Field by field equal kernel problems; the kept-factor solver's work
    arrays (a tuple field of the condensed problem) by shape."""
    for a, b in zip(first, second, strict=True):
        if isinstance(a, tuple):
            _same_shapes(a, b)
        else:
            np.testing.assert_array_equal(a, b)


def _same_shapes(first, second):
    """Equal shapes of the work arrays in (nested) tuples."""
    assert len(first) == len(second)
    for x, z in zip(first, second, strict=True):
        if isinstance(x, tuple):
            _same_shapes(x, z)
        else:
            assert np.shape(x) == np.shape(z)


def test_top_measure_zero_when_stuck():
    """A stuck Jenkins contact is linear: the higher harmonics vanish."""
    sol = hf.periodic_solution(OSC, 0.1, 0.7, 15)
    assert sol.contact_state == "contact stuck over the whole period"
    assert adaptive.top_measure(sol.harmonic_numbers, sol.coefficients) < 1e-12
    slip = hf.periodic_solution(OSC, 2.0, 0.7, 15)
    assert adaptive.top_measure(slip.harmonic_numbers, slip.coefficients) > 1e-5


def test_auto_compiles_nothing_per_level():
    """Kernels compile once per type signature: a second run that visits
    other levels (another force and tolerance) adds no signature, and the
    adaptive run's compiled trace (calibrations included) is the fixed-H
    one."""
    from hbmfric.kernels.aft import schemes as aft
    from hbmfric.kernels.linalg import lu as linalg
    from hbmfric.kernels.residuals import hbm
    from hbmfric.kernels.steps import arclength, newton, truncation

    hf.frf(OSC, 0.5, (0.5, 3.0), 7)
    traces = len(arclength.trace.signatures)

    def counts():
        out = {}
        for mod in (aft, arclength, hbm, linalg, newton, truncation):
            for name in dir(mod):
                obj = getattr(mod, name)
                if hasattr(obj, "signatures"):
                    out[mod.__name__ + "." + name] = len(obj.signatures)
        return out

    first = hf.frf(OSC, 0.5, (0.5, 3.0), "auto", harmonic_tolerance=1e-3)
    before = counts()
    second = hf.frf(OSC, 2.0, (0.5, 3.0), "auto", harmonic_tolerance=3e-5)
    assert set(second.point_harmonics) - set(first.point_harmonics)  # new levels
    assert counts() == before
    assert len(arclength.trace.signatures) == traces


def test_auto_save_load(tmp_path, branches):
    b = branches[1e-3]
    back = hf.Branch.load(b.save(tmp_path / "auto.npz"))
    np.testing.assert_array_equal(back.point_harmonics, b.point_harmonics)
    assert back.harmonics_at(0) == b.harmonics_at(0)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"harmonics": "many"}, "harmonics"),
        ({"harmonics": "auto", "n_time": 64}, "n_time"),
        ({"harmonics": "auto", "harmonic_tolerance": 0.0}, "harmonic_tolerance"),
        (
            {"harmonics": "auto", "harmonic_tolerance": float("nan")},
            "harmonic_tolerance",
        ),
    ],
)
def test_auto_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        hf.frf(OSC, 0.5, (0.5, 3.0), **kwargs)


def test_final_pass_solves_again_only_points_over_the_tolerance():
    """The final pass (``AdaptiveContinuation.settle``) solves a point again
    only if its own calibrated estimate exceeds the tolerance (count, not
    time). On the beam at Fn = 1 N the run lets a few points through
    (the estimate rose between two calibrations); with at most 8
    confirming calibrations per level the final pass also solved again 25
    points of 83-106 Hz whose carried estimate (2e-4) was several times
    their own (1e-5 to 8e-5)."""
    from hbmfric.continuation import ContinuationOptions
    from hbmfric.continuation.accuracy import truncation_errors
    from hbmfric.paper.beam import HZ, paper_beam, paper_calibration

    system = paper_beam(1.0, paper_calibration())
    start = adaptive.LADDER[adaptive.START]
    base = _problem(system, 2.0, start, None, None, "auto", None)
    problems = {start: base}

    def make(h):
        if h not in problems:
            problems[h] = base.with_harmonics(h)
        return problems[h]

    tol = 1e-4
    run = adaptive.AdaptiveContinuation(
        make, (15.0 * HZ, 110.0 * HZ), 1, ContinuationOptions(), None, tol
    )
    _, points, levels, _ = run.run()
    before = list(levels)
    # each point's own estimate at its level (what the final pass computes
    # when it calibrates the point)
    own = np.array(
        [
            adaptive.CHANGE_FACTOR * run._probe(h).change(y)
            if run._level(h).measure(y) > adaptive.LINEAR * 1e-4
            else 0.0
            for y, h in zip(points, before, strict=True)
        ]
    )
    # the run's own calibrations, reused by the final pass, are these
    # estimates of the same points
    fresh = np.array(run._fresh)
    assert fresh.shape == own.shape
    known = np.isfinite(fresh)
    assert np.count_nonzero(known) >= 20
    np.testing.assert_allclose(fresh[known], own[known], rtol=1e-12, atol=0.0)
    settled = run.n_settled
    errors = run.settle(points, levels, truncation_errors)
    again = {i for i in range(len(levels)) if levels[i] != before[i]}
    # the points aim at AIM times the requested tolerance: that is the bar
    aim = adaptive.AIM * tol
    assert run.tolerance == pytest.approx(aim)
    over = set(np.flatnonzero(own > aim).tolist())
    assert len(again) >= 3  # the run let some through: the check can fail
    assert again <= over
    assert run.n_settled - settled >= len(again)
    assert np.max(errors) <= aim


@pytest.mark.slow
def test_beam_auto_meets_the_tolerance_where_the_carried_ratio_read_low():
    """The beam at Fn = 1 N at defaults, 110-125 rad/s, against the exact
    event-driven reference: every point within the default tolerance
    (1e-4) on the first harmonic and half the peak-to-peak value of the
    contact. With the final pass relying on the run's calibrations (up to
    16 points apart) the H = 21 stretch there kept a ratio carried from
    109 rad/s, 4-10 times low, and the half peak-to-peak was 1.57e-4 off
    at 119.6 rad/s."""
    from hbmfric.paper.beam import HZ, paper_beam, paper_calibration
    from hbmfric.validation import exact_periodic_solution

    system = paper_beam(1.0, paper_calibration())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(system, 2.0, (15.0 * HZ, 110.0 * HZ))
    a1 = branch.amplitude(harmonic=1)
    app = branch.amplitude()
    index = np.flatnonzero((branch.omega >= 110.0) & (branch.omega <= 125.0))
    assert index.size >= 5
    worst = 0.0
    for i in index:
        ref = exact_periodic_solution(
            system,
            2.0,
            float(branch.omega[i]),
            initial_guess=branch.point(int(i)),
            tol=1e-12,
        )
        assert ref.residual <= 1e-12
        e1 = abs(a1[i] / ref.amplitude(harmonic=1) - 1.0)
        epp = abs(app[i] / ref.amplitude() - 1.0)
        worst = max(worst, e1, epp)
    assert worst <= 1e-4, worst
