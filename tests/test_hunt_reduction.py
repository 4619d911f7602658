"""Trust hunt, stop 28: a Craig–Bampton reduced structure asked for a
response above the pulsations its kept modes stand for.

The reference is the full structure (the one that was reduced): its natural
frequencies by a plain generalised eigenproblem, its response by the same
harmonic balance without reduction."""

import math
import warnings

import numpy as np
import pytest
from scipy.linalg import eigh

import hbmfric as hf

N = 40


def _chain() -> hf.LinearStructure:
    """40 masses of 0.1 kg in a fixed–free chain of 1e4 N/m springs, a
    Jenkins contact at the tip that stays stuck at the force used (slip
    force 1e3 N), driven at DOF 10."""
    K = 2e4 * np.eye(N) - 1e4 * (np.eye(N, k=1) + np.eye(N, k=-1))
    K[-1, -1] = 1e4
    return hf.LinearStructure(
        0.1 * np.eye(N),
        K,
        modal_damping=0.01,
        dof_names={"drive": 10, "tip": N - 1},
        load={"drive": 1.0},
        contact=hf.Jenkins(stiffness=2e3, slip_force=1e3),
        contact_dof="tip",
    )


def _cb_warnings(record) -> list[str]:
    return [
        str(w.message)
        for w in record
        if issubclass(w.category, hf.AccuracyWarning)
        and "Craig–Bampton" in str(w.message)
    ]


def test_the_reduced_modes_above_valid_below_are_not_the_structures():
    """The premise of the warning: below ``valid_below`` the reduced natural
    frequencies are within 1.5 % of the full structure's (plain eigh of the
    full matrices), above it they are off by more than 3 %."""
    full = _chain()
    M, _, K = full.matrices()
    w_full = np.sqrt(eigh(K, M, eigvals_only=True))
    for n_modes in (2, 4, 8, 16):
        reduced = hf.craig_bampton(full, ["tip", "drive"], n_modes=n_modes)
        assert reduced.valid_below == pytest.approx(
            2 * math.pi * reduced.cutoff_frequency
        )
        M_r, _, K_r = reduced.matrices()
        w_red = np.sqrt(eigh(K_r, M_r, eigvals_only=True))
        error = np.abs(w_red - w_full[: w_red.size]) / w_full[: w_red.size]
        below = w_red < reduced.valid_below
        assert np.all(error[below] < 0.015), (n_modes, error[below])
        assert np.all(error[~below] > 0.03), (n_modes, error[~below])


def test_periodic_solution_above_valid_below_warns_and_below_does_not():
    """Above ``valid_below`` the reduced model's response differs from the
    full structure's by more than 10 % (12 times here) and a warning says
    so; well below (0.15 of it), the two agree within 1 % and nothing is
    said about the reduction."""
    full = _chain()
    reduced = hf.craig_bampton(full, ["tip", "drive"], n_modes=2)
    w_cut = 2 * math.pi * reduced.cutoff_frequency  # documented on main too
    for omega, warned in ((0.15 * w_cut, False), (1.1 * w_cut, True)):
        with warnings.catch_warnings(record=True) as record:
            warnings.simplefilter("always")
            red = hf.periodic_solution(reduced, 1.0, omega, harmonics=3)
        ref = hf.periodic_solution(full, 1.0, omega, harmonics=3)
        a_red = red.amplitude(harmonic=1, dof="tip")
        a_ref = ref.amplitude(harmonic=1, dof="tip")
        error = abs(a_red - a_ref) / a_ref
        if warned:
            assert error > 0.1, error  # the reduced model is wrong there
            assert len(_cb_warnings(record)) == 1
        else:
            assert error < 0.01, error
            assert not _cb_warnings(record)


def test_frf_band_above_valid_below_warns():
    """An FRF over a band that straddles the cutoff (peak of the reduced
    model at 68.9 rad/s where the structure's is at 61.8 rad/s: its third
    mode is 12 % off) warns once; a band below it does not."""
    full = _chain()
    reduced = hf.craig_bampton(full, ["tip", "drive"], n_modes=2)
    w_cut = 2 * math.pi * reduced.cutoff_frequency  # documented on main too
    with pytest.warns(hf.AccuracyWarning, match="Craig–Bampton"):
        hf.frf(reduced, 1.0, (0.8 * w_cut, 1.2 * w_cut), harmonics=1)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        hf.frf(reduced, 1.0, (0.1 * w_cut, 0.3 * w_cut), harmonics=1)
    assert not _cb_warnings(record)


def test_guyan_reduction_stands_for_pulsations_below_the_first_interior_mode():
    """A Guyan reduction (no mode kept) has ``cutoff_frequency = 0``; its
    ``valid_below`` is the lowest fixed-interface pulsation (plain eigh of
    the interior matrices), and a band above it warns."""
    full = _chain()
    reduced = hf.craig_bampton(full, ["tip", "drive"], n_modes=0)
    assert reduced.cutoff_frequency == 0.0
    M, _, K = full.matrices()
    interior = np.setdiff1d(np.arange(N), [N - 1, 10])
    lowest = math.sqrt(
        eigh(
            K[np.ix_(interior, interior)],
            M[np.ix_(interior, interior)],
            eigvals_only=True,
        )[0]
    )
    assert reduced.valid_below == pytest.approx(lowest, rel=1e-12)
    with pytest.warns(hf.AccuracyWarning, match="Craig–Bampton"):
        hf.periodic_solution(reduced, 1.0, 1.05 * lowest, harmonics=1)


def test_nothing_reduced_never_warns():
    full = _chain()
    reduced = hf.craig_bampton(full, list(range(N)), n_modes=0)
    assert reduced.valid_below == math.inf
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        hf.periodic_solution(reduced, 1.0, 1e3, harmonics=1)
    assert not _cb_warnings(record)


def test_nonlinear_mode_above_valid_below_warns():
    """Mode 3 of the n_modes = 2 reduction lies above the cutoff (12 % off
    the structure's); mode 1 does not."""
    full = _chain()
    reduced = hf.craig_bampton(full, ["tip", "drive"], n_modes=2)
    with pytest.warns(hf.AccuracyWarning, match="Craig–Bampton"):
        hf.nonlinear_mode(reduced, mode=3, amplitude=(1e-4, 1e-3), points=2)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        hf.nonlinear_mode(reduced, mode=1, amplitude=(1e-4, 1e-3), points=2)
    assert not _cb_warnings(record)


def test_with_contact_keeps_the_reduction_and_its_warning():
    """``reduced.with_contact(law)`` was a plain LinearStructure: no
    ``expand``, no ``valid_below``, no warning above the cutoff."""
    reduced = hf.craig_bampton(_chain(), ["tip", "drive"], n_modes=2)
    other = reduced.with_contact(hf.Jenkins(stiffness=1e3, slip_force=1e3))
    assert isinstance(other, hf.ReducedStructure)
    assert other.valid_below == reduced.valid_below
    assert other.expand(np.zeros(other.n_dof)).shape == (N,)
    with pytest.warns(hf.AccuracyWarning, match="Craig–Bampton"):
        hf.periodic_solution(other, 1.0, 1.1 * other.valid_below, harmonics=1)
