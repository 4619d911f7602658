"""The straight line between two points at different harmonic levels
(``harmonics="auto"``): its estimate (``Branch.curve_errors``) against
fixed-frequency solves at a high ``H`` (issue 18, stop 31).

Across such a join the estimate compares the tangents of two truncations.
Where the final pass had raised single points near a contact transition
(the README's several-contacts example, 27.96-27.97 rad/s: levels 5, 5, 7,
5, 7), an H = 5 point between two H = 7 points had a slope 1.1-1.2 times
theirs, and the estimate read 1.2e-4, a false ``AccuracyWarning``, where
the line is 6.0e-5 off solves at H = 31. The lower end of a join whose
estimate exceeds ``curve_tolerance`` is now solved at the other end's
level (``AdaptiveContinuation.join_levels``).
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf

H_TRUE = 31  # the truth (63 where an end is at H >= 21)
INSTANTS = 5  # fixed-frequency solves inside each interval


def readme_structure() -> hf.LinearStructure:
    """The README's several-contacts example (as written there)."""
    law = hf.Jenkins(stiffness=500.0, slip_force=2.0)
    element = hf.Contact2D(500.0, 2e3, friction_coefficient=0.3, preload=5.0)
    return hf.LinearStructure(
        np.eye(4),
        1e3 * (2 * np.eye(4) - np.eye(4, k=1) - np.eye(4, k=-1)),
        modal_damping=0.01,
        load={0: 1.0},
        static_load={3: 5.0},
        contacts=[
            hf.Contact(law, 1),
            hf.Contact(law, 1, other=2),
            hf.Contact(element, 2, normal=3),
        ],
    )


def line_distances(
    system, branch: hf.Branch, i: int, instants: int = INSTANTS
) -> tuple[float, float]:
    """Distances of the straight line between points ``i`` and ``i + 1``
    (first-harmonic amplitude of the contact DOF against Ω) from
    fixed-frequency solves at ``instants`` evenly spaced pulsations inside
    the interval (H = 31, 63 where an end is at H >= 21), relative to the
    solved amplitude: (whole, chord). The chord's is the line's less the
    straight line between the ends' own errors (solved at the ends too),
    which the points' truncation estimates carry: what the estimate of
    ``Branch.curve_errors`` measures."""
    h = 63 if int(branch.point_harmonics[i : i + 2].max()) >= 21 else H_TRUE
    a = branch.amplitude(harmonic=1)
    taus = np.arange(instants + 2) / (instants + 1)
    dev, true = np.empty(taus.size), np.empty(taus.size)
    for k, tau in enumerate(taus):
        w = branch.omega[i] + tau * (branch.omega[i + 1] - branch.omega[i])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.AccuracyWarning)
            sol = hf.periodic_solution(
                system,
                branch.force,
                w,
                h,
                initial_guess=branch.point(i if tau <= 0.5 else i + 1),
                on_failure="raise",
            )
        true[k] = sol.amplitude(harmonic=1)
        dev[k] = a[i] + tau * (a[i + 1] - a[i]) - true[k]
    chord = dev - ((1.0 - taus) * dev[0] + taus * dev[-1])
    inside = slice(1, -1)
    whole = float(np.max(np.abs(dev[inside]) / true[inside]))
    return whole, float(np.max(np.abs(chord[inside]) / true[inside]))


def check_join(est: float, whole: float, tol: float) -> None:
    """The estimate on one join against the line's whole distance from the
    solves: never more than 2x below it where it exceeds half the tolerance
    (no missed warning), and never above twice it or twice half the
    tolerance (no false warning: over the tolerance only where the line is
    more than half of it off)."""
    if whole > 0.5 * tol:
        assert est >= 0.5 * whole, (est, whole)
    assert est <= 2.0 * max(whole, 0.5 * tol), (est, whole)


@pytest.fixture(scope="module")
def readme_run() -> tuple[hf.LinearStructure, hf.Branch, list]:
    """The README example's branch at defaults and its warnings."""
    system = readme_structure()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        b = hf.frf(system, 1.0, (5.0, 60.0))
    return system, b, [str(w.message) for w in caught]


def test_readme_several_contacts_no_false_curve_alarm(readme_run):
    """No curve warning on the README's example, and the estimate against
    fixed-frequency solves (:func:`check_join`) on the level joins where
    the alarm was (27.9-28.0 rad/s; every join: the stress row
    tests/stress/test_stop31_level_joins.py)."""
    system, b, caught = readme_run
    curve = [w for w in caught if "curve_tolerance" in w]
    assert not curve, curve
    est = b.curve_errors
    assert np.max(est) <= b.info["curve_tolerance"]
    joins = np.flatnonzero(np.diff(b.point_harmonics) != 0)
    near = joins[(b.omega[joins] > 27.9) & (b.omega[joins] < 28.0)]
    assert near.size >= 2
    tol = b.info["curve_tolerance"]
    for i in near:
        whole, _ = line_distances(system, b, int(i))
        check_join(est[i], whole, tol)


def test_readme_several_contacts_fold_climbs(readme_run):
    """The point at the fold near 45.02 rad/s (issue 18, stop 32). Its
    estimate at H = 15 read 7.4e-3 (the normal DOF; a first-order change
    at fixed Ω, singular at a fold) and the final pass could not solve it
    with more harmonics: the higher levels' folds lie at lower Ω, so
    Newton at its Ω had nothing to converge to, and ``frf`` warned. The
    climb now corrects such a point normal to its tangent.

    Stop 34, a new machine: the point reached the ladder's top (H = 63)
    with its fixed-Ω estimate still 4.8e-4 (how near the fold a point
    lands is rounding) and ``frf`` warned. At the fold the fixed-Ω
    distance between two truncations is ill-posed: solved at the point's
    own Ω, H = 63 and H = 127 differ by 2.2e-4 (their folds lie µrad/s
    apart and the curve is vertical there), 2.25e-5 rad/s inside the fold
    by 3e-6. A fold point at the top is now estimated normal to the
    branch (``accuracy.fold_estimates``). Checked: no warning, the fold
    point's estimate within the tolerance, and its neighbours on both
    sides of the fold (where fixed-Ω solves are well posed) within the
    tolerance of fixed-frequency solves at H = 127 (an independent, finer
    discretisation) on every DOF's first harmonic."""
    system, b, caught = readme_run
    assert not caught, caught
    tol = b.info["harmonic_tolerance"]
    # the fold: the first point after 44.9 rad/s that Ω turns back at
    i = next(k for k in range(len(b) - 1) if 44.9 < b.omega[k] >= b.omega[k + 1])
    assert 45.0210 < b.omega[i] < 45.0214
    assert b.truncation_error[i] <= tol
    for k in (i - 1, i + 1):
        point = b.point(k)
        ref = hf.periodic_solution(
            system, 1.0, float(b.omega[k]), 127, initial_guess=point, on_failure="raise"
        )
        for d in range(4):
            a, a_ref = (
                point.amplitude(dof=d, harmonic=1),
                ref.amplitude(dof=d, harmonic=1),
            )
            assert abs(a - a_ref) <= tol * a_ref, (k, d, a, a_ref)
