"""A frequency range or a solve centred on an undamped natural pulsation of
the stuck structure (stop 31).

The run's amplitude scale is the peak of the linear responses sampled on a
grid over the range; ``periodic_solution`` samples ``(Ω/2, 3Ω/2)``, whose
middle sample is Ω itself. On the undamped two-contact chain below, Ω = √2
is the stuck structure's first natural pulsation; sampled there within
rounding the stuck response read 1.1e12 m, and every test in units of that
scale passed. Before: ``hf.frf`` over ``(√2/2, 3√2/2)`` at H = 5 returned 18
points with a peak of 5.9e-3 m, complete, with a curve estimate of 5.5e-11
and no warning, where the response at Ω = √2 is 1.0004 m; the
state-condensed ``periodic_solution`` at √2 reported ``converged=True`` with
max|R| = 0.051 N under a 1e-3 N load, 3 % off.

References: the full (uncondensed) one-frequency solve, and the same
solve's amplitude at Ω a little off the pole, where no sample is singular.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf

M = np.eye(2)
K = np.array([[2.0, -1.0], [-1.0, 2.0]])  # stuck with k_t = 1 on both: √2, 2
FORCE = 1e-3
ROOT2 = math.sqrt(2.0)


def _chain():
    laws = [
        hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=1.0), 1),
        hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=1.0), 0),
    ]
    return hf.LinearStructure(M, K, contacts=laws, load=[0.0, 1.0])


def test_amplitude_scale_ignores_a_pole_sampled_within_rounding():
    """The scale of a range centred on the pole and of the same range moved
    by 1e-3 rad/s (no sample near the pole) agree within a factor 3."""
    from hbmfric import api

    s = _chain()
    problem = api._problem(s, FORCE, 5, None, None, "auto", None)
    on = problem.amplitude_scale((0.5 * ROOT2, 1.5 * ROOT2))
    off = problem.amplitude_scale((0.5 * ROOT2 + 1e-3, 1.5 * ROOT2 + 1e-3))
    assert np.isfinite(on) and on < 3.0 * off, (on, off)


def test_frf_over_a_range_centred_on_an_undamped_pole_keeps_the_peak():
    """The branch passes through the resonance at √2: its largest amplitude
    is at least that of the full one-frequency solve there, and it says
    nothing wrong about its curve."""
    s = _chain()
    ref = hf.periodic_solution(s, FORCE, ROOT2, harmonics=5, condense=False)
    assert ref.converged and ref.amplitude(harmonic=1) > 0.9
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.AccuracyWarning)
        branch = hf.frf(s, FORCE, (0.5 * ROOT2, 1.5 * ROOT2), harmonics=5)
    assert branch.complete
    peak = float(np.max(branch.amplitude(harmonic=1)))
    assert peak >= (1.0 - 1e-6) * ref.amplitude(harmonic=1), peak


@pytest.mark.parametrize("condense", ["state", "modal", None])
def test_one_frequency_on_the_pole_converges_to_the_full_solution(condense):
    s = _chain()
    full = hf.periodic_solution(s, FORCE, ROOT2, harmonics=5, condense=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.ConvergenceWarning)
        sol = hf.periodic_solution(s, FORCE, ROOT2, harmonics=5, condense=condense)
    assert sol.converged and sol.residual_norm < 1e-10 * max(FORCE, 1.0)
    for dof in (0, 1):
        assert sol.amplitude(harmonic=1, dof=dof) == pytest.approx(
            full.amplitude(harmonic=1, dof=dof), rel=1e-9
        )


@pytest.mark.parametrize("band", [(0.5, 3.0), (0.5, 5000.0), (1e-3, 1e3)])
def test_amplitude_scale_of_a_damped_oscillator_is_its_sampled_peak(band):
    """With no pole on the grid the scale is the largest sample of the stuck
    and free linear responses, closed form for the oscillator (m = 1,
    c = 0.02, k = 1, k_t = 3), also over a band of four decades whose
    median sample is 1e-7 of its largest (a rule on the median dropped the
    largest there)."""
    from hbmfric import api

    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    problem = api._problem(osc, 1.0, 5, None, None, "auto", None)
    w = np.linspace(band[0], band[1], 65)
    # the scale reads the cosine and sine coefficients, X = 1 / (k - Ω² + icΩ)
    peak = max(
        float(np.max(np.abs(np.r_[x.real, x.imag])))
        for x in (1.0 / (k - w**2 + 0.02j * w) for k in (4.0, 1.0))
    )
    assert problem.amplitude_scale(band) == pytest.approx(peak, rel=1e-12)
