"""Time to the first FRF branch in a fresh process, cold and warm Numba cache.

Run: ``python -m bench.cold_start [--profile-frf] [--profile]`` (from the
repository root); ``--profile-frf`` lists the compile time of every kernel
(exclusive of the kernels it calls) of the cold first FRF, in one more fresh
process with an empty cache; ``--profile`` does the same for a cold
``hbmfric paper``.

Each run is ``python -c "import hbmfric; hbmfric.frf(...)"`` (the SDOF
Jenkins branch, H = 15) in a new interpreter with ``NUMBA_CACHE_DIR`` in a
fresh temporary directory: the first run compiles every kernel and fills the
cache (cold), the next ones load it (warm). ``import hbmfric`` alone is timed
too.
"""

from __future__ import annotations

import os
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


def _run(code: str, cache: str) -> float:
    env = dict(os.environ, NUMBA_CACHE_DIR=cache, HBMFRIC_CACHE_DIR=cache)
    t = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT, env=env)
    return time.perf_counter() - t


def measure(warm_runs: int = 3) -> dict:
    """Seconds: cold first branch, warm first branch (min), import alone."""
    with tempfile.TemporaryDirectory() as cache:
        cold = _run(FRF, cache)
        warm = min(_run(FRF, cache) for _ in range(warm_runs))
        imp = min(_run("import hbmfric", cache) for _ in range(warm_runs))
        bare = min(_run("pass", cache) for _ in range(warm_runs))
    return {"cold_s": cold, "warm_s": warm, "import_s": imp, "python_s": bare}


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
    import json

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
    for k, v in measure().items():
        print(f"{k:>10}: {v:.2f}")
    if "--profile-frf" in sys.argv:
        wall, cpu, kernels = compile_profile(code=FRF)
        _table("cold first FRF", wall, cpu, kernels)
    if "--profile" in sys.argv:
        with tempfile.TemporaryDirectory() as out:
            wall, cpu, kernels = compile_profile(["paper", "--out", out, "--no-plot"])
        _table("cold 'hbmfric paper'", wall, cpu, kernels)


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
