"""AFT of the Masing laws (Menq, Iwan): both schemes (sampled reversals and
located reversals) against finite differences, against each other at many
samples, the half-period shortcut against the full period, and the
contact-state codes."""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.kernels.aft.masing import aft_masing
from hbmfric.kernels.aft.schemes import GROSS_SLIP, MICROSLIP, STUCK, aft_samples
from hbmfric.kernels.fourier.dft import fourier_matrices
from hbmfric.kernels.laws.updates import linear_limit

MENQ = hf.Menq.from_stiffness(stiffness=3e4, slip_force=10.0, microslip_onset=0.5)
IWAN = hf.Iwan.segalman(
    slip_force=10.0, stiffness=3e4, chi=-0.5, beta=0.2, n_elements=60
)
LAWS = {"menq": MENQ, "iwan": IWAN}
#: displacement unit: end of the linear range of each law
UNIT = {"menq": MENQ.slip_displacement, "iwan": 10.0 / 3e4}


def _evaluator(law, harmonics, n_time, scheme):
    hn = np.asarray(harmonics, dtype=np.int64)
    inverse, forward, derivative = fourier_matrices(hn, n_time)
    code = np.int64(law.code)
    params = law.params

    def run(X):
        n_coef = inverse.shape[1]
        F = np.empty(n_coef)
        dF = np.empty((n_coef, n_coef))
        if scheme == "events":
            state = aft_masing(code, params, hn, X, inverse, forward, derivative, F, dF)
        else:
            state = aft_samples(code, params, X, inverse, forward, F, dF)
        return F, dF, state

    return run


CASES = {
    "stuck": ([0.0, 0.5, 0.2, 0.0, 0.0, 0.0, 0.0], STUCK),
    "stuck shifted": ([1.0, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0], STUCK),
    "inner loops": ([0.2, 1.2, 0.4, 0.1, 0.3, 0.35, -0.2], MICROSLIP),
    "gross slip": ([0.3, 30.0, 10.0, 2.0, -5.0, 6.0, 4.0], GROSS_SLIP),
}


@pytest.mark.parametrize("scheme", ["samples", "events"])
@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("name", list(LAWS))
def test_jacobian_against_finite_differences(name, case, scheme):
    law = LAWS[name]
    coefficients, expected = CASES[case]
    if name == "menq" and case == "gross slip":
        coefficients = np.asarray(coefficients) / 10.0  # δ_gs ≈ 2.8 δ1
    unit = UNIT[name]
    if expected == STUCK:
        unit = linear_limit(np.int64(law.code), law.params)
    X = unit * np.asarray(coefficients, dtype=float)
    run = _evaluator(law, [0, 1, 2, 3], 64, scheme)
    F, dF, state = run(X)
    assert state == expected
    h = 1e-6 * unit
    fd = np.empty_like(dF)
    for c in range(X.size):
        e = np.zeros(X.size)
        e[c] = h
        fd[:, c] = (run(X + e)[0] - run(X - e)[0]) / (2.0 * h)
    np.testing.assert_allclose(dF, fd, rtol=0, atol=2e-6 * law.stuck_stiffness)


@pytest.mark.parametrize("name", list(LAWS))
def test_located_reversals_converge_faster_than_sampled_ones(name):
    """Both schemes tend to the same coefficients; at n_time = 8 H the
    located reversals are closer to the limit than sampled reversals at
    16 H."""
    law = LAWS[name]
    harmonics = [1, 3, 5, 7]
    X = UNIT[name] * np.array([1.5, 0.2, 0.5, 0.3, 0.1, 0.05, 0.02, 0.0])
    limit = _evaluator(law, harmonics, 2**14, "events")(X)[0]
    sampled = _evaluator(law, harmonics, 2**14, "samples")(X)[0]
    scale = np.max(np.abs(limit))
    assert np.max(np.abs(sampled - limit)) < 1e-6 * scale
    coarse_events = _evaluator(law, harmonics, 56, "events")(X)[0]
    fine_samples = _evaluator(law, harmonics, 112, "samples")(X)[0]
    err_events = np.max(np.abs(coarse_events - limit))
    err_samples = np.max(np.abs(fine_samples - limit))
    assert err_events < err_samples
    assert err_events < 1e-3 * scale


@pytest.mark.parametrize("name", list(LAWS))
def test_half_period_shortcut_matches_the_full_period(name):
    """Odd harmonics only: half a period is marched; the same motion
    written with all harmonics (even ones zero) marches the full period."""
    law = LAWS[name]
    odd = _evaluator(law, [1, 3, 5], 48, "events")
    full = _evaluator(law, [0, 1, 2, 3, 4, 5], 48, "events")
    X_odd = UNIT[name] * np.array([1.2, 0.4, 0.3, 0.35, -0.2, 0.1])
    X_full = np.zeros(11)
    X_full[[1, 2, 5, 6, 9, 10]] = X_odd
    F_odd, dF_odd, _ = odd(X_odd)
    F_full, dF_full, _ = full(X_full)
    keep = [1, 2, 5, 6, 9, 10]
    scale = np.max(np.abs(F_odd))
    np.testing.assert_allclose(F_full[keep], F_odd, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(np.delete(F_full, keep), 0.0, atol=1e-12 * scale)
    np.testing.assert_allclose(
        dF_full[np.ix_(keep, keep)],
        dF_odd,
        rtol=0,
        atol=1e-12 * law.stuck_stiffness,
    )
