"""Problem types per AFT family (issue 17): contacts that all go through
one AFT kernel get a problem type whose residual compiles that kernel alone,
so that a Jenkins run does not compile the AFT of every law.

The references here are the general problem type (the plain tuple and the
plain ``CondensedProblem``, which compile every law's AFT) and the family
rule written out in the test: the family types must give the same residual
bit for bit, refuse a law their family does not cover, and be chosen
exactly when every contact belongs to one family.
"""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.laws.updates import CUBIC, DAHL, IWAN, JENKINS, MENQ
from hbmfric.kernels.residuals.condensed import (
    CondensedProblem,
    CondensedSingleDahlProblem,
    CondensedSingleJenkinsProblem,
    CondensedSingleMasingProblem,
    condensed_residual,
)
from hbmfric.kernels.residuals.hbm import (
    AFT_EVENTS,
    AFT_SAMPLES,
    NOT_COMPILED_FOR_LAW,
    DahlProblem,
    JenkinsProblem,
    MasingProblem,
    aft_family,
    hbm_residual,
)


def _osc(law):
    return hf.Oscillator(1.0, 0.02, 1.0, law)


JENKINS_LAW = hf.Jenkins(stiffness=3.0, slip_force=1.0)
MENQ_LAW = hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0)
IWAN_LAW = hf.Iwan(stiffnesses=(1.0, 2.0), slip_forces=(0.4, 0.6))


@pytest.mark.parametrize(
    "codes, scheme, family",
    [
        ([JENKINS], AFT_EVENTS, "jenkins"),
        ([JENKINS, JENKINS, JENKINS], AFT_EVENTS, "jenkins"),
        ([JENKINS], AFT_SAMPLES, None),  # the sampled AFT: general type
        ([MENQ], AFT_EVENTS, "masing"),
        ([MENQ, IWAN], AFT_EVENTS, "masing"),
        ([IWAN], AFT_SAMPLES, None),
        ([DAHL], AFT_EVENTS, "dahl"),
        ([DAHL], AFT_SAMPLES, "dahl"),  # aft_dahl serves both schemes
        ([CUBIC], AFT_EVENTS, None),
        ([JENKINS, MENQ], AFT_EVENTS, None),
        ([JENKINS, CUBIC], AFT_EVENTS, None),
        ([], AFT_EVENTS, None),
    ],
)
def test_aft_family_rule(codes, scheme, family):
    assert aft_family(np.array(codes, dtype=np.int64), np.int64(scheme)) == family


@pytest.mark.parametrize(
    "law, aft, full, condensed",
    [
        (JENKINS_LAW, "events", JenkinsProblem, CondensedSingleJenkinsProblem),
        (JENKINS_LAW, "samples", tuple, CondensedProblem),
        (MENQ_LAW, "events", MasingProblem, CondensedSingleMasingProblem),
        (IWAN_LAW, "events", MasingProblem, CondensedSingleMasingProblem),
        (hf.Cubic(0.2), "events", tuple, CondensedProblem),
    ],
)
def test_problems_get_their_family_type(law, aft, full, condensed):
    assert type(HBMProblem(_osc(law), 0.5, 5, aft=aft).kernel_problem) is full
    assert (
        type(CondensedHBMProblem(_osc(law), 0.5, 5, aft=aft).kernel_problem)
        is condensed
    )


def test_dahl_problem_type():
    law = hf.ModifiedDahl(beta=50.0, upper=(2.0, 0.5), lower=(2.0, -0.5))
    assert type(HBMProblem(_osc(law), 0.5, 5).kernel_problem) is DahlProblem
    assert type(CondensedHBMProblem(_osc(law), 0.5, 5).kernel_problem) is (
        CondensedSingleDahlProblem
    )


def _y(problem, amplitude, omega):
    y = np.zeros(problem.n_unknowns + 1)
    y[0] = amplitude
    y[1] = 0.3 * amplitude
    y[2] = 0.1 * amplitude
    y[-1] = omega
    return y


@pytest.mark.parametrize("amplitude", [0.1, 2.0])  # stuck, slipping
def test_jenkins_type_same_residual_as_general(amplitude):
    problem = HBMProblem(_osc(JENKINS_LAW), 0.5, 7)
    kp = problem.kernel_problem
    assert type(kp) is JenkinsProblem
    y = _y(problem, amplitude, 1.1)
    n = problem.n_unknowns
    R, J = np.empty(n), np.empty((n, n + 1))
    R2, J2 = np.empty(n), np.empty((n, n + 1))
    s = hbm_residual(y, kp, R, J)
    s2 = hbm_residual(y, tuple(kp), R2, J2)
    assert s == s2 >= 0
    assert np.array_equal(R, R2) and np.array_equal(J, J2)


def test_condensed_jenkins_type_same_residual_as_general():
    problem = CondensedHBMProblem(_osc(JENKINS_LAW), 0.5, 7)
    kp = problem.kernel_problem
    assert type(kp) is CondensedSingleJenkinsProblem
    y = _y(problem, 2.0, 1.1)
    n = problem.n_unknowns
    R, J = np.empty(n), np.empty((n, n + 1))
    R2, J2 = np.empty(n), np.empty((n, n + 1))
    s = condensed_residual(y, kp, R, J)
    s2 = condensed_residual(y, CondensedProblem(*kp), R2, J2)
    assert s == s2 >= 0
    assert np.array_equal(R, R2) and np.array_equal(J, J2)


def test_family_type_refuses_other_laws():
    """A Jenkins type carrying another law (or the sampled scheme) returns
    NOT_COMPILED_FOR_LAW instead of a wrong force; the general type computes
    it."""
    problem = HBMProblem(_osc(hf.Cubic(0.2)), 0.5, 7)
    kp = problem.kernel_problem
    assert type(kp) is tuple
    y = _y(problem, 0.5, 1.1)
    n = problem.n_unknowns
    R, J = np.empty(n), np.empty((n, n + 1))
    assert hbm_residual(y, kp, R, J) >= 0
    assert hbm_residual(y, JenkinsProblem(*kp), R, J) == NOT_COMPILED_FOR_LAW
    jenkins = HBMProblem(_osc(JENKINS_LAW), 0.5, 7, aft="samples").kernel_problem
    assert type(jenkins) is tuple
    assert hbm_residual(y, JenkinsProblem(*jenkins), R, J) == NOT_COMPILED_FOR_LAW
