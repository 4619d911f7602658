"""The contact-model criterion on FRF families synthesised by HBM (and by an
independent describing-function model for microslip), clean, with 2 %
multiplicative noise and on resampled uneven grids; too-small families;
records and CSV input."""

from __future__ import annotations

import collections
import math
import subprocess
import sys

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.criterion import (
    FRFRecord,
    choose_contact_model,
    read_frfs,
    write_frfs,
)
from hbmfric.criterion.choose import MARGIN_Z
from hbmfric.criterion.smoothing import interp_log, smooth_grid, smoothed_noise

RATIOS = (10.0, 0.5, 0.2, 0.1, 0.001)
H = 5

# two SDOF parameter sets: the paper scene (SPEC §6) and another one
SCENES = {
    "paper": dict(m=1.0, k=1.0e4, zeta=0.02, kt=3.0e4, mu=1.0, lim=300.0, onset=0.5),
    "other": dict(m=2.0, k=5.0e3, zeta=0.01, kt=2.5e4, mu=0.5, lim=100.0, onset=0.3),
}
#: Fex/Fn of each scene's family (the paper's, scaled by μ for the other)
SCENE_RATIOS = {
    "paper": RATIOS,
    "other": tuple(0.5 * r for r in RATIOS),
}


def _band(p):
    w_slip = math.sqrt(p["k"] / p["m"])
    w_stuck = math.sqrt((p["k"] + p["kt"]) / p["m"])
    return 0.5 * w_slip, 1.5 * w_stuck


def _law(p, model, rough, normal_load):
    if model == "macroslip":
        law = hf.Jenkins(
            stiffness=p["kt"], friction_coefficient=p["mu"], normal_load=normal_load
        )
    else:
        law = _menq(p, normal_load)
    return hf.Roughness(law, p["lim"]) if rough else law


def _menq(p, normal_load):
    return hf.Menq.from_stiffness(
        p["kt"],
        microslip_onset=p["onset"],
        friction_coefficient=p["mu"],
        normal_load=normal_load,
    )


def synthesise(scene, model, rough, forces=(1.0, 1000.0)):
    """HBM family: one record per (force, ratio)."""
    p = SCENES[scene]
    ratios = SCENE_RATIOS[scene]
    c = 2.0 * p["zeta"] * math.sqrt(p["k"] * p["m"])
    out = []
    for force in forces:
        for ratio in ratios:
            fn = force / ratio
            osc = hf.Oscillator(p["m"], c, p["k"], _law(p, model, rough, fn))
            # Menq: 32 samples per harmonic (with the default 16 the run at
            # onset 0.3, Fex/Fn = 0.1 stalls near 99.6 rad/s: step below min)
            n_time = 32 * H if model == "microslip" else None
            b = hf.frf(osc, force, _band(p), H, n_time=n_time)
            assert b.stop_reason.startswith("end of frequency range")
            out.append(FRFRecord.from_branch(b, fn))
    return out


def perturb(records, seed, noise=0.02, n=150):
    """Measured-like copies: ``n`` random (uneven) frequencies, amplitude
    interpolated and multiplied by ``1 + noise * N(0, 1)``."""
    rng = np.random.default_rng(seed)
    out = []
    for r in records:
        w = np.sort(rng.uniform(r.omega[0], r.omega[-1], n))
        a = np.interp(w, r.omega, r.amplitude)
        out.append(
            FRFRecord(r.force, r.normal_load, w, a * (1 + noise * rng.normal(size=n)))
        )
    return out


_CACHE: dict = {}


@pytest.fixture(scope="module")
def families():
    """Families by key (scene, model, rough), synthesised once per module."""

    def get(scene, model, rough):
        key = (scene, model, rough)
        if key not in _CACHE:
            _CACHE[key] = synthesise(scene, model, rough)
        return _CACHE[key]

    return get


# ----------------------------------------------------------------------------
# independent microslip families: single-harmonic balance (describing
# function) of the SDOF with the closed-form Menq loop (SPEC §4), plain NumPy


def menq_loading(d, k0, f_star, alpha_l):
    """Virgin loading curve of the Menq bar (L = 1): stuck, microslip, gross
    slip (SPEC §4), vectorised over ``d``."""
    ea = k0 / (alpha_l * math.tanh(alpha_l))
    ks = alpha_l**2 * ea
    q = f_star
    ell = np.linspace(0.0, 1.0, 4001)
    f = q * ell + q / alpha_l * np.tanh(alpha_l * (1.0 - ell))
    dl = q / ks + (f * ell - q * ell**2 / 2.0) / ea
    d = np.asarray(d, dtype=float)
    return np.where(
        d <= dl[0], k0 * d, np.where(d >= dl[-1], f_star, np.interp(d, dl, f))
    )


def describing_function_frf(m, c, k, load, force, omega):
    """First-harmonic amplitude of ``m x'' + c x' + k x + f(x) = F cos Ωt``
    for a Masing law with virgin curve ``load`` (largest solution)."""
    theta = np.linspace(0.0, np.pi, 401)
    amps = np.logspace(-7, 1, 1000) * force
    # Masing unloading branch from (A, load(A)); antisymmetric second half
    u = amps[:, None] * np.cos(theta)[None, :]
    fa = load(amps)[:, None]
    f = fa - 2.0 * load((amps[:, None] - u) / 2.0)
    c1 = 2.0 / np.pi * np.trapezoid(f * np.cos(theta), theta, axis=1)
    s1 = 2.0 / np.pi * np.trapezoid(f * np.sin(theta), theta, axis=1)
    keq = (c1 - 1j * s1) / amps
    out = np.empty(omega.size)
    for i, w in enumerate(omega):
        g = amps * np.abs(k - m * w**2 + 1j * c * w + keq) - force
        j = np.nonzero(np.diff(np.sign(g)))[0][-1]
        t = g[j] / (g[j] - g[j + 1])
        out[i] = amps[j] * (amps[j + 1] / amps[j]) ** t
    return out


@pytest.fixture(scope="module")
def df_families():
    """Paper scene, Fex = 1 and 1000 N: Masing (Jenkins) and Menq (αL = 2)
    by the describing function, on a uniform grid."""
    p = SCENES["paper"]
    c = 2.0 * p["zeta"] * math.sqrt(p["k"] * p["m"])
    omega = np.linspace(50.0, 300.0, 501)
    fams = {}
    for name in ("macroslip", "microslip"):
        recs = []
        for force in (1.0, 1000.0):
            for ratio in RATIOS:
                fn = force / ratio
                if name == "macroslip":

                    def load(d, fn=fn):
                        return np.minimum(p["kt"] * d, p["mu"] * fn)
                else:

                    def load(d, fn=fn):
                        return menq_loading(d, p["kt"], p["mu"] * fn, 2.0)

                a = describing_function_frf(p["m"], c, p["k"], load, force, omega)
                recs.append(FRFRecord(force, fn, omega, a))
        fams[name] = recs
    return fams


# ----------------------------------------------------------------------------
# classification


@pytest.mark.parametrize("scene", ["paper", "other"])
@pytest.mark.parametrize("rough", [False, True])
def test_macroslip_families(families, scene, rough):
    fam = families(scene, "macroslip", rough)
    res = choose_contact_model(fam)
    assert (res.model, res.roughness) == ("macroslip", rough), res.explanation
    if not rough:
        # HBM FRFs normalised by Fex depend on Fex/Fn only (paper Sec. 3.1)
        assert res.indicators["ratio_spread"] < 1e-6
    # the stuck reference resonates at sqrt((k + kt)/m)
    p = SCENES[scene]
    w_stuck = math.sqrt((p["k"] + p["kt"]) / p["m"])
    assert res.indicators["stuck_frequency"] == pytest.approx(w_stuck, rel=2e-3)
    # mostly stuck Masing curves stay inside the stuck envelope, with a margin
    # of 2.5 to the default threshold (a lightly damped Masing curve that
    # slips over much of its period softens and rises ~3 % of its own peak
    # above the envelope)
    assert res.indicators["envelope_excess"] < 0.04
    for seed in (1, 2, 3):
        noisy = choose_contact_model(perturb(fam, seed))
        if scene == "other" and noisy.model == "undecided":
            # 1 % damping: 150 random frequencies straddle the peaks (half
            # width 1.2 rad/s, mean spacing 1.06); the chords of the clean
            # samples lie up to 81 % of a curve's peak off it (median 8.7 %,
            # against a 10 % threshold), an error counted since stop 34
            assert "chords" in noisy.explanation, noisy.explanation
            continue
        assert (noisy.model, noisy.roughness) == ("macroslip", rough), noisy.explanation


@pytest.mark.parametrize("scene", ["paper", "other"])
@pytest.mark.parametrize("rough", [False, True])
def test_microslip_families(families, scene, rough):
    fam = families(scene, "microslip", rough)
    res = choose_contact_model(fam)
    assert (res.model, res.roughness) == ("microslip", rough), res.explanation
    for seed in (1, 2, 3):
        noisy = choose_contact_model(perturb(fam, seed))
        if scene == "other" and noisy.model == "undecided":
            # the peaks straddled by 150 random frequencies (see above)
            assert "chords" in noisy.explanation, noisy.explanation
            continue
        assert (noisy.model, noisy.roughness) == ("microslip", rough), noisy.explanation


@pytest.mark.parametrize("model", ["macroslip", "microslip"])
def test_describing_function_families(df_families, model):
    """An independent synthesis (single-harmonic balance with the closed-form
    Menq and Masing loops) is classified the same way."""
    fam = df_families[model]
    for recs in (fam, perturb(fam, 7), perturb(fam, 8)):
        res = choose_contact_model(recs)
        assert (res.model, res.roughness) == (model, False), res.explanation
    shifts = choose_contact_model(fam).indicators["peak_shift"]
    # mostly stuck peaks sit below the stuck resonance in both models
    assert all(s < 0 for s in shifts.values())


def beam_like_family():
    """SDOF tuned to the paper's beam (slipping 24 Hz, stuck 87 Hz), macroslip;
    frequencies in Hz. The stuck measurement (Fn = 40 N, Fex = 2 N) and the
    twelve configurations Fex/Fn = 0.5, 1, 2 at Fn = 2.5, 3, 5, 10 N."""
    m, k = 1.0, (2 * math.pi * 24.0) ** 2
    kt = (2 * math.pi * 87.0) ** 2 - k
    c = 2 * 0.02 * math.sqrt(k * m)

    def record(force, fn):
        law = hf.Jenkins(stiffness=kt, friction_coefficient=5.0, normal_load=fn)
        b = hf.frf(hf.Oscillator(m, c, k, law), force, (2 * math.pi * 10, 754.0), H)
        r = FRFRecord.from_branch(b, fn)
        return FRFRecord(force, fn, r.omega / (2 * math.pi), r.amplitude)

    return [record(2.0, 40.0)] + [
        record(ratio * fn, fn) for ratio in (0.5, 1.0, 2.0) for fn in (2.5, 3, 5, 10)
    ]


def test_beam_like_family_is_macroslip_without_roughness():
    fam = beam_like_family()
    res = choose_contact_model(fam)
    assert res.verdict == "macroslip without roughness", res.explanation
    assert res.indicators["n_pairs"] == 18
    assert res.indicators["stuck_frequency"] == pytest.approx(87.0, rel=2e-3)
    noisy = choose_contact_model(perturb(fam, 5, n=120))
    assert noisy.verdict == "macroslip without roughness", noisy.explanation


# ----------------------------------------------------------------------------
# families too small to decide


def test_single_record_is_undecided(families):
    rec = families("paper", "macroslip", False)[2]
    res = choose_contact_model([rec])
    assert res.model == "undecided"
    assert "Fex/Fn" in res.explanation and "single" in res.explanation
    assert not res.indicators["roughness_assessed"]


def test_no_pair_at_equal_ratio_is_undecided(families):
    one_level = families("paper", "macroslip", False)[:5]  # Fex = 1 N only
    res = choose_contact_model(one_level)
    assert res.model == "undecided"
    assert "two force levels" in res.explanation
    assert res.indicators["ratio_spread"] is None


def test_no_mostly_stuck_curve_is_undecided(families):
    fam = [
        r
        for r in families("paper", "macroslip", False)
        if r.ratio in (10.0, 0.5) or r.ratio < 0.01
    ]
    res = choose_contact_model(fam)
    assert res.model == "undecided"
    assert "no mostly stuck curve" in res.explanation
    assert res.indicators["mostly_stuck_ratios"] == []


def test_empty_family_is_undecided():
    res = choose_contact_model([])
    assert res.model == "undecided" and "No FRF" in res.explanation


def test_given_stuck_reference_and_frequency(families):
    """A stuck FRF given separately (here the linear oscillator with the
    contact bonded) replaces the lowest-ratio curve."""
    p = SCENES["paper"]
    fam = [r for r in families("paper", "macroslip", False) if r.ratio > 0.01]
    w = np.linspace(50.0, 300.0, 400)
    c = 2 * p["zeta"] * math.sqrt(p["k"] * p["m"])
    linear = 1.0 / np.abs(p["k"] + p["kt"] - p["m"] * w**2 + 1j * c * w)
    stuck = FRFRecord(1.0, 1e6, w, linear)
    res = choose_contact_model(fam, stuck=stuck)
    assert res.verdict == "macroslip without roughness", res.explanation
    assert "given stuck FRF" in res.indicators["stuck_reference"]
    res2 = choose_contact_model(fam, stuck=stuck, stuck_frequency=200.0)
    assert res2.indicators["stuck_frequency"] == 200.0
    shift = res2.indicators["peak_shift"]
    assert all(-0.1 < s < 0 for s in shift.values())


# ----------------------------------------------------------------------------
# noise: a verdict only where the data support it

#: eight ratios, so that several noise curves pass for mostly stuck ones
NOISE_RATIOS = (10.0, 1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.001)


def noise_family(seed, sigma=0.3, n=150):
    """No resonance at all: a response proportional to the force times
    log-normal noise (``sigma`` in log amplitude), ``n`` random frequencies
    in [50, 300] per curve, Fex = 1 and 1000 N at each of NOISE_RATIOS.
    Before the noise margins the criterion read 34 of 40 seeds of this
    family (sigma 0.3, stuck_frequency = 200) as microslip, 4 as macroslip."""
    rng = np.random.default_rng(seed)
    out = []
    for force in (1.0, 1000.0):
        for ratio in NOISE_RATIOS:
            w = np.sort(rng.uniform(50.0, 300.0, n))
            a = force * rng.lognormal(0.0, sigma, n)
            out.append(FRFRecord(force, force / ratio, w, a))
    return out


def check_margins(res):
    """A decided verdict has its step 2 margin beyond MARGIN_Z noise units
    on the side of the verdict; an undecided one says why."""
    m = res.indicators["margin"]
    if res.model == "microslip":
        # a claim that some point leaves the envelope needs more than
        # MARGIN_Z: the margin grows with the stretches searched
        assert res.indicators["margin_z_leave"] > MARGIN_Z
        assert m["envelope_excess"] >= res.indicators["margin_z_leave"]
    elif res.model == "macroslip":
        assert m["envelope_excess"] <= -MARGIN_Z
        assert m.get("envelope_excess_above", -math.inf) <= -MARGIN_Z
    else:
        assert res.indicators["undecided_reason"] in ("data", "noise")
        assert "Undecided" in res.explanation
    if res.model != "undecided" and "ratio_spread" in m:
        assert abs(m["ratio_spread"]) >= MARGIN_Z
    return res


@pytest.mark.parametrize("n_seeds", [5, pytest.param(40, marks=pytest.mark.slow)])
@pytest.mark.parametrize("sigma", [0.02, 0.3])
def test_noise_only_families_are_undecided(sigma, n_seeds):
    """Measured (40 seeds, both sigmas, with and without stuck_frequency):
    undecided 160 of 160."""
    counts = collections.Counter()
    for seed in range(n_seeds):
        for options in ({}, {"stuck_frequency": 200.0}):
            res = check_margins(
                choose_contact_model(noise_family(seed, sigma), **options)
            )
            counts[res.verdict] += 1
    assert counts == {"undecided": 2 * n_seeds}, counts


@pytest.mark.parametrize("n_seeds", [5, pytest.param(20, marks=pytest.mark.slow)])
@pytest.mark.parametrize("noise", [0.1, 0.2])
def test_noisy_masing_never_reads_microslip(families, noise, n_seeds):
    """The paper's Masing families with 10 % and 20 % multiplicative noise
    (150 random frequencies per curve): macroslip or undecided, never
    microslip (before the noise margins: 1 and 18 of 40 read microslip).
    Measured with 20 seeds, without / with roughness: 10 %: 2 / 0 macroslip,
    18 / 20 undecided; 20 %: 20 / 20 undecided (5 %: 19 / 6 macroslip)."""
    for rough in (False, True):
        fam = families("paper", "macroslip", rough)
        for seed in range(n_seeds):
            res = check_margins(choose_contact_model(perturb(fam, seed, noise)))
            assert res.model in ("macroslip", "undecided"), res.explanation
            if res.model == "macroslip":
                assert res.roughness == rough, res.explanation
            else:
                assert res.indicators["undecided_reason"] == "noise"
                assert "noise units" in res.explanation


@pytest.mark.parametrize("n_seeds", [5, pytest.param(20, marks=pytest.mark.slow)])
@pytest.mark.parametrize("noise", [0.1, 0.2])
def test_noisy_microslip_never_reads_macroslip(families, noise, n_seeds):
    """Measured with 20 seeds, without / with roughness: 10 %: 3 / 1
    microslip, the rest undecided; 20 %: all undecided (5 %: 15 / 8
    microslip; before the noise margins: 3 of 80 read macroslip)."""
    for rough in (False, True):
        fam = families("paper", "microslip", rough)
        for seed in range(n_seeds):
            res = check_margins(choose_contact_model(perturb(fam, seed, noise)))
            assert res.model in ("microslip", "undecided"), res.explanation
            if res.model == "microslip":
                assert res.roughness == rough, res.explanation


@pytest.mark.parametrize(
    "seeds", [(0,), pytest.param(tuple(range(60)), marks=pytest.mark.slow)]
)
def test_noisy_beam_like_family_never_reads_microslip(seeds):
    """A sparse, 20 % noisy macroslip family (about 1.4 samples per Hz
    around a 3.5 Hz wide stuck peak): in seed 0 the single stuck record dips
    (log(1 + 0.2 N) has a heavy lower tail) and the excess passes its
    threshold by 3.3 noise units at one point of ~20 searched; with the
    margin raised for the number of stretches searched it is undecided.
    Measured over 60 seeds: 60 undecided (at 2 %: 60 macroslip)."""
    fam = beam_like_family()
    for seed in seeds:
        res = check_margins(choose_contact_model(perturb(fam, seed, 0.2)))
        assert res.model in ("macroslip", "undecided"), res.explanation


def test_clean_families_decide_with_wide_margins(families):
    for model in ("macroslip", "microslip"):
        for rough in (False, True):
            res = check_margins(choose_contact_model(families("paper", model, rough)))
            assert (res.model, res.roughness) == (model, rough)
            m = res.indicators["margin"]
            assert abs(m["envelope_excess"]) > 30
            assert m["stuck_rise"] > 1000
            assert "margin" in res.explanation


def test_smoothed_noise_matches_monte_carlo():
    """The noise propagated through interpolation and smoothing against the
    spread of 800 smoothed noise realisations (uneven samples, a grid finer
    than them, both ends of the band off the samples)."""
    rng = np.random.default_rng(3)
    w = np.sort(rng.uniform(1.0, 9.0, 120))
    grid = np.linspace(0.0, 10.0, 400)
    for width in (0.0, 0.3):
        pred = smoothed_noise(w, grid, width, 0.1)
        reps = np.array(
            [
                smooth_grid(
                    grid, interp_log(w, 0.1 * rng.normal(size=w.size), grid), width
                )
                for _ in range(800)
            ]
        )
        ok = np.isfinite(pred)
        np.testing.assert_array_equal(ok, np.isfinite(reps[0]))
        np.testing.assert_allclose(reps[:, ok].std(axis=0), pred[ok], rtol=0.15)
    # the local quadratic over about 9 samples lowers the noise by about 0.6
    assert 0.045 < np.median(pred[ok]) < 0.075


# ----------------------------------------------------------------------------
# records, CSV, plot


def test_record_validation():
    w = np.linspace(1.0, 2.0, 6)
    a = np.ones(6)
    with pytest.raises(ValueError, match="force"):
        FRFRecord(-1.0, 1.0, w, a)
    with pytest.raises(ValueError, match="normal_load"):
        FRFRecord(1.0, 0.0, w, a)
    with pytest.raises(ValueError, match="same length"):
        FRFRecord(1.0, 1.0, w, a[:-1])
    with pytest.raises(ValueError, match="finite"):
        FRFRecord(1.0, 1.0, w, np.r_[a[:-1], np.nan])
    with pytest.raises(ValueError, match="repeated"):
        FRFRecord(1.0, 1.0, np.r_[w[:-1], w[0]], a)
    with pytest.raises(ValueError, match="at least 5"):
        FRFRecord(1.0, 1.0, w[:3], a[:3])
    with pytest.raises(ValueError, match="> 0"):
        FRFRecord(1.0, 1.0, w, np.r_[a[:-1], 0.0])
    r = FRFRecord(2.0, 4.0, w[::-1], np.arange(1.0, 7.0))
    assert np.all(np.diff(r.omega) > 0)
    np.testing.assert_array_equal(r.amplitude, np.arange(6.0, 0.0, -1.0))
    assert r.ratio == 0.5
    np.testing.assert_array_equal(r.normalised, r.amplitude / 2.0)
    with pytest.raises(ValueError):
        r.omega[0] = 5.0  # read-only
    with pytest.raises(ValueError, match="FRFRecord"):
        choose_contact_model([r, "x"])


def test_csv_round_trip_and_paper_columns(tmp_path, families):
    fam = perturb(families("paper", "macroslip", False), 11)
    path = write_frfs(tmp_path / "family.csv", fam)
    back = read_frfs(path)
    assert len(back) == len(fam)
    for a, b in zip(fam, back, strict=True):
        assert (a.force, a.normal_load) == (b.force, b.normal_load)
        np.testing.assert_allclose(b.omega, a.omega, rtol=1e-11)
        np.testing.assert_allclose(b.amplitude, a.amplitude, rtol=1e-11)
    assert choose_contact_model(back).verdict == choose_contact_model(fam).verdict
    # the columns written by ``hbmfric paper``, rows shuffled, a comment line
    lines = [
        "# written by hand",
        "curve,force_N,normal_load_N,ratio,omega_rad_s,amplitude_h1_m,amplitude_m",
    ]
    rng = np.random.default_rng(0)
    rows = [
        f"c{i},{r.force},{r.normal_load},{r.ratio},{w},{a},{a}"
        for i, r in enumerate(fam[:2])
        for w, a in zip(r.omega, r.amplitude, strict=True)
    ]
    rng.shuffle(rows)
    (tmp_path / "paper.csv").write_text("\n".join(lines + rows) + "\n")
    recs = read_frfs(tmp_path / "paper.csv")
    assert sorted(r.label for r in recs) == ["c0", "c1"]
    assert {r.normal_load for r in recs} == {fam[0].normal_load, fam[1].normal_load}
    np.testing.assert_allclose(
        recs[[r.label for r in recs].index("c0")].omega, fam[0].omega, rtol=1e-12
    )


def test_csv_errors(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text("force,normal_load,omega\n1,2,3\n")
    with pytest.raises(ValueError, match="amplitude"):
        read_frfs(p)
    p.write_text("force,normal_load,omega,amplitude\n1,2,3,x\n")
    with pytest.raises(ValueError, match="line 2"):
        read_frfs(p)
    p.write_text(
        "curve,force,normal_load,omega,amplitude\n"
        + "".join(f"a,1,2,{w},1\n" for w in range(1, 6))
        + "a,1,3,7,1\n"
    )
    with pytest.raises(ValueError, match="normal_load"):
        read_frfs(p)
    p.write_text("")
    with pytest.raises(ValueError, match="empty"):
        read_frfs(p)


def test_plot_and_lazy_import(families):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res = choose_contact_model(families("paper", "macroslip", True))
    fig = res.plot()
    assert len(fig.axes) == 2
    plt.close(fig)
    code = (
        "import sys, hbmfric, hbmfric.criterion; sys.exit('matplotlib' in sys.modules)"
    )
    assert subprocess.run([sys.executable, "-c", code]).returncode == 0


def test_bad_options(families):
    fam = families("paper", "macroslip", False)
    with pytest.raises(ValueError, match="stuck_frequency"):
        choose_contact_model(fam, stuck_frequency=-1.0)
    with pytest.raises(ValueError, match="stuck"):
        choose_contact_model(fam, stuck="no")
    with pytest.raises(ValueError, match="n_grid"):
        choose_contact_model(fam, n_grid=3)


def test_curves_leaving_the_envelope_upwards_are_undecided():
    """A family whose partly stuck curves stiffen (resonance above the stuck
    one) fits neither friction model: closed-form linear FRFs."""
    w = np.linspace(100.0, 300.0, 400)

    def lin(w0, zeta):
        return 1.0 / np.abs(w0**2 - w**2 + 2j * zeta * w0 * w)

    curves = {0.001: lin(200.0, 0.02), 0.1: lin(230.0, 0.05), 1.0: lin(260.0, 0.5)}
    fam = [
        FRFRecord(force, force / ratio, w, force * a)
        for force in (1.0, 10.0)
        for ratio, a in curves.items()
    ]
    res = choose_contact_model(fam)
    assert res.model == "undecided"
    assert "high-frequency side" in res.explanation
    assert res.indicators["envelope_excess_above"] > 0.1
    assert res.indicators["envelope_excess_above_frequency"] > 200.0


def test_result_saves_as_json(tmp_path, families):
    import json

    res = choose_contact_model(families("paper", "macroslip", True))
    data = json.loads(res.save(tmp_path / "verdict.json").read_text())
    assert data["verdict"] == "macroslip with roughness"
    assert data["indicators"]["ratio_spread"] == res.indicators["ratio_spread"]
    assert set(data["indicators"]["peak_shift"]) == {"0.1", "0.2"}


def test_paper_beam_figures_13_and_14_together_are_macroslip():
    """The paper's beam (39 DOFs, Jenkins tip contact): Fig. 13 alone has no
    two loads at one ratio, Fig. 14 alone no stuck curve; together they give
    the paper's verdict, also with noise on resampled grids."""
    from hbmfric.paper import beam_normal_load_family, beam_ratio_family

    fig13 = beam_normal_load_family(harmonics=H).records()
    fig14 = beam_ratio_family(harmonics=H).records()
    assert choose_contact_model(fig13).model == "undecided"
    assert "no mostly stuck" in choose_contact_model(fig14).explanation
    res = choose_contact_model(fig13 + fig14)
    assert res.verdict == "macroslip without roughness", res.explanation
    assert res.indicators["ratio_spread"] < 1e-6
    for seed in (21, 22):
        noisy = choose_contact_model(perturb(fig13 + fig14, seed))
        assert noisy.verdict == "macroslip without roughness", noisy.explanation


def test_stuck_resonance_outside_the_band(families):
    """Data that stop below the stuck resonance cannot place it: undecided,
    unless the user gives ``stuck_frequency``."""
    cut = [
        FRFRecord(
            r.force, r.normal_load, r.omega[r.omega < 190], r.amplitude[r.omega < 190]
        )
        for r in families("paper", "macroslip", False)
    ]
    res = choose_contact_model(cut)
    assert res.model == "undecided"
    assert "stuck_frequency" in res.explanation
    res = choose_contact_model(cut, stuck_frequency=200.0)
    assert res.verdict == "macroslip without roughness", res.explanation


def folded_noise(records, seed, noise=0.3, n=150):
    """Like :func:`perturb` with the amplitude multiplied by ``|1 + noise
    N(0, 1)|``: the magnitude of a signal with noise of that relative size,
    whose logarithm has a heavy lower tail (samples close to zero)."""
    rng = np.random.default_rng(seed)
    out = []
    for r in records:
        w = np.sort(rng.uniform(r.omega[0], r.omega[-1], n))
        a = np.interp(w, r.omega, r.amplitude)
        factor = np.abs(1.0 + noise * rng.normal(size=n)) + 1e-3
        out.append(FRFRecord(r.force, r.normal_load, w, a * factor))
    return out


@pytest.mark.parametrize(
    "seeds", [(28, 37), pytest.param(tuple(range(40)), marks=pytest.mark.slow)]
)
@pytest.mark.parametrize("model", ["macroslip", "microslip"])
def test_heavy_lower_tail_noise_gives_no_wrong_verdict(families, model, seeds):
    """30 % noise on the magnitude (heavy lower tail in log): never the
    wrong model. Before deep dips were dropped, seeds 28 and 37 of the rough
    Masing family read microslip (2 of 40); now 0 of 160 are wrong."""
    for rough in (False, True):
        fam = families("paper", model, rough)
        for seed in seeds:
            res = check_margins(choose_contact_model(folded_noise(fam, seed)))
            assert res.model in (model, "undecided"), res.explanation


def test_dip_removal_keeps_peaks_and_drops_dips():
    """A sharp resonance with a few deep dips: every sample of the peak is
    kept, every planted dip dropped."""
    from hbmfric.criterion.smoothing import noise_level, without_dips

    rng = np.random.default_rng(3)
    w = np.sort(rng.uniform(150.0, 250.0, 400))
    y = -0.5 * np.log((1 - (w / 200.0) ** 2) ** 2 + (0.02 * w / 200.0) ** 2)
    y = y + 0.05 * rng.normal(size=w.size)
    dips = rng.choice(w.size, 6, replace=False)
    y[dips] -= 1.5
    grid = np.linspace(150.0, 250.0, 600)
    keep = without_dips(w, y, grid, 2.0, noise_level(w, y))
    assert not keep[dips].any()
    assert keep[np.abs(w - 200.0) < 2.0].all()
    assert np.count_nonzero(~keep) <= dips.size + 2
