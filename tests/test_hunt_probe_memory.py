"""The truncation estimate of a problem with 2D elements calibrates every
output on one probe level (hunt35, stop 34).

:func:`~hbmfric.continuation.accuracy.watched_truncation_errors` measures
the watched DOF and the normal displacement of each 2D element. On main
each output built a probe level of its own (its problem and its work
arrays: the Jacobian and the factored copy, dense, of the probe level's
order), all kept in the problem's cache: a full problem with ``e``
elements held ``2 (e + 1)`` such matrices where the memory guard
(:mod:`hbmfric._memory`) plans 2. A 60-DOF chain at ``H = 15`` with four
elements (``periodic_solution``, ``condense=False``) peaked 1.17 GB above
its start where the guard planned 0.34 GB; with eight 2.0 GB: a run the
guard lets through could be killed by the operating system. Now one
level's arrays serve every output: 0.29 GB for one or four elements.

References: the count of work arrays allocated (wrapped ``_Level.work``)
and each output's estimate from a fresh problem, which builds its own
probe (independent of the shared arrays' earlier contents).
"""

import warnings

import numpy as np

import hbmfric as hf
from hbmfric.continuation import adaptive
from hbmfric.continuation.accuracy import (
    normal_outputs,
    truncation_errors,
    watched_truncation_errors,
)
from hbmfric.hbm import HBMProblem

N_DOF = 9


def _chain(n_elements: int):
    K = np.zeros((N_DOF, N_DOF))
    for i in range(N_DOF):
        K[i, i] += 1.0
        if i + 1 < N_DOF:
            K[i, i] += 1.0
            K[i, i + 1] = K[i + 1, i] = -1.0
    element = hf.Contact2D(
        tangential_stiffness=1.0,
        normal_stiffness=2.0,
        friction_coefficient=0.3,
        preload=0.05,
    )
    return hf.LinearStructure(
        np.diag(1.0 + 0.1 * np.arange(N_DOF)),
        K,
        rayleigh=(0.01, 0.02),
        contacts=[
            hf.Contact(element, 2 * i + 1, normal=2 * i + 2) for i in range(n_elements)
        ],
        load={N_DOF - 1: 0.1},
    )


def _points(system, omegas):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        sols = [
            hf.periodic_solution(system, 1.0, w, harmonics=7, condense=False)
            for w in omegas
        ]
    rows = zip(sols, omegas, strict=True)
    return np.array([np.append(s.coefficients.reshape(-1), w) for s, w in rows])


def test_one_probe_level_for_every_output(monkeypatch):
    """Three elements: the watched DOF and three normal outputs are
    calibrated with the arrays of one probe level (main: four), and each
    normal output's estimate equals that of a fresh problem's own probe."""
    system = _chain(3)
    points = _points(system, (0.6, 1.2))
    built = []
    work = adaptive._Level.work

    def counting(self):
        if self._work is None:
            built.append(self)
        return work(self)

    monkeypatch.setattr(adaptive._Level, "work", counting)
    problem = HBMProblem(system, 1.0, harmonics=7, symmetry=False)
    outputs = normal_outputs(problem)
    assert len(outputs) == 3
    watched_truncation_errors(problem, points, every=1)
    assert len(built) == 1, len(built)
    for w in outputs:
        shared = truncation_errors(problem, points, every=1, output=w)
        fresh = HBMProblem(system, 1.0, harmonics=7, symmetry=False)
        own = truncation_errors(fresh, points, every=1, output=w)
        np.testing.assert_allclose(shared, own, rtol=1e-10, atol=0.0)
    assert len(built) == 4  # one per fresh problem, none more on the shared
