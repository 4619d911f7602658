"""Issue 15: the lap joint's branch time against the number of contact
pairs N, condensed and (for small N) uncondensed, with where the time goes.

``python -m bench.lap_scaling [N ...] [--full N ...]`` runs one warm branch
per N (:func:`bench.lap_speed.branch`: H = 15, 125-185 Hz, Fex/P = 1e-3,
``max_step = 0.05``; a short 160-161 Hz branch first in the same process
warms the kernels of that N), each in a fresh process, and the residual's
split at 162 Hz (:mod:`bench.lap_split`'s receptance / AFT / inverse
shares are not re-measured here: see bench/README.md). Writes
``bench/results/lap_scaling.csv`` and ``lap_scaling.png`` (CPU seconds
against N on log axes, with the issue's goals 0.5 / 3 / 20 s marked).
One BLAS thread.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import csv  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

RESULTS = Path(__file__).parent / "results"
GOALS = {10: 0.5, 40: 3.0, 100: 20.0}  # issue 15, s (warm, this 2-core machine)


def _one(n_pairs: int, condense: str) -> dict:
    """One warm branch in a fresh process."""
    code = (
        "import json, warnings; warnings.simplefilter('ignore');"
        "from bench.lap_speed import branch;"
        f"branch({n_pairs}, {condense!r}, band=(160.0, 161.0));"
        f"print(json.dumps(branch({n_pairs}, {condense!r}), default=float))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        cwd=Path(__file__).parents[1],
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv: list[str]) -> None:
    full = []
    if "--full" in argv:
        k = argv.index("--full")
        full = [int(a) for a in argv[k + 1 :]]
        argv = argv[:k]
    sizes = [int(a) for a in argv] or [10, 20, 40, 70, 100]
    rows = []
    for n in sizes:
        rows.append(_one(n, "state"))
        print(rows[-1], flush=True)
    for n in full:
        rows.append(_one(n, "false"))
        print(rows[-1], flush=True)
    RESULTS.mkdir(exist_ok=True)
    keys = ["n_pairs", "condense", "cpu_seconds", "seconds", "points", "load"]
    keys += ["peak_m_per_N", "peak_Hz", "curve_error_max"]
    with open(RESULTS / "lap_scaling.csv", "w", newline="") as f:
        w = csv.DictWriter(f, keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    for condense, label, style in (
        ("state", "condensed (default)", "o-"),
        ("false", "uncondensed", "s--"),
    ):
        pts = [
            (r["n_pairs"], r["cpu_seconds"]) for r in rows if r["condense"] == condense
        ]
        if pts:
            ax.loglog(*zip(*pts, strict=True), style, label=label)
    ax.loglog(list(GOALS), list(GOALS.values()), "kx", ms=9, label="issue 15 goals")
    ax.set_xlabel("contact pairs N")
    ax.set_ylabel("branch CPU time, s (warm, H = 15)")
    ax.set_title("Lap joint: one FRF branch through stick-slip")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(RESULTS / "lap_scaling.png", dpi=120)
    print(f"wrote {RESULTS / 'lap_scaling.csv'} and lap_scaling.png")


if __name__ == "__main__":
    main(sys.argv[1:])
