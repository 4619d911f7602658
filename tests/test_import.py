"""Importing hbmfric is cheap: no plotting library, no compilation."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_import_loads_no_matplotlib_and_compiles_nothing(tmp_path):
    """In a fresh process with an empty Numba cache, ``import hbmfric``
    leaves matplotlib unimported and every compiled kernel of the package
    without a signature (nothing compiled or loaded from cache); a first
    call to a small kernel then compiles, which shows that the check sees
    compilations."""
    code = textwrap.dedent(
        """
        import json, sys
        import hbmfric as hf

        def compiled():
            out = {}
            for name, mod in list(sys.modules.items()):
                if not name.startswith("hbmfric"):
                    continue
                for attr in dir(mod):
                    obj = getattr(mod, attr)
                    if hasattr(obj, "signatures") and hasattr(obj, "py_func"):
                        out[name + "." + attr] = len(obj.signatures)
            return out

        at_import = compiled()
        mpl = sorted(m for m in sys.modules if m.split(".")[0] == "matplotlib")
        heavy = sorted(
            m for m in ("scipy.optimize", "scipy.integrate") if m in sys.modules
        )
        import numpy as np
        from hbmfric.kernels.fourier.dft import n_coefficients
        n_coefficients(np.array([1, 3]))
        after_call = compiled()
        print(json.dumps({"import": at_import, "call": after_call, "mpl": mpl,
                          "heavy": heavy}))
        """
    )
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
        env=env,
    )
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["mpl"] == []
    assert report["heavy"] == []  # imported lazily, where they are used
    assert len(report["import"]) >= 10  # the kernels are visible to the check
    assert all(n == 0 for n in report["import"].values()), {
        k: v for k, v in report["import"].items() if v
    }
    assert sum(report["call"].values()) > 0  # ... and it sees a compilation


#: modules an oscillator's FRF does not use, loaded on first use of a name
#: they define (``hf.nonlinear_mode``, ``hf.CantileverBeam``, ...)
NOT_IMPORTED_EAGERLY = (
    "hbmfric.modes",
    "hbmfric.stability",
    "hbmfric.periodic",
    "hbmfric.switching",
    "hbmfric.bifurcation",
    "hbmfric.systems.beam",
    "hbmfric.systems.calibration",
    "hbmfric.systems.tensioner",
    "hbmfric.systems.matrix_files",
    "hbmfric.validation",
    "hbmfric.identify",
    "hbmfric.criterion",
)


def test_import_leaves_unused_modules_unimported():
    """``import hbmfric`` imports none of :data:`NOT_IMPORTED_EAGERLY`; each
    public name resolves on first use to the object of its module, also
    through ``from hbmfric import *`` and ``from hbmfric.systems import``."""
    code = textwrap.dedent(
        """
        import json, sys
        import hbmfric as hf
        eager = sorted(m for m in sys.modules if m.startswith("hbmfric"))
        from hbmfric.systems import CantileverBeam
        import hbmfric.api, hbmfric.modes, hbmfric.periodic, hbmfric.switching
        import hbmfric.systems.beam, hbmfric.systems.matrix_files
        import hbmfric.systems.lap_joint, hbmfric.systems.craig_bampton
        same = [
            hf.periodic_solution is hbmfric.periodic.periodic_solution,
            hbmfric.api.periodic_solution is hf.periodic_solution,
            hf.nonlinear_mode is hbmfric.modes.nonlinear_mode,
            hf.NonlinearMode is hbmfric.modes.NonlinearMode,
            hf.period_doubled_branch is hbmfric.switching.period_doubled_branch,
            hf.CantileverBeam is CantileverBeam is hbmfric.systems.beam.CantileverBeam,
            hf.read_matrix is hbmfric.systems.matrix_files.read_matrix,
            callable(hf.systems.lap_joint) and callable(hf.systems.craig_bampton),
            hf.lap_joint is hf.systems.lap_joint,
            hf.study.__module__ == "hbmfric.study",
        ]
        names = {}
        exec("from hbmfric import *", names)
        missing = sorted(set(hf.__all__) - set(names))
        print(json.dumps({"eager": eager, "same": same, "missing": missing}))
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    )
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert not set(report["eager"]) & set(NOT_IMPORTED_EAGERLY), report["eager"]
    assert all(report["same"]), report["same"]
    assert report["missing"] == []


#: the kernels' folders in the order of ``hbmfric/kernels/__init__.py``
KERNEL_STAGES = (
    "fourier",
    "linalg",
    "laws",
    "aft",
    "dlft",
    "residuals",
    "steps",
    "stability",
)


def test_kernel_folders_import_only_earlier_stages():
    """Each folder of ``hbmfric/kernels`` imports only from itself and the
    folders before it in the documented order (no module of the package
    outside ``kernels`` but ``_jit``); every kernel module sits in one of
    them."""
    import ast

    kernels = ROOT / "hbmfric" / "kernels"
    assert {p.name for p in kernels.iterdir() if p.is_dir()} - {"__pycache__"} == set(
        KERNEL_STAGES
    )
    assert [p.name for p in kernels.glob("*.py")] == ["__init__.py"]
    for rank, stage in enumerate(KERNEL_STAGES):
        for path in (kernels / stage).glob("*.py"):
            for node in ast.walk(ast.parse(path.read_text())):
                if not isinstance(node, ast.ImportFrom) or not node.level:
                    continue
                where = f"{path.relative_to(ROOT)}:{node.lineno}"
                module = node.module or ""
                if node.level == 1:
                    continue  # the same folder
                if node.level == 3:
                    assert module == "_jit", where
                    continue
                assert node.level == 2, where
                target = module.split(".")[0]
                assert target in KERNEL_STAGES[:rank], where
