"""The default AFT sampling of Masing laws (stop 35).

The event AFT locates a Masing law's reversals but not the kinks of its
force between them (an Iwan element's slip onset), so its error is second
order in ``n_time``. The reference is independent of that AFT: a two-element
Iwan contact is exactly its two Jenkins elements in parallel, whose event
AFT locates every slip onset (1e-15 between the two with the same sampled
AFT). With 8 samples per harmonic the Iwan was 7.4e-4 off at ``H = 7``
(the truncation estimate saw it and warned, and ``harmonics="auto"`` paid
for it with ``H`` up to 45-63); the default for Masing laws is now 16.
"""

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.hbm import HBMProblem, default_n_time


def _chain(laws):
    n = 4
    k = 1e4 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    k[-1, -1] = 1e4
    return hf.LinearStructure(
        0.1 * np.eye(n),
        k,
        modal_damping=0.01,
        load={0: 1.0},
        contacts=[hf.Contact(law, 3) for law in laws],
    )


def _pair():
    two = _chain([hf.Jenkins(2e3, 0.2), hf.Jenkins(3e3, 0.5)])
    one = _chain([hf.Iwan((2e3, 3e3), (0.2, 0.5))])
    return two, one, 2 * math.pi * one.natural_frequencies(1)[0]


def test_masing_laws_sample_sixteen_per_harmonic():
    two, one, _ = _pair()
    hn = np.arange(0, 8)
    assert HBMProblem(one, 1.0, 7).n_time == default_n_time(hn, "events", True) == 112
    assert HBMProblem(two, 1.0, 7).n_time == default_n_time(hn, "events") == 56
    menq = hf.Oscillator(1.0, 0.02, 1.0, hf.Menq.from_stiffness(3.0, 1.0, 0.3))
    assert HBMProblem(menq, 1.0, 15).n_time == 16 * 15
    # each level of an adaptive run keeps the rule
    assert HBMProblem(one, 1.0, 7).with_harmonics(21).n_time == 16 * 21


@pytest.mark.parametrize("ratio", [1.2, 1.5, 2.0])
def test_iwan_equals_its_jenkins_elements_at_the_default(ratio):
    two, one, w1 = _pair()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        a = hf.periodic_solution(two, 1.0, ratio * w1, harmonics=7)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        b = hf.periodic_solution(one, 1.0, ratio * w1, harmonics=7)
    err = np.max(np.abs(a.coefficients - b.coefficients))
    # 7.4e-4 at 1.5 ω1 with 8 samples per harmonic; 1.0e-4 with 16
    assert err <= 1.5e-4 * np.max(np.abs(a.coefficients))


def test_second_order_in_the_samples():
    # the AFT's own error halves twice per doubling of n_time (the
    # reference: the two Jenkins elements at the same H)
    two, one, w1 = _pair()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        a = hf.periodic_solution(two, 1.0, 1.5 * w1, harmonics=7)
        errors = []
        for n_time in (56, 112, 224):
            b = hf.periodic_solution(one, 1.0, 1.5 * w1, harmonics=7, n_time=n_time)
            errors.append(np.max(np.abs(a.coefficients - b.coefficients)))
    assert errors[0] > 3.0 * errors[1] > 9.0 * errors[2]
