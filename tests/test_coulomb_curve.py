"""The curve rule for a rigid Coulomb contact (DLFT, issue 18): what a user
draws of an ``frf`` branch at default settings (straight lines between the
points) is within ``curve_tolerance`` of the response, or the branch says
where it is not.

References, independent of the branch's step control: Den Hartog's exact
non-stop steady state of the Coulomb oscillator (``test_coulomb``), and for
the three-mass chain the harmonic balance solved afresh at each chord's
middle (:func:`hbmfric.periodic_solution` at the higher ``H`` of its ends),
which checks the chord against the branch it joins (the points' own
truncation error is estimated and warned about separately,
``Branch.truncation_error``)."""

import warnings

import numpy as np
import pytest
from test_coulomb import den_hartog_measures, is_non_stop

import hbmfric as hf

TOL = 1e-4


def _chain(law):
    """A new user's chain: three 1 kg masses on 1000 N/m springs from
    ground, 1 % modal damping, forced at the first, the contact to ground
    at the third."""
    K = 1000.0 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    return hf.LinearStructure(
        np.eye(3), K, modal_damping=0.01, contact=law, contact_dof=2, load={0: 1.0}
    )


def _frf(system, force, omega_range):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = hf.frf(system, force, omega_range)
    return branch, [str(w.message) for w in caught]


def _claimed(branch, i):
    """Whether the branch claims the chord ``i`` within the tolerance: its
    curve estimate and the truncation estimates of both ends are."""
    trunc = branch.truncation_error
    ends = 0.0 if trunc is None else max(trunc[i], trunc[i + 1])
    return branch.curve_errors[i] <= TOL and ends <= TOL


def test_coulomb_oscillator_curve_against_den_hartog():
    """F_s/P = 0.3, 1 % damping, 0.3-3 rad/s at defaults: at the middle of
    every chord in the non-stop regime the straight line is within 1e-4
    of Den Hartog's first harmonic wherever the branch claims it (both
    ends' truncation estimates and the chord's estimate within 1e-4), and
    the chords estimated within 1e-4 cover all but 1 % of that regime's
    width. With the curve rule off
    for Coulomb (before), 81 of 591 chords were estimated above 1e-4 (up to
    1.6e-2 near the resonance)."""
    c, fs = 0.02, 0.3
    branch, messages = _frf(
        hf.Oscillator(1.0, c, 1.0, hf.Coulomb(slip_force=fs)), 1.0, (0.3, 3.0)
    )
    assert branch.stop_reason.startswith("end")
    a = branch.amplitude(harmonic=1)
    w = branch.omega
    total = drawn = 0.0
    worst = 0.0
    for i in range(w.size - 1):
        mid = 0.5 * (w[i] + w[i + 1])
        if not all(is_non_stop(c, fs, 1.0, x) for x in (w[i], mid, w[i + 1])):
            continue
        width = w[i + 1] - w[i]
        total += width
        if branch.curve_errors[i] <= TOL:
            drawn += width
        if _claimed(branch, i):
            exact = den_hartog_measures(c, fs, 1.0, mid)[1]
            worst = max(worst, abs(0.5 * (a[i] + a[i + 1]) / exact - 1.0))
    assert total > 2.0
    assert drawn >= 0.99 * total, (drawn, total)
    assert worst <= TOL, worst
    # the points the top of the ladder cannot bring within the tolerance
    # (near the stop regime) are warned about
    if np.nanmax(branch.truncation_error) > TOL:
        assert any("truncation error" in m for m in messages)
    # where the branch's own curve estimate exceeds the tolerance, it says so
    if branch.curve_error > TOL:
        assert any("curve error" in m for m in messages)


@pytest.mark.slow
def test_chain_curve_against_chord_middles():
    """The chain with ``hf.Coulomb(slip_force=1)``, 5 N, 8-25 rad/s at
    defaults (condensed, adaptive H): at the middle of every fourth chord
    and of the 30 chords with the largest estimates, the straight line is
    within 1e-4 of the harmonic balance solved there wherever the branch
    claims it (see the other test), within 2e-4 wherever the chord's
    estimate is within 1e-4; at most 2 % of the chords are estimated above 1e-4 (the
    stick-phase kinks), and then the branch warns. Before (curve rule off
    for Coulomb): 741 points, 70 chords estimated above 1e-4, up to 9.4e-3
    at 8-8.3 rad/s."""
    system = _chain(hf.Coulomb(slip_force=1.0))
    branch, messages = _frf(system, 5.0, (8.0, 25.0))
    assert branch.stop_reason.startswith("end")
    est = np.nan_to_num(branch.curve_errors)
    over = int(np.sum(est > TOL))
    assert over <= 0.02 * est.size, (over, est.size)
    if over:
        assert any("curve error" in m for m in messages)
    a = branch.amplitude(harmonic=1)
    w, H = branch.omega, branch.point_harmonics
    chosen = set(range(0, est.size, 4)) | set(np.argsort(est)[-30:].tolist())
    worst = worst_claimed = 0.0
    checked = 0
    for i in sorted(chosen):
        if est[i] > TOL:
            continue
        mid = 0.5 * (w[i] + w[i + 1])
        sol = hf.periodic_solution(system, 5.0, mid, harmonics=int(max(H[i], H[i + 1])))
        if not sol.converged:
            continue
        checked += 1
        ref = sol.amplitude(harmonic=1)
        error = abs(0.5 * (a[i] + a[i + 1]) - ref) / min(a[i], a[i + 1])
        worst = max(worst, error)
        if _claimed(branch, i):
            worst_claimed = max(worst_claimed, error)
    assert checked >= 0.9 * len(chosen) - over
    # where the branch claims the drawn curve (chord and points within the
    # tolerance); elsewhere the points are warned about and the chord's own
    # estimate is within 2x (measured 1.3e-4 against an estimate <= 1e-4 at
    # 8-11 rad/s, where the points are 5e-3 off at H = 63)
    assert worst_claimed <= TOL, worst_claimed
    assert worst <= 2.0 * TOL, worst
