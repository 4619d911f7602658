"""Benchmarks of the engine (pytest-benchmark; not part of the test run).

Run: ``python -m pytest bench --benchmark-only``. Figures: ``bench/README.md``.
"""

import subprocess
import sys
import time

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.aft.schemes import aft_jenkins_events, aft_samples

LAW = hf.Jenkins(stiffness=3.0, slip_force=1.0)
OSC = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=LAW)


def _slipping_point(harmonics):
    sol = hf.periodic_solution(OSC, 0.5, 1.6, harmonics=harmonics)
    assert sol.contact_state.startswith("contact slips")
    return sol.coefficients[0].copy()


@pytest.mark.parametrize("harmonics", [5, 15, 31])
@pytest.mark.parametrize("scheme", ["events", "samples"])
def test_aft_with_jacobian(benchmark, harmonics, scheme):
    """One AFT evaluation (force coefficients and Jacobian) in gross slip."""
    problem = HBMProblem(OSC, 0.5, harmonics, aft=scheme)
    hn, _, _, _, _, _, codes, rows, _, inverse, forward, derivative = (
        problem.kernel_problem
    )
    code, params = codes[0], rows[0]
    X = _slipping_point(harmonics)
    F = np.empty(problem.n_coef)
    dF = np.empty((problem.n_coef, problem.n_coef))
    if scheme == "events":
        benchmark(aft_jenkins_events, params, hn, X, inverse, derivative, F, dF)
    else:
        benchmark(aft_samples, code, params, X, inverse, forward, F, dF)
    benchmark.extra_info["n_time"] = problem.n_time
    benchmark.extra_info["n_coef"] = problem.n_coef


def test_frf_branch_h15(benchmark):
    """The whole FRF branch 0.5–3.0 rad/s at H = 15 (F = 0.5)."""
    branch = benchmark(hf.frf, OSC, 0.5, (0.5, 3.0), 15)
    assert branch.stop_reason == "end of frequency range reached"
    benchmark.extra_info["points"] = len(branch)
    benchmark.extra_info["newton"] = branch.newton_iterations


@pytest.mark.parametrize("max_step", [0.08, 0.01])
def test_frf_branch_numpy_baseline(benchmark, max_step):
    """The same branch by a plain NumPy HBM with finite differences; with the
    engine's largest step (coarser trace than the engine's) and with a step
    that gives about as many points as the engine."""
    baseline = pytest.importorskip("numpy_hbm")
    result = benchmark.pedantic(
        baseline.trace_frf, kwargs={"ds_max": max_step}, rounds=3, iterations=1
    )
    benchmark.extra_info["points"] = len(result["omega"])


def test_time_integration_one_frequency(benchmark):
    """Time-integration reference to steady state at Ω = 1.2."""
    ref = benchmark.pedantic(
        hf.validation.steady_state, args=(OSC, 0.5, 1.2), rounds=3, iterations=1
    )
    assert ref.converged
    benchmark.extra_info["periods"] = ref.periods


def test_first_call_fresh_process(benchmark):
    """Import + first FRF in a new process with a warm on-disk cache."""
    code = (
        "import hbmfric as hf;"
        "o=hf.Oscillator(1.0,0.02,1.0,hf.Jenkins(stiffness=3.0,slip_force=1.0));"
        "hf.frf(o,0.5,(0.5,3.0),15)"
    )
    subprocess.run([sys.executable, "-c", code], check=True)  # warm the cache

    def run():
        t = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True)
        return time.perf_counter() - t

    benchmark.pedantic(run, rounds=3, iterations=1)
