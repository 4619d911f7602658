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


def test_cli_run_exits_1_when_a_study_set_fails(tmp_path, capsys):
    """A failing set among good ones (f_s = -1): the others are written,
    and the exit status says it (it was 0, the warning the only sign)."""
    from hbmfric.cli import main

    path = tmp_path / "family.toml"
    path.write_text(FAILING_SET)
    out = tmp_path / "o"
    with pytest.warns(hf.StudyWarning):
        assert main(["run", str(path), "--out", str(out)]) == 1
    assert "1 of 3 parameter sets failed" in capsys.readouterr().err
    curves = np.genfromtxt(out / "family.csv", delimiter=",", names=True)["curve"]
    assert set(curves.astype(int)) == {0, 2}
