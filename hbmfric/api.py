"""Public entry points: ``frf`` (a continuation run) and ``periodic_solution``
(one frequency, :mod:`hbmfric.periodic`, re-exported here)."""

from __future__ import annotations

import dataclasses
import warnings
from typing import TYPE_CHECKING

import numpy as np

from . import _memory
from ._validate import finite_float
from .continuation import AdaptiveContinuation, Continuation, ContinuationOptions
from .continuation.accuracy import fold_estimates, watched_truncation_errors
from .continuation.adaptive import JOIN_ROUNDS, LADDER, START
from .continuation.ends import (
    budget_note,
    cut_at_return,
    cut_at_stall,
    drop_folds_at,
    singular_note,
    stalled_meeting,
)
from .continuation.palc import rigid_coulomb
from .errors import AccuracyWarning, CoverageWarning, SingularPointWarning
from .hbm import HBMProblem
from .results import Branch, join_pieces
from .systems.craig_bampton import warn_above_cutoff
from .systems.protocol import check_system

if TYPE_CHECKING:  # re-exported, imported on first use (``__getattr__`` below)
    from .periodic import periodic_solution as periodic_solution


def __getattr__(name: str):
    # ``periodic_solution`` is re-exported from :mod:`hbmfric.periodic`,
    # imported on first use (an FRF does not need that module)
    if name == "periodic_solution":
        from .periodic import periodic_solution

        globals()[name] = periodic_solution
        return periodic_solution
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _plan_band(problem, omega_high: float) -> None:
    """Tell a condensed problem the top of the band it will be traced over
    (its complex-mode receptance sums the poles far above it once,
    :meth:`~hbmfric.condensation.CondensedHBMProblem.plan_band`)."""
    plan = getattr(problem, "plan_band", None)
    if plan is not None:
        plan(omega_high)


def _omega_range(omega) -> tuple[float, float]:
    try:
        lo, hi = omega
    except (TypeError, ValueError):
        raise ValueError(
            f"omega must be a pair (low, high) in rad/s, got {omega!r}"
        ) from None
    lo = finite_float("omega[0]", lo, low=0.0, low_open=True)
    hi = finite_float("omega[1]", hi, low=0.0, low_open=True)
    if not hi > lo:
        raise ValueError(
            f"omega range must be increasing and non-empty (low < high), got "
            f"({lo}, {hi}); use sweep='down' to trace from high to low"
        )
    return lo, hi


def _problem(
    system,
    force,
    harmonics,
    n_time,
    symmetry,
    aft,
    condense,
    subharmonic=1,
    *,
    at=(),
    top=None,
):
    """The HBM discretisation: condensed onto the contact DOF or full
    (``subharmonic``: see :class:`~hbmfric.hbm.HBMProblem`).

    ``at``: pulsations (rad/s) solved from a standing start (a fixed Ω, the
    ends of a range), ``top``: the highest harmonic a ladder of levels
    reaches. Where a harmonic of one of them lies on a pole of the
    condensed receptance (within
    :data:`~hbmfric.condensation.POLE_DISTANCE`: an undamped natural
    pulsation of the structure without its contacts), the default
    (``condense=None``) solves the full problem, and an explicit
    ``condense`` raises ``ValueError``.
    """
    data = check_system(system)  # before anything reads the system
    condensed = _condensed_problem(
        system, force, harmonics, n_time, symmetry, aft, condense, subharmonic, data
    )
    if not getattr(condensed, "condensed", False):
        return condensed
    from .condensation import POLE_DISTANCE

    for w in at:
        dist, k, w_r = condensed.pole_distance(w, top)
        if dist >= POLE_DISTANCE:
            continue
        if condense is None:
            return HBMProblem(
                system,
                force,
                harmonics,
                n_time,
                symmetry,
                aft,
                subharmonic=subharmonic,
                _checked=data,
            )
        raise ValueError(
            f"condense={condense!r} cannot be solved at Omega = {w:.10g} rad/s: "
            f"harmonic {k} of it lies within {dist:.2g} (relative) of the "
            f"natural pulsation {w_r:.10g} rad/s of the structure without its "
            "contacts, where the receptance of the condensation is infinite "
            "(undamped; nearly so: huge) and its recovered DOFs lose about 6e-17 / "
            f"{dist:.2g} of their value; use condense=False or None (the "
            "default solves the full problem there)"
        )
    return condensed


def _condensed_problem(
    system, force, harmonics, n_time, symmetry, aft, condense, subharmonic, data
):
    from .condensation import CondensedHBMProblem, condensed_by_default

    if condense is None:
        condense = condensed_by_default(system)
    if isinstance(condense, str) and condense in ("modal", "state", "direct"):
        return CondensedHBMProblem(
            system,
            force,
            harmonics,
            n_time,
            symmetry,
            aft,
            receptance=condense,
            subharmonic=subharmonic,
            _checked=data,
        )
    if not isinstance(condense, bool | np.bool_):
        raise ValueError(
            f"condense must be True, False, None, 'modal', 'state' or 'direct', got "
            f"{condense!r}"
        )
    cls = CondensedHBMProblem if condense else HBMProblem
    return cls(
        system,
        force,
        harmonics,
        n_time,
        symmetry,
        aft,
        subharmonic=subharmonic,
        _checked=data,
    )


def _describe(system, problem: HBMProblem, extra: dict) -> dict:
    def plain(obj):
        if dataclasses.is_dataclass(obj):
            d = {"type": type(obj).__name__}
            for f in dataclasses.fields(obj):
                d[f.name] = plain(getattr(obj, f.name))
            return d
        if isinstance(obj, float | int | str | bool) or obj is None:
            return obj
        return repr(obj)

    info = {
        "system": plain(system),
        "harmonics": problem.harmonics,
        "odd_only": problem.odd,
        "n_time": problem.n_time,
        "aft": problem.aft,
        "condensed": bool(getattr(problem, "condensed", False)),
    }
    if info["condensed"]:
        # "modal", "state" (complex modes) or "direct"
        info["receptance"] = problem.receptance_method
    info.update(extra)
    return info


def frf(
    system,
    force: float,
    omega: tuple[float, float],
    harmonics: int | str = "auto",
    *,
    n_time: int | None = None,
    symmetry: bool | None = None,
    aft: str = "auto",
    sweep: str = "up",
    harmonic_tolerance: float = 1e-4,
    options: ContinuationOptions | None = None,
    amplitude_scale: float | None = None,
    condense: bool | None = None,
    retrace: bool = True,
    **option_overrides,
) -> Branch:
    """Trace the forced response (FRF) of ``system`` over a frequency range.

    Parameters
    ----------
    system : Oscillator or compatible system
    force : float
        Amplitude ``F`` of the forcing ``F cos Ωt``, N.
    omega : (float, float)
        Frequency range ``(low, high)``, rad/s, ``0 < low < high``.
    harmonics : int or "auto", default "auto"
        Highest harmonic ``H``; ``"auto"`` chooses it along the branch
        (:mod:`hbmfric.continuation.adaptive`) so that the estimated
        relative truncation error stays below ``harmonic_tolerance``:
        stuck stretches run at ``H = 3``, stick–slip stretches higher (up
        to 63). The branch's coefficients are then padded with zeros to the
        largest ``H`` used and ``Branch.point_harmonics`` gives each point's.
        A fixed ``H`` is faster when you know what the scene needs; its
        branch carries the same per-point estimate
        (``Branch.truncation_error``) and warns when it exceeds
        ``harmonic_tolerance``.
    n_time : int, optional
        AFT samples per period (> 2 H); default depends on the AFT scheme
        (always the default with ``harmonics="auto"``).
    symmetry : bool, optional
        Odd harmonics only; default: whenever the system is symmetric.
    aft : {"auto", "events", "samples"}
        AFT scheme (see :mod:`hbmfric.kernels.aft.schemes`).
    sweep : {"up", "down"}
        Start at the low end and sweep up, or at the high end and sweep down.
    harmonic_tolerance : float, default 1e-4
        With ``harmonics="auto"``: target relative error of the
        first-harmonic amplitude and of half the peak-to-peak value,
        estimated from their first-order change when the basis grows to the
        next level (:mod:`hbmfric.continuation.adaptive`), at the contact
        DOF (and, in the final estimates, the normal DOF of each 2D
        element, :class:`~hbmfric.Contact2D`). Measured against time
        integration the error is typically 0.02-0.2 times it
        (``bench/README.md``); it does not see the AFT's own sampling
        error (Menq: about 1e-5 at the default ``n_time``), and a rigid
        Coulomb contact (error ~ 1/H) drives ``H`` to the top.
        With a fixed ``H``: the threshold of the
        :class:`~hbmfric.errors.AccuracyWarning` on the per-point estimate
        (:mod:`hbmfric.continuation.accuracy`).
    options : ContinuationOptions, optional
    amplitude_scale : float, optional
        Displacement scale of the arc length, m.
    condense : bool or {"modal", "state", "direct"}, optional
        Solve the HBM on the contact DOF only (linear DOFs eliminated per
        harmonic by the dynamic receptance, every DOF recovered at the
        end); several contacts: on their contact coordinates (relative
        displacements; two per 2D element, tangential and normal),
        through the receptance matrix per harmonic
        (:mod:`hbmfric.condensation`). Default: one contact to ground
        on a system with several DOFs, symmetric matrices and a regular
        ``K`` (:func:`~hbmfric.condensation.condensed_by_default`).
        Several contacts (fewer independent contact coordinates than
        DOFs) are condensed by default when their
        receptance comes from modal sums or complex modes; the curve rule
        of the condensed continuation draws the contact DOF recovered from
        the coordinates.
        The receptance comes from modal superposition with all modes when
        the damping is classical; else, for several contacts, from the
        complex modes of the first-order form when they reproduce direct
        solves (:func:`~hbmfric.condensation.state_space_modes`); else from
        a direct solve per harmonic (several contacts are then solved in
        full by default). ``"modal"``, ``"state"`` or ``"direct"`` force
        one. ``False`` solves the full HBM.
    retrace : bool, default True
        When the run ends without covering the range (the step collapsed,
        the step budget ran out, or the path turned back at a fold and
        left through the end it started from), trace again from the other
        end of the range in the opposite direction with the same settings
        and join the two pieces (``Branch.pieces``).
    **option_overrides
        Fields of :class:`ContinuationOptions` to override, among them
        ``curve_tolerance`` (default 1e-4; None or 0: off): the largest
        estimated relative error of the first-harmonic amplitude at the
        contact DOF of the straight lines between consecutive points, which
        the step control keeps (``Branch.curve_errors``; another DOF's lines
        are not bounded: ``Branch.curve_errors_of``, recorded in
        ``info["curve_tolerance"]`` for the warnings of ``Branch.plot``).

    Returns
    -------
    Branch
        Points in path order; ``stop_reason`` says why the run ended and
        ``coverage``, ``gaps`` and ``complete`` which part of the range it
        covers. A run that cannot go on returns the points so far, never
        NaN points.

    Warns
    -----
    CoverageWarning
        When the branch (after the retrace) does not cover the whole range.
    AccuracyWarning
        When a point's estimated truncation error exceeds
        ``harmonic_tolerance``, or the estimated error of the straight
        lines between the points exceeds ``curve_tolerance``; and, for a
        structure reduced by :func:`~hbmfric.craig_bampton`, when the band
        reaches above the pulsation the reduction stands for
        (``valid_below``).
    """
    lo, hi = _omega_range(omega)
    warn_above_cutoff(system, hi, "the FRF band", stacklevel=2)
    if sweep not in ("up", "down"):
        raise ValueError(f"sweep must be 'up' or 'down', got {sweep!r}")
    if not isinstance(retrace, bool | np.bool_):
        raise TypeError(f"retrace must be True or False, got {retrace!r}")
    retrace = bool(retrace)
    if not isinstance(options, ContinuationOptions | None):
        raise TypeError(
            f"options must be a ContinuationOptions, got {type(options).__name__}"
        )
    options = options or ContinuationOptions()
    if option_overrides:
        unknown = set(option_overrides) - {
            f.name for f in dataclasses.fields(ContinuationOptions)
        }
        if unknown:
            raise TypeError(
                f"frf got unexpected keyword argument(s) {sorted(unknown)} "
                "(not fields of ContinuationOptions)"
            )
        options = dataclasses.replace(options, **option_overrides)
    if amplitude_scale is not None:
        amplitude_scale = finite_float(
            "amplitude_scale", amplitude_scale, low=0.0, low_open=True
        )
    if isinstance(harmonics, str) and harmonics != "auto":
        raise ValueError(
            f"harmonics must be a positive integer or 'auto', got {harmonics!r}"
        )

    # the engine and its arguments around the options, called directly on
    # the default path: the warnings' stack levels count the frames from
    # the user's call (frf < _frf_fixed/_frf_auto < ...)
    if isinstance(harmonics, str):
        engine = _frf_auto
        head = (system, force, (lo, hi), n_time, symmetry, aft, sweep)
        tail = (amplitude_scale, condense, retrace)
    else:
        problem = _problem(
            system, force, harmonics, n_time, symmetry, aft, condense, at=(lo, hi)
        )
        _plan_band(problem, hi)
        engine = _frf_fixed
        head = (system, problem, (lo, hi), sweep)
        tail = (amplitude_scale, retrace)
    if options.curve_tolerance and rigid_coulomb(system):
        branch = _coulomb_frf(
            lambda opts: engine(*head, harmonic_tolerance, opts, *tail), options
        )
    else:
        branch = engine(*head, harmonic_tolerance, options, *tail)
    # what Branch.plot compares the curve of a DOF the rule did not watch with
    branch.info["curve_tolerance"] = options.curve_tolerance
    return branch


#: a Coulomb branch traced again without the curve rule is returned instead
#: of the first only when it covers more of the range by this fraction of
#: the range's width (else the two stall at the same seam, and the first
#: one's chords are bounded)
COVERAGE_MARGIN = 1e-3


def _covered(branch: Branch) -> float:
    """Width of the asked range the branch covers, rad/s."""
    low, high = branch.coverage
    gaps = sum(b - a for a, b in branch.gaps)
    return float(high - low - gaps) if branch.omega.size else 0.0


def _coulomb_frf(trace, options: ContinuationOptions) -> Branch:
    """A rigid Coulomb contact's branch with the curve rule, or without it
    where the rule's short steps stall.

    The DLFT residual is discontinuous at some seams (a stick phase born or
    dying at a sample; the paper beam at f_s = 2 N, H = 15, 77.1 Hz, with
    the tip just short of sticking): the rule's short steps land next to
    one and the corrector fails at every step, where the longer steps
    without the rule pass over it. A run whose first sweep does not end at
    the end of the range (also when its retrace from the other end covers
    the rest: a stuck rigid tip is at rest in the drawn plane, so the
    rule's steps there are long and the load DOF's curve coarse) is traced
    again without the rule and that branch returned when it does (its
    chords warned about against ``curve_tolerance``, with a warning that
    says so) or covers more of the range by ``COVERAGE_MARGIN`` of its
    width (the paper beam at defaults: both stall, without the rule further
    on); else the first run's branch and warnings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = trace(options)
    if not branch.stop_reason.startswith("end"):
        with warnings.catch_warnings(record=True) as again:
            warnings.simplefilter("always")
            plain = trace(dataclasses.replace(options, curve_tolerance=None))
        low, high = branch.coverage
        margin = COVERAGE_MARGIN * (high - low)
        if plain.stop_reason.startswith("end") or _covered(plain) > (
            _covered(branch) + margin
        ):
            warnings.warn(
                f"the curve rule's steps stalled ({branch.stop_reason}); the "
                "branch was traced again without the rule (rigid Coulomb "
                "contact): its chords are not bounded by curve_tolerance",
                AccuracyWarning,
                stacklevel=3,
            )
            for w in again:
                warnings.warn(w.message, w.category, stacklevel=3)
            _warn_curve(plain, options.curve_tolerance)
            return plain
    for w in caught:
        warnings.warn(w.message, w.category, stacklevel=3)
    return branch


def _frf_fixed(
    system, problem, omega_range, sweep, tolerance, options, amplitude_scale, retrace
) -> Branch:
    """``frf`` with a fixed ``H`` on the discretisation ``problem``.

    A subharmonic problem (``problem.subharmonic = ν > 1``) is traced over
    ``omega_range`` of the fundamental ``Ω/ν`` (the branch's ``omega``) and
    carries no truncation estimate (its first harmonic is zero)."""
    tolerance = finite_float(
        "harmonic_tolerance", tolerance, low=0.0, low_open=True, high=1.0
    )
    lo, hi = omega_range
    _memory.check_fixed(problem, "frf")
    extra = {"omega_range": [lo, hi], "harmonic_tolerance": tolerance}
    if problem.subharmonic != 1:
        extra["subharmonic"] = problem.subharmonic

    def trace(sweep: str) -> Branch:
        direction = 1 if sweep == "up" else -1
        cont = Continuation(problem, (lo, hi), direction, options, amplitude_scale)
        state, elapsed = cont.run()
        n = problem.n_unknowns
        pts = np.array(state.points).reshape(-1, n + 1)
        info = _describe(
            system,
            problem,
            {**extra, "sweep": sweep, "amplitude_scale": cont.base_scale},
        )
        return _branch(
            system,
            problem,
            state,
            elapsed,
            pts[:, n].copy(),
            problem.full_coefficients(pts),
            info,
            truncation_error=(
                watched_truncation_errors(
                    problem, pts, tolerance, amplitude_scale=cont.base_scale
                )
                if problem.subharmonic == 1
                else None
            ),
            tangents=_branch_tangents(
                problem, pts, state.tangents, cont.base_scale, hi - lo
            ),
        )

    branch = _covering(trace, sweep, retrace)
    _warn_truncation(branch, tolerance)
    _warn_curve(branch, options.curve_tolerance)
    return branch


#: arc-length step (scaled) of the central difference that carries the
#: tangent of a condensed problem over to the recovered DOFs
_RECOVERY_STEP = 1e-6


def _branch_tangents(problem, points, tangents, amplitude_scale, width, n_coef=None):
    """Tangents of :attr:`Branch.tangents` at solutions of ``problem``.

    Parameters
    ----------
    problem : HBMProblem
    points : ndarray, shape (k, n_unknowns + 1)
        ``[X, Ω]`` per point.
    tangents : ndarray, shape (k, n_unknowns + 1)
        The continuation's tangents in physical units, any positive length.
    amplitude_scale, width : float
        Scales of the arc length ``s`` (m, rad/s), see ``Branch.tangents``.
    n_coef : int, optional
        Coefficients per DOF of the branch (>= the problem's; the extra
        harmonics get zeros). Default: the problem's.

    Returns
    -------
    ndarray, shape (k, n_dof * n_coef + 1)
    """
    n = problem.n_unknowns
    t = np.array(tangents, dtype=float).reshape(-1, n + 1)
    norm = np.sqrt(np.sum((t[:, :n] / amplitude_scale) ** 2, axis=1))
    norm = np.hypot(norm, t[:, n] / width)
    t /= np.where(norm > 0.0, norm, 1.0)[:, None]
    k = t.shape[0]
    if getattr(problem, "condensed", False):
        # the eliminated DOFs depend on X and Ω through the contact force:
        # their tangent by a central difference along the branch's tangent
        h = _RECOVERY_STEP
        up = problem.full_coefficients(points + h * t)
        down = problem.full_coefficients(points - h * t)
        d = (up - down) / (2.0 * h)
        if not getattr(problem, "multi", False):
            d = _seam_safe(problem, points, t, up, down, d, h, amplitude_scale)
        if getattr(problem, "multi", False):
            # solved on several contact coordinates: the branch measures
            # its arc length on the contact DOF (Branch._arc_metric, as for
            # one condensed contact), so the tangents are unit there (the
            # chord estimates of Branch.curve_errors multiply them by a
            # length measured on that DOF); normalised on the coordinates
            # they were not
            c = problem.contact_dof
            norm = np.hypot(
                np.sqrt(np.sum(d[:, c, :] ** 2, axis=1)) / amplitude_scale,
                t[:, n] / width,
            )
            norm = np.where(norm > 0.0, norm, 1.0)
            d = d / norm[:, None, None]
            t[:, n] /= norm
    else:
        d = t[:, :n].reshape(k, problem.n_dof, problem.n_coef)
    m = problem.n_coef if n_coef is None else n_coef
    out = np.zeros((k, problem.n_dof * m + 1))
    out[:, :-1].reshape(k, problem.n_dof, m)[:, :, : problem.n_coef] = d
    out[:, -1] = t[:, n]
    return out


#: largest difference (times the amplitude scale) between the recovered
#: contact DOF's tangent and the condensed unknowns' own tangent before a
#: recovery difference counts as having crossed a seam
_SEAM_MISMATCH = 1e-3


def _seam_safe(problem, points, t, up, down, d, h, amplitude_scale):
    """The recovered tangents ``d`` with a one-sided difference where the
    central one crossed a seam of the recovery.

    The recovery (:meth:`CondensedHBMProblem.full_coefficients`) reads the
    contact force of the AFT at the perturbed points, off the branch; a
    DLFT force there can jump (a stick/slip decision flips), and a
    difference across the jump is no tangent: on the paper beam with a
    rigid Coulomb tip at f_s = 2 N, 77.26 Hz, the forward point of a step
    of 1e-6 jumped by 6.6e-6 m (the tip's amplitude 1.8e-9 m), the drawn
    tangent was 3.3 m per unit arc length and ``curve_errors`` read 7.7e4.
    The recovered contact DOF must move as the condensed unknowns do (the
    recovery reproduces them on the branch); a difference whose contact
    DOF misses them by more than ``_SEAM_MISMATCH`` of the scale is
    replaced by the one-sided difference that meets them (the central one
    is kept where neither does)."""
    c = problem.contact_dof
    k = t.shape[0]
    if k == 0:
        # a sweep without a point (no converged start: an undamped stuck
        # resonance at the range's end); the retrace may still cover it
        return d
    own = t[:, :-1].reshape(k, -1)

    def miss(diff, rows):
        return np.max(np.abs(diff[:, c, :] - own[rows]), axis=1) / amplitude_scale

    bad = miss(d, slice(None)) > _SEAM_MISMATCH
    if not np.any(bad):
        return d
    rows = np.flatnonzero(bad)
    centre = problem.full_coefficients(points[rows])
    d = d.copy()
    for diff in ((up[rows] - centre) / h, (centre - down[rows]) / h):
        take = bad[rows] & (miss(diff, rows) <= _SEAM_MISMATCH)
        d[rows[take]] = diff[take]
        bad[rows[take]] = False
    return d


def _warn_truncation(branch: Branch, tolerance: float) -> None:
    """An :class:`~hbmfric.errors.AccuracyWarning` when some point's
    estimated truncation error exceeds ``tolerance``."""
    errors = branch.truncation_error
    if errors is None or errors.size == 0 or not np.max(errors) > tolerance:
        return
    worst = int(np.argmax(errors))
    n_over = int(np.count_nonzero(errors > tolerance))
    limit = branch.info.get("memory_limit")
    if branch.point_harmonics is None:
        advice = "use harmonics='auto'"
    elif limit is not None and branch.harmonics_at(worst) >= limit["harmonics"]:
        advice = (
            f"the harmonic ladder stopped at H={limit['harmonics']}: the next "
            f"level's dense matrices need about "
            f"{_memory.gigabytes(limit['next_level_bytes'])} in all, more than "
            "this machine has available; condense onto the contacts or reduce "
            "the model (hf.craig_bampton) to go higher"
        )
    elif branch.harmonics_at(worst) >= LADDER[-1]:
        advice = (
            f"the top of the harmonic ladder (H={LADDER[-1]}) cannot meet it "
            "(a rigid contact?)"
        )
    else:
        advice = (
            "harmonics='auto' could not solve that point with more harmonics "
            "(Newton failed there)"
        )
    n_none = int(np.count_nonzero(np.isinf(errors)))
    if n_none:
        advice = (
            f"{n_none} of them without an estimate (none is formed below H = 3, "
            f"or its solve failed): nothing vouches for those; {advice}"
        )
    warnings.warn(
        f"estimated truncation error {errors[worst]:.2g} exceeds "
        f"harmonic_tolerance={tolerance:g} at {n_over} of {errors.size} points "
        f"(worst at omega={branch.omega[worst]:.6g} rad/s, H="
        f"{branch.harmonics_at(worst)}); {advice}, or raise harmonics; "
        "per-point estimates in Branch.truncation_error",
        AccuracyWarning,
        stacklevel=4,  # _warn/_covering < _frf_fixed/_frf_auto < frf < user
    )


_UNKNOWN = object()


def _warn_curve(branch: Branch, tolerance: float | None, errors=_UNKNOWN) -> None:
    """An :class:`~hbmfric.errors.AccuracyWarning` when the estimated
    error of the straight lines between the points
    (:attr:`Branch.curve_errors`) exceeds ``curve_tolerance`` (a corner
    taken below the step floor, a seam the rule could not resolve).
    ``errors``: :attr:`Branch.curve_errors` of ``branch`` when the caller
    has just computed them (ndarray of shape (n_points - 1,) or None)."""
    if not tolerance:
        return
    if errors is _UNKNOWN:
        errors = branch.curve_errors
    if errors is None or errors.size == 0 or not np.max(errors) > tolerance:
        return
    worst = int(np.argmax(errors))
    n_over = int(np.count_nonzero(errors > tolerance))
    warnings.warn(
        f"estimated curve error {errors[worst]:.2g} (straight lines between the "
        f"points) exceeds curve_tolerance={tolerance:g} on {n_over} of "
        f"{errors.size} intervals (worst between omega={branch.omega[worst]:.6g} "
        f"and {branch.omega[worst + 1]:.6g} rad/s); per-interval estimates in "
        "Branch.curve_errors",
        AccuracyWarning,
        stacklevel=3,
    )


def _ends(branch: Branch) -> str:
    """Where a piece stopped, for messages."""
    if len(branch) == 0:
        return "(no point)"
    return f"at Ω = {branch.omega[-1]:.6g} rad/s"


def _covering(trace, sweep: str, retrace: bool) -> Branch:
    """The branch of ``trace(sweep)``; if it does not cover the range and
    ``retrace`` is on, joined with ``trace`` of the opposite sweep
    (:func:`hbmfric.results.join_pieces`). Warns when the result is still
    incomplete."""
    branch = cut_at_return(trace(sweep))
    if branch.complete:
        _warn_ends(branch)
        return branch
    if retrace:
        other = "down" if sweep == "up" else "up"
        second = cut_at_return(trace(other))
        meeting = stalled_meeting(branch, second)
        if meeting is not None:
            branch = cut_at_stall(branch, meeting)
            second = cut_at_stall(second, meeting)
        lo, hi = branch.omega_range
        start = hi if other == "down" else lo
        reason = (
            f"{sweep} sweep: {branch.stop_reason} {_ends(branch)}; retraced "
            f"{other} from {start:.6g} rad/s: {second.stop_reason} {_ends(second)}"
        )
        # a singular point only where neither sweep passed: a piece that
        # turned back onto its own path where the other sweep went through
        # had its corrector reverse (cut, but nothing to say)
        singular = [] if meeting is None else [meeting]
        branch = join_pieces(branch, second, reason)
        if singular:
            branch.info["singular_points"] = singular
            drop_folds_at(branch, singular)
        if branch.complete:
            _warn_ends(branch)
            return branch
    _warn_ends(branch, budget=False)
    climb = budget_note(branch)
    lo, hi = branch.omega_range
    covered = ", ".join(
        f"[{branch.omega[p].min():.6g}, {branch.omega[p].max():.6g}]"
        for p in branch.piece_slices()
        if p.stop > p.start
    )
    warnings.warn(
        f"the branch covers only {covered or 'nothing'} of the asked range "
        f"[{lo:.6g}, {hi:.6g}] rad/s (gaps: "
        + ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in branch.gaps)
        + f"); stop: {branch.stop_reason}"
        + (f"; {climb}" if climb else ""),
        CoverageWarning,
        stacklevel=4,  # _warn/_covering < _frf_fixed/_frf_auto < frf < user
    )
    return branch


def _warn_ends(branch: Branch, budget: bool = True) -> None:
    """Warn about singular points the pieces met and (``budget``) about a
    step budget spent by a piece of a branch that otherwise covers its
    range (:mod:`hbmfric.continuation.ends`)."""
    note = singular_note(branch)
    if note:
        warnings.warn(note, SingularPointWarning, stacklevel=5)
    note = budget_note(branch) if budget else None
    if note:
        warnings.warn(
            f"{note}; stop: {branch.stop_reason}", CoverageWarning, stacklevel=5
        )


def _branch(system, problem, state, elapsed, omega, coefficients, info, **extra):
    """The :class:`Branch` of a finished continuation ``state``."""
    info["bridges"] = int(state.n_bridges)
    return Branch(
        omega=omega,
        coefficients=coefficients,
        harmonic_numbers=problem.harmonic_numbers.copy(),
        force=problem.force,
        folds=np.array(state.folds, dtype=np.int64),
        stop_reason=state.stop_reason,
        n_steps=state.n_steps,
        n_rejected=state.n_rejected,
        newton_iterations=state.n_newton,
        elapsed=elapsed,
        info=info,
        dof_names=dict(getattr(system, "dof_names", {})),
        _source={"system": system},
        **extra,
    )


def _assemble_levels(
    system,
    make_problem,
    cont: AdaptiveContinuation,
    state,
    points: list,
    levels: list,
    errors: np.ndarray,
    elapsed: float,
    omega_range,
    sweep: str,
    tolerance: float,
) -> Branch:
    """The :class:`Branch` of an adaptive run: each level's points in the
    leading columns of the top level's layout, its tangents and estimates."""
    top = make_problem(max(levels) if levels else LADDER[0])
    # the harmonics of a level are a prefix of the top level's, in the
    # same column layout: each level fills the leading columns of its
    # points
    coefficients = np.zeros((len(points), top.n_dof, top.n_coef))
    levels_array = np.array(levels, dtype=np.int64)
    omegas = np.empty(len(points))
    tangents = np.zeros((len(points), top.n_dof * top.n_coef + 1))
    scale = cont._cont(int(levels_array[0])).base_scale if levels else 1.0
    for h in np.unique(levels_array):
        idx = np.flatnonzero(levels_array == h)
        p = make_problem(int(h))
        pts = np.array([points[i] for i in idx.tolist()])
        omegas[idx] = pts[:, -1]
        coefficients[idx, :, : p.n_coef] = p.full_coefficients(pts)
        tangents[idx] = _branch_tangents(
            p,
            pts,
            np.array([state.tangents[i] for i in idx.tolist()]),
            scale,
            omega_range[1] - omega_range[0],
            top.n_coef,
        )
    info = _describe(
        system,
        top,
        {
            "omega_range": list(omega_range),
            "sweep": sweep,
            "harmonics": "auto",
            "harmonic_tolerance": tolerance,
            "harmonic_switches": cont.n_switches,
            "harmonic_resolves": cont.n_resolves,
            "harmonic_settled": cont.n_settled,
            "harmonic_calibrations": cont.n_calibrations,
            "amplitude_scale": scale,
        },
    )
    return _branch(
        system,
        top,
        state,
        elapsed,
        omegas,
        coefficients,
        info,
        point_harmonics=levels_array,
        truncation_error=errors,
        tangents=tangents,
    )


def _frf_auto(
    system,
    force,
    omega_range,
    n_time,
    symmetry,
    aft,
    sweep,
    tolerance,
    options,
    amplitude_scale,
    condense,
    retrace,
) -> Branch:
    """``frf`` with ``harmonics="auto"``."""
    if n_time is not None:
        raise ValueError("n_time cannot be given with harmonics='auto'")
    tolerance = finite_float(
        "harmonic_tolerance", tolerance, low=0.0, low_open=True, high=1.0
    )
    # the levels share the system's data (matrices, modes): one full
    # build, validating the input before any work
    base = _problem(
        system,
        force,
        LADDER[START],
        None,
        symmetry,
        aft,
        condense,
        at=omega_range,
        top=LADDER[-1],
    )
    _plan_band(base, omega_range[1])
    problems = {LADDER[START]: base}
    # the rungs whose dense matrices fit in memory (a large model solved in
    # full: the ladder stops below what does not fit, said in the warnings)
    ladder, memory_next = _memory.fitting_ladder(base, LADDER, START)

    def make_problem(h: int) -> HBMProblem:
        if h not in problems:
            problems[h] = base.with_harmonics(h)
        return problems[h]

    # the last traced branch whose curve estimates the join rounds computed
    # (the warning below reads them again when that branch is the result)
    chords_of: dict = {}

    def trace(sweep: str) -> Branch:
        direction = 1 if sweep == "up" else -1
        cont = AdaptiveContinuation(
            make_problem,
            omega_range,
            direction,
            options,
            amplitude_scale,
            tolerance,
            ladder=ladder,
        )
        state, points, levels, elapsed = cont.run()
        # a point solved again one rung higher takes that level's tangent
        # the final estimates watch the normal DOF of a 2D element too
        errors = cont.settle(points, levels, watched_truncation_errors, state.tangents)
        fold_estimates(cont, points, levels, errors, state.tangents)
        args = (system, make_problem, cont, state, points, levels, errors)
        branch = _assemble_levels(*args, elapsed, omega_range, sweep, tolerance)
        curve = options.curve_tolerance
        for _ in range(JOIN_ROUNDS if curve else 0):
            # chords over the tolerance between two levels: their lower end
            # solved again at the higher one (AdaptiveContinuation.join_levels)
            chords = branch.curve_errors
            chords_of.clear()
            chords_of[id(branch)] = (branch, chords)
            if chords is None:
                break
            joins = np.flatnonzero(
                (np.diff(branch.point_harmonics) != 0) & (chords > curve)
            )
            if joins.size == 0 or not cont.join_levels(
                joins, points, levels, errors, watched_truncation_errors, state.tangents
            ):
                break
            fold_estimates(cont, points, levels, errors, state.tangents)
            branch = _assemble_levels(*args, elapsed, omega_range, sweep, tolerance)
        return branch

    branch = _covering(trace, sweep, retrace)
    if memory_next is not None:
        branch.info["memory_limit"] = {
            "harmonics": int(ladder[-1]),
            "next_level_bytes": float(memory_next),
        }
    _warn_truncation(branch, tolerance)
    known = chords_of.get(id(branch))
    if known is not None and known[0] is branch:
        _warn_curve(branch, options.curve_tolerance, known[1])
    else:
        _warn_curve(branch, options.curve_tolerance)
    return branch
