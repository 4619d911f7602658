"""Trust hunt, stop 28: ``NonlinearMode.resonances`` and the gap between
the two pieces of a mode traced past an internal resonance
(``upper_branch=True``).

The resonances are the amplitudes where the force the mode needs (the
dissipated energy over ``π a |pᴴψ|``) equals the forcing. Across the gap no
point exists, and the crossing is rightly not interpolated; but before stop
28 a force whose balance changes sign across the gap and also elsewhere
returned the other resonances alone, without a word (on the 30-DOF spring
chain of issue 16, kt = 5e3, at F = 3 N: two resonances on the upper piece,
while the balance goes from 0.027 N to 4.8 N across the gap).

Reference: a one-DOF mode built by hand (m = 1 kg, unit load, motion
``a cos ωt``), whose needed force is ``2 D ω² a`` in closed form."""

import warnings

import numpy as np
import pytest

import hbmfric as hf


def _mode(amplitude, omega, damping_ratio, pieces) -> hf.NonlinearMode:
    a = np.asarray(amplitude, dtype=float)
    coefficients = np.zeros((a.size, 1, 3))
    coefficients[:, 0, 1] = a  # Xc1 = a on the one DOF of unit mass
    return hf.NonlinearMode(
        amplitude=a,
        omega=np.asarray(omega, dtype=float),
        damping_ratio=np.asarray(damping_ratio, dtype=float),
        coefficients=coefficients,
        harmonic_numbers=np.array([0, 1]),
        mode=1,
        linear_omega=float(omega[0]),
        linear_damping_ratio=float(damping_ratio[0]),
        requested=(float(a[0]), float(a[-1])),
        stop_reason="two pieces (built by hand)",
        newton_iterations=np.zeros(a.size, dtype=np.int64),
        n_steps=0,
        n_rejected=0,
        elapsed=0.0,
        load_vector=np.array([1.0 + 0.0j]),
        pieces=None if pieces is None else np.asarray(pieces, dtype=np.int64),
        _mass=np.eye(1),
    )


def _needed(mode) -> np.ndarray:
    """``2 D ω² a``: supplied energy ``2π D ω² a²`` over ``π a``."""
    return 2.0 * mode.damping_ratio * mode.omega**2 * mode.amplitude


# needed force: 0.1, 0.2, 0.3 | gap | 5, 2, 6 (N): at F = 3 N the balance
# changes sign across the gap and twice on the upper piece
A = np.array([1e-4, 2e-4, 3e-4, 1e-3, 2e-3, 3e-3])
W = np.array([10.0, 9.9, 9.8, 6.0, 5.9, 5.8])
NEED = np.array([0.1, 0.2, 0.3, 5.0, 2.0, 6.0])
D = NEED / (2.0 * W**2 * A)


def test_the_hand_built_mode_needs_the_forces_in_closed_form():
    np.testing.assert_allclose(
        _mode(A, W, D, [0, 3]).supplied_energy() / (np.pi * A), NEED, rtol=1e-12
    )


def test_a_sign_change_across_the_gap_is_said_when_others_are_found():
    mode = _mode(A, W, D, [0, 3])
    with pytest.warns(hf.CoverageWarning, match="across the gap a = 0.0003 to 0.001"):
        omega, amp = mode.resonances(3.0)
    # the two on the upper piece, interpolated in log a (closed form)
    assert amp.size == 2 and np.all((amp > 1e-3) & (amp < 3e-3))
    for a_res in amp:
        i = np.searchsorted(A, a_res) - 1
        u = (np.log(a_res) - np.log(A[i])) / (np.log(A[i + 1]) - np.log(A[i]))
        assert NEED[i] + u * (NEED[i + 1] - NEED[i]) == pytest.approx(3.0)


def test_a_sign_change_only_across_the_gap_names_the_gap():
    """F = 1 N: the balance crosses nowhere but in the gap; the warning
    says so (before: 'extend the amplitude range', which cannot help)."""
    mode = _mode(A, W, D, [0, 3])
    with pytest.warns(hf.CoverageWarning, match="gap") as record:
        omega, amp = mode.resonances(1.0)
    assert omega.size == 0
    assert not any("extend the amplitude range" in str(w.message) for w in record)


def test_one_piece_interpolates_and_is_silent():
    """The same points as one piece: three crossings at F = 3 N, no
    word about a gap. (Since stop 33 the balance's jumps between these six
    points, 0.3 -> 5 -> 2 -> 6 N, are said to make the crossings uncertain:
    an ``AccuracyWarning``, not a ``CoverageWarning``.)"""
    mode = _mode(A, W, D, None)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("error", hf.CoverageWarning)
        warnings.simplefilter("always", hf.AccuracyWarning)
        _, amp = mode.resonances(3.0)
    assert amp.size == 3
    assert all("bends sharply" in str(w.message) for w in record)


def test_resonance_of_a_strongly_non_harmonic_mode_warns():
    """The issue-16 spring chain (kt = 5e3) past its 3:1 internal
    resonance: at F = 3 N ``resonances`` predicts a = 1.1e-3 and 4.5e-3,
    where the harmonics above the first carry 60-80 % of Σ k² |X_k|²; time
    integration of the forced chain at the upper one's Ω gives a modal
    amplitude more than twice the predicted one (measured 0.018 against
    0.0045: the FRF peak is at a = 0.020). It warns now."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from test_modes import _spring_chain

    from hbmfric.signals import coefficient_columns

    chain, (mass, _, _) = _spring_chain(5e3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        mode = hf.nonlinear_mode(chain, amplitude=(1e-6, 1e-1), points=40)
    with pytest.warns(hf.AccuracyWarning, match="harmonics above the first"):
        omega, amp = mode.resonances(3.0)
    assert omega.size == 2
    ref = hf.validation.steady_state(chain, 3.0, float(omega[-1]))
    c = coefficient_columns(ref.harmonic_numbers)[1]
    xc, xs = ref.coefficients[:, c], ref.coefficients[:, c + 1]
    modal = float(np.sqrt(xc @ mass @ xc + xs @ mass @ xs))
    assert modal > 2.0 * amp[-1], (modal, amp[-1])


def test_resonance_of_a_nearly_harmonic_mode_is_silent():
    """The one-DOF Jenkins mode of tests/test_modes.py (ζ = 0.1 %, H = 7;
    share 0.33 % at most), whose resonances are within 1 % of the FRF
    peaks (test_backbone_through_frf_peaks): no warning."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from test_modes import _oscillator

    osc = _oscillator(1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        mode = hf.nonlinear_mode(osc, amplitude=(1e-6, 1e-1), points=61, harmonics=7)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        for force in (0.2, 0.5, 1.0, 1.5, 3.0):
            omega, _ = mode.resonances(force)
            assert omega.size >= 1
