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


def reduced_chain():
    """The gallery's chain (30 masses, free end, Jenkins at the tip, forced
    at DOF 10) reduced by Craig-Bampton onto tip and drive, 8 modes."""
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
    return hf.craig_bampton(full, ["tip", "drive"], n_modes=8), w1


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
