"""Nonlinear modes by the extended periodic motion concept (issue 16).

References, none of them produced by the EPMC code itself:

* the single-harmonic balance (describing function) of the Jenkins element
  in closed form (SPEC §4, :func:`naive.jenkins_first_harmonic`), and of an
  Iwan element as the sum of its Jenkins elements;
* the linear modes of a proportionally damped structure (plain
  ``scipy.linalg.eigh``): frequency and damping ratio exactly;
* the peaks of forced responses (``hf.frf`` and ``hf.periodic_solution``)
  of the same system, located by a bounded scalar search;
* a reference at a much larger ``H`` for the convergence order;
* the energy balance of the periodic motion: what ``-2 D ω M ẋ`` supplies
  per cycle against the energy the contact dissipates, computed by the
  naive Jenkins march (tests/naive.py) on a fine time grid.
"""

import dataclasses
import warnings

import numpy as np
import pytest
import scipy.linalg
from naive import iwan_march, jenkins_first_harmonic, jenkins_march, loop_work
from scipy.optimize import minimize_scalar

import hbmfric as hf

M, K, KT, FS = 1.0, 1e4, 3e4, 1.0


def _oscillator(zeta=0.02, law=None):
    c = 2.0 * zeta * np.sqrt(K * M)
    law = hf.Jenkins(stiffness=KT, slip_force=FS) if law is None else law
    return hf.Oscillator(M, c, K, law)


def _single_harmonic(a, c, c1, s1):
    """ω and D of the one-harmonic EPMC of ``m ẍ + c ẋ + k x + f = 0``
    with ``f ≈ c1 cos θ + s1 sin θ`` under ``x = a cos θ``: the cosine
    balance ``-m ω² a + k a + c1 = 0`` and the sine balance
    ``(c - 2 D ω m) ω a = s1``."""
    omega = np.sqrt((K + c1 / a) / M)
    ratio = c / (2.0 * M * omega) - s1 / (2.0 * M * omega**2 * a)
    return omega, ratio


@pytest.mark.parametrize("zeta", [0.0, 0.02])
def test_jenkins_single_harmonic_against_describing_function(zeta):
    """H = 1 on the Jenkins SDOF, stuck through microslip to gross slip
    (a from 1e-6 to 1e-1 m, the stick limit fs/kt = 3.3e-5 m): ω and D of
    the closed-form describing function to 1e-8 (measured: 3e-16)."""
    osc = _oscillator(zeta)
    nm = hf.nonlinear_mode(osc, amplitude=(1e-6, 1e-1), points=31, harmonics=1)
    assert nm.complete and len(nm) == 31
    np.testing.assert_allclose(nm.amplitude, np.geomspace(1e-6, 1e-1, 31), rtol=1e-13)
    for a, w, d in zip(nm.amplitude, nm.omega, nm.damping_ratio, strict=True):
        c1, s1 = jenkins_first_harmonic(a, KT, FS)
        w_ref, d_ref = _single_harmonic(a, osc.damping, c1, s1)
        assert abs(w / w_ref - 1.0) < 1e-8
        assert abs(d - d_ref) < 1e-8
    # the stuck and the slipping limits
    assert nm.omega[0] == pytest.approx(np.sqrt((K + KT) / M), rel=1e-12)
    assert nm.damping_ratio[0] == pytest.approx(zeta * np.sqrt(K / (K + KT)), abs=1e-12)
    assert nm.omega[-1] == pytest.approx(np.sqrt(K / M), rel=2e-3)


def test_iwan_single_harmonic_against_sum_of_jenkins():
    """An Iwan element of three Jenkins elements at H = 1: its first
    harmonic is the sum of the elements' describing functions. The Masing
    AFT samples the elements' stick/slip transitions (only the reversals
    are located), so the agreement is that of the sampling: measured worst
    over the mode 5.1e-4 at the default 32 samples, 1.6e-4 at 64, 6.9e-6 at
    256, 5.4e-7 at 1024, 3.3e-8 at 4096 (order 2 in n_time)."""
    ks, fs = (1e4, 2e4, 5e3), (0.2, 1.0, 3.0)
    osc = _oscillator(0.01, hf.Iwan(stiffnesses=ks, slip_forces=fs))
    worst = []
    for n_time in (256, 4096):
        nm = hf.nonlinear_mode(
            osc, amplitude=(1e-6, 1e-1), points=25, harmonics=1, n_time=n_time
        )
        assert nm.complete
        err = 0.0
        for a, w, d in zip(nm.amplitude, nm.omega, nm.damping_ratio, strict=True):
            parts = [
                jenkins_first_harmonic(a, k, f) for k, f in zip(ks, fs, strict=True)
            ]
            c1, s1 = np.sum(parts, axis=0)
            w_ref, d_ref = _single_harmonic(a, osc.damping, c1, s1)
            err = max(err, abs(w / w_ref - 1.0), abs(d - d_ref))
        worst.append(err)
    assert worst[1] < 1e-7
    # second order in the samples: 16 times more samples, >= 100 times less
    assert worst[0] / worst[1] > 100.0


def test_convergence_in_harmonics():
    """ω and D along the Jenkins mode (a = 3e-5 … 1e-3 m, microslip to
    gross slip) against H = 127: the error falls monotonically with H and
    its fitted order is about 3.3 (measured errors of ω: 4.7e-3 at H = 1,
    1.0e-4 at H = 7, 6.8e-6 at H = 15, 4.3e-7 at H = 31)."""
    osc = _oscillator(0.02)
    span = dict(amplitude=(3e-5, 1e-3), points=21)
    ref = hf.nonlinear_mode(osc, harmonics=127, **span)
    levels = np.array([1, 3, 5, 7, 9, 11, 15, 21, 31])
    err_w, err_d = [], []
    for h in levels:
        nm = hf.nonlinear_mode(osc, harmonics=int(h), **span)
        assert nm.complete
        err_w.append(np.max(np.abs(nm.omega / ref.omega - 1.0)))
        err_d.append(np.max(np.abs(nm.damping_ratio - ref.damping_ratio)))
    err_w, err_d = np.array(err_w), np.array(err_d)
    assert np.all(np.diff(err_w) < 0.0) and np.all(np.diff(err_d) < 0.0)
    order_w = -np.polyfit(np.log(levels[2:]), np.log(err_w[2:]), 1)[0]
    order_d = -np.polyfit(np.log(levels[2:]), np.log(err_d[2:]), 1)[0]
    assert order_w > 2.8 and order_d > 2.8
    assert err_w[-1] < 1e-6 and err_d[-1] < 1e-6


def _frf_peak(system, force, harmonics):
    """Ω and first-harmonic amplitude of the FRF peak: the largest point
    of ``hf.frf``, refined by a bounded search of ``hf.periodic_solution``
    between its neighbours."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(system, force, (80.0, 230.0), harmonics=harmonics)
    i = int(np.argmax(branch.amplitude(harmonic=1)))
    lo = branch.omega[max(i - 1, 0)]
    hi = branch.omega[min(i + 1, len(branch) - 1)]

    def minus_amplitude(omega):
        sol = hf.periodic_solution(system, force, omega, harmonics=harmonics)
        return -sol.amplitude(harmonic=1)

    res = minimize_scalar(
        minus_amplitude,
        bounds=(min(lo, hi), max(lo, hi)),
        method="bounded",
        options={"xatol": 1e-9 * branch.omega[i]},
    )
    return float(res.x), float(-res.fun)


@pytest.fixture(scope="module")
def light_mode():
    """The Jenkins mode at ζ = 0.1 %, H = 7, on a fine grid (241 points,
    amplitudes 5 % apart)."""
    osc = _oscillator(1e-3)
    return osc, hf.nonlinear_mode(osc, amplitude=(1e-6, 1e-1), points=241, harmonics=7)


@pytest.mark.parametrize("force", [2e-4, 0.02, 0.2, 0.5, 1.0, 1.5, 3.0])
def test_backbone_through_frf_peaks(force, light_mode):
    """ζ = 0.1 %: the FRF peak of the forced oscillator (stuck, microslip,
    the most damped stretch with D up to 0.23, gross slip) lies on the
    backbone, within 1e-3 in frequency (measured |Ω_peak / ω(a_peak) - 1|:
    2.5e-7, 6.2e-6, 3.7e-4, 8.8e-4, 7.7e-4, 6.5e-6, 1.7e-6), and the
    mode's energy balance predicts the force, F = 2 D ω² m a (within 1 %,
    measured 0.5 % at most). ``NonlinearMode.resonances`` predicts the
    peak from the mode alone: Ω within 3e-3 and the amplitude within 1 %
    (measured 2.6e-3 and 7.5e-3 at 1 N, D = 0.23; 2e-5 and 3e-3 or better
    elsewhere)."""
    osc, fine = light_mode
    h = 7
    omega_peak, a_peak = _frf_peak(osc, force, h)
    nm = hf.nonlinear_mode(
        osc, amplitude=(a_peak * (1 - 1e-9), a_peak * (1 + 1e-9)), points=2, harmonics=h
    )
    omega, ratio = float(nm.omega.mean()), float(nm.damping_ratio.mean())
    assert abs(omega_peak / omega - 1.0) < 1e-3
    assert 2.0 * ratio * omega**2 * M * a_peak == pytest.approx(force, rel=1e-2)
    w_res, a_res = fine.resonances(force)
    j = int(np.argmin(np.abs(np.log(a_res / a_peak))))
    assert abs(w_res[j] / omega_peak - 1.0) < 3e-3
    assert abs(a_res[j] / a_peak - 1.0) < 1e-2


def _proportional_chain(alpha, beta, kt):
    """Three masses in a chain, a Jenkins contact on the last one, damping
    proportional to the stuck structure: ``C = α M + β (K + kt e eᵀ)``."""
    mass = np.diag([1.0, 2.0, 1.5])
    stiffness = 1e4 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    stuck = stiffness.copy()
    stuck[2, 2] += kt
    damping = alpha * mass + beta * stuck
    law = hf.Jenkins(stiffness=kt, slip_force=1.0)
    system = hf.LinearStructure(
        mass, stiffness, damping, contact=law, contact_dof=2, load={0: 1.0}
    )
    return system, mass, stuck


@pytest.mark.parametrize("mode", [1, 2, 3])
def test_linear_limit_gives_the_modal_frequency_and_damping(mode):
    """Contact stuck (amplitudes far below the slip limit): every mode of a
    proportionally damped 3-DOF chain has exactly its linear natural
    pulsation and damping ratio ``(α + β ω²) / (2 ω)``."""
    alpha, beta, kt = 2.0, 1e-4, 3e4
    system, mass, stuck = _proportional_chain(alpha, beta, kt)
    w2, shapes = scipy.linalg.eigh(stuck, mass)
    w = np.sqrt(w2[mode - 1])
    nm = hf.nonlinear_mode(system, mode=mode, amplitude=(1e-9, 1e-6), points=4)
    np.testing.assert_allclose(nm.omega, w, rtol=1e-12)
    np.testing.assert_allclose(
        nm.damping_ratio, (alpha + beta * w * w) / (2.0 * w), rtol=1e-10
    )
    # the motion is the mode shape, a cosine, of modal amplitude a
    phi = shapes[:, mode - 1] / np.sqrt(
        shapes[:, mode - 1] @ mass @ shapes[:, mode - 1]
    )
    for a, X in zip(nm.amplitude, nm.coefficients, strict=True):
        col = 0 if nm.harmonic_numbers[0] == 1 else 1
        xc = X[:, col]
        np.testing.assert_allclose(np.abs(xc), a * np.abs(phi), rtol=1e-9)
        np.testing.assert_allclose(X[:, col + 1], 0.0, atol=1e-12 * a)


def test_linear_oscillator_without_contact():
    """No contact at all: ω = √(k/m) and D = c / (2 √(k m)) at every
    amplitude, and ``structural_damping=False`` gives D = 0."""
    osc = hf.Oscillator(2.0, 3.0, 500.0)
    nm = hf.nonlinear_mode(osc, amplitude=(1e-3, 1e3), points=5)
    np.testing.assert_allclose(nm.omega, np.sqrt(500.0 / 2.0), rtol=1e-13)
    np.testing.assert_allclose(
        nm.damping_ratio, 3.0 / (2.0 * np.sqrt(1000.0)), rtol=1e-12
    )
    bare = hf.nonlinear_mode(
        osc, amplitude=(1e-3, 1e3), points=5, structural_damping=False
    )
    np.testing.assert_allclose(bare.damping_ratio, 0.0, atol=1e-15)


def test_friction_share_without_structural_damping():
    """``structural_damping=False``: D is the contact's share alone; on the
    SDOF at H = 1 it is the describing function's ``-S1 / (2 m ω² a)``
    and the two conventions differ by ``c / (2 m ω)`` at the same ω."""
    osc = _oscillator(0.02)
    span = dict(amplitude=(1e-5, 1e-2), points=7, harmonics=1)
    kept = hf.nonlinear_mode(osc, **span)
    bare = hf.nonlinear_mode(osc, structural_damping=False, **span)
    np.testing.assert_allclose(bare.omega, kept.omega, rtol=1e-13)
    for a, w, d in zip(bare.amplitude, bare.omega, bare.damping_ratio, strict=True):
        c1, s1 = jenkins_first_harmonic(a, KT, FS)
        assert d == pytest.approx(-s1 / (2.0 * M * w * w * a), abs=1e-12)
    np.testing.assert_allclose(
        kept.damping_ratio - bare.damping_ratio,
        osc.damping / (2.0 * M * kept.omega),
        atol=1e-12,
    )


def _supplied_energy(nm, i, mass):
    """Energy the term ``2 D ω M ẋ`` supplies per cycle:
    ``2 D ω ∫ ẋᵀ M ẋ dt = 2π D ω² Σ_k k² (Xc_kᵀ M Xc_k + Xs_kᵀ M Xs_k)``."""
    X, w, d = nm.coefficients[i], nm.omega[i], nm.damping_ratio[i]
    total, col = 0.0, 0
    for k in nm.harmonic_numbers:
        if k == 0:
            col += 1
            continue
        xc, xs = X[:, col], X[:, col + 1]
        total += k * k * (xc @ mass @ xc + xs @ mass @ xs)
        col += 2
    return 2.0 * np.pi * d * w * w * total


def _displacement(nm, i, dof, n):
    """Samples of one DOF over a period, plain NumPy synthesis."""
    theta = 2.0 * np.pi * np.arange(n) / n
    X = nm.coefficients[i, dof]
    u, col = np.zeros(n), 0
    for k in nm.harmonic_numbers:
        if k == 0:
            u += X[col]
            col += 1
            continue
        u += X[col] * np.cos(k * theta) + X[col + 1] * np.sin(k * theta)
        col += 2
    return u


@pytest.mark.parametrize("law", ["jenkins", "iwan"])
def test_energy_balance_against_the_naive_march(law):
    """At H = 15, ``structural_damping=False``: what ``-2 D ω M ẋ``
    supplies per cycle equals the energy the contact dissipates along the
    computed motion, marched by the naive law on 2^16 samples (measured
    worst relative imbalance: Jenkins 2.7e-9, Iwan at 4096 AFT samples
    2.7e-7)."""
    if law == "jenkins":
        ks, fs = (KT,), (FS,)
        contact = hf.Jenkins(stiffness=KT, slip_force=FS)
    else:
        ks, fs = (1e4, 2e4), (0.3, 1.0)
        contact = hf.Iwan(stiffnesses=ks, slip_forces=fs)
    osc = _oscillator(0.02, contact)
    # the Iwan AFT samples the element transitions: 4e-4 off at the default
    # 120 samples, hence 4096
    n_time = 4096 if law == "iwan" else None
    nm = hf.nonlinear_mode(
        osc,
        amplitude=(4e-5, 1e-2),
        points=5,
        harmonics=15,
        n_time=n_time,
        structural_damping=False,
    )
    worst = 0.0
    for i in range(len(nm)):
        u = _displacement(nm, i, 0, 2**16)
        force = iwan_march(u, ks, fs) if law == "iwan" else jenkins_march(u, KT, FS)[0]
        dissipated = loop_work(u, force)
        supplied = _supplied_energy(nm, i, np.array([[M]]))
        worst = max(worst, abs(supplied / dissipated - 1.0))
    print(f"{law}: worst relative energy imbalance {worst:.2e}")
    assert worst < 1e-6
    helper = [_supplied_energy(nm, i, np.array([[M]])) for i in range(len(nm))]
    np.testing.assert_allclose(nm.supplied_energy(), helper, rtol=1e-12)


def test_input_validation():
    osc = _oscillator()
    with pytest.raises(ValueError, match="amplitude"):
        hf.nonlinear_mode(osc, amplitude=(1e-3, 1e-4))
    with pytest.raises(ValueError, match="amplitude"):
        hf.nonlinear_mode(osc, amplitude=1e-3)
    with pytest.raises(ValueError, match="amplitude"):
        hf.nonlinear_mode(osc, amplitude=(0.0, 1e-4))
    with pytest.raises(ValueError, match="mode"):
        hf.nonlinear_mode(osc, mode=2)
    with pytest.raises(ValueError, match="mode"):
        hf.nonlinear_mode(osc, mode=0)
    with pytest.raises(ValueError, match="points"):
        hf.nonlinear_mode(osc, points=1)
    nm = hf.nonlinear_mode(osc, amplitude=(1e-6, 1e-5), points=2, harmonics=1)
    with pytest.raises(ValueError, match="force"):
        nm.resonances(0.0)
    with pytest.raises(ValueError, match="Coulomb"):
        hf.nonlinear_mode(hf.Oscillator(1.0, 0.1, 1.0, hf.Coulomb(slip_force=1.0)))


def test_result_csv_and_plot(tmp_path):
    osc = _oscillator()
    nm = hf.nonlinear_mode(osc, amplitude=(1e-6, 1e-2), points=6, harmonics=3)
    path = nm.to_csv(tmp_path / "mode.csv")
    data = np.genfromtxt(path, delimiter=",", names=True)
    np.testing.assert_array_equal(data["amplitude"], nm.amplitude)
    np.testing.assert_array_equal(data["omega_rad_s"], nm.omega)
    np.testing.assert_array_equal(data["damping_ratio"], nm.damping_ratio)
    np.testing.assert_allclose(data["frequency_hz"], nm.omega / (2 * np.pi))
    ax_w, ax_d = nm.plot()
    assert len(ax_w.lines) == 1 and len(ax_d.lines) == 1
    np.testing.assert_allclose(nm.dof_amplitude(0), nm.amplitude, rtol=1e-12)


@pytest.fixture(scope="module")
def calibrated_beam():
    cal = hf.CantileverBeam.calibrate()
    return cal, cal.contact(normal_load=2.0, friction_coefficient=1.0)


def test_beam_mode_one_between_its_linear_limits(calibrated_beam):
    """The paper's calibrated beam without viscous damping, mode 1: stuck
    (small amplitude) it is the linear mode with the contact stiffness at
    the tip (87 Hz, ``D = 0`` exactly); in gross slip the frequency falls
    towards the free beam's 24 Hz (1.1e-5 off at a = 0.1: measured) and the
    friction damping decays like 1/a; D peaks (about 0.5) in between."""
    cal, law = calibrated_beam
    beam = dataclasses.replace(cal.beam, damping_ratio=0.0, contact=law)
    stuck = 2.0 * np.pi * beam.natural_frequencies("stuck", 1)[0]
    free = 2.0 * np.pi * beam.natural_frequencies("free", 1)[0]
    nm = hf.nonlinear_mode(
        beam, amplitude=(1e-6, 1e-1), points=11, harmonics=3, harmonic_tolerance=None
    )
    assert nm.complete
    assert nm.omega[0] == pytest.approx(stuck, rel=1e-11)
    assert abs(nm.damping_ratio[0]) < 1e-12
    assert np.all(np.diff(nm.omega) <= 1e-9 * stuck)  # softening throughout
    assert nm.omega[-1] == pytest.approx(free, rel=1e-4)
    assert 0.3 < nm.damping_ratio.max() < 0.7
    # far in gross slip D a is nearly constant (dissipation 4 fs u_tip)
    tail = nm.damping_ratio[-3:] * nm.amplitude[-3:]
    assert np.ptp(tail) < 1e-2 * tail.mean()  # measured 1.3e-3


@pytest.mark.slow
def test_beam_energy_balance_against_the_naive_march(calibrated_beam):
    """Beam mode 1 at H = 7 without the structure's damping: the energy
    supplied per cycle equals what the tip contact dissipates along the
    computed motion, marched by the naive Jenkins law (measured 2.5e-9)."""
    cal, law = calibrated_beam
    beam = cal.beam.with_contact(law)
    nm = hf.nonlinear_mode(
        beam,
        amplitude=(3e-4, 3e-2),
        points=4,
        harmonics=7,
        structural_damping=False,
        harmonic_tolerance=None,
    )
    assert nm.complete
    mass = beam.matrices()[0]
    worst = 0.0
    for i in range(len(nm)):
        u = _displacement(nm, i, beam.contact_dof, 2**16)
        dissipated = loop_work(u, jenkins_march(u, law.stiffness, law.slip_force)[0])
        worst = max(worst, abs(_supplied_energy(nm, i, mass) / dissipated - 1.0))
    assert worst < 1e-6


def _menq_first_harmonic(a, law):
    """``c1, s1`` of the closed-form Menq loop under ``u = a cos θ`` by
    adaptive quadrature: unloading from ``(a, F_load(a))`` by Masing's rule
    on ``[0, π]``, the odd mirror image on ``[π, 2π]``."""
    from naive import menq_virgin
    from scipy.integrate import quad

    args = (law.axial_rigidity, law.length, law.shear_stiffness, law.friction_limit)
    top = menq_virgin(a, *args)

    def force(theta):
        return top - 2.0 * menq_virgin(0.5 * a * (1.0 - np.cos(theta)), *args)

    opts = dict(epsabs=1e-15 * top, epsrel=1e-13, limit=200)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # quad's round-off notice at 1e-13
        c1 = quad(lambda t: force(t) * np.cos(t), 0.0, np.pi, **opts)[0]
        s1 = quad(lambda t: force(t) * np.sin(t), 0.0, np.pi, **opts)[0]
    return 2.0 * c1 / np.pi, 2.0 * s1 / np.pi


def test_menq_single_harmonic_against_the_closed_form_loop():
    """Menq microslip at H = 1 against the quadrature of the SPEC closed
    form loop, from stuck to gross slip. The Masing AFT samples the loop
    (reversals located): measured worst 8.8e-3 at the default 32 samples,
    5.1e-5 at 256, 2.3e-6 at 1024 (order 2 in n_time)."""
    law = hf.Menq(
        axial_rigidity=1e5, length=0.1, shear_stiffness=1e7, friction_limit=10.0
    )
    osc = _oscillator(0.02, law)
    worst = []
    for n_time in (256, 1024):
        nm = hf.nonlinear_mode(
            osc, amplitude=(1e-7, 1e-3), points=7, harmonics=1, n_time=n_time
        )
        assert nm.complete
        err = 0.0
        for a, w, d in zip(nm.amplitude, nm.omega, nm.damping_ratio, strict=True):
            w_ref, d_ref = _single_harmonic(
                a, osc.damping, *_menq_first_harmonic(a, law)
            )
            err = max(err, abs(w / w_ref - 1.0), abs(d - d_ref))
        worst.append(err)
    assert worst[1] < 5e-6
    assert worst[0] / worst[1] > 10.0  # 4 times the samples


def test_duffing_single_harmonic_backbone():
    """A cubic spring (a memoryless law, the sampled AFT alias-free) at
    H = 1: ``ω² = (k + ¾ k3 a²) / m`` and ``D = c / (2 m ω)``."""
    k3 = 1e8
    osc = _oscillator(0.02, hf.Cubic(k3))
    nm = hf.nonlinear_mode(osc, amplitude=(1e-4, 3e-2), points=9, harmonics=1)
    omega = np.sqrt((K + 0.75 * k3 * nm.amplitude**2) / M)
    np.testing.assert_allclose(nm.omega, omega, rtol=1e-12)
    np.testing.assert_allclose(
        nm.damping_ratio, osc.damping / (2 * M * omega), rtol=1e-11
    )


def test_several_contacts_stuck_limit():
    """The README's structure with three contacts (to ground, between two
    DOFs, a 2D element held closed by a static load against its preload),
    modes 1 and 2. Its modal damping is that of the structure without
    contacts, not proportional once they stick: at a = 1e-8 the EPMC then
    matches the complex eigenvalue λ of the stuck structure (state-space
    eigenvalues of K plus the stuck springs, built here by hand): ω = |λ|
    to 1e-8 and D = -Re λ / |λ| to 1e-4 relative (measured 4e-10 and
    7e-6); the backbone then softens."""
    law = hf.Jenkins(stiffness=500.0, slip_force=2.0)
    element = hf.Contact2D(500.0, 2e3, friction_coefficient=0.3, preload=5.0)
    mass = np.eye(4)
    stiffness = 1e3 * (2 * np.eye(4) - np.eye(4, k=1) - np.eye(4, k=-1))
    s = hf.LinearStructure(
        mass,
        stiffness,
        modal_damping=0.01,
        load={0: 1.0},
        static_load={3: 5.0},
        contacts=[
            hf.Contact(law, 1),
            hf.Contact(law, 1, other=2),
            hf.Contact(element, 2, normal=3),
        ],
    )
    stuck = stiffness.copy()
    stuck[1, 1] += 500.0  # to ground
    stuck[np.ix_([1, 2], [1, 2])] += 500.0 * np.array([[1.0, -1.0], [-1.0, 1.0]])
    stuck[2, 2] += 500.0  # 2D element, tangential
    stuck[3, 3] += 2e3  # 2D element, normal
    w_lin = np.sqrt(scipy.linalg.eigh(stuck, mass, eigvals_only=True))
    damping = s.matrices()[1]
    state = np.block(
        [
            [np.zeros((4, 4)), np.eye(4)],
            [-np.linalg.solve(mass, stuck), -np.linalg.solve(mass, damping)],
        ]
    )
    lam = np.linalg.eigvals(state)
    lam = lam[lam.imag > 0]
    lam = lam[np.argsort(np.abs(lam))]
    for mode in (1, 2):
        nm = hf.nonlinear_mode(s, mode=mode, amplitude=(1e-8, 1e1), points=10)
        assert nm.complete
        assert nm.linear_omega == pytest.approx(w_lin[mode - 1], rel=1e-12)
        ref = lam[mode - 1]
        assert nm.omega[0] == pytest.approx(abs(ref), rel=1e-8)
        assert nm.damping_ratio[0] == pytest.approx(-ref.real / abs(ref), rel=1e-4)
        assert np.all(np.diff(nm.omega) < 1e-9 * nm.omega[0])
        assert nm.omega[-1] < 0.9 * nm.omega[0]
        assert np.all(nm.damping_ratio > 0.0)


def test_warns_when_the_range_is_not_covered(monkeypatch):
    """A Newton that gives up after 2 iterations finds the stuck (linear)
    points but not the slipping ones: a CoverageWarning and the points
    found; with 1 iteration, from a slipping start, not even the first: a
    ConvergenceWarning."""
    import hbmfric.modes as modes

    osc = _oscillator()
    monkeypatch.setattr(modes, "MAX_ITERATIONS", 2)
    with pytest.warns(hf.CoverageWarning, match="up to a ="):
        nm = hf.nonlinear_mode(osc, amplitude=(1e-6, 1e-2), points=9, harmonics=3)
    assert not nm.complete and 1 <= len(nm) < 9
    assert nm.amplitude[-1] < 1e-4 and "Newton failed" in nm.stop_reason
    # from 1e-3 (slipping) the start backs off to the stuck 1e-5 (where the
    # linear mode is exact), then fails on the way back up
    monkeypatch.setattr(modes, "MAX_ITERATIONS", 1)
    with pytest.warns(hf.ConvergenceWarning, match="no point"):
        nm = hf.nonlinear_mode(osc, amplitude=(1e-3, 1e-2), points=9, harmonics=3)
    assert len(nm) == 0


@pytest.mark.slow
@pytest.mark.parametrize("force", [0.05, 5.0, 20.0])
def test_beam_backbone_through_frf_peaks(calibrated_beam, force):
    """The paper beam at ζ = 0.2 %, H = 5: the peak of the tip's FRF lies
    on the backbone at the peak's modal amplitude within 1e-3 where the
    damping is light (measured: 5.6e-4 stuck at 0.05 N, D = 0.008; 1.1e-5
    and 4.8e-6 in gross slip at 5 and 20 N). Not in the heavily damped
    microslip stretch: 2.2e-3 at 0.5 N (D = 0.07), 3.8e-2 at 2 N
    (D = 0.29), where the forced motion is no longer one mode's."""
    cal, law = calibrated_beam
    beam = dataclasses.replace(cal.beam, damping_ratio=0.002, contact=law)
    mass = beam.matrices()[0]
    h = 5
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(beam, force, (2 * np.pi * 15, 2 * np.pi * 100), harmonics=h)
    i = int(np.argmax(branch.amplitude(harmonic=1, dof="tip")))
    lo, hi = sorted((branch.omega[max(i - 1, 0)], branch.omega[i + 1]))

    def solve(omega):
        return hf.periodic_solution(beam, force, omega, harmonics=h)

    res = minimize_scalar(
        lambda w: -solve(w).amplitude(harmonic=1, dof="tip"),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-9 * hi},
    )
    X = solve(res.x).coefficients
    col = 0 if branch.harmonic_numbers[0] == 1 else 1
    a = np.sqrt(X[:, col] @ mass @ X[:, col] + X[:, col + 1] @ mass @ X[:, col + 1])
    nm = hf.nonlinear_mode(
        beam, amplitude=(a * (1 - 1e-9), a * (1 + 1e-9)), points=2, harmonics=h
    )
    assert abs(res.x / nm.omega.mean() - 1.0) < 1e-3


def test_docs_example_runs(tmp_path, monkeypatch):
    """docs/modes.md's example runs as written, without warnings."""
    import re
    from pathlib import Path

    text = (Path(__file__).parents[1] / "docs" / "modes.md").read_text()
    code = re.findall(r"```python\n(.*?)```", text, re.S)[0]
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        exec(compile(code, "docs/modes.md", "exec"), namespace)
    assert namespace["mode"].complete and (tmp_path / "mode.csv").exists()


def test_tensioner_dahl_energy_against_the_closed_form():
    """The belt tensioner (2 DOF, static load, modified Dahl contact with
    parallel envelopes a = d) at H = 1 without the belt's damping: the
    energy the mode supplies per cycle is the Dahl loop's closed-form
    energy (SPEC §4, μ = 1; a mean displacement shifts both envelopes
    alike, a = d) at the contact's first-harmonic amplitude X,
    ``W = 2 (b − e − (a + d)/β)(X − tanh(βX)/β)``: 2.7e-12 relative at
    4096 AFT samples (measured; 1.2e-3 at the default 32, 7.9e-8 at
    256)."""
    t = hf.BeltTensioner()
    law = t.contact
    (a, b), (d, e) = law.upper, law.lower
    nm = hf.nonlinear_mode(
        t,
        amplitude=(1e-4, 1e-1),
        points=7,
        harmonics=1,
        n_time=4096,
        structural_damping=False,
    )
    assert nm.complete
    X = nm.dof_amplitude(t.contact_dof)
    W = 2.0 * (b - e - (a + d) / law.beta) * (X - np.tanh(law.beta * X) / law.beta)
    np.testing.assert_allclose(nm.supplied_energy(), W, rtol=1e-10)


def test_save_and_load_round_trip(tmp_path, light_mode):
    """``save``/``load`` (npz, no pickle) keep every array and what
    ``resonances`` needs; a foreign file is refused with a ValueError."""
    _, nm = light_mode
    path = nm.save(tmp_path / "mode.npz")
    back = hf.NonlinearMode.load(path)
    for name in ("amplitude", "omega", "damping_ratio", "coefficients", "load_vector"):
        np.testing.assert_array_equal(getattr(back, name), getattr(nm, name))
    np.testing.assert_array_equal(back.harmonic_numbers, nm.harmonic_numbers)
    assert back.requested == nm.requested and back.info == nm.info
    np.testing.assert_array_equal(back.resonances(0.5)[0], nm.resonances(0.5)[0])
    other = tmp_path / "other.npz"
    np.savez(other, meta=np.array('{"format": "hbmfric.Branch/1"}'))
    with pytest.raises(ValueError, match="not an hbmfric nonlinear-mode file"):
        hf.NonlinearMode.load(other)


@pytest.mark.parametrize(
    "law",
    [hf.Cubic(1e8), hf.Jenkins(stiffness=KT, slip_force=FS)],
    ids=["cubic", "jenkins"],
)
def test_equations_jacobian_against_finite_differences(law):
    """The EPMC Jacobian (HBM rows with the ``-2 D ω M ẋ`` term, ω and D
    columns, the normalisation and phase rows) against central finite
    differences at a solution of the mode perturbed off it (Jenkins: in
    gross slip, away from the stick/slip kinks), H = 5 on two DOFs."""
    from hbmfric.modes import _EPMC

    mass = np.diag([1.0, 0.5])
    stiffness = 1e4 * np.array([[2.0, -1.0], [-1.0, 1.0]])
    s = hf.LinearStructure(
        mass, stiffness, rayleigh=(1.0, 1e-4), contact=law, contact_dof=1
    )
    epmc = _EPMC(s, 1, 5, None, "auto", True)
    a = 3e-3
    nm = hf.nonlinear_mode(s, amplitude=(a, 2 * a), points=2, harmonics=5)
    rng = np.random.default_rng(3)
    z = np.concatenate(
        [nm.coefficients[0].reshape(-1) / a, [nm.omega[0], nm.damping_ratio[0]]]
    )
    z = z * (1.0 + 1e-3 * rng.standard_normal(z.size))
    _, J, _ = epmc.equations(z, a)
    fd = np.empty_like(J)
    for j in range(z.size):
        h = 1e-7 * max(abs(z[j]), 1e-3)
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        fd[:, j] = (epmc.equations(zp, a)[0] - epmc.equations(zm, a)[0]) / (2 * h)
    np.testing.assert_allclose(J, fd, rtol=0, atol=1e-6 * np.max(np.abs(J)))


def test_newton_work():
    """Work counters: a stuck (linear) point takes 1 Newton iteration (the
    start and the predictor are exact there: the first correction is at
    rounding level), the slipping ones at most 8 (measured 3 to 4). At the
    stick limit ω falls from 200 to 137 rad/s within half a decade: the
    steps there are halved until the solution lands within 0.02 of the
    predictor (measured: 46 steps, 8 rejected, for the 31 points)."""
    nm = hf.nonlinear_mode(_oscillator(), amplitude=(1e-6, 1e-1), points=31)
    assert nm.complete and nm.folds.size == 0
    assert 31 <= nm.n_steps - nm.n_rejected <= 45 and nm.n_rejected <= 12
    stuck = nm.amplitude < FS / KT
    assert np.all(nm.newton_iterations[stuck] == 1)
    assert np.all(nm.newton_iterations <= 8)


def test_a_jump_to_another_shape_is_refused(monkeypatch):
    """Every step whose fundamental shape correlates below MAC_TOLERANCE
    with the previous point's is rejected: with the tolerance above 1 no
    step passes and the run stops with a CoverageWarning that says so."""
    import hbmfric.modes as modes

    monkeypatch.setattr(modes, "MAC_TOLERANCE", 1.5)
    with pytest.warns(hf.CoverageWarning, match="mode shape jumped"):
        nm = hf.nonlinear_mode(_oscillator(), amplitude=(1e-6, 1e-2), points=5)
    assert len(nm) == 1 and "internal resonance" in nm.stop_reason


def test_truncation_estimate_against_a_large_harmonic_reference():
    """``NonlinearMode.truncation_error`` (one Newton step in the basis
    2H + 1) against the true error (relative ω, absolute D) measured
    against H = 127 on the Jenkins mode: within a factor 2 at every
    non-linear point (measured ratios 0.74 to 1.28 for H = 1 … 31), and
    the AccuracyWarning fires above the tolerance only."""
    osc = _oscillator(0.02)
    span = dict(amplitude=(3e-5, 1e-3), points=11)
    ref = hf.nonlinear_mode(osc, harmonics=127, harmonic_tolerance=None, **span)
    for h in (3, 7, 15):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            nm = hf.nonlinear_mode(osc, harmonics=h, harmonic_tolerance=3e-4, **span)
        true = np.maximum(
            np.abs(nm.omega / ref.omega - 1.0),
            np.abs(nm.damping_ratio - ref.damping_ratio),
        )
        slipping = true > 1e-10
        ratio = nm.truncation_error[slipping] / true[slipping]
        assert np.all((ratio > 0.5) & (ratio < 2.0)), (h, ratio)
        warned = any(issubclass(w.category, hf.AccuracyWarning) for w in caught)
        assert warned == bool(np.any(nm.truncation_error > 3e-4))
    assert warned is False  # H = 15: 6.6e-6


def test_beam_backbone_turns_in_amplitude(calibrated_beam):
    """The paper beam's mode 1 turns twice in amplitude near the stick
    limit (at H = 3: a = 3.95e-5 and 1.27e-5; also at H = 7 and 9): the
    natural step fails at the first turn, the pseudo-arclength
    continuation follows the S and the grid continues past it, with a
    warning naming the turns. Between them one amplitude has three
    solutions: the grid point (the lower branch, reached from below) and
    two more on the path."""
    cal, law = calibrated_beam
    beam = cal.beam.with_contact(law)
    with pytest.warns(hf.HbmfricWarning, match="turns in amplitude"):
        nm = hf.nonlinear_mode(
            beam,
            amplitude=(1e-6, 1e-1),
            points=11,
            harmonics=3,
            harmonic_tolerance=None,
        )
    assert nm.complete and nm.folds.size == 2
    upper, lower = nm.folds
    assert 3.8e-5 < upper < 4.1e-5 and 1.2e-5 < lower < 1.35e-5
    a_path = nm.fold_path[:, 0]
    assert a_path.min() == pytest.approx(lower, rel=0.05)
    # three solutions at the grid amplitude 3.16e-5 inside the S
    i = 3
    assert lower < nm.amplitude[i] < upper
    crossings = np.flatnonzero(np.diff(np.sign(a_path - nm.amplitude[i])))
    assert crossings.size == 2
    omegas = [nm.omega[i]] + [nm.fold_path[j, 1] for j in crossings]
    assert np.min(np.abs(np.diff(np.sort(omegas)))) > 1.0  # rad/s apart


def _spring_chain(kt, zeta=0.01):
    """The 30-DOF spring-mass chain of issue 16 (fixed at DOF 0's outer
    spring, free at the tip), Jenkins at the tip, modal damping ``zeta`` of
    the chain without contact built here in plain SciPy; returns the
    structure and its (M, C, K)."""
    n, k, m = 30, 2.0e4, 0.05
    Kc = 2.0 * k * np.eye(n) - k * np.eye(n, k=1) - k * np.eye(n, k=-1)
    Kc[n - 1, n - 1] = k
    Mc = m * np.eye(n)
    w2, phi = scipy.linalg.eigh(Kc, Mc)
    Cc = Mc @ phi @ np.diag(2.0 * zeta * np.sqrt(w2)) @ phi.T @ Mc
    structure = hf.LinearStructure(
        Mc,
        Kc,
        damping=Cc,
        dof_names={"drive": 10, "tip": n - 1},
        load={"drive": 1.0},
        contact=hf.Jenkins(stiffness=kt, slip_force=1.0),
        contact_dof="tip",
    )
    return structure, (Mc, Cc, Kc)


def _chain_residual(nm, i, matrices, kt, n_time=4096):
    """Largest harmonic-balance residual of the EPMC equation at point
    ``i``, relative to the largest elastic force ``|K X|``: plain NumPy
    synthesis, the tip force by the naive Jenkins march, np.fft analysis."""
    Mc, Cc, Kc = matrices
    omega, ratio = nm.omega[i], nm.damping_ratio[i]
    X = np.array([_displacement(nm, i, d, n_time) for d in range(Mc.shape[0])])
    f = np.zeros_like(X)
    f[-1] = jenkins_march(X[-1], kt, 1.0)[0]
    spec_x = np.fft.rfft(X, axis=1)
    spec_f = np.fft.rfft(f, axis=1)
    worst, scale = 0.0, 0.0
    for k in nm.harmonic_numbers:
        w = k * omega
        dyn = Kc - w * w * Mc + 1j * w * (Cc - 2.0 * ratio * omega * Mc)
        r = dyn @ spec_x[:, k] + spec_f[:, k]
        worst = max(worst, float(np.max(np.abs(r))))
        scale = max(scale, float(np.max(np.abs(Kc @ spec_x[:, k]))))
    return worst / scale


def test_spring_chain_backbone_passes_the_internal_resonance_loop():
    """Issue 16: the chain with kt = 500 slips towards the free chain,
    whose modes are nearly 1:3:5 (97.62 / 32.57 = 2.997): the backbone
    loops about the 3:1 internal resonance, turning four times in
    amplitude (2.36e-2, 2.79e-3, 1.53e-2, 4.97e-3). The fold passage
    follows the loop and the mode covers 1e-6 to 1e-1 (on merge26: stopped
    at 2.3e-2, 'Newton failed'); its points satisfy the EPMC equations,
    checked by plain NumPy harmonic balance with the naive Jenkins march
    (the residual left is the AFT-versus-march and truncation part)."""
    kt = 500.0
    chain, matrices = _spring_chain(kt)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        with pytest.warns(hf.HbmfricWarning, match="turns in amplitude"):
            nm = hf.nonlinear_mode(chain, amplitude=(1e-6, 1e-1), points=40)
    assert nm.complete, nm.stop_reason
    assert nm.amplitude[-1] == 1e-1 and len(nm) == 40
    assert len(nm.folds) >= 2
    # stuck: the linear mode with the tip spring; far slipping: towards the
    # free chain's 32.57 rad/s
    w_free = np.sqrt(scipy.linalg.eigh(matrices[2], matrices[0], eigvals_only=True))
    assert nm.omega[0] == pytest.approx(nm.linear_omega, rel=1e-5)
    assert abs(nm.omega[-1] / w_free[0] - 1.0) < 2e-3
    worst = max(_chain_residual(nm, i, matrices, kt) for i in range(0, 40, 3))
    print(f"worst relative EPMC residual {worst:.2e}")
    assert worst < 1e-4


def test_spring_chain_stops_at_the_internal_resonance_with_that_reason():
    """Issue 16: with kt = 5e3 the stuck chain's mode 3 is at 3.05 ω1;
    just past the slip onset (a = 5.2e-4) the path turns back at
    a = 6.0e-4 and runs down along harmonic 3 (3 ω -> ω3 = 178.57 rad/s,
    the fundamental -> 0): mode 3 seen at a third of its frequency. The
    stop names the 3:1 internal resonance (on merge26: 'Newton failed')."""
    chain, _ = _spring_chain(5e3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        with pytest.warns(hf.CoverageWarning, match="3:1 internal resonance"):
            nm = hf.nonlinear_mode(
                chain, amplitude=(1e-6, 1e-1), points=40, upper_branch=False
            )
    assert "turns back at a = 0.0006" in nm.stop_reason
    assert "linear mode 3 of the stuck structure" in nm.stop_reason
    assert 5.2e-4 > nm.amplitude[-1] > 4.5e-4
    assert nm.pieces is None and nm.gaps == [(nm.amplitude[-1], 1e-1)]


def test_spring_chain_stiff_contact_stops_at_a_named_internal_resonance():
    """Issue 16: with kt = 5e4 the stuck chain is nearly 1:2:3:4:5 (ω5 =
    323.20 = 4.947 ω1). Past the slip onset the backbone turns (a =
    5.40e-4, 5.21e-4, 5.51e-4) and the path runs down along harmonic 5,
    which grows to 2.6 times the fundamental at a = 3.25e-5 (5 ω = 323.1
    rad/s: mode 5), turns back there and fails at a kink at a = 1.95e-4
    (plain Newton cycled between two corrections there; with the line
    search it converges, but no longer step passes the kink). The stop
    names the 5:1 internal resonance and the stuck mode 5 (on main:
    'Newton failed at a = 0.0005511', no resonance named); the points
    found satisfy the EPMC equations (plain NumPy check)."""
    kt = 5e4
    chain, matrices = _spring_chain(kt)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        with pytest.warns(hf.CoverageWarning, match="5:1 internal resonance"):
            nm = hf.nonlinear_mode(
                chain, amplitude=(1e-6, 1e-1), points=40, upper_branch=False
            )
    assert "linear mode 5 of the stuck structure" in nm.stop_reason
    assert "Newton failed" not in nm.stop_reason
    assert 5.2e-4 > nm.amplitude[-1] > 4.5e-4
    worst = max(_chain_residual(nm, i, matrices, kt) for i in range(0, len(nm), 3))
    assert worst < 1e-4


def _slipped_limit(matrices, slip_force=1.0):
    """ω and the damping-ratio function of the chain's mode 1 with the tip
    sliding freely: the free chain's ω1 and ``D(a) = ζ1 + W / (2π ω1² a²)``
    with ``W = 4 F_s a |φ_tip|`` the work of a sliding Coulomb force over
    one cycle of the tip's harmonic motion (φ mass-normalised)."""
    Mc, Cc, Kc = matrices
    w2, vecs = scipy.linalg.eigh(Kc, Mc)
    phi = vecs[:, 0] / np.sqrt(vecs[:, 0] @ Mc @ vecs[:, 0])
    w1 = float(np.sqrt(w2[0]))
    zeta = float(phi @ Cc @ phi) / (2.0 * w1)

    def ratio(a):
        return zeta + 4.0 * slip_force * abs(phi[-1]) / (2.0 * np.pi * w1**2 * a)

    return w1, ratio


@pytest.mark.parametrize("kt", [5e3, 5e4])
def test_spring_chain_upper_branch_beyond_the_internal_resonance(kt, tmp_path):
    """Issue 16: the run that stops at the internal resonance continues the
    mode down from the top of the range (upper_branch, default), from the
    chain's mode 1 with the tip slipping: two pieces, the gap between them
    reported. The upper piece against independent references: its points
    satisfy the EPMC equations (plain NumPy harmonic balance, naive
    Jenkins march; measured worst 4.5e-5 / 4.2e-5 at kt = 5e3 / 5e4); at
    a = 0.1 ω is the free chain's ω1 within 1e-3 (measured 1.2e-4 /
    2.4e-4) and D the sliding-Coulomb energy balance within 1e-3 (measured
    1.6e-4 / 5.6e-5), approached as a grows
    (the error of D falls over the last four points). Saved, loaded,
    drawn and written per piece; resonances not interpolated across the
    gap."""
    chain, matrices = _spring_chain(kt)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        with pytest.warns(hf.CoverageWarning, match="internal resonance"):
            nm = hf.nonlinear_mode(chain, amplitude=(1e-6, 1e-1), points=40)
    assert not nm.complete and nm.pieces is not None and len(nm.pieces) == 2
    lower, upper = nm.piece_slices()
    assert np.all(np.diff(nm.amplitude) > 0.0)
    assert nm.amplitude[-1] == 1e-1
    (gap,) = nm.gaps
    assert gap == (nm.amplitude[lower][-1], nm.amplitude[upper][0])
    assert 4.5e-4 < gap[0] < 5.2e-4 and 5.7e-4 < gap[1] < 1e-3
    assert "not computed between a = 0.0004924" in nm.stop_reason
    # the upper piece: EPMC residual, the slipped limits
    worst = max(
        _chain_residual(nm, i, matrices, kt) for i in range(upper.start, upper.stop)
    )
    assert worst < 1e-4
    w1, ratio = _slipped_limit(matrices)
    assert abs(nm.omega[-1] / w1 - 1.0) < 1e-3
    error = np.abs(nm.damping_ratio[upper] / ratio(nm.amplitude[upper]) - 1.0)
    assert error[-1] < 1e-3 and np.all(np.diff(error[-4:]) < 0.0)
    # far from stuck: the upper piece is in the slipped regime (ω near ω1,
    # not the stuck linear ω)
    assert np.all(nm.omega[upper] < 1.1 * w1)
    assert np.all(nm.omega[lower] > 0.9 * nm.linear_omega)
    # the force balanced over the mode jumps across the gap (kt = 5e3:
    # 0.027 N below it, 4.8 N above): no resonance is interpolated into it
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.CoverageWarning)
        for force in (0.1, 1.0, 2.0):
            _, a_res = nm.resonances(force)
            assert not np.any((a_res > gap[0]) & (a_res < gap[1])), (force, a_res)
    # per piece: the file, the plot, the CSV
    back = hf.NonlinearMode.load(nm.save(tmp_path / "m.npz"))
    np.testing.assert_array_equal(back.pieces, nm.pieces)
    assert back.gaps == nm.gaps
    ax_w, ax_d = nm.plot()
    assert len(ax_w.lines) == 2 and len(ax_d.lines) == 2
    data = np.genfromtxt(nm.to_csv(tmp_path / "m.csv"), delimiter=",", names=True)
    np.testing.assert_array_equal(
        data["piece"], [0] * lower.stop + [1] * (upper.stop - upper.start)
    )


def _chain_modal_amplitude(solution_coefficients, mass, harmonic_numbers):
    """Mass-norm amplitude of the fundamental, shape (...,)."""
    c = coefficient_columns_of(harmonic_numbers)[1]
    xc, xs = solution_coefficients[..., c], solution_coefficients[..., c + 1]
    return np.sqrt(
        np.einsum("...i,ij,...j->...", xc, mass, xc)
        + np.einsum("...i,ij,...j->...", xs, mass, xs)
    )


def coefficient_columns_of(harmonic_numbers):
    """Column of each harmonic's cosine (the mean: its only column)."""
    out, col = {}, 0
    for k in harmonic_numbers:
        out[int(k)] = col
        col += 1 if k == 0 else 2
    return out


def _chain_frf_peak(chain, Mc, force, omega_range, h):
    """The FRF peak of the forced chain in modal amplitude: the branch's
    largest point, refined by a bounded search of ``hf.periodic_solution``
    between its neighbours; returns ``(Ω_peak, a_peak)``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        branch = hf.frf(chain, force, omega_range, harmonics=h)
    a = _chain_modal_amplitude(branch.coefficients, Mc, branch.harmonic_numbers)
    i = int(np.argmax(a))

    def minus_amplitude(omega):
        sol = hf.periodic_solution(chain, force, omega, harmonics=h)
        X = sol.coefficients.reshape(Mc.shape[0], -1)
        return -float(_chain_modal_amplitude(X, Mc, sol.harmonic_numbers))

    lo, hi = branch.omega[max(i - 1, 0)], branch.omega[min(i + 1, len(branch) - 1)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        res = minimize_scalar(
            minus_amplitude,
            bounds=(min(lo, hi), max(lo, hi)),
            method="bounded",
            options={"xatol": 1e-9 * branch.omega[i]},
        )
    return float(res.x), float(-res.fun)


@pytest.mark.slow
@pytest.mark.parametrize("force", [0.003, 0.05])
def test_spring_chain_backbone_through_frf_peaks(force):
    """Issue 16 chain, kt = 500, ζ = 0.1 %: the FRF peak of the forced
    chain (driven at DOF 10; stuck, and at the slip onset, D = 5e-3),
    refined by a bounded search of ``hf.periodic_solution``, lies on the
    backbone at its modal amplitude within 1e-3 in frequency (measured
    6.7e-7 and 5.7e-4); the backbone point is continued from the stuck
    1e-4 up to that amplitude. Not asserted: the heavily damped peaks at
    F = 0.5 N (D = 0.041) and 2 N (D = 0.059) lie 2.5e-3 below and 4.9e-3
    above the backbone (about 1.4 D²: one forced mode is no longer the
    free one)."""
    chain, (Mc, _, _) = _spring_chain(500.0, 1e-3)
    h = 7
    omega_peak, a_peak = _chain_frf_peak(chain, Mc, force, (28.0, 44.0), h)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        nm = hf.nonlinear_mode(
            chain,
            amplitude=(min(1e-4, 0.5 * a_peak), a_peak),
            points=2,
            harmonics=h,
            harmonic_tolerance=None,
        )
    assert nm.complete, nm.stop_reason
    error = omega_peak / nm.omega[-1] - 1.0
    ratio = float(nm.damping_ratio[-1])
    print(
        f"F = {force}: a_peak {a_peak:.4g}, Ω_peak {omega_peak:.6f}, "
        f"D {ratio:.3g}, error {error:.2e}, error / D² {error / ratio**2:.3f}"
    )
    assert abs(error) < 1e-3


@pytest.mark.slow
def test_spring_chain_upper_branch_through_the_frf_peak():
    """Issue 16 chain, kt = 5e3, ζ = 0.1 %: under F = 3.2 N at DOF 10 the
    tip slides and the FRF peak (refined by a bounded search of
    ``hf.periodic_solution``) lies at a = 0.249, beyond the internal
    resonance that stops the continuation from the stuck side: the upper
    branch, continued down from the peak's amplitude, passes through it
    within 1e-3 in frequency (measured 3.5e-4; D = 3.4e-3 there)."""
    chain, (Mc, _, _) = _spring_chain(5e3, 1e-3)
    h, force = 7, 3.2
    omega_peak, a_peak = _chain_frf_peak(chain, Mc, force, (30.0, 36.0), h)
    assert a_peak > 0.1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        nm = hf.nonlinear_mode(
            chain,
            amplitude=(1e-6, a_peak),
            points=40,
            harmonics=h,
            harmonic_tolerance=None,
        )
    assert nm.pieces is not None and len(nm.gaps) == 1
    assert nm.amplitude[-1] == a_peak
    error = omega_peak / nm.omega[-1] - 1.0
    print(f"a_peak {a_peak:.4g}, D {nm.damping_ratio[-1]:.3g}, error {error:.2e}")
    assert abs(error) < 1e-3


# ----------------------------------------------------------------------------
# a 2D element that touches at rest (preload 0) or stands off (a gap)
# ----------------------------------------------------------------------------

#: bench/README.md stop 28: x tangential, y normal (positive closing), each
#: 1 kg on 1e4 N/m (100 rad/s bare), the element between them and ground
TOUCH_KT, TOUCH_KN, TOUCH_K = 3e4, 2e4, 1e4


def _touching_rig(preload):
    element = hf.Contact2D(
        TOUCH_KT, TOUCH_KN, friction_coefficient=0.5, preload=preload
    )
    return hf.LinearStructure(
        np.eye(2),
        np.diag([TOUCH_K, TOUCH_K]),
        static_load={"y": preload} if preload > 0 else None,
        contacts=[hf.Contact(element, "x", normal="y")],
        dof_names={"x": 0, "y": 1},
    )


def _bilinear_period_by_integration(y0):
    """Period of the free normal DOF released from ``y0 > 0`` at rest:
    ``ÿ = -k y - kn max(y, 0)``, integrated by scipy (events at y = 0),
    independent of hbmfric."""
    from scipy.integrate import solve_ivp

    def rhs(t, s):
        return [s[1], -TOUCH_K * s[0] - TOUCH_KN * max(s[0], 0.0)]

    def up(t, s):  # crossing y = 0 upwards: one period after release
        return s[0]

    up.direction = 1.0
    up.terminal = True

    def down(t, s):
        return s[0]

    # first the closed quarter to y = 0 (down), then on to the up-crossing
    down.direction = -1.0
    down.terminal = True
    first = solve_ivp(rhs, (0, 1.0), [y0, 0.0], events=down, rtol=1e-12, atol=1e-16)
    t1, s1 = first.t_events[0][0], first.y_events[0][0]
    second = solve_ivp(rhs, (t1, 2.0), s1, events=up, rtol=1e-12, atol=1e-16)
    t2 = second.t_events[0][0]
    # closed quarter again from y = 0 up to the top: the same as the first
    return t2 + t1


def test_mode_of_a_touching_2d_contact_is_bilinear_and_warns():
    """Preload exactly 0: the element is open at rest (linear modes 100 and
    100 rad/s, a repeated pair) but closes on any motion of y. Mode 2
    follows y's bilinear motion: ω = 2 ω_o ω_c / (ω_o + ω_c) at every
    amplitude (closed form, and the period of the free rig by scipy's
    integration, both to 3e-6 at H = 7), the limit of the preload 1e-6 mode 1 (to
    1e-4). It never tends to its ``linear_omega`` (100): that is said, with
    the touching contact named and the repeated pair (on main: silent)."""
    w_o = np.sqrt(TOUCH_K)
    w_c = np.sqrt(TOUCH_K + TOUCH_KN)
    bilinear = 2.0 * w_o * w_c / (w_o + w_c)
    by_integration = 2.0 * np.pi / _bilinear_period_by_integration(1e-3)
    assert by_integration == pytest.approx(bilinear, rel=1e-8)
    with pytest.warns(
        hf.HbmfricWarning, match="does not start on linear mode 2"
    ) as rec:
        nm = hf.nonlinear_mode(_touching_rig(0.0), 2, (1e-6, 1e-2), points=5)
    text = " ".join(str(w.message) for w in rec)
    assert "touches at rest" in text and "repeated pair" in text
    assert "'y'" in text  # the motion followed is named
    assert nm.linear_omega == pytest.approx(w_o, rel=1e-12)
    assert nm.complete
    # H = 7: 1.8e-6 off (the truncation estimate says 1.8e-6; H = 15:
    # 3e-8, H = 63: 2e-10)
    np.testing.assert_allclose(nm.omega, bilinear, rtol=3e-6)
    np.testing.assert_allclose(nm.omega, by_integration, rtol=3e-6)
    assert np.all(nm.dof_amplitude("x") < 1e-9 * nm.dof_amplitude("y"))
    assert nm.info["start_notes"]
    # the limit of a contact held closed: mode 1 of preload 1e-6 (stuck
    # pulsation w_c) lands on the same motion; it opens from a = 5e-11 on,
    # so at a >= 1e-6 it is the bilinear motion, the continuation of its
    # linear mode: a start where the contact acts is not reported
    held = hf.nonlinear_mode(_touching_rig(1e-6), 1, (1e-6, 1e-2), points=5)
    assert "start_notes" not in held.info
    assert held.linear_omega == pytest.approx(w_c, rel=1e-12)
    np.testing.assert_allclose(held.omega, nm.omega, rtol=1e-4)


def test_mode_of_a_2d_contact_with_a_small_gap_warns():
    """A gap of 5e-8 m (preload -1e-3 N), below the first amplitude: the
    first point already closes it (ω 25 % above the linear 100 rad/s, up
    to the bilinear value at large a), while the linear modes are a
    repeated pair: said (on main: silent). A gap above the first amplitude
    leaves the pair singular: no point, the repeated-pair
    ConvergenceWarning, as before."""
    w_o = np.sqrt(TOUCH_K)
    w_c = np.sqrt(TOUCH_K + TOUCH_KN)
    bilinear = 2.0 * w_o * w_c / (w_o + w_c)
    with pytest.warns(
        hf.HbmfricWarning, match="does not start on linear mode 2"
    ) as rec:
        nm = hf.nonlinear_mode(_touching_rig(-1e-3), 2, (1e-6, 1e-2), points=5)
    assert "repeated pair" in " ".join(str(w.message) for w in rec)
    assert w_o < nm.omega[0] < nm.omega[-1] < bilinear
    assert nm.omega[-1] == pytest.approx(bilinear, rel=1e-4)
    with pytest.warns(hf.ConvergenceWarning, match="repeated pair"):
        far = hf.nonlinear_mode(_touching_rig(-0.5), 2, (1e-6, 1e-2), points=5)
    assert len(far) == 0


def test_mode_that_starts_on_its_linear_mode_is_quiet():
    """The tangential mode at preload 1e-6 starts on its stuck pulsation
    when the range starts below the slip limit μ N0 / kt = 1.7e-11: no
    start note (the warning is about the start, not the softening)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        nm = hf.nonlinear_mode(_touching_rig(1e-6), 2, (1e-13, 1e-11), points=3)
    assert nm.omega[0] == pytest.approx(nm.linear_omega, rel=1e-6)
    assert "start_notes" not in nm.info


def test_start_on_another_shape_is_reported():
    """``_start_notes`` on a start whose shape is another linear mode's
    (the normal DOF's, for the tangential mode 2 at preload 1e-6: mass
    orthogonal, MAC 0) names the shape; the pulsation 13 % off alone is
    not a note (no element touches at rest)."""
    from hbmfric.modes import _EPMC, _start_notes

    rig = _touching_rig(1e-6)
    tangential = _EPMC(rig, 2, 3, None, "auto", True)
    normal = _EPMC(rig, 1, 3, None, "auto", True)
    z = normal.linear_guess(1e-3)
    notes = _start_notes(tangential, 2, 1e-3, z, {"x": 0, "y": 1})
    assert any(
        "not the linear mode's (modal assurance criterion 0)" in n for n in notes
    )
    assert not any("relative from the linear pulsation" in n for n in notes)
    assert _start_notes(tangential, 2, 1e-3, tangential.linear_guess(1e-3), {}) == []
