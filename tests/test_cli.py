"""The main job: ``hbmfric paper`` writes the Fig. 8 family, and its extreme
curves are the linear stuck and slipping FRFs."""

import csv
import warnings

import numpy as np
import pytest

from hbmfric.cli import main
from hbmfric.paper import PAPER_SDOF


def test_paper_writes_fig8(tmp_path, capsys):
    # the extra lap-joint set (not the paper's) has its own test
    args = ["paper", "--out", str(tmp_path), "--harmonics", "7"]
    assert main([*args, "--lap-joint-pairs", "0"]) == 0
    out = capsys.readouterr().out
    assert out.count("fig8 Masing") == len(PAPER_SDOF["ratios"])
    # the index: one row per figure written, each with what it shows, the
    # claim it checks and links to files that exist; its path printed last
    index = tmp_path / "index.md"
    assert f"index of the figures: {index}" in out
    rows = [r for r in index.read_text().splitlines() if r[:6] in ("| fig0", "| fig1")]
    written = sorted(p.stem for p in tmp_path.glob("*.csv") if "_time_" not in p.stem)
    assert sorted(r.split("|")[1].strip() for r in rows) == written
    for r in rows:
        cells = [c.strip() for c in r.split("|")[1:-1]]
        assert cells[2] and cells[3], r  # what it shows, claim checked
        for link in cells[1].split(", "):
            assert (tmp_path / link[1 : link.index("]")]).exists()
    assert "macroslip" in index.read_text()
    assert (tmp_path / "fig08_masing.png").stat().st_size > 10_000
    with open(tmp_path / "fig08_masing.csv") as fh:
        rows = list(csv.DictReader(fh))
    curves = {}
    for r in rows:
        curves.setdefault(float(r["ratio"]), []).append(
            (float(r["omega_rad_s"]), float(r["amplitude_h1_per_force_m_per_N"]))
        )
    assert set(curves) == set(PAPER_SDOF["ratios"])
    m, k, kt = (
        PAPER_SDOF["mass"],
        PAPER_SDOF["stiffness"],
        PAPER_SDOF["tangential_stiffness"],
    )
    c = 2 * PAPER_SDOF["damping_ratio"] * np.sqrt(k * m)
    for ratio, stiffness in ((0.001, k + kt), (10.0, k)):
        w, a = np.array(curves[ratio]).T
        linear = 1 / np.abs(stiffness - m * w**2 + 1j * c * w)
        # Fex/Fn = 0.001 is stuck everywhere; Fex/Fn = 10 slips with a small
        # friction force (f_s = Fex/10) that damps the peak only a little
        tol = 1e-9 if ratio < 1 else 0.15
        np.testing.assert_allclose(a, linear, rtol=tol)
    # in between, the peaks are flattened below the stuck peak (paper Fig. 8)
    stuck_peak = max(a for _, a in curves[0.001])
    for ratio in (0.5, 0.2, 0.1):
        assert max(a for _, a in curves[ratio]) < 0.5 * stuck_peak


def test_paper_rejects_bad_harmonics(tmp_path):
    import pytest

    with pytest.raises(SystemExit):
        main(["paper", "--out", str(tmp_path), "--harmonics", "0"])


def test_warmup_runs_every_path(capsys):
    """``hbmfric warmup`` runs one tiny problem per engine path and reports
    each; a second run loads everything from the cache (no compile line)."""
    assert main(["warmup"]) == 0
    out = capsys.readouterr().out
    for step in (
        "Jenkins FRF",
        "Menq FRF",
        "Coulomb FRF",
        "beam FRF",
        "time integration",
    ):
        assert f"warmup: {step}" in out
    assert "warmup: done" in out


def test_warmup_lanes_hold_every_step_once():
    """``hbmfric warmup --jobs N`` deals the steps to N worker processes:
    every step in exactly one lane, the condensed steps (the beam, the lap
    joint: the kernels no other step compiles) alone in the second, the
    others in their order in the rest, so that no two lanes start on the
    same kernels; one lane keeps the order; a job count below 1 is
    refused."""
    from hbmfric.warmup import CONDENSED_STEPS, _steps, lanes, warmup

    names = [name for name, _ in _steps()]
    assert set(CONDENSED_STEPS) <= set(names)
    assert lanes(names, 1) == [names]
    others = [n for n in names if n not in CONDENSED_STEPS]
    assert lanes(names, 2) == [others, list(CONDENSED_STEPS)]
    for jobs in (2, 3, len(names) + 2):
        dealt = lanes(names, jobs)
        assert len(dealt) == jobs
        assert sorted(sum(dealt, [])) == sorted(names)
        assert dealt[1] == [n for n in names if n in CONDENSED_STEPS]
        rest = [lane for i, lane in enumerate(dealt) if i != 1]
        assert max(map(len, rest)) - min(map(len, rest)) <= 1
        for lane in rest:  # each keeps the steps' order
            assert lane == [n for n in others if n in lane]
    for bad in (0, -1, 1.5, True):
        with pytest.raises(ValueError, match="jobs"):
            warmup(progress=None, jobs=bad)
    with pytest.raises(SystemExit):
        main(["warmup", "--jobs", "0"])


def test_first_run_is_read_from_the_cache(tmp_path):
    """The first run of a version (``hbmfric paper`` then compiles the
    beam's kernels in a second process) is one whose cache holds no index
    of the continuation's ``trace``; without a cache it is never one."""
    from hbmfric.warmup import PaperHelper, first_run

    assert first_run(str(tmp_path))
    steps = tmp_path / "kernels" / "steps"
    steps.mkdir(parents=True)
    (steps / "arclength.other-10.py311.nbi").write_bytes(b"")
    assert first_run(str(tmp_path))
    (steps / "arclength.trace-671.py311.nbi").write_bytes(b"")
    assert not first_run(str(tmp_path))
    # this run's own cache holds the continuation kernels after one FRF:
    # no helper
    import hbmfric as hf

    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    hf.frf(hf.Oscillator(1.0, 0.02, 1.0, law), 0.5, (0.5, 3.0), 5)
    lines = []
    assert PaperHelper.start(lines.append) is None and not lines


def test_paper_helper_compiles_the_tensioner_residual(monkeypatch):
    """The first paper's helper (``warmup._tensioner_residual``, after the
    beam) resolves the residual of the problem type the tensioner's FRF
    (Fig. 5) calls, so that the main process finds it in the cache.
    Reference: the types whose residual a real tensioner FRF resolves
    (recorded at the continuation's calls)."""
    import numba

    from hbmfric.continuation import adaptive, palc
    from hbmfric.kernels.residuals import pointer
    from hbmfric.systems.tensioner import BeltTensioner
    from hbmfric.systems.tensioner_response import hbm_frf
    from hbmfric.warmup import _tensioner_residual

    used = set()

    def recording(kp):
        used.add(numba.typeof(kp))
        return pointer.residual_address(kp)

    monkeypatch.setattr(palc, "residual_address", recording)
    monkeypatch.setattr(adaptive, "residual_address", recording)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        hbm_frf(BeltTensioner(), 20.0, (5.0, 30.0), 7)
    assert len(used) == 1
    monkeypatch.undo()
    helper = set()
    real = pointer.residual_address
    monkeypatch.setattr(
        pointer, "residual_address", lambda kp: helper.add(numba.typeof(kp)) or real(kp)
    )
    _tensioner_residual()
    assert used <= helper


def test_paper_helper_compiles_the_lap_joint_kernels(monkeypatch):
    """With the extra lap joint asked for, the first paper's helper
    (``warmup._lap_joint``) resolves the residual of every problem type the
    lap-joint figure set calls (reference: the types a real family, at a
    stuck and a macroslip ratio and both preloads, resolves)."""
    import numba

    from hbmfric.continuation import adaptive, palc
    from hbmfric.kernels.residuals import pointer
    from hbmfric.paper.lap_joint import lap_joint_family
    from hbmfric.warmup import _lap_joint

    used = set()

    def recording(kp):
        used.add(numba.typeof(kp))
        return pointer.residual_address(kp)

    monkeypatch.setattr(palc, "residual_address", recording)
    monkeypatch.setattr(adaptive, "residual_address", recording)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lap_joint_family(
            3, ratios=(2e-5, 4e-2), check_ratios=(4e-2,), frequency_range=(150, 175)
        )
        assert used
        family = set(used)
        used.clear()
        _lap_joint(3)
    assert family <= used


@pytest.mark.slow
def test_warmup_in_two_processes_runs_every_path(capsys):
    """``hbmfric warmup --jobs 2`` runs every step in one of two worker
    processes and reports each once."""
    from hbmfric.warmup import _steps

    assert main(["warmup", "--jobs", "2"]) == 0
    out = capsys.readouterr().out
    for name, _ in _steps():
        assert out.count(f"warmup: {name}: ") == 1, name
    assert "warmup: done" in out


def test_stable_column_of_a_figure(tmp_path):
    """``FigureResult.write_csv`` adds a ``stable`` column once the
    stability is computed: on a Duffing curve (two folds) exactly the
    points between the folds read 0 (Hill's verdict, checked against the
    time-domain monodromy in tests/test_stability.py); with ``resample``
    every dense sample takes its nearest point's verdict."""
    import hbmfric as hf
    from hbmfric.paper.sdof import FigureResult

    osc = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    branch = hf.frf(osc, 0.2, (0.5, 2.0), harmonics=5)
    par = {"force": 0.2, "normal_load": 0.0, "ratio": 0.0}
    fig = FigureResult("duffing", "Duffing", ["Duffing"], [branch], [par])
    path = fig.write_csv(tmp_path / "plain.csv")
    with open(path) as fh:
        assert "stable" not in next(csv.reader(fh))
    f0, f1 = branch.folds
    assert fig.stability() == f1 - f0
    with open(fig.write_csv(tmp_path / "stable.csv")) as fh:
        rows = list(csv.DictReader(fh))
    flags = np.array([int(r["stable"]) for r in rows])
    expected = np.ones(len(branch), dtype=int)
    expected[f0:f1] = 0
    np.testing.assert_array_equal(flags, expected)
    with open(fig.write_csv(tmp_path / "dense.csv", resample=4)) as fh:
        rows = list(csv.DictReader(fh))
    on_points = [int(r["stable"]) for r in rows if r["computed"] == "1"]
    np.testing.assert_array_equal(on_points, expected)
    assert {r["stable"] for r in rows} == {"0", "1"}
