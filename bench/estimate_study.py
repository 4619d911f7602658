"""How sharp is the truncation estimate: the true error of every point of a
fixed-``H`` branch against the first-order change to larger bases.

Run: ``python -m bench.estimate_study "beam Fn=0.5 N" 21,31,45`` from the
repository root (scene names of :mod:`bench.exact_reference`).

For each ``H`` the branch is traced, every point is compared with the exact
event-driven reference (:func:`hbmfric.validation.branch_errors`; true error
= the larger of the relative errors of the first-harmonic amplitude and of
half the peak-to-peak at the contact DOF), and the first-order change of the
same two measures is computed
(:func:`hbmfric.kernels.steps.truncation.truncation_change`) to the next rung of
the ladder (``c1``, the former estimate), to two rungs up (``c2``, the
probe level of :mod:`hbmfric.continuation.adaptive`), to ``2 H + 1``
(``cx``) and to ``3 H`` (``c3``). Printed per ``H`` and change: the largest
true error over the largest change, and the worst true/change ratio at the
points whose true error is within 3 times of the branch's largest (the
points that decide the level of an adaptive run).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import sys  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

import hbmfric as hf  # noqa: E402
from hbmfric.api import _problem  # noqa: E402
from hbmfric.continuation.adaptive import _Level, next_level  # noqa: E402
from hbmfric.continuation.palc import Continuation  # noqa: E402
from hbmfric.validation import branch_errors  # noqa: E402

from .exact_reference import scenes  # noqa: E402


def study(name: str, levels: list[int]) -> dict:
    scene = next(s for s in scenes() if s.name == name)
    out = {}
    for h in levels:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.AccuracyWarning)
            branch = hf.frf(scene.system, scene.force, scene.omega, h)
        err = branch_errors(branch, scene.system, on_failure="warn")
        true = np.maximum(err.error_h1, err.error_hpp)
        problem = _problem(scene.system, scene.force, h, None, None, "auto", None)
        state, _ = Continuation(problem, scene.omega).run()
        points = np.array(state.points)[err.index]
        probes = {
            "c1": next_level(h),
            "c2": next_level(next_level(h)),
            "cx": 2 * h + 1,
            "c3": 3 * h if (3 * h) % 2 else 3 * h + 1,
        }
        row = {"omega": err.omega, "true": true}
        near = true >= true.max() / 3.0
        line = f"{name} H={h}: true max {true.max():.3g}"
        for tag, hp in probes.items():
            probe = _Level(problem.with_harmonics(hp), None)
            change = np.array([probe.change(p) for p in points])
            row[tag] = change
            worst = np.max(true[near] / np.maximum(change[near], 1e-300))
            line += (
                f" | {tag} (H={hp}): true/change max-over-max "
                f"{true.max() / change.max():.2f}, worst near max {worst:.2f}"
            )
        print(line, flush=True)
        out[h] = row
    return out


if __name__ == "__main__":
    study(sys.argv[1], [int(h) for h in sys.argv[2].split(",")])
