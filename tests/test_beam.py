"""The clamped beam with a rubbing tip: finite elements against closed forms,
calibration, condensed against full HBM, HBM against time integration, and
the stuck and slipping linear limits."""

import numpy as np
import pytest
import scipy.optimize

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.hbm import HBMProblem

MU = 1.5
HZ = 2.0 * np.pi


@pytest.fixture(scope="module")
def calibration():
    return hf.CantileverBeam.calibrate(slip_frequency=24.0, stuck_frequency=87.0)


def _beam_constants(beam):
    return beam.bending_rigidity, beam.mass_per_length, beam.length


def analytic_frequencies(beam, spring=0.0, tip_mass=0.0, n_modes=3):
    """Bending frequencies (Hz) of a uniform Euler–Bernoulli cantilever with a
    tip spring and a tip mass: roots in β of the 2×2 determinant of
    ``W''(L) = 0`` and ``EI W'''(L) = (k - m ω²) W(L)`` for
    ``W = A (cosh βx - cos βx) + B (sinh βx - sin βx)``,
    ``ω = β² sqrt(EI / ρA)``."""
    ei, rho_a, L = _beam_constants(beam)
    c = np.sqrt(ei / rho_a)

    def det(beta):
        bl = beta * L
        ch, cs, sh, sn = np.cosh(bl), np.cos(bl), np.sinh(bl), np.sin(bl)
        stiff = spring - tip_mass * (c * beta**2) ** 2
        a1, b1 = ch + cs, sh + sn  # W''/β²
        a2 = ei * beta**3 * (sh - sn) - stiff * (ch - cs)
        b2 = ei * beta**3 * (ch + cs) - stiff * (sh - sn)
        return (a1 * b2 - b1 * a2) / np.cosh(bl) ** 2

    grid = np.linspace(0.1, 12.0 * n_modes, 20000) / L
    vals = det(grid)
    roots = []
    for i in np.nonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))[0]:
        roots.append(scipy.optimize.brentq(det, grid[i], grid[i + 1], xtol=1e-14))
        if len(roots) == n_modes:
            break
    return c * np.array(roots) ** 2 / HZ


def bending_frequencies(beam, spring=0.0):
    """FE frequencies (Hz) of the bending modes (axial ones removed)."""
    M, _, K = beam.matrices()
    bend = np.ones(beam.n_dof, bool)
    bend[0::3] = False  # axial DOFs do not couple with bending
    K = K[np.ix_(bend, bend)]
    M = M[np.ix_(bend, bend)]
    K[-2, -2] += spring
    w2 = np.linalg.eigvals(np.linalg.solve(M, K)).real
    return np.sort(np.sqrt(w2)) / HZ


def test_first_frequency_of_the_paper_beam():
    beam = hf.CantileverBeam()
    assert beam.n_dof == 39
    f_fe = beam.natural_frequencies(n_modes=1)[0]
    ei, rho_a, L = _beam_constants(beam)
    f_exact = 1.8751040687119611**2 / (HZ * L**2) * np.sqrt(ei / rho_a)
    assert f_exact == pytest.approx(26.82, abs=0.005)
    assert abs(f_fe / f_exact - 1.0) < 1e-3
    assert analytic_frequencies(beam, n_modes=1)[0] == pytest.approx(f_exact, 1e-10)


def test_frequencies_converge_with_order_four():
    """Cubic Hermite elements: eigenvalue errors fall as h⁴ (fitted)."""
    sizes = np.array([4, 8, 16])
    exact = analytic_frequencies(hf.CantileverBeam(), n_modes=3)
    errors = np.array(
        [
            bending_frequencies(hf.CantileverBeam(n_elements=n))[:3] / exact - 1.0
            for n in sizes
        ]
    )
    assert np.all(errors > 0)  # consistent mass: upper bounds
    for mode in range(3):
        order = -np.polyfit(np.log(sizes), np.log(errors[:, mode]), 1)[0]
        assert 3.7 < order < 4.3, (mode, order)


@pytest.mark.parametrize(
    ("spring", "tip_mass"), [(1.586e5, 0.0), (0.0, 0.077), (1.586e5, 0.077)]
)
def test_spring_supported_and_tip_mass_frequencies(spring, tip_mass):
    beam = hf.CantileverBeam(tip_mass=tip_mass)
    exact = analytic_frequencies(beam, spring, tip_mass, n_modes=3)
    fe = bending_frequencies(beam, spring)[:3]
    np.testing.assert_allclose(fe, exact, rtol=1e-3)
    np.testing.assert_allclose(fe[:2], exact[:2], rtol=2e-4)


def test_calibration_recovers_both_resonances(calibration):
    cal = calibration
    assert cal.residual < 1e-6
    assert cal.tip_mass == pytest.approx(0.077, rel=0.01)  # SPEC §6
    assert cal.contact_stiffness == pytest.approx(1.586e5, rel=0.002)
    beam = cal.beam
    assert beam.tip_mass == cal.tip_mass and beam.contact is None
    # independent: closed-form clamped beam with the calibrated tip mass/spring
    free = analytic_frequencies(beam, 0.0, cal.tip_mass, n_modes=1)[0]
    stuck = analytic_frequencies(beam, cal.contact_stiffness, cal.tip_mass, 1)[0]
    assert free == pytest.approx(24.0, rel=2e-4)
    assert stuck == pytest.approx(87.0, rel=2e-4)
    law = cal.contact(normal_load=40.0, friction_coefficient=MU)
    assert beam.with_contact(law).natural_frequencies("stuck")[0] == pytest.approx(
        87.0, abs=1e-6
    )
    with pytest.raises(ValueError, match="slip_frequency"):
        hf.CantileverBeam.calibrate(slip_frequency=30.0)
    with pytest.raises(ValueError, match="stuck_frequency"):
        hf.CantileverBeam.calibrate(stuck_frequency=500.0)


def test_damping_is_modal(calibration):
    beam = calibration.beam
    M, C, K = beam.matrices()
    omega, shapes = beam.modes()
    np.testing.assert_allclose(shapes.T @ M @ shapes, np.eye(beam.n_dof), atol=1e-9)
    modal = shapes.T @ C @ shapes
    np.testing.assert_allclose(
        modal, np.diag(2 * beam.damping_ratio * omega), atol=1e-9 * omega[-1]
    )


def _stick_slip_beam(calibration, normal_load=5.0):
    return calibration.beam.with_contact(calibration.contact(normal_load, MU))


def linear_tip_frf(beam, omega, stiffness):
    """First harmonic at the tip of the linear beam with a tip spring, by a
    direct complex solve (independent of the modal condensation)."""
    M, C, K = beam.matrices()
    K = K.copy()
    K[beam.contact_dof, beam.contact_dof] += stiffness
    p = beam.load_vector(1.0)
    c = beam.contact_dof
    out = [
        abs(np.linalg.solve(K - w * w * M + 1j * w * C, p)[c])
        for w in np.atleast_1d(omega)
    ]
    return np.array(out)


def test_condensed_jacobian_against_finite_differences(calibration):
    beam = _stick_slip_beam(calibration)
    problem = CondensedHBMProblem(beam, 2.0, 7)
    sol = hf.periodic_solution(beam, 2.0, HZ * 88.0, 7)
    assert sol.converged and sol.contact_state.startswith("contact slips")
    y = np.concatenate((sol.coefficients[beam.contact_dof], [sol.omega]))
    _, J, _ = problem.residual(y)
    fd = np.empty_like(J)
    for j in range(y.size):
        h = 1e-6 * np.max(np.abs(y[:-1])) if j < y.size - 1 else 1e-4
        up, down = y.copy(), y.copy()
        up[j] += h
        down[j] -= h
        fd[:, j] = (problem.residual(up)[0] - problem.residual(down)[0]) / (2 * h)
    assert np.max(np.abs(fd - J)) < 1e-6 * np.max(np.abs(J))
    assert np.max(np.abs(fd[:, -1] - J[:, -1])) < 1e-6 * np.max(np.abs(J[:, -1]))


def test_condensed_and_full_hbm_agree(calibration):
    """Every recovered point of the condensed branch solves the full HBM,
    and the full Newton solve from it stays put (1e-8 relative)."""
    beam = _stick_slip_beam(calibration)
    branch = hf.frf(beam, 2.0, (HZ * 15, HZ * 110), 7)
    assert branch.info["condensed"] and branch.stop_reason.startswith("end")
    full = HBMProblem(beam, 2.0, 7)
    for i in range(len(branch)):
        y = np.concatenate((branch.coefficients[i].ravel(), [branch.omega[i]]))
        R, _, _ = full.residual(y)
        assert np.max(np.abs(R)) < 1e-8 * 2.0
    slipping = [
        i
        for i in range(len(branch))
        if branch.amplitude(1)[i] * calibration.contact_stiffness > MU * 5.0
    ]
    picks = np.linspace(0, len(branch) - 1, 4).astype(int).tolist() + slipping[::2][:4]
    for i in picks:
        sol = hf.periodic_solution(
            beam, 2.0, branch.omega[i], 7, condense=False, initial_guess=branch.point(i)
        )
        assert sol.converged
        X = branch.coefficients[i]
        assert np.max(np.abs(sol.coefficients - X)) < 1e-8 * np.max(np.abs(X))


def test_hbm_agrees_with_time_integration(calibration):
    """Stick–slip (Fn = 5 N, Fex = 2 N): first harmonic at the tip, HBM (H =
    31) against the Newmark steady state, at 6 frequencies around the
    stuck resonance where the contact slips."""
    beam = _stick_slip_beam(calibration)
    branch = hf.frf(beam, 2.0, (HZ * 60, HZ * 110), 31)
    a = branch.amplitude(harmonic=1, dof="tip")
    slipping = np.nonzero(a * calibration.contact_stiffness > MU * 5.0 * 1.05)[0]
    assert slipping.size >= 6
    picks = slipping[np.linspace(0, slipping.size - 1, 6).astype(int)]
    for i in picks:
        ref = hf.validation.steady_state(
            beam, 2.0, branch.omega[i], initial_state="linear", tol=1e-9
        )
        assert ref.converged
        a_ref = ref.amplitude(harmonic=1, dof=beam.contact_dof)
        assert abs(a[i] / a_ref - 1.0) < 1e-3, (branch.omega[i] / HZ, a[i], a_ref)


@pytest.mark.parametrize(
    ("normal_load", "target", "stiffness"), [(1e6, 87.0, 1.0), (0.0, 24.0, 0.0)]
)
def test_stuck_and_slipping_limits_are_linear(
    calibration, normal_load, target, stiffness
):
    beam = calibration.beam.with_contact(calibration.contact(normal_load, MU))
    branch = hf.frf(beam, 2.0, (HZ * 15, HZ * 110), 15)
    a = branch.amplitude(harmonic=1, dof="tip")
    linear = 2.0 * linear_tip_frf(
        beam, branch.omega, stiffness * calibration.contact_stiffness
    )
    np.testing.assert_allclose(a, linear, rtol=1e-8)
    # peak of the damped FRF within 0.5 % of the calibrated resonance
    w = np.linspace(HZ * target * 0.98, HZ * target * 1.02, 2001)
    fine = linear_tip_frf(beam, w, stiffness * calibration.contact_stiffness)
    assert w[np.argmax(fine)] / HZ == pytest.approx(target, rel=5e-3)
    assert branch.omega[np.argmax(a)] / HZ == pytest.approx(target, rel=0.02)


def test_named_dofs_and_forcing(calibration):
    beam = _stick_slip_beam(calibration)
    sol = hf.periodic_solution(beam, 2.0, HZ * 40.0, 5)
    assert sol.amplitude(1, dof="tip") == sol.amplitude(1, dof=beam.contact_dof)
    assert sol.amplitude(1) == sol.amplitude(1, dof="tip")
    assert sol.amplitude(1, dof="force") == sol.amplitude(1, dof=beam.dof("node:11"))
    with pytest.raises(ValueError, match="dof name"):
        sol.amplitude(1, dof="root")
    p = hf.CantileverBeam(force_dof=4).load_vector(3.0)
    assert p[4] == 3.0 and np.count_nonzero(p) == 1
    for bad in ("node:14", "node:3:twist", 39, -1, "mid"):
        with pytest.raises(ValueError):
            hf.CantileverBeam(force_dof=bad)
    with pytest.raises(ValueError, match="length"):
        hf.CantileverBeam(length=-1.0)


def test_branch_save_load_keeps_names(tmp_path, calibration):
    beam = _stick_slip_beam(calibration)
    branch = hf.frf(beam, 2.0, (HZ * 20, HZ * 40), 5)
    path = branch.save(tmp_path / "beam.npz")
    back = hf.Branch.load(path)
    np.testing.assert_array_equal(
        back.amplitude(1, dof="force"), branch.amplitude(1, dof="force")
    )


def test_paper_families_show_the_measured_regimes():
    """Fig. 13: stuck at 40 N (peak at 87 Hz, contact force below μ Fn), no
    resonance peak left near 1 N, slipping peak at 24 Hz at 0.5 N; Fig. 14:
    the twelve curves collapse by Fex/Fn."""
    from hbmfric.paper import (
        beam_normal_load_family,
        beam_ratio_family,
        ratio_collapse,
    )

    fig = beam_normal_load_family(harmonics=7, normal_loads=(40.0, 1.0, 0.5))
    peaks = {}
    for b, par in zip(fig.branches, fig.parameters, strict=True):
        assert b.stop_reason.startswith("end")
        a = b.amplitude(harmonic=1, dof="tip")
        peaks[par["normal_load"]] = (b.omega[np.argmax(a)] / HZ, a.max())
    assert peaks[40.0][0] == pytest.approx(87.0, abs=0.5)
    assert peaks[40.0][1] * fig.branches[0].info["system"]["contact"]["stiffness"] < (
        MU * 40.0
    )
    assert peaks[0.5][0] == pytest.approx(24.0, abs=0.5)
    # flat: the 1 N curve peaks far below both resonances' peaks
    assert peaks[1.0][1] < 0.35 * peaks[40.0][1]
    assert peaks[1.0][1] < 0.1 * peaks[0.5][1]

    fig14 = beam_ratio_family(
        harmonics=5, ratios=(0.5, 2.0), ratio_normal_loads=(2.5, 10.0)
    )
    spread = ratio_collapse(fig14)
    assert set(spread) == {0.5, 2.0}
    assert max(spread.values()) < 1e-6
    records = fig14.records()
    assert len(records) == 4
    assert {r.force / r.normal_load for r in records} == {0.5, 2.0}
    assert all(r.omega.shape == r.amplitude.shape for r in records)


def test_criterion_says_macroslip_without_roughness():
    """SPEC §2: on Figs. 13 and 14 together (here fewer normal loads, H = 7)
    the criterion finds no roughness and the mostly stuck curves inside the
    stuck envelope."""
    from hbmfric.paper import beam_criterion_family

    records, stuck = beam_criterion_family(
        harmonics=7,
        normal_loads=(40.0, 10.0, 5.0, 1.0),
        ratio_normal_loads=(2.5, 10.0),
    )
    assert len(records) == 10 and stuck.normal_load == 40.0
    result = hf.criterion.choose_contact_model(records, stuck=stuck)
    assert result.verdict == "macroslip without roughness", str(result)
    assert result.indicators["ratio_spread"] < 1e-8


def test_readme_beam_example_runs():
    import re
    from pathlib import Path

    text = (Path(__file__).parents[1] / "README.md").read_text()
    code = [c for c in re.findall(r"```python\n(.*?)```", text, re.S) if "Beam" in c]
    namespace: dict = {}
    exec(compile(code[0], "README.md", "exec"), namespace)
    assert namespace["branch"].info["condensed"]
    assert not namespace["full"].info["condensed"]


def test_condensed_kernels_compile_once():
    """A fresh process: beams at new loads, damping, harmonics and forcing
    points add no kernel signature after the first batch."""
    import json
    import subprocess
    import sys
    import textwrap

    code = textwrap.dedent(
        """
        import json
        import numpy as np
        import hbmfric as hf
        from hbmfric.kernels.residuals import condensed
        from hbmfric.kernels.steps import newton

        def counts():
            out = {}
            for mod in (condensed, newton):
                for name in dir(mod):
                    obj = getattr(mod, name)
                    if hasattr(obj, "signatures") and obj.__module__ == mod.__name__:
                        out[mod.__name__ + "." + name] = len(obj.signatures)
            return out

        def runs(loads, zeta, H, force_dof):
            cal = hf.CantileverBeam.calibrate(damping_ratio=zeta, force_dof=force_dof)
            for fn in loads:
                beam = cal.beam.with_contact(cal.contact(fn, 1.5))
                hf.frf(beam, 2.0, (500.0, 600.0), H)
                hf.periodic_solution(beam, 2.0, 540.0, H)

        runs((5.0,), 0.03, 5, None)
        first = counts()
        runs((2.0, 40.0), 0.01, 7, "tip")
        print(json.dumps({"first": first, "second": counts()}))
        """
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["second"] == report["first"]
    assert (
        report["first"]["hbmfric.kernels.residuals.condensed.condensed_residual"] == 1
    )
    assert report["first"]["hbmfric.kernels.steps.newton.correct"] == 1


class _BeamWithDashpot:
    """The beam with a grounded dashpot at node 6: non-classical damping."""

    def __init__(self, beam, dashpot):
        self.beam = beam
        self.dashpot = dashpot
        self.n_dof = beam.n_dof
        self.contact = beam.contact
        self.contact_dof = beam.contact_dof
        self.symmetric = beam.symmetric

    def matrices(self):
        M, C, K = self.beam.matrices()
        d = self.beam.dof("node:6")
        C[d, d] += self.dashpot
        return M, C, K

    def load_vector(self, force):
        return self.beam.load_vector(force)


def test_direct_receptance_matches_modal_and_full(calibration):
    """The direct-solve receptance agrees with the modal one on the beam,
    and handles non-classical damping (a discrete dashpot), where it is
    checked against the full HBM."""
    beam = _stick_slip_beam(calibration)
    omega = (HZ * 80.0, HZ * 95.0)
    modal = hf.frf(beam, 2.0, omega, 5, condense="modal")
    direct = hf.frf(beam, 2.0, omega, 5, condense="direct")
    assert len(modal) == len(direct)
    # the same path to the corrector's tolerance (measured 1.1e-9 on Ω since
    # the curve rule budgets the points' estimate, 1e-12 before)
    np.testing.assert_allclose(direct.omega, modal.omega, rtol=1e-8)
    scale = np.max(np.abs(modal.coefficients))
    assert np.max(np.abs(direct.coefficients - modal.coefficients)) < 1e-8 * scale

    system = _BeamWithDashpot(beam, dashpot=20.0)
    problem = CondensedHBMProblem(system, 2.0, 5)
    assert problem.receptance_method == "direct"
    with pytest.raises(ValueError, match="classical"):
        CondensedHBMProblem(system, 2.0, 5, receptance="modal")
    branch = hf.frf(system, 2.0, omega, 5)
    assert branch.info["condensed"] and branch.stop_reason.startswith("end")
    full = HBMProblem(system, 2.0, 5)
    for i in range(0, len(branch), 4):
        y = np.concatenate((branch.coefficients[i].ravel(), [branch.omega[i]]))
        assert np.max(np.abs(full.residual(y)[0])) < 1e-8 * 2.0
    # the dashpot does damp: lower peak than the classical beam
    assert branch.amplitude(1).max() < modal.amplitude(1).max()


# Rigid Coulomb on the condensed path: tests/test_condensed_coulomb.py (its
# beam branch stalls in continuation on both paths, so only Menq here).
@pytest.mark.parametrize("law_name", ["menq"])
def test_condensed_other_laws_solve_the_full_hbm(calibration, law_name):
    """Menq microslip (located-reversal AFT) through the condensation: the
    full HBM solved from recovered points stays within 1e-8, and the contact
    both sticks and slips along the branch."""
    if law_name == "coulomb":
        law = hf.Coulomb(slip_force=2.0)
    else:
        law = hf.Menq(
            axial_rigidity=1e6,
            length=0.02,
            shear_stiffness=4e8,
            friction_coefficient=MU,
            normal_load=1.5,
        )
    beam = calibration.beam.with_contact(law)
    branch = hf.frf(beam, 2.0, (HZ * 40, HZ * 110), 5)
    assert branch.info["condensed"] and branch.stop_reason.startswith("end")
    full = HBMProblem(beam, 2.0, 5)
    states = {
        full.residual(np.append(c.ravel(), w))[2]
        for c, w in zip(branch.coefficients, branch.omega, strict=True)
    }
    assert len(states) > 1  # stuck and slipping points
    # the full Newton solve from each recovered point stays put; (residuals
    # are not compared: a rigid contact's penalty, 7.6e7 N/m here, turns a
    # 1e-15 m difference into 1e-7 N)
    for i in range(0, len(branch), 3):
        sol = hf.periodic_solution(
            beam, 2.0, branch.omega[i], 5, condense=False, initial_guess=branch.point(i)
        )
        assert sol.converged
        X = branch.coefficients[i]
        assert np.max(np.abs(sol.coefficients - X)) < 1e-8 * np.max(np.abs(X))


def test_validation_figure_writes_hbm_and_time_integration(tmp_path):
    from hbmfric.paper import beam_validation

    fig = beam_validation(
        harmonics=7, validation_normal_loads=(5.0,), validation_points=3
    )
    assert len(fig.reference) == 3
    assert fig.max_difference() < 1e-3
    csv_path = fig.write_csv(tmp_path / "fig15.csv")
    rows = (tmp_path / "fig15_time_integration.csv").read_text().splitlines()
    assert csv_path.exists() and len(rows) == 4
    assert fig.write_png(tmp_path / "fig15.png").exists()


def test_non_symmetric_matrices_fall_back_to_the_full_hbm(calibration):
    beam = _stick_slip_beam(calibration)
    system = _BeamWithDashpot(beam, dashpot=0.0)
    M, C, K = beam.matrices()
    K[0, 3] += 1.0  # not symmetric any more
    system.matrices = lambda: (M, C, K)
    with pytest.raises(ValueError, match="symmetric"):
        CondensedHBMProblem(system, 2.0, 3)
    sol = hf.periodic_solution(system, 2.0, HZ * 40.0, 3)
    assert sol.converged
