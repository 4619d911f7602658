"""Stress rows for the paths that landed at stop 26, each against a
reference the path does not use:

* the harmonic-block GMRES corrector of a condensed problem with many
  contacts (``law="blocks"``: eight contacts, 128 unknowns) against the
  same trace with a dense LU every iteration (``REUSE_MIN_UNKNOWNS``
  raised), and against time integration (the rows are in the matrix too);
* the second-order predictor on one-DOF Jenkins branches with sharp
  corners (stiff contacts, the onset of slip) against the exact periodic
  solution (stick and slip phases in closed form);
* the energy-proof stability shortcut (``stability._passive``) against
  Hill's eigenvalues at every point, and its verdict against time
  integration started off the orbit.

Run with ``python -m pytest -m stress tests/stress/test_stop26_paths.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf
import hbmfric.condensation as hc
from hbmfric.condensation import CondensedHBMProblem

from .cases import BLOCKS_ROWS, build

pytestmark = pytest.mark.stress


def _quiet_frf(*args, **kwargs) -> tuple[hf.Branch, list]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = hf.frf(*args, **kwargs)
    return branch, caught


@pytest.mark.parametrize("case", BLOCKS_ROWS, ids=lambda c: c.name)
def test_blocks_row_equals_the_dense_solve(case, monkeypatch):
    """The GMRES trace and the dense-LU trace of a many-contact row: both
    cover the range, the same peak (amplitude to 1e-4 relative, the curve
    tolerance, Ω to 1e-3: the two solvers' iterates differ by rounding,
    so the step control may place the points differently) and the same
    drawn curve (1e-4 relative on 39 Ω)."""
    system, force, omega = build(case)
    problem = CondensedHBMProblem(system, force, case.harmonics)
    assert problem.n_unknowns >= hc.REUSE_MIN_UNKNOWNS  # the GMRES path
    fast, w_fast = _quiet_frf(system, force, omega, case.harmonics, sweep=case.sweep)
    monkeypatch.setattr(hc, "REUSE_MIN_UNKNOWNS", 10**9)
    dense, w_dense = _quiet_frf(system, force, omega, case.harmonics, sweep=case.sweep)
    for branch, caught in ((fast, w_fast), (dense, w_dense)):
        assert branch.info["condensed"]
        assert branch.complete, [str(w.message) for w in caught]
        assert branch.omega.min() == pytest.approx(omega[0], rel=1e-9)
        assert branch.omega.max() == pytest.approx(omega[1], rel=1e-9)
    tip = system.n_dof - 1
    a_fast = fast.amplitude(harmonic=1, dof=tip)
    a_dense = dense.amplitude(harmonic=1, dof=tip)
    i, j = int(np.argmax(a_fast)), int(np.argmax(a_dense))
    assert a_fast[i] == pytest.approx(a_dense[j], rel=1e-4)
    assert fast.omega[i] == pytest.approx(dense.omega[j], rel=1e-3)
    grid = np.linspace(omega[0], omega[1], 41)[1:-1]
    for g in grid:
        u = fast.amplitude_at([g], harmonic=1, dof=tip)[0]
        v = dense.amplitude_at([g], harmonic=1, dof=tip)[0]
        u, v = np.sort(u[np.isfinite(u)]), np.sort(v[np.isfinite(v)])
        assert u.size == v.size and u.size > 0
        np.testing.assert_allclose(u, v, rtol=1e-4, atol=0.0)


#: one-DOF Jenkins rows with sharp corners (m = 1, k = 1, f_s = 1):
#: (c, kt, F, Ω range)
CORNER_ROWS = [
    (0.02, 1e3, 2.0, (0.3, 3.0)),  # stiff: a sharp corner at slip onset
    (0.02, 1e2, 1.2, (0.3, 3.0)),  # just above the slip force
    (0.002, 1e2, 1.5, (0.3, 3.0)),  # light damping, a sharp peak
]


@pytest.mark.parametrize(
    "row", CORNER_ROWS, ids=lambda r: f"c={r[0]} kt={r[1]} F={r[2]}"
)
def test_predictor_at_corners_against_the_exact_solution(row):
    """A branch traced with the second-order predictor covers the range
    and its points are the exact periodic solution (stick and slip phases
    in closed form, shooting started on the point) at 25 points spread
    over the branch and the five around the peak, to the larger of 2e-3
    and twice the point's estimated truncation error; the peak lies
    within 1 % in Ω of the exact solution's largest amplitude on a grid
    around it (a jump across a corner would skip the peak)."""
    c, kt, force, omega = row
    osc = hf.Oscillator(1.0, c, 1.0, hf.Jenkins(stiffness=kt, slip_force=1.0))
    branch, caught = _quiet_frf(osc, force, omega)
    assert branch.complete, [str(w.message) for w in caught]
    a = branch.amplitude(harmonic=1)
    ip = int(np.argmax(a))
    n = len(branch)
    picks = set(np.linspace(0, n - 1, 25).astype(int).tolist())
    picks |= {min(max(ip + d, 0), n - 1) for d in range(-2, 3)}
    for i in sorted(picks):
        with warnings.catch_warnings(record=True) as ref_caught:
            warnings.simplefilter("always")
            exact = hf.validation.exact_periodic_solution(
                osc, force, float(branch.omega[i]), initial_guess=branch.point(i)
            )
        assert not ref_caught, [str(w.message) for w in ref_caught]
        ref = exact.amplitude(harmonic=1)
        tol = max(2e-3, 2.0 * float(branch.truncation_error[i]))
        assert abs(a[i] - ref) / ref <= tol, (branch.omega[i], ref, a[i])
    # the exact peak on a grid of 1 % steps around the branch's
    grid = branch.omega[ip] * (1.0 + 0.01 * np.arange(-3, 4))
    start = branch.point(ip)
    peaks = []
    for g in grid:
        with warnings.catch_warnings():
            warnings.simplefilter("error", hf.HbmfricWarning)
            exact = hf.validation.exact_periodic_solution(
                osc, force, float(g), initial_guess=start
            )
        peaks.append(exact.amplitude(harmonic=1))
        start = exact
    assert 0 < int(np.argmax(peaks)) < grid.size - 1  # a maximum inside
    assert max(peaks) <= a[ip] * (1.0 + 2e-3)  # the branch's peak is the top


#: one-DOF Jenkins rows where the energy proof gives the signs
#: (m, c, k, kt, f_s, F, Ω range)
PASSIVE_ROWS = [
    (1.0, 0.02, 1.0, 3.0, 1.0, 0.5, (0.5, 3.0)),
    (1.0, 1e-3, 1.0, 3.0, 0.05, 0.5, (0.5, 3.0)),
    (1.0, 0.02, 1.0, 200.0, 0.2, 0.5, (0.5, 3.0)),
    (1e3, 2e4, 1e8, 3e8, 1e5, 5e4, (150.0, 900.0)),
]


@pytest.mark.parametrize(
    "row", PASSIVE_ROWS, ids=lambda r: f"c={r[1]} kt={r[3]} fs={r[4]}"
)
def test_passive_shortcut_verdicts(row):
    """``exponents="auto"`` on a one-DOF Jenkins branch (the signs by the
    energy proof, eigenvalues at a few points) gives Hill's verdicts at
    every point (all stable); and time integration started 20 % off the
    branch's peak point settles on it (to 5e-3 relative)."""
    m, c, k, kt, fs, force, omega = row
    osc = hf.Oscillator(m, c, k, hf.Jenkins(stiffness=kt, slip_force=fs))
    branch, _ = _quiet_frf(osc, force, omega)
    auto = branch.stability()
    assert auto.computed.sum() <= max(8, len(branch) // 8)
    stable = auto.stable.copy()
    branch._stability = None
    full = branch.stability(exponents="all")
    np.testing.assert_array_equal(stable, full.stable)
    assert stable.all()
    i = int(np.argmax(branch.amplitude(harmonic=1)))
    sol = branch.point(i)
    t, x = sol.time_response(n=64)
    x0 = 1.2 * float(np.ravel(x)[0])
    v0 = 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.ConvergenceWarning)
        ref = hf.validation.steady_state(
            osc,
            force,
            float(branch.omega[i]),
            initial_state=(np.array([x0]), np.array([v0])),
            tol=1e-8,
            max_periods=30000,
        )
    assert ref.converged
    a = sol.amplitude(harmonic=1)
    assert abs(ref.amplitude(harmonic=1) - a) / a < 5e-3
