"""Trust hunt, stop 28: ``modal_damping`` with different ratios on the
modes of one repeated natural frequency.

The mode shapes of a repeated frequency are any basis of their space (the
one the eigensolver returns by rounding), and ``M Φ diag(2 ζ ω) Φᵀ M``
with different ratios on them depends on that basis. Before stop 28 the
structure was built without a word: on a ring of three masses with ratios
(0.01, 0.02, 0.05) the damping matrix broke the ring's symmetry and a
perturbation of 1e-9 of one stiffness entry moved the driving-point
receptance at the repeated resonance from 2.39 to 0.96 m/N."""

import numpy as np
import pytest
from scipy.linalg import eigh

import hbmfric as hf

#: three unit masses on a ring, each on a spring of 4 N/m to ground and of
#: 1 N/m to each neighbour: ω = 2, √7, √7 rad/s
RING_K = np.array([[6.0, -1.0, -1.0], [-1.0, 6.0, -1.0], [-1.0, -1.0, 6.0]])
ROTATION = np.roll(np.eye(3), 1, axis=0)


def _plain_modal_damping(M, K, zeta, basis_turn=0.0):
    """``M Φ diag(2 ζ ω) Φᵀ M`` in plain SciPy, the repeated pair's shapes
    (modes 2 and 3) turned by ``basis_turn`` rad within their plane."""
    w2, phi = eigh(K, M)
    c, s = np.cos(basis_turn), np.sin(basis_turn)
    phi[:, 1:3] = phi[:, 1:3] @ np.array([[c, -s], [s, c]])
    mphi = M @ phi
    return mphi @ np.diag(2.0 * np.asarray(zeta) * np.sqrt(w2)) @ mphi.T


def test_the_premise_different_ratios_depend_on_the_basis():
    """Plain SciPy: two bases of the repeated pair give two damping
    matrices with different ratios, the same one with equal ratios."""
    M = np.eye(3)
    a = _plain_modal_damping(M, RING_K, [0.01, 0.02, 0.05])
    b = _plain_modal_damping(M, RING_K, [0.01, 0.02, 0.05], basis_turn=0.7)
    assert np.max(np.abs(a - b)) > 0.01
    a = _plain_modal_damping(M, RING_K, [0.01, 0.02, 0.02])
    b = _plain_modal_damping(M, RING_K, [0.01, 0.02, 0.02], basis_turn=0.7)
    np.testing.assert_allclose(a, b, atol=1e-14)


@pytest.mark.parametrize("ratios", [[0.01, 0.02, 0.05], [0.01, 0.02]])
def test_different_ratios_on_a_repeated_pair_are_refused(ratios):
    """Also when the list stops inside the pair (mode 3 then undamped)."""
    with pytest.raises(ValueError, match="modes 2 and 3 different ratios"):
        hf.LinearStructure(np.eye(3), RING_K, modal_damping=ratios)


def test_equal_ratios_on_a_repeated_pair_keep_the_rings_symmetry():
    s = hf.LinearStructure(np.eye(3), RING_K, modal_damping=[0.01, 0.02, 0.02])
    C = s.matrices()[1]
    np.testing.assert_allclose(ROTATION @ C @ ROTATION.T, C, atol=1e-14)
    np.testing.assert_allclose(
        C, _plain_modal_damping(np.eye(3), RING_K, [0.01, 0.02, 0.02]), atol=1e-14
    )


def test_a_split_pair_takes_different_ratios():
    """Mistuned by 1e-3 the pair is two modes with their own shapes: the
    ratios are the user's, C as in plain SciPy."""
    K = RING_K.copy()
    K[0, 0] += 1e-3
    zeta = [0.01, 0.02, 0.05]
    s = hf.LinearStructure(np.eye(3), K, modal_damping=zeta)
    np.testing.assert_allclose(
        s.matrices()[1], _plain_modal_damping(np.eye(3), K, zeta), atol=1e-12
    )


def test_rigid_body_modes_are_not_a_repeated_pair():
    """Two free masses joined by a spring and a free third one: ω = 0, 0,
    √2; ratios on the rigid-body modes add no damping (2 ζ ω = 0)."""
    K = np.array([[1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
    s = hf.LinearStructure(np.eye(3), K, modal_damping=[0.01, 0.02, 0.05])
    C = s.matrices()[1]
    np.testing.assert_allclose(
        C, 2 * 0.05 * np.sqrt(2) * np.outer([1, -1, 0], [1, -1, 0]) / 2, atol=1e-12
    )
