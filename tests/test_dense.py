"""Dense output of a branch (issue 18): the curve between the points.

References: closed-form curves (a linear oscillator's FRF, a folded
parametric curve), exact event-driven periodic solutions of the P1 Jenkins
oscillator (``hbmfric.validation.exact_branch``), and HBM solutions of the
branch's own discretisation at the checked pulsations (which isolate the
interpolation error from the points' own error).
"""

from __future__ import annotations

import csv
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.results import Branch

M, C, K, F = 1.0, 0.1, 1.0, 1.0


def _linear_response(omega):
    """Complex amplitude X of m x'' + c x' + k x = F cos Ωt, and dX/dΩ."""
    d = K - M * omega**2 + 1j * C * omega
    return F / d, -F * (-2.0 * M * omega + 1j * C) / d**2


def _branch(omega, coef, tangents=None, pieces=None, folds=()):
    """A Branch of one DOF with harmonic 1 only (coefficients [Xc, Xs])."""
    omega = np.asarray(omega, dtype=float)
    return Branch(
        omega=omega,
        coefficients=np.asarray(coef, dtype=float).reshape(omega.size, 1, 2),
        harmonic_numbers=np.array([1]),
        force=F,
        folds=np.asarray(folds, dtype=np.int64),
        stop_reason="test",
        n_steps=omega.size,
        n_rejected=0,
        newton_iterations=0,
        elapsed=0.0,
        tangents=tangents,
        pieces=pieces,
    )


def linear_branch(n, tangents=True, lo=0.5, hi=1.5):
    """The closed-form FRF of a linear oscillator at n equidistant Ω; with
    the exact tangents d(Xc, Xs, Ω)/dΩ (their length is irrelevant)."""
    w = np.linspace(lo, hi, n)
    X, dX = _linear_response(w)
    coef = np.stack((X.real, -X.imag), axis=1)
    t = np.stack((dX.real, -dX.imag, np.ones(n)), axis=1) if tangents else None
    return _branch(w, coef, t)


def interval_errors(branch, per=40):
    """True largest relative error of the dense amplitude at fixed Ω on
    every interval of a linear_branch (closed form)."""
    u = np.arange(1, per + 1) / (per + 1)
    w = branch.omega[:-1, None] + u * np.diff(branch.omega)[:, None]
    a = branch.amplitude_at(w.ravel())[:, 0].reshape(w.shape)
    exact = np.abs(_linear_response(w)[0])
    return np.max(np.abs(a - exact) / exact, axis=1)


@pytest.mark.parametrize("tangents", [True, False])
def test_dense_order_four_on_closed_form_frf(tangents):
    """Halving the step divides the dense error by about 16 (cubic Hermite,
    exact or five-point tangents), and at 161 points it is far below the
    straight lines' error."""
    errs = []
    for n in (41, 81, 161):
        b = linear_branch(n, tangents=tangents)
        errs.append(interval_errors(b, per=8).max())
    order = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(order > 3.5), (errs, order)
    b = linear_branch(161, tangents=tangents)
    w = np.linspace(0.5, 1.5, 997)
    exact = np.abs(_linear_response(w)[0])
    chords = np.abs(np.interp(w, b.omega, b.amplitude(harmonic=1)) - exact) / exact
    assert errs[-1] < 1e-5 and errs[-1] < 1e-2 * chords.max()


def test_dense_tangent_source_and_points_exact():
    b = linear_branch(41)
    s = b.evaluate(b.arclength)
    assert s.tangents == "stored"
    assert np.array_equal(s.omega, b.omega)
    assert np.array_equal(s.coefficients, b.coefficients)
    assert linear_branch(41, tangents=False).resample(2).tangents == (
        "finite differences"
    )


@pytest.mark.parametrize("n", [41, 81, 161, 321])
@pytest.mark.parametrize("tangents", [True, False])
def test_dense_error_estimate_never_below_half_the_true_error(n, tangents):
    """On every interval the estimate is at least half the true error (and
    not more than 50x it where that error is above rounding), from a
    resolution where the dense error is about 1e-3 (41 points over the
    resonance of a 5 % damped oscillator) to 3e-7."""
    b = linear_branch(n, tangents=tangents)
    true = interval_errors(b)
    est = b.dense_error()
    assert est.shape == (n - 1,)
    assert np.all(est >= 0.5 * true), np.max(true / est)
    big = true > 1e-12
    assert np.all(est[big] <= 50.0 * true[big]), np.max(est[big] / true[big])


def folded_branch(n, tangents=True):
    """Ω = 1 + cos(θ)/2, amplitude 2 + sin θ for θ in [-2, 2]: a fold at
    θ = 0 (Ω = 1.5)."""
    th = np.linspace(-2.0, 2.0, n)
    coef = np.stack((2.0 + np.sin(th), np.zeros(n)), axis=1)
    t = None
    if tangents:
        t = np.stack((np.cos(th), np.zeros(n), -0.5 * np.sin(th)), axis=1)
    return _branch(1.0 + 0.5 * np.cos(th), coef, t, folds=[n // 2 + 1])


@pytest.mark.parametrize("tangents", [True, False])
def test_amplitude_at_returns_every_value_past_a_fold(tangents):
    b = folded_branch(61, tangents)
    w = np.array([0.7, 0.85, 1.2, 1.45, 1.6, 1.0 + 0.5 * np.cos(2.0)])
    amp, err = b.amplitude_at(w, return_error=True)
    assert amp.shape == err.shape == (6, 2)
    # the path spans Ω in [1 + cos(2)/2, 1.5]: nothing below or above it,
    # two passes (in path order: θ < 0 first) in between
    assert np.all(np.isnan(amp[[0, 4]]))
    c = np.sqrt(1.0 - (2.0 * (w[1:4] - 1.0)) ** 2)  # |sin θ| of the two passes
    np.testing.assert_allclose(amp[1:4, 0], 2.0 - c, rtol=1e-5)
    np.testing.assert_allclose(amp[1:4, 1], 2.0 + c, rtol=1e-5)
    assert np.all(err[1:4] >= 0.0)
    # the first and last points (both at Ω = 1 + cos(2)/2): two values
    assert amp[5] == pytest.approx([2.0 - np.sin(2.0), 2.0 + np.sin(2.0)])


def test_nothing_is_interpolated_across_pieces():
    b = linear_branch(41)
    b.pieces = np.array([0, 20])
    s = b.arclength
    mid = 0.5 * (s[19] + s[20])
    out = b.evaluate([s[19], mid, s[20]])
    assert out.omega[0] == b.omega[19] and out.omega[2] == b.omega[20]
    assert np.isnan(out.omega[1]) and out.interval[1] == -1
    gap = 0.5 * (b.omega[19] + b.omega[20])
    assert np.all(np.isnan(b.amplitude_at([gap])))
    assert np.isnan(b.dense_error()[19])
    r = b.resample(4)
    assert len(r) == (20 - 1) * 4 + 1 + (21 - 1) * 4 + 1
    assert np.all(np.isfinite(r.omega))
    # outside the path
    assert np.all(np.isnan(b.evaluate([-1.0, s[-1] * 1.01]).omega))


def test_dense_output_of_empty_single_point_and_lone_point_pieces():
    empty = _branch(np.zeros(0), np.zeros((0, 2)))
    assert empty.arclength.size == 0 and len(empty.resample(4)) == 0
    assert np.isnan(empty.amplitude_at([1.0])).all()
    assert empty.dense_error().size == 0
    one = linear_branch(1)
    assert one.amplitude_at([0.5])[0, 0] == pytest.approx(one.amplitude(1)[0])
    assert np.isnan(one.amplitude_at([0.6])).all()
    assert len(one.resample(4)) == 1
    b = linear_branch(5)
    b.pieces = np.array([0, 4])  # the last point is a piece of its own
    r = b.resample(2)
    assert len(r) == 3 * 2 + 1 + 1 and r.omega[-1] == b.omega[-1]
    assert b.amplitude_at([b.omega[-1]])[0, 0] == pytest.approx(b.amplitude(1)[-1])
    assert np.isnan(b.dense_error()[3])


def test_dense_fallback_for_saved_branches_without_tangents(tmp_path):
    b = linear_branch(81)
    b.tangents = None
    path = b.save(tmp_path / "old.npz")
    old = Branch.load(path)
    assert old.tangents is None
    w = np.linspace(0.51, 1.49, 101)
    exact = np.abs(_linear_response(w)[0])
    err = np.abs(old.amplitude_at(w)[:, 0] - exact) / exact
    assert err.max() < 1e-4


def test_dense_input_validation():
    b = linear_branch(11)
    with pytest.raises(ValueError, match="arclength"):
        b.evaluate([np.nan])
    with pytest.raises(ValueError, match="omega"):
        b.amplitude_at([np.inf])
    with pytest.raises(ValueError, match="per_interval"):
        b.resample(0)


# ---------------------------------------------------------------------------
# P1 (Jenkins SDOF m=1, c=0.02, k=1, kt=3, fs=1) against exact references
# ---------------------------------------------------------------------------

P1 = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
P1_OMEGA = np.linspace(0.5, 3.0, 101)


@pytest.fixture(scope="module")
def p1_cases():
    from hbmfric.validation import exact_branch

    out = {}
    for force in (0.1, 0.5, 2.0):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            branch = hf.frf(P1, force, (0.5, 3.0))
        refs = exact_branch(P1, force, P1_OMEGA, on_failure="raise")
        exact = np.array([r.amplitude(harmonic=1) for r in refs])
        out[force] = (branch, exact)
    return out


@pytest.mark.parametrize("force", [0.1, 0.5, 2.0])
def test_p1_dense_output_within_1e4_of_exact(p1_cases, force):
    """Dense output of the default branch against exact event-driven
    solutions at 101 pulsations: within 1e-4 (relative)."""
    branch, exact = p1_cases[force]
    amp = branch.amplitude_at(P1_OMEGA)
    err = np.nanmin(np.abs(amp - exact[:, None]), axis=1) / exact
    assert np.all(np.isfinite(err))
    assert err.max() <= 1e-4, (err.max(), P1_OMEGA[np.argmax(err)])


@pytest.mark.parametrize("force", [0.1, 0.5, 2.0])
def test_p1_dense_estimate_never_below_half_the_interpolation_error(p1_cases, force):
    """The estimate of the interval holding each checked pulsation against
    the dense output's distance from the HBM solution of the branch's own
    discretisation there (the interpolation error alone). Intervals whose
    two points used different harmonics (``harmonics="auto"`` switching
    level) are left out: there the branch itself jumps by the change of
    truncation error, which is the points' error, not the interpolant's."""
    branch, _ = p1_cases[force]
    amp, est = branch.amplitude_at(P1_OMEGA, return_error=True)
    d = branch._dense()
    for j, w in enumerate(P1_OMEGA):
        ((i, _),) = d.solve_omega([w])[0][:1]
        if branch.harmonics_at(i) != branch.harmonics_at(i + 1):
            continue
        k = i if abs(branch.omega[i] - w) <= abs(branch.omega[i + 1] - w) else i + 1
        sol = hf.periodic_solution(
            P1, force, float(w), branch.harmonics_at(k), initial_guess=branch.point(k)
        )
        ref = sol.amplitude(harmonic=1)
        true = abs(amp[j, 0] - ref) / ref
        # checked where the error matters for the 1e-4 tolerance (above 1 %
        # of it); below, at 1e-7 after the merge with the final step
        # control, the estimate was once 3.3x low (F = 2, Ω = 0.575)
        if true > 1e-6:
            assert est[j, 0] >= 0.5 * true, (w, true, est[j, 0])


# ---------------------------------------------------------------------------
# users of the dense output: plot, CSV, criterion
# ---------------------------------------------------------------------------


def test_plot_draws_dense_curve_points_or_polyline():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    b = linear_branch(21)
    b.pieces = np.array([0, 10])
    ax = b.plot(harmonic=1)
    lines = ax.get_lines()
    assert [line.get_xdata().size for line in lines] == [9 * 8 + 1, 10 * 8 + 1]
    ax = b.plot(curve="points")
    assert all(line.get_linestyle() == "None" for line in ax.get_lines())
    assert sum(line.get_xdata().size for line in ax.get_lines()) == 21
    ax = b.plot(curve="polyline", per_interval=3)
    assert sum(line.get_xdata().size for line in ax.get_lines()) == 21
    with pytest.raises(ValueError, match="curve"):
        b.plot(curve="spline")
    plt.close("all")


def test_figure_csv_resample(tmp_path):
    from hbmfric.paper.sdof import FigureResult

    b = linear_branch(41)
    fig = FigureResult(
        "f", "f", ["a"], [b], [{"force": 1.0, "normal_load": 2.0, "ratio": 0.5}]
    )
    plain = fig.write_csv(tmp_path / "plain.csv")
    dense = fig.write_csv(tmp_path / "dense.csv", resample=4)
    rows = list(csv.DictReader(open(plain)))
    assert len(rows) == 41 and "computed" not in rows[0]
    rows = list(csv.DictReader(open(dense)))
    assert len(rows) == 40 * 4 + 1
    computed = [r for r in rows if r["computed"] == "1"]
    assert len(computed) == 41
    np.testing.assert_allclose(
        [float(r["amplitude_h1_m"]) for r in computed], b.amplitude(harmonic=1)
    )
    w = np.array([float(r["omega_rad_s"]) for r in rows])
    a = np.array([float(r["amplitude_h1_m"]) for r in rows])
    exact = np.abs(_linear_response(w)[0])
    chord = np.interp(w, b.omega, b.amplitude(harmonic=1))
    # the interpolated rows follow the closed form better than the chords
    assert np.max(np.abs(a - exact) / exact) < 0.2 * np.max(
        np.abs(chord - exact) / exact
    )
    with pytest.raises(ValueError, match="resample"):
        fig.write_csv(tmp_path / "bad.csv", resample=0)


def test_cli_resample_argument():
    import argparse

    from hbmfric.cli import _resample_arg

    assert _resample_arg("4") == 4
    for bad in ("0", "x", "-2"):
        with pytest.raises(argparse.ArgumentTypeError):
            _resample_arg(bad)


def test_criterion_record_samples_dense_output():
    from hbmfric.criterion import FRFRecord

    b = linear_branch(161)
    rec = FRFRecord.from_branch(b, 1.0)
    pts = FRFRecord.from_branch(b, 1.0, resample=None)
    assert pts.omega.size == 161 and rec.omega.size == 160 * 8 + 1
    exact = np.abs(_linear_response(rec.omega)[0])
    assert np.max(np.abs(rec.amplitude - exact) / exact) < 1e-4


# ---------------------------------------------------------------------------
# slow: the paper beam (exact event-driven references) and a Menq oscillator
# (time integration)
# ---------------------------------------------------------------------------


def _dense_check(branch, omega, reference, dof=None):
    """Dense curve error and, at every reference pulsation, the estimate of
    the interval used."""
    from hbmfric.dense import dense_curve_error

    err = dense_curve_error(branch, omega, reference, dof=dof)
    return err


@pytest.mark.slow
@pytest.mark.parametrize(
    "normal_load",
    [
        5.0,
        1.0,
        0.5,
    ],
)
def test_beam_dense_output_within_1e4_of_exact(normal_load):
    from hbmfric.paper.beam import HZ, paper_beam, paper_calibration
    from hbmfric.validation.curve import curve_references

    beam = paper_beam(normal_load, paper_calibration())
    rng = (15.0 * HZ, 110.0 * HZ)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(beam, 2.0, rng)
    for dof in ("contact", "force"):  # the tip and the forced DOF
        w, ref = curve_references(
            beam, 2.0, np.linspace(*rng, 101), method="exact", dof=dof
        )
        err = _dense_check(branch, w, ref, dof=dof)
        assert err.max <= 1e-4, (dof, err.max, err.worst_omega)


@pytest.mark.slow
def test_menq_dense_output_within_1e4_of_time_integration():
    from hbmfric.validation.curve import curve_references

    law = hf.Menq.from_stiffness(3.0, 1.0, microslip_onset=0.5)
    system = hf.Oscillator(1.0, 0.02, 1.0, law)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        branch = hf.frf(system, 0.5, (0.5, 3.0))
    w, ref = curve_references(
        system, 0.5, np.linspace(0.5, 3.0, 100), method="integrate"
    )
    err = _dense_check(branch, w, ref)
    assert err.max <= 1e-4, (err.max, err.worst_omega)
