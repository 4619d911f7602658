"""Which part of the asked frequency range a branch covers (issue 14, item 3):
``Branch.coverage``/``gaps``/``complete``/``pieces``, the retrace from the
other end of the range, the ``CoverageWarning`` and truthful stop reasons,
and the early stops that used to end runs short."""

import math
import warnings

import numpy as np
import pytest
from naive import cubic_coefficients, sdof_residual

import hbmfric as hf
from hbmfric.continuation.palc import RANGE_END, RANGE_START

HZ = 2.0 * math.pi


@pytest.fixture
def no_coverage_warning():
    """Turn a CoverageWarning into an error inside the test."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        yield


def _cubic():
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Cubic(1.0))


def _jenkins_readme():
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def _cubic_residual(branch, i):
    """Independent harmonic-balance residual of the cubic oscillator at
    point ``i`` (exact convolution of the cube, plain NumPy), N."""
    hn = branch.harmonic_numbers
    X = branch.coefficients[i, 0]
    return sdof_residual(
        hn, X, branch.omega[i], 1.0, 0.02, 1.0, 1.0, cubic_coefficients(hn, X, 1.0)
    )


# ----------------------------------------------------------------------------
# coverage of ordinary runs


@pytest.mark.parametrize("sweep", ["up", "down"])
@pytest.mark.parametrize("harmonics", [15, "auto"])
def test_full_runs_are_complete(sweep, harmonics, no_coverage_warning):
    """The README Jenkins example covers its range in either direction."""
    b = hf.frf(_jenkins_readme(), 0.5, (0.5, 3.0), harmonics, sweep=sweep)
    assert b.stop_reason == RANGE_END
    assert b.omega_range == (0.5, 3.0)
    assert b.coverage == (0.5, 3.0)
    assert b.gaps == [] and b.pieces is None
    assert b.complete and b.info["bridges"] == 0


def test_stop_reason_says_when_the_path_left_by_its_start():
    """Cubic k3 = 1, F = 1 swept down over (0.3, 5): the path from 5 goes
    down the lower branch to its fold near 1.65, turns back along the
    unstable middle branch and leaves the range at 5 again. It used to
    report "end of frequency range reached"."""
    with pytest.warns(hf.CoverageWarning, match=r"covers only \[1\.6"):
        b = hf.frf(_cubic(), 1.0, (0.3, 5.0), 15, sweep="down", retrace=False)
    assert b.stop_reason == RANGE_START
    assert b.omega[0] == 5.0 and b.omega[-1] == 5.0 and b.folds.size == 1
    lo, hi = b.coverage
    assert 1.6 < lo < 1.7 and hi == 5.0
    assert b.gaps == [(0.3, lo)]
    assert not b.complete


def test_retrace_completes_the_cubic_branch(no_coverage_warning):
    """The same run retraced up from 0.3 covers the range: two pieces, every
    point a solution of the harmonic balance (independent residual)."""
    b = hf.frf(_cubic(), 1.0, (0.3, 5.0), 15, sweep="down")
    assert b.complete and b.gaps == [] and b.coverage == (0.3, 5.0)
    first, second = b.piece_slices()
    # first piece: 5 -> fold -> 5; second: the up sweep reversed, 5 -> 0.3
    assert b.omega[first][[0, -1]].tolist() == [5.0, 5.0]
    assert b.omega[second][[0, -1]].tolist() == [5.0, 0.3]
    assert RANGE_START in b.stop_reason and RANGE_END in b.stop_reason
    # one fold in the first piece, the two of the hysteresis in the second
    assert b.folds.size == 3
    assert np.all(b.folds[1:] > first.stop)
    # a fold index marks a turn of Ω between points i - 1 and i
    d = np.diff(b.omega)
    for i in b.folds:
        assert d[i - 2] * d[i] < 0.0 or abs(d[i - 1]) < 1e-2
    for i in range(0, len(b), 7):
        R = _cubic_residual(b, i)
        assert np.max(np.abs(R)) < 1e-8


@pytest.mark.filterwarnings("ignore::hbmfric.AccuracyWarning")
def test_retrace_starts_past_a_load_fold(no_coverage_warning):
    """Cubic k3 = 1, F = 10 over (0.3, 3), swept up: the path turns at a
    fold near 0.314 and leaves by 0.3. The retrace from 3 rad/s found no
    starting point: at Ω = 3 the non-resonant solution the linear guesses
    lead to has just merged with the middle one (single-harmonic balance
    ``a (1 - Ω²) + 3/4 a³ = F`` peaks at 10.06 ≈ F), Newton and the load
    ramp stagnate at that fold (|R| = 2e-3) and only the resonant solution
    is left. Arc-length continuation in the load goes round the fold to
    it; the retrace then covers the range. The start is the resonant
    solution (single-harmonic root 3.77, 3 % off at H = 15) and every 7th
    point of the retrace solves an independent harmonic balance."""
    b = hf.frf(_cubic(), 10.0, (0.3, 3.0), 15)
    assert b.complete and b.coverage == (0.3, 3.0)
    first, second = b.piece_slices()
    # the retrace, stored in increasing Ω after the first piece, started at 3
    assert b.omega[second][[0, -1]].tolist() == [0.3, 3.0]
    a1 = b.amplitude(harmonic=1)[second.stop - 1]
    roots = np.roots([0.75, 0.0, 1.0 - 9.0, -10.0])
    upper = max(r.real for r in roots if abs(r.imag) < 1e-12)
    assert abs(a1 - upper) < 0.05 * upper
    hn = b.harmonic_numbers
    for i in range(second.start, second.stop, 7):
        X = b.coefficients[i, 0]
        cube = cubic_coefficients(hn, X, 1.0)
        R = sdof_residual(hn, X, b.omega[i], 1.0, 0.02, 1.0, 10.0, cube)
        assert np.max(np.abs(R)) < 1e-7


def test_range_end_only_claimed_with_a_point_on_the_boundary():
    """Rigid Coulomb, F = 10 f_s, H = 3, swept down over (0.3, 3): the path
    leaves the range below 0.3, but Newton finds no point at 0.3 itself
    (H = 3 has none there: the up sweep finds no start). The stop reason
    used to say "end of frequency range reached" with the last point at
    0.3055; it now says that no point was found on the boundary. (Without
    the curve rule: the path the case was found on; with it the run stops
    at a seam at 0.35 first.)"""
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Coulomb(slip_force=1.0))
    with pytest.warns(hf.CoverageWarning, match="no converged point on the boundary"):
        b = hf.frf(
            osc, 10.0, (0.3, 3.0), 3, sweep="down", retrace=False, curve_tolerance=None
        )
    assert b.omega.min() > 0.3 + 1e-3 and not b.complete
    assert b.stop_reason != RANGE_END and b.stop_reason.startswith(RANGE_END)
    assert f"last point at Ω = {b.omega[-1]:.6g}" in b.stop_reason


@pytest.mark.parametrize("harmonics", [15, "auto"])
@pytest.mark.parametrize("retrace", [False, True])
def test_warning_exactly_when_incomplete(harmonics, retrace):
    """A step budget too small for the range: a CoverageWarning naming the
    asked range, the covered parts and the stop reason; with the retrace
    the two pieces and the gap between them are recorded."""
    with pytest.warns(hf.CoverageWarning) as record:
        b = hf.frf(
            _jenkins_readme(), 0.5, (0.5, 3.0), harmonics, max_steps=5, retrace=retrace
        )
    assert len(record) == 1
    msg = str(record[0].message)
    assert "[0.5, 3]" in msg and "maximum number of steps" in msg
    assert not b.complete
    ((gap_lo, gap_hi),) = b.gaps
    if retrace:
        first, second = b.piece_slices()
        assert b.pieces.tolist() == [0, first.stop]
        assert b.omega[0] == 0.5 and b.omega[-1] == 3.0
        assert gap_lo == b.omega[first].max() and gap_hi == b.omega[second].min()
        assert "retraced down from 3" in b.stop_reason
    else:
        assert b.pieces is None and gap_hi == 3.0
        assert b.stop_reason == "maximum number of steps reached"
    if harmonics == "auto":
        assert b.point_harmonics.shape == b.omega.shape


def test_bad_retrace():
    with pytest.raises(TypeError, match="retrace"):
        hf.frf(_jenkins_readme(), 0.5, (0.5, 3.0), retrace="yes")


def test_coverage_survives_save_load(tmp_path):
    with pytest.warns(hf.CoverageWarning):
        b = hf.frf(_jenkins_readme(), 0.5, (0.5, 3.0), 5, max_steps=5)
    back = hf.Branch.load(b.save(tmp_path / "b.npz"))
    np.testing.assert_array_equal(back.pieces, b.pieces)
    assert back.coverage == b.coverage and back.gaps == b.gaps
    assert back.omega_range == (0.5, 3.0) and not back.complete
    full = hf.frf(_jenkins_readme(), 0.5, (0.5, 3.0), 5)
    back = hf.Branch.load(full.save(tmp_path / "full.npz"))
    assert back.pieces is None and back.complete


def test_old_branch_files_load(tmp_path):
    """A file without the ``pieces`` array (written before it existed) loads
    as one piece."""
    b = hf.frf(_jenkins_readme(), 0.5, (0.5, 3.0), 3)
    path = b.save(tmp_path / "old.npz")
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    assert "pieces" not in arrays
    np.savez(path, **arrays)
    back = hf.Branch.load(path)
    assert back.pieces is None and back.complete and back.coverage == (0.5, 3.0)


# ----------------------------------------------------------------------------
# early stops: root causes


def _rotated_back(hn, F, phi):
    """Coefficients of ``f(θ + φ)`` from those of ``f(θ)``."""
    out = F.copy()
    col = 0
    for k in hn:
        if k == 0:
            col += 1
            continue
        c, s = math.cos(k * phi), math.sin(k * phi)
        out[col] = F[col] * c + F[col + 1] * s
        out[col + 1] = -F[col] * s + F[col + 1] * c
        col += 2
    return out


@pytest.mark.parametrize("n_time", [32, 48])
def test_masing_force_continuous_when_reversal_pair_crosses_a_sample(n_time):
    """``u = cos ψ + a cos 3ψ``, ``ψ = θ - φ``, with ``a`` just above 1/3 has
    a pair of extremes 0.6 sample intervals apart near ``ψ = π/2``. Shifting
    the phase ``φ`` moves the pair across the samples; the force of the
    shifted motion, shifted back, must change smoothly with ``φ`` (it is
    exactly independent of ``φ`` up to the sampled quadrature). The Masing
    AFT used to see only extremes bracketed by the sampled slope: the pair
    and its minor loop dropped out while it sat inside one interval and the
    force jumped by 0.2 f_s (110 times the typical step)."""
    from hbmfric.kernels.aft.masing import aft_masing
    from hbmfric.kernels.fourier.dft import fourier_matrices

    law = hf.Menq.from_stiffness(stiffness=1000.0, slip_force=1.0)
    hn = np.array([1, 3], dtype=np.int64)
    inverse, forward, derivative = fourier_matrices(hn, n_time)
    h = 2.0 * math.pi / n_time
    a = 1.0 / 3.0 + 4.0 * (0.3 * h) ** 2 / 3.0
    F = np.empty(4)
    dF = np.empty((4, 4))
    forces = []
    for phi in np.linspace(0.0, 2.0 * h, 401):
        X = 2.0 * np.array(
            [math.cos(phi), math.sin(phi), a * math.cos(3 * phi), a * math.sin(3 * phi)]
        )
        aft_masing(
            np.int64(law.code), law.params, hn, X, inverse, forward, derivative, F, dF
        )
        forces.append(_rotated_back(hn, F, phi))
    steps = np.max(np.abs(np.diff(np.array(forces), axis=0)), axis=1)
    assert steps.max() < 10.0 * np.median(steps)


def test_stiff_menq_branch_passes_superharmonic_region(no_coverage_warning):
    """Menq K0 = 1000 k, F = 2 f_s: near Ω = 0.36 (third superharmonic
    resonance) the branch used to stall (at 0.3613, and the retrace from
    47.46 at 0.5287): pairs of extremes of the contact displacement were
    born inside one sample interval (see the test above), and at the seam
    left where one dies the corrector fails at every step size (bridged by
    a fixed-Ω solve). The branch now runs through in one piece, without a
    fold, and a point in the former gap agrees with time integration
    started on it to the accuracy of the run elsewhere (3.8e-2 at 0.349,
    before the gap: H = 15 on a stiff Menq loop)."""
    from stress.cases import spot_check

    osc = hf.Oscillator(
        1.0, 0.02, 1.0, hf.Menq.from_stiffness(stiffness=1000.0, slip_force=1.0)
    )
    # the sampling of the case when written (8 per harmonic; since stop 35
    # Masing laws take 16 by default, with which this branch meets no
    # seam to bridge): the seams are what is tested
    b = hf.frf(osc, 2.0, (0.3, 47.46), 15, retrace=False, n_time=120)
    assert b.complete and b.stop_reason == RANGE_END
    assert b.folds.size == 0 and np.all(np.diff(b.omega) > 0.0)
    assert b.info["bridges"] > 0
    i = int(np.argmin(np.abs(b.omega - 0.45)))
    error, why, _ = spot_check(osc, 2.0, b, i)
    assert error < 5e-2, why


@pytest.mark.filterwarnings("ignore::hbmfric.AccuracyWarning")
def test_stiff_iwan_branch_turns_past_seams(no_coverage_warning):
    """Iwan (Segalman, 50 elements) kt/k = 1e4, F = 10 f_s, ζ = 0.01: at the
    third superharmonic resonance in gross slip the up sweep stalled at
    Ω = 0.3483 and the retrace from 150 rad/s at 0.4028. At a seam of the
    piecewise smooth residual the branch leaves at more than a right angle
    to the direction it came from: the predictor points away from every
    solution and the corrector failed at every step size; the fixed-Ω
    bridge does not apply (tangent nearly vertical in Ω). The run now
    takes the tangent beyond the seam and reaches the end in one piece,
    increasing in Ω, and points across the former gap agree with time
    integration started on them (5e-3, the stress matrix's tolerance)."""
    from stress.cases import Case, build, spot_check

    osc, force, omega = build(Case(law="iwan", ratio=10.0, stiffness_ratio=1e4))
    # 8 samples per harmonic, as when written (the default for Masing laws
    # is 16 since stop 35; the seams are what is tested)
    b = hf.frf(osc, force, omega, 15, retrace=False, n_time=120)
    assert b.complete and b.stop_reason == RANGE_END and b.info["bridges"] > 0
    assert np.all(np.diff(b.omega) > 0.0)
    gap = np.nonzero((b.omega > 0.3483) & (b.omega < 0.4028))[0]
    assert gap.size > 20
    for i in gap[:: gap.size // 4]:
        error, why, _ = spot_check(osc, force, b, i)
        assert error < 5e-3, (b.omega[i], why)


def test_barely_slipping_jenkins_branch_reaches_the_end(no_coverage_warning):
    """Jenkins kt/k = 1e5, ζ = 1e-3, F = f_s: above Ω ≈ 25 the stuck
    response barely exceeds the slip limit (kt |x| ≈ 1.02 f_s), and the
    corrector failed at every step size at 45.18 of 474 rad/s. Now the run
    reaches the end in one piece, and every fifth point solves the
    harmonic balance of a plain-NumPy sampled Jenkins march (2^14 samples
    per period) to 1e-6 N."""
    from naive import analyse, jenkins_march, sample_angles, synthesize

    osc = hf.Oscillator(1.0, 2e-3, 1.0, hf.Jenkins(stiffness=1e5, slip_force=1.0))
    omega = (0.3, 1.5 * math.sqrt(1.0 + 1e5))
    b = hf.frf(osc, 1.0, omega, 15, retrace=False)
    # in one piece; with the second-order predictor of the curve rule the
    # corrector no longer needs a bridge here (the bridges are tested above)
    assert b.complete and b.stop_reason == RANGE_END
    hn = b.harmonic_numbers
    theta = sample_angles(2**14)
    for i in range(0, len(b), 5):
        X = b.coefficients[i, 0]
        loop, _ = jenkins_march(synthesize(hn, X, theta), 1e5, 1.0)
        contact = analyse(hn, loop)
        R = sdof_residual(hn, X, b.omega[i], 1.0, 2e-3, 1.0, 1.0, contact)
        assert np.max(np.abs(R)) < 1e-6, b.omega[i]


@pytest.fixture(scope="module")
def calibrated_beam():
    return hf.CantileverBeam.calibrate()


@pytest.mark.slow
def test_coulomb_beam_swept_down_reaches_the_end(calibrated_beam, no_coverage_warning):
    """Beam with a Coulomb tip, f_s = 2 N, Fex = 2 N, swept down from 110 Hz:
    used to stop at 77.3 Hz; now one piece to 15 Hz."""
    beam = calibrated_beam.beam.with_contact(hf.Coulomb(slip_force=2.0))
    b = hf.frf(beam, 2.0, (HZ * 15.0, HZ * 110.0), 15, sweep="down", retrace=False)
    assert b.complete and b.stop_reason == RANGE_END


@pytest.mark.slow
def test_coulomb_beam_stall_is_reported(calibrated_beam):
    """f_s = 1 N swept down from 110 to 55 Hz stalls at 62.3 Hz, and the
    retrace up from 55 Hz at 62.07 Hz (two topologies of a short stick
    phase, bench/README.md): the branch says so, with the gap between the
    pieces, and warns."""
    beam = calibrated_beam.beam.with_contact(hf.Coulomb(slip_force=1.0))
    with pytest.warns(hf.CoverageWarning, match="gaps: "):
        b = hf.frf(beam, 2.0, (HZ * 55.0, HZ * 110.0), 15, sweep="down")
    assert not b.complete and b.pieces.size == 2
    ((lo, hi),) = b.gaps
    assert 61.5 < lo / HZ < hi / HZ < 63.0
    assert b.coverage == (HZ * 55.0, HZ * 110.0)


def _piece(omega, harmonics, folds, sweep, point_harmonics=None):
    """A synthetic branch piece: coefficient [p, d, c] = 100 p + 10 d + c."""
    omega = np.asarray(omega, dtype=float)
    n_coef = sum(1 if k == 0 else 2 for k in harmonics)
    p, d, c = np.meshgrid(
        np.arange(omega.size), np.arange(2), np.arange(n_coef), indexing="ij"
    )
    return hf.Branch(
        omega=omega,
        coefficients=(100.0 * p + 10.0 * d + c) * (1.0 if sweep == "up" else -1.0),
        harmonic_numbers=np.asarray(harmonics, dtype=np.int64),
        force=1.0,
        folds=np.asarray(folds, dtype=np.int64),
        stop_reason=f"{sweep} stop",
        n_steps=omega.size,
        n_rejected=1,
        newton_iterations=10,
        elapsed=0.5,
        info={"omega_range": [1.0, 5.0], "sweep": sweep},
        point_harmonics=point_harmonics,
    )


def test_join_pieces_layout():
    """Second piece reversed after the first, shorter harmonic layouts
    padded with zeros, folds moved to the reversed indices, counters
    summed, the gap between the pieces found."""
    from hbmfric.results import join_pieces

    first = _piece([1.0, 1.5, 2.0, 1.8, 2.2], [1, 3], [3], "up", np.array([3] * 5))
    second = _piece([5.0, 4.0, 3.0, 3.5], [1, 3, 5], [3], "down", np.array([5] * 4))
    b = join_pieces(first, second, "joined")
    path = [1.0, 1.5, 2.0, 1.8, 2.2, 3.5, 3.0, 4.0, 5.0]
    np.testing.assert_array_equal(b.omega, path)
    np.testing.assert_array_equal(b.harmonic_numbers, [1, 3, 5])
    assert b.coefficients.shape == (9, 2, 6)
    np.testing.assert_array_equal(b.coefficients[:5, :, :4], first.coefficients)
    np.testing.assert_array_equal(b.coefficients[:5, :, 4:], 0.0)
    np.testing.assert_array_equal(b.coefficients[5:], second.coefficients[::-1])
    # the fold between points 2 and 3 of the second piece lies between its
    # reversed points 0 and 1, i.e. joined points 5 and 6
    np.testing.assert_array_equal(b.folds, [3, 6])
    np.testing.assert_array_equal(b.point_harmonics, [3] * 5 + [5] * 4)
    np.testing.assert_array_equal(b.pieces, [0, 5])
    assert (b.n_steps, b.n_rejected, b.newton_iterations) == (9, 2, 20)
    assert b.elapsed == 1.0 and b.stop_reason == "joined"
    assert b.gaps == [(2.2, 3.0)] and b.coverage == (1.0, 5.0)
    assert not b.complete
    assert [p["stop_reason"] for p in b.info["pieces"]] == ["up stop", "down stop"]


def test_plot_draws_each_piece_on_its_own(tmp_path):
    """No line across the jump between pieces."""
    import matplotlib

    matplotlib.use("Agg")
    from hbmfric.results import join_pieces

    first = _piece([1.0, 1.5, 2.0], [1, 3], [], "up")
    second = _piece([5.0, 4.0, 3.0], [1, 3], [], "down")
    ax = join_pieces(first, second, "joined").plot(harmonic=1, curve="polyline")
    lines = [line.get_xdata().tolist() for line in ax.lines]
    assert lines == [[1.0, 1.5, 2.0], [3.0, 4.0, 5.0]]
    assert ax.lines[0].get_color() == ax.lines[1].get_color()


@pytest.mark.parametrize(
    ("name", "osc", "force", "omega"),
    [
        ("cubic", _cubic(), 1.0, (0.3, 5.0)),
        (
            "menq",
            hf.Oscillator(
                1.0, 0.02, 1.0, hf.Menq.from_stiffness(stiffness=1000.0, slip_force=1.0)
            ),
            2.0,
            (0.3, 47.46),
        ),
    ],
)
def test_adaptive_harmonics_recover_from_a_level_change(
    name, osc, force, omega, no_coverage_warning
):
    """``harmonics="auto"`` swept up: on the cubic the run lowered from
    H = 45 to 3 by truncation (the ``H^-3.5`` law misjudges a geometric
    spectrum) and stalled at 0.4765; on the stiff Menq it raised from 7 to
    63 at the first point and stalled there. Both now reach the end: the
    run solves the point again at the new level or returns to the old
    one. Cubic: every point solves the harmonic balance in its own basis
    (independent residual)."""
    b = hf.frf(osc, force, omega, "auto", retrace=False)
    assert b.complete and b.stop_reason == RANGE_END
    if name == "cubic":
        for i in range(0, len(b), 5):
            h = b.harmonics_at(i)
            hn = b.harmonic_numbers[b.harmonic_numbers <= h]
            X = b.coefficients[i, 0, : 2 * hn.size]
            R = sdof_residual(
                hn, X, b.omega[i], 1.0, 0.02, 1.0, 1.0, cubic_coefficients(hn, X, 1.0)
            )
            assert np.max(np.abs(R)) < 1e-8, (b.omega[i], h)
