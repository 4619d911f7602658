"""The curve drawn of a DOF the step control does not watch (stop 30).

The step control bounds the straight lines between the points of the
watched contact DOF (``curve_tolerance``, 1e-4). The lap joint of the docs
(10 pairs, 8 modes, 36 N, 125-185 Hz, H = 9) watches a contact coordinate;
its forced end ``"drive"`` is what the docs read. Its straight lines are
2.5e-4 off (relative to the smaller end) over 126-130 Hz, against
fixed-frequency solves at the chords' fractions; before stop 30 a polyline
plot of it (``plot(dof="drive", curve="polyline")``) was drawn without a
word. The dense output (``plot``'s default) stays within 1e-5 of the same
solves there: no warning for it.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.results import CURVE_REST

FRACTIONS = (0.21132486540518713, 0.5, 0.7886751345948129)
FORCE = 36.0


@pytest.fixture(scope="module")
def setup():
    system = hf.lap_joint(n_pairs=10, n_modes=8)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(system, FORCE, (2 * np.pi * 125, 2 * np.pi * 185), 9)
    return system, branch


def _measured(system, b, i, dof):
    """Largest distance of the straight line and of the dense output of
    ``dof`` from H = 9 solves at the chord's fractions, relative as
    :attr:`Branch.curve_errors` (the smaller end, at least ``CURVE_REST`` of
    the scale)."""
    a = b.amplitude(1, dof)
    ref = max(min(a[i], a[i + 1]), CURVE_REST * b.info["amplitude_scale"])
    line, dense = 0.0, 0.0
    for tau in FRACTIONS:
        w = b.omega[i] + tau * (b.omega[i + 1] - b.omega[i])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            s = hf.periodic_solution(
                system, FORCE, w, 9, initial_guess=b.point(i if tau < 0.5 else i + 1)
            )
        assert s.converged
        true = s.amplitude(1, dof)
        line = max(line, abs(a[i] + tau * (a[i + 1] - a[i]) - true) / ref)
        values = b.amplitude_at([w], 1, dof)[0]
        values = values[np.isfinite(values)]
        dense = max(dense, float(np.min(np.abs(values - true))) / ref)
    return line, dense


def test_lines_of_the_drive_dof_estimated_and_warned(setup):
    system, b = setup
    tol = b.info["curve_tolerance"]
    assert tol == pytest.approx(1e-4)
    watched = b.curve_errors
    drive = b.curve_errors_of("drive")
    assert np.array_equal(b.curve_errors_of(None), watched)
    for i in np.argsort(drive)[::-1][:3]:
        line, dense = _measured(system, b, i, "drive")
        assert line > 2.0 * tol, (b.omega[i], line)  # truly off
        assert watched[i] <= tol
        assert line / 1.5 <= drive[i] <= 1.5 * line, (b.omega[i], drive[i], line)
        assert dense < 0.2 * tol, (b.omega[i], dense)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    try:
        with pytest.warns(hf.AccuracyWarning, match="DOF 'drive'"):
            b.plot(ax=ax, dof="drive", curve="polyline")
        with warnings.catch_warnings():
            warnings.simplefilter("error", hf.AccuracyWarning)
            b.plot(ax=ax, dof="drive")  # the dense output
            b.plot(ax=ax, curve="polyline")  # the watched DOF: frf's business
    finally:
        plt.close(fig)


SCENE = """
[system]
kind = "matrices"
mass = "M.npy"
stiffness = "K.npy"
modal_damping = 0.01
dof_names = { drive = 0, tip = 2 }
load = { drive = 1.0, tip = [0.0, 0.3] }

[[contacts]]
law = "jenkins"
stiffness = 500.0
slip_force = 2.0
dof = "tip"

[frf]
force = 1.0
frequency_hz = [0.8, 9.5]
harmonics = 7

[output]
directory = "out"
csv = "frf.csv"
"""


def _matrices(tmp_path):
    np.save(tmp_path / "M.npy", np.diag([1.0, 1.0, 0.5]))
    K = 1e3 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    np.save(tmp_path / "K.npy", K)
    return hf.LinearStructure(
        np.diag([1.0, 1.0, 0.5]),
        K,
        modal_damping=0.01,
        dof_names={"drive": 0, "tip": 2},
        load={"drive": 1.0, "tip": 0.3j},
        contacts=[hf.Contact(hf.Jenkins(stiffness=500.0, slip_force=2.0), "tip")],
    )


def test_scene_csv_of_the_drive_dof_warns(tmp_path):
    """The README's 3-DOF structure as a scene file with ``[output] dof =
    "drive"``: its lines are 3.6e-4 off near 31.7 rad/s (fixed-frequency
    solves; the watched tip's 7.7e-5); the CSV of that DOF warns, of the
    watched DOF not; a study's CSV of it warns once."""
    from hbmfric.cli import main

    system = _matrices(tmp_path)
    (tmp_path / "a.toml").write_text(SCENE + 'dof = "drive"\n')
    (tmp_path / "b.toml").write_text(SCENE.replace('"out"', '"out_b"'))
    with pytest.warns(hf.AccuracyWarning, match="DOF 'drive'"):
        assert main(["run", str(tmp_path / "a.toml")]) == 0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["run", str(tmp_path / "b.toml")]) == 0
    assert not any(
        "straight lines between the points of DOF" in str(w.message) for w in caught
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        b = hf.frf(system, 1.0, (2 * np.pi * 0.8, 2 * np.pi * 9.5), 7)
    i = int(np.argmax(b.curve_errors_of("drive")))
    line, _ = _measured_at(system, b, i, "drive", 1.0, 7)
    assert line > 2.0 * b.info["curve_tolerance"]
    res = hf.study(
        _build, [{"force": 1.0}, {"force": 0.5}], (2 * np.pi * 0.8, 2 * np.pi * 9.5),
        executor="serial", harmonics=7, progress=False,
    )  # fmt: skip
    with pytest.warns(hf.AccuracyWarning, match="in 2 of 2 runs"):
        res.to_csv(tmp_path / "study.csv", dof="drive")


def _build(p):
    K = 1e3 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    return hf.LinearStructure(
        np.diag([1.0, 1.0, 0.5]),
        K,
        modal_damping=0.01,
        dof_names={"drive": 0, "tip": 2},
        load={"drive": 1.0, "tip": 0.3j},
        contacts=[hf.Contact(hf.Jenkins(stiffness=500.0, slip_force=2.0), "tip")],
    )


def _measured_at(system, b, i, dof, force, harmonics):
    a = b.amplitude(1, dof)
    ref = max(min(a[i], a[i + 1]), CURVE_REST * b.info["amplitude_scale"])
    line = 0.0
    for tau in FRACTIONS:
        w = b.omega[i] + tau * (b.omega[i + 1] - b.omega[i])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.HbmfricWarning)
            s = hf.periodic_solution(
                system, force, w, harmonics, initial_guess=b.point(i)
            )
        assert s.converged
        line = max(
            line, abs(a[i] + tau * (a[i + 1] - a[i]) - s.amplitude(1, dof)) / ref
        )
    return line, None
