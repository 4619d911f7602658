"""A new user's first day (stop 33): the mistakes a newcomer makes at the
public edge are refused or warned about with what to do."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf


def _chain(n: int = 3):
    k = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    return np.eye(n), k


def test_scalar_load_says_what_to_give():
    m, k = _chain()
    with pytest.raises(ValueError, match=r"mapping \{dof: value\}.*load=\{j: 1.0\}"):
        hf.LinearStructure(m, k, load=1.0)


def test_wrong_length_load_mentions_the_mapping():
    m, k = _chain()
    with pytest.raises(ValueError, match=r"shape \(3,\).*mapping"):
        hf.LinearStructure(m, k, load=[1.0, 0.0])


def _build(p):  # reads only force-independent "slip_force"
    return hf.Oscillator(1.0, 0.05, 1.0, hf.Jenkins(3.0, p["slip_force"]))


def _study(params):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = hf.study(_build, params, (0.8, 1.2), executor="serial", harmonics=3)
    return result, [str(w.message) for w in caught if w.category is hf.StudyWarning]


def test_study_warns_about_a_parameter_build_never_reads():
    # a misspelt axis ("slip_forse") is never read: both sets are the same
    # system, which the study used to trace twice without a word
    params = hf.grid(force=[0.1], slip_force=[1.0], slip_forse=[0.5, 2.0])
    result, messages = _study(params)
    assert any("'slip_forse'" in m and "never read" in m for m in messages)
    assert all(r.unread == ("slip_forse",) for r in result.runs)


def test_study_is_quiet_when_every_parameter_is_read():
    params = hf.grid(force=[0.1], slip_force=[0.5, 1.0], normal_load=[1.0])
    result, messages = _study(params)
    assert not messages  # normal_load: a tag for the criterion, not warned
    assert all(r.unread == ("normal_load",) for r in result.runs)


def test_read_tracker_counts_bulk_reads():
    from hbmfric.study import _ReadTracker

    for read in (dict, lambda p: {**p}, lambda p: list(p.items()), list):
        p = _ReadTracker({"a": 1, "b": 2})
        read(p)
        assert p.read == {"a", "b"}
    p = _ReadTracker({"a": 1, "b": 2})
    p.get("a")
    assert p.read == {"a"}


SCENE = """
[system]
kind = "matrices"
mass = "model.npz:M"
stiffness = "model.npz:K"
modal_damping = 0.02
dof_names = {{ tip = 2 }}
load = {{ 0 = 1.0 }}
{extra}

[contact]
law = "jenkins"
stiffness = 0.5
slip_force = 2e-4

[frf]
force = 1e-4
omega = [0.2, 1.5]
harmonics = 3

[output]
csv = "out.csv"
png = "out.png"
dof = "tip"
"""


def _scene(tmp_path, extra="contact_dof = 2"):
    m, k = _chain()
    np.savez(tmp_path / "model.npz", M=m, K=k)
    path = tmp_path / "s.toml"
    path.write_text(SCENE.format(extra=extra))
    return path


def test_scene_static_load_takes_dof_indices(tmp_path):
    # TOML keys are strings: `{ 1 = 0.3 }` is DOF 1, as for `load`
    from hbmfric.scene import load_scene

    scene = load_scene(_scene(tmp_path, "contact_dof = 2\nstatic_load = { 1 = 0.3 }"))
    np.testing.assert_array_equal(scene.system({}).static_load(), [0.0, 0.3, 0.0])


def test_scene_unknown_table_suggests_the_right_one(tmp_path):
    from hbmfric.scene import SceneError, load_scene

    path = _scene(tmp_path)
    path.write_text(path.read_text().replace("[output]", "[outptu]"))
    with pytest.raises(SceneError, match=r"\[outptu\] \(did you mean \[output\]\?\)"):
        load_scene(path)


def test_scene_png_draws_the_csv_amplitude_inside_the_figure(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from hbmfric.scene import run_scene

    saved = []
    original = Figure.savefig

    def spy(fig, *args, **kwargs):
        original(fig, *args, **kwargs)
        renderer = fig.canvas.get_renderer()
        left = 0.0  # pixels: the figure's edge
        if kwargs.get("bbox_inches") == "tight":
            left = fig.get_tightbbox(renderer).x0 * fig.dpi  # inches -> pixels
        label = fig.axes[0].yaxis.label.get_window_extent(renderer).x0
        saved.append((fig, label - left))

    monkeypatch.setattr(Figure, "savefig", spy)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        out = run_scene(_scene(tmp_path), progress=lambda s: None)
    (fig, inside) = saved[0]
    # the y label (beside wide tick labels of metres) is inside the saved area
    assert inside >= 0.0
    ax = fig.axes[0]
    csv = np.loadtxt(tmp_path / "out.csv", delimiter=",", skiprows=1)
    # the curve drawn goes through the CSV's points (first harmonic of the
    # tip), not half the peak-to-peak value
    x, y = ax.lines[0].get_data()
    np.testing.assert_allclose(np.interp(csv[:, 0], x, y), csv[:, 1], rtol=1e-9)
    np.testing.assert_allclose(
        csv[:, 1], out["branch"].amplitude(harmonic=1, dof="tip"), rtol=1e-10
    )
    assert "harmonic 1" in ax.get_ylabel() and "tip" in ax.get_title()


def test_python_dash_m_runs_the_command():
    # `python -m hbmfric run scene.toml` said "No module named
    # hbmfric.__main__"; the console script is not always on the PATH
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).parents[1]
    done = subprocess.run(
        [sys.executable, "-m", "hbmfric", "--version"],
        cwd=root,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("hbmfric")


SCENE_2D = """
[system]
kind = "matrices"
mass = "model.npz:M"
stiffness = "model.npz:K"
damping = "model.npz:C"
dof_names = { x_tip = 0, y_tip = 1 }
load = { x_tip = 4.0, y_tip = 12.0 }
static_load = { y_tip = 10.0 }

[[contacts]]
law = "contact2d"
tangential_stiffness = 3e4
normal_stiffness = 2e4
friction_coefficient = 0.5
preload = 10.0
dof = "x_tip"
normal = "y_tip"

[frf]
force = 1.0
omega = [80.0, 90.0]
harmonics = 4
"""


def test_scene_takes_the_2d_element(tmp_path):
    # docs/laws.md's 2D example as a scene (the 2D element needed Python)
    from hbmfric.scene import load_scene, run_scene

    m, k, c = np.eye(2), np.diag([1e4, 1e4]), 6.0 * np.eye(2)
    np.savez(tmp_path / "model.npz", M=m, K=k, C=c)
    (tmp_path / "s.toml").write_text(SCENE_2D)
    element = hf.Contact2D(3e4, 2e4, friction_coefficient=0.5, preload=10.0)
    ref = hf.LinearStructure(
        m,
        k,
        damping=c,
        dof_names={"x_tip": 0, "y_tip": 1},
        load={"x_tip": 4.0, "y_tip": 12.0},
        static_load={"y_tip": 10.0},
        contacts=[hf.Contact(element, "x_tip", normal="y_tip")],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        out = run_scene(tmp_path / "s.toml", progress=lambda s: None)
        b = hf.frf(ref, 1.0, (80.0, 90.0), harmonics=4)
    np.testing.assert_array_equal(out["branch"].omega, b.omega)
    np.testing.assert_array_equal(out["branch"].coefficients, b.coefficients)
    # in [contact] (no normal DOF) it is refused, saying where it goes
    (tmp_path / "t.toml").write_text(
        SCENE_2D.replace("[[contacts]]", "[contact]")
        .replace('dof = "x_tip"\nnormal = "y_tip"\n', "")
        .replace("[system]\n", "[system]\ncontact_dof = 0\n")
    )
    with pytest.raises(ValueError, match=r"\[\[contacts\]\] entry.*normal"):
        load_scene(tmp_path / "t.toml")


def test_steady_state_warning_says_what_to_do():
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    with pytest.warns(hf.ConvergenceWarning) as caught:
        ref = hf.validation.steady_state(osc, 0.5, 1.2, max_periods=3)
    assert not ref.converged
    text = str(caught[0].message)
    assert "max_periods = 3" in text and "tol = 1e-10" in text
    assert "initial_state='linear'" in text


def test_branch_to_csv_holds_the_first_harmonic_of_the_dof(tmp_path):
    m, k = _chain()
    s = hf.LinearStructure(
        m,
        k,
        modal_damping=0.02,
        dof_names={"tip": 2},
        load={0: 1.0},
        contact=hf.Jenkins(stiffness=0.5, slip_force=0.2),
        contact_dof="tip",
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        b = hf.frf(s, 0.1, (0.6, 0.9), harmonics=3)
        path = b.to_csv(tmp_path / "frf.csv", dof=0)
    rows = path.read_text().splitlines()
    assert rows[0] == "omega,amplitude,truncation_error" and len(rows) == len(b) + 1
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    # DOF 0: [X0, Xc1, Xs1, ...], or [Xc1, Xs1, Xc3, ...] for odd harmonics
    c = (
        b.coefficients[:, 0, :]
        if b.harmonic_numbers[0] == 0
        else np.pad(b.coefficients[:, 0, :], ((0, 0), (1, 0)))
    )
    np.testing.assert_allclose(data[:, 0], b.omega, rtol=1e-11)
    np.testing.assert_allclose(data[:, 1], np.hypot(c[:, 1], c[:, 2]), rtol=1e-11)
