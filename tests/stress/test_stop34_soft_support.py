"""Stress rows for stop 34 (hunt35): several contacts condensed on a
structure held by a soft spring, with a static load.

Each row: a 6-DOF chain grounded by a spring ``soft`` times its others,
a static load driving the soft mode, and either a 2D element or two
Jenkins contacts to ground, solved by ``periodic_solution`` condensed by
default at one pulsation. The reference is the full HBM residual of
every DOF recovered from the condensed solution (independent of the
condensed residual): below 1e-8 of the load, or below twice the full
solve's own residual where that is larger (two Jenkins contacts at
``soft = 1e-9``: the mean is 1e7 m, carried by the soft spring alone, and
the full solve rounds at 3e-9 N). On main the condensed
corrector accepted residuals at the rounding level of the near-singular
static receptance (2.5 N at ``soft = 1e-9``): the recovered solution's
full residual reached 4.9 times the load, quietly.

Run with ``python -m pytest -m stress tests/stress/test_stop34_soft_support.py``.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.hbm import HBMProblem

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from test_hunt_soft_support import _element, _two_jenkins  # noqa: E402

pytestmark = pytest.mark.stress

ROWS = [
    (kind, soft, omega)
    for kind in ("element", "two jenkins")
    for soft in (1e-5, 1e-7, 1e-9)
    for omega in (0.3, 0.8, 1.5)
]


@pytest.mark.parametrize(("kind", "soft", "omega"), ROWS)
def test_condensed_solution_solves_the_full_balance(kind, soft, omega):
    s = _element(soft) if kind == "element" else _two_jenkins(soft)
    full = HBMProblem(s, 0.1, harmonics=7, symmetry=False)
    load = np.max(np.abs(full.load))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        a = hf.periodic_solution(s, 0.1, omega, harmonics=7)
        b = hf.periodic_solution(s, 0.1, omega, harmonics=7, condense=False)
    assert a.converged and b.converged
    R, _, state = full.residual(np.append(a.coefficients.reshape(-1), omega))
    floor, _, _ = full.residual(np.append(b.coefficients.reshape(-1), omega))
    assert state >= 0
    assert np.max(np.abs(R)) < max(1e-8 * load, 2.0 * np.max(np.abs(floor)))
