"""Benchmarks of the contact laws (pytest-benchmark; not part of the test run).

Run: ``python -m pytest bench/test_bench_laws.py --benchmark-only``.
Figures: ``bench/README.md``. Scene of ``test_bench_engine.py``: ``m = 1,
c = 0.02, k = 1``, laws with stuck stiffness 3 and slip force 1, ``F = 0.5``,
H = 15 (odd harmonics).
"""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.aft.masing import aft_masing
from hbmfric.kernels.aft.schemes import aft_jenkins_events, aft_samples

LAWS = {
    "jenkins": hf.Jenkins(stiffness=3.0, slip_force=1.0),
    "menq": hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0, microslip_onset=0.5),
    "iwan50": hf.Iwan.segalman(
        slip_force=1.0, stiffness=3.0, chi=-0.5, beta=0.1, n_elements=50
    ),
    "iwan200": hf.Iwan.segalman(
        slip_force=1.0, stiffness=3.0, chi=-0.5, beta=0.1, n_elements=200
    ),
    "rough-jenkins": hf.Roughness(
        hf.Jenkins(stiffness=6.0, friction_coefficient=1.0, normal_load=1.0),
        limit_load=8.0,
    ),
    "rough-menq": hf.Roughness(
        hf.Menq.from_stiffness(
            stiffness=3.0,
            friction_coefficient=1.0,
            normal_load=1.0,
            microslip_onset=0.5,
        ),
        limit_load=8.0,
    ),
}
#: Ω of a point in gross slip and of one in partial slip (stuck for Jenkins)
OMEGA = {"slip": 1.6, "partial": 1.3}


def _setup(name, point, scheme):
    osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=LAWS[name])
    X = hf.periodic_solution(osc, 0.5, OMEGA[point], harmonics=15).coefficients[0]
    problem = HBMProblem(osc, 0.5, 15, aft=scheme)
    hn, _, _, _, _, _, codes, rows, _, inverse, forward, derivative = (
        problem.kernel_problem
    )
    code, params = codes[0], rows[0]
    F = np.empty(problem.n_coef)
    dF = np.empty((problem.n_coef, problem.n_coef))
    X = np.ascontiguousarray(X)
    if scheme == "samples":
        return aft_samples, (code, params, X, inverse, forward, F, dF), problem
    if name.endswith("jenkins"):
        return aft_jenkins_events, (params, hn, X, inverse, derivative, F, dF), problem
    args = (code, params, hn, X, inverse, forward, derivative, F, dF)
    return aft_masing, args, problem


@pytest.mark.parametrize("point", list(OMEGA))
@pytest.mark.parametrize("name", list(LAWS))
def test_aft_with_jacobian_h15(benchmark, name, point):
    """One AFT evaluation (force coefficients and Jacobian) at H = 15 with the
    default scheme of the law (event-located for Jenkins, located reversals
    for Menq and Iwan, n_time = 120)."""
    kernel, args, problem = _setup(name, point, "events")
    state = benchmark(kernel, *args)
    benchmark.extra_info["state"] = int(state)
    benchmark.extra_info["n_time"] = problem.n_time


@pytest.mark.parametrize("name", ["jenkins", "menq", "iwan50"])
def test_aft_sampled_h15(benchmark, name):
    """The sampled-reversal AFT (n_time = 240) at the gross-slip point."""
    kernel, args, problem = _setup(name, "slip", "samples")
    benchmark(kernel, *args)
    benchmark.extra_info["n_time"] = problem.n_time


@pytest.mark.parametrize("name", ["jenkins", "menq", "iwan50"])
def test_sdof_branch_h15(benchmark, name):
    """Whole FRF branch 0.5–3.0 rad/s at H = 15 (F = 0.5)."""
    osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=LAWS[name])
    branch = benchmark(hf.frf, osc, 0.5, (0.5, 3.0), 15)
    assert branch.stop_reason == "end of frequency range reached"
    benchmark.extra_info["points"] = len(branch)
    benchmark.extra_info["newton"] = branch.newton_iterations


@pytest.mark.parametrize("name", ["jenkins", "menq", "iwan50"])
def test_time_integration_slipping(benchmark, name):
    """Time-integration reference to steady state at Ω = 1.6 (slipping)."""
    osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=LAWS[name])
    ref = benchmark.pedantic(
        hf.validation.steady_state, args=(osc, 0.5, 1.6), rounds=3, iterations=1
    )
    assert ref.converged
    benchmark.extra_info["periods"] = ref.periods
