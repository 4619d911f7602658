"""Several friction contacts on one structure (hf.Contact, issue 15).

References, each independent of the multi-contact residual:
- the condensed single-contact solve (another residual, another path);
- the single-DOF oscillator a symmetric two-contact structure reduces to;
- central finite differences of the residual;
- an explicit central-difference time march written here (plain loops,
  Jenkins by return mapping), integrated to steady state.
"""

import math

import numpy as np
import pytest
from numba import njit

import hbmfric as hf
from hbmfric.hbm import HBMProblem

M3 = np.diag([1.0, 0.8, 1.2])
K3 = np.array([[2.0, -1.0, 0.0], [-1.0, 2.5, -1.5], [0.0, -1.5, 1.5]])


def _chain(contacts, **kwargs):
    return hf.LinearStructure(
        M3, K3, rayleigh=(0.02, 0.02), contacts=contacts, load={0: 1.0}, **kwargs
    )


def test_one_listed_contact_matches_the_condensed_single_contact():
    """contacts=[Contact(law, 2)] solved uncondensed against the same law
    given as contact/contact_dof, condensed by default (another residual)."""
    law = hf.Jenkins(stiffness=1.0, slip_force=0.3)
    single = hf.LinearStructure(
        M3, K3, rayleigh=(0.02, 0.02), contact=law, contact_dof=2, load={0: 1.0}
    )
    listed = _chain([hf.Contact(law, 2)])
    for w in (0.4, 0.9, 1.6):
        a = hf.periodic_solution(single, 0.5, w, harmonics=9)
        b = hf.periodic_solution(listed, 0.5, w, harmonics=9, condense=False)
        for dof in (0, 1, 2):
            assert b.amplitude(dof=dof) == pytest.approx(a.amplitude(dof=dof), rel=1e-9)


def test_symmetric_pair_of_contacts_reduces_to_the_oscillator():
    """Two equal masses coupled by a spring, each held by the same Jenkins
    contact and loaded alike, move in phase: each is the oscillator
    (m, c, k_ground, law). A relative contact between them carries no force
    in that motion."""
    m, kg, kc, c = 1.0, 1.0, 0.7, 0.03
    law = hf.Jenkins(stiffness=2.0, slip_force=0.4)
    structure = hf.LinearStructure(
        m * np.eye(2),
        [[kg + kc, -kc], [-kc, kg + kc]],
        c * np.eye(2),
        contacts=[
            hf.Contact(law, 0),
            hf.Contact(law, 1),
            hf.Contact(hf.Jenkins(stiffness=5.0, slip_force=0.1), 0, 1),
        ],
        load={0: 1.0, 1: 1.0},
    )
    oscillator = hf.Oscillator(m, c, kg, law)
    omega = np.linspace(0.6, 2.2, 9)
    branch = hf.frf(structure, 0.8, (0.5, 2.5), harmonics=15)
    reference = hf.frf(oscillator, 0.8, (0.5, 2.5), harmonics=15)
    assert branch.complete and reference.complete
    for dof in (0, 1):
        a = branch.amplitude_at(omega, dof=dof)
        assert np.max(np.abs(a / reference.amplitude_at(omega) - 1.0)) < 1e-4


def test_jacobian_against_finite_differences():
    """Two contacts, one between DOFs 0 and 1, at states where both stick,
    slip and where one slips: the analytic Jacobian against central
    differences."""
    contacts = [
        hf.Contact(hf.Jenkins(stiffness=1.5, slip_force=0.2), 2),
        hf.Contact(hf.Menq.from_stiffness(stiffness=2.0, slip_force=0.3), 0, 1),
    ]
    problem = HBMProblem(_chain(contacts), 0.5, harmonics=5, aft="samples")
    rng = np.random.default_rng(3)
    for scale in (0.01, 0.3, 3.0):
        y = np.empty(problem.n_unknowns + 1)
        y[:-1] = scale * rng.standard_normal(problem.n_unknowns)
        y[-1] = 1.1
        _, J, state = problem.residual(y)
        assert state >= 0
        h = 1e-7 * max(scale, 1e-3)
        fd = np.empty_like(J)
        for j in range(y.size):
            yp, ym = y.copy(), y.copy()
            yp[j] += h
            ym[j] -= h
            fd[:, j] = (problem.residual(yp)[0] - problem.residual(ym)[0]) / (2 * h)
        assert np.max(np.abs(J - fd)) <= 1e-5 * max(1.0, np.max(np.abs(J)))


@njit(cache=False)
def _acceleration(m_inv, damping, stiffness, load, pairs, f, x, v, t, omega):
    n = x.size
    force = np.empty(n)
    for r in range(n):
        force[r] = load[r] * math.cos(omega * t)
        for q in range(n):
            force[r] -= stiffness[r, q] * x[q] + damping[r, q] * v[q]
    for i in range(f.size):
        force[pairs[i, 0]] -= f[i]
        if pairs[i, 1] >= 0:
            force[pairs[i, 1]] += f[i]
    return m_inv @ force


@njit(cache=False)
def _march(mass, damping, stiffness, load, pairs, kt, fs, omega, n_steps, n_periods):
    """Velocity Verlet, Jenkins contacts by return mapping on the
    displacement increment; returns the displacements over the last period,
    shape (n_steps, n)."""
    n = mass.shape[0]
    dt = 2.0 * math.pi / omega / n_steps
    x = np.zeros(n)
    v = np.zeros(n)
    f = np.zeros(kt.size)
    u_prev = np.zeros(kt.size)
    m_inv = np.linalg.inv(mass)
    out = np.zeros((n_steps, n))
    a = _acceleration(m_inv, damping, stiffness, load, pairs, f, x, v, 0.0, omega)
    for period in range(n_periods):
        for step in range(n_steps):
            if period == n_periods - 1:
                out[step] = x
            t = (period * n_steps + step + 1) * dt
            v_half = v + 0.5 * dt * a
            x = x + dt * v_half
            for i in range(kt.size):
                p, q = pairs[i, 0], pairs[i, 1]
                u = x[p] - (x[q] if q >= 0 else 0.0)
                trial = f[i] + kt[i] * (u - u_prev[i])
                f[i] = min(max(trial, -fs[i]), fs[i])
                u_prev[i] = u
            a = _acceleration(
                m_inv, damping, stiffness, load, pairs, f, x, v_half, t, omega
            )
            v = v_half + 0.5 * dt * a
    return out


def _first_harmonic(samples):
    n = samples.shape[0]
    e = np.exp(-2j * np.pi * np.arange(n) / n)
    return 2.0 * np.abs(e @ samples) / n


def test_three_dof_chain_against_a_time_march():
    """A Jenkins contact to ground at DOF 2 and one between DOFs 0 and 1:
    the first-harmonic amplitude of every DOF at four pulsations (stuck,
    slipping and near the resonances) against an explicit time march to
    steady state (measured 1e-4 to 5e-4 apart, the march's own error)."""
    laws = [hf.Jenkins(stiffness=1.5, slip_force=0.15), hf.Jenkins(2.0, 0.1)]
    pairs = np.array([[2, -1], [0, 1]])
    structure = _chain([hf.Contact(laws[0], 2), hf.Contact(laws[1], 0, 1)])
    M, C, K = structure.matrices()
    kt = np.array([law.stiffness for law in laws])
    fs = np.array([law.slip_force for law in laws])
    force = 0.4
    for omega in (0.35, 0.8, 1.3, 2.0):
        sol = hf.periodic_solution(structure, force, omega, harmonics=21)
        assert sol.converged
        # decay time 2 / (α + β ω²) of the lowest modes: ~ 60 s
        n_periods = int(math.ceil(900.0 * omega / (2 * math.pi)))
        samples = _march(
            M, C, K, force * structure.load.real, pairs, kt, fs, omega, 8192, n_periods
        )
        reference = _first_harmonic(samples)
        for dof in range(3):
            assert sol.amplitude(harmonic=1, dof=dof) == pytest.approx(
                reference[dof], rel=2e-3
            ), (omega, dof)


def test_branch_covers_the_range_with_two_contacts():
    """The default frf call on the chain with a relative contact traces the
    whole range and says so."""
    structure = _chain(
        [
            hf.Contact(hf.Jenkins(stiffness=1.5, slip_force=0.15), 2),
            hf.Contact(hf.Iwan(stiffnesses=(1.0, 1.0), slip_forces=(0.05, 0.1)), 0, 1),
        ]
    )
    branch = hf.frf(structure, 0.4, (0.2, 2.5))
    assert branch.complete
    assert branch.omega.min() <= 0.2 + 1e-9 and branch.omega.max() >= 2.5 - 1e-9


def test_bad_contacts_are_refused_with_the_argument_named():
    law = hf.Jenkins(stiffness=1.0, slip_force=0.3)
    with pytest.raises(ValueError, match="either contacts or contact"):
        hf.LinearStructure(M3, K3, contact=law, contact_dof=0, contacts=[])
    with pytest.raises(ValueError, match=r"contacts\[1\].other"):
        _chain([hf.Contact(law, 0), hf.Contact(law, 1, 7)])
    with pytest.raises(ValueError, match="itself"):
        _chain([hf.Contact(law, 1, 1)])
    with pytest.raises(ValueError, match="unknown DOF name"):
        _chain([hf.Contact(law, "tip")])
    with pytest.raises(TypeError, match="Contact.law"):
        hf.Contact("jenkins", 0)
    with pytest.raises(ValueError, match="only contact"):
        s = _chain([hf.Contact(hf.Coulomb(slip_force=0.2), 2), hf.Contact(law, 0)])
        hf.frf(s, 0.5, (0.5, 2.0))
    two = _chain([hf.Contact(law, 2), hf.Contact(law, 0, 1)])
    with pytest.raises(ValueError, match="condense=False"):
        hf.frf(two, 0.5, (0.5, 2.0), condense="modal")
    # the time-integration reference takes several contacts
    # (tests/test_multi_reference.py)
    assert hf.validation.steady_state(two, 0.5, 1.0, steps_per_period=256).converged


def test_craig_bampton_keeps_every_contact():
    """Reducing onto the contact DOFs keeps the contacts (renumbered): the
    reduced chain with all DOFs as boundary is the chain itself."""
    law = hf.Jenkins(stiffness=1.5, slip_force=0.15)
    chain = _chain(
        [hf.Contact(law, 2), hf.Contact(law, 0, 1)],
        dof_names={"a": 0, "b": 1, "c": 2},
    )
    with pytest.raises(ValueError, match="boundary DOF"):
        hf.craig_bampton(chain, boundary=[0, 2], n_modes=1)
    reduced = hf.craig_bampton(chain, boundary=[2, 1, 0], n_modes=0)
    assert [(c.dof, c.other) for c in reduced.contacts] == [(0, None), (2, 1)]
    a = hf.periodic_solution(chain, 0.4, 0.9, harmonics=9)
    b = hf.periodic_solution(reduced, 0.4, 0.9, harmonics=9)
    assert b.amplitude(dof="c") == pytest.approx(a.amplitude(dof="c"), rel=1e-8)
