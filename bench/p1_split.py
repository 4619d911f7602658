"""P1's warm branch time at defaults split into the compiled kernels called
from Python and the rest (issue 18, stop 34).

Run: ``python -m bench.p1_split [--repeats 15] [--forces 0.1,0.5,2]`` from
the repository root (``PYTHONPATH`` set to the tree to measure). Each
compiled entry point the Python layer calls (the compiled stretch
``arclength.trace``, ``advance``, the corrector ``newton.correct``, the
tangents, the final pass's ``branch_truncation``, the run's calibrations
``truncation_change``, ``output_measure``, the linear response) is wrapped
with ``time.process_time``; "Python" is the branch's CPU time less theirs.
The run with the least total CPU time of ``repeats`` warm ``hf.frf`` calls
is printed per force, with the load average. The wrappers add about 1 µs
per compiled call (tens per branch).

P1: m = 1, c = 0.02, k = 1, Jenkins kt = 3, f_s = 1, Ω 0.5-3 rad/s.
"""

# ruff: noqa: E402  (BLAS threads are set before NumPy is imported)
from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import functools
import time
import warnings

import hbmfric as hf
import hbmfric.continuation.accuracy as _accuracy
import hbmfric.continuation.adaptive as _adaptive
import hbmfric.hbm as _hbm
from hbmfric.kernels.steps import arclength as _arclength
from hbmfric.kernels.steps import newton as _newton

P1_RANGE = (0.5, 3.0)

#: (module, name, label) of the compiled entry points the Python layer calls
ENTRIES = (
    (_arclength, "trace", "trace"),
    (_arclength, "advance", "advance"),
    (_newton, "correct", "correct"),
    (_newton, "tangent", "tangent"),
    (_newton, "block_tangent", "tangent"),
    (_accuracy, "branch_truncation", "final estimates"),
    (_adaptive, "truncation_change", "calibration"),
    (_adaptive, "output_measure", "output measure"),
    (_hbm, "first_harmonic_response", "linear response"),
)


def _wrap(parts: dict) -> None:
    """Time each entry of :data:`ENTRIES` into ``parts`` (label -> s)."""
    for module, name, label in ENTRIES:
        kernel = getattr(module, name)

        @functools.wraps(kernel)
        def timed(*args, _kernel=kernel, _label=label, **kwargs):
            start = time.process_time()
            try:
                return _kernel(*args, **kwargs)
            finally:
                parts[_label] = parts.get(_label, 0.0) + time.process_time() - start

        setattr(module, name, timed)


def split(forces, repeats: int) -> list[dict]:
    """Least-total run per force: total, compiled parts and Python, ms."""
    parts: dict = {}
    _wrap(parts)
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        for force in forces:
            hf.frf(osc, force, P1_RANGE, "auto")  # warm-up
            best = None
            for _ in range(repeats):
                parts.clear()
                start = time.process_time()
                hf.frf(osc, force, P1_RANGE, "auto")
                total = time.process_time() - start
                if best is None or total < best[0]:
                    best = (total, dict(parts))
            total, compiled = best
            rows.append(
                {
                    "force": force,
                    "total": 1e3 * total,
                    "compiled": {k: 1e3 * v for k, v in compiled.items()},
                    "python": 1e3 * (total - sum(compiled.values())),
                    "load": os.getloadavg()[0],
                }
            )
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=15)
    p.add_argument("--forces", default="0.1,0.5,2")
    a = p.parse_args(argv)
    forces = [float(f) for f in a.forces.split(",")]
    print(f"tree: {os.path.dirname(os.path.dirname(hf.__file__))}")
    for row in split(forces, a.repeats):
        compiled = row["compiled"]
        detail = ", ".join(
            f"{k} {v:.2f}" for k, v in sorted(compiled.items(), key=lambda x: -x[1])
        )
        print(
            f"F = {row['force']:g}: total {row['total']:.2f} ms, compiled "
            f"{sum(compiled.values()):.2f} ({detail}), Python {row['python']:.2f}; "
            f"load {row['load']:.2f}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
