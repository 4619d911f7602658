"""Parameter studies (issue 17, part 2): every parameter set gets its own
branch, identical to a direct hf.frf call, whatever runs it (this process,
worker processes, a two-worker Dask LocalCluster); failures are kept with
their reason and never lose the rest; the table feeds the criterion."""

import csv
import sys
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.criterion import choose_contact_model, read_frfs

MU = 0.3
OMEGA = (0.5, 3.0)
OPTIONS = dict(harmonics=5, harmonic_tolerance=0.5)  # coarse on purpose


def jenkins_sdof(p):
    """The P1 oscillator with slip force μ N (module level: picklable)."""
    law = hf.Jenkins(stiffness=3.0, slip_force=MU * p["normal_load"])
    return hf.Oscillator(1.0, 0.02, 1.0, law)


def direct(p):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        return hf.frf(jenkins_sdof(p), p["force"], OMEGA, **OPTIONS)


def assert_same_branches(result, params):
    assert [r.parameters for r in result.runs] == params
    for run, p in zip(result.runs, params, strict=True):
        ref = direct(p)
        np.testing.assert_array_equal(run.branch.omega, ref.omega)
        np.testing.assert_array_equal(run.branch.coefficients, ref.coefficients)


def test_grid_is_the_cartesian_product():
    g = hf.grid(force=[1, 2], normal_load=[10, 20, 30])
    assert len(g) == 6
    assert g[0] == {"force": 1, "normal_load": 10}
    assert g[1] == {"force": 1, "normal_load": 20}
    assert g[-1] == {"force": 2, "normal_load": 30}
    with pytest.raises(ValueError, match="empty"):
        hf.grid(force=[])
    with pytest.raises(ValueError, match="at least one"):
        hf.grid()


def test_serial_study_matches_direct_calls():
    params = hf.grid(force=[0.1, 0.5], normal_load=[1.0, 2.0])
    res = hf.study(jenkins_sdof, params, OMEGA, executor="serial", **OPTIONS)
    assert res.executor == "serial" and len(res) == 4 and not res.failures
    assert_same_branches(res, params)


def test_worker_processes_match_direct_calls():
    params = hf.grid(force=[0.2, 1.0], normal_load=[1.0, 3.0])
    res = hf.study(jenkins_sdof, params, OMEGA, workers=2, **OPTIONS)
    assert res.executor == "processes" and not res.failures
    assert_same_branches(res, params)


def test_a_failed_set_is_reported_and_the_rest_kept():
    params = [
        {"force": 0.5, "normal_load": 1.0},
        {"force": 0.5, "normal_load": -1.0},  # negative slip force: refused
        {"force": 0.5, "normal_load": 2.0},
    ]
    with pytest.warns(hf.StudyWarning, match="1 of 3 parameter sets failed") as rec:
        res = hf.study(jenkins_sdof, params, OMEGA, workers=2, **OPTIONS)
    assert len(rec) == 1
    (bad,) = res.failures
    assert bad.index == 1 and bad.branch is None
    assert bad.parameters == params[1]
    assert bad.error.startswith("ValueError") and "slip_force" in bad.error
    assert res.runs[0].ok and res.runs[2].ok
    for run in (res.runs[0], res.runs[2]):
        ref = direct(run.parameters)
        np.testing.assert_array_equal(run.branch.omega, ref.omega)


def test_a_failed_set_is_named_beside_the_csv(tmp_path):
    """The CSV of a study with a failed set holds the traced sets (read by
    read_frfs and by NumPy as a plain table); the failed set is named in
    ``<stem>.failed.csv`` with its reason."""
    params = [
        {"force": 0.5, "normal_load": 1.0},
        {"force": 0.5, "normal_load": -1.0},  # negative slip force: refused
    ]
    with pytest.warns(hf.StudyWarning):
        res = hf.study(jenkins_sdof, params, OMEGA, executor="serial", **OPTIONS)
    path = res.to_csv(tmp_path / "family.csv")
    (record,) = read_frfs(path)
    assert record.normal_load == 1.0
    table = np.genfromtxt(path, delimiter=",", names=True)
    assert np.all(table["normal_load"] == 1.0)
    with open(tmp_path / "family.failed.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 1 and rows[0]["index"] == "1"
    assert "-1.0" in rows[0]["parameters"] and rows[0]["error"].startswith("ValueError")
    # a later study without failures written to the same path leaves none
    ok = hf.study(jenkins_sdof, params[:1], OMEGA, executor="serial", **OPTIONS)
    ok.to_csv(path)
    assert not (tmp_path / "family.failed.csv").exists()


def test_table_feeds_the_criterion(tmp_path):
    """A force × normal-load family (two normal loads per Fex/Fn) → CSV →
    read_frfs → the criterion, and the records straight from the result."""
    ratios = (0.0005, 0.01, 0.05, 0.2, 1.0)
    params = [{"force": r * n, "normal_load": n} for r in ratios for n in (1.0, 10.0)]
    res = hf.study(
        jenkins_sdof,
        params,
        OMEGA,
        executor="serial",
        harmonics=7,
        harmonic_tolerance=0.5,
    )
    path = res.to_csv(tmp_path / "family.csv")
    records = read_frfs(path)
    assert len(records) == len(params)
    table = res.table()
    assert set(table) >= {"curve", "force", "normal_load", "omega", "amplitude"}
    n_points = sum(len(b) for b in res.branches)
    assert table["omega"].size == n_points
    # a Jenkins family depends on Fex/Fn alone: macroslip, no roughness
    verdict = choose_contact_model(res.records())
    assert verdict.model == "macroslip" and not verdict.roughness, verdict.explanation
    assert choose_contact_model(records).model == "macroslip"
    npz = np.load(res.to_npz(tmp_path / "family.npz"))
    np.testing.assert_array_equal(npz["amplitude"], table["amplitude"])
    assert npz["failures"].size == 0


def test_bad_study_input():
    with pytest.raises(TypeError, match="picklable"):
        hf.study(lambda p: jenkins_sdof(p), [{"force": 1.0, "normal_load": 1.0}], OMEGA)
    with pytest.raises(ValueError, match="has no 'force'"):
        hf.study(jenkins_sdof, [{"normal_load": 1.0}], OMEGA, executor="serial")
    with pytest.raises(ValueError, match="executor must be one of"):
        hf.study(
            jenkins_sdof, [{"force": 1.0, "normal_load": 1.0}], OMEGA, executor="mpi"
        )
    with pytest.raises(ValueError, match="at least one parameter set"):
        hf.study(jenkins_sdof, [], OMEGA)
    with pytest.raises(ValueError, match="workers"):
        hf.study(jenkins_sdof, [{"force": 1.0, "normal_load": 1.0}], OMEGA, workers=0)
    with pytest.raises(TypeError, match="callable"):
        hf.study(3, [{"force": 1.0}], OMEGA)


def test_progress_line(capsys):
    params = hf.grid(force=[0.5], normal_load=[1.0, 2.0])
    hf.study(jenkins_sdof, params, OMEGA, executor="serial", progress=True, **OPTIONS)
    err = capsys.readouterr().err
    assert "study (serial): 2/2 done, 0 failed" in err


def test_dask_local_cluster_matches_direct_calls():
    distributed = pytest.importorskip("distributed")
    cloudpickle = pytest.importorskip("cloudpickle")
    # the workers cannot import this test module: send its functions by value
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    params = hf.grid(force=[0.1, 0.5, 2.0], normal_load=[1.0, 2.0])
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        res = hf.study(jenkins_sdof, params, OMEGA, client=client, **OPTIONS)
    assert res.executor == "dask" and not res.failures
    assert_same_branches(res, params)
