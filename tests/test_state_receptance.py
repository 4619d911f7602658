"""The receptance of several contact coordinates from the complex modes of
the first-order form (``receptance="state"``, issue 15 stop 24).

References, each independent of the complex modes: dense complex solves of
``K - ω² M + iω C`` (NumPy), and the direct-receptance kernel path."""

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem, state_space_modes

HZ = 2.0 * np.pi


def test_complex_modes_reproduce_the_lap_joints_receptance():
    """``B X diag(1/(iω - λ)) Y Bᵀ`` against ``B Z(ω)⁻¹ Bᵀ`` by dense solves,
    and the same for the drive load, over the harmonics 1-15 of the
    figure's 125-185 Hz: 1e-10 of the largest term (the lap joint's
    reduced model has non-classical damping and natural pulsations from
    12.6 to 8e5 rad/s)."""
    s = hf.lap_joint(10)
    M, C, K = (np.asarray(a) for a in s.matrices())
    poles, X, Y, _ = state_space_modes(M, C, K)
    p = CondensedHBMProblem(s, 1.0, harmonics=3)
    B = p.selection
    load = s.load_vector(1.0).astype(complex)
    worst = 0.0
    for f in (125.0, 162.0, 185.0):
        for k in range(1, 16, 2):
            w = k * HZ * f
            Z = K - w * w * M + 1j * w * C
            exact = B @ np.linalg.solve(Z, np.column_stack([B.T, load]))
            approx = B @ ((X / (1j * w - poles)) @ (Y @ np.column_stack([B.T, load])))
            worst = max(worst, np.max(np.abs(approx - exact)) / np.max(np.abs(exact)))
    assert worst < 1e-10


def test_lap_joint_residual_by_complex_modes_is_the_direct_one():
    """The condensed residual and Jacobian of the lap joint (H = 15, at
    three times the free linear response at 162 Hz, partly slipping) with
    the complex modes against the direct solve per harmonic, to 1e-9 of
    their largest terms (the receptance's 1e-12 times the condition number
    of ``G``, about 1e4)."""
    s = hf.lap_joint(10)
    state = CondensedHBMProblem(s, 36.0, 15)
    direct = CondensedHBMProblem(s, 36.0, 15, receptance="direct")
    assert state.receptance_method == "state"
    omega = HZ * 162.0
    y = np.append(3.0 * direct.linear_response(omega, "free"), omega)
    Ra, Ja, sa = state.residual(y)
    Rb, Jb, sb = direct.residual(y)
    assert sa == sb >= 0
    assert np.max(np.abs(Ra - Rb)) < 1e-9 * np.max(np.abs(Rb))
    assert np.max(np.abs(Ja - Jb)) < 1e-9 * np.max(np.abs(Jb))
    dOmega = np.max(np.abs(Ja[:, -1] - Jb[:, -1]))
    assert dOmega < 1e-8 * np.max(np.abs(Jb[:, -1]))


def _three_dof(critical: bool):
    """Three DOFs, damping non-classical (modes 2 and 3 coupled); every
    mode critically damped (defective double poles) or lightly damped."""
    M = np.eye(3)
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    w2, phi = np.linalg.eigh(K)
    modal = np.diag((2.0 if critical else 0.1) * np.sqrt(w2))
    modal[1, 2] = modal[2, 1] = 0.05
    C = phi @ modal @ phi.T
    contacts = [
        hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.05), 0),
        hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.05), 1, 2),
    ]
    return hf.LinearStructure(M, K, damping=C, contacts=contacts, load={2: 1.0})


def test_defective_modes_fall_back_to_the_direct_solve():
    """Critically damped modes (double poles, no basis of eigenvectors):
    the complex modes fail their check, ``"auto"`` takes the direct solve
    and ``receptance="state"`` refuses; the same structure lightly damped
    takes the complex modes, whose branch point equals the direct one."""
    defective = _three_dof(critical=True)
    assert state_space_modes(*defective.matrices()) is None
    assert CondensedHBMProblem(defective, 0.1, 5).receptance_method == "direct"
    with pytest.raises(ValueError, match="receptance='direct'"):
        CondensedHBMProblem(defective, 0.1, 5, receptance="state")
    light = _three_dof(critical=False)
    assert CondensedHBMProblem(light, 0.1, 5).receptance_method == "state"
    a = hf.periodic_solution(light, 0.1, 1.1, harmonics=5, condense="state")
    b = hf.periodic_solution(light, 0.1, 1.1, harmonics=5, condense="direct")
    assert a.converged and b.converged
    scale = np.max(np.abs(b.coefficients))
    assert np.max(np.abs(a.coefficients - b.coefficients)) < 1e-10 * scale
    # by default: condensed by complex modes, or (defective) solved in full
    branch = hf.frf(light, 0.1, (1.0, 1.1), harmonics=3)
    assert branch.info["condensed"] and branch.info["receptance"] == "state"
    assert not hf.frf(defective, 0.1, (1.0, 1.1), harmonics=3).info["condensed"]


def _tangent(J):
    """Unit null vector of the Jacobian ``J`` (shape (n, n + 1)): the
    branch's tangent, by SVD."""
    t = np.linalg.svd(J)[2][-1]
    return t / np.linalg.norm(t)


@pytest.mark.parametrize("receptance", ["state", "modal"])
def test_curve_rule_draws_the_recovered_contact_dof(receptance):
    """What the condensed curve rule draws
    (:func:`hbmfric.kernels.residuals.condensed.coordinates_drawn`): the amplitude
    of the first harmonic of the contact DOF and its derivative along the
    branch's tangent, against the recovery of every DOF by dense solves
    (``full_coefficients`` of ``receptance="direct"``, with the AFT forces)
    at the solution and at two points a small step along the tangent
    (central difference). Lap joint (complex modes) and a chain with
    Rayleigh damping (modal sums), partly slipping."""
    from hbmfric.kernels.residuals.condensed import coordinates_drawn

    if receptance == "state":
        s = hf.lap_joint(10)
        force, omega, H = 0.04 * 36e3, HZ * 146.0, 7
    else:
        M = np.diag(1.0 + 0.1 * np.arange(5))
        K = 2.0 * np.eye(5) - np.eye(5, k=1) - np.eye(5, k=-1)
        K[-1, -1] = 1.0
        contacts = [
            hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.03), 1),
            hf.Contact(hf.Jenkins(stiffness=0.5, slip_force=0.02), 2, 4),
        ]
        s = hf.LinearStructure(
            M, K, contacts=contacts, load={4: 1.0}, rayleigh=(0.01, 0.02)
        )
        force, omega, H = 0.1, 0.5, 7
    # solved with the direct receptance: its Newton stops at 1e-11 of the
    # load here, the complex modes' at their (larger) rounding level
    sol = hf.periodic_solution(s, force, omega, harmonics=H, condense="direct")
    assert sol.converged
    p = CondensedHBMProblem(s, force, H, receptance=receptance)
    assert p.receptance_method == receptance and p.multi
    y = np.append(p.unknowns_from_full(sol.coefficients), omega)
    R, J, _ = p.residual(y)
    # converged to the rounding level of D = G⁻¹ (κ(G) 1e4 on the joint)
    assert np.max(np.abs(R)) <= max(1e-10 * force, p.rounding_level())
    t = _tangent(J)
    hn = list(p.harmonic_numbers)
    col = sum(1 if k == 0 else 2 for k in hn[: hn.index(1)])
    X = np.empty(p.n_coef)
    ok, w, dw, a, da, v, n_coef = coordinates_drawn(
        p.kernel_problem, y, t, np.ones_like(y), col, X
    )
    assert ok and w == omega and dw == t[-1] and n_coef == p.n_coef
    c = p.contact_dof
    direct = CondensedHBMProblem(s, force, H, receptance="direct")

    def amplitude(point):
        X = direct.full_coefficients(point[None])[0]
        return np.hypot(X[c, col], X[c, col + 1])

    assert a == pytest.approx(amplitude(y), rel=1e-8)
    Xd = direct.full_coefficients(y[None])[0, c]
    np.testing.assert_allclose(X, Xd, rtol=0, atol=1e-8 * np.max(np.abs(Xd)))
    h = 1e-6 * np.linalg.norm(y)
    fd = (amplitude(y + h * t) - amplitude(y - h * t)) / (2.0 * h)
    assert da == pytest.approx(fd, rel=1e-5)
    dX = (
        direct.full_coefficients((y + h * t)[None])[0, c]
        - direct.full_coefficients((y - h * t)[None])[0, c]
    ) / (2.0 * h)
    assert v == pytest.approx(np.sum(dX**2), rel=1e-4)
