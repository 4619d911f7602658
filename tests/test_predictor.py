"""The second-order predictor of the continuation (issue 18, stop 26): the
parabola through the previous point, its guards, and what it saves on P1."""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.continuation import Continuation, ContinuationOptions
from hbmfric.kernels.steps import arclength

P1_RANGE = (0.5, 3.0)


def p1():
    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    return hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)


def _circle(s, radius, scale):
    """Point at arc length ``s`` (scaled) of a circle through the origin,
    in physical units (``scale`` per coordinate)."""
    phi = s / radius
    return np.array([radius * np.sin(phi), radius * (1.0 - np.cos(phi))]) * scale


def _settings(on=True, max_angle=0.3):
    s = np.zeros(arclength.N_SETTINGS)
    s[arclength.PREDICTOR] = 1.0 if on else 0.0
    s[arclength.MAX_ANGLE] = max_angle
    return s


def _predict(step, h, radius, scale, settings, history=None):
    y = _circle(0.0, radius, scale)
    t = np.array([1.0, 0.0])  # unit tangent at the origin, scaled variables
    if history is None:
        history = np.vstack([_circle(-h, radius, scale), y])
    y_pred = np.empty(2)
    used = arclength.predict(y, t, step, scale, settings, history, y_pred)
    # distance from the circle, scaled
    c = np.array([0.0, radius])
    miss = abs(np.linalg.norm(y_pred / scale - c) - radius)
    return used, miss


@pytest.mark.parametrize("scale", [np.array([1.0, 1.0]), np.array([1e-3, 2.5])])
def test_parabola_misses_the_branch_by_the_cube_of_the_step(scale):
    """On a circle of radius r (scaled variables) the tangent's line misses
    by ds²/(2r); the parabola through the previous point (h = ds back) by
    O(ds³): 8 times less per halving, and far below the line."""
    r = 0.7
    misses = []
    for ds in (0.04, 0.02, 0.01):
        used, miss = _predict(ds, ds, r, scale, _settings())
        assert used
        _, line = _predict(ds, ds, r, scale, _settings(on=False))
        assert line == pytest.approx(ds * ds / (2.0 * r), rel=0.02)
        assert miss < 0.05 * line
        misses.append(miss)
    assert misses[0] / misses[1] > 6.0 and misses[1] / misses[2] > 6.0


def test_predictor_falls_back_to_the_tangent():
    """Straight line when the option is off, without a previous point of
    this very point (a corner, a failed corrector, a point set outside the
    kernels) and when the parabola would turn more than max_angle."""
    scale = np.array([1.0, 1.0])
    r, ds = 0.7, 0.02
    line = ds * ds / (2.0 * r)
    used, miss = _predict(ds, ds, r, scale, _settings(on=False))
    assert not used and miss == pytest.approx(line, rel=0.02)
    stale = np.vstack([_circle(-ds, r, scale), _circle(1e-9, r, scale)])
    used, miss = _predict(ds, ds, r, scale, _settings(), stale)
    assert not used and miss == pytest.approx(line, rel=0.02)
    none = np.full((2, 2), np.nan)
    used, _ = _predict(ds, ds, r, scale, _settings(), none)
    assert not used
    # turn over the step ds / r = 0.029 rad
    used, _ = _predict(ds, ds, r, scale, _settings(max_angle=0.02))
    assert not used
    used, _ = _predict(ds, ds, r, scale, _settings(max_angle=0.04))
    assert used


def test_history_follows_the_accepted_points():
    """advance leaves the previous point and the new one in ``history``;
    a step rejected for its corrector clears it (the retry predicts along
    the tangent)."""
    from hbmfric.hbm import HBMProblem

    problem = HBMProblem(p1(), 2.0, 7)
    cont = Continuation(problem, P1_RANGE, 1, ContinuationOptions())
    assert cont._settings[arclength.PREDICTOR] == 1.0
    off = Continuation(problem, P1_RANGE, 1, ContinuationOptions(curve_tolerance=None))
    assert off._settings[arclength.PREDICTOR] == 0.0
    # condensed problems keep the tangent (no gain on the paper beam)
    from hbmfric.condensation import CondensedHBMProblem

    condensed = CondensedHBMProblem(p1(), 2.0, 7)
    kept = Continuation(condensed, P1_RANGE, 1, ContinuationOptions())
    assert kept._settings[arclength.PREDICTOR] == 0.0
    state = cont.init()
    y0 = state.y.copy()
    while len(state.points) < 2:
        state = cont.step(state)
    np.testing.assert_array_equal(cont._history[0], y0)
    np.testing.assert_array_equal(cont._history[1], state.y)
    # a corrector that cannot converge in one iteration: rejected, cleared
    s = cont._settings.copy()
    s[arclength.MAX_NEWTON] = 1
    y, t = state.y.copy(), state.tangent.copy()
    out, _, _ = arclength.advance(
        problem.kernel_problem,
        cont._residual_at(),
        y,
        t,
        0.05,
        cont.scale.copy(),
        s,
        *cont._work,
    )
    assert out == arclength.REJECTED
    assert np.isnan(cont._history[1, -1])


@pytest.mark.parametrize("force", [0.1, 2.0])
def test_p1_corrector_needs_fewer_evaluations(force):
    """P1 with the curve rule: the tangent predictor missed the short
    steps' branch by about 4 curve tolerances and the corrector took 2.96 to
    3.04 residual evaluations per point (H = 7, F = 0.1 / 2); the parabola
    takes 2.23 to 2.26. The curve still meets the rule."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        b = hf.frf(p1(), force, P1_RANGE, 7)
    assert b.complete
    assert b.newton_iterations / len(b) < 2.5
    assert b.curve_error <= 1e-4


def test_points_solved_again_take_their_levels_tangent(monkeypatch):
    """The final pass of harmonics="auto" solves points over the tolerance
    again one rung higher; their stored tangents are the new level's
    (dX/dΩ against central differences of periodic solutions at Ω ± δ at
    that level, as in tests/test_curve.py), not the old level's padded
    ones (on P1 at F = 0.1 those were off by 5e-4 of the largest dX/dΩ,
    a new harmonic's whole slope missing)."""
    from hbmfric.continuation import adaptive

    settled = []
    original = adaptive.AdaptiveContinuation.settle

    def settle(self, points, levels, *args, **kwargs):
        before = list(levels)
        out = original(self, points, levels, *args, **kwargs)
        settled.extend(
            i for i, (a, b) in enumerate(zip(before, levels, strict=True)) if a != b
        )
        return out

    monkeypatch.setattr(adaptive.AdaptiveContinuation, "settle", settle)
    osc = p1()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        b = hf.frf(osc, 0.1, P1_RANGE)
    assert settled
    t = b.tangents
    for i in settled:
        h = b.harmonics_at(i)
        d = 1e-6
        sol = [hf.periodic_solution(osc, 0.1, b.omega[i] + s * d, h) for s in (1, -1)]
        fd = (sol[0].coefficients - sol[1].coefficients) / (2 * d)
        m = fd.shape[1]
        tg = t[i, :-1].reshape(b.coefficients.shape[1:])[:, :m] / t[i, -1]
        assert np.max(np.abs(fd - tg)) <= 1e-4 * np.max(np.abs(fd)), i


def test_p1_steps_sized_for_the_growing_bend():
    """Towards the stuck resonance the chord error per squared step grows
    from step to step; sized for the last one, the longer steps the
    parabola allows were rejected by the curve rule 14 times on P1 at
    F = 0.5, H = 7 (10 of 13 rejections at H = 15 were the rule's, at
    2.16-2.34 rad/s). Sized for the bend ahead: at most 10, and the curve
    within the rule."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        b = hf.frf(p1(), 0.5, P1_RANGE, 7)
    assert b.complete
    assert b.n_rejected <= 10
    assert b.curve_error <= 1e-4
