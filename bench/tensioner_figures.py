"""Print the bench/README.md figures of the tensioner FRF comparison:
``python bench/tensioner_figures.py`` (several minutes: the BDF route)."""

import time

import numpy as np
from test_bench_tensioner import FORCE, RIG, _frequencies, _hbm

from hbmfric.systems.tensioner_response import time_domain_frf


def main() -> None:
    _hbm()  # warm-up (Numba cache load)
    t0 = time.perf_counter()
    curve = _hbm()
    t_hbm = time.perf_counter() - t0
    pick = _frequencies(curve)
    freqs = curve.frequency[pick]
    time_domain_frf(RIG, FORCE, freqs[:2], "jit")  # warm-up
    jit = time_domain_frf(RIG, FORCE, freqs, "jit")
    print(f"HBM: {curve.frequency.size} points, {t_hbm:.3f} s, {curve.work}")
    print(f"JIT: {freqs.size} frequencies, {jit.elapsed:.3f} s, {jit.work}")
    bdf = time_domain_frf(RIG, FORCE, freqs, "bdf")
    print(f"BDF: {freqs.size} frequencies, {bdf.elapsed:.1f} s, {bdf.work}")
    for name, td in (("JIT", jit), ("BDF", bdf)):
        err = np.abs(curve.tension_range[pick] / td.tension_range - 1.0)
        print(f"HBM vs {name}: max {err.max():.2e}, median {np.median(err):.2e}")
    err = np.abs(jit.tension_range / bdf.tension_range - 1.0)
    print(f"JIT vs BDF: max {err.max():.2e}, median {np.median(err):.2e}")
    ratio_hbm = bdf.elapsed / t_hbm
    ratio_jit = bdf.elapsed / jit.elapsed
    print(f"ratios: BDF/HBM {ratio_hbm:.0f}x, BDF/JIT {ratio_jit:.0f}x")
    print("all converged:", jit.converged.all(), bdf.converged.all())


if __name__ == "__main__":
    main()
