"""The straight lines between points at two harmonic levels (issue 18,
stop 31): ``Branch.curve_errors`` against fixed-frequency solves, on the
intervals joining two levels and on intervals within one level.

Run: ``python -m bench.level_joins [--cases p1_0.5,p1_2,menq,iwan,beam1,readme]``
from the repository root (the README example takes about 10 minutes of
CPU: its joins at H >= 21 are checked at H = 63). Per case: every join not
across a fold or between two pieces, and 30 intervals within one level
(the 15 of largest estimate, 15 at random); the truth at 7 instants inside
and at both ends (:func:`test_level_joins.line_distances`, whose *whole*
is the line against the solves and *chord* the same less the straight
line between the ends' own errors). Prints the ratio estimate/truth (min,
median, max over intervals where either exceeds 1e-5) and the largest
absolute difference from the chord's truth.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

import hbmfric as hf

sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
from stress.test_stop31_level_joins import _case  # noqa: E402
from test_level_joins import line_distances  # noqa: E402

CASES = ("p1_0.5", "p1_2", "menq", "iwan", "beam1", "readme")
WITHIN = 30
INSTANTS = 7


def intervals(b: hf.Branch) -> tuple[np.ndarray, np.ndarray]:
    """(joins, within): interval indices, folds and piece joins left out."""
    t = b.tangents[:, -1]
    ok = ((t[:-1] > 0.0) == (t[1:] > 0.0)) & (np.diff(b.omega) != 0.0)
    if b.pieces is not None:
        for p in b.pieces:
            if 0 < p < len(b):
                ok[p - 1] = False
    step = np.diff(b.point_harmonics) != 0
    joins, within = np.flatnonzero(step & ok), np.flatnonzero(~step & ok)
    est = b.curve_errors
    big = within[np.argsort(est[within])[::-1][: WITHIN // 2]]
    rng = np.random.default_rng(0)
    spread = rng.choice(within, min(WITHIN // 2, within.size), replace=False)
    return joins, np.unique(np.concatenate((big, spread)))


def measure(name: str) -> dict:
    system, force, omega = _case(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        b = hf.frf(system, force, omega)
    est = b.curve_errors
    out = {}
    for kind, idx in zip(("joins", "within"), intervals(b), strict=True):
        rows = []
        for i in idx:
            whole, chord = line_distances(system, b, int(i), INSTANTS)
            rows.append((est[i], whole, chord))
        out[kind] = np.array(rows).reshape(-1, 3)
    return out


def summary(rows: np.ndarray, col: int) -> str:
    big = (rows[:, 0] > 1e-5) | (rows[:, col] > 1e-5)
    if not np.any(big):
        return "-"
    q = rows[big, 0] / rows[big, col]
    return f"{q.min():.2f}-{np.median(q):.2f}-{q.max():.2f}"


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", default=",".join(CASES))
    a = p.parse_args(argv)
    print("| case | intervals | est/whole | est/chord | largest |est - chord| |")
    print("|---|---|---|---|---|")
    for name in [c.strip() for c in a.cases.split(",") if c.strip()]:
        for kind, rows in measure(name).items():
            diff = np.max(np.abs(rows[:, 0] - rows[:, 2]), initial=0.0)
            print(
                f"| {name} | {len(rows)} {kind} | {summary(rows, 1)} | "
                f"{summary(rows, 2)} | {diff:.1e} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
