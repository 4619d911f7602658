"""Wrong input fails at the public edge with a TypeError or ValueError that
names the parameter (or the system field, or the file and field), instead of
an AttributeError, IndexError, LinAlgError, MemoryError or a numpy
broadcast error from deep inside."""

import io
import math
import zipfile

import naive
import numpy as np
import pytest

import hbmfric as hf
from hbmfric import cli
from hbmfric._validate import finite_float

OSC = hf.Oscillator(1.0, 0.05, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


class TwoDof:
    """A duck-typed user system whose matrices the tests spoil one at a time."""

    n_dof = 2
    symmetric = True

    def __init__(self, M=None, C=None, K=None, contact_dof=1, load=None):
        self.M = np.diag([1.0, 0.5]) if M is None else M
        self.C = 0.02 * np.eye(2) if C is None else C
        self.K = np.array([[3.0, -1.0], [-1.0, 1.0]]) if K is None else K
        self.contact_dof = contact_dof
        self.contact = hf.Jenkins(stiffness=3.0, slip_force=1.0)
        self.load = load

    def matrices(self):
        return self.M, self.C, self.K

    def load_vector(self, force):
        return np.array([force, 0.0]) if self.load is None else self.load


# --- systems -----------------------------------------------------------------
def test_frf_of_none_names_system():
    with pytest.raises(TypeError, match="system must be an hbmfric system"):
        hf.frf(None, 1.0, (0.5, 3.0))


def test_periodic_solution_of_object_lists_missing_fields():
    with pytest.raises(TypeError, match="system.*without.*matrices"):
        hf.periodic_solution(object(), 1.0, 1.0)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"M": np.eye(3)}, r"system\.mass .*shape \(2, 2\)"),
        ({"C": np.ones(2)}, r"system\.damping .*shape \(2, 2\)"),
        ({"contact_dof": 5}, r"system\.contact_dof .*\[0, 1\]"),
        ({"contact_dof": -1}, r"system\.contact_dof"),
        ({"K": np.array([[np.nan, -1.0], [-1.0, 1.0]])}, r"system\.stiffness .*finite"),
        ({"M": np.diag([1.0, 0.0])}, r"system\.mass .*positive definite"),
        ({"M": np.diag([1.0, -0.5])}, r"system\.mass .*positive definite"),
        ({"M": np.array([[1.0, 0.1], [0.0, 1.0]])}, r"system\.mass .*symmetric"),
        ({"load": np.array([1.0, 0.0, 0.0])}, r"system\.load_vector"),
        ({"load": np.array([np.inf, 0.0])}, r"system\.load_vector"),
    ],
)
@pytest.mark.parametrize("entry", ["frf", "periodic_solution", "steady_state"])
def test_bad_user_system_names_the_field(kwargs, match, entry):
    system = TwoDof(**kwargs)
    with pytest.raises(ValueError, match=match):
        if entry == "frf":
            hf.frf(system, 1.0, (0.5, 3.0), 3)
        elif entry == "periodic_solution":
            hf.periodic_solution(system, 1.0, 1.0, 3)
        else:
            hf.validation.steady_state(system, 1.0, 1.0)


def test_contact_must_be_a_law():
    system = TwoDof()
    system.contact = "jenkins"
    with pytest.raises(TypeError, match="system.contact"):
        hf.periodic_solution(system, 1.0, 1.0, 3)


def test_builtin_systems_pass_the_protocol():
    from hbmfric.systems.protocol import check_system

    beam = hf.CantileverBeam(contact=hf.Jenkins(stiffness=1e5, slip_force=1.0))
    for system in (OSC, beam, TwoDof()):
        data = check_system(system)
        assert data.mass.shape == (system.n_dof, system.n_dof)


# --- options, guesses, numbers -------------------------------------------------
@pytest.mark.parametrize("entry", ["frf", "periodic_solution"])
def test_options_must_be_continuation_options(entry):
    with pytest.raises(TypeError, match="options must be a ContinuationOptions"):
        if entry == "frf":
            hf.frf(OSC, 1.0, (0.5, 3.0), options="x")
        else:
            hf.periodic_solution(OSC, 1.0, 1.0, options="x")


def _solution(n_dof):
    return hf.PeriodicSolution(
        omega=1.0,
        force=1.0,
        harmonic_numbers=np.arange(4),
        coefficients=np.ones((n_dof, 7)),
        converged=True,
        newton_iterations=0,
        residual_norm=0.0,
    )


def test_guess_of_another_layout_is_refused():
    # a beam solution (39 DOFs) as guess for the oscillator raised a numpy
    # broadcast error
    with pytest.raises(ValueError, match="initial_guess .*39 DOFs.*has 1"):
        hf.periodic_solution(OSC, 1.0, 1.0, 3, initial_guess=_solution(39))
    # a 1-DOF solution given to a 2-DOF system was silently broadcast to both
    with pytest.raises(ValueError, match="initial_guess .*1 DOFs.*has 2"):
        hf.periodic_solution(
            TwoDof(), 1.0, 1.0, 3, initial_guess=_solution(1), condense=False
        )


@pytest.mark.parametrize("value", ["1.0", True, np.bool_(False), 1j, [1.0], None])
def test_finite_float_takes_numbers_only(value):
    with pytest.raises(TypeError, match="x must be a real number"):
        finite_float("x", value)


@pytest.mark.parametrize(
    "value", [2, 2.0, np.float32(2.0), np.int64(2), np.array(2.0), np.array(2)]
)
def test_finite_float_accepts_real_numbers(value):
    assert finite_float("x", value) == 2.0


def test_public_numbers_refuse_strings_and_bools():
    with pytest.raises(TypeError, match="stiffness"):
        hf.Jenkins(stiffness="3.0", slip_force=1.0)
    with pytest.raises(TypeError, match="mass"):
        hf.Oscillator(mass=True, damping=0.0, stiffness=1.0)
    with pytest.raises(TypeError, match="force"):
        hf.periodic_solution(OSC, "1.0", 1.0)


# --- laws --------------------------------------------------------------------
def test_segalman_close_to_minus_one_is_exact():
    """χ → -1 made every power-law stiffness underflow to 0 ("stiffnesses
    must all be > 0"); now the cells keep their exact stiffness and the
    totals hold, and the law's loop is the sum of its Jenkins elements."""
    fs, kt, beta = 1.5, 4.0, 0.1
    for chi in (-0.999999, -1.0 + 1e-12, -0.5):
        law = hf.Iwan.segalman(fs, kt, chi=chi, beta=beta, n_elements=20)
        k, f = np.array(law.stiffnesses), np.array(law.slip_forces)
        assert np.all(k > 0) and np.all(f >= 0)
        assert math.isclose(k.sum(), kt, rel_tol=1e-12)
        assert math.isclose(f.sum(), fs, rel_tol=1e-12)
        # the delta at φ_max: S = β F_S / (φ_max (β + c)), S φ_max its force
        c = (chi + 1.0) / (chi + 2.0)
        phi_max = fs * (1.0 + beta) / (kt * (beta + c))
        s = beta * fs / (phi_max * (beta + c))
        assert math.isclose(k[-1], s, rel_tol=1e-12)
        assert math.isclose(f[-1], s * phi_max, rel_tol=1e-12)
        # each power-law cell: ∫ρ and ∫φρ of ρ = R φ^χ between its nodes
        m = k.size - 1
        nodes = phi_max * (np.arange(m + 1) / m) ** (1.0 / (chi + 1.0))
        if chi == -0.5:
            r = fs * (chi + 1.0) / (phi_max ** (chi + 2.0) * (beta + c))
            np.testing.assert_allclose(
                f[:-1], r / (chi + 2.0) * np.diff(nodes ** (chi + 2.0)), rtol=1e-12
            )
        u = 2.0 * phi_max * np.cos(2 * np.pi * np.arange(64) / 64)
        np.testing.assert_allclose(
            law.hysteresis(u), naive.iwan_march(u, k, f), rtol=1e-9, atol=1e-12
        )


@pytest.mark.parametrize(
    "args, match",
    [
        ((1.0, -1.0, 300.0), "normal_load"),
        ((1.0, float("nan"), 300.0), "normal_load"),
        ((1.0, 10.0, 0.0), "limit_load"),
        ((-1.0, 10.0, 300.0), "asymptotic_stiffness"),
    ],
)
def test_hertz_mindlin_stiffness_input(args, match):
    with pytest.raises(ValueError, match=match):
        hf.hertz_mindlin_stiffness(*args)


def test_hertz_mindlin_stiffness_values():
    assert hf.hertz_mindlin_stiffness(8.0, 37.5, 300.0) == pytest.approx(4.0)
    assert hf.hertz_mindlin_stiffness(8.0, 400.0, 300.0) == 8.0


# --- files -------------------------------------------------------------------
def _branch(n=3, n_dof=2):
    return hf.Branch(
        omega=np.linspace(1.0, 2.0, n),
        coefficients=np.zeros((n, n_dof, 7)),
        harmonic_numbers=np.arange(4),
        force=1.0,
        folds=np.array([1], dtype=np.int64),
        stop_reason="done",
        n_steps=n,
        n_rejected=0,
        newton_iterations=0,
        elapsed=0.0,
        dof_names={"contact": 1},
    )


def _rewrite(path, field, array=None, header=None):
    """Replace one member of an .npz file by ``array`` or by a bare header."""
    with zipfile.ZipFile(path) as zf:
        members = {i.filename: zf.read(i) for i in zf.infolist()}
    buf = io.BytesIO()
    if header is not None:
        np.lib.format.write_array_header_1_0(buf, header)
        buf.write(b"\0" * 64)
    else:
        np.lib.format.write_array(buf, np.asarray(array))
    members[field + ".npy"] = buf.getvalue()
    with zipfile.ZipFile(path, "w") as zf:
        for name, data in members.items():
            zf.writestr(name, data)


def test_branch_load_roundtrip(tmp_path):
    path = _branch().save(tmp_path / "b.npz")
    back = hf.Branch.load(path)
    assert back.coefficients.shape == (3, 2, 7) and back.dof_names == {"contact": 1}


def test_branch_load_huge_header(tmp_path):
    path = _branch().save(tmp_path / "b.npz")
    header = {"descr": "<f8", "fortran_order": False, "shape": (2**40 - 1,)}
    _rewrite(path, "omega", header=header)
    with pytest.raises(ValueError, match=r"b\.npz.*'omega'.*claims shape"):
        hf.Branch.load(path)


@pytest.mark.parametrize(
    "field, array, match",
    [
        ("omega", np.linspace(1.0, 2.0, 5), "'coefficients'"),
        ("harmonic_numbers", np.arange(6), "'coefficients'"),
        ("harmonic_numbers", np.array([0, 2, 1, 3]), "'harmonic_numbers'"),
        ("folds", np.array([7]), "'folds'"),
        ("point_harmonics", np.array([3, 3]), "'point_harmonics'"),
    ],
)
def test_branch_load_inconsistent_arrays(tmp_path, field, array, match):
    path = _branch().save(tmp_path / "b.npz")
    _rewrite(path, field, array)
    with pytest.raises(ValueError, match=r"b\.npz.*" + match):
        hf.Branch.load(path)


def test_branch_load_dof_names_out_of_range(tmp_path):
    branch = _branch()
    branch.dof_names = {"tip": 5}
    path = branch.save(tmp_path / "b.npz")
    with pytest.raises(ValueError, match=r"b\.npz.*'dof_names'"):
        hf.Branch.load(path)


# --- command line --------------------------------------------------------------
def test_paper_out_is_a_file(tmp_path, capsys):
    target = tmp_path / "results"
    target.write_text("a file")
    assert cli.main(["paper", "--out", str(target)]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "existing file" in err
    assert target.read_text() == "a file"


class _FakeFigure:
    def __init__(self, name):
        self.name = name

    def write_csv(self, path):
        path.write_text("omega\n")
        return path

    def write_png(self, path):
        path.write_bytes(b"png")
        return path


def test_paper_writes_each_figure_when_computed(tmp_path, monkeypatch):
    import hbmfric.paper as paper

    def figures(**kwargs):
        yield _FakeFigure("fig08_fake")
        yield _FakeFigure("fig09_fake")

    def fails(**kwargs):
        raise RuntimeError("scene failed")

    monkeypatch.setattr(paper, "iter_sdof_figures", figures, raising=False)
    monkeypatch.setattr(paper, "sdof_figures", lambda **kw: list(figures()))
    monkeypatch.setattr(paper, "beam_normal_load_family", fails)
    with pytest.raises(RuntimeError, match="scene failed"):
        cli.main(["paper", "--out", str(tmp_path)])
    for name in ("fig08_fake", "fig09_fake"):
        assert (tmp_path / f"{name}.csv").exists()
        assert (tmp_path / f"{name}.png").exists()


def _mode(tmp_path):
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    mode = hf.nonlinear_mode(osc, amplitude=(0.1, 1.0), points=4, harmonics=3)
    return mode.save(tmp_path / "m.npz")


def test_mode_load_huge_header(tmp_path):
    """A forged header must not make NonlinearMode.load allocate 8 TiB."""
    path = _mode(tmp_path)
    header = {"descr": "<f8", "fortran_order": False, "shape": (2**40 - 1,)}
    _rewrite(path, "omega", header=header)
    with pytest.raises(ValueError, match=r"m\.npz.*'omega'.*claims shape"):
        hf.NonlinearMode.load(path)


@pytest.mark.parametrize(
    "field, array, match",
    [
        ("omega", np.linspace(1.0, 2.0, 7), "'omega'"),
        ("damping_ratio", np.zeros(2), "'damping_ratio'"),
        ("harmonic_numbers", np.arange(6), "'coefficients'"),
        ("harmonic_numbers", np.array([3, 1]), "'harmonic_numbers'"),
        ("amplitude", np.array([0.1, np.nan, 0.3, 1.0]), "'amplitude'"),
        ("truncation_error", np.zeros(9), "'truncation_error'"),
    ],
)
def test_mode_load_inconsistent_arrays(tmp_path, field, array, match):
    path = _mode(tmp_path)
    _rewrite(path, field, array)
    with pytest.raises(ValueError, match=r"m\.npz.*" + match):
        hf.NonlinearMode.load(path)
