"""Stress rows for stop 35: Hill's stability holds no more memory than
its plan.

Before stop 35 ``stability_of_points`` planned nothing: Hill's problem of a
full model holds 12-15 dense matrices of the Jacobian's order (the frf plan
counts 12), so a branch that fitted could be killed in its stability call.
Each row measures the peak of NumPy's allocations (``tracemalloc``) of one
call on a chain with a Jenkins contact and compares it with
:func:`hbmfric.stability.hill_bytes` (never under it, at most twice it).

Run with ``python -m pytest -m stress tests/stress/test_stop35_hill_memory.py``.
"""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np
import pytest
from test_stability_memory import _chain

import hbmfric as hf
from hbmfric.stability import hill_bytes, stability_of_points

pytestmark = pytest.mark.stress

CASES = [
    # (n_dof, H, points, symmetric)
    (6, 7, 2, False),
    (6, 7, 5, True),
    (24, 9, 3, False),
    (24, 9, 3, True),
    (12, 15, 8, False),
    (30, 15, 2, False),  # order 930: one Jacobian 6.9 MB, companion 28 MB
    (30, 15, 2, True),
]


@pytest.mark.parametrize(("n_dof", "harmonics", "n_points", "symmetric"), CASES)
def test_hill_peak_within_its_plan(n_dof, harmonics, n_points, symmetric):
    system = _chain(n_dof)
    omegas = np.linspace(0.1, 0.12, n_points)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sols = [
            hf.periodic_solution(system, 1.0, w, harmonics=harmonics) for w in omegas
        ]
    coef = np.stack([p.coefficients for p in sols])
    hn = sols[0].harmonic_numbers
    # compiled or loaded before the measure (Numba's allocations are not
    # the problem's)
    stability_of_points(
        system, 1.0, omegas[:1], hn, coef[:1], np.full(1, harmonics), method="hill"
    )
    tracemalloc.start()
    try:
        st = stability_of_points(
            system,
            1.0,
            omegas,
            hn,
            coef,
            np.full(n_points, harmonics),
            method="hill",
            exponents="all",
            symmetric=symmetric,
        )
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    n = n_dof * (2 * harmonics + 1)
    orders = [n]
    if symmetric:
        orders = [n_dof * (harmonics + 1), n_dof * harmonics]
    kept, working = hill_bytes(n, orders, n_points)
    assert np.all(np.isfinite(st.max_real))
    assert peak <= kept + working
    assert kept + working <= 2.0 * peak
