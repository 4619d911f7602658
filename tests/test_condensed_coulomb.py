"""Rigid Coulomb contacts on the condensed path (issue 3): the condensed
residual runs the same DLFT scheme as the full one (located by default, the
linear tail with ``linear_tail=True``, classic for ``aft="samples"``), so the
condensed and the full (uncondensed) HBM have the same solutions.

References are independent of the condensed code: the full HBM residual and
Newton solve on all DOFs (``condense=False``), central finite differences,
and direct complex solves of the dynamic stiffness."""

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem, can_condense
from hbmfric.hbm import HBMProblem

HZ = 2.0 * np.pi


def _central_differences(problem, y, steps, state):
    """Central-difference Jacobian of ``problem.residual`` at ``y`` (step
    ``steps[j]`` in unknown ``j``); both sides must stay in contact state
    ``state``."""
    fd = np.empty((problem.n_unknowns, y.size))
    for j in range(y.size):
        up, down = y.copy(), y.copy()
        up[j] += steps[j]
        down[j] -= steps[j]
        Rp, _, sp = problem.residual(up)
        Rm, _, sm = problem.residual(down)
        assert sp == sm == state
        fd[:, j] = (Rp - Rm) / (2.0 * steps[j])
    return fd


class Chain:
    """Three masses in a chain grounded at the first, the contact on the
    last; Rayleigh damping (duck-typed system)."""

    n_dof = 3
    contact_dof = 2
    symmetric = True

    def __init__(self, contact):
        self.contact = contact

    def matrices(self):
        m = np.diag([1.0, 0.7, 0.5])
        k = np.array([[3.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
        return m, 0.01 * k + 0.02 * m, k

    def load_vector(self, force):
        return np.array([force, 0.0, 0.3 * force])

    def with_contact(self, contact):
        return Chain(contact)


def _chain(slip_force, tail=False):
    return Chain(hf.Coulomb(slip_force=slip_force, linear_tail=tail))


def stick_fraction(sol, dof, n=2048):
    """Fraction of the period where the velocity of ``dof`` is below 2 % of
    its peak (stick phases), from the Fourier series."""
    X = sol.coefficients[dof]
    theta = 2.0 * np.pi * np.arange(n) / n
    v = sum(
        k * (X[2 * j + 1] * np.cos(k * theta) - X[2 * j] * np.sin(k * theta))
        for j, k in enumerate(sol.harmonic_numbers)
    )
    return float(np.mean(np.abs(v) < 0.02 * np.max(np.abs(v))))


def test_can_condense_accepts_coulomb():
    assert can_condense(_chain(0.3))
    assert can_condense(_chain(0.3, tail=True))
    cal = hf.CantileverBeam.calibrate()
    assert can_condense(cal.beam.with_contact(hf.Coulomb(slip_force=2.0)))
    sol = hf.periodic_solution(_chain(0.3), 1.0, 1.2, 5)
    assert sol.converged


# (slip force, Ω, regime): stop = stick phases in the period (checked on
# the full solution), slip = non-stop, stuck = stuck all period
CHAIN_CASES = [
    (0.5, 0.3, "stop"),
    (0.5, 0.8, "stop"),
    (0.3, 1.2, "slip"),
    (0.3, 1.8, "slip"),
    (0.7, 0.5, "stuck"),
]


@pytest.mark.parametrize("scheme", ["located", "tail", "samples"])
@pytest.mark.parametrize(("slip_force", "omega", "regime"), CHAIN_CASES)
def test_chain_condensed_matches_full(scheme, slip_force, omega, regime):
    """Condensed and full Newton solves, each from its own linear guesses,
    reach the same periodic solution: contact-DOF harmonics and the
    recovered DOFs to 1e-8 relative."""
    system = _chain(slip_force, tail=scheme == "tail")
    aft = "samples" if scheme == "samples" else "events"
    H = 15
    cond = hf.periodic_solution(system, 1.0, omega, H, aft=aft, condense=True)
    full = hf.periodic_solution(system, 1.0, omega, H, aft=aft, condense=False)
    assert cond.converged and full.converged
    c = system.contact_dof
    scale = np.max(np.abs(full.coefficients))
    if regime == "stuck":
        assert full.contact_state.startswith("contact stuck")
        assert np.max(np.abs(full.coefficients[c])) < 1e-12 * scale
    else:
        frac = stick_fraction(full, c)
        assert (frac > 0.1) if regime == "stop" else (frac < 0.05), frac
        xc = full.coefficients[c]
        assert np.max(np.abs(cond.coefficients[c] - xc)) < 1e-8 * np.max(np.abs(xc))
    assert np.max(np.abs(cond.coefficients - full.coefficients)) < 1e-8 * scale


@pytest.mark.parametrize("receptance", ["modal", "direct"])
@pytest.mark.parametrize("scheme", ["located", "tail", "samples"])
@pytest.mark.parametrize(("slip_force", "omega"), [(0.5, 0.8), (0.3, 1.2)])
def test_condensed_jacobian_against_finite_differences(
    receptance, scheme, slip_force, omega
):
    """Analytic [dR/dX_c, dR/dΩ] of the condensed Coulomb residual against
    central differences, at a point off the solution (the DLFT residual is
    piecewise smooth: the state is checked on both sides of each step)."""
    system = _chain(slip_force, tail=scheme == "tail")
    aft = "samples" if scheme == "samples" else "events"
    problem = CondensedHBMProblem(system, 1.0, 7, aft=aft, receptance=receptance)
    sol = hf.periodic_solution(system, 1.0, omega, 7, aft=aft)
    y = np.append(sol.coefficients[system.contact_dof], omega)
    rng = np.random.default_rng(5)
    y[:-1] += 0.02 * np.max(np.abs(y[:-1])) * rng.standard_normal(y.size - 1)
    R, J, state = problem.residual(y)
    fd = _central_differences(problem, y, np.full(y.size, 1e-7), state)
    np.testing.assert_allclose(J, fd, atol=1e-6 * np.max(np.abs(J)))
    # the condensed residual is the Schur complement of the full one: at a
    # full solution it vanishes
    R0, _, _ = problem.residual(np.append(sol.coefficients[system.contact_dof], omega))
    assert np.max(np.abs(R0)) < 1e-9


def test_modal_tail_receptance_against_direct_solves():
    """The modal sums of the tail coefficients (beam, 39 modes) against
    :func:`contact_receptance` (direct complex solves of the dynamic
    stiffness), odd and all harmonics."""
    from hbmfric.kernels.dlft.tail import contact_receptance
    from hbmfric.kernels.residuals.condensed import _modal_tail_receptance

    cal = hf.CantileverBeam.calibrate()
    beam = cal.beam.with_contact(hf.Coulomb(slip_force=2.0, linear_tail=True))
    for symmetry in (True, False):
        p = CondensedHBMProblem(beam, 2.0, 7, symmetry=symmetry, receptance="modal")
        kp = p.kernel_problem
        M, C, K = p._matrices
        mu = kp.law_params[3]
        assert mu == pytest.approx(np.linalg.inv(M)[p.contact_dof, p.contact_dof])
        n = int(kp.law_params[4]) + 1
        for omega in (HZ * 30.0, HZ * 87.0):
            q1, dq1 = np.zeros(n, complex), np.zeros(n, complex)
            q2, dq2 = np.zeros(n, complex), np.zeros(n, complex)
            a, da, ok = _modal_tail_receptance(kp, omega, mu, q1, dq1)
            b, db, ok2 = contact_receptance(
                M, C, K, p.contact_dof, omega, kp.harmonic_numbers, mu, q2, dq2
            )
            assert ok and ok2 and a == b and da == db
            assert np.max(np.abs(q1 - q2)) < 1e-9 * np.max(np.abs(q2[1:]))
            assert np.max(np.abs(dq1 - dq2)) < 1e-9 * np.max(np.abs(dq2[1:]))


@pytest.mark.parametrize("tail", [False, True])
def test_chain_branch_condensed_matches_full(tail):
    """Whole FRF branches, condensed and full, each traced on its own: every
    condensed point solves the full HBM and every full point the condensed
    one; both reach the end of the range with the same peak."""
    system = _chain(0.3, tail)
    H = 9
    cond = hf.frf(system, 1.0, (0.9, 2.5), H)
    full = hf.frf(system, 1.0, (0.9, 2.5), H, condense=False)
    assert cond.info["condensed"] and not full.info["condensed"]
    for b in (cond, full):
        assert b.stop_reason == "end of frequency range reached"
    fp = HBMProblem(system, 1.0, H)
    cp = CondensedHBMProblem(system, 1.0, H)
    for X, w in zip(cond.coefficients, cond.omega, strict=True):
        assert np.max(np.abs(fp.residual(np.append(X.ravel(), w))[0])) < 1e-8
    for X, w in zip(full.coefficients, full.omega, strict=True):
        y = np.append(X[system.contact_dof], w)
        assert np.max(np.abs(cp.residual(y)[0])) < 1e-8
    peak_c = np.max(cond.amplitude(1))
    peak_f = np.max(full.amplitude(1))
    assert abs(peak_c / peak_f - 1.0) < 1e-3


def full_newton(problem, y, iterations=6):
    """Plain Newton steps at fixed Ω on the full HBM residual from ``y``."""
    y = y.copy()
    n = problem.n_unknowns
    for _ in range(iterations):
        R, J, _ = problem.residual(y)
        y[:n] -= np.linalg.solve(J[:, :n], R)
    return y


def _beam(tail=False):
    cal = hf.CantileverBeam.calibrate(slip_frequency=24.0, stuck_frequency=87.0)
    return cal.beam.with_contact(hf.Coulomb(slip_force=2.0, linear_tail=tail))


@pytest.mark.parametrize("f_hz", [30.0, 87.0, 100.0])
def test_beam_condensed_solution_solves_the_full_hbm(f_hz):
    """39-DOF beam with a Coulomb tip: the condensed solution, recovered on
    every DOF, is a fixed point of Newton on the full HBM residual (1e-8),
    stuck (30 Hz) and slipping (87, 100 Hz)."""
    beam = _beam()
    H = 7
    cond = hf.periodic_solution(beam, 2.0, HZ * f_hz, H)
    assert cond.converged
    X = cond.coefficients
    y = full_newton(HBMProblem(beam, 2.0, H), np.append(X.ravel(), HZ * f_hz))
    full = y[:-1].reshape(X.shape)
    assert np.max(np.abs(full - X)) < 1e-8 * np.max(np.abs(X))
    c = beam.contact_dof
    if f_hz == 30.0:
        assert cond.contact_state.startswith("contact stuck")
    else:
        assert cond.contact_state.startswith("contact slips")
        assert np.max(np.abs(X[c] - full[c])) < 1e-8 * np.max(np.abs(full[c]))


@pytest.mark.slow
@pytest.mark.parametrize("tail", [False, True])
@pytest.mark.parametrize("f_hz", [30.0, 87.0])
def test_beam_condensed_and_full_from_their_own_guesses(tail, f_hz):
    """Each path from its own linear guesses and presolve (the full one
    takes seconds): the same solution to 1e-8 relative."""
    beam = _beam(tail)
    cond = hf.periodic_solution(beam, 2.0, HZ * f_hz, 7)
    full = hf.periodic_solution(beam, 2.0, HZ * f_hz, 7, condense=False)
    assert cond.converged and full.converged
    scale = np.max(np.abs(full.coefficients))
    assert np.max(np.abs(cond.coefficients - full.coefficients)) < 1e-8 * scale
    c = beam.contact_dof
    if f_hz == 87.0:
        xc = full.coefficients[c]
        assert np.max(np.abs(cond.coefficients[c] - xc)) < 1e-8 * np.max(np.abs(xc))


@pytest.mark.slow
def test_beam_jacobian_against_finite_differences():
    """The condensed Coulomb Jacobian on the beam (modal receptance, tail)."""
    beam = _beam(tail=True)
    problem = CondensedHBMProblem(beam, 2.0, 7)
    sol = hf.periodic_solution(beam, 2.0, HZ * 87.0, 7)
    y = np.append(sol.coefficients[beam.contact_dof], sol.omega)
    rng = np.random.default_rng(2)
    y[:-1] += 0.01 * np.max(np.abs(y[:-1])) * rng.standard_normal(y.size - 1)
    _, J, state = problem.residual(y)
    steps = np.full(y.size, 1e-6 * np.max(np.abs(y[:-1])))
    steps[-1] = 1e-4
    fd = _central_differences(problem, y, steps, state)
    assert np.max(np.abs(fd - J)) < 1e-6 * np.max(np.abs(J))


def test_condensed_coulomb_kernels_compile_once():
    """A fresh process: condensed Coulomb problems at new slip forces,
    penalties, harmonics, schemes and receptances add no kernel signature
    after the first batch."""
    code = textwrap.dedent(
        """
        import json, sys
        import hbmfric as hf
        from hbmfric.kernels.residuals import condensed
        from hbmfric.kernels.dlft import coulomb as dlft
        from hbmfric.kernels.dlft import tail as dlft_tail
        from hbmfric.kernels.steps import newton
        sys.path.insert(0, TESTS_DIR)
        from test_condensed_coulomb import Chain

        def counts():
            out = {}
            for mod in (condensed, dlft, dlft_tail, newton):
                for name in dir(mod):
                    obj = getattr(mod, name)
                    if hasattr(obj, "signatures") and obj.__module__ == mod.__name__:
                        out[mod.__name__ + "." + name] = len(obj.signatures)
            return out

        def runs(slip_forces, penalty, H):
            for fs in slip_forces:
                for tail in (False, True):
                    law = hf.Coulomb(slip_force=fs, penalty=penalty, linear_tail=tail)
                    for rec in ("modal", "direct"):
                        for aft in ("events", "samples"):
                            hf.periodic_solution(Chain(law), 1.0, 1.2, H,
                                                 condense=rec, aft=aft)
            hf.frf(Chain(hf.Coulomb(slip_force=slip_forces[0])), 1.0, (1.5, 1.7), H)

        runs((0.3,), None, 5)
        first = counts()
        runs((0.2, 0.5), 4.0, 9)
        print(json.dumps({"first": first, "second": counts()}))
        """
    ).replace("TESTS_DIR", repr(str(Path(__file__).parent)))
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["second"] == report["first"]
    assert (
        report["first"]["hbmfric.kernels.residuals.condensed.condensed_residual"] == 1
    )


def test_samples_scheme_and_penalty_reach_the_condensed_kernel():
    """The condensed problem carries the full problem's DLFT parameters
    (penalty, penalty damping from M_cc, tail length) and M_cc."""
    system = _chain(0.3, tail=True)
    cond = CondensedHBMProblem(system, 1.0, 7)
    full = HBMProblem(system, 1.0, 7)
    np.testing.assert_array_equal(
        cond.kernel_problem.law_params, full.kernel_problem[7][0]
    )
    assert cond.kernel_problem.contact_mass == 0.5
    assert cond.penalty == full.penalty
    assert cond.kernel_problem.aft_scheme == full.kernel_problem[8]


@pytest.mark.slow
def test_beam_branch_condensed_matches_full():
    """The beam's Coulomb FRF branch (f_s = 0.2 N, 15-110 Hz, H = 5),
    condensed and full, each traced on its own: both reach the end, every
    condensed point solves the full HBM and every full point the condensed
    one, and the resonance peaks agree."""
    cal = hf.CantileverBeam.calibrate()
    beam = cal.beam.with_contact(hf.Coulomb(slip_force=0.2))
    H = 5
    rng = (HZ * 15.0, HZ * 110.0)
    cond = hf.frf(beam, 2.0, rng, H)
    full = hf.frf(beam, 2.0, rng, H, condense=False)
    assert cond.info["condensed"] and not full.info["condensed"]
    for b in (cond, full):
        assert b.stop_reason == "end of frequency range reached"
    fp = HBMProblem(beam, 2.0, H)
    cp = CondensedHBMProblem(beam, 2.0, H)
    c = beam.contact_dof
    # residuals in N; the penalty (≈ 1e8 N/m) turns 1e-16 m into 1e-8 N
    for X, w in zip(cond.coefficients, cond.omega, strict=True):
        assert np.max(np.abs(fp.residual(np.append(X.ravel(), w))[0])) < 1e-7
    for X, w in zip(full.coefficients, full.omega, strict=True):
        assert np.max(np.abs(cp.residual(np.append(X[c], w))[0])) < 1e-7
    peak_c = np.max(cond.amplitude(1))
    peak_f = np.max(full.amplitude(1))
    assert abs(peak_c / peak_f - 1.0) < 1e-3
