"""Stress rows for stop 34: the time-integration reference's own error.

``hf.validation.steady_state`` (trapezoidal rule, 2048 steps per period by
default) said nothing about its discretisation error: its step-halving
estimate was relative to the largest DOF (7.1e-5 where the contact DOF was
9.5e-4 off on a 3-DOF chain), and on the flank of a lightly damped stuck
resonance its first harmonic was 3.9e-4 (0.1 % damping) to 3.9e-3 (0.01 %)
off the closed form with ``converged=True``.

Rows: the halving estimate against the exact event-driven solution on a
3-DOF chain (two contact stiffnesses, two dampings, three regimes), and
the stuck structures (one oscillator, a chain with a ground and a relative
contact) against their closed-form linear response: right to 1e-4 or
warned, with ``scheme_error`` within a factor 2 of the true error.

Run with ``python -m pytest -m stress tests/stress/test_stop34_reference.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf

pytestmark = pytest.mark.stress


def _chain(zeta, contacts):
    n = 3
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    return hf.LinearStructure(
        np.eye(n), K, modal_damping=zeta, load={0: 1.0}, contacts=contacts
    )


HALVING_ROWS = [
    (100.0, 0.01, 0.3, 3.0),
    (100.0, 0.01, 0.6, 3.0),
    (100.0, 0.01, 1.6, 1.0),
    (100.0, 0.001, 0.3, 3.0),
    (100.0, 0.001, 1.6, 1.0),
    (1e4, 0.01, 1.2, 3.0),
    (1e4, 0.01, 1.6, 1.0),
    (1e4, 0.001, 0.6, 3.0),
    (1e4, 0.001, 1.6, 1.0),
]


@pytest.mark.parametrize(("kt", "zeta", "omega", "force"), HALVING_ROWS)
def test_halving_estimate_against_the_exact_solution(kt, zeta, omega, force):
    chain = _chain(zeta, [hf.Contact(hf.Jenkins(kt, 1.0), 2)])
    exact = hf.validation.exact_periodic_solution(
        chain, force, omega, on_failure="raise"
    )
    ref = hf.validation.steady_state(chain, force, omega, check_halving=True)
    assert ref.converged
    for dof in range(3):
        error = abs(ref.amplitude(1, dof=dof) / exact.amplitude(1, dof=dof) - 1.0)
        assert error <= 2.0 * 4.0 / 3.0 * ref.error_estimate


def _stuck_rows():
    rows = []
    for zeta in (1e-2, 1e-3, 3e-4):
        for shift in (-1.0, 0.0, 1.0, None):
            for kind in ("oscillator", "chain"):
                rows.append((kind, zeta, shift))
    return rows


@pytest.mark.parametrize(("kind", "zeta", "shift"), _stuck_rows())
def test_stuck_structure_right_or_warned(kind, zeta, shift):
    force = 1e-5  # every contact stuck (slip force 1 N)
    if kind == "oscillator":
        system = hf.Oscillator(1.0, 4.0 * zeta, 1.0, contact=hf.Jenkins(3.0, 1.0))
        M, C, K = np.eye(1), np.array([[4.0 * zeta]]), np.array([[4.0]])
        p = np.ones(1)
    else:
        law = hf.Jenkins(2.0, 1.0)
        system = _chain(zeta, [hf.Contact(law, 2), hf.Contact(law, 0, other=1)])
        M, C, K = system.matrices()
        K = K.copy()
        K[2, 2] += 2.0
        K[np.ix_([0, 1], [0, 1])] += 2.0 * np.array([[1.0, -1.0], [-1.0, 1.0]])
        p = system.load_vector(1.0)
    w0 = float(np.sqrt(np.linalg.eigvalsh(np.linalg.solve(M, K))[0]))
    omega = 0.5 * w0 if shift is None else w0 * (1.0 + shift * zeta)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        ref = hf.validation.steady_state(system, force, omega, initial_state="linear")
    warned = any(issubclass(w.category, hf.AccuracyWarning) for w in record)
    exact = np.linalg.solve(K - omega**2 * M + 1j * omega * C, force * p)
    coefficient = ref.coefficients[:, 1] - 1j * ref.coefficients[:, 2]
    size = np.maximum(np.abs(exact), 1e-4 * np.max(np.abs(exact)))
    error = float(np.max(np.abs(coefficient - exact) / size))
    assert ref.converged
    assert error <= 1e-4 or warned
    assert warned == (ref.scheme_error > 1e-4)
    assert 0.5 * error <= ref.scheme_error <= 2.0 * error + 1e-9
