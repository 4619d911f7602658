"""A period-doubling case: a Duffing oscillator with a static preload.

``ẍ + 0.02 ẋ + x + x³ = 1 + 0.5 cos Ωt``: the preload shifts the rest
point to ``x_s ≈ 0.682``, about which the cubic spring has a quadratic
part (``3 x_s y²``), so near twice the linearised frequency (``2 × 1.548
rad/s``) the response's stiffness is modulated at ``Ω`` and the
principal parametric resonance doubles the period: a Floquet multiplier
leaves the unit circle through −1 at about Ω = 2.996 and returns at
3.178 rad/s.

Checked against the monodromy matrix of the time-integration reference
(:func:`hbmfric.validation.monodromy`), an independent route: Hill's
verdict at every point, the multipliers' moduli, and the located period
doublings. Before the one-per-family selection of the Hill exponents, a
real negative multiplier's two conjugate members ``σ ± iΩ/2`` were both
taken and the other family dropped: 6 of the 10 unstable points read
"stable".
"""

import numpy as np
import pytest
from stability_cases import preloaded_duffing

import hbmfric as hf
from hbmfric.signals import state_at_zero
from hbmfric.validation import monodromy

OMEGA_RANGE = (2.5, 3.6)


@pytest.fixture(scope="module")
def branch():
    return hf.frf(preloaded_duffing(), 0.5, OMEGA_RANGE, harmonics=9)


def _verdicts_agree(system, branch, margin=1e-3):
    """Hill's verdict and moduli against the time-domain monodromy at every
    point whose largest time-domain modulus is not within ``margin`` of 1.
    Returns (worst modulus difference, points compared, unstable points)."""
    hill = branch.stability()
    worst, compared, unstable = 0.0, 0, 0
    for i in range(len(branch)):
        td = monodromy(system, branch.point(i))
        if abs(td.max_modulus - 1.0) <= margin:
            continue
        compared += 1
        unstable += td.max_modulus > 1.0
        assert (td.max_modulus < 1.0) == bool(hill.stable[i]), (
            i,
            branch.omega[i],
            hill.multipliers[i],
            td.multipliers,
        )
        worst = max(
            worst,
            float(
                np.max(
                    np.abs(
                        np.sort(np.abs(td.multipliers))
                        - np.sort(np.abs(hill.multipliers[i]))
                    )
                )
            ),
        )
    return worst, compared, unstable


def test_hill_verdicts_against_the_time_domain_monodromy(branch):
    """Every point: the same verdict, moduli within 1e-3 (measured 1e-4),
    with 10 unstable points between the two period doublings."""
    worst, compared, unstable = _verdicts_agree(preloaded_duffing(), branch)
    assert compared >= len(branch) - 2
    assert unstable >= 5
    assert worst < 1e-3


def test_period_doublings_located(branch):
    """Two period doublings, each with a multiplier −1 (to 1e-6), where the
    time-domain monodromy of the located solution also has a multiplier
    −1 (to 1e-3: the Newmark scheme's error)."""
    points = branch.special_points()
    assert [p.kind for p in points] == ["period doubling", "period doubling"]
    assert points[0].omega == pytest.approx(2.9965, abs=2e-3)
    assert points[1].omega == pytest.approx(3.1782, abs=2e-3)
    system = preloaded_duffing()
    for p in points:
        assert abs(p.multiplier + 1.0) < 1e-6
        x0, v0 = state_at_zero(p.harmonic_numbers, p.coefficients, p.omega)
        td = monodromy(system, (x0, v0), force=0.5, omega=p.omega)
        assert np.min(np.abs(td.multipliers + 1.0)) < 1e-3


def test_select_exponents_takes_one_member_per_family():
    """Two real negative multipliers: the Hill spectrum holds both families'
    conjugate members at ``±Ω/2``; the selection is one of each."""
    omega = 3.0
    sigma1, sigma2 = 0.01, -0.03
    spectrum = np.array(
        [
            sigma1 + 0.5j * omega,
            sigma1 - 0.5j * omega,
            sigma2 + 0.5j * omega * (1 + 1e-9),
            sigma2 - 0.5j * omega * (1 + 1e-9),
            sigma1 + 1.5j * omega,
            sigma2 - 1.5j * omega,
        ]
    )
    from hbmfric.stability import select_exponents

    lam = select_exponents(spectrum, 2, omega)
    np.testing.assert_allclose(np.sort(lam.real), [sigma2, sigma1], atol=1e-12)
    # a complex pair just inside the strip is two families
    # (and its members one Ω away, outside the strip, are left out)
    b = 0.4999 * omega
    pair = np.array([-0.02 + 1j * b, -0.02 - 1j * b, -0.02 + 1j * (b - omega)])
    lam = select_exponents(pair, 2, omega)
    np.testing.assert_allclose(np.sort(lam.imag), [-b, b], atol=1e-12)


@pytest.mark.stress
@pytest.mark.parametrize(("preload", "force"), [(0.5, 0.5), (1.0, 0.3), (2.0, 1.0)])
def test_stress_hill_verdicts_with_period_doubling(preload, force):
    """Stress: other preloads and forces of the same oscillator, over a
    band around twice its linearised frequency; every point's verdict
    against the time-domain monodromy."""
    system = preloaded_duffing(preload)
    x_s = np.roots([1.0, 0.0, 1.0, -preload]).real.max()
    w0 = np.sqrt(1.0 + 3.0 * x_s**2)
    b = hf.frf(system, force, (1.6 * w0, 2.4 * w0), harmonics=9)
    worst, compared, _ = _verdicts_agree(system, b)
    assert compared >= len(b) - 4
    assert worst < 1e-3


# -- branch switching onto the period-doubled branch -------------------------


@pytest.fixture(scope="module")
def doubled(branch):
    points = branch.special_points()
    return points, hf.period_doubled_branch(branch, points[0])


def test_doubled_branch_joins_the_two_doublings(doubled):
    """Born at the first period doubling (2.9965 rad/s, subcritical: it
    leaves towards lower Ω), the period-2T branch folds three times and
    returns to the period-T branch at the second one (3.1782): its Ω/2
    harmonic vanishes at both ends and is of the order of the response in
    between."""
    points, b2 = doubled
    assert b2.info["subharmonic"] == 2
    assert b2.stop_reason.startswith("returned to the period-T branch")
    forcing = 2.0 * b2.omega
    assert forcing[0] == pytest.approx(points[0].omega, abs=1e-3)
    assert forcing[-1] == pytest.approx(points[1].omega, abs=1e-3)
    assert forcing[1] < forcing[0]  # subcritical
    half = b2.amplitude(harmonic=1)  # harmonic 1 of Ω/2
    assert half[0] < 1e-2 * half.max() and half[-1] < 1e-2 * half.max()
    assert half.max() > 1.0
    assert b2.folds.size == 3


def test_doubled_branch_stability_against_the_time_domain_monodromy(doubled):
    """Hill on the period-2T balance against the monodromy of two forcing
    periods, at 5 points of each stretch between the folds: same verdict,
    moduli within 1e-3 (measured 1e-4)."""
    _, b2 = doubled
    hill = b2.stability()
    bounds = [0, *b2.folds.tolist(), len(b2)]
    system = preloaded_duffing()
    for lo, hi in zip(bounds[:-1], bounds[1:], strict=True):
        for i in np.linspace(lo + 3, hi - 4, 5).round().astype(int):
            td = monodromy(system, b2.point(int(i)))
            assert td.periods == 2
            assert (td.max_modulus < 1.0) == bool(hill.stable[i])
            moduli = np.sort(np.abs(td.multipliers))
            assert np.max(np.abs(moduli - np.sort(np.abs(hill.multipliers[i])))) < 1e-3


def _integrate(omega, x0, v0, periods):
    """``ẍ + 0.02 ẋ + x + x³ = 1 + 0.5 cos Ωt`` by DOP853 (independent of
    the package); the displacement over the last two forcing periods."""
    from scipy.integrate import solve_ivp

    def rhs(t, z):
        x, v = z
        return [v, 1.0 + 0.5 * np.cos(omega * t) - 0.02 * v - x - x**3]

    T = 2.0 * np.pi / omega
    t_end = periods * T
    t = t_end - 2.0 * T + 2.0 * T * np.arange(256) / 256
    sol = solve_ivp(
        rhs,
        (0.0, t_end),
        [x0, v0],
        method="DOP853",
        rtol=1e-10,
        atol=1e-12,
        t_eval=t,
    )
    assert sol.success
    return sol.y[0]


def _half_harmonic(x):
    """Amplitude of the Ω/2 component of two periods sampled at 256 points."""
    c = np.fft.rfft(x) / x.size
    return 2.0 * abs(c[1])


def test_doubled_branch_against_time_integration(branch, doubled):
    """At Ω = 3.1 rad/s the period-T solution is unstable and a stable
    period-2T one exists: started on it, an independent integration stays
    there for 200 periods (its Ω/2 harmonic within 1e-4); started on the
    period-T solution nudged by 1e-6, it leaves it and grows a Ω/2
    harmonic."""
    _, b2 = doubled
    hill = b2.stability()
    omega = 3.1
    candidates = [
        i
        for i in range(len(b2) - 1)
        if (2 * b2.omega[i] - omega) * (2 * b2.omega[i + 1] - omega) <= 0
        and hill.stable[i]
    ]
    assert candidates
    i = candidates[-1]  # the stretch that returns to the second doubling
    sol = b2.point(i)
    x0, v0 = (
        float(a[0])
        for a in state_at_zero(sol.harmonic_numbers, sol.coefficients, b2.omega[i])
    )
    x = _integrate(2 * b2.omega[i], x0, v0, periods=200)
    assert abs(_half_harmonic(x) - sol.amplitude(harmonic=1)) < 1e-4
    # the period-T solution at the same Ω (unstable there)
    j = int(np.argmin(np.abs(branch.omega - 2 * b2.omega[i])))
    assert not branch.stable[j]
    p1 = branch.point(j)
    x0, v0 = (
        float(a[0])
        for a in state_at_zero(p1.harmonic_numbers, p1.coefficients, branch.omega[j])
    )
    x = _integrate(float(branch.omega[j]), x0 * (1 + 1e-6), v0, periods=400)
    assert _half_harmonic(x) > 0.05


def test_switching_refuses_what_it_cannot_do(branch, doubled):
    points, b2 = doubled
    fold_branch = hf.frf(
        hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1)), 0.2, (0.5, 2.0), 9
    )
    fold = fold_branch.special_points()[0]
    with pytest.raises(ValueError, match="period doubling"):
        hf.period_doubled_branch(fold_branch, fold)
    with pytest.raises(ValueError, match="must contain"):
        hf.period_doubled_branch(branch, points[0], (3.05, 3.3))
    with pytest.raises(ValueError, match="already a subharmonic"):
        hf.period_doubled_branch(b2, points[0])
    with pytest.raises(ValueError, match="harmonics"):
        hf.period_doubled_branch(branch, points[0], harmonics=4)


def test_switching_says_when_no_point_is_found(branch, monkeypatch):
    """A bordered Newton that does not converge raises ConvergenceError
    (never a branch of something else)."""
    from hbmfric import switching

    monkeypatch.setattr(switching, "MAX_NEWTON", 0)
    with pytest.raises(hf.ConvergenceError, match="period-doubled branch"):
        hf.period_doubled_branch(branch, branch.special_points()[0])
