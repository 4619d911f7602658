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

import hbmfric as hf
from hbmfric.validation import monodromy

OMEGA_RANGE = (2.5, 3.6)


def preloaded_duffing(preload: float = 1.0):
    return hf.LinearStructure(
        np.eye(1),
        np.eye(1),
        0.02 * np.eye(1),
        load={0: 1.0},
        static_load={0: preload},
        contacts=[hf.Contact(hf.Cubic(1.0), 0)],
    )


def _state(coefficients, harmonic_numbers, omega):
    X = np.asarray(coefficients)[0]
    x0, v0, col = 0.0, 0.0, 0
    for k in harmonic_numbers:
        if k == 0:
            x0 += X[col]
            col += 1
        else:
            x0 += X[col]
            v0 += k * omega * X[col + 1]
            col += 2
    return x0, v0


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
        x0, v0 = _state(p.coefficients, p.harmonic_numbers, p.omega)
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
