"""Stability of branch points by Hill's method (issue 16).

Every test compares Hill's exponents with an independent result: the
closed form of a linear oscillator, the Floquet multipliers of the
time-domain monodromy matrix (variational equations of the Duffing ODE
integrated by ``scipy.integrate.solve_ivp``), the folds located by the
continuation's tangent, or the exponents at a much larger ``H``.
"""

import numba
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from stability_cases import FRICTION_DUFFING, friction_duffing

import hbmfric as hf
from hbmfric.hbm import HBMProblem
from hbmfric.stability import floquet_exponents, stability_of_points

DUFFING = dict(mass=1.0, damping=0.05, stiffness=1.0, k3=0.1, force=0.2)


@pytest.fixture(scope="module")
def duffing_branch():
    d = DUFFING
    osc = hf.Oscillator(d["mass"], d["damping"], d["stiffness"], hf.Cubic(d["k3"]))
    return osc, hf.frf(osc, d["force"], (0.5, 2.0), harmonics=9)


def _fold_omega(branch, i):
    """Ω of the fold between points i - 1 and i: where the Ω component of
    the tangent vanishes (linear interpolation of dΩ/ds)."""
    t0, t1 = branch.tangents[i - 1, -1], branch.tangents[i, -1]
    w0, w1 = branch.omega[i - 1], branch.omega[i]
    return w0 + (w1 - w0) * t0 / (t0 - t1)


def _change_omega(branch, stab, i):
    """Ω where the largest real part crosses 0 between points i - 1 and i
    (linear interpolation)."""
    r0, r1 = stab.max_real[i - 1], stab.max_real[i]
    w0, w1 = branch.omega[i - 1], branch.omega[i]
    return w0 + (w1 - w0) * r0 / (r0 - r1)


def test_duffing_middle_branch_unstable(duffing_branch):
    """Hardening Duffing with two folds: the stretch between the folds is
    unstable, the outer ones stable, and stability changes exactly between
    the two points that straddle each fold (where dΩ/ds changes sign)."""
    _, branch = duffing_branch
    assert branch.folds.size == 2
    f0, f1 = branch.folds
    stable = branch.stable
    assert stable[:f0].all() and stable[f1:].all()
    assert not stable[f0:f1].any()
    stab = branch.stability()
    np.testing.assert_array_equal(stab.changes(), branch.folds)
    # the Ω-tangent sign change brackets the crossing of the exponent
    dw = branch.tangents[:, -1]
    for i in branch.folds:
        assert np.sign(dw[i - 1]) != np.sign(dw[i])
        spacing = abs(branch.omega[i] - branch.omega[i - 1])
        gap = abs(_change_omega(branch, stab, i) - _fold_omega(branch, i))
        assert gap <= spacing


def _duffing_monodromy(branch, i):
    """Floquet multipliers of point ``i`` of the Duffing branch from the
    variational equations integrated over one period."""
    d = DUFFING
    m, c, k, k3, F = d["mass"], d["damping"], d["stiffness"], d["k3"], d["force"]
    w = float(branch.omega[i])
    hn, X = branch.harmonic_numbers, branch.coefficients[i, 0]
    x0 = X[0::2].sum() if hn[0] != 0 else X[0] + X[1::2].sum()
    cols = np.arange(hn.size) * 2 + (0 if hn[0] != 0 else 1)
    kk = hn[hn > 0]
    v0 = float(np.sum(kk * w * X[cols[hn > 0] + 1]))

    def rhs(t, z):
        x, v = z[0], z[1]
        acc = (F * np.cos(w * t) - c * v - k * x - k3 * x**3) / m
        P = z[2:].reshape(2, 2)
        A = np.array([[0.0, 1.0], [-(k + 3.0 * k3 * x * x) / m, -c / m]])
        return np.concatenate(([v, acc], (A @ P).ravel()))

    z0 = np.concatenate(([x0, v0], np.eye(2).ravel()))
    T = 2.0 * np.pi / w
    sol = solve_ivp(rhs, (0.0, T), z0, method="DOP853", rtol=1e-11, atol=1e-12)
    assert sol.success
    # the HBM orbit closes (its truncation error is small)
    assert abs(sol.y[0, -1] - x0) < 1e-5 * max(1.0, abs(x0))
    return np.linalg.eigvals(sol.y[2:, -1].reshape(2, 2))


def test_duffing_multipliers_against_monodromy(duffing_branch):
    """Hill's multipliers exp(λT) against the eigenvalues of the monodromy
    matrix of the variational equations, at 5 points of each of the three
    stretches (lower stable, middle unstable, upper stable): magnitudes
    within 1e-3."""
    _, branch = duffing_branch
    stab = branch.stability()
    f0, f1 = branch.folds
    worst = 0.0
    for lo, hi in ((0, f0), (f0, f1), (f1, len(branch))):
        for i in np.linspace(lo + 1, hi - 2, 5).round().astype(int):
            ref = np.sort(np.abs(_duffing_monodromy(branch, i)))
            hill = np.sort(np.abs(stab.multipliers[i]))
            worst = max(worst, float(np.max(np.abs(hill - ref))))
            assert (ref.max() < 1.0) == bool(stab.stable[i])
    # measured 1.9e-7 (the points next to the folds); the issue asks 1e-3
    assert worst < 1e-5


@pytest.mark.parametrize("omega", [0.7, 1.3, 2.9, 4.5])
def test_linear_oscillator_closed_form(omega):
    """No contact: the exponents are -ζω₀ ± iω_d modulo iΩ, exactly, in
    the full basis (here the odd/even split of a symmetric system too)."""
    m, c, k = 1.0, 0.1, 4.0
    lin = hf.Oscillator(m, c, k)
    sol = hf.periodic_solution(lin, 1.0, omega, harmonics=5)
    lam = sol.stability().exponents[0]
    w0 = np.sqrt(k / m)
    zeta = c / (2.0 * np.sqrt(k * m))
    wd = w0 * np.sqrt(1.0 - zeta**2)
    folded = wd - omega * np.round(wd / omega)
    expected = np.array([-zeta * w0 + 1j * folded, -zeta * w0 - 1j * folded])
    np.testing.assert_allclose(
        np.sort_complex(lam), np.sort_complex(expected), atol=1e-12
    )
    assert sol.stable


def test_linear_two_dof_against_state_matrix():
    """Two DOFs, no contact, non-classical damping: the exponents are the
    eigenvalues of the first-order state matrix, modulo iΩ."""
    M = np.diag([1.0, 2.0])
    C = np.array([[0.3, -0.1], [-0.1, 0.05]])
    K = np.array([[5.0, -2.0], [-2.0, 3.0]])
    omega = 1.1
    J = np.zeros((2 * 7, 2 * 7))  # H = 3: 7 coefficients per DOF
    hn = np.arange(4)
    for p in range(2):
        for q in range(2):
            J[p * 7, q * 7] = K[p, q]
            for kk in (1, 2, 3):
                w = kk * omega
                r, s = p * 7 + 2 * kk - 1, q * 7 + 2 * kk - 1
                J[r, s] = J[r + 1, s + 1] = K[p, q] - M[p, q] * w * w
                J[r, s + 1] = C[p, q] * w
                J[r + 1, s] = -C[p, q] * w
    lam = floquet_exponents(J, M, C, hn, omega)
    A = np.block(
        [
            [np.zeros((2, 2)), np.eye(2)],
            [-np.linalg.solve(M, K), -np.linalg.solve(M, C)],
        ]
    )
    ref = np.linalg.eigvals(A)
    ref = ref.real + 1j * (ref.imag - omega * np.round(ref.imag / omega))
    np.testing.assert_allclose(np.sort_complex(lam), np.sort_complex(ref), atol=1e-12)


def test_symmetric_split_equals_full_basis(duffing_branch):
    """The odd/even split of a symmetric branch gives the exponents of the
    whole full-basis problem (the Jacobian couples no odd to even
    harmonic)."""
    osc, branch = duffing_branch
    idx = np.array([10, branch.folds[0] + 5, branch.folds[1] + 5])
    args = (
        osc,
        branch.force,
        branch.omega[idx],
        branch.harmonic_numbers,
        branch.coefficients[idx],
        np.full(idx.size, 9),
    )
    split = stability_of_points(*args, aft=branch.info["aft"], symmetric=True)
    whole = stability_of_points(*args, aft=branch.info["aft"], symmetric=False)
    np.testing.assert_allclose(split.exponents, whole.exponents, atol=1e-10)


def _exponents(system, force, omega, harmonics, **kwargs):
    sol = hf.periodic_solution(system, force, omega, harmonics=harmonics, **kwargs)
    assert sol.converged
    return sol.stability().exponents[0]


def test_convergence_in_harmonics_duffing():
    """The selected exponents of a smooth law converge spectrally in H:
    each step of 2 harmonics gains at least two digits until rounding
    (measured against H = 41: 1.3e-6, 1.0e-9, 5.7e-13 at H = 3, 5, 7)."""
    duf = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    kw = dict(branch_side="below")
    ref = _exponents(duf, 0.2, 1.2, 41, **kw)
    errors = [
        np.max(np.abs(_exponents(duf, 0.2, 1.2, h, **kw) - ref)) for h in (3, 5, 7)
    ]
    assert errors[0] > 1e-8  # H = 3 is visibly truncated
    assert errors[1] < 1e-2 * errors[0] and errors[2] < 1e-2 * errors[1]
    assert errors[2] < 1e-11


def test_convergence_in_harmonics_jenkins():
    """Jenkins P1 in stick-slip (Ω = 2.2, F = 0.5): the selected exponents
    (the pair with |Im λ| <= Ω/2) converge in H towards those at H = 127
    (measured 2.7e-4, 5.6e-5, 2.6e-6 at H = 5, 15, 45), while the other
    Hill eigenvalues sit near ±kΩ."""
    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    osc = hf.Oscillator(1.0, 0.02, 1.0, law)
    ref = _exponents(osc, 0.5, 2.2, 127)
    errors = [np.max(np.abs(_exponents(osc, 0.5, 2.2, h) - ref)) for h in (5, 15, 45)]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1e-5
    assert np.all(np.abs(ref.imag) <= 1.1 + 1e-12)


def test_plot_draws_unstable_stretches_dashed(duffing_branch):
    """Before stability is computed every line is solid; afterwards the
    middle stretch is dashed and its samples lie between the two folds."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, branch = duffing_branch
    fresh = hf.Branch(
        **{
            f: getattr(branch, f)
            for f in (
                "omega",
                "coefficients",
                "harmonic_numbers",
                "force",
                "folds",
                "stop_reason",
                "n_steps",
                "n_rejected",
                "newton_iterations",
                "elapsed",
                "info",
                "tangents",
            )
        }
    )
    ax = fresh.plot()
    assert {ln.get_linestyle() for ln in ax.lines} == {"-", "None"}
    plt.close(ax.figure)
    branch.stability()
    for curve in ("dense", "polyline"):
        ax = branch.plot(curve=curve)
        dashed = [ln for ln in ax.lines if ln.get_linestyle() == "--"]
        solid = [ln for ln in ax.lines if ln.get_linestyle() == "-"]
        assert len(dashed) == 1 and len(solid) == 2
        colors = {ln.get_color() for ln in dashed + solid}
        assert len(colors) == 1
        w = dashed[0].get_xdata()
        lo, hi = np.sort(branch.omega[branch.folds])
        assert np.all(w >= lo - 1e-6) and np.all(w <= hi + 1e-6)
        plt.close(ax.figure)
    ax = branch.plot(curve="points")
    hollow = [ln for ln in ax.lines if ln.get_markerfacecolor() == "none"]
    f0, f1 = branch.folds
    assert len(hollow) == 1 and hollow[0].get_xdata().size == f1 - f0
    plt.close(ax.figure)


def test_loaded_branch_needs_the_system(duffing_branch, tmp_path):
    osc, branch = duffing_branch
    loaded = hf.Branch.load(branch.save(tmp_path / "b.npz"))
    with pytest.raises(ValueError, match="needs the system"):
        loaded.stability()
    np.testing.assert_array_equal(loaded.stability(osc).stable, branch.stable)


def test_rigid_coulomb_is_refused():
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Coulomb(slip_force=0.3))
    sol = hf.periodic_solution(osc, 0.5, 1.2, harmonics=5)
    with pytest.raises(ValueError, match="rigid Coulomb"):
        sol.stability()


M3 = np.diag([1.0, 0.8, 1.2])
K3 = np.array([[2.0, -1.0, 0.0], [-1.0, 2.5, -1.5], [0.0, -1.5, 1.5]])
C3 = 0.02 * M3 + 0.02 * K3


def _chain_monodromy(branch, i, k3, force):
    """Floquet multipliers of point ``i`` of the 3-DOF chain (cubic spring
    k3 x_2³ to ground, force on DOF 0) from the variational equations."""
    w = float(branch.omega[i])
    hn, X = branch.harmonic_numbers, branch.coefficients[i]
    cols = 2 * np.arange(hn.size)  # odd harmonics only: [a1, b1, a3, b3, …]
    x0 = X[:, cols].sum(axis=1)
    v0 = (X[:, cols + 1] * (hn * w)).sum(axis=1)
    Minv = np.linalg.inv(M3)
    p = np.array([force, 0.0, 0.0])

    def rhs(t, z):
        x, v = z[:3], z[3:6]
        f = K3 @ x + C3 @ v
        f[2] += k3 * x[2] ** 3
        acc = Minv @ (p * np.cos(w * t) - f)
        Kt = K3.copy()
        Kt[2, 2] += 3.0 * k3 * x[2] ** 2
        A = np.block([[np.zeros((3, 3)), np.eye(3)], [-Minv @ Kt, -Minv @ C3]])
        P = z[6:].reshape(6, 6)
        return np.concatenate((v, acc, (A @ P).ravel()))

    z0 = np.concatenate((x0, v0, np.eye(6).ravel()))
    sol = solve_ivp(
        rhs, (0.0, 2 * np.pi / w), z0, method="DOP853", rtol=1e-11, atol=1e-12
    )
    assert sol.success
    return np.linalg.eigvals(sol.y[6:, -1].reshape(6, 6))


def test_condensed_three_dof_chain_against_monodromy():
    """A 3-DOF chain with a cubic spring, traced condensed onto the contact
    DOF (the default): its stability uses the recovered DOFs with the full
    matrices. The changes fall on the folds and the six multipliers agree
    with the time-domain monodromy at two points per stretch (the
    difference falls with H like the truncation error)."""
    k3, force = 0.5, 0.05
    chain = hf.LinearStructure(
        M3, K3, C3, contact=hf.Cubic(k3), contact_dof=2, load={0: 1.0}
    )
    branch = hf.frf(chain, force, (0.3, 0.7), harmonics=11)
    assert branch.info["condensed"] and branch.folds.size == 2
    stab = branch.stability()
    assert stab.exponents.shape == (len(branch), 6)
    np.testing.assert_array_equal(stab.changes(), branch.folds)
    f0, f1 = branch.folds
    assert not stab.stable[f0:f1].any() and stab.stable[:f0].all()
    for lo, hi in ((0, f0), (f0, f1), (f1, len(branch))):
        for i in np.linspace(lo + 2, hi - 3, 2).round().astype(int):
            ref = np.sort(np.abs(_chain_monodromy(branch, i, k3, force)))
            hill = np.sort(np.abs(stab.multipliers[i]))
            # measured 2.9e-8 (H = 7: 2.3e-5, H = 15: 3.2e-11)
            np.testing.assert_allclose(hill, ref, atol=1e-6)


def test_perturbation_harmonics_truncate_the_perturbation_only(duffing_branch):
    """A smaller perturbation basis (the Jacobian still at the whole
    solution) approaches the full one as it grows, keeps the stability of
    every point of the Duffing branch at Hp = 5, and is recorded."""
    osc, branch = duffing_branch
    full = branch.stability().exponents.copy()
    errors = []
    for hp in (1, 3, 5):
        s = branch.stability(perturbation_harmonics=hp)
        assert np.all(s.harmonics == hp)
        errors.append(float(np.max(np.abs(s.exponents - full))))
    assert errors[0] > errors[1] > errors[2]
    np.testing.assert_array_equal(s.stable, branch.stability().stable)
    assert np.all(branch.stability().harmonics == 9)
    with pytest.raises(ValueError, match="perturbation_harmonics"):
        branch.stability(perturbation_harmonics=0)


def test_jenkins_against_the_exact_monodromy():
    """Jenkins P1 in stick-slip: the exact monodromy matrix (closed-form
    phases, located transitions and the saltation that locks the slider at
    slip onset, hbmfric.validation.exact) against Hill's multipliers from
    the AFT Jacobian at H = 31. The AFT linearisation is exact only at
    λ = 0 (docs/stability.md): the verdict agrees and the largest
    multiplier is close (measured 0.006, 0.028, 0.029 apart at Ω = 1.6,
    1.9, 2.2), the other one is not (0.22 against 0.03 at Ω = 1.6)."""
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    for w in (1.6, 1.9, 2.2):
        ex = hf.validation.exact_periodic_solution(osc, 0.5, w)
        assert ex.kind == "stick-slip"
        mu = ex.floquet_multipliers()
        assert abs(mu[-1]) < 1e-12  # the slider locked at slip onset
        exact = abs(mu[0])
        sol = hf.periodic_solution(osc, 0.5, w, harmonics=31)
        hill = np.max(np.abs(sol.stability().multipliers))
        assert (exact < 1.0) == sol.stable
        assert abs(hill - exact) < 0.04


def test_pickled_branch_keeps_a_picklable_system_only(duffing_branch):
    """A branch crosses process boundaries (hf.study workers): its system
    travels when it pickles, and is dropped (not an error) when not."""
    import pickle

    osc, branch = duffing_branch
    back = pickle.loads(pickle.dumps(branch))
    np.testing.assert_array_equal(back.stable, branch.stable)
    branch._source = {"system": osc, "unpicklable": lambda: None}
    try:
        back = pickle.loads(pickle.dumps(branch))
    finally:
        branch._source = {"system": osc}
    assert back._source is None
    with pytest.raises(ValueError, match="needs the system"):
        back.stability()


def test_selected_exponents_make_the_hill_pencil_singular(duffing_branch):
    """Δ0 + λΔ1 + λ²Δ2 (hill_matrices) is singular at every selected
    exponent, unfolded (λ + i m Ω for any m is an eigenvalue too), and
    regular half-way between two of them."""
    from hbmfric.hbm import HBMProblem
    from hbmfric.stability import _to_full_basis, hill_matrices

    osc, branch = duffing_branch
    problem = HBMProblem(osc, branch.force, 9, symmetry=False)
    for i in (10, branch.folds[0] + 20):
        w = float(branch.omega[i])
        y = np.append(
            _to_full_basis(branch.harmonic_numbers, branch.coefficients[i], 9), w
        )
        J = problem.residual(y)[1][:, :-1]
        d0, d1, d2 = hill_matrices(
            J, np.eye(1), 0.05 * np.eye(1), problem.harmonic_numbers, w
        )
        lams = branch.stability().exponents[i]
        for lam in (*lams, lams[0] + 1j * w, 0.5 * (lams[0] + lams[1])):
            s = np.linalg.svd(d0 + lam * d1 + lam**2 * d2, compute_uv=False)
            ratio = s[-1] / s[0]
            if lam == 0.5 * (lams[0] + lams[1]):
                assert ratio > 1e-6
            else:
                assert ratio < 1e-12


# -- located special points (hbmfric.bifurcation) -----------------------------


def _duffing_folds_closed_form(guesses):
    """Folds of the single-harmonic Duffing balance
    ``G(a, Ω) = ((k − mΩ² + 3/4 k3 a²)² + (cΩ)²) a² − F² = 0`` where
    ``∂G/∂a = 0`` (vertical tangent in the (Ω, a) plane), from guesses
    ``(Ω, a)``."""
    from scipy.optimize import fsolve

    d = DUFFING
    m, c, k, k3, F = d["mass"], d["damping"], d["stiffness"], d["k3"], d["force"]

    def equations(z):
        w, a = z
        s = k - m * w * w + 0.75 * k3 * a * a
        g = (s * s + (c * w) ** 2) * a * a - F * F
        dg = 2.0 * a * (s * s + (c * w) ** 2) + a * a * 2.0 * s * 1.5 * k3 * a
        return [g / F**2, dg / F**2]

    out = []
    for w, a in guesses:
        z, _, ok, _ = fsolve(equations, [w, a], xtol=1e-14, full_output=True)
        assert ok == 1
        out.append(z)
    return np.array(out)


def test_folds_located_against_the_single_harmonic_closed_form():
    """At H = 1 the HBM of the Duffing oscillator is its describing-function
    balance exactly (x³ of one harmonic has harmonics 1 and 3 only, sampled
    without aliasing): the located folds agree with the closed form's to
    1e-9 in Ω and amplitude, where the branch points bracketing them are
    1e-5 to 1e-2 apart in Ω."""
    d = DUFFING
    osc = hf.Oscillator(d["mass"], d["damping"], d["stiffness"], hf.Cubic(d["k3"]))
    branch = hf.frf(osc, d["force"], (0.5, 2.0), harmonics=1)
    points = branch.special_points(stability=False)
    assert [p.kind for p in points] == ["fold", "fold"]
    guesses = [(p.omega, p.amplitude()) for p in points]
    exact = _duffing_folds_closed_form(guesses)
    for p, (w, a) in zip(points, exact, strict=True):
        assert abs(p.omega - w) <= 1e-9 * w
        assert abs(p.amplitude() - a) <= 1e-9 * a
        # an extremum of Ω next to the two points that bracket it
        i = p.index
        lo, hi = sorted(branch.omega[i - 1 : i + 1])
        assert p.omega <= lo + 1e-12 or p.omega >= hi - 1e-12
        assert abs(p.omega - 0.5 * (lo + hi)) <= 10.0 * (hi - lo) + 1e-9


def test_stability_changes_located_at_the_folds(duffing_branch):
    """H = 9: each stability change, located as the zero of the largest
    Floquet exponent (a root search independent of the fold's), lies at
    the located fold to 1e-6 in Ω (the issue's bound; measured to
    rounding), and the crossing multiplier is +1."""
    osc, branch = duffing_branch
    points = branch.special_points()
    assert [p.kind for p in points] == ["fold", "fold"]
    assert [p.index for p in points] == list(branch.folds)
    for p in points:
        assert p.stability_omega is not None
        assert abs(p.stability_omega - p.omega) <= 1e-6
        assert abs(p.multiplier - 1.0) <= 1e-6
        # a solution of the balance in the full basis 0..9
        problem = HBMProblem(osc, DUFFING["force"], 9, symmetry=False)
        R, _, _ = problem.residual(np.append(p.coefficients.ravel(), p.omega))
        assert np.max(np.abs(R)) <= 1e-10 * DUFFING["force"]


def test_special_point_not_located_warns(monkeypatch, duffing_branch):
    """A point whose trial solutions do not converge is left out with a
    ConvergenceWarning, never returned unlocated."""
    from hbmfric import bifurcation

    _, branch = duffing_branch
    monkeypatch.setattr(bifurcation, "MAX_NEWTON", 0)
    with pytest.warns(hf.ConvergenceWarning, match="not located"):
        points = branch.special_points(stability=False)
    assert points == []


def test_special_points_of_rigid_coulomb_refused():
    osc = hf.Oscillator(1.0, 0.02, 1.0, hf.Coulomb(slip_force=1.0))
    branch = hf.frf(osc, 2.0, (0.5, 3.0), harmonics=7)
    with pytest.raises(ValueError, match="Coulomb"):
        branch.special_points()


def test_exact_monodromy_of_a_stuck_response():
    """A response that never slips is the linear stuck oscillator: the
    exact reference's multipliers are exp(λT) with λ = −ζω₀ ± iω_d of
    ``m ẍ + c ẋ + (k + kt) x`` (closed form), plus 1 for the neutral
    slider offset; Hill's method agrees on the two that decide."""
    m, c, k, kt = 1.0, 0.02, 1.0, 3.0
    osc = hf.Oscillator(m, c, k, hf.Jenkins(stiffness=kt, slip_force=1.0))
    w = 1.3
    ex = hf.validation.exact_periodic_solution(osc, 0.05, w)
    assert ex.kind == "stuck"
    w0 = np.sqrt((k + kt) / m)
    zeta = c / (2.0 * np.sqrt((k + kt) * m))
    lam = -zeta * w0 + 1j * w0 * np.sqrt(1.0 - zeta**2)
    T = 2.0 * np.pi / w
    expected = np.exp(np.array([lam, np.conj(lam)]) * T)
    mu = ex.floquet_multipliers()
    assert np.min(np.abs(mu - 1.0)) < 1e-12
    rest = np.delete(mu, np.argmin(np.abs(mu - 1.0)))
    np.testing.assert_allclose(
        np.sort_complex(rest), np.sort_complex(expected), rtol=0, atol=1e-10
    )
    hill = hf.periodic_solution(osc, 0.05, w, harmonics=7).stability().multipliers
    np.testing.assert_allclose(np.sort(np.abs(hill[0])), np.abs(expected), rtol=1e-8)


# -- a friction case with stability changes -----------------------------------


@numba.njit(cache=False)
def _march(omega, x0, v0, slider, periods, params, steps=2048):
    """Velocity Verlet of ``ẍ + c ẋ + x + k3 x³ + f_J = F cos Ωt`` with the
    Jenkins force by return mapping (written here, independent of the
    package; ``params = (c, k3, kt, f_s, F)``); returns the first-harmonic
    amplitude over the last period."""
    c, k3, kt, fs, F = params[0], params[1], params[2], params[3], params[4]
    dt = 2.0 * np.pi / omega / steps
    x, v, w = x0, v0, slider
    f = kt * (x - w)
    if f > fs:
        w, f = x - fs / kt, fs
    elif f < -fs:
        w, f = x + fs / kt, -fs
    a = F - c * v - x - k3 * x**3 - f
    last = np.empty(steps)
    n = steps * periods
    for s in range(n):
        t = (s + 1) * dt
        vh = v + 0.5 * dt * a
        x = x + dt * vh
        f = kt * (x - w)
        if f > fs:
            w, f = x - fs / kt, fs
        elif f < -fs:
            w, f = x + fs / kt, -fs
        rhs = F * np.cos(omega * t) - x - k3 * x**3 - f
        v = (vh + 0.5 * dt * rhs) / (1.0 + 0.5 * dt * c)
        a = rhs - c * v
        if s >= n - steps:
            last[s - (n - steps)] = x
    theta = 2.0 * np.pi * np.arange(1, steps + 1) / steps
    return 2.0 / steps * np.hypot(last @ np.cos(theta), last @ np.sin(theta))


def _start_state(branch, i):
    """Displacement, velocity and Jenkins slider at t = 0 of branch point
    ``i``: the slider from two periods of the return map over the HBM
    displacement (the second one periodic)."""
    d = FRICTION_DUFFING
    t, x = branch.point(i).time_response(4096)
    w = 0.0
    for _ in range(2):
        for xk in x[:, 0] if x.ndim == 2 else x:
            f = d["kt"] * (xk - w)
            if f > d["fs"]:
                w = xk - d["fs"] / d["kt"]
            elif f < -d["fs"]:
                w = xk + d["fs"] / d["kt"]
    X = branch.coefficients[i, 0]
    hn = branch.harmonic_numbers
    cols = np.cumsum([0] + [1 if k == 0 else 2 for k in hn[:-1]])
    x0 = sum(X[c] for c in cols)
    v0 = sum(
        branch.omega[i] * k * X[c + 1] for k, c in zip(hn, cols, strict=True) if k > 0
    )
    return float(x0), float(v0), w


@pytest.mark.slow
def test_friction_duffing_stability_against_time_integration():
    """Duffing with a Jenkins contact (H = 31: two folds): Hill's method on
    the AFT Jacobian finds the stretch between the folds unstable and the
    outer ones stable, the changes located at the folds (multiplier 1; the
    linearisation of a hysteretic law is exact where a real exponent
    crosses zero). Time integration written here, started on the HBM
    solution nudged by 1e-4 at 5 points in the inner 60 % of each stretch
    (Hill's largest multiplier there 0.58-0.92 and 1.06-1.22), stays on it
    where Hill says stable (first harmonic within 2e-3 after 150 periods)
    and leaves it where Hill says unstable (by more than 1 %, a hundred
    times the nudge)."""
    s = friction_duffing()
    branch = hf.frf(s, FRICTION_DUFFING["force"], (0.5, 2.5), harmonics=31)
    assert branch.folds.size == 2
    f0, f1 = branch.folds
    stable = branch.stable
    assert stable[: f0 - 2].all() and stable[f1 + 2 :].all()
    assert not stable[f0 + 2 : f1 - 2].any()
    points = branch.special_points()
    assert [p.kind for p in points] == ["fold", "fold"]
    for p in points:
        assert abs(p.stability_omega - p.omega) <= 1e-6
    amp = branch.amplitude(1)
    d = FRICTION_DUFFING
    params = np.array([d["c"], d["k3"], d["kt"], d["fs"], d["force"]])
    for lo, hi in ((0, f0), (f0, f1), (f1, len(branch))):
        # the inner 60 % of each stretch: next to a fold the multiplier is
        # near 1 and the time integration would need thousands of periods
        margin = (hi - lo) // 5
        for i in np.linspace(lo + margin, hi - margin, 5).round().astype(int):
            x0, v0, w = _start_state(branch, i)
            # a 1e-4 nudge: decays on a stable orbit, grows on an unstable one
            x0 *= 1.0 + 1e-4
            a1 = _march(float(branch.omega[i]), x0, v0, w, 150, params)
            gap = abs(a1 - amp[i]) / amp[i]
            if stable[i]:
                assert gap < 2e-3, (i, branch.omega[i], gap)
            else:
                # the 1e-4 nudge amplified at least 100 times (a stable
                # orbit keeps it below 20); close to a fold the multiplier
                # is near 1 and the growth over 150 periods is slower
                assert gap > 1e-2, (i, branch.omega[i], gap)
