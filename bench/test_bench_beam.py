"""Benchmarks of the beam (pytest-benchmark; not part of the test run).

Run: ``python -m pytest bench/test_bench_beam.py --benchmark-only``.
Figures: ``bench/README.md`` (section "Clamped beam").

The scene: the calibrated paper beam (39 DOFs), Jenkins tip contact with
μ = 1.5, Fn = 5 N, Fex = 2 N (stuck at both ends of the range, slipping
around the stuck resonance), Ω over 15–110 Hz (in rad/s), H = 15.
"""

import numpy as np
import pytest

import hbmfric as hf

HZ = 2.0 * np.pi
RANGE = (HZ * 15.0, HZ * 110.0)
CAL = hf.CantileverBeam.calibrate()
BEAM = CAL.beam.with_contact(CAL.contact(normal_load=5.0, friction_coefficient=1.5))
OSC = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def _info(benchmark, branch):
    benchmark.extra_info["points"] = len(branch)
    benchmark.extra_info["newton"] = branch.newton_iterations
    benchmark.extra_info["continuation_s"] = branch.elapsed


def test_sdof_branch_h15(benchmark):
    """Reference: the SDOF branch of the engine benchmark, same H."""
    branch = benchmark(hf.frf, OSC, 0.5, (0.5, 3.0), 15)
    _info(benchmark, branch)


# The same beam with a rigid Coulomb tip contact, f_s = 0.2 N (slipping over
# the range): the condensed path runs the same DLFT as the full one (issue 3).
BEAM_COULOMB = CAL.beam.with_contact(hf.Coulomb(slip_force=0.2))
TIPS = pytest.mark.parametrize("beam", [BEAM, BEAM_COULOMB], ids=["jenkins", "coulomb"])


@TIPS
def test_beam_branch_condensed_h15(benchmark, beam):
    """Condensed HBM (16 unknowns), every DOF recovered at the end."""
    branch = benchmark(hf.frf, beam, 2.0, RANGE, 15)
    assert branch.info["condensed"]
    assert branch.stop_reason.startswith("end")
    _info(benchmark, branch)


@TIPS
def test_beam_branch_full_h15(benchmark, beam):
    """The same branch by the uncondensed HBM (39 × 16 = 624 unknowns)."""
    branch = benchmark.pedantic(
        hf.frf,
        args=(beam, 2.0, RANGE, 15),
        kwargs={"condense": False},
        rounds=1,
        iterations=1,
        warmup_rounds=0,
    )
    assert not branch.info["condensed"]
    _info(benchmark, branch)


@pytest.mark.parametrize("condense", [True, False])
def test_beam_one_point(benchmark, condense):
    """Newton at one slipping frequency (87 Hz) from the linear guesses."""
    sol = benchmark(hf.periodic_solution, BEAM, 2.0, HZ * 87.0, 15, condense=condense)
    benchmark.extra_info["newton"] = sol.newton_iterations


def test_beam_time_integration_one_frequency(benchmark):
    """Time-integration reference of the 39-DOF beam at 87 Hz (slipping),
    2048 steps per period, from the stuck linear steady state."""
    ref = benchmark.pedantic(
        hf.validation.steady_state,
        args=(BEAM, 2.0, HZ * 87.0),
        kwargs={"initial_state": "linear", "tol": 1e-9},
        rounds=3,
        iterations=1,
    )
    assert ref.converged
    benchmark.extra_info["periods"] = ref.periods


@pytest.mark.parametrize("condense", [True, False])
def test_beam_coulomb_one_point(benchmark, condense):
    """Rigid Coulomb tip: presolve + Newton at 87 Hz from the linear guesses."""
    sol = benchmark.pedantic(
        hf.periodic_solution,
        args=(BEAM_COULOMB, 2.0, HZ * 87.0, 15),
        kwargs={"condense": condense},
        rounds=3,
        iterations=1,
    )
    assert sol.converged
    benchmark.extra_info["newton"] = sol.newton_iterations
