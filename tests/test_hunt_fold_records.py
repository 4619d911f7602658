"""A branch through folds as a criterion record (stop 35, hunt37).

``FRFRecord.from_branch`` kept the first of exactly repeated frequencies
only: a Duffing branch with two folds (three amplitudes between them) gave
a record that, sorted by frequency, zigzagged between the sheets (its
slope changed sign 1654 times between the folds). The study's CSV of such
a branch, read by ``read_frfs``, did the same without a word. Reference:
the one-term harmonic balance of the Duffing oscillator (closed form),
whose largest root a sweep up measures between the folds and whose
smallest a sweep down measures (at Ω = 1.4 the record of the sweep up
read 0.325 on main, the lower sheet; the one-term roots are 0.325, 1.425
and 1.727, the branch's upper sheet 1.707).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.criterion import FRFRecord, read_frfs

C, K3, F = 0.05, 0.5, 0.3
BAND = (0.5, 3.0)


def duffing(p=None):
    return hf.Oscillator(1.0, C, 1.0, hf.Cubic(K3))


def one_term_roots(omega):
    """Amplitudes of ``a² ((1 - Ω² + 3/4 k3 a²)² + (c Ω)²) = F²``."""
    d, e = 1.0 - omega**2, 0.75 * K3
    # cubic in s = a²: e² s³ + 2 d e s² + (d² + c² Ω²) s - F² = 0
    s = np.roots([e * e, 2 * d * e, d * d + (C * omega) ** 2, -F * F])
    s = np.sort(s[np.abs(s.imag) < 1e-9].real)
    return np.sqrt(s[s > 0])


@pytest.fixture(scope="module")
def branches():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        up = hf.frf(duffing(), F, BAND, harmonics=7)
        down = hf.frf(duffing(), F, BAND, harmonics=7, sweep="down")
    return up, down


@pytest.mark.parametrize("side", ["up", "down"])
def test_record_keeps_what_a_sweep_measures(branches, side):
    branch = branches[0 if side == "up" else 1]
    assert np.any(np.diff(np.sign(np.diff(branch.omega))))  # it folds
    r = FRFRecord.from_branch(branch, 1.0)
    slope = np.sign(np.diff(r.amplitude))
    assert np.count_nonzero(np.diff(slope[slope != 0])) <= 1  # one peak
    roots = one_term_roots(1.4)  # upper and middle sheets 21 % apart
    assert roots.size == 3  # between the folds
    want = roots[-1] if side == "up" else roots[0]
    got = np.interp(1.4, r.omega, r.amplitude)
    assert got == pytest.approx(want, rel=0.03)  # H = 7 against one term: 1.2 %


def test_study_csv_of_a_folded_branch_is_said(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        st = hf.study(
            duffing,
            [{"force": F, "normal_load": 1.0}],
            BAND,
            executor="serial",
            harmonics=7,
        )
        path = st.to_csv(tmp_path / "f.csv")
    with pytest.warns(hf.DataWarning, match="turn back in frequency"):
        read_frfs(path)
