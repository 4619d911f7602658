"""Benchmarks of the rigid Coulomb contact (DLFT), pytest-benchmark.

Run: ``python -m pytest bench/test_bench_coulomb.py --benchmark-only``.
Figures: ``bench/README.md`` (section "Rigid Coulomb").
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.hbm import HBMProblem

sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
from test_coulomb import den_hartog, is_non_stop  # noqa: E402

C, FS, P = 0.02, 0.3, 1.0
#: located DLFT without the tail (``linear_tail=False``)
OSC = hf.Oscillator(1.0, C, 1.0, hf.Coulomb(slip_force=FS, linear_tail=False))
#: the default: with the linear tail
TAIL = OSC.with_contact(hf.Coulomb(slip_force=FS))


def _branch_error(branch):
    """Largest relative error of the peak amplitude against Den Hartog over
    the non-stop points of the branch (away from the resonance itself)."""
    errors = [
        abs(a / den_hartog(C, FS, P, w)[0] - 1.0)
        for w, a in zip(branch.omega, branch.amplitude(), strict=True)
        if abs(w - 1.0) > 0.05 and is_non_stop(C, FS, P, w)
    ]
    return max(errors), len(errors)


@pytest.mark.parametrize("aft", ["tail", "events", "samples"])
def test_coulomb_frf_branch_h31(benchmark, aft):
    """Whole FRF branch 0.3-3 rad/s at H = 31 (stop and non-stop regimes):
    with the linear tail (default), located without it, classic."""
    osc = TAIL if aft == "tail" else OSC
    aft = "events" if aft == "tail" else aft
    branch = benchmark.pedantic(
        hf.frf,
        args=(osc, P, (0.3, 3.0), 31),
        kwargs={"aft": aft},
        rounds=3,
        iterations=1,
    )
    assert branch.stop_reason == "end of frequency range reached"
    error, checked = _branch_error(branch)
    benchmark.extra_info.update(
        points=len(branch),
        newton=branch.newton_iterations,
        max_error_vs_den_hartog=error,
        non_stop_points=checked,
    )


@pytest.mark.parametrize("aft", ["events", "samples"])
def test_dlft_residual_h31(benchmark, aft):
    """One residual-and-Jacobian evaluation in the non-stop regime, H = 31."""
    problem = HBMProblem(OSC, P, 31, aft=aft)
    sol = hf.periodic_solution(OSC, P, 0.7, harmonics=31, aft=aft)
    y = np.append(sol.coefficients.reshape(-1), 0.7)
    benchmark(problem.residual, y)
    benchmark.extra_info["n_time"] = problem.n_time
    assert math.isfinite(float(np.max(np.abs(problem.residual(y)[0]))))


@pytest.mark.parametrize("tail", [False, True])
def test_dlft_tail_residual_h31(benchmark, tail):
    """One residual-and-Jacobian evaluation in the non-stop regime, H = 31,
    located scheme without and with the linear tail."""
    osc = TAIL if tail else OSC
    problem = HBMProblem(osc, P, 31)
    sol = hf.periodic_solution(osc, P, 0.7, harmonics=31)
    y = np.append(sol.coefficients.reshape(-1), 0.7)
    benchmark(problem.residual, y)
    benchmark.extra_info["error_first_harmonic"] = abs(
        sol.amplitude(harmonic=1) / _first_harmonic(0.7) - 1.0
    )


@pytest.mark.parametrize("tail", [False, True])
def test_dlft_tail_branch_non_stop(benchmark, tail):
    """Branch 0.6-3 rad/s (non-stop regime only), H = 31, without and with
    the linear tail."""
    osc = TAIL if tail else OSC
    branch = benchmark.pedantic(
        hf.frf, args=(osc, P, (0.6, 3.0), 31), rounds=2, iterations=1
    )
    assert branch.stop_reason == "end of frequency range reached"
    error, checked = _branch_error(branch)
    benchmark.extra_info.update(
        points=len(branch), max_error_vs_den_hartog=error, non_stop_points=checked
    )


def _first_harmonic(w):
    from test_coulomb import den_hartog_measures

    return den_hartog_measures(C, FS, P, w)[1]
