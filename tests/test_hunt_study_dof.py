"""Trust hunt, stop 28: a DOF index in a study whose parameter changes the
number of DOFs (a mesh refinement).

Before stop 28 ``StudyResult.table(dof=5)`` (and the CSV of a scene study
with ``[output] dof = 5``) wrote one ``amplitude`` column mixing the
rotation of the tip of a 2-element beam and the rotation of node 2 of a
13-element one, without a word; with one model too small for the index the
scene crashed after every run with a traceback. The reference here is each
branch's own amplitude at a DOF chosen by its name."""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.scene import SceneError, load_scene


def _chain(params: dict) -> hf.LinearStructure:
    """A fixed–free chain of ``n`` unit masses, Jenkins at the tip, driven
    at the tip (module level: picklable)."""
    n = int(params["n"])
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    return hf.LinearStructure(
        np.eye(n),
        K,
        modal_damping=0.05,
        dof_names={"tip": n - 1},
        contact=hf.Jenkins(stiffness=1.0, slip_force=10.0),
        contact_dof="tip",
    )


def test_study_table_refuses_a_dof_index_when_the_dof_count_changes(tmp_path):
    res = hf.study(
        _chain,
        [{"force": 0.1, "n": 2}, {"force": 0.1, "n": 3}],
        (0.2, 0.4),
        executor="serial",
        harmonics=1,
    )
    assert not res.failures
    with pytest.raises(ValueError, match="different point"):
        res.table(dof=1)
    with pytest.raises(ValueError, match="different point"):
        res.to_csv(tmp_path / "family.csv", dof=0)
    # by name, or the contact DOF: each branch's own tip
    for dof in ("tip", None):
        t = res.table(dof=dof)
        for r in res.runs:
            rows = t["curve"] == r.index
            np.testing.assert_array_equal(
                t["amplitude"][rows], r.branch.amplitude(harmonic=1, dof="tip")
            )


def test_study_table_keeps_a_dof_index_when_the_dof_count_is_fixed():
    res = hf.study(
        _chain,
        [{"force": 0.1, "n": 3}, {"force": 0.2, "n": 3}],
        (0.2, 0.4),
        executor="serial",
        harmonics=1,
    )
    t = res.table(dof=1)
    for r in res.runs:
        rows = t["curve"] == r.index
        np.testing.assert_array_equal(
            t["amplitude"][rows], r.branch.amplitude(harmonic=1, dof=1)
        )


SCENE = """
[system]
kind = "beam"
tip_mass = 0.0772
damping_ratio = 0.05
[contact]
law = "jenkins"
stiffness = 1.6e5
friction_coefficient = 1.5
normal_load = 40.0
[frf]
force = 2.0
frequency_hz = [15.0, 110.0]
harmonics = 3
[study]
executor = "serial"
"system.n_elements" = [2, 13]
[output]
directory = "out"
csv = "family.csv"
dof = {dof}
"""


@pytest.mark.parametrize("dof", ["5", "1"])
def test_scene_refuses_an_output_dof_index_across_meshes(tmp_path, dof):
    """Refused when the file is read, before any run (2 and 13 elements:
    6 and 39 DOFs)."""
    path = tmp_path / "mesh.toml"
    path.write_text(SCENE.format(dof=dof))
    with pytest.raises(SceneError, match=r"\[output\] dof.*6, 39 DOFs"):
        load_scene(path)


def test_scene_accepts_an_output_dof_name_across_meshes(tmp_path):
    path = tmp_path / "mesh.toml"
    path.write_text(SCENE.format(dof='"tip"'))
    load_scene(path)


FAILING_SET = """
[system]
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
harmonics = 3
[study]
executor = "serial"
"contact.slip_force" = [1.0, -1.0, 0.5]
[output]
csv = "family.csv"
"""


def test_cli_run_exits_1_when_a_study_set_fails(tmp_path, capsys, monkeypatch):
    """A failing set among good ones (f_s = -1): the others are written,
    and the exit status says it (it was 0, the warning the only sign).
    The load-time check of the sets' values (which refuses this file, the
    test below) is switched off to reach the run: a set can still fail
    there (a ``system.*`` value of a matrices scene, a combination)."""
    import hbmfric.scene
    from hbmfric.cli import main

    monkeypatch.setattr(hbmfric.scene, "_check_set_values", lambda *a: None)
    path = tmp_path / "family.toml"
    path.write_text(FAILING_SET)
    out = tmp_path / "o"
    with pytest.warns(hf.StudyWarning):
        assert main(["run", str(path), "--out", str(out)]) == 1
    assert "1 of 3 parameter sets failed" in capsys.readouterr().err
    curves = np.genfromtxt(out / "family.csv", delimiter=",", names=True)["curve"]
    assert set(curves.astype(int)) == {0, 2}


@pytest.mark.parametrize(
    ("axis", "match"),
    [
        (
            '"contact.slip_force" = [1.0, -1.0, 0.5]',
            r"set 1 \('contact.slip_force' = -1.0\)",
        ),
        ('"frf.force" = [0.5, inf]', r"set 1 \('frf.force' = inf\): \[frf\]"),
        (
            '"system.mass" = [1.0, 2.0, 0.0]',
            r"set 2 \('system.mass' = 0.0\): \[system\]",
        ),
        (
            'sets = [{ "contact.slip_force" = 1.0 }, { "contact.law" = "cubic" }]',
            r"set 1 \('contact.law' = 'cubic'\): \[contact\]: unknown key",
        ),
    ],
)
def test_a_bad_value_in_a_later_study_set_is_refused_at_load(tmp_path, axis, match):
    """Only the first set's model was checked at load: a bad value later in
    an axis (f_s = -1 in set 1) failed at run time, after the sets before
    it had run. Now every set's values are checked at load (the laws, the
    force, a cheap built-in system), the message naming the set, the key
    and the value; the CLI exits 2 before running anything. A value good
    only with another of its set's (a law and its keys) passes."""
    from hbmfric.cli import main
    from hbmfric.scene import SceneError, load_scene

    text = FAILING_SET.replace('"contact.slip_force" = [1.0, -1.0, 0.5]', axis)
    path = tmp_path / "family.toml"
    path.write_text(text)
    with pytest.raises(SceneError, match=match) as info:
        load_scene(path)
    assert "family.toml" in str(info.value)
    assert main(["run", str(path), "--out", str(tmp_path / "o")]) == 2
    assert not (tmp_path / "o").exists()
    # a value good only with another of its set's: menq from its stiffness
    path.write_text(
        FAILING_SET.replace(
            '"contact.slip_force" = [1.0, -1.0, 0.5]',
            'sets = [{ "contact.slip_force" = 1.0 }, '
            '{ "contact.law" = "menq", "contact.from_stiffness" = true }]',
        )
    )
    sets = load_scene(path).data["study"]["sets"]
    assert len(sets) == 2
