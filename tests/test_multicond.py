"""Harmonic balance condensed onto several contact coordinates (issue 15).

References, each independent of the condensed residual:
- the full (uncondensed) harmonic balance of the same structure, solved by
  its own residual and Newton from its own linear starting guesses;
- central finite differences of the condensed residual;
- the full HBM residual evaluated at the recovered coefficients of every
  DOF;
- the single-DOF oscillator, of which uncoupled copies are the structure;
- a receptance matrix built here in plain NumPy (``B Z⁻¹ Bᵀ``).
"""

import json
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem, can_condense
from hbmfric.hbm import HBMProblem

N_DOF = 7
#: non-classical damping: the receptance from complex modes ("auto" picks
#: it) or the direct one
C_DIRECT = 0.02 * np.eye(N_DOF) + 0.01 * np.diag(np.ones(N_DOF - 1), 1)
C_DIRECT = C_DIRECT + C_DIRECT.T


def _matrices(n_dof=N_DOF):
    """A clamped-free chain with unequal masses and springs."""
    m = 1.0 + 0.1 * np.arange(n_dof)
    k = 1.0 + 0.3 * np.cos(np.arange(n_dof))
    K = np.zeros((n_dof, n_dof))
    for i in range(n_dof):
        K[i, i] += k[i]
        if i + 1 < n_dof:
            K[i, i] += k[i + 1]
            K[i, i + 1] = K[i + 1, i] = -k[i + 1]
    return np.diag(m), K


CONTACT_SETS = {
    "one relative": [hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.04), 2, 3)],
    "two": [
        hf.Contact(hf.Jenkins(stiffness=1.5, slip_force=0.05), 4),
        hf.Contact(hf.Menq.from_stiffness(stiffness=2.0, slip_force=0.06), 0, 1),
    ],
    "three": [
        hf.Contact(hf.Jenkins(stiffness=1.5, slip_force=0.05), 6),
        hf.Contact(hf.Jenkins(stiffness=0.8, slip_force=0.03), 1, 2),
        hf.Contact(hf.Iwan(stiffnesses=(1.0, 1.0), slip_forces=(0.02, 0.05)), 3, 5),
    ],
    "five": [
        hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.04), 0),
        hf.Contact(hf.Jenkins(stiffness=1.2, slip_force=0.05), 1, 2),
        hf.Contact(hf.Menq.from_stiffness(stiffness=0.9, slip_force=0.03), 2, 3),
        hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.06), 5),
        hf.Contact(hf.Jenkins(stiffness=0.7, slip_force=0.02), 4, 6),
    ],
    # sampled AFT (the modified Dahl law and the cubic spring)
    "mixed laws": [
        hf.Contact(hf.Cubic(0.5), 6),
        hf.Contact(
            hf.ModifiedDahl(beta=20.0, upper=(0.0, 0.05), lower=(0.0, -0.05)), 1, 2
        ),
        hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.03), 3, 4),
    ],
}


def _structure(contacts, receptance="modal"):
    M, K = _matrices()
    damping = (
        {"rayleigh": (0.01, 0.02)} if receptance == "modal" else {"damping": C_DIRECT}
    )
    return hf.LinearStructure(
        M, K, contacts=contacts, load={N_DOF - 1: 1.0, 2: 0.4 - 0.3j}, **damping
    )


@pytest.mark.parametrize("receptance", ["modal", "state", "direct"])
@pytest.mark.parametrize("name", list(CONTACT_SETS))
def test_condensed_matches_the_full_solve_at_fixed_frequencies(name, receptance):
    """Each solve from its own linear starting guesses: the condensed
    solution (every DOF recovered) against the full HBM, to 1e-8 of the
    largest coefficient, from stuck to slipping."""
    s = _structure(CONTACT_SETS[name], receptance)
    assert can_condense(s)
    for omega in (0.15, 0.45, 0.8, 1.3, 2.2):
        a = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=receptance)
        b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
        assert a.converged and b.converged
        scale = np.max(np.abs(b.coefficients))
        assert np.max(np.abs(a.coefficients - b.coefficients)) < 1e-8 * scale, omega


@pytest.mark.parametrize("receptance", ["modal", "state", "direct"])
def test_static_load_on_the_mean_matches_the_full_solve(receptance):
    """A constant load on two DOFs (harmonic 0 solved, condensed through
    the static receptance ``B K⁻¹ Bᵀ``): condensed against full to 1e-8
    (measured 7e-11)."""
    M, K = _matrices()
    damping = (
        {"rayleigh": (0.01, 0.02)} if receptance == "modal" else {"damping": C_DIRECT}
    )
    s = hf.LinearStructure(
        M,
        K,
        contacts=CONTACT_SETS["three"],
        load={6: 1.0},
        static_load={3: 0.02, 1: -0.01},
        **damping,
    )
    for omega in (0.3, 0.9, 1.7):
        a = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=receptance)
        b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
        assert a.harmonic_numbers[0] == 0
        scale = np.max(np.abs(b.coefficients))
        assert np.max(np.abs(a.coefficients - b.coefficients)) < 1e-8 * scale, omega


@pytest.mark.parametrize("receptance", ["modal", "state", "direct"])
def test_condensed_branch_is_the_full_branch_and_recovers_every_dof(receptance):
    """A branch through the resonances condensed onto three coordinates:
    at every point the recovered coefficients of all DOFs satisfy the full
    HBM residual; at every 5th point the full Newton, started 1 % off,
    returns to the same solution within 1e-8."""
    s = _structure(CONTACT_SETS["three"], receptance)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        branch = hf.frf(s, 0.1, (0.1, 2.5), harmonics=7, condense=receptance)
    assert branch.complete and branch.info["condensed"]
    full = HBMProblem(s, 0.1, harmonics=7, symmetry=branch.info["odd_only"])
    n = full.n_unknowns
    scale = np.max(np.abs(branch.coefficients))
    load = np.max(np.abs(full.load))
    for i, omega in enumerate(branch.omega):
        y = np.append(branch.coefficients[i].reshape(-1), omega)
        R, J, _ = full.residual(y)
        assert np.max(np.abs(R)) < 1e-8 * load, (i, omega)
        if i % 5:
            continue
        x = y.copy()
        x[:n] *= 1.01
        for _ in range(30):
            R, J, _ = full.residual(x)
            if np.max(np.abs(R)) < 1e-12 * load:
                break
            x[:n] -= np.linalg.solve(J[:, :n], R)
        assert np.max(np.abs(x[:n] - y[:n])) < 1e-8 * scale, (i, omega)


@pytest.mark.parametrize("receptance", ["modal", "state", "direct"])
@pytest.mark.parametrize("symmetry", [True, False])
def test_jacobian_against_central_differences(receptance, symmetry):
    """Stuck, slipping and mixed states (small, large and mixed amplitudes
    per coordinate), with and without the mean: the analytic Jacobian, Ω
    column included, against central differences."""
    s = _structure(CONTACT_SETS["three"], receptance)
    p = CondensedHBMProblem(
        s, 0.1, harmonics=5, symmetry=symmetry, receptance=receptance
    )
    assert p.receptance_method == receptance
    rng = np.random.default_rng(3)
    n = p.n_unknowns
    for amplitudes in ((1e-3, 1e-3, 1e-3), (1.0, 1.0, 1.0), (1e-3, 1.0, 0.05)):
        y = rng.standard_normal(n + 1)
        y[:n] *= np.repeat(amplitudes, p.n_coef)
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


@pytest.mark.parametrize("receptance", ["modal", "state", "direct"])
def test_linear_part_is_the_plain_numpy_receptance(receptance):
    """At any state, the residual minus the contact forces is
    ``G⁻¹ (q - p)`` with ``G = B Z⁻¹ Bᵀ`` and ``p = B Z⁻¹ P`` built here by
    dense complex solves."""
    s = _structure(CONTACT_SETS["two"], receptance)
    p = CondensedHBMProblem(s, 0.1, harmonics=3, symmetry=False, receptance=receptance)
    assert p.receptance_method == receptance
    M, C, K = (np.asarray(a) for a in s.matrices())
    B = np.zeros((2, N_DOF))
    B[0, 4] = 1.0
    B[1, 0], B[1, 1] = 1.0, -1.0
    omega = 0.7
    rng = np.random.default_rng(5)
    y = np.append(rng.standard_normal(p.n_unknowns), omega)
    R, _, _ = p.residual(y)
    forces = p.contact_forces(y)[0]  # (n_c, n_coef)
    P = s.load_vector(0.1).astype(complex)
    q = y[:-1].reshape(2, p.n_coef)
    for k, c in ((0, 0), (1, 1), (2, 3), (3, 5)):
        Z = K - (k * omega) ** 2 * M + 1j * k * omega * C
        G = B @ np.linalg.solve(Z, B.T)
        pk = B @ np.linalg.solve(Z, P) if k == 1 else np.zeros(2)
        qk = q[:, c] if k == 0 else q[:, c] - 1j * q[:, c + 1]
        r = np.linalg.solve(G, qk - pk)
        fk = forces[:, c] if k == 0 else forces[:, c] - 1j * forces[:, c + 1]
        got = R.reshape(2, p.n_coef)
        expect = r + fk
        np.testing.assert_allclose(got[:, c], expect.real, rtol=0, atol=1e-10)
        if k:
            np.testing.assert_allclose(got[:, c + 1], -expect.imag, rtol=0, atol=1e-10)


@pytest.mark.parametrize("receptance", ["modal", "direct"])
def test_one_coordinate_to_ground_reproduces_the_single_dof_path(receptance):
    """One contact to ground keeps the single-DOF kernel path (its residual
    is bit-for-bit that of the release before, checked when this was
    built); the coordinate path run on the same contact (forced here)
    gives the same residual and Jacobian to rounding: two implementations
    of one formula."""
    import copy

    M, K = _matrices()
    damping = (
        {"rayleigh": (0.01, 0.02)} if receptance == "modal" else {"damping": C_DIRECT}
    )
    law = hf.Menq.from_stiffness(stiffness=2.0, slip_force=0.06)
    s = hf.LinearStructure(M, K, contact=law, contact_dof=3, load={6: 1.0}, **damping)
    single = CondensedHBMProblem(s, 0.1, harmonics=5, symmetry=False)
    assert not single.multi and single.kernel_problem.law_codes.size == 0
    general = copy.copy(single)
    general.multi = True
    general.kernel_problem = single.full_kernel_problem
    general._condense()
    assert general.kernel_problem.law_codes.size == 1
    rng = np.random.default_rng(7)
    for amplitude in (1e-3, 0.2):
        y = np.append(amplitude * rng.standard_normal(single.n_unknowns), 0.8)
        R1, J1, s1 = single.residual(y)
        R2, J2, s2 = general.residual(y)
        assert s1 == s2
        np.testing.assert_allclose(R2, R1, rtol=0, atol=1e-12 * np.max(np.abs(R1)))
        np.testing.assert_allclose(J2, J1, rtol=0, atol=1e-12 * np.max(np.abs(J1)))


def test_uncoupled_copies_of_the_oscillator_are_the_oscillator():
    """Three uncoupled copies of the oscillator, each with its own contact
    to ground, condensed onto the three coordinates: each DOF is the
    single-DOF oscillator's solution (another residual, no condensation),
    to the Newton tolerance (1e-10 of the load; measured 7e-11 of the
    amplitude)."""
    m, c, k = 1.0, 0.04, 1.0
    law = hf.Jenkins(stiffness=1.5, slip_force=0.2)
    structure = hf.LinearStructure(
        m * np.eye(3),
        k * np.eye(3),
        c * np.eye(3),
        contacts=[hf.Contact(law, i) for i in range(3)],
        load={0: 1.0, 1: 1.0, 2: 1.0},
    )
    assert not can_condense(structure)  # as many coordinates as DOFs
    oscillator = hf.Oscillator(m, c, k, law)
    for omega in (0.6, 1.2, 1.6, 2.4):
        a = hf.periodic_solution(structure, 0.5, omega, harmonics=9, condense="modal")
        b = hf.periodic_solution(oscillator, 0.5, omega, harmonics=9)
        for dof in range(3):
            scale = np.max(np.abs(b.coefficients))
            np.testing.assert_allclose(
                a.coefficients[dof], b.coefficients[0], rtol=0, atol=1e-9 * scale
            )


def test_condensed_frf_of_several_contacts_estimates_its_accuracy():
    """``hf.frf`` with adaptive harmonics and ``condense=True`` condenses a
    chain with five contacts, covers the range and gives a finite
    truncation estimate at every point (the accuracy rules watch the first
    coordinate). Over 0.1-2.5 rad/s: 2434 points, 15 s condensed, 64 s
    full; here a part of it. (Several contacts are condensed by default
    again since stop 24: see ``condensed_by_default``.)"""
    s = _structure(CONTACT_SETS["five"])
    assert hf.frf(s, 0.1, (0.3, 0.35), 3).info["condensed"]
    branch = hf.frf(s, 0.1, (0.3, 0.6), harmonic_tolerance=1e-3, condense=True)
    assert branch.complete and branch.info["condensed"]
    assert np.all(np.isfinite(branch.truncation_error))
    assert branch.coefficients.shape[1] == N_DOF


def test_truncation_estimate_is_the_full_problems():
    """The first contact acts on DOF 0 to ground, so the first coordinate
    (which the condensed accuracy rules watch) is the DOF the full problem
    watches: the per-point truncation estimates of both layouts at the same
    solutions agree (they once read the coordinates as one DOF: 1e3
    against 6e-3)."""
    from hbmfric.continuation.accuracy import truncation_errors

    s = _structure(CONTACT_SETS["five"])
    condensed = CondensedHBMProblem(s, 0.1, harmonics=7)
    full = HBMProblem(s, 0.1, harmonics=7)
    rows_c, rows_f = [], []
    for omega in (0.3, 0.6, 1.0, 1.5, 2.2):
        X = hf.periodic_solution(s, 0.1, omega, harmonics=7).coefficients
        rows_c.append(np.append(condensed.unknowns_from_full(X), omega))
        rows_f.append(np.append(full.unknowns_from_full(X), omega))
    a = truncation_errors(condensed, np.array(rows_c))
    b = truncation_errors(full, np.array(rows_f))
    assert np.all(b > 0.0)
    np.testing.assert_allclose(a, b, rtol=1e-6)


def test_what_is_not_condensed_is_refused_or_solved_in_full():
    law = hf.Jenkins(stiffness=1.0, slip_force=0.05)
    # dependent coordinates: x0, x1 and x0 - x1
    loop = _structure([hf.Contact(law, 0), hf.Contact(law, 1), hf.Contact(law, 0, 1)])
    assert not can_condense(loop)
    with pytest.raises(ValueError, match="not independent.*condense=False"):
        CondensedHBMProblem(loop, 0.1, harmonics=3)
    # the same pair twice
    twice = _structure([hf.Contact(law, 2, 3), hf.Contact(law, 3, 2)])
    with pytest.raises(ValueError, match="not independent"):
        hf.periodic_solution(twice, 0.1, 0.5, harmonics=3, condense=True)
    # a loop of contacts is still solved, uncondensed, by default
    sol = hf.periodic_solution(loop, 0.1, 0.5, harmonics=3)
    assert sol.converged
    element = hf.Contact2D(
        tangential_stiffness=1.0,
        normal_stiffness=2.0,
        friction_coefficient=0.3,
        preload=0.5,
    )
    # a 2D element is condensed onto two coordinates
    # (tests/test_condensed_contact2d.py), unless they repeat another
    # contact's coordinate
    two_d = _structure([hf.Contact(element, 2, normal=3), hf.Contact(law, 3)])
    assert not can_condense(two_d)
    with pytest.raises(ValueError, match="not independent"):
        CondensedHBMProblem(two_d, 0.1, harmonics=3)


def test_condensed_coordinate_kernels_compile_once():
    """A fresh process: problems with other numbers of contacts, DOFs,
    laws, harmonics and receptances add no kernel signature after the
    first batch (one compilation of the condensed kernels per problem type
    serves every contact set: the general type of mixed laws, and the
    Jenkins family's type of Jenkins contacts alone)."""
    code = textwrap.dedent(
        """
        import json, sys, warnings
        import numpy as np
        import hbmfric as hf
        from hbmfric.kernels.residuals import condensed
        from hbmfric.kernels.steps import newton
        sys.path.insert(0, TESTS_DIR)
        import test_multicond as t

        def counts():
            out = {}
            for mod in (condensed, newton):
                for name in dir(mod):
                    obj = getattr(mod, name)
                    if hasattr(obj, "signatures") and obj.__module__ == mod.__name__:
                        out[mod.__name__ + "." + name] = len(obj.signatures)
            return out

        def runs(names, H):
            for name in names:
                for rec in ("modal", "direct"):
                    s = t._structure(t.CONTACT_SETS[name], rec)
                    hf.periodic_solution(s, 0.1, 0.8, H, condense=rec)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                hf.frf(t._structure(t.CONTACT_SETS[names[0]]), 0.1, (0.5, 0.7), H)

        runs(["two", "one relative"], 5)
        first = counts()
        runs(["five", "one relative"], 9)
        print(json.dumps({"first": first, "second": counts()}))
        """
    ).replace("TESTS_DIR", repr(str(Path(__file__).parent)))
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["second"] == report["first"]
    # one per problem type: CondensedProblem (Jenkins and Menq contacts) and
    # CondensedJenkinsProblem (Jenkins contacts alone)
    assert (
        report["first"]["hbmfric.kernels.residuals.condensed.condensed_residual"] == 2
    )


def test_condensed_tangents_are_unit_on_the_contact_dof():
    """``Branch.tangents`` of a branch condensed onto several coordinates
    are unit tangents in the metric the branch measures its arc length in
    (``Branch._arc_metric``: the contact DOF and Ω, scaled by
    ``info["amplitude_scale"]`` and the range width), as documented for a
    condensed branch; the chord estimates of ``Branch.curve_errors``
    multiply them by lengths measured there. Reference: the chords between
    neighbouring points, normalised in that metric, point along them.
    (They were normalised on all the coordinates: norms 0.72-1.0 here.)"""
    s = _structure(CONTACT_SETS["two"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)  # H = 5
        branch = hf.frf(s, 0.1, (0.3, 0.6), harmonics=5, condense=True)
    scale = branch.info["amplitude_scale"]
    width = 0.3
    dof = s.contact_dof
    n_dof, n_coef = branch.coefficients.shape[1:]
    t = branch.tangents
    tx = t[:, :-1].reshape(-1, n_dof, n_coef)[:, dof] / scale
    tw = t[:, -1] / width
    norms = np.hypot(np.linalg.norm(tx, axis=1), tw)
    np.testing.assert_allclose(norms, 1.0, rtol=1e-12)
    dx = np.diff(branch.coefficients[:, dof], axis=0) / scale
    dw = np.diff(branch.omega) / width
    length = np.hypot(np.linalg.norm(dx, axis=1), dw)
    chord = np.column_stack([dx, dw]) / length[:, None]
    mid = 0.5 * (np.column_stack([tx, tw])[:-1] + np.column_stack([tx, tw])[1:])
    off = np.linalg.norm(chord - mid, axis=1)
    assert np.median(off) < 0.05, np.median(off)
