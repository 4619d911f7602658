"""Contact-law objects: normal load as a parameter and roughness, checked
against closed forms (linear stuck FRF, the Hertz–Mindlin stiffness rule)."""

import numpy as np
import pytest

import hbmfric as hf


def test_friction_coefficient_and_normal_load_give_the_slip_force():
    law = hf.Jenkins(stiffness=3e4, friction_coefficient=0.5, normal_load=20.0)
    assert law.slip_force == 10.0
    moved = law.with_normal_load(40.0)
    assert moved.slip_force == 20.0 and moved.stiffness == 3e4
    assert moved.friction_coefficient == 0.5
    np.testing.assert_array_equal(
        law.params, hf.Jenkins(stiffness=3e4, slip_force=10.0).params
    )


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({}, "slip_force"),
        ({"friction_coefficient": 0.5}, "normal_load"),
        ({"normal_load": 2.0}, "friction_coefficient"),
        ({"friction_coefficient": -0.5, "normal_load": 2.0}, "friction_coefficient"),
        ({"friction_coefficient": 0.5, "normal_load": -2.0}, "normal_load"),
        (
            {"slip_force": 3.0, "friction_coefficient": 0.5, "normal_load": 2.0},
            "either",
        ),
    ],
)
def test_bad_friction_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        hf.Jenkins(stiffness=1.0, **kwargs)


def test_with_normal_load_needs_a_friction_coefficient():
    with pytest.raises(ValueError, match="friction_coefficient"):
        hf.Jenkins(stiffness=1.0, slip_force=1.0).with_normal_load(2.0)


def _paper_oscillator(contact):
    return hf.Oscillator(mass=1.0, damping=4.0, stiffness=1e4, contact=contact)


def test_roughness_above_the_limit_load_is_the_plain_law():
    plain = hf.Jenkins(stiffness=3e4, friction_coefficient=1.0, normal_load=500.0)
    rough = hf.Roughness(plain, limit_load=300.0)
    np.testing.assert_array_equal(rough.params, plain.params)
    a = hf.frf(_paper_oscillator(plain), 50.0, (50.0, 300.0), harmonics=7)
    b = hf.frf(_paper_oscillator(rough), 50.0, (50.0, 300.0), harmonics=7)
    np.testing.assert_allclose(b.amplitude(harmonic=1), a.amplitude(harmonic=1))


def test_roughness_softens_the_stuck_contact():
    """Stuck (huge μ) below the limit load: linear FRF with
    k + kt_∞ (F_n/F_lim)^(1/3), to 1e-8."""
    law = hf.Jenkins(stiffness=3e4, friction_coefficient=1e6, normal_load=37.5)
    rough = hf.Roughness(law, limit_load=300.0)
    kt = 3e4 * 0.5  # (37.5 / 300)^(1/3) = 1/2
    assert rough.tangential_stiffness == pytest.approx(kt, rel=1e-14)
    branch = hf.frf(_paper_oscillator(rough), 1.0, (50.0, 300.0), harmonics=7)
    w = branch.omega
    exact = 1.0 / np.abs(1e4 + kt - w**2 + 4j * w)
    np.testing.assert_allclose(branch.amplitude(harmonic=1), exact, rtol=1e-8)
    moved = rough.with_normal_load(2400.0)
    assert moved.tangential_stiffness == 3e4
    assert moved.params[1] == pytest.approx(2.4e9)


def test_custom_roughness_law():
    law = hf.Jenkins(stiffness=100.0, friction_coefficient=0.3, normal_load=50.0)
    rough = hf.Roughness(
        law, limit_load=200.0, stiffness_law=lambda k, f, fl: k * f / fl
    )
    assert rough.tangential_stiffness == pytest.approx(25.0)
    with pytest.raises(ValueError, match="stiffness_law"):
        hf.Roughness(law, stiffness_law=lambda k, f, fl: -1.0)
    with pytest.raises(ValueError, match="normal_load"):
        hf.Roughness(hf.Jenkins(stiffness=1.0, slip_force=1.0))
    with pytest.raises(ValueError, match="limit_load"):
        hf.Roughness(law, limit_load=0.0)


def test_roughness_breaks_the_ratio_invariance():
    """Paper Sec. 3.1: with roughness, equal Fex/Fn at Fex = 1 N and 1000 N
    give different normalised FRFs, the low-load one at lower frequency;
    without roughness they coincide."""
    ratio = 0.1
    peaks = {}
    for rough in (False, True):
        for force in (1.0, 1000.0):
            law = hf.Jenkins(
                stiffness=3e4, friction_coefficient=1.0, normal_load=force / ratio
            )
            contact = hf.Roughness(law) if rough else law
            b = hf.frf(_paper_oscillator(contact), force, (50.0, 300.0), harmonics=7)
            a = b.amplitude(harmonic=1) / force
            peaks[rough, force] = (b.omega[np.argmax(a)], a.max())
    assert peaks[False, 1.0] == pytest.approx(peaks[False, 1000.0], rel=1e-6)
    assert peaks[True, 1000.0] == pytest.approx(peaks[False, 1000.0], rel=1e-6)
    assert peaks[True, 1.0][0] < 0.9 * peaks[True, 1000.0][0]


@pytest.mark.parametrize(
    "law",
    [
        hf.Jenkins(stiffness=3.0, slip_force=1.0),
        hf.Cubic(0.5),
        hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0, microslip_onset=0.4),
        hf.Iwan.segalman(slip_force=1.0, stiffness=3.0, chi=-0.5, beta=0.1),
        hf.Roughness(
            hf.Menq.from_stiffness(
                stiffness=3.0, friction_coefficient=1.0, normal_load=1.0
            ),
            limit_load=2.0,
        ),
    ],
    ids=["jenkins", "cubic", "menq", "iwan", "roughness"],
)
def test_every_law_has_a_loop_an_energy_and_a_plot(law):
    """The loop closes and its area is the law's energy per cycle (closed
    form where there is one); plot_loop draws it."""
    import matplotlib

    matplotlib.use("Agg")
    a = 1.5
    theta = 2.0 * np.pi * np.arange(4096) / 4096
    u = a * np.cos(theta)
    f = law.hysteresis(u)
    du = np.roll(u, -1) - u
    area = float(np.sum(0.5 * (f + np.roll(f, -1)) * du))
    assert law.energy_per_cycle(a) == pytest.approx(area, rel=1e-5, abs=1e-12)
    ax = law.plot_loop(a, n_samples=64)
    (line,) = ax.get_lines()
    assert line.get_xydata().shape == (65, 2)
    with pytest.raises(ValueError, match="amplitude"):
        law.energy_per_cycle(-1.0)
    with pytest.raises(ValueError, match="n_samples"):
        law.plot_loop(a, n_samples=2)


def test_roughness_rejects_other_laws():
    with pytest.raises(ValueError, match="Jenkins, Menq or Iwan"):
        hf.Roughness(hf.Cubic(1.0))


def test_law_step_contract_for_scalar_state_laws():
    """``law_init``/``law_step`` on Jenkins and the cubic spring follow the
    plain-NumPy laws along a random path; trial steps leave the state alone."""
    from naive import cubic_force, jenkins_update

    from hbmfric.kernels.laws import updates as kl

    rng = np.random.default_rng(7)
    path = np.cumsum(rng.normal(0.0, 0.4, 200))
    for law in (hf.Jenkins(stiffness=3.0, slip_force=1.0), hf.Cubic(0.7)):
        code = np.int64(law.code)
        state = np.empty(kl.state_size(code, law.params))
        assert state.size == 1
        kl.law_init(code, law.params, path[0], state)
        f_ref = (
            jenkins_update(0.0, 0.0, path[0], 3.0, 1.0)
            if law.code == kl.JENKINS
            else float(cubic_force(path[0], 0.7))
        )
        assert state[0] == pytest.approx(f_ref, abs=1e-14)
        for u_prev, u in zip(path[:-1], path[1:], strict=True):
            before = state.copy()
            trial = kl.law_step(code, law.params, state, u_prev, u, False)[0]
            np.testing.assert_array_equal(state, before)
            f = kl.law_step(code, law.params, state, u_prev, u, True)[0]
            if law.code == kl.JENKINS:
                f_ref = jenkins_update(f_ref, u_prev, u, 3.0, 1.0)
            else:
                f_ref = float(cubic_force(u, 0.7))
            assert f == trial == state[0]
            assert f == pytest.approx(f_ref, abs=1e-12)
