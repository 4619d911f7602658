"""Quiet failures found on the newer public paths (issue 14, last loose
ends): each used to give a wrong number without a word, or a traceback
where a clear error belongs."""

import warnings

import numpy as np
import pytest
import scipy.io

import hbmfric as hf

M = 0.05 * np.eye(3)
K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]) * 1e4


@pytest.mark.parametrize("suffix", [".npz", ".mat"])
def test_two_arrays_that_may_be_one_matrix_are_refused(tmp_path, suffix):
    """A file holding "M" and "m" read the last of them (names were looked
    up ignoring case, the later one won): twice the mass, no word. A
    Nastran export with the unconstrained and the constrained set (MGG and
    Mff) took the first found."""
    path = tmp_path / f"model{suffix}"
    arrays = {"M": M, "K": K, "m": 2 * M}
    if suffix == ".npz":
        np.savez(path, **arrays)
    else:
        # MATLAB names are case-sensitive too
        scipy.io.savemat(path, arrays)
    with pytest.raises(ValueError, match=r"several arrays .* mass .*\bM\b.*\bm\b"):
        hf.read_matrices(path)
    with pytest.raises(ValueError, match="names="):
        hf.LinearStructure.from_file(path, modal_damping=0.01, load={0: 1.0})
    out = hf.read_matrices(path, {"mass": "M"})
    np.testing.assert_array_equal(out["mass"], M)
    np.testing.assert_array_equal(out["stiffness"], K)
    nastran = tmp_path / "nastran.mat"
    scipy.io.savemat(nastran, {"MGG": np.eye(4), "KGG": np.eye(4), "Mff": M, "Kff": K})
    with pytest.raises(ValueError, match=r"MGG, Mff"):
        hf.read_matrices(nastran)


SCENE = """[system]
kind = "oscillator"
mass = 1.0
damping = 0.02
stiffness = 1.0

[contact]
law = "jenkins"
stiffness = 3.0
slip_force = 1.0

[frf]
force = 0.5
omega = [0.5, 3.0]
"""


@pytest.mark.parametrize(
    "line, match",
    [
        ("harmonics = 0", "harmonics must be a positive integer"),
        ('harmonics = "autoo"', "'autoo'"),
        ("max_step = -1.0", "max_step must be > 0"),
        ('sweep = "sideways"', "sweep must be 'up' or 'down'"),
        ("harmonic_tolerance = 2.0", "harmonic_tolerance must be <= 1"),
        ("retrace = 1", "retrace must be true or false"),
        ("n_time = 3", "n_time cannot be given"),
        ('aft = "x"', "aft must be one of"),
    ],
)
def test_bad_frf_values_of_a_scene_are_refused_without_a_traceback(
    tmp_path, capsys, line, match
):
    """``hbmfric run`` checked the keys of [frf] but not their values: a
    bad value came out of hf.frf as a traceback."""
    from hbmfric.cli import main

    path = tmp_path / "s.toml"
    path.write_text(SCENE + line + "\n")
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}: [frf]: " in err and match in err
    assert "Traceback" not in err


def test_contacts_that_cannot_go_together_are_refused_at_load(tmp_path):
    """A rigid Coulomb law among several contacts passed the scene checks
    and failed inside hf.frf with a traceback."""
    from hbmfric.scene import SceneError, load_scene

    np.savez(tmp_path / "model.npz", M=M, K=K)
    (tmp_path / "s.toml").write_text(
        '[system]\nkind = "matrices"\nmass = "model.npz:M"\n'
        'stiffness = "model.npz:K"\nmodal_damping = 0.01\nload = { 0 = 1.0 }\n\n'
        '[[contacts]]\nlaw = "jenkins"\nstiffness = 2000.0\nslip_force = 1.0\n'
        'dof = 1\nother = 2\n\n[[contacts]]\nlaw = "coulomb"\nslip_force = 0.3\n'
        "dof = 0\n\n[frf]\nforce = 0.5\nomega = [8.0, 60.0]\n"
    )
    with pytest.raises(SceneError, match=r"s.toml: \[\[contacts\]\]: .*Coulomb"):
        load_scene(tmp_path / "s.toml")


@pytest.mark.parametrize(
    "force, omega", [(0.5, 1.6), (2.0, 1.2), (0.1, 1.5)], ids=["F0.5", "F2", "stuck"]
)
def test_periodic_solution_at_a_fixed_h_warns_when_truncation_exceeds(force, omega):
    """hf.frf at a fixed H warns when a point's estimated truncation error
    exceeds harmonic_tolerance; hf.periodic_solution at the same H returned
    P1 6.6e-3 (H = 3) and 2.6e-4 (H = 7) off the exact solution without a
    word. The warning now follows the exact error: issued where it
    exceeds 1e-4, not where it does not (H = 15, 31; the stuck point)."""
    from hbmfric.validation import exact_periodic_solution

    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    system = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)
    exact = exact_periodic_solution(system, force, omega).amplitude(harmonic=1)
    for harmonics in (3, 7, 15, 31):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            sol = hf.periodic_solution(system, force, omega, harmonics=harmonics)
        warned = any(issubclass(w.category, hf.AccuracyWarning) for w in caught)
        error = abs(sol.amplitude(harmonic=1) / exact - 1)
        assert warned == (error > 1e-4), (harmonics, error, warned)
    with pytest.raises(ValueError, match="harmonic_tolerance"):
        hf.periodic_solution(system, force, omega, 7, harmonic_tolerance=0.0)


def test_a_scene_study_writes_the_output_dof(tmp_path):
    """[output] dof chose the DOF of a single FRF's CSV but a study's CSV
    and NPZ held the contact DOF whatever it said."""
    from hbmfric.scene import run_scene

    np.savez(tmp_path / "model.npz", M=np.eye(3), K=K / 10.0)
    (tmp_path / "s.toml").write_text(
        '[system]\nkind = "matrices"\nmass = "model.npz:M"\n'
        'stiffness = "model.npz:K"\nmodal_damping = 0.01\nload = { 0 = 1.0 }\n\n'
        '[[contacts]]\nlaw = "jenkins"\nstiffness = 2000.0\nslip_force = 1.0\n'
        "dof = 1\nother = 2\n\n[frf]\nforce = 0.5\nomega = [8.0, 12.0]\n"
        'harmonics = 5\n\n[output]\ncsv = "out.csv"\nnpz = "out.npz"\ndof = 0\n\n'
        '[study]\nexecutor = "serial"\n"frf.force" = [0.5, 1.0]\n'
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        out = run_scene(tmp_path / "s.toml", progress=lambda s: None)
    runs = out["study"].runs
    expected = np.concatenate([r.branch.amplitude(harmonic=1, dof=0) for r in runs])
    contact = np.concatenate([r.branch.amplitude(harmonic=1) for r in runs])
    assert not np.allclose(expected, contact, rtol=1e-3)
    rows = (tmp_path / "out.csv").read_text().splitlines()
    column = rows[0].split(",").index("amplitude")
    written = np.array([float(r.split(",")[column]) for r in rows[1:]])
    np.testing.assert_allclose(written, expected, rtol=1e-11)
    with np.load(tmp_path / "out.npz") as data:
        np.testing.assert_array_equal(data["amplitude"], expected)
