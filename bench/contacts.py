"""Several contacts: FRF time against the number of contacts and DOFs.

A chain of ``n_dof`` unit masses (unit springs, clamped at one end, 2 %
modal damping), forced at the free end, with Jenkins contacts between
neighbouring masses (``kt = 1``, slip force 0.05) at ``n_contacts`` evenly
spaced places; ``hf.frf`` over 0.02–0.6 rad/s (the first modes) at H = 7,
solved by the full harmonic balance (several contacts are not condensed).
Each case is traced once to compile, then timed (median of ``repeats``).

Run: ``python -m bench.contacts [--repeats 3]`` from the repository root;
prints a Markdown table and writes it to ``bench/results/contacts.md``.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

import hbmfric as hf

CASES = [(10, 1), (10, 2), (10, 5), (20, 5), (20, 10), (40, 10)]


def chain(n_dof: int, n_contacts: int) -> hf.LinearStructure:
    """The chain of the module docstring."""
    K = 2.0 * np.eye(n_dof) - np.eye(n_dof, k=1) - np.eye(n_dof, k=-1)
    K[-1, -1] = 1.0
    law = hf.Jenkins(stiffness=1.0, slip_force=0.05)
    places = np.linspace(0, n_dof - 2, n_contacts).round().astype(int)
    return hf.LinearStructure(
        np.eye(n_dof),
        K,
        modal_damping=0.02,
        load={n_dof - 1: 1.0},
        contacts=[hf.Contact(law, int(p), int(p) + 1) for p in places],
    )


def measure(repeats: int = 3) -> list[dict]:
    rows = []
    for n_dof, n_contacts in CASES:
        s = chain(n_dof, n_contacts)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            branch = hf.frf(s, 0.05, (0.02, 0.6), harmonics=7)
            times = []
            for _ in range(repeats):
                t = time.perf_counter()
                branch = hf.frf(s, 0.05, (0.02, 0.6), harmonics=7)
                times.append(time.perf_counter() - t)
        rows.append(
            {
                "n_dof": n_dof,
                "n_contacts": n_contacts,
                "unknowns": branch.coefficients.shape[1] * branch.coefficients.shape[2],
                "points": branch.omega.size,
                "complete": branch.complete,
                "time": statistics.median(times),
            }
        )
    return rows


def table(rows: list[dict]) -> str:
    lines = [
        "| DOFs | contacts | unknowns | points | complete | time (s) | ms/point |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['n_dof']} | {r['n_contacts']} | {r['unknowns']} | {r['points']} "
            f"| {r['complete']} | {r['time']:.3f} | "
            f"{1e3 * r['time'] / r['points']:.2f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    text = table(measure(args.repeats))
    print(text)
    out = Path(__file__).parent / "results" / "contacts.md"
    out.write_text("# Several contacts (python -m bench.contacts)\n\n" + text + "\n")


if __name__ == "__main__":
    main()
