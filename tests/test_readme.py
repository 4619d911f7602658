"""The README's example runs as written, and its HBM and time-integration
amplitudes agree."""

import re
from pathlib import Path


def test_readme_example_runs(tmp_path, monkeypatch):
    text = (Path(__file__).parents[1] / "README.md").read_text()
    code = re.findall(r"```python\n(.*?)```", text, re.S)[0]
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    sol, ref = namespace["sol"], namespace["ref"]
    assert abs(sol.amplitude(harmonic=1) / ref.amplitude(harmonic=1) - 1) < 1e-3
    assert (tmp_path / "frf.npz").exists()


def test_readme_contact_law_example_runs():
    text = (Path(__file__).parents[1] / "README.md").read_text()
    (code,) = [
        block
        for block in re.findall(r"```python\n(.*?)```", text, re.S)
        if "hf.Menq" in block
    ]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    assert abs(namespace["menq"].stiffness / 3e4 - 1) < 1e-12


def test_readme_own_system_example_runs():
    text = (Path(__file__).parents[1] / "README.md").read_text()
    (code,) = [
        block
        for block in re.findall(r"```python\n(.*?)```", text, re.S)
        if "class TwoMasses" in block
    ]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    branch = namespace["branch"]
    assert branch.stop_reason == "end of frequency range reached"
    # default DOF of the results: the one named "contact"
    assert (branch.amplitude(harmonic=1) == branch.amplitude(1, dof=1)).all()


def test_readme_fe_matrices_example_runs():
    """The structure-from-matrices example runs; its reduction keeps the
    lowest natural frequency of the full model."""
    import numpy as np

    text = (Path(__file__).parents[1] / "README.md").read_text()
    (code,) = [
        block
        for block in re.findall(r"```python\n(.*?)```", text, re.S)
        if "hf.LinearStructure(" in block and "hf.craig_bampton" in block
    ]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    branch, s, reduced = namespace["branch"], namespace["s"], namespace["reduced"]
    assert branch.complete
    f_full = s.natural_frequencies(1)
    f_red = reduced.with_contact(None).natural_frequencies(1)
    assert np.isclose(f_red[0], f_full[0], rtol=1e-2)


def test_readme_study_example_runs(tmp_path, monkeypatch):
    text = (Path(__file__).parents[1] / "README.md").read_text()
    (code,) = [
        block
        for block in re.findall(r"```python\n(.*?)```", text, re.S)
        if "hf.study(" in block
    ]
    monkeypatch.chdir(tmp_path)
    script = tmp_path / "study_example.py"
    script.write_text(code)
    import subprocess
    import sys

    proc = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "macroslip" in proc.stdout or "undecided" in proc.stdout
    assert (tmp_path / "family.csv").exists()


def test_readme_several_contacts_example_runs():
    """The several-contacts example runs and traces its whole range."""
    text = (Path(__file__).parents[1] / "README.md").read_text()
    (code,) = [
        block
        for block in re.findall(r"```python\n(.*?)```", text, re.S)
        if "hf.Contact2D(" in block
    ]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    assert namespace["branch"].complete
