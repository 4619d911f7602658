"""Stress rows for stop 30: Floquet exponents of points whose monodromy
has a multiplier exactly 0.

A Jenkins element that slips forgets its state over the period, so the
time-domain monodromy (``method="auto"`` for a contact with memory on
several DOFs) can hold a multiplier 0. Its exponent is -inf + 0j; before
stop 30 the complex division ``log(mu) / T`` gave -inf + nan j with a
NumPy ``RuntimeWarning``, so a user's ``Stability.exponents`` held NaN.

Run with ``python -m pytest -m stress tests/stress/test_stop30_zero_multiplier.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_stability_monodromy_sparse import two_contact_pair

import hbmfric as hf

pytestmark = pytest.mark.stress


@pytest.mark.parametrize("damping_second", [0.0, 0.02])
@pytest.mark.parametrize("omega", [1.04, 1.06, 1.1])
def test_exponents_of_a_zero_multiplier_are_minus_infinity(damping_second, omega):
    """``periodic_solution(...).stability()`` on two DOFs with a grounded
    and a between-DOF Jenkins contact, near the resonance where both slip:
    no NaN, no RuntimeWarning; a zero multiplier's exponent is -inf, the
    others satisfy exp(λ T) = μ (NumPy from the multipliers)."""
    system = two_contact_pair(damping_second)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        warnings.simplefilter("error", RuntimeWarning)
        sol = hf.periodic_solution(system, 0.5, omega, 5)
        st = sol.stability()
    mu = np.asarray(st.multipliers).ravel()
    lam = np.asarray(st.exponents).ravel()
    assert not np.isnan(lam).any()
    zero = mu == 0
    assert np.all(lam[zero] == -np.inf)
    period = 2 * np.pi / omega
    np.testing.assert_allclose(
        np.exp(lam[~zero] * period), mu[~zero], rtol=1e-9, atol=1e-12
    )
