"""A corner (a kink of the branch at a contact transition) taken by the
curve rule: a step across it that the rule would shorten below the corner
floor (CORNER_FLOOR min_step) was accepted as it was, whatever its error;
it is now tried again at the floor (examples/gallery/fe_matrices.py warned
"estimated curve error 0.00029 on 2 of 961 intervals" at such a kink)."""

import warnings

import numpy as np

import hbmfric as hf

N, K_SPRING, MASS = 30, 2.0e4, 0.05
#: the kink: the slope of a₁(Ω) at the tip drops from 7.7e-4 to 3.1e-4
#: m s/rad within 0.003 rad/s (at H = 45)
WINDOW = (45.79, 45.84)


def reduced_chain(n_modes=8):
    """The gallery's chain (30 masses, free end, Jenkins at the tip, forced
    at DOF 10) reduced by Craig-Bampton onto tip and drive."""
    K = (
        np.diag(np.full(N, 2 * K_SPRING))
        - np.diag(np.full(N - 1, K_SPRING), 1)
        - np.diag(np.full(N - 1, K_SPRING), -1)
    )
    K[-1, -1] = K_SPRING
    full = hf.LinearStructure(
        MASS * np.eye(N),
        K,
        modal_damping=0.01,
        dof_names={"drive": 10, "tip": N - 1},
        load={"drive": 1.0},
        contact=hf.Jenkins(stiffness=5.0e3, slip_force=1.0),
        contact_dof="tip",
    )
    w1 = 2 * np.pi * full.natural_frequencies(1)[0]
    return hf.craig_bampton(full, ["tip", "drive"], n_modes=n_modes), w1


def test_a_corner_step_over_the_tolerance_is_not_taken_as_it_is():
    """F = 1 N: on main the step across the kink (scaled length 9.4e-5,
    corner, estimate 3.8e-4, doubled as a kink) would have been shortened
    to 9.4e-6 < 1e-5 and was accepted; the straight line there is 6.6e-4
    off the fixed-Ω solutions. Now every chord near the kink is within the
    tolerance of independent fixed-Ω solves at the branch's own H, and no
    AccuracyWarning."""
    system, w1 = reduced_chain()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = hf.frf(system, 1.0, (0.5 * w1, 1.6 * w1))
    curve = [w for w in caught if "curve error" in str(w.message)]
    assert not curve, curve[0].message
    assert branch.curve_error <= 1e-4
    a = branch.amplitude(harmonic=1)
    w = branch.omega
    chords = np.flatnonzero((w[1:] >= WINDOW[0]) & (w[:-1] <= WINDOW[1]))
    assert chords.size >= 5
    worst = 0.0
    for j in chords:
        for f in (0.25, 0.5, 0.75):
            omega = w[j] + f * (w[j + 1] - w[j])
            sol = hf.periodic_solution(
                system, 1.0, omega, harmonics=int(branch.point_harmonics[j])
            )
            assert sol.converged
            ref = sol.amplitude(harmonic=1)
            line = a[j] + f * (a[j + 1] - a[j])
            worst = max(worst, abs(line - ref) / ref)
    assert worst <= 1e-4, worst


def test_points_solved_again_by_the_final_pass_get_their_own_tangent():
    """harmonics='auto' solves points over the tolerance again one rung
    higher after the run (``AdaptiveContinuation.settle``); their stored
    tangent was the old level's, zero-padded. On the chain reduced to 10
    modes at F = 2 N, two such points near 32.64 rad/s (H 31 -> 45) carried
    slopes da₁/dΩ 19 and 9 times off the new level's branch, and the curve
    estimate read 1.1e-4 (an AccuracyWarning) where the chords are within
    1.7e-5 of fixed-Ω solves. Every tangent slope there against central
    differences of fixed-Ω solutions at the point's own H."""
    system, w1 = reduced_chain(n_modes=10)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = hf.frf(system, 2.0, (0.5 * w1, 1.6 * w1))
    curve = [w for w in caught if "curve error" in str(w.message)]
    assert not curve, curve[0].message
    n = branch.n_points
    n_dof, n_coef = branch.coefficients.shape[1:]
    dc = branch.tangents[:, :-1].reshape(n, n_dof, n_coef)[:, 0, :2]
    x = branch.coefficients[:, 0, :2]
    slope = np.sum(x * dc, axis=1) / np.hypot(x[:, 0], x[:, 1]) / branch.tangents[:, -1]
    h = 1e-5
    for j in np.flatnonzero((branch.omega > 32.61) & (branch.omega < 32.66)):
        harmonics = int(branch.point_harmonics[j])
        up, down = (
            hf.periodic_solution(
                system, 2.0, branch.omega[j] + d, harmonics=harmonics
            ).amplitude(harmonic=1)
            for d in (h, -h)
        )
        fd = (up - down) / (2 * h)
        assert abs(slope[j] - fd) <= 1e-3 * abs(fd) + 1e-8, (j, slope[j], fd)


def test_beam_at_1n_no_false_curve_warning():
    """The paper beam at Fn = 1 N (defaults) warned "estimated curve error
    0.00011" between 121.1 and 122.6 rad/s, where the straight line is
    2.3e-5 off the exact solution: the points there were solved again at
    H = 31 and kept the tangents of their first level. Now no warning, and
    the estimates of the largest chords match the exact midpoint errors."""
    from hbmfric.paper.beam import HZ, paper_beam, paper_calibration
    from hbmfric.validation import exact_periodic_solution

    system = paper_beam(1.0, paper_calibration())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = hf.frf(system, 2.0, (15.0 * HZ, 110.0 * HZ))
    curve = [w for w in caught if "curve error" in str(w.message)]
    assert not curve, curve[0].message
    a = branch.amplitude(harmonic=1)
    for j in np.argsort(branch.curve_errors)[-3:]:
        omega = 0.5 * (branch.omega[j] + branch.omega[j + 1])
        exact = exact_periodic_solution(system, 2.0, omega).amplitude(harmonic=1)
        error = abs(0.5 * (a[j] + a[j + 1]) / exact - 1)
        assert error <= 1e-4
        assert 0.5 * error <= branch.curve_errors[j] <= 2.0 * error + 1e-6
