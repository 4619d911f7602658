"""Stress rows for the stop-29 trust hunt (branch hunt29).

* Estimates of a DOF at or near rest: the paper beam with a rigid Coulomb
  tip at three slip forces and both sweeps, H = 15, 55-110 Hz. A stuck
  tip's truncation estimate is 0 to round-off (was 4e3); the largest
  truncation estimate of a branch is at most 100 times its change to H = 63
  (relative to ``CURVE_REST`` of the scale at least; was 8.9e3 against
  0.21); the three largest chord estimates are at most 10 times the
  distance of the chord from H = 15 solutions at its fractions (was 7.7e4
  against 7e-3: a tangent recovered across a DLFT seam).
* Measured files: decimal commas in comma-separated files are refused in
  every column layout.
* Studies on a Dask ``LocalCluster`` with two threads per worker: each
  set keeps its own warnings.

Run with ``python -m pytest -m stress tests/stress/test_stop29_rest.py``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.criterion import read_frfs
from hbmfric.results import CURVE_REST

pytestmark = pytest.mark.stress

HZ = 2.0 * math.pi
FRACTIONS = (0.21132486540518713, 0.5, 0.7886751345948129)


@pytest.fixture(scope="module")
def beam():
    return hf.CantileverBeam.calibrate().beam


def _solve(system, omega, harmonics, guess):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        s = hf.periodic_solution(system, 2.0, omega, harmonics, initial_guess=guess)
    return s if s.converged else None


@pytest.mark.parametrize(
    "slip_force, sweep",
    [(2.0, "down"), (2.0, "up"), (1.0, "down"), (0.5, "up")],
    ids=["fs=2 down", "fs=2 up", "fs=1 down", "fs=0.5 up"],
)
def test_rigid_coulomb_beam_estimates_are_measures(beam, slip_force, sweep):
    system = beam.with_contact(hf.Coulomb(slip_force=slip_force))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        b = hf.frf(system, 2.0, (HZ * 55.0, HZ * 110.0), 15, sweep=sweep)
    rest = CURVE_REST * b.info["amplitude_scale"]
    a, half = b.amplitude(1), b.amplitude()
    te = b.truncation_error
    stuck = a < 1e-15
    assert np.all(te[stuck] < 1e-6), te[stuck]
    i = int(np.argmax(te))
    s = _solve(system, b.omega[i], 63, b.point(i))
    if s is not None:
        change = max(
            abs(s.amplitude(1) - a[i]) / max(a[i], rest),
            abs(s.amplitude() - half[i]) / max(half[i], rest),
        )
        assert te[i] <= 100.0 * change + 1e-3, (b.omega[i] / HZ, te[i], change)
    errors = b.curve_errors
    for j in np.argsort(errors)[::-1][:3]:
        if errors[j] <= 1e-4:
            break
        ref = max(min(a[j], a[j + 1]), rest)
        measured = []
        for tau in FRACTIONS:
            w = b.omega[j] + tau * (b.omega[j + 1] - b.omega[j])
            s = _solve(system, w, 15, b.point(j if tau < 0.5 else j + 1))
            if s is not None:
                line = a[j] + tau * (a[j + 1] - a[j])
                measured.append(abs(line - s.amplitude(1)) / ref)
        if measured:
            worst = max(measured)
            assert errors[j] <= 10.0 * worst + 1e-4, (b.omega[j] / HZ, errors[j])


@pytest.mark.parametrize(
    "header, row",
    [
        ("force,normal_load,omega,amplitude", "1,5,{w},5,1,{a}"),
        ("curve,force,normal_load,omega,amplitude", "A,1,5,{w},5,1,{a}"),
        ("force,normal_load,omega,amplitude,curve", "1,5,{w},5,1,{a},A"),
        ("omega,amplitude,force,normal_load", "{w},5,1,{a},1,5"),
    ],
)
def test_decimal_commas_in_comma_separated_files_are_refused(tmp_path, header, row):
    p = tmp_path / "lab.csv"
    body = [row.format(w=10 + k, a=k + 1) for k in range(6)]
    p.write_text("\n".join([header, *body]) + "\n")
    with pytest.raises(ValueError, match="decimal"):
        read_frfs(p)


def _build(p):
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def test_study_on_threaded_dask_workers_keeps_each_sets_warnings():
    distributed = pytest.importorskip("dask.distributed")
    forces = [0.5 if i % 2 == 0 else 1e-4 for i in range(8)]
    sets = [{"force": f, "normal_load": 1.0} for f in forces]
    with (
        distributed.LocalCluster(
            n_workers=1, threads_per_worker=2, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore", hf.StudyWarning)
        result = hf.study(_build, sets, (0.3, 3.0), client=client, harmonics=3)
    for run in result.runs:
        warned = any("AccuracyWarning" in w for w in run.warnings)
        # H = 3 at 0.5 N is far from converged; at 1e-4 N the contact is
        # stuck and the response linear
        assert warned == (run.parameters["force"] == 0.5), (run.index, run.warnings)


def _build_or_die(p):
    if p["die"]:
        import os

        os._exit(3)
    return _build(p)


def test_study_on_dask_keeps_the_sets_a_dying_worker_did_not_take():
    """A set whose worker dies every time ends as ``KilledWorker`` in its
    own run's error; the other sets are traced (the study raised
    ``KilledWorker`` and returned nothing)."""
    distributed = pytest.importorskip("dask.distributed")
    sets = [{"force": 1e-4, "normal_load": 1.0, "die": i == 2} for i in range(4)]
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore", hf.StudyWarning)
        result = hf.study(_build_or_die, sets, (0.5, 2.0), client=client, harmonics=1)
    assert "KilledWorker" in result.runs[2].error
    assert all(r.ok for r in result.runs if r.index != 2)
