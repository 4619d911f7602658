"""Time to the first FRF branch in a fresh process, cold and warm Numba cache.

Run: ``python -m bench.cold_start [--phases] [--profile-frf]
[--profile-families] [--profile] [--paper]`` (from the repository root);
``--paper`` times a whole cold ``hbmfric paper`` (:func:`paper_cold`), with
its compiling helper, and ``hbmfric warmup --jobs 2`` on an empty cache
followed by ``hbmfric paper``, wall and CPU (of every process); ``--phases``
splits the warm first FRF of a fresh process into its parts
(:data:`PHASES`); ``--profile-frf`` lists the compile time of every kernel
(exclusive of the kernels it calls) of the cold first FRF, in one more fresh
process with an empty cache; ``--profile-families`` the same for the paper's
four kinds of FRF in one process (:data:`FAMILIES`); ``--profile`` for a
cold ``hbmfric paper``. Every run also times the README's first FRF
(:data:`FRF_README`, ``harmonics="auto"``) cold, as a newcomer meets it.

Each run is ``python -c "import hbmfric; hbmfric.frf(...)"`` (the SDOF
Jenkins branch, H = 15) in a new interpreter with ``NUMBA_CACHE_DIR`` in a
fresh temporary directory: the first run compiles every kernel and fills the
cache (cold), the next ones load it (warm). ``import hbmfric`` alone is timed
too.

Python's bytecode: with ``PYTHONDONTWRITEBYTECODE=1`` in the environment (as
on the project's machine) no ``.pyc`` file of hbmfric is ever written, and
every process compiles all of hbmfric's imported modules from source (about
0.1 s of a first FRF). An installed package has its ``.pyc`` files (pip
writes them), so the warm figures are also given as an installed package
sees them (``*_pyc``: ``PYTHONPYCACHEPREFIX`` in a temporary directory, the
variable above removed, one run beforehand to write them).
"""

from __future__ import annotations

import glob
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FRF = (
    "import hbmfric as hf;"
    "o=hf.Oscillator(1.0,0.02,1.0,hf.Jenkins(stiffness=3.0,slip_force=1.0));"
    "b=hf.frf(o,0.5,(0.5,3.0),15);"
    "assert b.stop_reason.startswith('end')"
)

#: the paper's four kinds of FRF in one process, one problem type each (the
#: residual's; the continuation kernels take them as two chain types, full
#: and condensed): the SDOF paper oscillator with a Jenkins and with a Menq
#: contact (``harmonics="auto"``), the paper beam at Fn = 5 N (condensed,
#: auto) and the belt tensioner (Dahl, H = 7)
#: the README's first FRF as a newcomer runs it: P1 with ``harmonics="auto"``
#: (the default), which compiles the adaptive run's kernels (truncation
#: estimates, the probes) on top of :data:`FRF`'s
FRF_README = (
    "import hbmfric as hf;"
    "o=hf.Oscillator(1.0,0.02,1.0,hf.Jenkins(stiffness=3.0,slip_force=1.0));"
    "b=hf.frf(o,0.5,(0.5,3.0));"
    "assert b.complete"
)

FAMILIES = """
import hbmfric as hf
from hbmfric.continuation import ContinuationOptions
from hbmfric.paper.beam import PAPER_BEAM_SCENE, _omega_range, paper_beam
from hbmfric.paper.scenes import paper_oscillator
from hbmfric.paper.sdof import menq_law
from hbmfric.systems.tensioner import BeltTensioner
from hbmfric.systems.tensioner_response import hbm_frf
o = paper_oscillator(10.0)
hf.frf(o, 1.0, (50.0, 300.0), "auto")
menq = hf.Oscillator(o.mass, o.damping, o.stiffness, menq_law(10.0))
hf.frf(menq, 1.0, (50.0, 300.0), "auto")
band = _omega_range(PAPER_BEAM_SCENE)
hf.frf(paper_beam(5.0), 2.0, band, "auto", max_step=PAPER_BEAM_SCENE["max_step"])
options = ContinuationOptions(max_step=0.03)
hbm_frf(BeltTensioner(), 5.0, (5.0, 100.0), 7, options=options)
"""


def _env(cache: str, pyc: str | None = None) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, HBMFRIC_CACHE_DIR=cache)
    if pyc is not None:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = pyc
    return env


def _run(code: str, cache: str, pyc: str | None = None) -> float:
    t = time.perf_counter()
    subprocess.run(
        [sys.executable, "-c", code], check=True, cwd=ROOT, env=_env(cache, pyc)
    )
    return time.perf_counter() - t


def _timed(argv: list[str], cache: str, quiet: bool = True) -> tuple[float, float]:
    """Wall and CPU seconds (user + system, of the process and of every
    process it waited for, e.g. its spawned helpers) of ``python argv``."""
    env = _env(cache)
    if quiet:
        env["HBMFRIC_QUIET"] = "1"
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run(
        [sys.executable, *argv],
        check=True,
        cwd=ROOT,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


#: ``hbmfric <argv>`` in a fresh process
CLI = "import sys; from hbmfric.cli import main; sys.exit(main(sys.argv[1:]))"


def paper_cold(lap_joint_pairs: int = 10) -> dict:
    """A first-ever ``hbmfric paper`` (its figures written to a temporary
    directory, plots included), wall and CPU seconds of all its processes:
    ``paper`` on an empty cache (its compiling helper,
    :class:`hbmfric.warmup.PaperHelper`, included); ``warmup`` (``hbmfric
    warmup --jobs 2`` on another empty cache) and ``paper_after_warmup``
    (``hbmfric paper`` then, on that cache). ``lap_joint_pairs``: the
    extra lap-joint figure set's ``--lap-joint-pairs`` (0 skips it).
    Each line is printed when measured, with the load."""
    out = {}
    pairs = ["--lap-joint-pairs", str(lap_joint_pairs)]
    with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
        for name, cache, argv in (
            ("paper", a, ["paper", "--out", os.path.join(a, "out"), *pairs]),
            ("warmup", b, ["warmup", "--jobs", "2"]),
            (
                "paper_after_warmup",
                b,
                ["paper", "--out", os.path.join(b, "out"), *pairs],
            ),
        ):
            load = os.getloadavg()[0]
            start = time.time()
            wall, cpu = _timed(["-c", CLI, *argv], cache)
            out[name] = (wall, cpu)
            # the paper's own figures (fig*), before the extra lap joint's
            figures = glob.glob(os.path.join(cache, "out", "fig*"))
            last = max((os.path.getmtime(f) for f in figures), default=start)
            print(
                f"{name:>20}: {wall:7.1f} s wall, {cpu:7.1f} s CPU "
                f"(load {load:.1f} -> {os.getloadavg()[0]:.1f})"
                + (
                    f"; the paper's figures written after {last - start:.1f} s"
                    if figures
                    else ""
                ),
                flush=True,
            )
    return out


def first_frf_cpu(runs: int = 5, cache: str | None = None) -> dict:
    """The warm first FRF of :data:`FRF` in a fresh process, import
    included: least wall and CPU seconds (of the whole process) over
    ``runs`` processes, and the same for ``import hbmfric`` alone."""
    with tempfile.TemporaryDirectory() as new:
        cache = new if cache is None else cache
        _run(FRF, cache)  # compiles if cold
        rows: dict[str, list] = {}
        for _ in range(runs):
            for name, code in (("frf", FRF), ("import", "import hbmfric")):
                wall, cpu = _timed(["-c", code], cache)
                rows.setdefault(f"{name}_wall_s", []).append(wall)
                rows.setdefault(f"{name}_cpu_s", []).append(cpu)
    return {k: min(v) for k, v in rows.items()}


def readme_frf_cold() -> tuple[float, float]:
    """Wall and CPU seconds of :data:`FRF_README` in a fresh process on an
    empty cache (import and compilation included)."""
    with tempfile.TemporaryDirectory() as cache:
        return _timed(["-c", FRF_README], cache)


def measure(warm_runs: int = 5, cache: str | None = None) -> dict:
    """Seconds: cold first branch, warm first branch (min), import alone,
    the bare interpreter; the warm ones also with ``.pyc`` files (``*_pyc``,
    see the module's docstring). The warm runs alternate between the two
    settings. ``cache``: an empty directory for the Numba cache, left
    filled (default: a temporary one)."""
    with tempfile.TemporaryDirectory() as new, tempfile.TemporaryDirectory() as pyc:
        cache = new if cache is None else cache
        cold = _run(FRF, cache)
        _run(FRF, cache, pyc)  # writes the .pyc files
        runs: dict[str, list[float]] = {}
        for _ in range(warm_runs):
            for name, code in (("warm", FRF), ("import", "import hbmfric")):
                runs.setdefault(f"{name}_s", []).append(_run(code, cache))
                runs.setdefault(f"{name}_pyc_s", []).append(_run(code, cache, pyc))
        bare = min(_run("pass", cache) for _ in range(warm_runs))
    return {"cold_s": cold, **{k: min(v) for k, v in runs.items()}, "python_s": bare}


#: run in a fresh process with a warm cache: the parts of the first FRF, in
#: seconds (``time.perf_counter``); Numba's registry set-up (the first
#: ``refresh`` of its CPU target, which every first compilation or cache
#: load does and which imports ``scipy.linalg`` through
#: ``numba.np.arraymath``) is timed on its own before the FRF, and the
#: kernels' cache loads inside it
PHASES_CODE = """
import json, sys, time
t0 = time.perf_counter()
import numba
t1 = time.perf_counter()
import hbmfric as hf
t2 = time.perf_counter()
from numba.core import caching
from numba.core.registry import cpu_target
cpu_target.target_context.refresh()
t3 = time.perf_counter()
loads = []
_load = caching.Cache.load_overload
def load_overload(self, sig, ctx):
    t = time.perf_counter()
    out = _load(self, sig, ctx)
    loads.append(time.perf_counter() - t)
    return out
caching.Cache.load_overload = load_overload
{body}
t4 = time.perf_counter()
print("PHASES" + json.dumps({
    "import numba": t1 - t0, "import hbmfric (rest)": t2 - t1,
    "Numba registry set-up": t3 - t2, "kernel cache loads": sum(loads),
    "first FRF (rest)": t4 - t3 - sum(loads), "kernels loaded": len(loads),
    "modules": len(sys.modules)}))
"""

#: parts reported by :func:`phases`
PHASES = (
    "python",
    "import numba",
    "import hbmfric (rest)",
    "Numba registry set-up",
    "kernel cache loads",
    "first FRF (rest)",
    "total",
)


def phases(runs: int = 5, pyc: bool = False, cache: str | None = None) -> dict:
    """The warm first FRF of a fresh process split into :data:`PHASES`
    (seconds, each the min over ``runs`` processes; ``python`` is the bare
    interpreter's start and exit, ``total`` the whole process, min over
    the same runs) plus the number of kernels loaded and of modules.

    Parameters
    ----------
    runs : int
        Fresh processes.
    pyc : bool
        Let Python use ``.pyc`` files (an installed package; see the
        module's docstring).
    cache : str, optional
        Numba cache directory to use (default: a new one, compiled first).
    """
    code = PHASES_CODE.replace("{body}", FRF.replace(";", "\n"))
    with tempfile.TemporaryDirectory() as new, tempfile.TemporaryDirectory() as tmp:
        cache = new if cache is None else cache
        where = tmp if pyc else None
        _run(FRF, cache, where)  # compiles if cold, writes the .pyc files
        out: dict[str, list] = {}
        for _ in range(runs):
            t = time.perf_counter()
            proc = subprocess.run(
                [sys.executable, "-c", code],
                check=True,
                cwd=ROOT,
                env=_env(cache, where),
                capture_output=True,
                text=True,
            )
            total = time.perf_counter() - t
            line = [x for x in proc.stdout.splitlines() if x.startswith("PHASES")]
            parts = json.loads(line[-1][len("PHASES") :])
            parts["total"] = total
            for k, v in parts.items():
                out.setdefault(k, []).append(v)
            out.setdefault("python", []).append(_run("pass", cache, where))
    return {k: min(v) for k, v in out.items()}


#: run in a fresh process with an empty cache: every compilation of a
#: hbmfric kernel timed by Numba's ``numba:compile`` event, exclusive of the
#: kernels it compiles in turn, in CPU seconds of the process
#: (``time.process_time``: compiling is single-threaded, and on a shared
#: machine the CPU time moves far less with the load than the wall time)
PROFILE = """
import json, sys, time
from numba.core import event

records, stack = [], []

class Timer(event.Listener):
    def on_start(self, ev):
        stack.append([time.process_time(), 0.0])
    def on_end(self, ev):
        t0, children = stack.pop()
        total = time.process_time() - t0
        if stack:
            stack[-1][1] += total
        f = ev.data["dispatcher"].py_func
        records.append((f.__module__ + "." + f.__qualname__, total - children))

event.register("numba:compile", Timer())
t = time.perf_counter()
c = time.process_time()
{body}
records.append(("TOTAL cpu", time.process_time() - c))
records.append(("TOTAL wall", time.perf_counter() - t))
print("PROFILE" + json.dumps(records))
"""


def compile_profile(
    argv: list[str] | None = None, code: str | None = None
) -> tuple[float, float, list[tuple[str, float, int]]]:
    """Compile time of every kernel during ``hbmfric <argv>`` (or the
    Python ``code``) run cold.

    Returns
    -------
    wall : float
        Wall time of the whole command, s.
    cpu : float
        CPU time of the whole command (compiling and running), s.
    kernels : list of (name, cpu_seconds, compilations)
        Exclusive compile CPU time per kernel (summed over its
        signatures), largest first.
    """
    with tempfile.TemporaryDirectory() as cache:
        env = dict(
            os.environ,
            NUMBA_CACHE_DIR=cache,
            HBMFRIC_CACHE_DIR=cache,
            HBMFRIC_QUIET="1",
        )
        if code is None:
            body = "from hbmfric.cli import main\nmain(sys.argv[1:])"
        else:
            body = code.replace(";", "\n")
        proc = subprocess.run(
            [sys.executable, "-c", PROFILE.replace("{body}", body), *(argv or [])],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
            check=True,
        )
    line = [x for x in proc.stdout.splitlines() if x.startswith("PROFILE")][-1]
    records = json.loads(line[len("PROFILE") :])
    wall = records.pop()[1]
    cpu = records.pop()[1]
    per: dict[str, list] = {}
    for name, sec in records:
        per.setdefault(name, [0.0, 0])
        per[name][0] += sec
        per[name][1] += 1
    kernels = sorted(((k, v[0], v[1]) for k, v in per.items()), key=lambda r: -r[1])
    return wall, cpu, kernels


def main() -> None:
    with tempfile.TemporaryDirectory() as cache:
        for k, v in measure(cache=cache).items():
            print(f"{k:>12}: {v:.2f}")
        if "--phases" in sys.argv:
            _print_phases(cache)
        load = os.getloadavg()[0]
        parts = first_frf_cpu(cache=cache)
        print(f"warm first FRF in a fresh process (min of 5, load {load:.1f}):")
        for k, v in parts.items():
            print(f"  {k:>14}: {v:.2f}")
    load = os.getloadavg()[0]
    wall, cpu = readme_frf_cold()
    print(
        f"cold README first FRF (harmonics='auto'): {wall:.1f} s wall, "
        f"{cpu:.1f} s CPU (load {load:.1f} -> {os.getloadavg()[0]:.1f})"
    )
    if "--paper" in sys.argv:
        paper_cold()
    if "--profile-frf" in sys.argv:
        wall, cpu, kernels = compile_profile(code=FRF)
        _table("cold first FRF", wall, cpu, kernels)
    if "--profile-families" in sys.argv:
        wall, cpu, kernels = compile_profile(code=FAMILIES)
        _table("cold four kinds of FRF, one process", wall, cpu, kernels)
    if "--profile" in sys.argv:
        with tempfile.TemporaryDirectory() as out:
            wall, cpu, kernels = compile_profile(["paper", "--out", out, "--no-plot"])
        _table("cold 'hbmfric paper'", wall, cpu, kernels)


def _print_phases(cache: str) -> None:
    for pyc in (False, True):
        parts = phases(pyc=pyc, cache=cache)
        print(
            f"warm first FRF by part ({'with' if pyc else 'without'} .pyc "
            f"files, min of 5, load {os.getloadavg()[0]:.1f}):"
        )
        for k in PHASES:
            print(f"  {k:>24}: {parts[k]:.3f} s")
        n_kernels, n_modules = parts["kernels loaded"], parts["modules"]
        print(f"  kernels loaded {n_kernels}, modules {n_modules}")


def _table(what: str, wall: float, cpu: float, kernels: list) -> None:
    total = sum(k[1] for k in kernels)
    print(
        f"{what}: {wall:.1f} s wall, {cpu:.1f} s CPU, of which compiling "
        f"{total:.1f} s CPU (load {os.getloadavg()[0]:.1f})"
    )
    print("| kernel | compile CPU s (exclusive) | compilations |")
    print("|---|---|---|")
    for name, sec, n in kernels[:25]:
        print(f"| {name} | {sec:.2f} | {n} |")


if __name__ == "__main__":
    main()
