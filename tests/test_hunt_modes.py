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


def _ring(mistune: float = 0.0) -> hf.LinearStructure:
    """Three unit masses in a ring (springs 1 N/m between neighbours, 1 N/m
    to ground), a Jenkins contact (kt = 3 N/m, f_s = 1 N) to ground at each:
    stuck, modes at 2 rad/s and a repeated pair at √7 rad/s."""
    K = 3.0 * np.eye(3)
    for i in range(3):
        K[i, (i + 1) % 3] -= 1.0
        K[(i + 1) % 3, i] -= 1.0
    K[0, 0] *= 1.0 + mistune
    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    return hf.LinearStructure(
        np.eye(3),
        K,
        modal_damping=0.01,
        contacts=[hf.Contact(law, i) for i in range(3)],
    )


def test_a_repeated_pair_of_linear_modes_is_named_in_the_warning():
    """A mode of a repeated pair (a cyclic structure) has no isolated EPMC
    solution: no point, and the warning says why (before: only "no
    solution near the linear mode"); mistuned by 1e-6 it is followed from
    its linear pulsation (√7 rad/s, closed form) over the whole range."""
    ring = _ring()
    with pytest.warns(hf.HbmfricWarning, match="repeated pair") as caught:
        mode = hf.nonlinear_mode(ring, mode=2, amplitude=(1e-3, 10.0), points=12)
    assert len(mode) == 0 and not mode.complete
    assert "repeated pair" in mode.stop_reason
    assert any("break the symmetry" in str(w.message) for w in caught)
    # the single mode 1 (2 rad/s) is not a pair: no such note
    assert "repeated" not in str(
        hf.nonlinear_mode(ring, mode=1, amplitude=(1e-3, 10.0), points=12).stop_reason
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        tuned = hf.nonlinear_mode(
            _ring(1e-6), mode=2, amplitude=(1e-3, 10.0), points=12
        )
    assert tuned.complete
    assert tuned.omega[0] == pytest.approx(np.sqrt(7.0), rel=1e-6)
