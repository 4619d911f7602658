"""Stop 33 trust hunt: a resonance predicted across the onset of slip.

``NonlinearMode.resonances`` interpolates the energy balance linearly in
``log a`` between the mode's points. Where a contact starts to slip
between two points the balance has a kink (no friction loss below, a
steep rise above) and the chord's zero can lie anywhere in the interval:
a Jenkins oscillator whose peak lies just past the slip onset read 3.4 %
low with 241 points over 1e-6 to 1e-1, without a word. The reference is
the closed-form balance at ``H = 1`` (the describing function of
``tests/naive.py``), not the mode.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

import hbmfric as hf
from tests.naive import jenkins_energy, jenkins_first_harmonic

M, C, K = 1.0, 0.2, 1e4
KT, FS = 20800.83823051904, 1.0


def _balance_amplitude(force: float) -> float:
    """Phase resonance at ``H = 1``: the load's work ``π a F`` equals the
    viscous ``π c ω(a) a²`` plus the Jenkins loop's ``4 f_s (a − f_s/k_t)``,
    ``ω(a)² = (k + C1(a)/a)/m``."""

    def excess(a):
        c1, _ = jenkins_first_harmonic(a, KT, FS)
        omega = np.sqrt((K + c1 / a) / M)
        return np.pi * C * omega * a * a + jenkins_energy(a, KT, FS) - np.pi * a * force

    return brentq(excess, 1e-7, 1e-1, xtol=1e-16, rtol=1e-14)


@pytest.fixture(scope="module")
def mode():
    osc = hf.Oscillator(M, C, K, hf.Jenkins(stiffness=KT, slip_force=FS))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return hf.nonlinear_mode(
            osc, 1, amplitude=(1e-6, 1e-1), points=241, harmonics=1
        )


def _predict(mode, force):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _, amp = mode.resonances(force)
    said = [
        w
        for w in caught
        if issubclass(w.category, hf.AccuracyWarning) and "bends" in str(w.message)
    ]
    return amp, said


def test_a_peak_just_past_the_slip_onset_is_right_or_said(mode):
    force = 0.002  # the peak lies 2.6e-4 past the onset a = f_s / k_t
    ref = _balance_amplitude(force)
    assert ref == pytest.approx(FS / KT, rel=1e-3)
    amp, said = _predict(mode, force)
    assert amp.size == 1
    error = abs(amp[0] / ref - 1.0)
    assert error < 0.01 or said, f"{error:.2%} off, no warning"
    if said:  # the bound it states covers the error
        bound = float(str(said[0].message).split("off by up to ")[1].split("%")[0])
        assert error <= bound / 100.0


@pytest.mark.parametrize("force", [2e-4, 0.2, 0.5, 1.0])
def test_peaks_on_smooth_stretches_stay_quiet_and_right(mode, force):
    amp, said = _predict(mode, force)
    assert not said
    assert amp[0] == pytest.approx(_balance_amplitude(force), rel=3e-3)
