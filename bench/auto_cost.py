"""Cost of ``harmonics="auto"`` against the best fixed ``H`` (issue 14).

Run: ``python -m bench.auto_cost [--repeats 5] [--scenes a,b] [--profile]``
from the repository root.

For each scene (the belt tensioner at f1 = 2 and 5 N over 5-100 Hz, the
paper beam with a Jenkins tip at Fn = 5, 1 and 0.5 N over 15-110 Hz, all
at ``hf.frf`` defaults) the default ``hf.frf`` (auto) and the smallest
fixed ``H`` that meets 1e-4 against the scene's independent reference
(bench/README.md: shooting for the tensioner, the exact event-driven
solution for the beam) are timed in the same process, interleaved
(auto, H1, H2, auto, H1, H2, ...), least of ``repeats`` warm runs.

``--profile`` splits one auto run of each scene: the adaptive trace
(:meth:`AdaptiveContinuation.run`), its calibrations and re-solves, the
final pass (:meth:`AdaptiveContinuation.settle`: the final estimates and
the re-solves of points over the tolerance) and the rest (branch
assembly, tangents, curve errors).
"""

# ruff: noqa: E402  (BLAS threads are set before NumPy is imported)
from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

import hbmfric as hf
from hbmfric.continuation import accuracy as _accuracy
from hbmfric.continuation import adaptive as _adaptive
from hbmfric.paper.beam import HZ, paper_beam, paper_calibration


@dataclass(frozen=True)
class Scene:
    name: str
    system: object
    force: float
    omega: tuple[float, float]
    #: fixed H compared with (the smallest meeting 1e-4, and its neighbour)
    fixed: tuple[int, ...]


def scenes() -> list[Scene]:
    rig = hf.BeltTensioner()
    band = (2.0 * math.pi * 5.0, 2.0 * math.pi * 100.0)
    cal = paper_calibration()
    beam = (15.0 * HZ, 110.0 * HZ)
    return [
        Scene("tensioner 2 N", rig, 2.0, band, (11, 15)),
        Scene("tensioner 5 N", rig, 5.0, band, (15, 21)),
        Scene("beam Fn=5 N", paper_beam(5.0, cal), 2.0, beam, (11, 13)),
        Scene("beam Fn=1 N", paper_beam(1.0, cal), 2.0, beam, (23, 27)),
        Scene("beam Fn=0.5 N", paper_beam(0.5, cal), 2.0, beam, (41,)),
    ]


def _frf(scene: Scene, harmonics):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        return hf.frf(scene.system, scene.force, scene.omega, harmonics)


def compare(scene: Scene, repeats: int) -> dict:
    """Least warm time of auto and of each fixed H, interleaved."""
    keys = ["auto", *scene.fixed]
    for k in keys:  # warm (levels built once per process are not cached)
        branch = _frf(scene, k)
        if k == "auto":
            auto = branch
    least = dict.fromkeys(keys, math.inf)
    for _ in range(repeats):
        for k in keys:
            t = time.perf_counter()
            _frf(scene, k)
            least[k] = min(least[k], time.perf_counter() - t)
    levels, counts = np.unique(auto.point_harmonics, return_counts=True)
    return {
        "scene": scene.name,
        "auto_ms": 1e3 * least["auto"],
        "fixed_ms": {h: 1e3 * least[h] for h in scene.fixed},
        "points": len(auto),
        "levels": " ".join(f"{h}:{c}" for h, c in zip(levels, counts, strict=True)),
        "estimate_max": float(np.max(auto.truncation_error)),
        "info": {
            k: auto.info.get(k)
            for k in (
                "harmonic_switches",
                "harmonic_resolves",
                "harmonic_settled",
                "harmonic_calibrations",
            )
        },
    }


def profile(scene: Scene, repeats: int = 3) -> dict:
    """Split of the least of ``repeats`` auto runs (wall time of
    ``run``, ``settle``, the final estimates inside ``settle`` and the
    whole ``frf``)."""
    cls = _adaptive.AdaptiveContinuation
    run0, settle0, change0 = cls.run, cls.settle, _adaptive._Level.change
    est0 = _accuracy.truncation_errors
    spent = {}

    def timer(name, fn):
        def wrapped(*a, **k):
            t = time.perf_counter()
            out = fn(*a, **k)
            spent[name] = spent.get(name, 0.0) + time.perf_counter() - t
            spent[name + "#"] = spent.get(name + "#", 0) + 1
            return out

        return wrapped

    best = None
    try:
        cls.run = timer("run", run0)
        cls.settle = timer("settle", settle0)
        _adaptive._Level.change = timer("python_calibration", change0)
        _frf(scene, "auto")
        for _ in range(repeats):
            spent.clear()
            est = timer("final_estimates", est0)

            def settle(self, points, levels, estimate, _s=settle0, _e=est):
                return _s(self, points, levels, _e)

            cls.settle = timer("settle", settle)
            t = time.perf_counter()
            branch = _frf(scene, "auto")
            spent["frf"] = time.perf_counter() - t
            if best is None or spent["frf"] < best["frf"]:
                best = dict(spent)
                best["info"] = {
                    k: branch.info.get(k)
                    for k in (
                        "harmonic_switches",
                        "harmonic_resolves",
                        "harmonic_settled",
                        "harmonic_calibrations",
                    )
                }
    finally:
        cls.run, cls.settle, _adaptive._Level.change = run0, settle0, change0
    best["scene"] = scene.name
    return best


def tensioner_whole(force: float, harmonics: int, every: int = 1) -> dict:
    """Largest error of every ``every``-th point of the fixed-``H`` branch of
    the tensioner at ``force`` against the shooting reference at its own
    frequency (tension range, first harmonics of both DOFs;
    :mod:`bench.tensioner_reference`), and the frequency where it is."""
    from bench import tensioner_reference as tr

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(tr.RIG, force, tr._band(), harmonics)
    values = tr.quantities(branch)
    worst, at = 0.0, math.nan
    for i in range(0, len(branch), every):
        fq = branch.omega[i] / (2.0 * math.pi)
        start = (branch.harmonic_numbers, branch.coefficients[i], branch.omega[i])
        _, rv = tr.reference(force, fq, start)
        e = float(np.max(tr._relative(values[i], rv)))
        if e > worst:
            worst, at = e, fq
    return {"force": force, "H": harmonics, "error": worst, "at_Hz": at}


def check_auto(names=None) -> list[dict]:
    """Every point of the default (auto) branch of each scene against its
    independent reference: shooting for the tensioner (tension range and
    first harmonics of both DOFs), the exact event-driven solution for the
    beam and the paper's SDOF scenes (first harmonic and half peak-to-peak
    at the contact DOF, :func:`hbmfric.validation.branch_errors`)."""
    from bench import exact_reference as er
    from bench import tensioner_reference as tr
    from hbmfric.validation import branch_errors

    rows = []
    for scene in [s for s in scenes() if s.name.startswith("tensioner")]:
        if names and scene.name not in names:
            continue
        branch = _frf(scene, "auto")
        values = tr.quantities(branch)
        worst, at = 0.0, math.nan
        for i in range(len(branch)):
            fq = branch.omega[i] / (2.0 * math.pi)
            start = (branch.harmonic_numbers, branch.coefficients[i], branch.omega[i])
            _, rv = tr.reference(scene.force, fq, start)
            e = float(np.max(tr._relative(values[i], rv)))
            if e > worst:
                worst, at = e, fq
        rows.append(
            {
                "scene": scene.name,
                "points": len(branch),
                "error": worst,
                "at": at,
                "estimate_max": float(np.max(branch.truncation_error)),
            }
        )
        print(rows[-1], flush=True)
    for scene in er.scenes():
        if names and scene.name not in names:
            continue
        branch = _frf(scene, "auto")
        err = branch_errors(branch, scene.system, on_failure="raise")
        true = np.maximum(err.error_h1, err.error_hpp)
        i = int(np.argmax(true))
        rows.append(
            {
                "scene": scene.name,
                "points": len(branch),
                "error": float(true[i]),
                "at": float(err.omega[i]),
                "estimate_max": float(np.max(branch.truncation_error)),
            }
        )
        print(rows[-1], flush=True)
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--scenes", default="", help="comma-separated scene names")
    p.add_argument("--profile", action="store_true")
    p.add_argument(
        "--check",
        action="store_true",
        help="every point of each default branch against its reference",
    )
    p.add_argument(
        "--whole",
        default="",
        help="force:H,... fixed-H tensioner branches checked point by point",
    )
    a = p.parse_args(argv)
    names = [s.strip() for s in a.scenes.split(",") if s.strip()]
    if a.check:
        check_auto(names)
        return 0
    if a.whole:
        for item in a.whole.split(","):
            f, h = item.split(":")
            print(tensioner_whole(float(f), int(h)), flush=True)
        return 0
    print(f"load: {os.getloadavg()}", flush=True)
    for scene in scenes():
        if names and scene.name not in names:
            continue
        if a.profile:
            s = profile(scene)
            print(
                scene.name,
                " ".join(
                    f"{k}={v * 1e3:.1f}ms" if isinstance(v, float) else f"{k}={v}"
                    for k, v in s.items()
                    if k != "scene"
                ),
                flush=True,
            )
            continue
        r = compare(scene, a.repeats)
        fixed = ", ".join(
            f"H={h}: {t:.1f} ms ({r['auto_ms'] / t:.2f}x)"
            for h, t in r["fixed_ms"].items()
        )
        print(
            f"{r['scene']}: auto {r['auto_ms']:.1f} ms, {fixed}; {r['points']} "
            f"points {r['levels']}; est max {r['estimate_max']:.2g}; {r['info']}",
            flush=True,
        )
    print(f"load: {os.getloadavg()}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
