"""Several contacts: FRF time against the number of contacts and DOFs,
condensed onto the contact coordinates and uncondensed.

A chain of ``n_dof`` unit masses (unit springs, clamped at one end, 2 %
modal damping), forced at the free end, with Jenkins contacts between
neighbouring masses (``kt = 1``, slip force 0.05) at ``n_contacts`` evenly
spaced places; ``hf.frf`` over 0.02–0.6 rad/s (the first modes) at H = 7
(odd harmonics: 8 coefficients per unknown block), once condensed onto the
``n_contacts`` contact coordinates (the default, modal receptance) and once
by the full harmonic balance (``condense=False``). Each branch is traced
once to compile, then timed (median of ``repeats``; one run when the first
took longer than ``LONG`` seconds). Branches above ``--full-max-dof`` DOFs
(uncondensed) or ``--branch-max-dof`` DOFs (condensed) are not traced.

For every case, also the cost of one Newton iteration with every contact
in gross slip (Ω = 0.3 rad/s, random coefficients of amplitude 1, twenty
times the slip displacement, so that no block of the Jacobian is
diagonal): one residual-and-Jacobian evaluation and one LU of the Jacobian
by the project's kernel (:func:`hbmfric.kernels.linalg.lu.lu_factor`, which
skips zero multipliers: the sparse full Jacobian factors faster than its
size says), condensed and uncondensed, median of ``repeats``.

Run: ``python -m bench.contacts [--repeats 3]`` from the repository root;
prints two Markdown tables and writes them to ``bench/results/contacts.md``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import warnings
from pathlib import Path

import numpy as np

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.linalg.lu import lu_factor

CASES = [
    (10, 1),
    (10, 2),
    (10, 5),
    (20, 5),
    (20, 10),
    (40, 10),
    (100, 10),
    (200, 40),
    (400, 100),
]
#: a first (warm-up) run longer than this, s: time that run only once more
LONG = 30.0
OMEGA = (0.02, 0.6)
FORCE = 0.05
HARMONICS = 7


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


def _branch(s, condense: bool, repeats: int) -> dict:
    """Time of ``hf.frf`` on ``s``: the warm run's branch, point count and
    median time."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        branch = hf.frf(s, FORCE, OMEGA, harmonics=HARMONICS, condense=condense)
        first = time.perf_counter() - t
        times = []
        for _ in range(1 if first > LONG else repeats):
            t = time.perf_counter()
            branch = hf.frf(s, FORCE, OMEGA, harmonics=HARMONICS, condense=condense)
            times.append(time.perf_counter() - t)
    assert branch.info["condensed"] == condense
    return {
        "points": branch.omega.size,
        "complete": branch.complete,
        "time": statistics.median(times),
    }


def _iteration(problem, repeats: int) -> tuple[float, float]:
    """Median times (s) of one residual-and-Jacobian evaluation and of one
    LU of the Jacobian of ``problem`` with every contact slipping."""
    n = problem.n_unknowns
    y = np.append(np.random.default_rng(0).standard_normal(n), 0.3)
    problem.residual(y)
    t_res, t_lu = [], []
    for _ in range(repeats):
        t = time.perf_counter()
        _, J, _ = problem.residual(y)
        t_res.append(time.perf_counter() - t)
        A = np.ascontiguousarray(J[:, :n])
        piv = np.empty(n, dtype=np.int64)
        t = time.perf_counter()
        lu_factor(A, piv)
        t_lu.append(time.perf_counter() - t)
    return statistics.median(t_res), statistics.median(t_lu)


def measure(
    repeats: int = 3, full_max_dof: int = 40, branch_max_dof: int = 200
) -> list[dict]:
    rows = []
    for n_dof, n_contacts in CASES:
        s = chain(n_dof, n_contacts)
        condensed = CondensedHBMProblem(s, FORCE, HARMONICS)
        full = HBMProblem(s, FORCE, HARMONICS)
        row = {
            "n_dof": n_dof,
            "n_contacts": n_contacts,
            "unknowns": condensed.n_unknowns,
            "full_unknowns": full.n_unknowns,
            "iteration": _iteration(condensed, repeats),
            "full_iteration": _iteration(full, 1 if n_dof > 100 else repeats),
            "condensed": None,
            "full": None,
        }
        if n_dof <= branch_max_dof:
            row["condensed"] = _branch(s, True, repeats)
        if n_dof <= full_max_dof:
            row["full"] = _branch(s, False, repeats)
        rows.append(row)
        print(row, flush=True)
    return rows


def _cell(b: dict | None) -> str:
    if b is None:
        return "— | — | —"
    mark = "" if b["complete"] else " (incomplete)"
    per_point = 1e3 * b["time"] / b["points"]
    return f"{b['points']}{mark} | {b['time']:.2f} | {per_point:.2f}"


def table(rows: list[dict]) -> str:
    lines = [
        "| DOFs | contacts | unknowns cond. / full | condensed: points | s | "
        "ms/point | full: points | s | ms/point | speed-up |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        c, f = r["condensed"], r["full"]
        gain = f"{f['time'] / c['time']:.1f}x" if c and f else "—"
        lines.append(
            f"| {r['n_dof']} | {r['n_contacts']} | {r['unknowns']} / "
            f"{r['full_unknowns']} | {_cell(c)} | {_cell(f)} | {gain} |"
        )
    lines += [
        "",
        "One Newton iteration, every contact slipping (Ω = 0.3 rad/s), ms:",
        "",
        "| DOFs | contacts | condensed: residual | LU | full: residual | LU |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        (a, b), (c, d) = r["iteration"], r["full_iteration"]
        lines.append(
            f"| {r['n_dof']} | {r['n_contacts']} | {1e3 * a:.2f} | {1e3 * b:.2f} "
            f"| {1e3 * c:.2f} | {1e3 * d:.1f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--full-max-dof", type=int, default=40)
    parser.add_argument("--branch-max-dof", type=int, default=200)
    args = parser.parse_args(argv)
    load = os.getloadavg()
    text = table(measure(args.repeats, args.full_max_dof, args.branch_max_dof))
    text += (
        f"\n\nLoad average at the start: {load[0]:.1f}, at the end: "
        f"{os.getloadavg()[0]:.1f} (2 cores)."
    )
    print(text)
    out = Path(__file__).parent / "results" / "contacts.md"
    out.write_text("# Several contacts (python -m bench.contacts)\n\n" + text + "\n")


if __name__ == "__main__":
    main()
