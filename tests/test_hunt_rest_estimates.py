"""The accuracy estimates of a branch whose watched DOF is (nearly) at rest.

The paper beam with a rigid Coulomb tip (f_s = 2 N, Fex = 2 N, H = 15,
swept down over 55-110 Hz) sticks below about 77.2 Hz; just above, the tip
moves by 1.8e-9 m against a displacement scale of 4.2e-5 m. Before stop
29 the branch warned "estimated truncation error 1.7e+04" and "estimated
curve error 7.7e+04" there, and 4e3 at the stuck points, whose response is
linear. The points themselves solve the H = 15 balance; their tip amplitude
is 1.3-2.5 times its H = 127 value (2.4 times the exact stiff-Jenkins
limit, ``hbmfric.validation.exact_periodic_solution`` at kt = 1e10, 1e11
N/m), the load DOF within 1.6e-4: a warning is right, the numbers were not.

References: Newton solves at fixed Ω (H = 15 on the chords, H = 63 for the
truncation), independent of the tangents and of the first-order estimate.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.results import CURVE_REST

HZ = 2.0 * np.pi
FORCE = 2.0


@pytest.fixture(scope="module")
def setup():
    beam = hf.CantileverBeam.calibrate().beam.with_contact(hf.Coulomb(slip_force=2.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(beam, FORCE, (HZ * 55.0, HZ * 110.0), 15, sweep="down")
    return beam, branch


def _solve(beam, omega, harmonics, guess=None):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        s = hf.periodic_solution(beam, FORCE, omega, harmonics, initial_guess=guess)
    return s if s.converged else None


def test_curve_estimates_match_fixed_frequency_solves(setup):
    """The five largest chord estimates against H = 15 solutions at the
    chord's fractions 0.21, 0.5, 0.79 in Ω (the tip's first harmonic,
    relative to the smaller end, at least ``CURVE_REST`` of the scale, as
    :attr:`Branch.curve_errors` measures): an estimate is at most 10 times
    the largest distance measured (was 7.7e4 against 7e-3 at 77.26 Hz: a
    tangent recovered across a seam of the DLFT force) and at least a
    third of it."""
    beam, b = setup
    rest = CURVE_REST * b.info["amplitude_scale"]
    a = b.amplitude(1)
    errors = b.curve_errors
    checked = 0
    for i in np.argsort(errors)[::-1][:5]:
        w0, w1 = b.omega[i], b.omega[i + 1]
        ref = max(min(a[i], a[i + 1]), rest)
        measured = []
        for tau in (0.21132486540518713, 0.5, 0.7886751345948129):
            w = w0 + tau * (w1 - w0)
            s = _solve(beam, w, 15, b.point(i if tau < 0.5 else i + 1))
            if s is not None:
                line = a[i] + tau * (a[i + 1] - a[i])
                measured.append(abs(line - s.amplitude(1)) / ref)
        if not measured:
            continue
        checked += 1
        worst = max(measured)
        assert errors[i] <= 10.0 * worst + 1e-4, (w0 / HZ, errors[i], worst)
        assert errors[i] >= worst / 3.0 - 1e-4, (w0 / HZ, errors[i], worst)
    assert checked >= 3


def test_stuck_points_carry_no_truncation_error(setup):
    """A stuck rigid tip makes the beam linear: every harmonic but the
    first is zero and the tip's amplitude is round-off (1e-20 m). The
    estimate there was 4e3 (relative to the round-off); H = 63 gives the
    same load DOF to 1e-10."""
    beam, b = setup
    a = b.amplitude(1)
    stuck = a < 1e-15
    assert np.count_nonzero(stuck) >= 3
    assert np.all(b.truncation_error[stuck] < 1e-6), b.truncation_error[stuck]
    i = int(np.flatnonzero(stuck)[len(np.flatnonzero(stuck)) // 2])
    s = _solve(beam, b.omega[i], 63, b.point(i))
    assert s is not None
    load = b.point(i).amplitude(1, "force")
    assert s.amplitude(1, "force") == pytest.approx(load, rel=1e-10)


def test_truncation_estimates_just_short_of_sticking(setup):
    """Between 77.2 and 77.7 Hz (the tip just short of sticking) the
    estimate of a point against its change to H = 63, relative to at least
    ``CURVE_REST`` of the scale: not below half of it, not above 30 times
    it (was 8.9e3 at 77.26 Hz against a change of 0.21: a first-order step
    of the DLFT far outside its model)."""
    beam, b = setup
    f = b.omega / HZ
    rest = CURVE_REST * b.info["amplitude_scale"]
    rows = np.flatnonzero((f > 77.2) & (f < 77.7))
    assert rows.size >= 8
    a = b.amplitude(1)
    half = b.amplitude()
    for i in rows[:: max(1, rows.size // 6)]:
        s = _solve(beam, b.omega[i], 63, b.point(i))
        if s is None:
            continue
        change = max(
            abs(s.amplitude(1) - a[i]) / max(a[i], rest),
            abs(s.amplitude() - half[i]) / max(half[i], rest),
        )
        est = b.truncation_error[i]
        assert change / 2.0 <= est <= 30.0 * change + 1e-3, (f[i], est, change)
