"""harmonics="auto": the harmonic count chosen along the branch."""

import numpy as np
import pytest

import hbmfric as hf

OSC = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


@pytest.fixture(scope="module")
def branches():
    return {
        tol: hf.frf(OSC, 0.5, (0.5, 3.0), "auto", harmonic_tolerance=tol)
        for tol in (1e-3, 1e-4)
    }


SLOW = pytest.mark.slow


@pytest.mark.parametrize(
    "force, tol",
    [
        (0.5, 1e-3),
        (2.0, 1e-4),
        pytest.param(0.1, 1e-3, marks=SLOW),
        pytest.param(0.1, 1e-4, marks=SLOW),
        pytest.param(0.5, 1e-4, marks=SLOW),
        pytest.param(2.0, 1e-3, marks=SLOW),
    ],
)
def test_auto_reaches_tolerance_against_high_h(force, tol):
    """At 20 points spread over the branch, the first-harmonic amplitude and
    half the peak-to-peak of the adaptive branch agree with an H = 63
    solution to the tolerance (F = 2 slips over the whole range; F = 0.1
    mostly sticks)."""
    b = hf.frf(OSC, force, (0.5, 3.0), "auto", harmonic_tolerance=tol)
    assert b.stop_reason == "end of frequency range reached"
    worst = 0.0
    for i in np.unique(np.linspace(0, len(b) - 1, 20).astype(int)):
        ref = hf.periodic_solution(
            OSC, force, float(b.omega[i]), 63, initial_guess=b.point(i)
        )
        assert ref.converged
        for harmonic in (1, None):
            a = b.amplitude(harmonic=harmonic)[i]
            r = ref.amplitude(harmonic=harmonic)
            worst = max(worst, abs(a - r) / r)
    assert worst <= tol, worst
    assert worst > 0.0  # the check can fail: slipping points carry an error


def test_auto_low_h_when_stuck_high_h_at_the_peak(branches):
    b = branches[1e-4]
    h = b.point_harmonics
    amp = b.amplitude(harmonic=1)
    assert h[0] == 3 and h[-1] == 3  # both ends stuck: linear, lowest level
    assert h[int(np.argmax(amp))] >= 7
    assert b.harmonic_numbers[-1] == h.max()
    # the truncated coefficients of a low-level point are exactly zero
    low = np.flatnonzero(h == 3)[0]
    assert np.all(b.coefficients[low, 0, 4:] == 0.0)


def test_auto_branch_continuous_across_changes(branches):
    """Where H changes, successive points stay as close as elsewhere on the
    branch (in the scaled norm of the continuation), and the point after the
    change is the fixed-H solution of its level (no branch jump)."""
    b = branches[1e-4]
    h = b.point_harmonics
    changes = np.flatnonzero(np.diff(h)) + 1
    assert changes.size >= 2
    X = b.coefficients[:, 0]
    scale = np.max(np.abs(X))
    d = np.hypot(
        np.diff(b.omega) / 2.5, np.max(np.abs(np.diff(X, axis=0)), axis=1) / scale
    )
    assert np.max(d[changes - 1]) <= 1.5 * np.max(np.delete(d, changes - 1))
    for i in changes:
        fixed = hf.periodic_solution(
            OSC, 0.5, float(b.omega[i]), int(h[i]), initial_guess=b.point(i)
        )
        a = b.amplitude(harmonic=1)[i]
        assert abs(fixed.amplitude(harmonic=1) - a) <= 1e-8 * a


def test_auto_save_load(tmp_path, branches):
    b = branches[1e-3]
    back = hf.Branch.load(b.save(tmp_path / "auto.npz"))
    np.testing.assert_array_equal(back.point_harmonics, b.point_harmonics)
    assert back.harmonics_at(0) == b.harmonics_at(0)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"harmonics": "many"}, "harmonics"),
        ({"harmonics": "auto", "n_time": 64}, "n_time"),
        ({"harmonics": "auto", "harmonic_tolerance": 0.0}, "harmonic_tolerance"),
        (
            {"harmonics": "auto", "harmonic_tolerance": float("nan")},
            "harmonic_tolerance",
        ),
    ],
)
def test_auto_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        hf.frf(OSC, 0.5, (0.5, 3.0), **kwargs)
