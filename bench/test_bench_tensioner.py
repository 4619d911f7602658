"""Belt-tensioner tension FRF: scipy BDF vs the JIT integrator vs HBM
continuation (pytest-benchmark; not part of the test run).

Run: ``python -m pytest bench/test_bench_tensioner.py --benchmark-only``
(the BDF case takes several minutes). Figures: ``bench/README.md``.

The same curve three ways: HBM continuation over 5–100 Hz (H = 15), then the
time domain at the 40 HBM path points nearest to 40 log-spaced frequencies,
so that every time-domain point has its exact HBM partner.
"""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.continuation import ContinuationOptions
from hbmfric.systems.tensioner_response import hbm_frf, time_domain_frf

RIG = hf.BeltTensioner()
FORCE = 20.0
BAND = (5.0, 100.0)
OPTIONS = ContinuationOptions(max_step=0.03)


def _hbm():
    return hbm_frf(RIG, FORCE, BAND, harmonics=15, options=OPTIONS)


def _frequencies(curve, n=40):
    targets = np.geomspace(*BAND, 4 * n)
    pick = np.unique([int(np.argmin(np.abs(curve.frequency - f))) for f in targets])
    pick = pick[np.linspace(0, pick.size - 1, n).astype(int)]
    assert np.unique(pick).size == n
    return pick


@pytest.fixture(scope="module")
def reference():
    curve = _hbm()
    return curve, _frequencies(curve)


def test_hbm_continuation(benchmark, reference):
    curve = benchmark.pedantic(_hbm, rounds=3, iterations=1, warmup_rounds=1)
    benchmark.extra_info["points"] = int(curve.frequency.size)


def test_jit_time_domain(benchmark, reference):
    curve, pick = reference
    td = benchmark.pedantic(
        time_domain_frf,
        args=(RIG, FORCE, curve.frequency[pick], "jit"),
        rounds=3,
        iterations=1,
        warmup_rounds=1,
    )
    err = np.abs(curve.tension_range[pick] / td.tension_range - 1.0)
    benchmark.extra_info["max_rel_error_hbm_vs_jit"] = float(err.max())
    assert td.converged.all()


def test_bdf_time_domain(benchmark, reference):
    curve, pick = reference
    td = benchmark.pedantic(
        time_domain_frf,
        args=(RIG, FORCE, curve.frequency[pick], "bdf"),
        rounds=1,
        iterations=1,
    )
    err = np.abs(curve.tension_range[pick] / td.tension_range - 1.0)
    benchmark.extra_info["max_rel_error_hbm_vs_bdf"] = float(err.max())
    assert td.converged.all()
