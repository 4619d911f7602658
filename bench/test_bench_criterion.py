"""Benchmarks of the contact-model criterion and of the paper's SDOF study
(pytest-benchmark; not part of the test run).

Run: ``python -m pytest bench/test_bench_criterion.py --benchmark-only``.

The family: the paper scene with a Menq contact (Fig. 9), Fex = 1 and
1000 N, five ratios, H = 7; clean (dense continuation points) and
"measured" (150 random frequencies per curve, 2 % multiplicative noise).
"""

import numpy as np
import pytest

from hbmfric.criterion import FRFRecord, choose_contact_model
from hbmfric.paper import menq_family, sdof_figures


@pytest.fixture(scope="module")
def family():
    return menq_family(harmonics=7, check_force=1000.0).records()


@pytest.fixture(scope="module")
def measured(family):
    rng = np.random.default_rng(0)
    out = []
    for r in family:
        w = np.sort(rng.uniform(r.omega[0], r.omega[-1], 150))
        a = np.interp(w, r.omega, r.amplitude) * (1 + 0.02 * rng.normal(size=150))
        out.append(FRFRecord(r.force, r.normal_load, w, a))
    return out


def test_criterion_clean(benchmark, family):
    res = benchmark(choose_contact_model, family)
    assert res.verdict == "microslip without roughness"


def test_criterion_noisy(benchmark, measured):
    res = benchmark(choose_contact_model, measured)
    assert res.verdict == "microslip without roughness"
    benchmark.extra_info["smoothing_half_width"] = res.indicators[
        "smoothing_half_width"
    ]


def test_sdof_figures_h15(benchmark):
    """Figs. 8–11 (30 distinct continuation runs), as ``hbmfric paper``."""
    figs = benchmark.pedantic(sdof_figures, kwargs={"harmonics": 15}, rounds=3)
    benchmark.extra_info["curves"] = sum(len(f.branches) for f in figs)
