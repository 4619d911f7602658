"""Stress rows for stop 31: undamped structures solved at (and 1e-14
away from) the natural pulsations of the structure without its contacts,
where the condensed receptance has a pole.

Before stop 31 these raised ``ZeroDivisionError`` (one contact or several
on modal sums) or returned ``converged=True`` amplitudes up to 7 % off.
The reference is closed form: the contacts stay stuck (small force), so
``x = (K + K_t - Ω² M)⁻¹ p``.

Run with ``python -m pytest -m stress tests/stress/test_stop31_poles.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.linalg import eigh

import hbmfric as hf

pytestmark = pytest.mark.stress

FORCE = 1e-3
KT = 1.0
CHAINS = {
    "chain2": (np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]])),
    "chain3": (
        np.diag([1.0, 2.0, 0.5]),
        np.array([[3.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.5]]),
    ),
}


def _case(name, contacts):
    M, K = CHAINS[name]
    n = K.shape[0]
    dofs = [n - 1] if contacts == 1 else [n - 1, 0]
    laws = [hf.Contact(hf.Jenkins(stiffness=KT, slip_force=1.0), d) for d in dofs]
    load = np.zeros(n)
    load[n - 1] = 1.0
    ks = np.zeros((n, n))
    ks[dofs, dofs] = KT
    return hf.LinearStructure(M, K, contacts=laws, load=load), M, K + ks, load


@pytest.mark.parametrize("harmonics", [5, "auto"])
@pytest.mark.parametrize("offset", [0.0, 1e-14])
@pytest.mark.parametrize("mode", [0, 1])
@pytest.mark.parametrize("contacts", [1, 2])
@pytest.mark.parametrize("name", sorted(CHAINS))
def test_periodic_solution_on_a_pole(name, contacts, mode, offset, harmonics):
    s, M, k_stuck, load = _case(name, contacts)
    M0, K0 = CHAINS[name]
    w_r = np.sqrt(eigh(K0, M0, eigvals_only=True))
    omega = float(w_r[mode]) * (1.0 + offset)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        sol = hf.periodic_solution(s, FORCE, omega, harmonics=harmonics)
    assert sol.converged
    ref = np.abs(np.linalg.solve(k_stuck - omega**2 * M, FORCE * load))
    for dof in range(M.shape[0]):
        amp = sol.amplitude(harmonic=1, dof=dof)
        assert amp == pytest.approx(ref[dof], rel=1e-8, abs=1e-12 * ref.max())
