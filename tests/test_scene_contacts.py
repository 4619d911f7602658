"""Scenes with contacts between DOFs, several contacts, the output DOF, and
the mistakes a new user made (a force with units, a misspelt key, a .mat
file holding several arrays): each refused with the key's path."""

import warnings

import numpy as np
import pytest
import scipy.io

import hbmfric as hf
from hbmfric.scene import SceneError, load_scene, run_scene

M = np.eye(3)
K = np.array(
    [[2000.0, -1000.0, 0.0], [-1000.0, 2000.0, -1000.0], [0.0, -1000.0, 1000.0]]
)

CHAIN = """
[system]
kind = "matrices"
mass = "model.npz:M"
stiffness = "model.npz:K"
modal_damping = 0.01
load = { 0 = 1.0 }

[[contacts]]
law = "jenkins"
stiffness = 2000.0
slip_force = 1.0
dof = 1
other = 2

[frf]
force = 0.5
omega = [8.0, 12.0]
harmonics = 5

[output]
csv = "out.csv"
dof = 0
"""


def quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        return fn(*args, **kwargs)


@pytest.fixture
def chain_dir(tmp_path):
    np.savez(tmp_path / "model.npz", M=M, K=K)
    return tmp_path


def test_contact_between_two_dofs_and_output_dof(chain_dir):
    (chain_dir / "s.toml").write_text(CHAIN)
    out = quiet(run_scene, chain_dir / "s.toml", progress=lambda s: None)
    law = hf.Jenkins(stiffness=2000.0, slip_force=1.0)
    system = hf.LinearStructure(
        M, K, modal_damping=0.01, load={0: 1.0}, contacts=[hf.Contact(law, 1, other=2)]
    )
    ref = quiet(hf.frf, system, 0.5, (8.0, 12.0), 5)
    np.testing.assert_array_equal(out["branch"].omega, ref.omega)
    rows = (chain_dir / "out.csv").read_text().splitlines()
    assert rows[0] == "omega,amplitude,truncation_error"
    amplitude = np.array([float(r.split(",")[1]) for r in rows[1:]])
    # the CSV holds DOF 0 (the forced one), not the contact's
    np.testing.assert_allclose(amplitude, ref.amplitude(harmonic=1, dof=0), rtol=1e-11)
    assert not np.allclose(amplitude, ref.amplitude(harmonic=1), rtol=1e-3)


def test_two_contacts(chain_dir):
    text = CHAIN.replace(
        "[frf]",
        '[[contacts]]\nlaw = "jenkins"\nstiffness = 500.0\nslip_force = 2.0\n'
        "dof = 0\n\n[frf]",
    )
    (chain_dir / "s.toml").write_text(text)
    system = load_scene(chain_dir / "s.toml").system()
    assert len(system.contacts) == 2
    assert system.contacts[1].dof == 0 and system.contacts[1].other is None


@pytest.mark.parametrize(
    "edit, match",
    [
        (("force = 0.5", 'force = "5 N"'), r"\[frf\] force: must be a number"),
        (
            ("omega = [8.0", "omga = [8.0"),
            r"unknown key\(s\) 'omga' \(did you mean 'omega'\?\)",
        ),
        (("dof = 1\n", ""), r"\[\[contacts\]\]\[0\]: missing key 'dof'"),
        (("other = 2", "other = 7"), r"contacts.*7"),
        (("dof = 0\n", 'dof = "tip"\n'), r"\[output\] dof"),
        (("[[contacts]]", "[contact]\nlaw = 'none'\n\n[[contacts]]"), "not both"),
    ],
)
def test_mistakes_are_refused_with_the_key(chain_dir, edit, match):
    old, new = edit
    assert old in CHAIN
    (chain_dir / "s.toml").write_text(CHAIN.replace(old, new, 1))
    with pytest.raises(SceneError, match=match):
        load_scene(chain_dir / "s.toml")


def test_several_contacts_only_for_matrices(tmp_path):
    (tmp_path / "s.toml").write_text(
        '[system]\nkind = "oscillator"\nmass = 1.0\ndamping = 0.02\n'
        'stiffness = 1.0\n\n[[contacts]]\nlaw = "jenkins"\nstiffness = 3.0\n'
        "slip_force = 1.0\ndof = 0\n\n[frf]\nforce = 0.5\nomega = [0.5, 3.0]\n"
    )
    with pytest.raises(SceneError, match="only kind 'matrices'"):
        load_scene(tmp_path / "s.toml")


def test_mat_file_with_several_arrays_names_the_scene_syntax(chain_dir):
    scipy.io.savemat(chain_dir / "model.mat", {"Mff": M, "Kff": K})
    text = CHAIN.replace('"model.npz:M"', '"model.mat"').replace(
        '"model.npz:K"', '"model.mat:Kff"'
    )
    (chain_dir / "s.toml").write_text(text)
    with pytest.raises(SceneError, match=r'mass = "model.mat:<name>"'):
        load_scene(chain_dir / "s.toml")
    (chain_dir / "s.toml").write_text(text.replace('"model.mat"', '"model.mat:Mff"'))
    assert load_scene(chain_dir / "s.toml").system().n_dof == 3


TWO = CHAIN.replace(
    "[frf]",
    '[[contacts]]\nlaw = "jenkins"\nstiffness = 500.0\nslip_force = 2.0\n'
    "dof = 0\n\n[frf]",
)


def _scene(chain_dir, study):
    (chain_dir / "s.toml").write_text(TWO + "\n[study]\n" + study)
    return load_scene(chain_dir / "s.toml")


def test_study_axes_reach_into_contacts(chain_dir):
    """Both spellings of a path into [[contacts]], quoted and unquoted: each
    set's system carries its values on the entry it names, the other entry
    untouched."""
    from hbmfric.scene import study_sets

    scene = _scene(
        chain_dir,
        'executor = "serial"\n"contacts.0.slip_force" = [0.5, 1.5]\n'
        '"contacts[1].stiffness" = [300.0]\n',
    )
    sets = study_sets(scene)
    assert [set(p) for p in sets] == [
        {"contacts.0.slip_force", "contacts[1].stiffness"}
    ] * 2
    for p in sets:
        system = scene.system(p)
        assert system.contacts[0].law.slip_force == p["contacts.0.slip_force"]
        assert system.contacts[0].law.stiffness == 2000.0
        assert system.contacts[1].law.stiffness == 300.0
        assert system.contacts[1].law.slip_force == 2.0
        assert (system.contacts[0].dof, system.contacts[0].other) == (1, 2)
    # unquoted dotted keys arrive as nested tables
    scene = _scene(chain_dir, "contacts.1.slip_force = [1.0, 3.0]\n")
    sets = study_sets(scene)
    assert sets == [{"contacts.1.slip_force": 1.0}, {"contacts.1.slip_force": 3.0}]
    assert scene.system(sets[1]).contacts[1].law.slip_force == 3.0
    # explicit sets too
    scene = _scene(chain_dir, 'sets = [{ "contacts[0].slip_force" = 0.7 }]\n')
    assert scene.system(study_sets(scene)[0]).contacts[0].law.slip_force == 0.7


@pytest.mark.parametrize(
    "study, match",
    [
        ('"contacts.2.slip_force" = [1.0]\n', r"'contacts.2.slip_force': no \[\[co"),
        ('"contacts[5].slip_force" = [1.0]\n', r"has 2 \(indices 0 to 1"),
        ('"contacts.first.slip_force" = [1.0]\n', r"'contacts.<index>.<key>'"),
        ('"contacts.0" = [1.0]\n', r"'contacts.0': a path into"),
        ('"contacts.0.slip_forse" = [1.0]\n', r"did you mean 'slip_force'"),
        ('"contact.slip_force" = [1.0]\n', r"such as 'contacts.0.slip_force'"),
        ('"contacts.0.slip_force" = [-1.0]\n', r"contacts\]\]\[0\].*slip_force"),
        (
            'sets = [{ "frf.force" = 0.2 }, { "contacts.3.stiffness" = 1.0 }]\n',
            r"'contacts.3.stiffness'",
        ),
    ],
)
def test_bad_contacts_axes_are_refused_with_the_path(chain_dir, study, match):
    with pytest.raises(SceneError, match=match) as info:
        _scene(chain_dir, study)
    assert "s.toml" in str(info.value)


def test_contacts_axis_without_contacts_suggests_contact(tmp_path):
    (tmp_path / "s.toml").write_text(
        '[system]\nkind = "oscillator"\nmass = 1.0\ndamping = 0.02\n'
        'stiffness = 1.0\n\n[contact]\nlaw = "jenkins"\nstiffness = 3.0\n'
        "slip_force = 1.0\n\n[frf]\nforce = 0.5\nomega = [0.5, 3.0]\n\n"
        '[study]\n"contacts.0.slip_force" = [1.0, 2.0]\n'
    )
    with pytest.raises(SceneError, match=r"no \[\[contacts\]\].*'contact.slip_force'"):
        load_scene(tmp_path / "s.toml")


def test_study_over_contacts_runs(chain_dir):
    """A scene study over a [[contacts]] entry: every set's branch is the
    direct call's with that entry changed."""
    text = (
        CHAIN
        + '\n[study]\nexecutor = "serial"\n"contacts.0.slip_force" = [0.05, 2.0]\n'
    )
    (chain_dir / "s.toml").write_text(text.replace('csv = "out.csv"\n', ""))
    out = quiet(run_scene, chain_dir / "s.toml", progress=lambda s: None)
    runs = out["study"].runs
    assert [r.parameters["contacts.0.slip_force"] for r in runs] == [0.05, 2.0]
    for run in runs:
        law = hf.Jenkins(
            stiffness=2000.0, slip_force=run.parameters["contacts.0.slip_force"]
        )
        system = hf.LinearStructure(
            M,
            K,
            modal_damping=0.01,
            load={0: 1.0},
            contacts=[hf.Contact(law, 1, other=2)],
        )
        ref = quiet(hf.frf, system, 0.5, (8.0, 12.0), 5)
        np.testing.assert_array_equal(run.branch.coefficients, ref.coefficients)
    a0, a1 = (r.branch.amplitude(harmonic=1) for r in runs)
    assert not np.allclose(a0.max(), a1.max(), rtol=1e-3)


def test_study_axis_into_a_roughness_base(tmp_path):
    """'contact.base.friction_coefficient' reaches the wrapped law of a
    roughness contact (it used to become an unknown key
    'base.friction_coefficient')."""
    from hbmfric.scene import study_sets

    (tmp_path / "s.toml").write_text(
        '[system]\nkind = "oscillator"\nmass = 1.0\ndamping = 0.02\n'
        'stiffness = 1.0\n\n[contact]\nlaw = "roughness"\n\n[contact.base]\n'
        'law = "jenkins"\nstiffness = 3.0\nfriction_coefficient = 0.3\n'
        "normal_load = 10.0\n\n[frf]\nforce = 0.5\nomega = [0.5, 3.0]\n\n"
        '[study]\n"contact.base.friction_coefficient" = [0.1, 0.5]\n'
    )
    scene = load_scene(tmp_path / "s.toml")
    laws = [scene.system(p).contact.law for p in study_sets(scene)]
    np.testing.assert_allclose([law.slip_force for law in laws], [1.0, 5.0])


def test_study_axis_into_a_load_table(chain_dir):
    """'system.load.0' reaches the load of DOF 0 (a table whose keys are
    text in the file)."""
    from hbmfric.scene import study_sets

    (chain_dir / "s.toml").write_text(
        CHAIN + '\n[study]\n"system.load.0" = [1.0, 2.0]\n"system.load.2" = [0.5]\n'
    )
    scene = load_scene(chain_dir / "s.toml")
    loads = [scene.system(p).load_vector(1.0) for p in study_sets(scene)]
    np.testing.assert_array_equal(np.real(loads), [[1.0, 0.0, 0.5], [2.0, 0.0, 0.5]])
