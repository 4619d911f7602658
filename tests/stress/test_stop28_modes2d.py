"""Stress rows for stop 28: nonlinear modes of the 2D element's rig when
the element touches at rest (preload 0) or stands off (a gap), against the
bilinear oscillator's closed form, free time integration (scipy, from the
mode's own initial state) and the limit of a small positive preload.

Run with ``python -m pytest -m stress tests/stress/test_stop28_modes2d.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_modes import TOUCH_K, TOUCH_KN, _touching_rig

import hbmfric as hf
from hbmfric.signals import coefficient_columns

pytestmark = pytest.mark.stress

W_O = np.sqrt(TOUCH_K)
W_C = np.sqrt(TOUCH_K + TOUCH_KN)
BILINEAR = 2.0 * W_O * W_C / (W_O + W_C)


def _mode(preload, mode, amplitude, harmonics, points=5):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        return hf.nonlinear_mode(
            _touching_rig(preload), mode, amplitude, points=points, harmonics=harmonics
        )


def _signal(nm, i, t):
    """y(t) and ẏ(t) of point ``i`` (normal DOF), from the coefficients."""
    cols = coefficient_columns(nm.harmonic_numbers)
    c = nm.coefficients[i, 1]
    w = nm.omega[i]
    y = np.zeros_like(t)
    v = np.zeros_like(t)
    for k in nm.harmonic_numbers:
        col = cols[int(k)]
        if k == 0:
            y += c[col]
            continue
        ck, sk = c[col], c[col + 1]
        y += ck * np.cos(k * w * t) + sk * np.sin(k * w * t)
        v += k * w * (-ck * np.sin(k * w * t) + sk * np.cos(k * w * t))
    return y, v


def _free_normal(preload, y0, v0, t):
    """The free normal DOF, ``ÿ = -k y - max(0, N0 + kn y)``, by scipy."""

    def rhs(_, s):
        return [s[1], -TOUCH_K * s[0] - max(0.0, preload + TOUCH_KN * s[0])]

    sol = solve_ivp(rhs, (0.0, t[-1]), [y0, v0], t_eval=t, rtol=1e-11, atol=1e-18)
    return sol.y[0]


@pytest.mark.parametrize(("harmonics", "tol"), [(7, 3e-6), (15, 1e-7), (31, 3e-8)])
def test_touching_mode_converges_to_the_bilinear_closed_form(harmonics, tol):
    """Preload 0, mode 2: ω at every amplitude within ``tol`` of the closed
    form (measured 1.8e-6, 3.0e-8, 1.2e-8), and the truncation estimate
    within a factor 3 of the true error."""
    nm = _mode(0.0, 2, (1e-6, 1e-2), harmonics)
    err = np.abs(nm.omega / BILINEAR - 1.0)
    assert nm.complete and np.all(err < tol), err
    est = nm.truncation_error
    assert np.all(est < 3.0 * err + 1e-9) and np.all(err < 3.0 * est + 1e-9)


@pytest.mark.parametrize(
    ("preload", "index"), [(0.0, 0), (0.0, 4), (-1e-3, 0), (-1e-3, 2)]
)
def test_mode_against_free_time_integration(preload, index):
    """The mode's normal motion (H = 31) released from its own state at
    t = 0 and integrated freely over one period (D = 0: no damping) stays
    on the HBM signal within 2e-5 of its peak (measured 3.4e-6 to 8.1e-6);
    touching and 5e-8 m gap."""
    nm = _mode(preload, 2, (1e-6, 1e-2), 31)
    assert abs(nm.damping_ratio[index]) < 1e-9
    t = np.linspace(0.0, 2 * np.pi / nm.omega[index], 257)
    y, v = _signal(nm, index, t)
    ref = _free_normal(preload, y[0], v[0], t)
    assert np.max(np.abs(ref - y)) < 2e-5 * np.max(np.abs(y))


def test_small_preload_is_the_limit():
    """Mode 1 at preload 1e-3, 1e-6, 1e-9 N (stuck pulsation 173.2 rad/s):
    at a = 1e-2 the preload-0 mode 2 (same H = 7) to 1e-5, 1e-8, 1e-11
    (measured 3.1e-6, 3.1e-9, 3.1e-12: first order in the preload)."""
    ref = _mode(0.0, 2, (1e-2, 2e-2), 7, points=2).omega[0]
    errs = [
        abs(_mode(p, 1, (1e-2, 2e-2), 7, points=2).omega[0] / ref - 1.0)
        for p in (1e-3, 1e-6, 1e-9)
    ]
    assert errs[0] < 1e-5 and errs[1] < 1e-8 and errs[2] < 1e-11
