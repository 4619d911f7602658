"""Structures from matrices (issue 15, first part): hf.LinearStructure, the
FE file readers and the Craig–Bampton reduction, checked against closed
forms (linear receptance), the built-in systems built independently, the
full model's eigenvalues and the time-integration reference."""

import math
import warnings

import numpy as np
import pytest
import scipy.io
import scipy.sparse

import hbmfric as hf


def chain(n=6, k=1000.0, m=0.1):
    """A fixed-free spring–mass chain, n DOFs: M = m I, K tridiagonal."""
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k
        if i + 1 < n:
            K[i, i] += k
            K[i, i + 1] = K[i + 1, i] = -k
    return m * np.eye(n), K


# --------------------------------------------------------------------------
# the linear structure against closed forms


def test_phased_loads_match_the_linear_receptance():
    """No contact, loads on two DOFs with different phases: every harmonic-
    balance amplitude equals |(K - Ω²M + iΩC)⁻¹ q| at several frequencies."""
    M, K = chain(4)
    q = np.array([1.0, 0.0, 0.5 * np.exp(-0.7j), 0.0])
    s = hf.LinearStructure(M, K, rayleigh=(2.0, 1e-5), load=q)
    C = 2.0 * M + 1e-5 * K
    for omega in (20.0, 55.0, 140.0):
        sol = hf.periodic_solution(s, 3.0, omega, harmonics=1)
        X = np.linalg.solve(K - omega**2 * M + 1j * omega * C, 3.0 * q)
        for dof in range(4):
            assert sol.amplitude(dof=dof) == pytest.approx(abs(X[dof]), rel=1e-10)
        # phase: x = Re(X e^{iΩt}) → cosine coefficient Re X, sine −Im X
        c = sol.coefficients[2]
        assert c[0] == pytest.approx(X[2].real, rel=1e-9, abs=1e-14)
        assert c[1] == pytest.approx(-X[2].imag, rel=1e-9, abs=1e-14)


def test_a_real_load_vector_stays_a_cosine_load():
    M, K = chain(3)
    s = hf.LinearStructure(M, K, modal_damping=0.02, load={0: 2.0})
    assert s.load_vector(1.5).dtype.kind == "f"
    np.testing.assert_array_equal(s.load_vector(1.5), [3.0, 0.0, 0.0])


def test_modal_and_rayleigh_damping():
    M, K = chain(5)
    zeta = [0.01, 0.02, 0.03]
    s = hf.LinearStructure(M, K, modal_damping=zeta)
    omega, phi = s.modes()
    modal = phi.T @ s.matrices()[1] @ phi
    expected = np.zeros(5)
    expected[:3] = 2.0 * np.array(zeta) * omega[:3]
    np.testing.assert_allclose(modal, np.diag(expected), atol=1e-9 * omega[-1])
    np.testing.assert_allclose(phi.T @ M @ phi, np.eye(5), atol=1e-12)
    r = hf.LinearStructure(M, K, rayleigh=(0.5, 1e-4))
    np.testing.assert_allclose(r.matrices()[1], 0.5 * M + 1e-4 * K)
    # the free-free chain (no ground spring) is allowed: K semi-definite
    K_free = K.copy()
    K_free[0, 0] -= 1000.0
    free = hf.LinearStructure(M, K_free, modal_damping=0.01)
    assert free.natural_frequencies()[0] == pytest.approx(0.0, abs=1e-3)


# --------------------------------------------------------------------------
# the same engine path as the built-in systems


def test_oscillator_as_a_linear_structure_gives_the_same_branch():
    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    osc = hf.Oscillator(1.0, 0.02, 1.0, law)
    s = hf.LinearStructure([[1.0]], [[1.0]], [[0.02]], contact=law, contact_dof=0)
    a = hf.frf(osc, 0.5, (0.5, 3.0), 15)
    b = hf.frf(s, 0.5, (0.5, 3.0), 15)
    np.testing.assert_array_equal(a.omega, b.omega)
    np.testing.assert_allclose(b.coefficients, a.coefficients, rtol=0, atol=1e-13)


def test_beam_matrices_give_the_beam_branch():
    """The cantileved beam's matrices, load and tip contact handed over as
    plain arrays: the same points as the built-in beam."""
    law = hf.Jenkins(stiffness=2e5, slip_force=1.5 * 5.0)
    beam = hf.CantileverBeam(contact=law)
    M, C, K = beam.matrices()
    s = hf.LinearStructure(
        M,
        K,
        C,
        load=beam.load_vector(1.0),
        contact=law,
        contact_dof=beam.contact_dof,
        dof_names={"tip": beam.contact_dof},
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        a = hf.frf(beam, 0.5, 2 * math.pi * np.array([15.0, 110.0]), 7)
        b = hf.frf(s, 0.5, 2 * math.pi * np.array([15.0, 110.0]), 7)
    assert len(a) == len(b)
    np.testing.assert_allclose(b.omega, a.omega, rtol=1e-12)
    np.testing.assert_allclose(
        b.amplitude(dof="tip"), a.amplitude(dof="tip"), rtol=1e-9
    )


# --------------------------------------------------------------------------
# files from FE codes


def test_matrix_files_give_the_same_structure(tmp_path):
    M, K = chain(6)
    C = 0.001 * K + 0.1 * M
    scipy.io.mmwrite(
        tmp_path / "M.mtx", scipy.sparse.coo_matrix(M), symmetry="symmetric"
    )
    scipy.io.mmwrite(tmp_path / "K.mtx", scipy.sparse.csr_matrix(K), symmetry="general")
    scipy.io.savemat(
        tmp_path / "model.mat", {"Mff": M, "Kff": scipy.sparse.csc_matrix(K), "C": C}
    )
    np.savez(tmp_path / "model.npz", mass=M, stiffness=K, damping=C)
    np.save(tmp_path / "C.npy", C)
    law = hf.Jenkins(stiffness=500.0, slip_force=2.0)
    kw = dict(contact=law, contact_dof=5, load={5: 1.0})
    ref = hf.LinearStructure(M, K, C, **kw)
    built = [
        hf.LinearStructure.from_files(
            tmp_path / "M.mtx", tmp_path / "K.mtx", tmp_path / "C.npy", **kw
        ),
        hf.LinearStructure.from_file(tmp_path / "model.mat", **kw),
        hf.LinearStructure.from_file(tmp_path / "model.npz", **kw),
        hf.LinearStructure.from_files(
            f"{tmp_path / 'model.mat'}:Mff",
            f"{tmp_path / 'model.mat'}:Kff",
            f"{tmp_path / 'model.mat'}:C",
            **kw,
        ),
    ]
    omega = 0.8 * ref.modes()[0][0]
    expected = hf.periodic_solution(ref, 3.0, omega, harmonics=9)
    for s in built:
        for a, b in zip(s.matrices(), ref.matrices(), strict=True):
            np.testing.assert_allclose(a, b, rtol=1e-15, atol=0)
        sol = hf.periodic_solution(s, 3.0, omega, harmonics=9)
        np.testing.assert_allclose(
            sol.coefficients, expected.coefficients, rtol=1e-12, atol=1e-15
        )


def test_matrix_file_errors(tmp_path):
    M, K = chain(3)
    np.savez(tmp_path / "two.npz", A=M, B=K)
    with pytest.raises(ValueError, match="holds 2 arrays"):
        hf.read_matrix(tmp_path / "two.npz")
    with pytest.raises(ValueError, match="no array 'X'"):
        hf.read_matrix(tmp_path / "two.npz", "X")
    with pytest.raises(ValueError, match="no mass matrix found"):
        hf.read_matrices(tmp_path / "two.npz")
    with pytest.raises(FileNotFoundError):
        hf.read_matrix(tmp_path / "missing.mtx")
    (tmp_path / "m.txt").write_text("1 2")
    with pytest.raises(ValueError, match="unknown matrix file type"):
        hf.read_matrix(tmp_path / "m.txt")
    out = hf.read_matrices(tmp_path / "two.npz", {"mass": "A", "stiffness": "B"})
    assert set(out) == {"mass", "stiffness"}


# --------------------------------------------------------------------------
# Craig–Bampton


def test_craig_bampton_frequencies_and_frf():
    """The beam (39 DOFs) reduced onto the tip and the forced DOF plus 10
    fixed-interface modes: the first five natural frequencies within 0.1 %
    of the full model, and the nonlinear response with the tip contact
    within 1e-3 below the reduction's cutoff."""
    law = hf.Jenkins(stiffness=2e5, slip_force=1.5)
    beam = hf.CantileverBeam(contact=law)
    M, C, K = beam.matrices()
    full = hf.LinearStructure(
        M,
        K,
        C,
        load=beam.load_vector(1.0),
        contact=law,
        contact_dof=beam.contact_dof,
        dof_names=beam.dof_names,
    )
    red = hf.craig_bampton(full, ["tip", "force"], n_modes=10)
    assert red.n_dof == 12
    f_full = full.natural_frequencies(5)
    f_red = red.with_contact(None).natural_frequencies(5)
    np.testing.assert_allclose(f_red, f_full, rtol=1e-3)
    assert red.cutoff_frequency > 5 * 110.0
    for hz in (20.0, 45.0, 80.0, 100.0):
        omega = 2 * math.pi * hz
        a = hf.periodic_solution(full, 1.0, omega, harmonics=9)
        b = hf.periodic_solution(red, 1.0, omega, harmonics=9)
        assert a.converged and b.converged
        assert b.amplitude(dof="tip") == pytest.approx(a.amplitude(dof="tip"), rel=1e-3)
        # recovery of the interior: the full displacement field
        x_full = red.expand(b.coefficients)
        assert np.max(np.abs(x_full - a.coefficients)) < 1e-3 * np.max(
            np.abs(a.coefficients)
        )


def test_craig_bampton_errors():
    M, K = chain(5)
    s = hf.LinearStructure(M, K, contact=hf.Jenkins(10.0, 1.0), contact_dof=4)
    with pytest.raises(ValueError, match="contact DOF 4 must be a boundary DOF"):
        hf.craig_bampton(s, [0], 2)
    with pytest.raises(ValueError, match="n_modes must be in"):
        hf.craig_bampton(s, [4], 9)
    with pytest.raises(ValueError, match="repeated"):
        hf.craig_bampton(s, [4, 4], 1)
    # a contact DOF the user named is named back, with what to do
    named = hf.LinearStructure(
        M, K, contact=hf.Jenkins(10.0, 1.0), contact_dof="tip", dof_names={"tip": 4}
    )
    with pytest.raises(ValueError, match=r"DOF 4 \('tip'\) must be a boundary DOF"):
        hf.craig_bampton(named, [0], 2)
    with pytest.raises(ValueError, match="does not exist"):
        hf.craig_bampton(s, [4, 7], 1)


# --------------------------------------------------------------------------
# bad input


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(mass=np.eye(3), stiffness=np.eye(2)), r"stiffness has shape \(2, 2\)"),
        (
            dict(mass=[[1.0, 0.1], [0.0, 1.0]], stiffness=np.eye(2)),
            "mass must be symmetric",
        ),
        (
            dict(mass=np.eye(2), stiffness=[[1.0, 2.0], [2.0, 1.0]]),
            "negative eigenvalue",
        ),
        (
            dict(mass=[[1.0, 0.0], [0.0, 0.0]], stiffness=np.eye(2)),
            "mass must be positive definite",
        ),
        (dict(mass=np.eye(2), stiffness=[[1.0, np.nan], [np.nan, 1.0]]), "finite"),
        (
            dict(
                mass=np.eye(2),
                stiffness=np.eye(2),
                contact_dof=2,
                contact=hf.Jenkins(1.0, 1.0),
            ),
            "does not exist",
        ),
        (
            dict(mass=np.eye(2), stiffness=np.eye(2), contact=hf.Jenkins(1.0, 1.0)),
            "contact_dof is required",
        ),
        (
            dict(mass=np.eye(2), stiffness=np.eye(2), contact_dof="tip"),
            "unknown DOF name 'tip'",
        ),
        (
            dict(
                mass=np.eye(2), stiffness=np.eye(2), rayleigh=(1, 0), modal_damping=0.1
            ),
            "at most one damping",
        ),
        (
            dict(mass=np.eye(2), stiffness=np.eye(2), load=[1.0, 2.0, 3.0]),
            r"load must have shape \(2,\)",
        ),
        (dict(mass=np.eye(2), stiffness=np.eye(2), load={5: 1.0}), "does not exist"),
        (
            dict(mass=np.eye(2), stiffness=np.eye(2), modal_damping=[0.1, 0.1, 0.1]),
            "has 3 ratios",
        ),
        (
            dict(mass=np.eye(2), stiffness=np.eye(2), contact="jenkins", contact_dof=0),
            "contact law",
        ),
        (
            dict(mass=np.eye(2), stiffness=np.eye(2), dof_names={"a": 3}),
            "does not exist",
        ),
    ],
)
def test_bad_structures_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        hf.LinearStructure(**kwargs)


def test_exact_reference_refuses_phased_loads():
    s = hf.LinearStructure(
        [[1.0]],
        [[1.0]],
        [[0.02]],
        contact=hf.Jenkins(3.0, 1.0),
        contact_dof=0,
        load=[1j],
    )
    with pytest.raises(ValueError, match="cosine loads"):
        hf.validation.exact_periodic_solution(s, 0.5, 1.2)


# --------------------------------------------------------------------------
# time-integration reference with phased loads


@pytest.mark.slow
def test_phased_loads_with_friction_against_time_integration():
    """Two DOFs, loads 90° apart, a Jenkins contact on DOF 1: the HBM
    first-harmonic amplitudes against the time-integration steady state."""
    M = np.diag([1.0, 0.5])
    K = np.array([[2.0, -1.0], [-1.0, 1.0]])
    s = hf.LinearStructure(
        M,
        K,
        modal_damping=0.02,
        load={0: 1.0, 1: -0.6j},
        contact=hf.Jenkins(stiffness=2.0, slip_force=0.4),
        contact_dof=1,
    )
    for omega in (0.6, 0.9, 1.3, 1.8):
        hbm = hf.periodic_solution(s, 0.5, omega, harmonics=31)
        ref = hf.validation.steady_state(s, 0.5, omega, steps_per_period=4096)
        for dof in (0, 1):
            assert hbm.amplitude(dof=dof) == pytest.approx(
                ref.amplitude(dof=dof), rel=2e-4
            )
