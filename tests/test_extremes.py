"""Zero forcing, extreme forces and extreme unit scales: never a hang, never a
wrong number (issue: trust, item 2).

Each call runs in a daemon thread with a deadline: the compiled kernels
release the GIL and cannot be interrupted, so a hang shows as a failed test
instead of a stuck run. The expected values are closed forms (the zero
response, the linear free oscillator) and the scaling invariance of the
equations of motion.
"""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.kernels.aft import schemes as _aft
from hbmfric.kernels.fourier.dft import fourier_matrices

#: wall-time allowance per call, s (each call takes milliseconds once the
#: kernels are compiled; compilation itself happens in the first call)
DEADLINE = 240.0


def within_deadline(fn, deadline: float = DEADLINE):
    """``fn()`` run in a daemon thread; fails the test if it does not return
    within ``deadline`` seconds."""
    out: dict = {}

    def target():
        try:
            out["value"] = fn()
        except BaseException as exc:  # re-raised in the test's thread
            out["error"] = exc

    worker = threading.Thread(target=target, daemon=True)
    worker.start()
    worker.join(deadline)
    if worker.is_alive():
        pytest.fail(f"call did not return within {deadline:.0f} s (hang)")
    if "error" in out:
        raise out["error"]
    return out["value"]


def jenkins_oscillator(length=1.0, force=1.0, kt=3.0, zeta=0.01):
    """``m = k = 1``, slip force 1 (N), in units where a length is ``length``
    m and a force ``force`` N: every stiffness and mass scales by
    ``force/length``, the slip force by ``force``."""
    s = force / length
    law = hf.Jenkins(stiffness=kt * s, slip_force=1.0 * force)
    return hf.Oscillator(mass=s, damping=2 * zeta * s, stiffness=s, contact=law)


def linear_amplitude(F, omega, m=1.0, c=0.02, k=1.0):
    return F / np.hypot(k - m * omega**2, c * omega)


# -- zero forcing: the zero response, at once ------------------------------


def test_zero_force_branch_is_zero_and_covers_the_range():
    branch = within_deadline(lambda: hf.frf(jenkins_oscillator(), 0.0, (0.5, 3.0)))
    assert np.all(branch.coefficients == 0.0)
    assert branch.omega.min() == pytest.approx(0.5)
    assert branch.omega.max() == pytest.approx(3.0)


def test_zero_force_periodic_solution_is_zero():
    sol = within_deadline(lambda: hf.periodic_solution(jenkins_oscillator(), 0.0, 1.2))
    assert sol.converged
    assert np.all(sol.coefficients == 0.0)


def test_zero_initial_guess_converges_to_the_branch():
    osc = jenkins_oscillator()
    # the stuck linear response at F = 0.2 < slip force (closed form with
    # the stuck stiffness k + kt = 4): Newton from exactly zero displacement
    n_unknowns = 16  # odd harmonics 1..15 (symmetric): 8 × (cos, sin)
    sol = within_deadline(
        lambda: hf.periodic_solution(
            osc, 0.2, 0.8, 15, initial_guess=np.zeros(n_unknowns)
        )
    )
    assert sol.converged
    expected = linear_amplitude(0.2, 0.8, k=4.0)
    assert sol.amplitude(harmonic=1) == pytest.approx(expected, rel=1e-10)


def test_zero_force_beam_condensed_and_full():
    cal = hf.CantileverBeam.calibrate(slip_frequency=24.0, stuck_frequency=87.0)
    beam = cal.beam.with_contact(cal.contact(normal_load=5.0, friction_coefficient=1.5))
    for condense in (None, False):
        branch = within_deadline(
            lambda c=condense: hf.frf(
                beam, 0.0, (100.0, 120.0), harmonics=5, condense=c
            )
        )
        assert np.all(branch.coefficients == 0.0)
        assert branch.omega.max() == pytest.approx(120.0)


# -- forces far above the slip force: the free linear oscillator ------------


@pytest.mark.parametrize("law", ["jenkins", "menq", "iwan", "coulomb"])
def test_force_far_above_slip_force_gives_the_free_oscillator(law):
    make = {
        "jenkins": lambda: hf.Jenkins(stiffness=3.0, slip_force=1.0),
        "menq": lambda: hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0),
        "iwan": lambda: hf.Iwan.segalman(
            stiffness=3.0, slip_force=1.0, chi=-0.5, beta=0.5
        ),
        "coulomb": lambda: hf.Coulomb(slip_force=1.0),
    }[law]
    osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=make())
    F = 1e12
    branch = within_deadline(lambda: hf.frf(osc, F, (0.5, 3.0)))
    assert branch.omega.min() == pytest.approx(0.5)
    assert branch.omega.max() == pytest.approx(3.0)
    # the friction force (at most the slip force, 1 N) is 1e-12 of F
    expected = linear_amplitude(F, branch.omega)
    np.testing.assert_allclose(branch.amplitude(harmonic=1), expected, rtol=1e-9)


# -- scale invariance -------------------------------------------------------


@pytest.mark.parametrize(
    "length, force", [(1e-15, 1.0), (1.0, 1e-15), (1e-15, 1e-15), (1e15, 1e15)]
)
def test_units_scaled_by_1e15_give_the_same_branch(length, force):
    base = within_deadline(lambda: hf.frf(jenkins_oscillator(), 0.5, (0.5, 3.0)))
    scaled = within_deadline(
        lambda: hf.frf(jenkins_oscillator(length, force), 0.5 * force, (0.5, 3.0))
    )
    # the equations in scaled units are the same equations: same path, the
    # same points to the corrector's tolerance (since the curve rule budgets
    # the points' estimate, rounding-level differences of the estimate move
    # the step by ~1e-16, which a Newton stop at the tolerance turns into
    # ~1e-10 on Ω; measured 6e-11 after that merge, 1e-12 before)
    assert len(scaled) == len(base)
    np.testing.assert_allclose(scaled.omega, base.omega, rtol=1e-9)
    np.testing.assert_allclose(
        scaled.amplitude(harmonic=1) / length,
        base.amplitude(harmonic=1),
        rtol=1e-9,
    )


def test_huge_amplitude_scale_still_covers_the_range_with_true_points():
    osc = jenkins_oscillator()
    branch = within_deadline(
        lambda: hf.frf(osc, 0.5, (0.5, 3.0), 15, amplitude_scale=1e300)
    )
    assert branch.omega.max() == pytest.approx(3.0)
    # every point solves the equations: Newton started there stays there
    for i in range(0, len(branch), max(1, len(branch) // 5)):
        point = branch.point(i)
        again = hf.periodic_solution(osc, 0.5, point.omega, 15, initial_guess=point)
        assert again.converged
        assert again.amplitude(harmonic=1) == pytest.approx(
            point.amplitude(harmonic=1), rel=1e-8
        )


# -- the event search itself -------------------------------------------------


def _events_kernel(X):
    harmonic_numbers = np.arange(1, 16, 2, dtype=np.int64)
    n_time = 64
    inverse, _, derivative = fourier_matrices(harmonic_numbers, n_time)
    n_coef = X.size
    F = np.empty(n_coef)
    dF = np.empty((n_coef, n_coef))
    params = np.array([3.0, 1.0])
    return _aft.aft_jenkins_events(
        params, harmonic_numbers, X, inverse, derivative, F, dF
    )


def test_event_search_returns_at_once_for_constant_and_non_finite_motion():
    X = np.zeros(16)
    assert within_deadline(lambda: _events_kernel(X)) == _aft.STUCK
    X[0] = np.nan
    assert within_deadline(lambda: _events_kernel(X)) == _aft.SEARCH_BUDGET
    X[0] = np.inf
    assert within_deadline(lambda: _events_kernel(X)) == _aft.SEARCH_BUDGET


def test_huge_force_regression_from_a_linear_guess():
    # a point deep in gross slip solved directly (no continuation)
    osc = jenkins_oscillator(zeta=0.01)
    sol = within_deadline(lambda: hf.periodic_solution(osc, 1e12, 0.7))
    assert sol.converged
    assert sol.amplitude(harmonic=1) == pytest.approx(
        linear_amplitude(1e12, 0.7), rel=1e-9
    )
    assert math.isfinite(sol.residual_norm)
