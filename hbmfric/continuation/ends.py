"""How a traced piece of an FRF ended, read from its points.

Two endings a stop reason alone does not tell apart from a normal one:

* **A return along itself.** At a singular point of the HBM equations that
  is not a fold (the Jacobian is singular, but the branch does not turn:
  e.g. an undamped structure whose stuck contacts make it linear while a
  harmonic ``kΩ`` meets one of its natural frequencies), the tangent flips
  and the corrector follows the branch back the way it came. The piece then
  "turns back at a fold and leaves the range at its starting end" on the
  very point it started from, and lists folds where the branch does not
  turn. A piece whose last point equals its first is cut at its turning
  point (:func:`cut_at_return`); the retrace from the other end of the
  range then reaches the same point from the other side.
* **A step budget spent climbing.** An undamped resonance that the contacts
  cannot bound (a slipping contact passes at most its slip force) has an
  unbounded response: each sweep climbs towards it until ``max_steps`` runs
  out, and the two pieces meet in Ω at amplitudes that are the budget's,
  not the response's (:func:`budget_note`).
"""

from __future__ import annotations

import numpy as np

from ..results import Branch
from .palc import MAX_STEPS, MIN_STEP, RANGE_START

#: a piece returned to its start when its last point's coefficients are
#: within this fraction of their norm of its first point's (a fold that
#: leads back to the starting end lands on another solution: the upper and
#: lower branches differ by a finite amount there)
RETURN_RTOL = 1e-8
#: Ω equal to this fraction of the range width
OMEGA_RTOL = 1e-9
#: a point traced after a stall revisits the path before it when its
#: first-harmonic amplitude is within this fraction of the path's at its Ω
#: (linear interpolation between the earlier points: chord-level accuracy)
REVISIT_RTOL = 1e-3
#: a piece that spent its step budget "climbs" when its last amplitude is
#: this many times its largest amplitude in the first half of its points
CLIMB_RATIO = 1e3


def returned_to_start(branch: Branch) -> bool:
    """Whether a one-piece trace turned back and ended on its first point."""
    if not branch.stop_reason.startswith(RANGE_START) or branch.omega.size < 3:
        return False
    if branch.pieces is not None and len(branch.pieces) > 1:
        return False
    lo, hi = branch.omega_range or (np.min(branch.omega), np.max(branch.omega))
    if abs(branch.omega[-1] - branch.omega[0]) > OMEGA_RTOL * (hi - lo):
        return False
    first, last = branch.coefficients[0], branch.coefficients[-1]
    size = np.linalg.norm(first)
    return bool(np.linalg.norm(last - first) <= RETURN_RTOL * max(size, 1e-300))


def cut_at_return(branch: Branch) -> Branch:
    """``branch`` cut at its turning point if it returned along itself.

    Parameters
    ----------
    branch : Branch
        One traced piece (``info["sweep"]`` is "up" or "down").

    Returns
    -------
    Branch
        ``branch`` itself when it did not return to its start; else a new
        branch holding its points up to the turning point (the largest Ω of
        an up sweep, the smallest of a down sweep), without the folds at
        and after it, with ``stop_reason`` naming the singular point and
        ``info["turned_at"]`` its Ω (rad/s).
    """
    if not returned_to_start(branch):
        return branch
    down = branch.info.get("sweep") == "down"
    turn = int(np.argmin(branch.omega) if down else np.argmax(branch.omega))
    omega_turn = float(branch.omega[turn])
    return _truncated(
        branch,
        turn,
        omega_turn,
        f"turned back onto its own path at Ω = {omega_turn:.8g} rad/s (the "
        "tangent reversed: not a fold)",
    )


def cut_at_stall(branch: Branch, omega_singular: float) -> Branch:
    """``branch`` cut at its first arrival at ``omega_singular`` if what it
    traced afterwards only stayed at that Ω or went back over its own path
    (within :data:`REVISIT_RTOL` of the path before, in the first-harmonic
    amplitude at the same Ω); else ``branch`` itself. For a piece that
    stalled at a singular point (:func:`stalled_meeting`)."""
    w = branch.omega
    if w.size < 2:
        return branch
    lo, hi = branch.omega_range or (np.min(w), np.max(w))
    at = np.abs(w - omega_singular) <= OMEGA_RTOL * (hi - lo)
    if not at.any():
        return branch
    first = int(np.argmax(at))
    if first == w.size - 1:
        return branch
    a = branch.amplitude(harmonic=1)
    for j in range(first + 1, w.size):
        if at[j]:
            continue
        # earlier segments spanning Ω_j: the amplitude there, interpolated
        w0, w1 = w[:first], w[1 : first + 1]
        a0, a1 = a[:first], a[1 : first + 1]
        span = (np.minimum(w0, w1) <= w[j]) & (w[j] <= np.maximum(w0, w1))
        span &= w0 != w1
        if not span.any():
            return branch
        u = (w[j] - w0[span]) / (w1[span] - w0[span])
        earlier = a0[span] + u * (a1[span] - a0[span])
        if np.min(np.abs(earlier - a[j])) > REVISIT_RTOL * max(abs(a[j]), 1e-300):
            return branch
    return _truncated(
        branch,
        first,
        omega_singular,
        f"stalled at Ω = {omega_singular:.8g} rad/s (step below min_step, or "
        "the step budget spent there; not a fold)",
    )


def _truncated(branch: Branch, last: int, omega_singular: float, reason: str):
    """The points ``0 .. last`` of a one-piece ``branch``, folds near
    ``omega_singular`` or after ``last`` dropped, ``info["turned_at"]``
    set."""
    keep = slice(0, last + 1)
    lo, hi = branch.omega_range or (np.min(branch.omega), np.max(branch.omega))
    near = np.abs(branch.omega - omega_singular) <= OMEGA_RTOL * (hi - lo)
    # a fold i lies between points i - 1 and i
    folds = np.array(
        [i for i in branch.folds if i <= last and not (near[i - 1] or near[i])],
        dtype=np.int64,
    )
    info = dict(branch.info)
    info["turned_at"] = [omega_singular]
    info["dropped_points"] = int(branch.omega.size - last - 1)

    def cut(a):
        return None if a is None else a[keep].copy()

    return Branch(
        omega=branch.omega[keep].copy(),
        coefficients=branch.coefficients[keep].copy(),
        harmonic_numbers=branch.harmonic_numbers,
        force=branch.force,
        folds=folds,
        stop_reason=reason,
        n_steps=branch.n_steps,
        n_rejected=branch.n_rejected,
        newton_iterations=branch.newton_iterations,
        elapsed=branch.elapsed,
        info=info,
        point_harmonics=cut(branch.point_harmonics),
        dof_names=dict(branch.dof_names),
        pieces=None,
        truncation_error=cut(branch.truncation_error),
        tangents=cut(branch.tangents),
        _source=branch._source,
    )


def stalled_meeting(first: Branch, second: Branch) -> float | None:
    """Ω where two pieces traced from the two ends of the range both stalled
    (step below ``min_step``, a return cut by :func:`cut_at_return`, or a
    step budget spent without climbing) at
    the same Ω, to ``OMEGA_RTOL`` of the range width; else None. Neither
    side could pass that point: it is singular (the undamped chain of
    ``tests/test_piece_ends.py`` at H = 7 stalls there from both sides,
    with 17 'folds' jittering within 1e-12 rad/s)."""
    if first.omega.size == 0 or second.omega.size == 0:
        return None
    stalled = (MIN_STEP, "turned back onto its own path", "stalled at")

    def stuck(b: Branch) -> bool:
        # a budget spent jittering there counts (the chain at H = 15 with
        # the second-order predictor: 3500 steps at one Ω), one spent
        # climbing an unbounded resonance does not (budget_note says that)
        if b.stop_reason.startswith(stalled):
            return True
        if not b.stop_reason.startswith(MAX_STEPS):
            return False
        a = b.amplitude(harmonic=1)
        return _climb_ratio(a[-1], a[: a.size // 2]) <= CLIMB_RATIO

    if not (stuck(first) and stuck(second)):
        return None
    lo, hi = first.omega_range or (np.min(first.omega), np.max(first.omega))
    if abs(first.omega[-1] - second.omega[-1]) > OMEGA_RTOL * (hi - lo):
        return None
    return float(first.omega[-1])


def drop_folds_at(branch: Branch, omegas) -> None:
    """Remove from ``branch.folds`` (in place) the folds between two points
    within ``OMEGA_RTOL`` of the range width of any Ω in ``omegas``: the
    turns of a path that stalled or jittered at a singular point (the
    uncondensed chain of ``tests/test_piece_ends.py`` stalled there on its
    up sweep with six 'folds' 1e-12 rad/s apart)."""
    if not len(omegas) or branch.folds.size == 0:
        return
    lo, hi = branch.omega_range or (np.min(branch.omega), np.max(branch.omega))
    tol = OMEGA_RTOL * (hi - lo)
    w = branch.omega
    near = np.zeros(w.size, dtype=bool)
    for omega in omegas:
        near |= np.abs(w - omega) <= tol
    folds = branch.folds
    keep = ~(near[np.maximum(folds - 1, 0)] | near[np.minimum(folds, w.size - 1)])
    branch.folds = folds[keep].astype(np.int64)


def singular_note(branch: Branch) -> str | None:
    """A sentence on the singular points the pieces of ``branch`` met, or
    None."""
    points = list(branch.info.get("singular_points", []))
    for piece in branch.info.get("pieces", []) or []:
        points += list(piece.get("singular_points", []))
    if not points:
        return None
    where = ", ".join(f"{w:.8g}" for w in sorted(set(points)))
    return (
        f"the continuation met a singular point of the HBM equations at "
        f"Ω = {where} rad/s, which no sweep could pass (the path turned back "
        "onto itself or its step fell below min_step there; not a fold, and "
        "the folds listed there before are dropped); the points on either "
        "side are solutions, each piece traced up to it from its end of the "
        "range. Typical cause: a structure without damping whose stuck "
        "contacts make it linear while a harmonic of Ω meets one of its "
        "natural frequencies; a little modal damping removes it"
    )


def _climb_ratio(last: float, earlier: np.ndarray) -> float:
    """``last`` over the largest of ``earlier`` (amplitudes)."""
    if earlier.size == 0:
        return 1.0
    return float(last) / max(float(np.max(earlier)), 1e-300)


def budget_note(branch: Branch) -> str | None:
    """A sentence on the pieces of ``branch`` that spent their step budget,
    or None. Says where each stopped, and whether its amplitude was still
    climbing (its last amplitude over :data:`CLIMB_RATIO` times the largest
    in the first half of its points: a resonance nothing bounds)."""
    amplitude = None  # read only where a piece spent its budget
    notes = []
    slices = branch.piece_slices()
    reasons = [p.get("stop_reason", "") for p in branch.info.get("pieces", [])]
    if len(reasons) != len(slices):
        reasons = [branch.stop_reason] * len(slices)
    for piece, reason in zip(slices, reasons, strict=True):
        if not reason.startswith(MAX_STEPS) or piece.stop - piece.start < 2:
            continue
        if amplitude is None:
            amplitude = branch.amplitude(harmonic=1)
        a = amplitude[piece]
        # a second piece is stored reversed: its last traced point is first
        end = 0 if piece.start > 0 else -1
        first_half = a[: a.size // 2] if end == -1 else a[a.size // 2 :]
        last = float(a[end])
        ratio = _climb_ratio(last, first_half)
        note = (
            "a sweep spent its step budget (max_steps) at Ω = "
            f"{branch.omega[piece][end]:.8g} rad/s with a first-harmonic "
            f"amplitude {last:.3g}"
        )
        if ratio > CLIMB_RATIO:
            note += (
                f", {ratio:.3g} times its earlier largest: the response was "
                "still climbing (a resonance nothing bounds: no damping, and a "
                "contact that slips passes at most its slip force), so the peak "
                "there is not resolved"
            )
        notes.append(note)
    return "; ".join(notes) if notes else None
