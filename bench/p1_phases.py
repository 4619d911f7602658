"""Where P1's compiled trace spends its time, phase by phase (issue 18,
stop 35).

Run: ``python -m bench.p1_phases [--forces 0.5,2] [--repeats 20]`` from
the repository root (needs ``gcc``). It copies ``hbmfric`` into a temporary
directory, inserts cycle-counter reads (``rdtsc``, a tiny C library called
through ctypes, which compiled code can call) around the phases of
:func:`hbmfric.kernels.steps.arclength.trace` and of the calibrations, and
runs P1 at default settings (``harmonics="auto"``) in a child process on
that copy, with a fresh Numba cache directory (the instrumented kernels
hold the library's addresses: never cached across processes). The first
run compiles every kernel: a few minutes.

Printed per force: the branch's least CPU time (``time.process_time``,
the instrumented code: a few % above the plain one), and per phase the
least over the repeats of its summed time (wall clock from the cycle
counter: a phase preempted by another process reads long, so each phase
takes its own least; they need not add up exactly) and its count:

- ``trace``: the compiled stretches as a whole;
- ``advance (accepted / rejected)``: the steps, by outcome;
- ``predict``, ``correct``: the predictor and the corrector with its new
  tangent (:func:`~hbmfric.kernels.steps.newton.palc_correct`), within it
  ``residual`` (every evaluation), ``rows + LU + solve`` (the bordered
  matrix built, factored, solved), ``lagged solve`` (a confirming
  evaluation's update from the previous factors) and ``tangent``;
- ``chord``: the curve rule's chord estimate; ``stays``: the level rule,
  within it ``calibration (run)``; ``next step``;
- ``calibration (final pass)``: the final estimates' calibrations
  (:func:`~hbmfric.kernels.steps.truncation.branch_truncation`), and
  every calibration's parts: ``probe residual``, ``probe solve``,
  ``extremes`` (the rest of
  :func:`~hbmfric.kernels.steps.truncation.truncation_change`);
- the residual, the LU and the tangent by order of the system.

The instrumentation is a list of text insertions (:data:`PATCHES`); one
whose anchor is not found exactly once stops the tool with the anchor's
text (the kernels changed: update the anchor).
"""

# ruff: noqa: E402  (BLAS threads are set before NumPy is imported)
from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
import warnings

C_SOURCE = r"""
#include <stdint.h>
#include <x86intrin.h>
static uint64_t acc[256]; static uint64_t cnt[256]; static uint64_t t0[256];
void ptic(int64_t k){ t0[k] = __rdtsc(); }
void ptoc(int64_t k){ acc[k] += __rdtsc() - t0[k]; cnt[k]++; }
void ptoc2(int64_t s, int64_t k){ acc[k] += __rdtsc() - t0[s]; cnt[k]++; }
uint64_t pget(int64_t k){ return acc[k]; }
uint64_t pcnt(int64_t k){ return cnt[k]; }
void preset(void){ for (int i = 0; i < 256; i++) { acc[i] = 0; cnt[i] = 0; } }
"""

PROF_MODULE = """import ctypes

_lib = ctypes.CDLL({path!r})
ptic = _lib.ptic
ptic.argtypes = [ctypes.c_int64]
ptic.restype = None
ptoc = _lib.ptoc
ptoc.argtypes = [ctypes.c_int64]
ptoc.restype = None
ptoc2 = _lib.ptoc2
ptoc2.argtypes = [ctypes.c_int64, ctypes.c_int64]
ptoc2.restype = None
pget = _lib.pget
pget.argtypes = [ctypes.c_int64]
pget.restype = ctypes.c_uint64
pcnt = _lib.pcnt
pcnt.argtypes = [ctypes.c_int64]
pcnt.restype = ctypes.c_uint64
preset = _lib.preset
preset.argtypes = []
preset.restype = None
"""

#: phase slots: name per counter index (by order: 100 + n // 2 residual,
#: 150 + n // 2 LU, 200 + n // 2 tangent, n the unknowns)
PHASES = {
    0: "trace",
    1: "advance, accepted",
    11: "advance, rejected",
    2: "predict",
    3: "correct (+ tangent)",
    4: "  residual",
    5: "  rows + LU + solve",
    6: "  lagged solve",
    7: "  tangent",
    8: "chord",
    9: "stays",
    10: "  calibration (run)",
    12: "next step",
    13: "calibration (final pass)",
    14: "calibration (final, over tol)",
    20: "any calibration: probe residual",
    21: "any calibration: probe solve",
    22: "any calibration: extremes",
}

_ARC = "hbmfric/kernels/steps/arclength.py"
_NEWTON = "hbmfric/kernels/steps/newton.py"
_TRUNC = "hbmfric/kernels/steps/truncation.py"
_IMPORT = "from .._prof import ptic, ptoc, ptoc2\n\n\n"

#: ``(file, anchor, replacement)``: each anchor must occur exactly once
PATCHES = [
    (_ARC, "\n@jit_inline\ndef stays(", "\n" + _IMPORT + "@jit_inline\ndef stays("),
    (
        _ARC,
        "        change = truncation_change(\n            y,\n            problem,",
        "        ptic(10)\n        change = truncation_change(\n            y,\n"
        "            problem,",
    ),
    (
        _ARC,
        "            cdX,\n        )\n        est = watch[W_CHANGE_FACTOR] * change",
        "            cdX,\n        )\n        ptoc(10)\n"
        "        est = watch[W_CHANGE_FACTOR] * change",
    ),
    (
        _ARC,
        "    predict(y, tangent, step, scale, settings, history, y_pred)\n"
        "    status, evaluations, effort, distance, angle = palc_correct(",
        "    ptic(2)\n    predict(y, tangent, step, scale, settings, history, y_pred)\n"
        "    ptoc(2)\n    ptic(3)\n"
        "    status, evaluations, effort, distance, angle = palc_correct(",
    ),
    (
        _ARC,
        "        t_new,\n    )\n    ok = status == CONVERGED\n    corner = False",
        "        t_new,\n    )\n    ptoc(3)\n    ok = status == CONVERGED\n"
        "    corner = False",
    ),
    (
        _ARC,
        "        target = chord_target(settings)\n        curve = problem_chord_error(",
        "        target = chord_target(settings)\n        ptic(8)\n"
        "        curve = problem_chord_error(",
    ),
    (
        _ARC,
        "            settings[KINK_FLOOR] != 0.0,\n        )\n        length2 = 0.0",
        "            settings[KINK_FLOOR] != 0.0,\n        )\n        ptoc(8)\n"
        "        length2 = 0.0",
    ),
    (
        _ARC,
        "    new_step = next_step(step, effort, angle, curve, settings)",
        "    ptic(12)\n    new_step = next_step(step, effort, angle, curve, settings)",
    ),
    (
        _ARC,
        "    follow_amplitude(y, tangent, scale, settings[BASE_SCALE])\n"
        "    return outcome, new_step, evaluations",
        "    follow_amplitude(y, tangent, scale, settings[BASE_SCALE])\n    ptoc(12)\n"
        "    return outcome, new_step, evaluations",
    ),
    (
        _ARC,
        "    attempts = 0\n    while True:\n        if n_accepted == capacity:",
        "    attempts = 0\n    ptic(0)\n    while True:\n"
        "        if n_accepted == capacity:\n            ptoc(0)",
    ),
    (
        _ARC,
        "        if attempts == max_attempts:\n            return BUDGET_SPENT",
        "        if attempts == max_attempts:\n            ptoc(0)\n"
        "            return BUDGET_SPENT",
    ),
    (
        _ARC,
        "        attempts += 1\n        outcome, step, spent = advance(",
        "        attempts += 1\n        ptic(1)\n"
        "        outcome, step, spent = advance(",
    ),
    (
        _ARC,
        "        evaluations += spent\n        if outcome == LEFT_RANGE:\n"
        "            return RANGE_LEFT",
        "        evaluations += spent\n"
        "        if outcome == REJECTED or outcome == STEP_TOO_SMALL:\n"
        "            ptoc2(1, 11)\n        else:\n            ptoc(1)\n"
        "        if outcome == LEFT_RANGE:\n            ptoc(0)\n"
        "            return RANGE_LEFT",
    ),
    (
        _ARC,
        "            if outcome == STEP_TOO_SMALL:\n"
        "                return STEP_BELOW_MIN",
        "            if outcome == STEP_TOO_SMALL:\n                ptoc(0)\n"
        "                return STEP_BELOW_MIN",
    ),
    (
        _ARC,
        "            if not stays(y, watch, calibration):\n"
        "                return WATCH_STOP",
        "            ptic(9)\n            stays_ = stays(y, watch, calibration)\n"
        "            ptoc(9)\n            if not stays_:\n                ptoc(0)\n"
        "                return WATCH_STOP",
    ),
    (_NEWTON, "\n@jit\ndef correct_core(", "\n" + _IMPORT + "@jit\ndef correct_core("),
    (
        _NEWTON,
        "    aft = call_residual(residual_at, y, problem, R, J)\n    evaluations = 1",
        "    ptic(4)\n    aft = call_residual(residual_at, y, problem, R, J)\n"
        "    ptoc(4)\n    ptoc2(4, 100 + R.size // 2)\n    evaluations = 1",
    ),
    (
        _NEWTON,
        "            b[n] = -g\n            lu_solve(A, piv, b)",
        "            b[n] = -g\n            ptic(6)\n            lu_solve(A, piv, b)\n"
        "            ptoc(6)",
    ),
    (
        _NEWTON,
        "        bordered_rows(problem, J, scale, A, b)\n        for i in range(n):\n"
        "            rows[i] = b[i]",
        "        ptic(5)\n        bordered_rows(problem, J, scale, A, b)\n"
        "        for i in range(n):\n            rows[i] = b[i]",
    ),
    (
        _NEWTON,
        "        if not bordered_solve(problem, A, piv, b):\n"
        "            return SINGULAR, evaluations, evaluations, False\n"
        "        factored",
        "        solved_ = bordered_solve(problem, A, piv, b)\n        ptoc(5)\n"
        "        ptoc2(5, 150 + R.size // 2)\n        if not solved_:\n"
        "            return SINGULAR, evaluations, evaluations, False\n"
        "        factored",
    ),
    (
        _NEWTON,
        "            aft = call_residual(residual_at, y_try, problem, R, J)\n"
        "            evaluations += 1",
        "            ptic(4)\n"
        "            aft = call_residual(residual_at, y_try, problem, R, J)\n"
        "            ptoc(4)\n            ptoc2(4, 100 + R.size // 2)\n"
        "            evaluations += 1",
    ),
    (
        _NEWTON,
        "    if lagged:\n"
        "        ok = lagged_tangent(J, scale, tangent_prev, A, piv, rows, t_new)\n"
        "    else:\n        ok = bordered_tangent(problem, A, piv, t_new)",
        "    ptic(7)\n    if lagged:\n"
        "        ok = lagged_tangent(J, scale, tangent_prev, A, piv, rows, t_new)\n"
        "    else:\n        ok = bordered_tangent(problem, A, piv, t_new)\n"
        "    ptoc(7)\n    ptoc2(7, 200 + y_pred.size // 2)",
    ),
    (
        _TRUNC,
        "\n@jit\ndef truncation_change(",
        "\n" + _IMPORT + "@jit\ndef truncation_change(",
    ),
    (
        _TRUNC,
        "    status = call_residual(residual_at, y, problem, R, J)\n"
        "    if status < 0:\n        return np.inf\n    for i in range(n):\n"
        "        dX[i] = -R[i]\n"
        "    if not probe_solve(problem, J, A, dX, n_dof, n_coef, first):\n"
        "        return np.inf",
        "    ptic(20)\n    status = call_residual(residual_at, y, problem, R, J)\n"
        "    ptoc(20)\n    if status < 0:\n        return np.inf\n"
        "    for i in range(n):\n        dX[i] = -R[i]\n    ptic(21)\n"
        "    solved_ = probe_solve(problem, J, A, dX, n_dof, n_coef, first)\n"
        "    ptoc(21)\n    ptic(22)\n    if not solved_:\n        return np.inf",
    ),
    (
        _TRUNC,
        "    if e > worst:\n        worst = e\n    if not np.isfinite(worst):",
        "    if e > worst:\n        worst = e\n    ptoc(22)\n"
        "    if not np.isfinite(worst):",
    ),
    (
        _TRUNC,
        "        elif chosen[i]:\n            change = truncation_change(",
        "        elif chosen[i]:\n            ptic(13)\n"
        "            change = truncation_change(",
    ),
    (
        _TRUNC,
        "            errors[i] = factor * change\n        if chosen[i]:",
        "            ptoc(13)\n            errors[i] = factor * change\n"
        "        if chosen[i]:",
    ),
    (
        _TRUNC,
        "        if errors[i] > tolerance and confirmed < max_confirmed:\n"
        "            change = truncation_change(",
        "        if errors[i] > tolerance and confirmed < max_confirmed:\n"
        "            ptic(14)\n            change = truncation_change(",
    ),
    (
        _TRUNC,
        "            errors[i] = factor * change\n"
        "            if errors[i] > tolerance:",
        "            ptoc(14)\n            errors[i] = factor * change\n"
        "            if errors[i] > tolerance:",
    ),
]


def instrument(tree: str, work: str) -> str:
    """Copy ``tree``'s package into ``work``, build the counter library and
    apply :data:`PATCHES`; returns the directory to put on ``PYTHONPATH``."""
    dst = os.path.join(work, "src")
    shutil.copytree(
        os.path.join(tree, "hbmfric"),
        os.path.join(dst, "hbmfric"),
        ignore=shutil.ignore_patterns("__pycache__"),
    )
    c_file = os.path.join(work, "prof.c")
    lib = os.path.join(work, "libprof.so")
    with open(c_file, "w") as f:
        f.write(C_SOURCE)
    subprocess.run(["gcc", "-O2", "-shared", "-fPIC", "-o", lib, c_file], check=True)
    with open(os.path.join(dst, "hbmfric", "kernels", "_prof.py"), "w") as f:
        f.write(PROF_MODULE.format(path=lib))
    for rel, old, new in PATCHES:
        path = os.path.join(dst, rel)
        with open(path) as f:
            text = f.read()
        if text.count(old) != 1:
            raise SystemExit(
                f"p1_phases: anchor found {text.count(old)} times in {rel}:\n{old}"
            )
        with open(path, "w") as f:
            f.write(text.replace(old, new))
    return dst


def child(forces, repeats: int) -> None:
    """Run in the instrumented copy: time P1 and print the phases."""
    from hbmfric.kernels._prof import pcnt, pget, preset, ptic, ptoc

    import hbmfric as hf

    print(f"instrumented copy: {os.path.dirname(hf.__file__)}", flush=True)

    ptic(255)
    t = time.perf_counter()
    time.sleep(0.3)
    ptoc(255)
    per_ms = pget(255) / (time.perf_counter() - t) / 1e3  # counter ticks per ms
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        for force in forces:
            hf.frf(osc, force, (0.5, 3.0))
            cpu = float("inf")
            least = {}
            counts = {}
            for _ in range(repeats):
                preset()
                c = time.process_time()
                b = hf.frf(osc, force, (0.5, 3.0))
                cpu = min(cpu, time.process_time() - c)
                for k in range(255):
                    n = pcnt(k)
                    if n:
                        ms = pget(k) / per_ms
                        least[k] = min(least.get(k, float("inf")), ms)
                        counts[k] = n
            print(
                f"F = {force}: {len(b.omega)} points, branch {1e3 * cpu:.2f} ms CPU "
                f"(least of {repeats}, instrumented); phases, ms (least) and count:"
            )
            for k, name in PHASES.items():
                if k in least:
                    print(f"  {name:34s} {least[k]:7.3f}  {counts[k]:5d}")
            for base, name in (
                (100, "residual"),
                (150, "rows + LU + solve"),
                (200, "tangent"),
            ):
                cells = [
                    f"n={2 * (k - base)}-{2 * (k - base) + 1}: {least[k]:.3f} ms / "
                    f"{counts[k]} ({1e3 * least[k] / counts[k]:.2f} µs)"
                    for k in range(base, base + 50)
                    if k in least
                ]
                print(f"  {name} by unknowns: " + "; ".join(cells))
            sys.stdout.flush()


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--forces", default="0.5,2")
    p.add_argument("--repeats", type=int, default=20)
    p.add_argument("--tree", default=os.path.dirname(os.path.dirname(__file__)))
    p.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    forces = [float(f) for f in a.forces.split(",")]
    if a.child:
        child(forces, a.repeats)
        return 0
    tree = os.path.abspath(a.tree)
    with tempfile.TemporaryDirectory(prefix="p1_phases_") as work:
        src = instrument(tree, work)
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join([src, tree])
        env["HBMFRIC_CACHE_DIR"] = os.path.join(work, "cache")
        env["HBMFRIC_QUIET"] = "1"
        print(f"tree {tree}; load {os.getloadavg()}", flush=True)
        cmd = [sys.executable, "-m", "bench.p1_phases", "--child"]
        cmd += ["--forces", a.forces, "--repeats", str(a.repeats)]
        # run from ``work``: the tree's own package must not shadow the copy
        subprocess.run(cmd, env=env, cwd=work, check=True)
        print(f"load {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
