"""Parameter studies: 200 FRFs of P1 over a force × normal-load grid, run
serially, in local worker processes and on a two-worker Dask LocalCluster.

Run: ``python -m bench.study [--n-forces 20] [--n-loads 10]`` from the
repository root. Prints a table (wall time, speed-up against serial, the
summed in-worker time, and the per-task overhead
``(workers × wall − Σ in-worker time) / tasks``) and writes it to
``bench/results/study.md``.

P1: ``m = 1, c = 0.02, k = 1``, Jenkins ``kt = 3``, slip force ``μ N`` with
``μ = 0.3``; forces 0.05–2 N, normal loads 1–10 N (log-spaced), Ω 0.5–3
rad/s, ``harmonics=15`` (as the engine benchmarks).
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

import hbmfric as hf

MU = 0.3


def p1(p: dict) -> hf.Oscillator:
    """P1 with slip force μ N."""
    law = hf.Jenkins(stiffness=3.0, slip_force=MU * p["normal_load"])
    return hf.Oscillator(1.0, 0.02, 1.0, law)


def measure(n_forces: int = 20, n_loads: int = 10, workers: int = 2) -> list[dict]:
    params = hf.grid(
        force=np.geomspace(0.05, 2.0, n_forces).tolist(),
        normal_load=np.geomspace(1.0, 10.0, n_loads).tolist(),
    )
    opts = dict(harmonics=15)
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        # warm every path once (compiled kernels loaded in this process)
        hf.study(p1, params[:2], (0.5, 3.0), executor="serial", **opts)
        for label, kwargs in (
            ("serial", dict(executor="serial")),
            (f"processes ({workers})", dict(workers=workers)),
        ):
            t = time.perf_counter()
            res = hf.study(p1, params, (0.5, 3.0), **kwargs, **opts)
            rows.append(_row(label, res, time.perf_counter() - t, workers))
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            return rows
        with (
            LocalCluster(
                n_workers=workers, threads_per_worker=1, dashboard_address=None
            ) as cluster,
            Client(cluster) as client,
        ):
            hf.study(p1, params[:4], (0.5, 3.0), client=client, **opts)  # warm
            t = time.perf_counter()
            res = hf.study(p1, params, (0.5, 3.0), client=client, **opts)
            rows.append(
                _row(
                    f"Dask LocalCluster ({workers})",
                    res,
                    time.perf_counter() - t,
                    workers,
                )
            )
    serial = rows[0]["wall_s"]
    for r in rows:
        r["speedup"] = serial / r["wall_s"]
    return rows


def _row(label: str, res, wall: float, workers: int) -> dict:
    busy = sum(r.elapsed for r in res.runs)
    n = len(res)
    used = 1 if label == "serial" else workers
    return {
        "executor": label,
        "tasks": n,
        "failed": len(res.failures),
        "wall_s": wall,
        "in_worker_s": busy,
        "overhead_ms": 1e3 * (used * wall - busy) / n,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-forces", type=int, default=20)
    ap.add_argument("--n-loads", type=int, default=10)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path("bench/results"))
    a = ap.parse_args()
    rows = measure(a.n_forces, a.n_loads, a.workers)
    lines = [
        "| executor | tasks | failed | wall (s) | speed-up | Σ in-worker (s) "
        "| overhead per task (ms) |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['executor']} | {r['tasks']} | {r['failed']} | {r['wall_s']:.2f} | "
            f"{r['speedup']:.2f} | {r['in_worker_s']:.2f} | {r['overhead_ms']:.1f} |"
        )
    text = "\n".join(lines)
    print(text)
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / "study.md").write_text(text + "\n")


if __name__ == "__main__":
    main()
