"""Stress rows for stop 28's trust hunt (branch hunt28): the Craig–Bampton
reduction's valid range, and a DOF index across studies whose models
change size.

Run with ``python -m pytest -m stress tests/stress/test_stop28_paths.py``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.linalg import eigh

import hbmfric as hf

pytestmark = pytest.mark.stress

N = 40


def _chain(kt: float, f_s: float) -> hf.LinearStructure:
    K = 2e4 * np.eye(N) - 1e4 * (np.eye(N, k=1) + np.eye(N, k=-1))
    K[-1, -1] = 1e4
    return hf.LinearStructure(
        0.1 * np.eye(N),
        K,
        modal_damping=0.01,
        dof_names={"drive": 10, "tip": N - 1},
        load={"drive": 1.0},
        contact=hf.Jenkins(stiffness=kt, slip_force=f_s),
        contact_dof="tip",
    )


def _peak(branch) -> tuple[float, float]:
    a = branch.amplitude(harmonic=1)
    i = int(np.argmax(a))
    return float(branch.omega[i]), float(a[i])


@pytest.mark.parametrize("n_modes", [2, 4, 8, 16])
@pytest.mark.parametrize("kt, f_s", [(2e3, 1e3), (2e3, 0.05)])
def test_reduced_chain_against_full_below_and_warning_above(n_modes, kt, f_s):
    """The first resonance (stuck, or slipping at f_s = 0.05 N, H = 7) of
    the reduced chain against the full chain's: frequency within 0.3 %,
    peak within 3 %, and no warning about the reduction (the band lies
    below valid_below); a band across valid_below warns, and the reduced
    natural frequencies above it are off the full chain's (plain eigh) by
    more than 3 %."""
    full = _chain(kt, f_s)
    reduced = hf.craig_bampton(full, ["tip", "drive"], n_modes=n_modes)
    w1 = full.modes()[0][0]
    band = (0.5 * w1, 1.5 * w1)
    assert band[1] < reduced.valid_below
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        red = hf.frf(reduced, 2.0, band, harmonics=7)
    assert not [w for w in record if "Craig–Bampton" in str(w.message)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        ref = hf.frf(full, 2.0, band, harmonics=7)
    (w_r, a_r), (w_f, a_f) = _peak(red), _peak(ref)
    assert abs(w_r - w_f) / w_f < 3e-3
    assert abs(a_r - a_f) / a_f < 3e-2
    w_cut = reduced.valid_below
    with pytest.warns(hf.AccuracyWarning, match="Craig–Bampton"):
        hf.frf(reduced, 2.0, (0.9 * w_cut, 1.1 * w_cut), harmonics=3)
    M, _, K = full.with_contact(None).matrices()
    M_r, _, K_r = reduced.with_contact(None).matrices()
    w_full = np.sqrt(eigh(K, M, eigvals_only=True))
    w_red = np.sqrt(eigh(K_r, M_r, eigvals_only=True))
    above = w_red > w_cut
    assert np.all(np.abs(w_red[above] / w_full[: w_red.size][above] - 1) > 0.03)


def _beam(params: dict):
    return hf.CantileverBeam(
        n_elements=int(params["n_elements"]),
        tip_mass=0.0772,
        damping_ratio=0.05,
        contact=hf.Jenkins(stiffness=1.6e5, friction_coefficient=1.5, normal_load=5.0),
    )


def test_beam_mesh_study_by_name_and_refused_by_index():
    """The paper's beam at 2, 5 and 13 elements: the table by name is each
    branch's own tip amplitude; an index is refused (6, 15, 39 DOFs);
    the first resonance converges with the mesh (13 against 5 elements
    within 1 %)."""
    res = hf.study(
        _beam,
        hf.grid(force=[2.0], n_elements=[2, 5, 13]),
        (2 * math.pi * 15.0, 2 * math.pi * 110.0),
        executor="serial",
        harmonics=3,
    )
    assert not res.failures
    with pytest.raises(ValueError, match="6, 15, 39 DOFs"):
        res.table(dof=3)
    t = res.table(dof="tip")
    for r in res.runs:
        rows = t["curve"] == r.index
        np.testing.assert_array_equal(
            t["amplitude"][rows], r.branch.amplitude(harmonic=1, dof="tip")
        )
    peaks = [_peak(r.branch)[0] for r in res.runs]
    assert abs(peaks[2] - peaks[1]) / peaks[2] < 1e-2


def _bladed_disk(load_sector: int) -> hf.LinearStructure:
    """Six sectors, each a disk DOF (2 kg, 100 N/m to ground, 50 N/m to the
    next disk) and a blade DOF (0.5 kg, 80 N/m and a 0.05 N s/m dashpot to
    its disk: non-classical damping), a Jenkins damper (kt 200 N/m, f_s
    0.05 N) from each blade tip to ground; load on one blade. Cyclic: the
    modes come in repeated pairs (7.375375 rad/s twice, ...)."""
    n_sectors = 6
    n = 2 * n_sectors
    K = np.zeros((n, n))
    C = np.zeros((n, n))

    def spring(a, i, j, k):
        a[i, i] += k
        if j is not None:
            a[j, j] += k
            a[i, j] -= k
            a[j, i] -= k

    for s in range(n_sectors):
        disk, blade = 2 * s, 2 * s + 1
        spring(K, disk, None, 100.0)
        spring(K, disk, 2 * ((s + 1) % n_sectors), 50.0)
        spring(K, disk, blade, 80.0)
        spring(C, disk, blade, 0.05)
    law = hf.Jenkins(stiffness=200.0, slip_force=0.05)
    return hf.LinearStructure(
        np.diag([2.0, 0.5] * n_sectors),
        K,
        C,
        load={2 * load_sector + 1: 1.0},
        contacts=[hf.Contact(law, 2 * s + 1) for s in range(n_sectors)],
    )


def test_bladed_disk_repeated_modes_condensed_against_full_and_rotated():
    """Repeated pairs of complex modes (the 'state' receptance, chosen by
    default) with six friction dampers, H = 5, F = 0.3, (4, 20) rad/s: the
    condensed branch's drawn curve at the loaded blade against the full
    (uncondensed) branch, and against the same disk loaded two sectors on
    (read at that sector's blade: cyclic symmetry), within 1e-4 at 200 Ω
    (measured 2.9e-5 both)."""
    base, turned = _bladed_disk(0), _bladed_disk(2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        condensed = hf.frf(base, 0.3, (4.0, 20.0), harmonics=5)
        full = hf.frf(base, 0.3, (4.0, 20.0), harmonics=5, condense=False)
        rotated = hf.frf(turned, 0.3, (4.0, 20.0), harmonics=5)
    assert condensed.info["receptance"] == "state"
    assert condensed.complete and full.complete and rotated.complete
    grid = np.linspace(4.01, 19.99, 200)
    a = condensed.amplitude_at(grid, dof=1)
    b = full.amplitude_at(grid, dof=1)
    c = rotated.amplitude_at(grid, dof=5)
    assert a.shape == b.shape == c.shape
    assert np.nanmax(np.abs(a - b) / b) < 1e-4
    assert np.nanmax(np.abs(c - b) / b) < 1e-4


def test_bladed_disk_modal_damping_per_mode():
    """Per-mode ratios on the bladed disk's modes (five repeated pairs):
    equal within each pair is accepted and keeps the cyclic symmetry of
    the damping matrix (turned by one sector, to 1e-12 relative); one
    pair split is refused."""
    base = _bladed_disk(0)
    M, _, K = base.matrices()
    omega = base.modes()[0]
    # one ratio per distinct frequency, shared by the members of a pair
    distinct = np.unique(np.round(omega, 6))
    ratio_of = {w: 0.005 * (i + 1) for i, w in enumerate(distinct)}
    zeta = [ratio_of[w] for w in np.round(omega, 6)]
    s = hf.LinearStructure(M, K, modal_damping=zeta)
    C = s.matrices()[1]
    turn = np.roll(np.eye(12), 2, axis=0)
    np.testing.assert_allclose(turn @ C @ turn.T, C, atol=1e-12 * np.abs(C).max())
    split = list(zeta)
    split[2] *= 2.0  # mode 3, the second of the pair at 7.375375 rad/s
    with pytest.raises(ValueError, match="modes 2 and 3 different ratios"):
        hf.LinearStructure(M, K, modal_damping=split)
