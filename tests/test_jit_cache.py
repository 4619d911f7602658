"""The Numba cache of hbmfric (hbmfric/_jit.py): it never serves code compiled
from older sources, and a missing cache location costs speed, not the import.

Most tests run a tiny copy of the package (the real ``_jit.py`` and
``errors.py`` plus two small kernels) in a subprocess, so that they compile
in a second instead of minutes.
"""

import json
import os
import shutil
import subprocess
import sys
import textwrap

import pytest

import hbmfric
from hbmfric import _jit

CALLEE = """\
from .._jit import jit


@jit
def value(x):
    return x + {increment}
"""

CALLER = """\
from .._jit import jit
from .callee import value


@jit
def twice(x):
    return 2.0 * value(x)
"""

RUN = """\
import warnings

with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    from hbmfric.kernels.caller import twice
    from hbmfric.errors import CacheWarning

    result = twice(1.0)
n_cache = sum(issubclass(w.category, CacheWarning) for w in caught)
print(result, n_cache, len(twice.stats.cache_hits), len(twice.signatures))
for w in caught:
    print("WARNING", w.category.__name__, w.message)
"""


def _tiny_package(root, increment="1.0"):
    """Write a package ``hbmfric`` with the real cache module under ``root``."""
    pkg = root / "hbmfric"
    (pkg / "kernels").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "kernels" / "__init__.py").write_text("")
    for name in ("_jit.py", "errors.py"):
        shutil.copy(os.path.join(_jit.PACKAGE_DIR, name), pkg / name)
    (pkg / "kernels" / "callee.py").write_text(CALLEE.format(increment=increment))
    (pkg / "kernels" / "caller.py").write_text(CALLER)
    return pkg


def _process(root, env_extra):
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    for name in ("HBMFRIC_CACHE_DIR", "HBMFRIC_QUIET"):
        env.pop(name, None)
    env.update(PYTHONPATH=str(root), **env_extra)
    proc = subprocess.run(
        [sys.executable, "-c", RUN],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        cwd=str(root),
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return proc


def _run(root, env_extra):
    proc = _process(root, env_extra)
    first, *rest = proc.stdout.splitlines()
    result, n_cache, n_hits, n_sigs = first.split()
    return float(result), int(n_cache), int(n_hits), int(n_sigs), rest


def _nbi_files(path):
    return [
        os.path.join(d, f)
        for d, _, fs in os.walk(path)
        for f in fs
        if f.endswith(".nbi")
    ]


def test_edited_callee_is_never_served_stale(tmp_path):
    # Numba's own cache keys a caller by its own file: after the callee in
    # another file changes, the cached caller would still return 2 * (1 + 1).
    root = tmp_path / "src"
    pkg = _tiny_package(root, increment="1.0")
    env = {"HBMFRIC_CACHE_DIR": str(tmp_path / "cache")}

    assert _run(root, env)[:4] == (4.0, 0, 0, 1)
    # Second process: served from the cache, same answer.
    assert _run(root, env)[:4] == (4.0, 0, 1, 1)

    (pkg / "kernels" / "callee.py").write_text(CALLEE.format(increment="2.0"))
    result, n_cache, _, n_sigs, _ = _run(root, env)
    assert result == 2.0 * (1.0 + 2.0)
    assert (n_cache, n_sigs) == (0, 1)

    # The cache lives in the user cache directory, never in the package.
    assert _nbi_files(pkg) == []
    # one directory per source key (and the remembered key's file)
    assert len([p for p in (tmp_path / "cache").iterdir() if p.is_dir()]) == 2


def _notices(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.startswith("hbmfric: compil")]


def test_first_compilation_says_so_once(tmp_path):
    """The first compilation prints one line (what, why, that it happens
    once); a process that loads every kernel from the cache prints none;
    HBMFRIC_QUIET silences it."""
    root = tmp_path / "src"
    _tiny_package(root)
    env = {"HBMFRIC_CACHE_DIR": str(tmp_path / "cache")}

    cold = _notices(_process(root, env).stderr)
    assert len(cold) == 1  # two kernels compiled, one line
    assert "once per installed version" in cold[0]
    assert str(tmp_path / "cache") in cold[0]
    assert _notices(_process(root, env).stderr) == []  # warm: silent

    quiet = dict(env, HBMFRIC_CACHE_DIR=str(tmp_path / "other"), HBMFRIC_QUIET="1")
    assert _notices(_process(root, quiet).stderr) == []


def test_compile_notice_without_cache_says_every_process(tmp_path):
    import io

    from numba import njit

    stream = io.StringIO()
    notice = _jit.CompileNotice(os.path.dirname(__file__), None, stream)

    class Event:
        data = {"dispatcher": njit(lambda x: x)}

    notice.on_start(Event())
    notice.on_start(Event())
    lines = stream.getvalue().splitlines()
    assert len(lines) == 1 and "every process" in lines[0]

    elsewhere = _jit.CompileNotice(str(tmp_path), None, io.StringIO())
    elsewhere.on_start(Event())  # a kernel outside the package: silent
    assert elsewhere.stream.getvalue() == ""


def test_no_writable_cache_location_one_warning(tmp_path):
    # A regular file where directories should be: no cache directory can be
    # made (this holds even for root, unlike a chmod).
    root = tmp_path / "src"
    pkg = _tiny_package(root)
    blocker = tmp_path / "blocker"
    blocker.write_text("not a directory")
    (pkg / "kernels" / "__pycache__").write_text("not a directory")
    (pkg / "__pycache__").write_text("not a directory")
    env = {
        "HBMFRIC_CACHE_DIR": str(blocker / "hbmfric"),
        "XDG_CACHE_HOME": str(blocker / "xdg"),
        "HOME": str(blocker / "home"),
    }
    result, n_cache, n_hits, n_sigs, lines = _run(root, env)
    assert result == 4.0
    assert n_cache == 1, lines
    assert (n_hits, n_sigs) == (0, 1)
    assert any("HBMFRIC_CACHE_DIR" in line for line in lines)


def test_source_key_follows_kernel_sources(tmp_path):
    copy = tmp_path / "hbmfric"
    shutil.copytree(
        _jit.PACKAGE_DIR, copy, ignore=shutil.ignore_patterns("__pycache__")
    )
    key = _jit.source_key(str(copy))
    assert key == _jit.source_key(_jit.PACKAGE_DIR)  # content, not location
    assert len(key) == 16

    rel = [os.path.relpath(p, copy) for p in _jit.kernel_sources(str(copy))]
    assert (
        os.path.join("kernels", "residuals", "dispatch.py") in rel
    )  # caches via @overload
    assert os.path.join("kernels", "fourier", "dft.py") in rel
    assert "_jit.py" in rel
    assert "api.py" not in rel

    # Editing a module that compiled code does not depend on keeps the key.
    with open(copy / "api.py", "a") as f:
        f.write("\n# a comment\n")
    assert _jit.source_key(str(copy)) == key

    # Editing any kernel, even one only called from other files, changes it.
    with open(copy / "kernels" / "fourier" / "dft.py", "a") as f:
        f.write("\n# a comment\n")
    key2 = _jit.source_key(str(copy))
    assert key2 != key

    # A plain module that a kernel imports (constants frozen into compiled
    # code) counts as a kernel source too.
    (copy / "kernels" / "fourier" / "constants.py").write_text("LIMIT = 3\n")
    assert _jit.source_key(str(copy)) == key2
    with open(copy / "kernels" / "fourier" / "dft.py", "a") as f:
        f.write("from .constants import (\n    LIMIT,\n)\n")
    key3 = _jit.source_key(str(copy))
    (copy / "kernels" / "fourier" / "constants.py").write_text("LIMIT = 4\n")
    assert _jit.source_key(str(copy)) != key3


def test_remembered_source_key(tmp_path, monkeypatch):
    """The key is remembered between processes with the stamp (size,
    modification time) of the sources: the same key as ``source_key``,
    computed again when a source changes or the remembered line is
    damaged, never read for another package directory."""
    copy = tmp_path / "hbmfric"
    shutil.copytree(
        _jit.PACKAGE_DIR, copy, ignore=shutil.ignore_patterns("__pycache__")
    )
    base = tmp_path / "cache"
    key = _jit.source_key(str(copy))

    # Files written just now are not remembered: an edit in the same tick of
    # the file-system clock could keep their times and size.
    assert _jit.remembered_source_key(str(copy), str(base)) == key
    assert not list(base.glob("source-key-*"))
    monkeypatch.setattr(_jit, "RACY_NS", 0)  # the copy counts as old from here

    assert _jit.remembered_source_key(str(copy), str(base)) == key
    (memo,) = base.glob("source-key-*")

    computed = []
    real = _jit.source_key

    def counting(package_dir):
        computed.append(package_dir)
        return real(package_dir)

    monkeypatch.setattr(_jit, "source_key", counting)
    assert _jit.remembered_source_key(str(copy), str(base)) == key
    assert computed == []  # read, not computed

    with open(copy / "kernels" / "fourier" / "dft.py", "a") as f:
        f.write("\n# a comment\n")
    key2 = real(str(copy))
    assert key2 != key
    assert _jit.remembered_source_key(str(copy), str(base)) == key2
    assert len(computed) == 1

    # A new file anywhere in the package changes the stamp (it may become a
    # kernel source once imported).
    (copy / "kernels" / "fourier" / "constants.py").write_text("LIMIT = 3\n")
    assert _jit.remembered_source_key(str(copy), str(base)) == key2
    assert len(computed) == 2

    memo.write_text("garbage")
    assert _jit.remembered_source_key(str(copy), str(base)) == key2
    assert len(computed) == 3
    assert _jit.remembered_source_key(str(copy), str(base)) == key2
    assert len(computed) == 3

    # Another package directory (a second checkout) has its own line.
    other = tmp_path / "other" / "hbmfric"
    shutil.copytree(copy, other)
    assert _jit.remembered_source_key(str(other), str(base)) == key2
    assert len(list(base.glob("source-key-*"))) == 2

    # No writable base: computed, no error.
    blocker = tmp_path / "blocker"
    blocker.write_text("not a directory")
    assert _jit.remembered_source_key(str(copy), str(blocker / "c")) == key2


def test_cache_directory_checked_once_per_directory(tmp_path, monkeypatch):
    """Numba's writability check of a cache directory (create it, write a
    temporary file) runs once per directory, not once per kernel."""
    monkeypatch.setattr(_jit, "CACHE_DIR", str(tmp_path / "cache"))
    checked = []
    real = _jit._KeyedCacheLocator.ensure_cache_path

    def counting(self):
        checked.append(self.get_cache_path())
        real(self)

    monkeypatch.setattr(_jit._KeyedCacheLocator, "ensure_cache_path", counting)
    from hbmfric.kernels.fourier import dft, segments

    locators = [
        _jit._KeyedCacheLocator.from_function(f.py_func, mod.__file__)
        for mod, f in (
            (dft, dft.evaluate),
            (dft, dft.fourier_matrices),
            (dft, dft.n_coefficients),
            (segments, segments.trig_series),
        )
    ]
    assert all(loc is not None for loc in locators)
    path = str(tmp_path / "cache" / "kernels" / "fourier")
    assert checked == [path]
    assert os.path.isdir(path)


def test_cache_base_resolution(tmp_path):
    home = os.path.expanduser("~")
    assert _jit.cache_base({}) == os.path.join(home, ".cache", "hbmfric")
    assert _jit.cache_base({"XDG_CACHE_HOME": str(tmp_path)}) == str(
        tmp_path / "hbmfric"
    )
    assert _jit.cache_base({"NUMBA_CACHE_DIR": str(tmp_path)}) == str(
        tmp_path / "hbmfric"
    )
    env = {"HBMFRIC_CACHE_DIR": str(tmp_path / "x"), "NUMBA_CACHE_DIR": "/elsewhere"}
    assert _jit.cache_base(env) == str(tmp_path / "x")


def test_package_kernels_use_the_keyed_cache():
    from hbmfric.kernels.fourier import dft

    if not _jit.CACHE:
        pytest.skip("no writable cache in this environment")
    assert os.path.basename(_jit.CACHE_DIR) == _jit.source_key()
    cache = dft.evaluate._cache
    assert cache.cache_path == os.path.join(_jit.CACHE_DIR, "kernels", "fourier")


@pytest.mark.slow
def test_real_package_without_cache_location(tmp_path):
    """End to end: the whole package imports and solves with no writable
    cache location, with one CacheWarning (compiles every kernel: minutes)."""
    blocker = tmp_path / "blocker"
    blocker.write_text("not a directory")
    code = textwrap.dedent(
        """
        import warnings
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            import hbmfric as hf
            osc = hf.Oscillator(mass=1.0, damping=0.05, stiffness=1.0,
                                contact=hf.Jenkins(stiffness=3.0, slip_force=1.0))
            sol = hf.periodic_solution(osc, force=0.5, omega=1.3, harmonics=5)
        print(sum(issubclass(w.category, hf.CacheWarning) for w in caught))
        """
    )
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.update(
        HBMFRIC_CACHE_DIR=str(blocker / "c"),
        PYTHONPATH=os.path.dirname(os.path.dirname(hbmfric.__file__)),
    )
    proc = subprocess.run(
        [sys.executable, "-c", code],
        env=env,
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.split()[-1] == "1"


#: kernels a Jenkins FRF must not compile: the rigid-Coulomb DLFT (only a
#: Coulomb problem type compiles it), the AFT of the other laws and the 2D
#: element (only the general problem type compiles them: a Jenkins problem
#: has its own type, :class:`hbmfric.kernels.residuals.hbm.JenkinsProblem`)
#: and the kernels inlined into the continuation (``jit_inline``: compiled
#: as kernels of their own they would each emit the whole residual once
#: more)
NOT_IN_A_JENKINS_FRF = (
    "hbmfric.kernels.dlft.tail.",
    "hbmfric.kernels.dlft.coulomb.",
    "hbmfric.kernels.residuals.hbm._coulomb",
    "hbmfric.kernels.residuals.condensed._coulomb",
    "hbmfric.kernels.residuals.hbm._aft",
    "hbmfric.kernels.residuals.hbm._contact2d",
    "hbmfric.kernels.aft.contact2d.",
    "hbmfric.kernels.aft.masing.",
    "hbmfric.kernels.aft.dahl.",
    "hbmfric.kernels.aft.schemes.aft_samples",
    "hbmfric.kernels.laws.dahl.",
    "hbmfric.kernels.steps.arclength.advance",
    "hbmfric.kernels.steps.arclength.stays",
    "hbmfric.kernels.steps.newton.palc_step",
    "hbmfric.kernels.steps.newton.palc_correct",
)


def _compiled_names(code: str, env: dict, timeout: float):
    """Run ``code`` in a fresh process; the kernel names it printed after
    ``NAMES`` (JSON) and its standard error."""
    proc = subprocess.run(
        [sys.executable, "-c", code],
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    line = [x for x in proc.stdout.splitlines() if x.startswith("NAMES")][-1]
    return json.loads(line[len("NAMES") :]), proc.stderr


@pytest.mark.slow
def test_cold_jenkins_frf_compiles_only_what_it_uses(tmp_path):
    """A cold first FRF of the Jenkins oscillator (fresh process, empty
    cache; a minute or more) compiles no DLFT kernel, no other law's AFT and
    none of the inlined continuation kernels, each kernel once, and still
    says once that it compiles; a second fresh process compiles nothing."""
    code = textwrap.dedent(
        """
        import json
        from numba.core import event

        names = []

        class Names(event.Listener):
            def on_start(self, ev):
                f = ev.data["dispatcher"].py_func
                names.append(f.__module__ + "." + f.__qualname__)

            def on_end(self, ev):
                pass

        event.register("numba:compile", Names())
        import hbmfric as hf

        o = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
        b = hf.frf(o, 0.5, (0.5, 3.0), 15)
        assert b.stop_reason.startswith("end")
        print("NAMES" + json.dumps(names))
        """
    )
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.pop("HBMFRIC_QUIET", None)
    env.update(
        HBMFRIC_CACHE_DIR=str(tmp_path / "cache"),
        PYTHONPATH=os.path.dirname(os.path.dirname(hbmfric.__file__)),
    )
    names, stderr = _compiled_names(code, env, timeout=1800)
    ours = [n for n in names if n.startswith("hbmfric.")]
    # the residual, compiled once, as its own kernel (the chain calls it
    # through its address)
    assert ours.count("hbmfric.kernels.residuals.hbm.hbm_residual") == 1
    assert "hbmfric.kernels.residuals.dispatch._residual.<locals>.full" not in ours
    assert not [n for n in ours if n.startswith(NOT_IN_A_JENKINS_FRF)]
    twice = sorted({n for n in ours if ours.count(n) > 1})
    # a kernel with several call signatures by design (e.g. one per
    # argument layout) would show here: none in this run
    assert not twice
    assert stderr.count("hbmfric: compiling the Numba kernels") == 1
    # the chain calls the residual through its address: a second fresh
    # process loads every kernel from the cache, the residual as well (its
    # address resolved from the loaded code), and compiles nothing
    names, stderr = _compiled_names(code, env, timeout=600)
    assert names == []
    assert "hbmfric: compiling" not in stderr
