"""Stress rows for stop 35 (hunt37): an FE engineer's own files and studies.

* Fine beam meshes in SI units (translations and rotations): accepted,
  their first three natural frequencies against the Euler–Bernoulli
  cantilever (closed form) and against the same beam in mm–tonne units;
  the clamped beam is not taken for a free-floating one, the free beam
  is. On main the meshes with elements of 0.2 mm and less were refused as
  "not positive definite", and ``condensation._singular`` called the
  clamped 50-element 1 cm beam singular.
* The same beams condensed with a static load (harmonic 0) against the
  full solve.
* ``scipy.sparse.save_npz`` files (every format, M, K and C) against the
  dense matrices.
* ``with_contact`` on a relative contact, law by law, against the
  structure built directly (main put the new law to ground).
* A study traced with few steps: every incomplete set listed with its
  gaps, read back by ``read_frfs`` into ``FRFRecord.gaps``, and the
  criterion warns; the complete branch's peak lies in a gap.
* Duffing branches through two folds as records: one peak, and between
  the folds the one-term closed form's largest root (sweep up) or
  smallest (sweep down); ``read_frfs`` warns on rows that turn back over a
  common range and not on sorted, reversed or shuffled rows.

Run with ``python -m pytest -m stress tests/stress/test_stop35_files.py``.
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

import hbmfric as hf
from hbmfric.condensation import _singular
from hbmfric.criterion import choose_contact_model, read_frfs

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from test_hunt_fe_units import RHO, B, E, T, beam, to_mm_tonne  # noqa: E402

pytestmark = pytest.mark.stress

MESHES = [(50, 0.01), (40, 0.004), (100, 0.02), (200, 0.04), (20, 0.001), (60, 0.5)]
BETA_L = np.array([1.875104069, 4.694091133, 7.854757438])


def _exact(length):
    ei, rho_a = E * B * T**3 / 12.0, RHO * B * T
    return BETA_L**2 / (2 * math.pi) * math.sqrt(ei / (rho_a * length**4))


@pytest.mark.parametrize("n_el, length", MESHES)
def test_fine_mesh_frequencies_and_regular_stiffness(n_el, length):
    M, K = beam(n_el, length)
    f = hf.LinearStructure(M, K, modal_damping=0.01).natural_frequencies(3)
    np.testing.assert_allclose(f, _exact(length), rtol=1e-4)
    f_mm = hf.LinearStructure(*to_mm_tonne(M, K)).natural_frequencies(3)
    np.testing.assert_allclose(f_mm, f, rtol=1e-5)  # SI rounds at 5e-7 (200 el.)
    assert not _singular(K)
    assert _singular(beam(n_el, length, clamped=False)[1])


@pytest.mark.parametrize("n_el, length", [(50, 0.01), (20, 0.001)])
def test_condensed_with_a_mean_against_full(n_el, length):
    M, K = beam(n_el, length)
    tip = M.shape[0] - 2
    k_tip = 3 * E * B * T**3 / 12.0 / length**3
    s = hf.LinearStructure(
        M,
        K,
        modal_damping=0.01,
        contact=hf.Jenkins(0.25 * k_tip, 2.0),
        contact_dof=tip,
        load={tip: 1.0},
        static_load={tip: 0.5},
    )
    w1 = 2 * math.pi * s.natural_frequencies(1)[0]
    for omega in (0.9 * w1, 1.02 * w1, 1.2 * w1):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.AccuracyWarning)
            c = hf.periodic_solution(s, 3.0, omega, harmonics=3, condense=True)
            f = hf.periodic_solution(s, 3.0, omega, harmonics=3, condense=False)
        a, b = c.coefficients[tip], f.coefficients[tip]
        assert np.max(np.abs(a - b)) <= 1e-5 * np.max(np.abs(b))


@pytest.mark.parametrize("fmt", ["csr", "csc", "coo", "bsr", "dia", "lil", "dok"])
def test_save_npz_matrices(tmp_path, fmt):
    M, K = beam(10, 0.2)
    C = 1e-4 * K + 0.5 * M
    for name, a in (("M", M), ("K", K), ("C", C)):
        try:
            sp.save_npz(tmp_path / f"{name}.npz", sp.csr_matrix(a).asformat(fmt))
        except NotImplementedError:
            pytest.skip(f"scipy does not save {fmt}")
    s = hf.LinearStructure.from_files(
        tmp_path / "M.npz", tmp_path / "K.npz", tmp_path / "C.npz"
    )
    m, c, k = s.matrices()
    np.testing.assert_array_equal(m, M)
    np.testing.assert_array_equal(k, K)
    np.testing.assert_allclose(c, C, rtol=0, atol=1e-15 * np.max(np.abs(C)))


N = 5
K5 = 1e4 * (2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1))
K5[-1, -1] = 1e4
LAWS = {
    "jenkins": hf.Jenkins(5e3, 0.3),
    "menq": hf.Menq.from_stiffness(5e3, 0.3),
    "iwan": hf.Iwan((2e3, 3e3), (0.1, 0.3)),
}


@pytest.mark.parametrize("name", [k for k, v in LAWS.items() if v is not None])
def test_with_contact_relative(name):
    def chain(law):
        return hf.LinearStructure(
            0.1 * np.eye(N),
            K5,
            modal_damping=0.01,
            load={0: 1.0},
            contacts=[hf.Contact(law, 2, other=4)],
        )

    old, new = hf.Jenkins(5e3, 1.0), LAWS[name]
    swapped, direct = chain(old).with_contact(new), chain(new)
    w1 = 2 * math.pi * direct.natural_frequencies(1)[0]
    for omega in (0.9 * w1, 1.05 * w1):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.AccuracyWarning)
            a = hf.periodic_solution(swapped, 1.0, omega, harmonics=5)
            b = hf.periodic_solution(direct, 1.0, omega, harmonics=5)
        np.testing.assert_allclose(a.coefficients, b.coefficients, atol=1e-12)


def _build(p):
    return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 0.3 * p["normal_load"]))


@pytest.mark.parametrize("max_steps", [40, 60, 120, 200])
def test_study_gaps_reach_the_criterion(tmp_path, max_steps):
    grid = hf.grid(force=[0.02, 0.2, 2.0], normal_load=[1.0, 10.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        short = hf.study(
            _build, grid, (0.5, 3.0), executor="serial", max_steps=max_steps
        )
        full = hf.study(_build, grid, (0.5, 3.0), executor="serial")
    path = short.to_csv(tmp_path / "f.csv")
    records = read_frfs(path)
    inner = 0
    for r, run, ref in zip(records, short.runs, full.runs, strict=True):
        gaps = [
            (lo, hi)
            for lo, hi in run.branch.gaps
            if lo > run.branch.omega.min() and hi < run.branch.omega.max()
        ]
        assert len(r.gaps) == len(gaps)
        for (lo, hi), (a, b) in zip(r.gaps, gaps, strict=True):
            assert lo == pytest.approx(a, rel=1e-11)
            assert hi == pytest.approx(b, rel=1e-11)
            assert not np.any((r.omega > lo) & (r.omega < hi))
        inner += bool(gaps)
        peak = ref.branch.omega[np.argmax(ref.branch.amplitude())]
        if gaps and not run.branch.complete:
            covered = [(run.branch.omega.min(), run.branch.omega.max())]
            assert covered  # the peak is either in a gap or sampled
            in_gap = any(lo < peak < hi for lo, hi in gaps)
            near = np.min(np.abs(run.branch.omega - peak)) < 1e-2
            assert in_gap or near
    if inner:
        with pytest.warns(hf.CoverageWarning, match="records have gaps"):
            choose_contact_model(records)


def _roots(c, k3, f, omega):
    d, e = 1.0 - omega**2, 0.75 * k3
    s = np.roots([e * e, 2 * d * e, d * d + (c * omega) ** 2, -f * f])
    s = np.sort(s[np.abs(s.imag) < 1e-9].real)
    return np.sqrt(s[s > 0])


@pytest.mark.parametrize("k3", [0.3, 0.5, 1.0])
@pytest.mark.parametrize("force", [0.2, 0.3])
@pytest.mark.parametrize("sweep", ["up", "down"])
def test_fold_records(k3, force, sweep):
    from hbmfric.criterion import FRFRecord

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        b = hf.frf(
            hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(k3)),
            force,
            (0.5, 3.5),
            harmonics=7,
            sweep=sweep,
        )
    turns = np.nonzero(np.diff(np.sign(np.diff(b.omega))))[0]
    r = FRFRecord.from_branch(b, 1.0)
    slope = np.sign(np.diff(r.amplitude))
    assert np.count_nonzero(np.diff(slope[slope != 0])) <= 1
    if turns.size < 2:
        return
    lo, hi = np.sort(b.omega[turns + 1])
    # where the one-term sheets are furthest apart, inside the folds
    grid = np.linspace(lo, hi, 41)[4:-4]
    sep = []
    for w in grid:
        roots = _roots(0.05, k3, force, w)
        sep.append((roots[-1] - roots[1]) / roots[-1] if roots.size == 3 else 0.0)
    w = grid[int(np.argmax(sep))]
    roots = _roots(0.05, k3, force, w)
    assert roots.size == 3 and max(sep) > 0.1
    want = roots[-1] if sweep == "up" else roots[0]
    assert np.interp(w, r.omega, r.amplitude) == pytest.approx(want, rel=0.03)


@pytest.mark.parametrize(
    "order, warns",
    [
        ("sorted", False),
        ("reversed", False),
        ("shuffled", False),
        ("down then up, disjoint", False),
        ("up then down", True),
        ("up, down, up", True),
    ],
)
def test_read_frfs_turning_rows(tmp_path, order, warns):
    w = np.linspace(1.0, 10.0, 30)
    rows = {
        "sorted": w,
        "reversed": w[::-1],
        "shuffled": np.random.default_rng(3).permutation(w),
        "down then up, disjoint": np.r_[w[:10][::-1], w[10:]],
        "up then down": np.r_[w, w[::-1][1:] - 0.05],
        "up, down, up": np.r_[w[:20], w[5:19][::-1] + 0.01, w[5:] + 0.02],
    }[order]
    path = tmp_path / "f.csv"
    with open(path, "w") as fh:
        fh.write("force,normal_load,omega,amplitude\n")
        for x in rows:
            fh.write(f"1,1,{float(x)!r},{1.0 / (abs(float(x) - 5.0) + 0.1)!r}\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        read_frfs(path)
    said = [c for c in caught if issubclass(c.category, hf.DataWarning)]
    assert bool(said) == warns


@pytest.mark.parametrize("harmonics", [7, "auto"])
def test_iwan_against_its_jenkins_elements_is_right_or_warned(harmonics):
    # the located-reversal AFT of a two-element Iwan at the default n_time
    # (8 H) misses its elements' slip onsets: 7.4e-4 off the same contact
    # given as its two Jenkins elements at H = 7 (1e-15 with the same
    # sampled AFT). Not quiet: the truncation estimate, whose probe level
    # samples twice as finely, reads 7.9e-4 and warns; "auto" climbs to
    # H = 45 and agrees to 1.5e-5 (at the lead's review of hunt37's row)
    jenkins = [hf.Jenkins(2e3, 0.2), hf.Jenkins(3e3, 0.5)]
    iwan = hf.Iwan((2e3, 3e3), (0.2, 0.5))
    n = 4
    k = 1e4 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    k[-1, -1] = 1e4

    def chain(laws):
        return hf.LinearStructure(
            0.1 * np.eye(n),
            k,
            modal_damping=0.01,
            load={0: 1.0},
            contacts=[hf.Contact(law, 3) for law in laws],
        )

    two, one = chain(jenkins), chain([iwan])
    w1 = 2 * math.pi * one.natural_frequencies(1)[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        a = hf.periodic_solution(two, 1.0, 1.5 * w1, harmonics=15)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        b = hf.periodic_solution(one, 1.0, 1.5 * w1, harmonics=harmonics)
    m = min(a.coefficients.shape[1], b.coefficients.shape[1])
    err = np.max(np.abs(a.coefficients[:, :m] - b.coefficients[:, :m]))
    err /= np.max(np.abs(a.coefficients))
    warned = [c for c in caught if issubclass(c.category, hf.AccuracyWarning)]
    assert err <= 1e-4 or warned
