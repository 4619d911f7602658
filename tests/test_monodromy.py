"""The monodromy matrix of the time-integration reference
(:func:`hbmfric.validation.monodromy`): central differences of the Newmark
period map, checked against the closed form of a linear oscillator (and
its second order in the step), Hill's method on the Duffing branch (exact
there), the exact Jenkins monodromy of the event-driven reference, and
Hill's verdicts on the friction-Duffing case."""

import numpy as np
import pytest
import scipy.linalg
from stability_cases import friction_duffing

import hbmfric as hf
from hbmfric.validation import exact_periodic_solution, monodromy, steady_state
from hbmfric.validation import integrator as kernels

JENKINS3 = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


def _linear_monodromy(m, c, k, omega):
    A = np.array([[0.0, 1.0], [-k / m, -c / m]])
    return scipy.linalg.expm(A * 2.0 * np.pi / omega)


def test_linear_oscillator_closed_form_second_order():
    """exp(A T) of ``m ẍ + c ẋ + k x = F cos Ωt``; the error falls by about
    4 when the step halves (measured 3.1e-5, 7.9e-6, 2.0e-6)."""
    m, c, k, omega = 1.0, 0.05, 1.0, 1.3
    osc = hf.Oscillator(m, c, k)
    exact = _linear_monodromy(m, c, k, omega)
    errors = []
    for steps in (512, 1024, 2048):
        ref = steady_state(osc, 0.5, omega, steps_per_period=steps)
        result = monodromy(osc, ref)
        assert result.labels == ["x[0]", "v[0]"]
        errors.append(float(np.max(np.abs(result.matrix - exact))))
    assert errors[-1] < 5e-6
    for coarse, fine in zip(errors[:-1], errors[1:], strict=True):
        assert 3.0 < coarse / fine < 5.0


def test_duffing_multipliers_against_hill():
    """Duffing (Hill exact up to truncation): at 5 points of each of the
    three stretches (lower stable, middle unstable, upper stable), started
    from the harmonic-balance solution, magnitudes within 1e-3 (measured
    4e-5) and the same verdict."""
    osc = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    branch = hf.frf(osc, 0.2, (0.5, 2.0), harmonics=9)
    hill = branch.stability()
    f0, f1 = branch.folds
    worst = 0.0
    for lo, hi in ((0, f0), (f0, f1), (f1, len(branch))):
        for i in np.linspace(lo + 2, hi - 3, 5).round().astype(int):
            result = monodromy(osc, branch.point(i))
            td = np.sort(np.abs(result.multipliers))
            assert td.size == 2  # a memoryless law adds no state
            worst = max(
                worst, float(np.max(np.abs(td - np.sort(np.abs(hill.multipliers[i])))))
            )
            assert (result.max_modulus < 1.0) == bool(hill.stable[i])
    assert worst < 1e-3


@pytest.mark.parametrize(
    ("force", "omega", "kind", "tolerance"),
    [
        (0.5, 1.2, "stuck", 1e-5),
        (0.1, 1.0, "stuck", 1e-5),
        (0.5, 1.6925, "stick-slip", 3e-3),
        (2.0, 1.1, "stick-slip", 3e-3),
    ],
)
def test_jenkins_against_the_exact_monodromy(force, omega, kind, tolerance):
    """The exact event-driven monodromy (phase propagators and saltation):
    stuck responses to rounding of the scheme (measured 5e-7, with the
    slider's neutral multiplier 1), stick-slip ones to the first order of
    the located reversals (measured 1.3e-4 to 1.7e-4 at 8192 steps)."""
    exact = exact_periodic_solution(JENKINS3, force, omega)
    assert exact.kind == kind
    ref = steady_state(JENKINS3, force, omega, steps_per_period=8192)
    result = monodromy(JENKINS3, ref)
    assert result.labels == ["x[0]", "v[0]", "f[0]"]
    error = np.abs(np.abs(exact.floquet_multipliers()) - np.abs(result.multipliers))
    assert error.max() < tolerance
    if kind == "stuck":
        assert abs(result.multipliers[0] - 1.0) < 1e-6


@pytest.mark.slow
def test_friction_duffing_verdicts_against_hill():
    """Duffing with a Jenkins contact on the same DOF (two contacts, the
    several-contact integrator): the time-domain multipliers give Hill's
    verdict at 5 points of each stretch, the unstable ones with a modulus
    of 1.06-1.22. (Their magnitudes differ from Hill's by up to 0.06:
    Hill's linearisation of a hysteretic law is exact only where an
    exponent crosses zero.)"""
    structure = friction_duffing()
    with pytest.warns(hf.AccuracyWarning):  # H = 15 gives extra folds
        branch = hf.frf(structure, 0.2, (0.5, 2.5), harmonics=31)
    stable = branch.stable
    assert branch.folds.size == 2
    f0, f1 = branch.folds
    for lo, hi in ((0, f0), (f0, f1), (f1, len(branch))):
        margin = (hi - lo) // 5
        for i in np.linspace(lo + margin, hi - margin, 5).round().astype(int):
            result = monodromy(structure, branch.point(i))
            assert result.labels == ["x[0]", "v[0]", "f[1]"]
            if stable[i]:
                assert result.max_modulus < 1.0 + 1e-6, (i, result.multipliers)
            else:
                assert result.max_modulus > 1.03, (i, result.multipliers)


@pytest.mark.parametrize(("omega", "tolerance"), [(1.2, 1e-6), (1.6925, 3e-3)])
def test_start_from_a_state_and_from_a_steady_state_agree(omega, tolerance):
    """From ``(x0, v0)`` the Jenkins force starts virgin and settles over two
    periods; the multipliers agree with those from the steady state's own
    state: to rounding when stuck (1.2 rad/s), to the first-order accuracy
    of the scheme's reversals in stick-slip (measured 1.9e-3 at 2048
    steps)."""
    ref = steady_state(JENKINS3, 0.5, omega)
    x, v, _ = ref.final_state
    from_state = monodromy(JENKINS3, (x, v), force=0.5, omega=omega)
    from_ref = monodromy(JENKINS3, ref)
    np.testing.assert_allclose(
        np.abs(from_state.multipliers), np.abs(from_ref.multipliers), atol=tolerance
    )


def test_kernels_compile_once():
    osc = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    for omega in (0.9, 1.3):
        monodromy(JENKINS3, steady_state(JENKINS3, 0.5, omega))
        monodromy(osc, steady_state(osc, 0.2, omega))
    assert len(kernels.newmark_periods.signatures) == 1
    assert len(kernels.record_period.signatures) == 1


def test_refusals():
    menq = hf.Oscillator(
        1.0, 0.02, 1.0, hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0)
    )
    with pytest.raises(ValueError, match="Menq and Iwan"):
        monodromy(menq, (0.1, 0.0), force=0.5, omega=1.2)
    with pytest.raises(ValueError, match="force and omega"):
        monodromy(JENKINS3, (0.1, 0.0))
    with pytest.warns(hf.ConvergenceWarning):
        unsettled = steady_state(JENKINS3, 0.5, 1.2, max_periods=2)
    with pytest.raises(ValueError, match="not a converged"):
        monodromy(JENKINS3, unsettled)
    ref = steady_state(JENKINS3, 0.5, 1.2)
    with pytest.raises(ValueError, match="perturbation"):
        monodromy(JENKINS3, ref, perturbation=0.5)
    with pytest.raises(ValueError, match="steps_per_period"):
        monodromy(JENKINS3, ref, steps_per_period=4)
    two_dof = hf.LinearStructure(
        np.eye(2), 2.0 * np.eye(2), 0.02 * np.eye(2), load={0: 1.0}
    )
    with pytest.raises(ValueError, match="another system"):
        monodromy(two_dof, ref)


def test_state_at_zero_against_the_series():
    """``signals.state_at_zero``: the series and its derivative at t = 0,
    against a direct evaluation and a central difference."""
    from hbmfric.signals import state_at_zero, synthesis_matrix

    rng = np.random.default_rng(4)
    hn = np.array([0, 1, 3, 5])
    X = rng.normal(size=(2, 7))
    omega = 1.7
    x0, v0 = state_at_zero(hn, X, omega)
    h = 1e-6
    theta = np.array([-omega * h, 0.0, omega * h])
    x = X @ synthesis_matrix(hn, theta).T
    np.testing.assert_allclose(x0, x[:, 1], atol=1e-14)
    np.testing.assert_allclose(v0, (x[:, 2] - x[:, 0]) / (2 * h), rtol=1e-7)


def test_zero_forcing_is_the_stuck_linear_oscillator():
    """At rest (F = 0) a Jenkins contact stays stuck: the multipliers are
    those of exp(A T) of the stuck linear oscillator (k + kt) plus the
    slider's neutral 1."""
    result = monodromy(JENKINS3, (0.0, 0.0), force=0.0, omega=1.2)
    stuck = np.linalg.eigvals(_linear_monodromy(1.0, 0.02, 1.0 + 3.0, 1.2))
    expected = np.sort(np.abs(np.append(stuck, 1.0)))
    np.testing.assert_allclose(np.sort(np.abs(result.multipliers)), expected, atol=1e-5)
