"""Determinant signs of Jenkins branches by proof (issue 16, stop 26).

On one DOF with ``c > 0``, ``k > 0`` and Jenkins contacts to ground on the
event AFT, every diagonal block of harmonics of the HBM Jacobian has a
positive determinant at any coefficients, not only at solutions
(``hbmfric.stability._passive``: the event AFT's Jacobian is the exact
Galerkin projection of a linearisation whose work against ``δu'`` is a sum
of squares). ``Branch.stability()`` therefore runs no AFT for the signs on
such a branch. Checked here against NumPy's determinants of the AFT's own
Jacobians at random coefficients, far from any solution, and against the
energy inequality itself; a softening cubic law, which the proof does not
cover, gives negative determinants with the same check (the check can
fail).
"""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.kernels.stability.hill import hill_jacobians
from hbmfric.stability import _passive, _stability_problem, derivative_operator

H = 7


def _jacobians(system, X, omega):
    """``∂R/∂X`` (k, n, n) of the full basis ``0 … H`` at the coefficient
    rows ``X`` (k, 2H + 1) and pulsations ``omega`` (k,), from the AFT."""
    problem = _stability_problem(system, 1.0, H, None, "auto", 1)
    pts = np.ascontiguousarray(np.column_stack([X, omega]))
    n = problem.n_unknowns
    J = np.empty((pts.shape[0], n, n))
    status = np.empty(pts.shape[0], dtype=np.int64)
    hill_jacobians(
        pts,
        problem.kernel_problem,
        J,
        status,
        np.zeros((0, 0), dtype=np.int64),
        np.zeros(0, dtype=np.int64),
        np.zeros((pts.shape[0], 0), dtype=np.int64),
        np.zeros(0, dtype=np.int64),
        np.zeros(0),
        np.zeros((0, 0)),
        1e-10,
        np.zeros(3),
    )
    assert np.all(status >= 0)
    return problem, pts, J


def _blocks():
    """Index sets of harmonic blocks: all, odd, even, ``0 … 3``, and
    harmonics {1, 2, 5} (any union of harmonics is closed under d/dt)."""
    per = np.repeat(np.arange(H + 1), [1] + [2] * H)
    return {
        "all": np.arange(per.size),
        "odd": np.flatnonzero(per % 2 == 1),
        "even": np.flatnonzero(per % 2 == 0),
        "low": np.flatnonzero(per <= 3),
        "mixed": np.flatnonzero(np.isin(per, (1, 2, 5))),
    }


def _random_points(rng, count, scale, odd=False):
    X = rng.normal(size=(count, 2 * H + 1)) * scale
    X *= (1.0 + np.repeat(np.arange(H + 1), [1] + [2] * H)) ** -1.5  # decaying
    if odd:
        per = np.repeat(np.arange(H + 1), [1] + [2] * H)
        X[:, per % 2 == 0] = 0.0
    omega = rng.uniform(0.2, 4.0, size=count)
    return X, omega


@pytest.mark.parametrize(
    "kt, fs, scale",
    [(3.0, 1.0, 1.0), (3.0, 1.0, 0.3), (50.0, 0.2, 1.0), (1e4, 1.0, 0.1)],
)
def test_every_harmonic_block_of_a_jenkins_jacobian_has_a_positive_determinant(
    kt, fs, scale
):
    rng = np.random.default_rng(int(kt * 7 + fs * 11 + scale * 13))
    system = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=kt, slip_force=fs))
    X, omega = _random_points(rng, 200, scale)
    problem, pts, J = _jacobians(system, X, omega)
    for name, idx in _blocks().items():
        sign, _ = np.linalg.slogdet(J[:, idx][:, :, idx])
        assert np.all(sign > 0), name
    odd_pts = _random_points(rng, 50, scale, odd=True)
    assert _passive(problem, np.column_stack(odd_pts))
    assert not _passive(problem, pts)  # even harmonics: not a symmetric branch


def test_jenkins_contact_work_is_a_sum_of_squares():
    """The inequality behind the proof: with ``W`` the rows' Galerkin
    weights and ``D`` the derivative operator, ``(D δX)ᵀ W J δX >= c Ω
    |D δX|²_W`` for every ``δX`` (the mass and stiffness terms cancel, the
    contact's work is a sum of squares)."""
    rng = np.random.default_rng(5)
    c = 0.02
    system = hf.Oscillator(1.0, c, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    X, omega = _random_points(rng, 100, 1.0)
    _, _, J = _jacobians(system, X, omega)
    weight = np.array([2.0] + [1.0] * (2 * H))  # ∫ψ_r² relative: mean row 1/2π
    low = np.inf
    for i in range(J.shape[0]):
        D = derivative_operator(np.arange(H + 1), omega[i])
        for _ in range(20):
            dX = rng.normal(size=2 * H + 1)
            v = D @ dX
            work = v @ (weight * (J[i] @ dX))
            floor = c * (v @ (weight * v))
            low = min(low, (work - floor) / max(abs(work), floor, 1e-300))
    assert low >= -1e-10


def test_softening_cubic_jacobian_can_have_a_negative_determinant():
    """The same check on a law the proof does not cover fails: a softening
    cubic spring at large amplitude (the check can fail)."""
    rng = np.random.default_rng(3)
    system = hf.Oscillator(1.0, 0.02, 1.0, hf.Cubic(-0.5))
    X, omega = _random_points(rng, 200, 2.0)
    problem, _, J = _jacobians(system, X, omega)
    sign, _ = np.linalg.slogdet(J)
    assert np.any(sign < 0)
    assert not _passive(problem, np.column_stack([X, omega]))


def _two_sliders():
    return hf.LinearStructure(
        np.eye(1),
        np.eye(1),
        0.02 * np.eye(1),
        load={0: 1.0},
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=3.0, slip_force=1.0), 0),
            hf.Contact(hf.Jenkins(stiffness=6.0, slip_force=0.4), 0),
        ],
    )


JENKINS_BRANCHES = {
    "p1-weak": lambda: hf.frf(
        hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0)),
        0.05,
        (0.5, 3.0),
        harmonics=15,
    ),
    "p1-strong": lambda: hf.frf(
        hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0)),
        1.5,
        (0.5, 3.0),
        harmonics=9,
    ),
    "stiff": lambda: hf.frf(
        hf.Oscillator(1.0, 0.05, 1.0, hf.Jenkins(stiffness=200.0, slip_force=0.2)),
        0.5,
        (0.3, 3.0),
        harmonics=11,
    ),
    "two-sliders": lambda: hf.frf(_two_sliders(), 0.8, (0.5, 4.0), harmonics=9),
}


@pytest.mark.filterwarnings("ignore::hbmfric.errors.AccuracyWarning")
@pytest.mark.parametrize("name", sorted(JENKINS_BRANCHES))
def test_jenkins_branches_proof_against_measured_signs_and_every_point(
    name, monkeypatch
):
    """On Jenkins branches the route by proof gives the verdicts of Hill's
    eigenvalues at every point (also with a smaller perturbation basis),
    and the signs the measured route computes by LU at every point (the
    AFT Jacobians of the solutions) are all +1, as the proof says."""
    import hbmfric.stability as stab_module

    branch = JENKINS_BRANCHES[name]()
    assert branch.info["odd_only"]
    for hp in (None, 5):
        branch._stability = None
        auto = branch.stability(perturbation_harmonics=hp)
        stable, computed = auto.stable.copy(), auto.computed.copy()
        branch._stability = None
        full = branch.stability(perturbation_harmonics=hp, exponents="all")
        np.testing.assert_array_equal(stable, full.stable)
        assert computed.sum() <= max(8, len(branch) // 8)
    # the measured signs: the same levels with the proof switched off
    seen = []
    original = stab_module._Level.determinant_signs

    def record(self):
        out = original(self)
        seen.append(out.copy())
        return out

    monkeypatch.setattr(stab_module, "_passive", lambda problem, points: False)
    monkeypatch.setattr(stab_module, "_stuck_everywhere", lambda *args: None)
    monkeypatch.setattr(stab_module._Level, "determinant_signs", record)
    branch._stability = None
    measured = branch.stability()
    np.testing.assert_array_equal(measured.stable, full.stable)
    signs = np.concatenate(seen)
    assert signs.shape[0] == len(branch) and np.all(signs == 1)
