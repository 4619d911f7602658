"""The recovery of a condensed branch with direct receptances solves its
points in chunks (hunt35, stop 34).

One contact to ground on a structure with non-classical damping is
condensed by default with a direct solve of ``Z(kΩ) = K - (kΩ)² M + ikΩ
C`` per harmonic; the recovery of every DOF stacked ``Z`` over every
point of the branch at once: ``n_points × n_dof²`` complex terms, copied
by the solve (472 MB peak for 500 points of a 200-DOF chain; 32 GB for
2000 points of 1000 DOFs), which the memory guard (condensed unknowns
only) does not count: a long run killed by the operating system at its
end. Now at most :data:`~hbmfric.condensation.DIRECT_CHUNK_BYTES` of
stacked matrices at once (109 MB peak for the same 500 points).

References: the shapes handed to ``numpy.linalg.solve`` (recorded) and a
plain per-point, per-harmonic solve of the full equations written here.
"""

import numpy as np

import hbmfric as hf
from hbmfric import condensation
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.signals import coefficient_columns

N_DOF = 40


def _structure():
    K = np.zeros((N_DOF, N_DOF))
    for i in range(N_DOF):
        K[i, i] += 1.0
        if i + 1 < N_DOF:
            K[i, i] += 1.0
            K[i, i + 1] = K[i + 1, i] = -1.0
    C = 0.02 * np.eye(N_DOF)
    C[0, 1] = C[1, 0] = 0.01  # not classical: direct receptance
    return hf.LinearStructure(
        np.eye(N_DOF),
        K,
        C,
        contacts=[hf.Contact(hf.Jenkins(stiffness=1.0, slip_force=0.05), 20)],
        load={N_DOF - 1: 0.1},
    )


def test_recovery_in_chunks_matches_plain_solves(monkeypatch):
    s = _structure()
    p = CondensedHBMProblem(s, 0.1, harmonics=3)
    assert p.receptance_method == "direct"
    rng = np.random.default_rng(3)
    points = rng.normal(size=(300, p.n_unknowns + 1)) * 1e-2
    points[:, -1] = np.linspace(0.2, 2.0, 300)
    monkeypatch.setattr(condensation, "DIRECT_CHUNK_BYTES", 16 * N_DOF**2 * 64)
    sizes = []
    solve = np.linalg.solve

    def recording(a, b):
        sizes.append(np.asarray(a).nbytes)
        return solve(a, b)

    monkeypatch.setattr(np.linalg, "solve", recording)
    X = p.full_coefficients(points)
    monkeypatch.setattr(np.linalg, "solve", solve)
    assert max(sizes) <= condensation.DIRECT_CHUNK_BYTES
    # plain reference: x_k = Z(kΩ)⁻¹ (P_k - e_c F_k), point by point
    M, C, K = (np.asarray(a) for a in s.matrices())
    F = p.contact_forces(points)
    load = p.load.reshape(N_DOF, p.n_coef)
    cols = coefficient_columns(p.harmonic_numbers)
    for i in range(0, 300, 37):
        for k in p.harmonic_numbers:
            c = cols[int(k)]
            w = k * points[i, -1]
            z = K - w * w * M + 1j * w * C
            if k == 0:
                rhs = load[:, c].astype(complex)
                rhs[20] -= F[i, c]
                x = np.linalg.solve(z, rhs)
                np.testing.assert_allclose(X[i, :, c], x.real, rtol=0, atol=1e-12)
                continue
            rhs = load[:, c] - 1j * load[:, c + 1]
            rhs[20] -= F[i, c] - 1j * F[i, c + 1]
            x = np.linalg.solve(z, rhs)
            np.testing.assert_allclose(X[i, :, c], x.real, rtol=0, atol=1e-12)
            np.testing.assert_allclose(X[i, :, c + 1], -x.imag, rtol=0, atol=1e-12)
