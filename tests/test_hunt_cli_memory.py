"""``hbmfric run`` on a model too large for the machine (stop 35, hunt37).

The memory guard's ``MemoryError`` (how much, and what to do) reached the
user under a 20-line traceback, exit status 1 (the status of failed study
sets); now the message alone, status 2 (the scene cannot be run as it is).
"""

from __future__ import annotations

import scipy.io
import scipy.sparse as sp

from hbmfric.cli import main

SCENE = """
[system]
kind = "matrices"
mass = "M.mtx"
stiffness = "K.mtx"
modal_damping = 0.01
load = {{ 10 = 1.0 }}

[[contacts]]
law = "jenkins"
stiffness = 5e3
slip_force = 1.0
dof = {last}

[[contacts]]
law = "jenkins"
stiffness = 5e3
slip_force = 1.0
dof = {a}
other = {b}

[frf]
force = 2.0
omega = [1, 3]
harmonics = 127
condense = false
"""


def test_too_large_for_memory_says_so_without_a_traceback(tmp_path, capsys):
    n = 600
    k = 2e4 * (2 * sp.eye(n) - sp.eye(n, k=1) - sp.eye(n, k=-1)).tolil()
    k[n - 1, n - 1] = 2e4
    scipy.io.mmwrite(tmp_path / "K.mtx", k.tocoo(), symmetry="symmetric")
    scipy.io.mmwrite(tmp_path / "M.mtx", 0.05 * sp.eye(n).tocoo())
    scene = tmp_path / "big.toml"
    scene.write_text(SCENE.format(last=n - 1, a=n - 2, b=n - 3))
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "needs about" in err and "craig_bampton" in err
    assert "Traceback" not in err
