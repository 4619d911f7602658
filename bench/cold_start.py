"""Time to the first FRF branch in a fresh process, cold and warm Numba cache.

Run: ``python -m bench.cold_start`` (from the repository root).

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
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
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


def main() -> None:
    for k, v in measure().items():
        print(f"{k:>10}: {v:.2f}")


if __name__ == "__main__":
    main()
