"""The bolted lap joint (issue 15, showcase): hf.LapJoint / hf.lap_joint
checked against closed forms (the free–free monolithic beam, the bolt
preload), linear limits of the friction model (stuck springs, zero slip
force) solved independently with NumPy, the full finite-element model's
eigenvalues, and mesh convergence."""

import math
import warnings

import numpy as np
import pytest
import scipy.linalg

import hbmfric as hf
from hbmfric.systems.frame import TRANSVERSE

HZ = 2.0 * math.pi


def linear_receptance(M, C, K, p, omega):
    """Complex response of the linear structure to ``Re(p e^{iΩt})``."""
    return np.linalg.solve(K - omega**2 * M + 1j * omega * C, p)


# --------------------------------------------------------------------------
# interface loads


@pytest.mark.parametrize("n_pairs", [2, 10, 40, 100])
def test_slip_forces_add_up_to_mu_times_the_preload(n_pairs):
    joint = hf.LapJoint(n_pairs=n_pairs, bolt_preload=(11e3, 12e3, 13e3))
    assert joint.normal_loads().sum() == pytest.approx(36e3, rel=1e-12)
    assert joint.slip_forces().sum() == pytest.approx(0.6 * 36e3, rel=1e-12)
    assert np.all(joint.normal_loads() >= 0.0)


def test_pressure_integrates_to_the_preload_and_nodal_loads_converge():
    """The pressure profile integrates (quadrature, independent of the
    nodal rule) to the total preload over the interface width, and the
    nodal loads of a fine mesh approach the integral of the pressure over
    each pair's tributary strip."""
    joint = hf.LapJoint(n_pairs=10)
    x = np.linspace(0.0, joint.joint_length, 200001)
    total = np.trapezoid(joint.pressure(x), x) * joint.width
    assert total == pytest.approx(joint.total_preload, rel=1e-6)
    fine = hf.LapJoint(n_pairs=401)
    xp, ell = fine.pair_positions, fine.tributary_lengths
    strip = np.array(
        [
            np.trapezoid(joint.pressure(s := np.linspace(c - h / 2, c + h / 2, 51)), s)
            for c, h in zip(xp, ell, strict=True)
        ]
    )
    strip *= fine.width
    assert np.max(np.abs(fine.normal_loads() - strip)) < 1e-3 * strip.max()


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match="n_pairs"):
        hf.LapJoint(n_pairs=1)
    with pytest.raises(ValueError, match="bolt_positions"):
        hf.LapJoint(bolt_positions=(0.2,))
    with pytest.raises(ValueError, match="bolt_preload"):
        hf.LapJoint(bolt_preload=(1.0, 2.0))
    with pytest.raises(ValueError, match="joint_length"):
        hf.LapJoint(joint_length=0.5)
    with pytest.raises(ValueError, match="contact"):
        hf.LapJoint().structure("glued")


# --------------------------------------------------------------------------
# the finite-element model


def free_free_frequencies(length, e, rho, h, n=2):
    """Bending frequencies of a uniform free–free Euler–Bernoulli beam of
    square-ish section of height ``h``, Hz (β L = 4.7300, 7.8532)."""
    beta_l = np.array([4.730040745, 7.853204624])[:n]
    return beta_l**2 / (HZ * length**2) * math.sqrt(e * h * h / (12.0 * rho))


def test_a_rigidly_tied_joint_converges_to_the_monolithic_beam():
    """Every pair closed (one pressure zone over the whole overlap) and a
    very stiff contact: the two eccentric half-thickness beams become one
    beam as the pairs get denser, so the first two elastic frequencies tend
    to those of the uniform free–free beam of the assembly's length. The
    halves are tied at the nodes only (their surface displacements differ
    between nodes), so the error falls about as 1/n_pairs; the extrapolated
    limit (Richardson, fitted order) is within the rotary-inertia shift
    (0.25 % and 0.55 %) of the Euler–Bernoulli closed form. Without the
    eccentricity of the overlap elements (the change of coordinates to the
    surface DOFs) the first frequency is 163 Hz instead of 244 Hz."""
    f = []
    for n_pairs in (13, 25, 49):
        joint = hf.LapJoint(
            n_pairs=n_pairs,
            n_elements=24,
            bolt_positions=(0.06,),
            pressure_radius=1.0,
            contact_stiffness=1e19,
        )
        fr = joint.natural_frequencies("stuck", 6)
        f.append(fr[fr > 20.0][:2])
    f = np.array(f)
    d = np.diff(f, axis=0)
    assert np.all(d > 0.0)  # stiffer as the tie gets denser
    ratio = d[0] / d[1]
    assert np.all((ratio > 1.6) & (ratio < 2.6)), ratio  # about first order
    limit = f[-1] + d[-1] / (ratio - 1.0)
    ref = free_free_frequencies(
        joint.total_length, joint.youngs_modulus, joint.density, joint.thickness
    )
    np.testing.assert_allclose(limit, ref, rtol=7e-3)
    assert np.all(limit < ref)  # rotary inertia lowers them


def test_first_bending_frequency_converges_with_the_element_count():
    """Cubic Hermite elements: the frequency error falls as h⁴ (fitted
    order of the successive differences over three refinements)."""
    f = [
        hf.LapJoint(n_pairs=10, n_elements=n).natural_frequencies("stuck", 4)[3]
        for n in (2, 4, 8, 16)
    ]
    d = np.abs(np.diff(f))
    orders = np.log2(d[:-1] / d[1:])
    assert np.all(orders > 3.5), orders
    assert d[-1] < 1e-5 * f[-1]


def test_reduced_model_keeps_the_full_eigenfrequencies():
    """Craig–Bampton onto the contact DOFs plus 8 fixed-interface modes:
    the first bending frequencies (stuck and slipped joint) match the full
    model's."""
    joint = hf.LapJoint(n_pairs=10)
    for contact in ("stuck", "free"):
        full = joint.natural_frequencies(contact, 7)
        red = joint.reduced(8, contact=contact).natural_frequencies(7)
        bending = full > 20.0
        # first bending (the showcase's mode) to 1e-4, the second to 1e-3
        np.testing.assert_allclose(red[bending][0], full[bending][0], rtol=1e-4)
        np.testing.assert_allclose(red[bending][1], full[bending][1], rtol=1e-3)


# --------------------------------------------------------------------------
# the friction model's linear limits, by harmonic balance


def test_stuck_limit_is_the_linear_frf_with_contact_springs():
    """Far below the first slip (forcing 1e-3 of the onset level), every
    Jenkins element sticks: the harmonic balance of the full model equals
    the linear solve of K + Σ k_t (e_a − e_b)(e_a − e_b)ᵀ."""
    joint = hf.LapJoint(n_pairs=10)
    s = joint.structure()
    M, C, K = joint.structure("free").matrices()
    K = K + joint.contact_stiffness_matrix()
    p = s.load_vector(1.0)
    force = 1e-3
    for f in (150.0, 166.0, 175.0):
        sol = hf.periodic_solution(s, force, HZ * f, harmonics=3)
        X = linear_receptance(M, C, K, force * p, HZ * f)
        for dof in ("drive", "tip", "pair:4:a"):
            j = s.dof(dof)
            assert sol.amplitude(1, j) == pytest.approx(abs(X[j]), rel=1e-8)


def test_zero_friction_is_the_linear_frf_of_the_free_structure():
    """Zero slip forces (μ = 0): the contacts carry nothing and the harmonic
    balance equals the linear solve of the structure without them."""
    joint = hf.LapJoint(n_pairs=10, friction_coefficient=0.0)
    s = joint.structure()
    M, C, K = joint.structure("free").matrices()
    p = s.load_vector(1.0)
    # at the slipped resonance itself (144.3 Hz) the uncondensed Newton
    # could not reach tol_residual = 1e-10 |F| (the residual's rounding
    # floor there is 2e-9 N: terms of 1e7 N) and periodic_solution ran its
    # fallbacks for minutes; the corrector now accepts the rounding floor
    w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    resonance = float(np.sqrt(w2[np.argmin(np.abs(np.sqrt(w2) - HZ * 144.3))]))
    for w, condense in ((HZ * 140.0, None), (HZ * 150.0, None), (resonance, False)):
        sol = hf.periodic_solution(s, 2.0, w, harmonics=3, condense=condense)
        assert sol.converged
        X = linear_receptance(M, C, K, 2.0 * p, w)
        for dof in ("drive", "tip"):
            j = s.dof(dof)
            assert sol.amplitude(1, j) == pytest.approx(abs(X[j]), rel=1e-8)


def test_reduced_stuck_frf_matches_the_full_linear_solve():
    """The reduced model (what the showcase runs) in the stuck limit against
    the full model's linear FRF at the drive point, across the first
    bending resonance."""
    joint = hf.LapJoint(n_pairs=10)
    r = hf.lap_joint(n_pairs=10, n_modes=8)
    full = joint.structure("stuck")
    M, C, K = full.matrices()
    p = full.load_vector(1.0)
    force = 1e-3
    # (at the peak itself, 167.1 Hz, the reduced model's 4e-5 frequency
    # error is 0.75 % of the amplitude at ζ = 0.2 %; 16 modes: 0.04 %)
    for f in (150.0, 160.0, 175.0):
        sol = hf.periodic_solution(r, force, HZ * f, harmonics=3)
        X = linear_receptance(M, C, K, force * p, HZ * f)
        j = full.dof("drive")
        assert sol.amplitude(1, "drive") == pytest.approx(abs(X[j]), rel=1.5e-3)


def test_dof_names_point_at_the_pairs():
    joint = hf.LapJoint(n_pairs=5, n_elements=3)
    names = joint.dof_names
    a, b = joint.pair_dofs()
    xa = joint.node_positions("A")
    xb = joint.node_positions("B")
    for i in range(5):
        assert names[f"pair:{i}:a"] == a[i]
        na, nb = a[i] // 3, b[i] // 3 - joint.nodes_per_beam
        assert xa[na] == pytest.approx(xb[nb])
    assert names["drive"] == TRANSVERSE
    assert joint.node_positions("B")[-1] == pytest.approx(joint.total_length)


# --------------------------------------------------------------------------
# the extra figure set of `hbmfric paper`


def test_extra_figure_set_is_labelled_and_depends_on_the_ratio_only(tmp_path):
    """A small version of the extra figure set: labelled as not the
    paper's; its stuck curve is the linear stuck FRF (NumPy solve of the
    reduced model with contact springs) at every point; the two curves at
    the same Fex/P but different preloads coincide per unit force (every
    slip force scales with the preload, the stiffness does not)."""
    from hbmfric.paper import lap_joint_family

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fam = lap_joint_family(
            ratios=(2e-5, 1e-3),
            check_ratios=(1e-3,),
            harmonics=3,
            frequency_range=(158.0, 172.0),
            max_step=0.3,
        )
    # one warning for the set, naming the scene's fixed H (one per curve,
    # advising harmonics='auto', before)
    accuracy = [w for w in caught if issubclass(w.category, hf.AccuracyWarning)]
    assert len(accuracy) == 1
    assert "fixed H = 3" in str(accuracy[0].message)
    # the drive DOF it draws is not watched by the step control: the
    # warning names its lines' largest estimate (checked against
    # fixed-frequency solves in test_hunt_unwatched_dof.py)
    drive = max(float(b.curve_errors_of("drive").max()) for b in fam.branches)
    assert f"up to {drive:.2g} off" in str(accuracy[0].message)
    assert "not in the paper" in fam.title
    assert fam.name == "extra_lapjoint_n10"
    stuck = fam.branches[0]
    a = stuck.amplitude(1, "drive") / fam.parameters[0]["force"]
    r = hf.LapJoint(n_pairs=10).reduced(8, contact="stuck")
    M, C, K = r.matrices()
    p = r.load_vector(1.0)
    j = r.dof("drive")
    lin = [abs(linear_receptance(M, C, K, p, w)[j]) for w in stuck.omega]
    np.testing.assert_allclose(a, lin, rtol=1e-7)
    assert 166.5 < stuck.omega[np.argmax(a)] / HZ < 167.5
    b1, b2 = fam.branches[1], fam.branches[2]
    w = np.linspace(159.0, 171.0, 50) * HZ
    y1 = b1.amplitude_at(w, 1, "drive")[:, 0] / fam.parameters[1]["force"]
    y2 = b2.amplitude_at(w, 1, "drive")[:, 0] / fam.parameters[2]["force"]
    np.testing.assert_allclose(y1, y2, rtol=1e-6)
    path = fam.write_csv(tmp_path / "x.csv")
    header = path.read_text().splitlines()[0]
    assert "drive_amplitude_h1_per_force_m_per_N" in header


def test_lap_joint_pairs_option_is_checked():
    from hbmfric.cli import main

    with pytest.raises(SystemExit):
        main(["paper", "--lap-joint-pairs", "1"])


def test_contact2d_variant_in_the_stuck_limit():
    """The Contact2D variant (normal load varying over the cycle, the bolt
    clamping as a static load): at rest each pair carries its N_i, so far
    below slip the response is the same linear stuck FRF (normal springs
    from the elements' penalty), with no mean displacement."""
    joint = hf.LapJoint(n_pairs=6, n_elements=6)
    s = joint.structure("contact2d")
    assert len(s.contacts) == joint.closed_pairs.size
    assert not s.symmetric
    M, C, K = joint.structure("free").matrices()
    K = K + joint.contact_stiffness_matrix()
    p = s.load_vector(1.0)
    force = 1e-3
    for f in (150.0, 175.0):
        sol = hf.periodic_solution(s, force, HZ * f, harmonics=3)
        X = linear_receptance(M, C, K, force * p, HZ * f)
        for dof in ("drive", "pair:2:a"):
            j = s.dof(dof)
            assert sol.amplitude(1, j) == pytest.approx(abs(X[j]), rel=1e-7)
        mean = sol.coefficients[:, 0]
        assert np.max(np.abs(mean)) < 1e-6 * np.max(np.abs(X))


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::hbmfric.AccuracyWarning")
def test_the_criterion_reads_the_joint_as_microslip():
    """The default extra figure set (about 80 s): the stuck curve peaks at
    the stuck eigenfrequency, the highest level at the slipped one (every
    pair slipping: the structure without tangential contacts), and the
    criterion reads the family (Jenkins elements with different slip
    forces) as microslip without roughness."""
    from hbmfric.paper import lap_joint_family

    fam = lap_joint_family()
    joint = hf.LapJoint(n_pairs=10)
    stuck_f = joint.natural_frequencies("stuck", 4)[3]
    free_f = joint.natural_frequencies("free", 5)[4]
    peaks = [b.omega[np.argmax(b.amplitude(1, "drive"))] / HZ for b in fam.branches]
    assert peaks[0] == pytest.approx(stuck_f, abs=0.05)
    assert peaks[5] == pytest.approx(free_f, abs=0.3)
    assert fam.criterion().verdict == "microslip without roughness"


def _stuck_resonance_frf(condense, sweep="up"):
    from hbmfric.paper.lap_joint import LAP_JOINT_SCENE

    joint = hf.LapJoint(n_pairs=10, bolt_preload=12000.0)
    s = joint.reduced(LAP_JOINT_SCENE["n_modes"])
    force = 2e-5 * joint.total_preload
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        return hf.frf(
            s,
            force,
            (HZ * 160.0, HZ * 172.0),
            LAP_JOINT_SCENE["harmonics"],
            max_step=LAP_JOINT_SCENE["max_step"],
            condense=condense,
            sweep=sweep,
        )


def test_default_frf_covers_the_stuck_resonance():
    """The stuck joint (Fex/P = 2e-5) across its resonance at defaults
    (condensed onto the contact coordinates by complex modes since stop
    24; solved in full before): complete, every point the linear stuck
    FRF, peak at the stuck eigenfrequency (167.1 Hz)."""
    branch = _stuck_resonance_frf(None)
    assert branch.complete and branch.info["condensed"]
    a = branch.amplitude(1, "drive") / (2e-5 * 36e3)
    np.testing.assert_allclose(a, _stuck_linear_drive(branch.omega), rtol=1e-7)
    assert branch.omega[np.argmax(a)] / HZ == pytest.approx(167.11, abs=0.05)


def _stuck_linear_drive(omega):
    """Drive-point receptance (m/N) of the reduced joint with stuck contact
    springs, plain NumPy solves, at pulsations ``omega``."""
    from hbmfric.paper.lap_joint import LAP_JOINT_SCENE

    r = hf.LapJoint(n_pairs=10, bolt_preload=12000.0).reduced(
        LAP_JOINT_SCENE["n_modes"], contact="stuck"
    )
    M, C, K = r.matrices()
    p = r.load_vector(1.0)
    j = r.dof("drive")
    return np.array([abs(linear_receptance(M, C, K, p, w)[j]) for w in omega])


@pytest.mark.parametrize("sweep", ["up", "down"])
def test_condensed_frf_covers_the_stuck_resonance(sweep):
    """The same branch condensed onto the 8 contact coordinates
    (``condense=True``): complete,
    and every point is the linear stuck FRF (the joint is stuck at this
    level; NumPy solves of the reduced model with contact springs), peak at
    167.11 Hz. Before issue 15's fix the step collapsed at 166.6 Hz (2938
    points, a gap, the peak read 1.27e-4 m/N instead of 2.46e-4): the
    residual on the coordinates, ``D (q - p) + f`` with ``D = G⁻¹``,
    jitters in Ω at 2e-10 to 1e-9 N (``cond(G)`` 1.7e4) above the
    tolerance 7.2e-11 N, and the corrector hit its iteration limit."""
    branch = _stuck_resonance_frf(True, sweep)
    assert branch.complete and branch.info["condensed"]
    force = 2e-5 * 36e3
    a = branch.amplitude(1, "drive") / force
    np.testing.assert_allclose(a, _stuck_linear_drive(branch.omega), rtol=1e-7)
    assert branch.omega[np.argmax(a)] / HZ == pytest.approx(167.11, abs=0.05)
    assert len(branch.omega) < 700


def test_condensed_residual_reports_its_rounding_level():
    """On several contact coordinates the linear part of the residual is
    ``D (q - p)`` with ``D = G⁻¹``: the rounding of ``G`` reaches ``D``
    amplified by ``cond(G)``, so ``R`` jitters as Ω moves by a few ulps.
    Near the stuck resonance that jitter exceeds both the tolerance (1e-10
    of the load) and the generic floor of the residual's terms
    (:func:`~hbmfric.kernels.steps.newton.rounding_floor`), and the level the
    problem reports (which the corrector accepts) bounds it. The point is
    the stuck linear response, an exact solution at this level."""
    from hbmfric.condensation import CondensedHBMProblem
    from hbmfric.kernels.steps.newton import rounding_floor
    from hbmfric.paper.lap_joint import LAP_JOINT_SCENE

    joint = hf.LapJoint(n_pairs=10, bolt_preload=12000.0)
    s = joint.reduced(LAP_JOINT_SCENE["n_modes"])
    force = 2e-5 * joint.total_preload
    problem = CondensedHBMProblem(s, force, harmonics=9)
    n = problem.n_unknowns
    rng = np.random.default_rng(3)
    tolerance = 1e-10 * force
    for f in (166.0, 166.7, 167.1):
        y = np.append(problem.linear_response(HZ * f, "stuck"), HZ * f)
        R, J, _ = problem.residual(y)
        level = problem.rounding_level()
        floor = rounding_floor(J, y)
        jitter = 0.0
        for _ in range(40):
            d = np.zeros(n + 1)
            d[n] = y[n] * 1e-13 * rng.standard_normal()
            R2, _, _ = problem.residual(y + d)
            jitter = max(jitter, float(np.max(np.abs(R2 - R - J @ d))))
        assert jitter > max(tolerance, floor)
        assert jitter <= level
        assert np.max(np.abs(R)) <= level


def test_condensed_chords_keep_the_curve_tolerance_on_the_contact_dof():
    """Condensed onto the 8 contact coordinates (the default), the curve
    rule draws the contact DOF recovered from them, the DOF the branch
    reports: its chords stay within the curve tolerance (1e-4) where the
    rule on the first pair's slip left them 5e-4 off (Fex/P = 4e-2,
    136-139 Hz, H = 9; ``condense="direct"`` keeps that rule: the check of
    this test fails there)."""
    s = hf.lap_joint(10)
    force = 4e-2 * 36e3
    band = (HZ * 136.0, HZ * 139.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(s, force, band, 9, max_step=0.05)
        old = hf.frf(s, force, band, 9, max_step=0.05, condense="direct")
    assert branch.complete and branch.info["receptance"] == "state"
    assert np.max(branch.curve_errors) <= 1e-4
    assert np.max(old.curve_errors) > 2e-4
