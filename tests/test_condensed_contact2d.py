"""Harmonic balance condensed onto the coordinates of 2D contact elements
(:class:`hbmfric.Contact2D`, issue 15): each element gives two contact
coordinates, its tangential and its normal relative displacement.

References, each independent of the condensed residual:
- the full (uncondensed) harmonic balance of the same structure, solved by
  its own residual (its own 2D dispatch) from its own starting guesses;
- the full HBM residual evaluated at the coefficients of every DOF
  recovered from a condensed branch;
- central finite differences of the condensed residual;
- the normal force ``n0 + k_n v(t)`` synthesised here from the full
  solution (the cases must separate: that is what the element adds).
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import (
    CondensedHBMProblem,
    can_condense,
    condensed_by_default,
)
from hbmfric.continuation.accuracy import normal_outputs, watched_truncation_errors
from hbmfric.hbm import HBMProblem

N_DOF = 6
KN = 2.0
N0 = 0.05
ELEMENT = hf.Contact2D(
    tangential_stiffness=1.0,
    normal_stiffness=KN,
    friction_coefficient=0.3,
    preload=N0,
)
JENKINS = hf.Jenkins(stiffness=1.0, slip_force=0.04)
#: non-classical damping: complex modes ("auto") or direct solves
C_DIRECT = 0.02 * np.eye(N_DOF) + 0.01 * np.diag(np.ones(N_DOF - 1), 1)
C_DIRECT = C_DIRECT + C_DIRECT.T

#: contacts and the (DOF, other DOF) of the element's normal coordinate
CASES = {
    "alone to ground": ([hf.Contact(ELEMENT, 2, normal=4)], (4, -1)),
    "to ground beside Jenkins": (
        [hf.Contact(ELEMENT, 2, normal=4), hf.Contact(JENKINS, 5)],
        (4, -1),
    ),
    "between DOFs beside Jenkins": (
        [hf.Contact(ELEMENT, 1, 2, normal=3, normal_other=4), hf.Contact(JENKINS, 5)],
        (3, 4),
    ),
}
OMEGAS = (0.2, 0.5, 0.8, 1.1, 1.5, 2.2)


def _matrices(n_dof=N_DOF, clamped=True):
    """A clamped-free chain with unequal masses and springs (free-free,
    with a rigid-body mode, when not ``clamped``)."""
    m = 1.0 + 0.1 * np.arange(n_dof)
    k = 1.0 + 0.3 * np.cos(np.arange(n_dof))
    if not clamped:
        k[0] = 0.0
    K = np.zeros((n_dof, n_dof))
    for i in range(n_dof):
        K[i, i] += k[i]
        if i + 1 < n_dof:
            K[i, i] += k[i + 1]
            K[i, i + 1] = K[i + 1, i] = -k[i + 1]
    return np.diag(m), K


def _structure(contacts, receptance="modal", n_dof=N_DOF, clamped=True):
    M, K = _matrices(n_dof, clamped)
    damping = (
        {"rayleigh": (0.01, 0.02)}
        if receptance == "modal"
        else {"damping": C_DIRECT[:n_dof, :n_dof]}
    )
    return hf.LinearStructure(
        M,
        K,
        contacts=contacts,
        load={n_dof - 1: 1.0, 4: 0.5, 2: 0.3 - 0.2j},
        static_load={4: 0.01},
        **damping,
    )


def _normal_force_range(solution, pair):
    """Least and largest ``n0 + k_n v(t)`` over the period, ``v`` the
    normal relative displacement synthesised here from the coefficients."""
    X = solution.coefficients
    v = X[pair[0]] - (X[pair[1]] if pair[1] >= 0 else 0.0)
    t = np.linspace(0.0, 2.0 * np.pi, 512, endpoint=False)
    signal = np.zeros_like(t)
    c = 0
    for k in solution.harmonic_numbers:
        if k == 0:
            signal += v[c]
            c += 1
        else:
            signal += v[c] * np.cos(k * t) + v[c + 1] * np.sin(k * t)
            c += 2
    n = N0 + KN * signal
    return float(n.min()), float(n.max())


@pytest.mark.parametrize("receptance", ["modal", "state", "direct"])
@pytest.mark.parametrize("name", list(CASES))
def test_condensed_matches_the_full_solve_at_fixed_pulsations(name, receptance):
    """Each solve from its own starting guesses: every DOF recovered from
    the condensed solution against the full HBM to 1e-8 of the largest
    coefficient (measured at most 7e-11), the element separating over part
    of the period at each pulsation (synthesised from the full solution)
    and the preload giving a mean."""
    contacts, pair = CASES[name]
    s = _structure(contacts, receptance)
    assert can_condense(s)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        for omega in OMEGAS:
            a = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=receptance)
            b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
            assert a.converged and b.converged
            assert a.harmonic_numbers[0] == 0
            scale = np.max(np.abs(b.coefficients))
            err = np.max(np.abs(a.coefficients - b.coefficients))
            assert err < 1e-8 * scale, (omega, err / scale)
            low, high = _normal_force_range(b, pair)
            assert low < 0.0 < high, omega


@pytest.mark.parametrize("receptance", ["state", "direct"])
def test_free_free_chain_held_by_the_element(receptance):
    """A free-free chain (singular stiffness: no static receptance) held by
    the 2D element and a Jenkins contact, the mean solved: condensed with
    the contacts' stiffnesses moved into the structure
    (``CondensedHBMProblem.shift``), against the full solve to 1e-8 of the
    largest coefficient at 3 pulsations, the element separating."""
    contacts, pair = CASES["to ground beside Jenkins"]
    s = _structure(contacts, receptance, clamped=False)
    assert can_condense(s)
    p = CondensedHBMProblem(s, 0.1, harmonics=5, receptance=receptance)
    np.testing.assert_array_equal(p.shift, [1.0, KN, 1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        for omega in OMEGAS[::2]:
            a = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=receptance)
            b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
            assert a.converged and b.converged
            scale = np.max(np.abs(b.coefficients))
            err = np.max(np.abs(a.coefficients - b.coefficients))
            assert err < 1e-8 * scale, (omega, err / scale)
            low, high = _normal_force_range(b, pair)
            assert low < 0.0 < high, omega


def test_condensed_by_default():
    """``condense=None`` condenses a structure with a 2D element (classical
    damping: modal sums) and gives the full solution."""
    s = _structure(CASES["to ground beside Jenkins"][0])
    problem = CondensedHBMProblem(s, 0.1, harmonics=5)
    assert problem.n_coordinates == 3 and problem.receptance_method == "modal"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(s, 0.1, (0.7, 0.9), harmonics=5)
        assert branch.info["condensed"]
        b = hf.periodic_solution(s, 0.1, 0.8, harmonics=5, condense=False)
    a = hf.periodic_solution(s, 0.1, 0.8, harmonics=5)
    scale = np.max(np.abs(b.coefficients))
    assert np.max(np.abs(a.coefficients - b.coefficients)) < 1e-8 * scale


@pytest.mark.parametrize("receptance", ["modal", "direct"])
def test_condensed_branch_solves_the_full_residual(receptance):
    """A condensed branch over the first resonance (the element separating):
    at every point the recovered coefficients of every DOF satisfy the full
    HBM residual to 1e-8 of the load; at the branch's peak (largest first
    harmonic of the drawn DOF) the full solve gives the recovered
    coefficients to 1e-8. (Over 0.1-2.5 rad/s the branch has 5000 points,
    condensed or full; with the non-classical damping neither covers it
    within the step budget.)"""
    contacts, _ = CASES["between DOFs beside Jenkins"]
    s = _structure(contacts, receptance)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(s, 0.1, (0.17, 0.26), harmonics=5, condense=receptance)
        assert branch.complete and branch.info["condensed"]
        full = HBMProblem(s, 0.1, harmonics=5, symmetry=False)
        assert np.array_equal(full.harmonic_numbers, branch.harmonic_numbers)
        load = np.max(np.abs(full.load))
        for i, omega in enumerate(branch.omega):
            y = np.append(branch.coefficients[i].reshape(-1), omega)
            R, _, state = full.residual(y)
            assert state >= 0
            assert np.max(np.abs(R)) < 1e-8 * load, (i, omega)
        peak = int(np.argmax(branch.amplitude()))
        sol = hf.periodic_solution(
            s, 0.1, float(branch.omega[peak]), harmonics=5, condense=False
        )
    scale = np.max(np.abs(sol.coefficients))
    err = np.max(np.abs(sol.coefficients - branch.coefficients[peak]))
    assert err < 1e-8 * scale, err / scale


@pytest.mark.parametrize("receptance", ["modal", "state", "direct"])
def test_jacobian_against_central_differences(receptance):
    """Closed and stuck, closed and slipping, separating: the analytic
    Jacobian of the condensed residual (the element's coupled tangential
    and normal blocks, the Ω column) against central differences."""
    contacts, _ = CASES["between DOFs beside Jenkins"]
    s = _structure(contacts, receptance)
    p = CondensedHBMProblem(s, 0.1, harmonics=3, receptance=receptance)
    assert p.receptance_method == receptance and p.n_coordinates == 3
    n_coef = p.n_coef
    rng = np.random.default_rng(7)
    n = p.n_unknowns
    # amplitudes of (tangential, normal, Jenkins); the normal mean +0.01
    # keeps the element closed, small normal amplitudes keep it closed
    for amplitudes in ((1e-3, 1e-3, 1e-3), (1.0, 1e-3, 1.0), (0.2, 0.2, 0.05)):
        y = rng.standard_normal(n + 1)
        y[:n] *= np.repeat(amplitudes, n_coef)
        y[n_coef] = 0.01
        y[n] = 0.9
        R, J, state = p.residual(y)
        assert state >= 0
        fd = np.empty_like(J)
        for i in range(n + 1):
            h = 1e-6 * max(1.0, abs(y[i]))
            up, down = y.copy(), y.copy()
            up[i] += h
            down[i] -= h
            fd[:, i] = (p.residual(up)[0] - p.residual(down)[0]) / (2.0 * h)
        assert np.max(np.abs(fd - J)) < 1e-6 * np.max(np.abs(J)), amplitudes
        # the element's normal block couples into the tangential rows
        assert np.max(np.abs(J[:n_coef, n_coef : 2 * n_coef])) > 0.0 or (
            amplitudes[0] < 1e-2
        )


def test_normal_coordinate_is_watched_as_in_full():
    """The final estimates watch each element's normal coordinate: the
    condensed problem's normal output is that coordinate, and the watched
    truncation estimates at the same solutions equal the full problem's
    (which watches the contact DOF and the normal relative displacement)."""
    contacts, _ = CASES["to ground beside Jenkins"]
    s = _structure(contacts)
    condensed = CondensedHBMProblem(s, 0.1, harmonics=7)
    full = HBMProblem(s, 0.1, harmonics=7)
    (w,) = normal_outputs(condensed)
    assert w.shape == (2, 3) and w[0, 1] == 1.0 and np.sum(np.abs(w)) == 1.0
    rows_c, rows_f = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        for omega in (0.3, 0.8, 1.5):
            X = hf.periodic_solution(s, 0.1, omega, harmonics=7).coefficients
            rows_c.append(np.append(condensed.unknowns_from_full(X), omega))
            rows_f.append(np.append(full.unknowns_from_full(X), omega))
    a = watched_truncation_errors(condensed, np.array(rows_c))
    b = watched_truncation_errors(full, np.array(rows_f))
    assert np.all(b > 0.0)
    np.testing.assert_allclose(a, b, rtol=1e-6)


def test_what_is_not_condensed_is_refused_or_solved_in_full():
    """As many coordinates as DOFs: not condensed by default; a normal
    coordinate that repeats another contact's: refused with the reason
    (solved in full by default); a 2D element without its normal DOF:
    refused when the structure is built."""
    M, K = _matrices(3)
    # 3 DOFs: the element's two coordinates and a Jenkins one
    crowded = hf.LinearStructure(
        M,
        K,
        rayleigh=(0.01, 0.02),
        contacts=[hf.Contact(ELEMENT, 0, normal=1), hf.Contact(JENKINS, 2)],
        load={2: 1.0},
    )
    assert not can_condense(crowded)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        assert not hf.frf(crowded, 0.1, (0.5, 0.55), harmonics=3).info["condensed"]
    # the normal coordinate (DOF 4 to ground) is also a Jenkins contact's
    twice = _structure([hf.Contact(ELEMENT, 2, normal=4), hf.Contact(JENKINS, 4)])
    assert not can_condense(twice)
    with pytest.raises(ValueError, match="not independent.*condense=False"):
        hf.periodic_solution(twice, 0.1, 0.5, harmonics=3, condense=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        sol = hf.periodic_solution(twice, 0.1, 0.5, harmonics=3)
    assert sol.converged
    with pytest.raises(ValueError, match="needs its normal DOF"):
        _structure([hf.Contact(ELEMENT, 2)])


@pytest.mark.slow
def test_lap_joint_contact2d_condensed_is_full():
    """The lap joint's Contact2D variant (``n_pairs = 4``, 96 DOFs; its
    stiffness singular: the beams' axial rigid-body modes, held by the
    elements): condensed by default onto its elements' coordinates,
    shifted by their stiffnesses, against the full solve at 3 pulsations
    around the first bending resonance, to 1e-8 of the largest coefficient
    (measured 3e-11)."""
    joint = hf.LapJoint(n_pairs=4)
    s = joint.structure("contact2d")
    assert condensed_by_default(s)
    p = CondensedHBMProblem(s, 36.0, harmonics=5)
    assert np.all(p.shift > 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        for f in (150.0, 162.0, 175.0):
            omega = 2.0 * np.pi * f
            a = hf.periodic_solution(s, 36.0, omega, harmonics=5)
            b = hf.periodic_solution(s, 36.0, omega, harmonics=5, condense=False)
            assert a.converged and b.converged
            scale = np.max(np.abs(b.coefficients))
            err = np.max(np.abs(a.coefficients - b.coefficients))
            assert err < 1e-8 * scale, (f, err / scale)
