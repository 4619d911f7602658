"""The documentation's examples run as written, and say what they do.

Every ```python block of a ``docs/*.md`` page runs, the blocks of one page
in order in one namespace (as a reader pastes them), in a temporary
directory. Then the page's check compares what the page states (a printed
value it quotes, a warning it announces, a claim of its text) with an
independent fact where there is one: a closed form, the time-integration
reference, an invariance of the physics. A block that warns
(``hf.HbmfricWarning``) must be one whose page says so; a page's warnings
are listed in ``EXPECTED_WARNINGS``.

A page marks a block with an HTML comment on the line before it:
``<!-- docs-test: skip REASON -->`` (not run; the reason is reported as the
skip reason of its own test) or ``<!-- docs-test: script REASON -->`` (run
as its own file in a fresh process, e.g. a block that starts worker
processes). A block that only includes a file (``--8<--``) is a gallery
script, run by ``tests/test_gallery.py``.

Besides the Python blocks: every ``hbmfric`` command of the docs and the
README names a sub-command and flags that exist (checked against
``--help``, nothing is run), every ``hf.`` / ``hbmfric.`` name resolves,
every repository path named exists, and nothing points outside the
repository.
"""

from __future__ import annotations

import contextlib
import importlib
import io
import math
import re
import shlex
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import hbmfric as hf

ROOT = Path(__file__).parents[1]
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.glob("*.md"))

_BLOCK = re.compile(
    r"(?:<!--\s*docs-test:\s*(?P<mark>[^>]*?)\s*-->\s*\n)?"
    r"^```python\n(?P<code>.*?)^```",
    re.S | re.M,
)


def _blocks(page: Path) -> list[tuple[int, str, str, str]]:
    """(index, kind, reason, code) of every Python block of a page, kind
    ``"run"``, ``"script"``, ``"skip"`` or ``"gallery"``."""
    out = []
    for i, m in enumerate(_BLOCK.finditer(page.read_text(encoding="utf-8"))):
        code, mark = m["code"], (m["mark"] or "").strip()
        if "--8<--" in code:
            out.append((i, "gallery", "a gallery script: tests/test_gallery.py", code))
            continue
        kind, _, reason = mark.partition(" ")
        kind = kind or "run"
        assert kind in ("run", "script", "skip"), (page.name, i, mark)
        if kind == "skip":
            assert reason.strip(), f"{page.name} block {i}: a skip needs a reason"
        out.append((i, kind, reason.strip(), code))
    return out


def _run_page(page: str, tmp_path, monkeypatch) -> tuple[dict, dict]:
    """Run a page's blocks in order; its namespace and, per block index,
    the ``HbmfricWarning``s it raised."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    import matplotlib

    matplotlib.use("Agg")
    namespace: dict = {"__name__": "__docs__"}
    raised: dict = {}
    for i, kind, _, code in _blocks(DOCS / page):
        if kind == "skip" or kind == "gallery":
            continue
        if kind == "script":
            script = tmp_path / f"block{i}.py"
            script.write_text(code, encoding="utf-8")
            proc = subprocess.run(
                [sys.executable, str(script)],
                cwd=tmp_path,
                capture_output=True,
                text=True,
                timeout=900,
                env={**__import__("os").environ, "PYTHONPATH": str(ROOT)},
            )
            assert proc.returncode == 0, f"{page} block {i}:\n{proc.stderr[-3000:]}"
            namespace[f"_script{i}"] = proc
            raised[i] = [
                w
                for w in proc.stderr.splitlines()
                if "Warning:" in w and "hbmfric" in w
            ]
            continue
        with warnings.catch_warnings(record=True) as record:
            warnings.simplefilter("always")
            try:
                exec(compile(code, f"{page} block {i}", "exec"), namespace)
            except Exception as exc:  # name the block, keep the traceback
                raise AssertionError(f"{page} block {i} failed: {exc!r}") from exc
        raised[i] = [w for w in record if issubclass(w.category, hf.HbmfricWarning)]
    import matplotlib.pyplot as plt

    plt.close("all")
    return namespace, raised


# the warnings each page announces for a block: (page, block) -> category
EXPECTED_WARNINGS = {
    ("laws.md", 0): hf.AccuracyWarning,  # "The branch warns"
    ("lap-joint.md", 0): hf.AccuracyWarning,  # "The frf call warns"
}


def _check_warnings(page: str, raised: dict) -> None:
    for i, got in raised.items():
        expected = EXPECTED_WARNINGS.get((page, i))
        if expected is None:
            assert not got, (
                f"{page} block {i} warns and its page does not say so: {got}"
            )
        else:
            assert got, f"{page} block {i}: the page says it warns; it did not"
            assert all(issubclass(w.category, expected) for w in got), got


# ---------------------------------------------------------------- checks


def _jenkins_h1(kt: float, fs: float, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """First-harmonic force coefficients (C1, S1) of a Jenkins element under
    ``u = a cos θ``: the closed form stated in docs/laws.md (stuck:
    ``C1 = kt a``, ``S1 = 0``)."""
    a = np.asarray(a, dtype=float)
    c1, s1 = kt * a, np.zeros_like(a)
    slip = a > fs / kt
    r = fs / (kt * a[slip])
    beta = np.arccos(1.0 - 2.0 * r)
    c1[slip] = kt * a[slip] / math.pi * (beta - 0.5 * np.sin(2.0 * beta))
    s1[slip] = -4.0 * fs / math.pi * (1.0 - r)
    return c1, s1


def _check_getting_started(ns: dict) -> None:
    branch, sol, osc = ns["branch"], ns["sol"], ns["osc"]
    # "the estimated relative truncation error stays below 1e-4"
    assert branch.complete
    assert branch.truncation_error.max() <= 1e-4
    assert sol.converged
    t, x = ns["t"], ns["x"]
    assert t.shape[-1] == 256 and x.shape[-1] == 256
    # the point against both references the page names
    exact = hf.validation.exact_periodic_solution(osc, 0.5, 1.2)
    a_hbm = sol.amplitude(harmonic=1)
    assert abs(a_hbm / exact.amplitude(harmonic=1) - 1) < 1e-4
    assert abs(a_hbm / ns["ref"].amplitude(harmonic=1) - 1) < 1e-3


def _check_laws(ns: dict) -> None:
    sol, ref, s = ns["sol"], ns["ref"], ns["s"]
    # "agree with the time integration within 1e-4", both DOFs
    for dof in ("x_tip", "y_tip"):
        a, b = sol.amplitude(1, dof=dof), ref.amplitude(1, dof=dof)
        assert abs(a / b - 1) < 1e-4, (dof, a, b)
    # "this contact opens during every cycle": N0 + kn v < 0 somewhere
    _, v = sol.time_response(n=512, dof="y_tip")
    assert (10.0 + 2e4 * v).min() < 0
    assert ns["branch"].complete
    # the warning the page quotes: "up to 1.5e-3 on this band"
    assert float(f"{ns['branch'].truncation_error.max():.1e}") == 1.5e-3
    # "without it ... at rest v = -N0/(k_y + k_n)": the static balance of
    # two springs in parallel, read at a vanishing force
    bare = hf.LinearStructure(
        np.eye(2),
        np.diag([1e4, 1e4]),
        damping=6.0 * np.eye(2),
        dof_names={"x_tip": 0, "y_tip": 1},
        load={"x_tip": 4.0, "y_tip": 12.0},
        contacts=[hf.Contact(ns["element"], "x_tip", normal="y_tip")],
    )
    rest = hf.periodic_solution(bare, 1e-9, 110.0, harmonics=2)
    mean_v = rest.coefficients[1, 0]
    assert mean_v == pytest.approx(-10.0 / (1e4 + 2e4), rel=1e-6)
    del s


def _check_stability(ns: dict) -> None:
    branch, stab = ns["branch"], ns["stab"]
    n = len(branch)
    assert stab.exponents.shape == (n, 2) and stab.computed.shape == (n,)
    assert branch.stable.shape == (n,) and branch.stable.dtype == bool
    # the Duffing oscillator x'' + 0.05 x' + x + 0.1 x^3 = 0.2 cos Ωt: its
    # folds from the first-harmonic (describing-function) closed form,
    # ((1 + 0.075 a² − Ω²) a)² + (0.05 Ω a)² = 0.04, solved for Ω² per a
    a = np.linspace(0.2, 4.5, 200001)
    kk = 1 + 0.075 * a**2
    # s² − (2 kk − 0.0025) s + kk² − 0.04/a² = 0, s = Ω²; the larger root
    # traces the lower branch (small a, above resonance), the unstable
    # middle one and the upper branch up to the peak
    bq = 2 * kk - 0.0025
    disc = bq**2 - 4 * (kk**2 - 0.04 / a**2)
    ok = disc >= 0
    a, s = a[ok], (bq[ok] + np.sqrt(disc[ok])) / 2
    fold_high = math.sqrt(s[a > 2.0].max())  # upper meets middle: jump down
    fold_low = math.sqrt(s[(a > 0.5) & (a < 2.0)].min())  # jump up
    folds = sorted(p.omega for p in branch.special_points() if p.kind == "fold")
    assert len(folds) == 2
    # H = 9 against the H = 1 closed form: a weakly nonlinear Duffing, the
    # higher harmonics move the folds by less than 1e-2 rad/s
    assert folds[0] == pytest.approx(fold_low, abs=1e-2)
    assert folds[1] == pytest.approx(fold_high, abs=1e-2)
    # one DOF: the stability changes sit at the folds, the stretch between
    # them unstable
    changes = stab.changes()
    assert len(changes) == 2
    w = branch.omega
    for i in changes:
        assert min(abs(w[i] - f) for f in folds) < 1e-2
    # the time-domain monodromy at point 300 against Hill: "magnitudes
    # within 4e-5"
    m = ns["m"]
    hill = np.sort(np.abs(branch.stability().multipliers[300]))
    assert np.allclose(np.sort(np.abs(m.multipliers)), hill, atol=4e-5)
    # the preloaded Duffing: rest point x_s of x + x³ = 1 and linearised
    # pulsation sqrt(1 + 3 x_s²): the period doubles near twice it
    x_s = np.roots([1.0, 0.0, 1.0, -1.0]).real.max()
    w_lin = math.sqrt(1 + 3 * x_s**2)
    assert w_lin == pytest.approx(1.548, abs=1e-3)  # the page's figure
    pd = ns["pd"]
    assert [round(p.omega, 4) for p in pd] == [2.9965, 3.1782]
    assert pd[0].omega < 2 * w_lin < pd[1].omega
    for p in pd:
        assert abs(p.multiplier + 1) < 1e-6
    b2 = ns["b2"]
    assert b2.stable.shape == (len(b2),)
    # "leaves the doubling at 2.9965 rad/s towards lower Ω (subcritical),
    # folds three times and returns at the second doubling, 3.1782 rad/s"
    forcing = 2 * b2.omega
    assert abs(forcing[0] - pd[0].omega) < 2e-4
    assert abs(forcing[-1] - pd[1].omega) < 2e-4
    assert forcing[1] < forcing[0] and len(b2.folds) == 3


def _check_modes(ns: dict) -> None:
    mode = ns["mode"]
    m, c, k, kt, fs = 1.0, 4.0, 1e4, 3e4, 1.0
    a = mode.amplitude  # m √kg, m = 1 kg: the first-harmonic amplitude
    assert a[0] == pytest.approx(1e-6) and a[-1] == pytest.approx(1e-2)
    assert mode.complete
    # stuck start: the linear mode with the contact spring
    w0 = math.sqrt((k + kt) / m)
    assert mode.omega[0] == pytest.approx(w0, rel=1e-9)
    assert mode.damping_ratio[0] == pytest.approx(c / (2 * m * w0), rel=1e-9)
    assert np.allclose(mode.frequency, mode.omega / (2 * math.pi))
    # the whole backbone against the describing function of docs/laws.md
    # (H = 1): ω² = (k + C1/a)/m, D = c/(2mω) − S1/(2mω²a); H = 7 differs
    # from H = 1 by the truncation of H = 1, 4.7e-3 at most (docs/modes.md)
    c1, s1 = _jenkins_h1(kt, fs, a / math.sqrt(m))
    w_df = np.sqrt((k + c1 / a) / m)
    d_df = c / (2 * m * w_df) - s1 / (2 * m * w_df**2 * a)
    assert np.max(np.abs(mode.omega / w_df - 1)) < 5e-3
    assert np.max(np.abs(mode.damping_ratio - d_df)) < 6e-3
    # the energy balance: supplied energy 2π D ω² a² (one DOF, one harmonic
    # dominant) against the Jenkins loop's closed form 4 fs (a − fs/kt)
    # plus the viscous c π ω a², at the last (gross-slip) point
    e = mode.supplied_energy()[-1]
    x1 = mode.dof_amplitude(0)[-1]
    w = mode.omega[-1]
    assert e == pytest.approx(
        4 * fs * (x1 - fs / kt) + c * math.pi * w * x1**2, rel=1e-2
    )
    assert (Path("mode.csv")).exists() and (Path("mode.npz")).exists()
    loaded = hf.NonlinearMode.load("mode.npz")
    assert np.array_equal(loaded.omega, mode.omega)


def _check_lap_joint(ns: dict) -> None:
    branch = ns["branch"]
    assert branch.complete
    # the warning the page quotes: "an estimated truncation error of 0.03"
    assert float(f"{branch.truncation_error.max():.0e}") == 0.03
    drive = branch.amplitude(1, "drive") / 36.0
    i = int(np.argmax(drive))
    # the table of the page: 2.176e-5 m/N at 162.21 Hz (the computed
    # points fall on the peak differently: frequency within 0.03 %)
    assert drive[i] == pytest.approx(2.176e-5, abs=0.0006e-5)
    assert branch.omega[i] / (2 * math.pi) == pytest.approx(162.21, rel=3e-4)


# docs/lap-joint.md, "Results": Fex -> (drive peak m/N, at Hz)
LAP_TABLE = {
    0.72: ("2.464e-4", 167.11),
    3.6: ("1.106e-4", 167.09),
    36.0: ("2.176e-5", 162.21),
    144.0: ("1.48e-5", 155.90),
    432.0: ("3.554e-5", 145.17),
    1440.0: ("1.963e-4", 144.29),
}


@pytest.mark.slow  # six lap-joint FRFs: 8 s at load 5 on two cores
def test_lap_joint_table_holds():
    """Every row of the lap-joint page's table, traced as the page's example
    does: the peaks to the stated digits, their frequencies to 0.05 Hz (the
    computed points fall on the peak differently)."""
    s = hf.lap_joint(n_pairs=10, n_modes=8)
    band = (2 * math.pi * 125, 2 * math.pi * 185)
    for force, (peak, at) in LAP_TABLE.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.AccuracyWarning)  # stated there
            branch = hf.frf(s, force, band, harmonics=9)
        drive = branch.amplitude(1, "drive") / force
        i = int(np.argmax(drive))
        mantissa, exponent = peak.split("e")
        half_unit = 0.5 * 10.0 ** (int(exponent) - len(mantissa.split(".")[1]))
        assert abs(drive[i] - float(peak)) <= half_unit, (force, drive[i])
        assert branch.omega[i] / (2 * math.pi) == pytest.approx(at, abs=0.05), force
    # the stuck limit: the linear FRF's resonance with the contact springs
    f_stuck = hf.LapJoint(n_pairs=10).natural_frequencies("stuck", 4)
    assert np.any(np.abs(f_stuck - 167.10) < 0.01)


def _check_structures(ns: dict) -> None:
    n, k, m = 40, 2e4, 0.05
    # a fixed-free chain of equal springs and masses:
    # ω_j = 2 sqrt(k/m) sin((2j − 1) π / (2 (2n + 1)))
    j = np.arange(1, 6)
    w_exact = 2 * math.sqrt(k / m) * np.sin((2 * j - 1) * math.pi / (2 * (2 * n + 1)))
    s = ns["s"]
    f = s.natural_frequencies(5)  # Hz, without the contacts
    assert np.allclose(2 * math.pi * f, w_exact, rtol=1e-10)
    branch = ns["branch"]
    assert branch.complete
    # "the uncondensed solve gives the same branch to 1e-8": one point
    w = 0.5 * (ns["w_lo"] + ns["w_hi"])
    cond = hf.periodic_solution(s, 2.0, w, harmonics=5)
    full = hf.periodic_solution(s, 2.0, w, harmonics=5, condense=False)
    for dof in ("tip", "drive", "shroud_a"):
        a, b = cond.amplitude(1, dof=dof), full.amplitude(1, dof=dof)
        assert abs(a / b - 1) < 1e-8, (dof, a, b)
    # Craig–Bampton: valid_below is 2π cutoff_frequency; below it the
    # reduced frequencies are within 1.5 % of the chain's closed form
    reduced = ns["reduced"]
    assert reduced.valid_below == pytest.approx(2 * math.pi * reduced.cutoff_frequency)
    w_red = 2 * math.pi * reduced.natural_frequencies()
    jj = np.arange(1, w_red.size + 1)
    w_chain = 2 * math.sqrt(k / m) * np.sin((2 * jj - 1) * math.pi / (2 * (2 * n + 1)))
    below = w_red < reduced.valid_below
    assert below.any()
    assert np.all(np.abs(w_red[below] / w_chain[below] - 1) < 0.015)
    assert ns["full_coefficients"].shape[1] == n


def _check_criterion(ns: dict) -> None:
    result = ns["result"]
    # a Jenkins contact is Masing macroslip, and with a slip force
    # proportional to Fn and no other load dependence the FRFs per unit
    # force depend on Fex/Fn only: x(F, Fn) = Fn x(F/Fn, 1) exactly
    assert result.model == "macroslip"
    assert result.roughness is False or result.roughness == False  # noqa: E712
    assert str(result).startswith("macroslip without roughness")
    margins = result.indicators["margin"]
    assert margins  # each test's distance to its threshold


def _check_scenes(ns: dict) -> None:
    proc = ns["_script0"]
    assert Path("family.csv").exists()
    from hbmfric.criterion import read_frfs

    family = read_frfs("family.csv")
    assert len(family) == 6, proc.stdout


CHECKS = {
    "getting-started.md": _check_getting_started,
    "laws.md": _check_laws,
    "stability.md": _check_stability,
    "modes.md": _check_modes,
    "lap-joint.md": _check_lap_joint,
    "structures.md": _check_structures,
    "criterion.md": _check_criterion,
    "scenes-and-studies.md": _check_scenes,
}
SLOW: dict[str, str] = {}

RUN_PAGES = [
    p.name
    for p in PAGES
    if any(kind in ("run", "script") for _, kind, _, _ in _blocks(p))
]


def test_every_page_with_examples_has_a_check():
    assert sorted(RUN_PAGES) == sorted(CHECKS)


@pytest.mark.parametrize(
    "page",
    [
        pytest.param(p, marks=pytest.mark.slow(reason=SLOW[p])) if p in SLOW else p
        for p in RUN_PAGES
    ],
)
def test_page_examples_run_and_hold(page, tmp_path, monkeypatch):
    namespace, raised = _run_page(page, tmp_path, monkeypatch)
    _check_warnings(page, raised)
    CHECKS[page](namespace)


_NOT_RUN = [
    (p.name, i, kind, reason)
    for p in PAGES
    for i, kind, reason, _ in _blocks(p)
    if kind in ("skip", "gallery")
]


@pytest.mark.parametrize(
    ("page", "index", "kind", "reason"),
    _NOT_RUN,
    ids=[f"{p}-{i}" for p, i, _, _ in _NOT_RUN],
)
def test_blocks_not_run_here(page, index, kind, reason):
    """Each block this file does not run, with why (shown as the skip)."""
    if kind == "gallery":
        script = re.search(r'--8<--\s*"([^"]+)"', _blocks(DOCS / page)[index][3])
        assert script and (ROOT / script[1]).exists()
    pytest.skip(f"{page} block {index}: {reason}")


# ------------------------------------------------------- shell commands


def _commands() -> list[tuple[str, str]]:
    """(where, command) of every ``hbmfric ...`` command in the docs and
    the README: shell blocks and inline code."""
    out = []
    for path in [*PAGES, ROOT / "README.md"]:
        text = path.read_text(encoding="utf-8")
        shell = re.findall(
            r"^```(?:bash|console|sh|shell)\n(.*?)^```", text, re.S | re.M
        )
        lines = [ln for block in shell for ln in block.splitlines()]
        lines += re.findall(r"`(hbmfric [^`]+)`", text)
        for line in lines:
            line = line.split("#")[0].strip().lstrip("$ ")
            for part in re.split(r"&&|\|\||;|\|", line):
                part = part.strip()
                if part.startswith("hbmfric "):
                    out.append((path.name, part))
    return out


def _help(sub: str) -> str:
    from hbmfric.cli import main

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer), pytest.raises(SystemExit) as exit_:
        main([sub, "--help"])
    assert exit_.value.code == 0, sub
    return buffer.getvalue()


@pytest.mark.parametrize(("where", "command"), _commands())
def test_documented_command_exists(where, command):
    tokens = shlex.split(command)
    sub = tokens[1]
    assert sub in ("paper", "run", "warmup"), (where, command)
    text = _help(sub)
    for token in tokens[2:]:
        if token.startswith("-"):
            flag = token.split("=")[0]
            assert re.search(rf"(?<![\w-]){re.escape(flag)}(?![\w-])", text), (
                where,
                command,
                flag,
            )


def test_documented_commands_found():
    """The collector sees the commands the pages show (so an empty list
    cannot pass the test above)."""
    commands = {c for _, c in _commands()}
    assert "hbmfric paper --out paper-results" in commands
    assert "hbmfric warmup --jobs 2" in commands


# ------------------------------------------------- names, paths, links


def _texts() -> list[tuple[str, str]]:
    return [
        (p.name, p.read_text(encoding="utf-8")) for p in [*PAGES, ROOT / "README.md"]
    ]


def _resolve(dotted: str) -> bool:
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for name in parts[cut:]:
                obj = getattr(obj, name)
        except AttributeError:
            return False
        return True
    return False


def test_every_named_api_exists():
    """``hf.X.y`` and ``hbmfric.mod.name`` in the docs and the README
    resolve (a name that no longer exists is stale documentation)."""
    missing = []
    for where, text in _texts():
        names = set(
            re.findall(r"(?<![\w.])hf\.([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)*)", text)
        )
        full = set(re.findall(r"(?<![\w./-])(hbmfric(?:\.[A-Za-z_]\w*)+)", text))
        for name in sorted(names):
            name = name.rstrip(".")
            if not _resolve(f"hbmfric.{name}"):
                missing.append((where, f"hf.{name}"))
        for name in sorted(full):
            if not _resolve(name):
                missing.append((where, name))
    assert not missing, missing


def test_every_repository_path_named_exists():
    missing = []
    pattern = r"(?<![\w/.-])((?:tests|bench|examples|docs|hbmfric)/[\w./-]*[\w])"
    for where, text in _texts():
        for path in set(re.findall(pattern, text)):
            if "NAME" in path or "*" in path:
                continue
            if not (ROOT / path).exists():
                missing.append((where, path))
    assert not missing, missing


def test_nothing_points_outside_the_repository():
    for where, text in _texts():
        assert "../shared" not in text and "SPEC.md" not in text, where
        for target in re.findall(r"\]\(([^)#\s]+)", text):
            if "://" in target:
                continue
            base = DOCS if where != "README.md" else ROOT
            assert (base / target).exists(), (where, target)


def test_trust_table_on_failure_is_an_argument_where_it_says():
    """docs/trust.md: ``on_failure="raise"`` is an argument of these calls
    and not of ``hf.frf``."""
    import inspect

    text = (DOCS / "trust.md").read_text(encoding="utf-8")
    assert "not of `hf.frf`" in text
    for call in (
        hf.periodic_solution,
        hf.validation.steady_state,
        hf.validation.exact_periodic_solution,
        hf.validation.exact_branch,
    ):
        assert "on_failure" in inspect.signature(call).parameters, call
    assert "on_failure" not in inspect.signature(hf.frf).parameters


# ------------------------------------------- README blocks test_readme skips

_README = ROOT / "README.md"


def _readme_block(marker: str) -> str:
    blocks = re.findall(
        r"^```python\n(.*?)^```", _README.read_text(encoding="utf-8"), re.S | re.M
    )
    (code,) = [b for b in blocks if marker in b]
    return code


def _exec(code: str, where: str) -> tuple[dict, list]:
    namespace: dict = {"__name__": "__docs__"}
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        exec(compile(code, where, "exec"), namespace)
    return namespace, [w for w in record if issubclass(w.category, hf.HbmfricWarning)]


def test_readme_beam_block(tmp_path, monkeypatch):
    """The calibrated beam: the values the comment quotes, and the defining
    property of the calibration (free 24 Hz, stuck 87 Hz)."""
    monkeypatch.chdir(tmp_path)
    ns, raised = _exec(_readme_block("CantileverBeam.calibrate"), "README beam")
    assert not raised, raised
    cal = ns["cal"]
    assert round(cal.tip_mass, 4) == 0.0772  # "≈ 0.0772 kg"
    assert round(cal.contact_stiffness, -2) == 1.586e5  # "≈ 1.586e5 N/m"
    beam = ns["beam"]
    assert beam.natural_frequencies("free", 1)[0] == pytest.approx(24.0, rel=1e-6)
    assert beam.natural_frequencies("stuck", 1)[0] == pytest.approx(87.0, rel=1e-6)
    assert ns["branch"].complete and ns["full"].complete


def test_readme_criterion_block(tmp_path, monkeypatch):
    """The criterion block reads the reader's ``frfs.csv``: here a family of
    a Jenkins oscillator (slip force ∝ Fn), which is Masing macroslip
    without roughness by construction."""
    monkeypatch.chdir(tmp_path)
    import matplotlib

    matplotlib.use("Agg")

    def build(p):
        return hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(3.0, 0.3 * p["normal_load"]))

    grid = hf.grid(force=[0.02, 0.2, 2.0], normal_load=[1.0, 10.0])
    hf.study(build, grid, (0.5, 3.0), executor="serial").to_csv("frfs.csv")
    ns, raised = _exec(_readme_block('read_frfs("frfs.csv")'), "README criterion")
    assert not raised, raised
    assert ns["result"].model == "macroslip" and not ns["result"].roughness
    import matplotlib.pyplot as plt

    plt.close("all")


def test_readme_tensioner_block(tmp_path, monkeypatch):
    """The belt tensioner block: the closed-form energy per cycle equals
    the area of the loop the law marches (trapezoidal rule on a fine
    cycle), and the identified law reproduces the synthetic loop's law."""
    monkeypatch.chdir(tmp_path)
    ns, raised = _exec(_readme_block("ModifiedDahl("), "README tensioner")
    assert not raised, raised
    law = ns["law"]
    n = 1 << 14
    u = 2e-3 * np.cos(2 * np.pi * np.arange(n + 1) / n)
    f = law.hysteresis(u[:-1])
    f = np.append(f, f[0])
    area = abs(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(u)))
    assert ns["W"] == pytest.approx(area, rel=1e-4)
    assert ns["branch"].complete


def test_toml_fragments_parse():
    """The TOML fragments of the docs are valid TOML (the shipped scene
    files they include are run by the scene tests)."""
    import tomllib

    found = 0
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for block in re.findall(r"^```toml\n(.*?)^```", text, re.S | re.M):
            if "--8<--" in block:
                continue
            tomllib.loads(block)
            found += 1
    assert found >= 2
