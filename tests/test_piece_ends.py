"""How a traced piece ended (``hbmfric.continuation.ends``): a return along
itself at a singular point that is not a fold, and a step budget spent
climbing an unbounded resonance. Both were quiet before stop 28: false
folds and a duplicated curve, and a finite "peak" of 1e13 m in a branch
called complete, without a warning."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.continuation.ends import (
    budget_note,
    cut_at_return,
    cut_at_stall,
    drop_folds_at,
    returned_to_start,
    stalled_meeting,
)
from hbmfric.continuation.palc import MAX_STEPS, MIN_STEP, RANGE_START
from hbmfric.results import Branch


def _synthetic(omega, amplitude, folds, sweep="up", reason=RANGE_START, pieces=None):
    """A branch of one DOF and one harmonic (cosine amplitude) with the given
    path; the range is the span of ``omega``."""
    omega = np.asarray(omega, dtype=float)
    n = omega.size
    coefficients = np.zeros((n, 1, 3))
    coefficients[:, 0, 1] = amplitude
    return Branch(
        omega=omega,
        coefficients=coefficients,
        harmonic_numbers=np.array([0, 1]),
        force=1.0,
        folds=np.asarray(folds, dtype=np.int64),
        stop_reason=reason,
        n_steps=n,
        n_rejected=0,
        newton_iterations=2 * n,
        elapsed=0.0,
        info={"sweep": sweep, "omega_range": (omega.min(), omega.max())},
        pieces=pieces,
        tangents=np.tile([0.0, 1.0, 0.0, 0.0], (n, 1)),
        truncation_error=np.zeros(n),
    )


def test_a_return_along_the_same_path_is_cut_at_the_turn():
    """Up to Ω = 1, then back along the same points to the start: cut at
    Ω = 1, the folds there dropped, the singular point named."""
    w_out = np.linspace(0.2, 1.0, 9)
    a_out = 1.0 / (1.5 - w_out)
    omega = np.concatenate((w_out, w_out[-2::-1]))
    amplitude = np.concatenate((a_out, a_out[-2::-1]))
    branch = _synthetic(omega, amplitude, folds=[3, 9, 10])
    assert returned_to_start(branch)
    cut = cut_at_return(branch)
    np.testing.assert_array_equal(cut.omega, w_out)
    np.testing.assert_array_equal(cut.amplitude(harmonic=1), a_out)
    # the fold at 3 lies before the turn, away from it: kept
    np.testing.assert_array_equal(cut.folds, [3])
    assert cut.info["turned_at"] == [1.0]
    assert "turned back onto its own path" in cut.stop_reason
    assert cut.tangents.shape == (9, 4)
    assert cut.truncation_error.shape == (9,)


def test_a_fold_back_to_the_start_on_another_solution_is_kept():
    """A true fold: the path comes back to the starting Ω on the upper
    branch (another amplitude): nothing is cut."""
    w_out = np.linspace(0.2, 1.0, 9)
    omega = np.concatenate((w_out, w_out[-2::-1]))
    amplitude = np.concatenate((np.ones(9), 1.0 + np.linspace(0.1, 1.0, 8)))
    branch = _synthetic(omega, amplitude, folds=[9])
    assert not returned_to_start(branch)
    assert cut_at_return(branch) is branch


def test_a_stall_is_cut_at_its_first_arrival_when_the_rest_revisits():
    """Up to Ω = 1, jitter there, back over the same curve to 0.9 (other
    points on it) and up again: cut at the first arrival. A path that goes
    on to another amplitude after the stall is left whole."""
    w_out = np.linspace(0.5, 1.0, 501)
    curve = lambda w: 1.0 / (1.2 - w)  # noqa: E731
    w_back = np.array([1.0, 1.0, 0.97, 0.93, 0.9, 0.95, 1.0])
    omega = np.concatenate((w_out, w_back))
    branch = _synthetic(omega, curve(omega), folds=[502, 505, 506], reason=MIN_STEP)
    cut = cut_at_stall(branch, 1.0)
    np.testing.assert_array_equal(cut.omega, w_out)
    assert cut.folds.size == 0 and cut.info["turned_at"] == [1.0]
    other = np.concatenate((curve(w_out), 2.0 * curve(w_back)))
    branch = _synthetic(omega, other, folds=[502, 505, 506], reason=MIN_STEP)
    assert cut_at_stall(branch, 1.0) is branch


def test_a_meeting_of_stalls_and_of_budgets():
    """Two pieces that end at one Ω: stalled (min_step) or a budget spent
    without climbing there is a singular point; a budget spent climbing
    (an unbounded resonance) is not."""
    up_w = np.linspace(0.5, 1.0, 40)
    down_w = np.linspace(2.0, 1.0, 40)
    calm = np.linspace(1.0, 2.0, 40)
    climbing = np.geomspace(1.0, 1e6, 40)
    up = _synthetic(up_w, calm, [], reason=MIN_STEP)
    down = _synthetic(down_w, calm, [], sweep="down", reason=MAX_STEPS)
    assert stalled_meeting(up, down) == 1.0
    down = _synthetic(down_w, climbing, [], sweep="down", reason=MAX_STEPS)
    assert stalled_meeting(up, down) is None
    up = _synthetic(up_w, climbing, [], reason=MAX_STEPS)
    assert stalled_meeting(up, down) is None


def test_folds_at_a_singular_point_are_dropped():
    """A path that jittered at Ω = 1 (folds 1e-13 apart there) and turned
    for real at Ω = 0.5: only the real fold stays."""
    omega = [0.2, 0.4, 0.5, 0.45, 0.7, 1.0 - 1e-13, 1.0, 1.0 - 2e-13, 1.0]
    branch = _synthetic(omega, np.arange(9.0), folds=[3, 6, 7, 8], reason="end")
    drop_folds_at(branch, [1.0])
    np.testing.assert_array_equal(branch.folds, [3])


@pytest.mark.parametrize("reason", [MAX_STEPS, "end of frequency range reached"])
def test_other_stops_are_never_cut(reason):
    w = np.concatenate((np.linspace(0.2, 1.0, 5), np.linspace(0.8, 0.2, 4)))
    a = np.concatenate((np.linspace(1, 2, 5), np.linspace(2, 1, 5)[1:]))
    branch = _synthetic(w, a, folds=[5], reason=reason)
    assert cut_at_return(branch) is branch


def test_budget_note_names_the_climb():
    """A piece that spent its budget with its amplitude 1e6 times its
    earlier largest: 'still climbing'; one that stopped calmly: named,
    without the climb."""
    w = np.linspace(0.5, 0.999, 50)
    climbing = _synthetic(w, np.geomspace(1.0, 1e6, 50), [], reason=MAX_STEPS)
    note = budget_note(climbing)
    assert note is not None and "still climbing" in note
    calm = _synthetic(w, np.linspace(1.0, 2.0, 50), [], reason=MAX_STEPS)
    note = budget_note(calm)
    assert note is not None and "still climbing" not in note
    done = _synthetic(w, np.linspace(1.0, 2.0, 50), [], reason="end")
    assert budget_note(done) is None


def test_undamped_friction_oscillator_above_den_hartog_limit_warns():
    """m = 1, k = 1, no damping, Jenkins kt = 3, f_s = 1, F = 2 > 4 f_s/π:
    the slipping oscillator's energy input π F a outgrows the friction's
    4 f_s a, so the response at Ω = 1 is unbounded. Both sweeps climb
    until their step budget runs out and meet at Ω = 1 (the branch covers
    the range in Ω): a CoverageWarning must say the peak is not resolved.
    With 2 % damping the same call ends normally and does not warn so."""
    undamped = hf.Oscillator(1.0, 0.0, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    with pytest.warns(hf.CoverageWarning, match="still climbing"):
        branch = hf.frf(undamped, 2.0, (0.5, 3.0), harmonics=7)
    assert branch.complete  # in Ω: the pieces meet at Ω = 1
    assert branch.amplitude(harmonic=1).max() > 1e6
    # a smaller budget leaves a gap: the coverage warning names the budget
    with pytest.warns(hf.CoverageWarning, match="gaps.*step budget"):
        branch = hf.frf(undamped, 2.0, (0.5, 3.0), harmonics=7, max_steps=400)
    assert not branch.complete
    damped = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        branch = hf.frf(damped, 2.0, (0.5, 3.0), harmonics=7)
    assert branch.complete


def undamped_contact_chain() -> hf.LinearStructure:
    """Ten unit masses and springs clamped at one end, no damping, forced
    at the free end, eight Jenkins contacts (slip force 1, stiffnesses
    log-evenly 0.1 to 10) to ground on the first eight masses (the
    stress matrix's ``law="blocks"`` chain without its damping: a new user
    who forgets ``modal_damping``)."""
    n = 10
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    contacts = [
        hf.Contact(hf.Jenkins(stiffness=float(kt), slip_force=1.0), i)
        for i, kt in enumerate(np.logspace(-1.0, 1.0, 8))
    ]
    return hf.LinearStructure(np.eye(n), K, load={n - 1: 1.0}, contacts=contacts)


@pytest.mark.slow
def test_undamped_chain_singular_point_is_named_not_folded():
    """At Ω = 0.7495 the third harmonic meets a natural frequency of the
    stuck chain (3Ω = 2.2486): the HBM Jacobian is singular and both sweeps
    turned back there along their own path. Before stop 28 the branch held
    the duplicate return paths (5015 points) and 12 folds at that one Ω,
    without a word. Now: no folds, two pieces meeting at the singular
    point, a SingularPointWarning, and 3Ω equal to an eigenfrequency of
    K + diag(k_t) (closed form)."""
    system = undamped_contact_chain()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        with pytest.warns(hf.SingularPointWarning, match="singular point"):
            branch = hf.frf(system, 0.5, (0.02, 0.8), harmonics=15)
    assert branch.folds.size == 0
    assert branch.complete and len(branch.pieces) == 2
    (w_s,) = set(branch.info["singular_points"])
    ends = [branch.omega[p][[0, -1]] for p in branch.piece_slices()]
    assert ends[0][-1] == pytest.approx(w_s, abs=1e-9)
    assert ends[1][0] == pytest.approx(w_s, abs=1e-9)
    stuck = 2.0 * np.eye(10) - np.eye(10, k=1) - np.eye(10, k=-1)
    stuck[-1, -1] = 1.0
    stuck[np.arange(8), np.arange(8)] += np.logspace(-1.0, 1.0, 8)
    natural = np.sqrt(np.linalg.eigvalsh(stuck))
    assert np.min(np.abs(natural - 3.0 * w_s)) < 1e-6 * natural.max()
    # no duplicate curve: each piece runs one way in Ω (at the singular Ω
    # itself the path may run along the family of solutions there)
    for p in branch.piece_slices():
        step = np.diff(branch.omega[p])
        assert np.all(step >= -1e-12) or np.all(step <= 1e-12)
