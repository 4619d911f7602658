"""``NonlinearMode.resonances`` beyond the mode's amplitudes (issue 14):
it returned empty arrays without a word where the forced response has its
peak above the amplitudes the mode was computed for."""

import warnings

import numpy as np
import pytest

import hbmfric as hf

OSC = hf.Oscillator(1.0, 4.0, 1e4, hf.Jenkins(stiffness=3e4, slip_force=1.0))


def test_a_resonance_beyond_the_mode_warns_and_is_found_when_covered():
    short = hf.nonlinear_mode(OSC, amplitude=(1e-6, 1e-2), harmonics=5, points=20)
    with pytest.warns(hf.CoverageWarning, match="no resonance at force = 10"):
        omega, amplitude = short.resonances(10.0)
    assert omega.size == 0 and amplitude.size == 0
    # covered: the peak of the forced response (an independent route, the
    # FRF traced at this force) within 1 %
    wide = hf.nonlinear_mode(OSC, amplitude=(1e-6, 1.0), harmonics=5, points=40)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        omega, amplitude = wide.resonances(10.0)
    branch = hf.frf(OSC, 10.0, (80.0, 220.0))
    peak = int(np.argmax(branch.amplitude(harmonic=1)))
    assert omega.size == 1
    assert abs(omega[0] / branch.omega[peak] - 1.0) < 1e-2
    # one DOF of unit mass: the modal amplitude is the displacement's
    assert abs(amplitude[0] / branch.amplitude(harmonic=1)[peak] - 1.0) < 1e-2
