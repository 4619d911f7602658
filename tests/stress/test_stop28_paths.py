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
