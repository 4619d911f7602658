"""The README's example runs as written, and its HBM and time-integration
amplitudes agree."""

import re
from pathlib import Path

README = Path(__file__).parents[1] / "README.md"


def _blocks() -> list[str]:
    """The README's Python code blocks, in order."""
    return re.findall(r"```python\n(.*?)```", README.read_text(), re.S)


def _run_block(*markers: str) -> dict:
    """Run the one Python block of the README containing every marker;
    its namespace."""
    (code,) = [b for b in _blocks() if all(m in b for m in markers)]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    return namespace


def test_readme_example_runs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(_blocks()[0], "README.md", "exec"), namespace)
    sol, ref = namespace["sol"], namespace["ref"]
    assert abs(sol.amplitude(harmonic=1) / ref.amplitude(harmonic=1) - 1) < 1e-3
    assert (tmp_path / "frf.npz").exists()


def test_readme_contact_law_example_runs():
    namespace = _run_block("hf.Menq")
    assert abs(namespace["menq"].stiffness / 3e4 - 1) < 1e-12


def test_readme_own_system_example_runs():
    namespace = _run_block("class TwoMasses")
    branch = namespace["branch"]
    assert branch.stop_reason == "end of frequency range reached"
    # default DOF of the results: the one named "contact"
    assert (branch.amplitude(harmonic=1) == branch.amplitude(1, dof=1)).all()


def test_readme_fe_matrices_example_runs():
    """The structure-from-matrices example runs; its reduction keeps the
    lowest natural frequency of the full model."""
    import numpy as np

    namespace = _run_block("hf.LinearStructure(", "hf.craig_bampton")
    branch, s, reduced = namespace["branch"], namespace["s"], namespace["reduced"]
    assert branch.complete
    f_full = s.natural_frequencies(1)
    f_red = reduced.with_contact(None).natural_frequencies(1)
    assert np.isclose(f_red[0], f_full[0], rtol=1e-2)


def test_readme_study_example_runs(tmp_path, monkeypatch):
    (code,) = [b for b in _blocks() if "hf.study(" in b]
    monkeypatch.chdir(tmp_path)
    script = tmp_path / "study_example.py"
    script.write_text(code)
    import subprocess
    import sys

    proc = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    # the grid has two loads per ratio and mostly stuck curves: a verdict,
    # not "undecided" (whose explanation also mentions macroslip)
    assert proc.stdout.startswith("macroslip without roughness"), proc.stdout
    assert (tmp_path / "family.csv").exists()


def test_readme_several_contacts_example_runs():
    """The several-contacts example runs and traces its whole range."""
    namespace = _run_block("hf.Contact2D(")
    assert namespace["branch"].complete
