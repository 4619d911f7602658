"""The implicit contact update of the time-integration reference with a
stiff contact (``kt/k = 1e4``) at the default step counts.

The scalar equation ``u + g_c f(u) = target`` is a difference of terms as
large as the step's start values; where the contact displacement crosses
zero, a tolerance relative to the new values alone asked for accuracy
below the rounding of those terms and the update failed (the stress
matrix needed 4096 steps per period). References: the closed-form stick
solution of one update, the closed-form stuck FRF, and a run with 8 times
smaller steps.
"""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.kernels.laws.updates import JENKINS
from hbmfric.validation import steady_state
from hbmfric.validation.integrator import contact_update

KT = 1e4


def test_update_across_zero_matches_the_stick_solution():
    """One step of the failing run: the contact stays stuck and crosses
    ``u = 0``; Newton's root is the stick line's, to the rounding of the
    start values."""
    params = np.array([KT, 1.0])
    f_prev, u_prev = 1.227042751157669e-06, 1.2270427511576643e-10
    target, g_c = 3.223687614517833e-16, 4.1815173e-4
    u, f, iterations, ok = contact_update(JENKINS, params, f_prev, u_prev, target, g_c)
    assert ok
    assert iterations <= 3
    exact = (target - g_c * (f_prev - KT * u_prev)) / (1.0 + g_c * KT)
    assert abs(u - exact) <= 1e-14 * (abs(u_prev) + g_c * abs(f_prev))
    assert f == pytest.approx(f_prev + KT * (u - u_prev), rel=0, abs=1e-18)


@pytest.mark.parametrize("steps", [512, 1024])
def test_stuck_stiff_contact_at_the_default_steps(steps):
    """Stuck Jenkins contact, kt/k = 1e4, ζ = 1e-4: the amplitude is the
    closed-form linear one with the stuck stiffness."""
    m, k = 1.0, 1.0
    c = 2.0 * 1e-4
    osc = hf.Oscillator(m, c, k, hf.Jenkins(stiffness=KT * k, slip_force=1.0))
    force, omega = 1e-4, 0.3
    # from rest: the undamped-looking transient of the stiff stuck mode
    # (ζ = 1e-4) crosses zero at every step size; the update must never
    # fail, though the steady state is not reached in 200 periods (warned)
    with pytest.warns(hf.ConvergenceWarning, match="max_periods"):
        transient = steady_state(
            osc, force, omega, steps_per_period=steps, tol=1e-8, max_periods=200
        )
    assert transient.status == 0, transient.message
    ref = steady_state(
        osc, force, omega, steps_per_period=steps, tol=1e-8, initial_state="linear"
    )
    assert ref.converged, ref.message
    exact = force / abs(k + KT * k - m * omega**2 + 1j * c * omega)
    assert ref.amplitude(harmonic=1) == pytest.approx(exact, rel=1e-6)


def test_slipping_stiff_contact_converges_in_the_step():
    """Gross slip, kt/k = 1e4, Fex/Fn = 10: 1024 steps per period agree
    with 8192 (second order: the difference is the coarse run's error)."""
    osc = hf.Oscillator(1.0, 0.4, 1.0, hf.Jenkins(stiffness=KT, slip_force=1.0))
    runs = [
        steady_state(osc, 10.0, 0.8, steps_per_period=n, tol=1e-9) for n in (1024, 8192)
    ]
    for r in runs:
        assert r.status == 0, r.message
    a, b = (r.amplitude(harmonic=1) for r in runs)
    assert abs(a - b) <= 1e-4 * b
