"""FE matrices in SI units with small beam elements (stop 35, hunt37).

A beam or shell model mixes translations (mass entries ~ m, stiffness
~ EI/L³) with rotations (~ m L², EI/L). With elements of 0.2 mm in SI
units the consistent mass of a 1 cm steel cantilever has eigenvalues from
4.9e-11 of its largest: :class:`hbmfric.LinearStructure` refused it as
"not positive definite (every DOF needs mass)", though every DOF has
mass and the same beam in mm units was accepted. Its stiffness has
singular values down to 8e-13 of its largest, and the condensation took
the clamped beam for a free-floating one (no static receptance).

References: Euler–Bernoulli cantilever frequencies (closed form), the
same beam in mm–tonne units, and the uncondensed solve.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import _singular

E, RHO, B, T = 2.1e11, 7800.0, 0.01, 0.002  # Pa, kg/m³, m, m


def beam(n_el: int, length: float, clamped: bool = True):
    """Consistent mass (kg, kg m, kg m²) and stiffness (N/m, N, N m) of an
    Euler–Bernoulli steel beam, DOFs (w, θ) per node, the first node
    clamped (removed) when ``clamped``."""
    el = length / n_el
    ei, rho_a = E * B * T**3 / 12.0, RHO * B * T
    ke = (ei / el**3) * np.array(
        [
            [12, 6 * el, -12, 6 * el],
            [6 * el, 4 * el**2, -6 * el, 2 * el**2],
            [-12, -6 * el, 12, -6 * el],
            [6 * el, 2 * el**2, -6 * el, 4 * el**2],
        ]
    )
    me = (rho_a * el / 420.0) * np.array(
        [
            [156, 22 * el, 54, -13 * el],
            [22 * el, 4 * el**2, 13 * el, -3 * el**2],
            [54, 13 * el, 156, -22 * el],
            [-13 * el, -3 * el**2, -22 * el, 4 * el**2],
        ]
    )
    n = 2 * (n_el + 1)
    M, K = np.zeros((n, n)), np.zeros((n, n))
    for e in range(n_el):
        i = slice(2 * e, 2 * e + 4)
        M[i, i] += me
        K[i, i] += ke
    if clamped:
        M, K = M[2:, 2:], K[2:, 2:]
    return M, K


def to_mm_tonne(M, K):
    """The same beam in mm, tonne, N: translations ×1e3, rotations as
    they are; mass in tonnes, stiffness in N/mm."""
    s = np.ones(M.shape[0])
    s[0::2] = 1e3
    t = 1.0 / s
    return M * np.outer(t, t) / 1e3, K * np.outer(t, t) / 1e3


def test_fine_si_beam_accepted_with_its_closed_form_frequencies():
    M, K = beam(50, 0.01)  # 0.2 mm elements
    assert np.linalg.eigvalsh(M)[0] / np.linalg.eigvalsh(M)[-1] < 1e-9
    s = hf.LinearStructure(M, K, modal_damping=0.01)
    f = s.natural_frequencies(3)
    ei, rho_a = E * B * T**3 / 12.0, RHO * B * T
    beta_l = np.array([1.875104069, 4.694091133, 7.854757438])
    exact = beta_l**2 / (2 * math.pi) * math.sqrt(ei / (rho_a * 0.01**4))
    np.testing.assert_allclose(f, exact, rtol=1e-5)
    s_mm = hf.LinearStructure(*to_mm_tonne(M, K), modal_damping=0.01)
    np.testing.assert_allclose(s_mm.natural_frequencies(3), f, rtol=1e-7)


def test_massless_dof_is_named():
    M, K = beam(4, 0.2)
    M[3, :] = M[:, 3] = 0.0
    with pytest.raises(ValueError, match=r"DOF 3 has mass\[3, 3\] = 0"):
        hf.LinearStructure(M, K)


def test_clamped_fine_si_beam_is_not_free_floating():
    M, K = beam(50, 0.01)
    assert not _singular(K)
    assert not _singular(to_mm_tonne(M, K)[1])
    assert _singular(beam(50, 0.01, clamped=False)[1])  # two rigid-body modes


def test_fine_si_beam_condensed_with_a_mean_matches_the_full_solve():
    M, K = beam(50, 0.01)
    tip = M.shape[0] - 2
    s = hf.LinearStructure(
        M,
        K,
        modal_damping=0.01,
        contact=hf.Jenkins(1e6, 2.0),
        contact_dof=tip,
        load={tip: 1.0},
        static_load={tip: 0.5},  # harmonic 0 solved: the static receptance
    )
    w1 = 2 * math.pi * s.natural_frequencies(1)[0]
    for omega in (0.9 * w1, 1.0 * w1, 1.02 * w1):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", hf.AccuracyWarning)
            cond = hf.periodic_solution(s, 3.0, omega, harmonics=3, condense=True)
            full = hf.periodic_solution(s, 3.0, omega, harmonics=3, condense=False)
        a, b = cond.coefficients[tip], full.coefficients[tip]
        assert np.max(np.abs(a - b)) <= 1e-5 * np.max(np.abs(b))
        # the mean: between the static load on the cantilever with the
        # contact stuck, P / (3 EI / L³ + kt), and without it, P L³ / (3 EI)
        k_tip = 3 * E * B * T**3 / 12.0 / 0.01**3
        assert 0.5 / (k_tip + 1e6) * (1 - 1e-6) <= a[0] <= 0.5 / k_tip * (1 + 1e-6)
