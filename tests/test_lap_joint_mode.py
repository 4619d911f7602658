"""The nonlinear mode (EPMC) of the bolted lap joint's first bending mode.

The joint (``hf.lap_joint(n_pairs=10)``, hung on soft springs: its modes
1-3 are rigid-body modes near 2-3.5 Hz) bends first at 167.11 Hz with its
contacts stuck and at 144.28 Hz with every pair slipped. The backbone must
join the two limits, the friction damping must rise and fall between them,
and the FRF peak of the forced joint must lie on it where its damping is
light (the issue asks 1e-3 in frequency).
"""

import numpy as np
import pytest
import scipy.linalg

import hbmfric as hf


@pytest.mark.slow
def test_lap_joint_backbone_joins_stuck_and_slipped_limits():
    joint = hf.lap_joint(n_pairs=10)
    mode = hf.nonlinear_mode(joint, 4, amplitude=(1e-6, 1.0), points=32, harmonics=5)
    assert mode.complete
    stuck = mode.linear_omega / (2.0 * np.pi)
    M, _, K = joint.matrices()
    # slipped, the two beams also slide axially on their springs: four
    # modes below 4 Hz, the bending mode fifth
    free = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)[4]) / (2.0 * np.pi)
    assert stuck == pytest.approx(167.1089, abs=1e-3)
    assert free == pytest.approx(144.2838, abs=1e-3)
    f = mode.frequency
    assert abs(f[0] / stuck - 1.0) < 1e-8  # stuck at small amplitude
    assert abs(f[-1] / free - 1.0) < 1e-4  # measured 1e-5 at a = 1
    assert np.all(np.diff(f) <= 1e-9 * stuck)  # softening all the way
    d = mode.damping_ratio
    assert d[0] == pytest.approx(mode.linear_damping_ratio, rel=1e-6)
    assert d.max() > 10.0 * d[0]  # friction damping in microslip
    assert d[-1] < 0.5 * d.max()  # and less again in macroslip
    # the FRF peak under 36 N (microslip, light damping) on the backbone
    omega, _ = mode.resonances(36.0)
    assert omega.size == 1
    with pytest.warns(hf.AccuracyWarning):  # H = 5 is coarse above 160 Hz
        branch = hf.frf(joint, 36.0, (2 * np.pi * 140, 2 * np.pi * 172), harmonics=5)
    # the peak of the curve drawn (the dense output), not of the points
    # alone: steps near the peak are 0.6 rad/s (6e-4 of Ω) long. Measured:
    # the backbone's peak 8.35e-4 below the dense output's, 8.42e-4 below
    # the peak of a branch at curve_tolerance 1e-6 (1767 points)
    curve = branch.resample(16)
    peak = curve.omega[np.argmax(curve.amplitude(1, dof="drive"))]
    assert abs(omega[0] / peak - 1.0) < 1e-3
