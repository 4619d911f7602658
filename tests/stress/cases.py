"""The numerical stress matrix: case definitions and the checks of one case.

Shared by the tests (``tests/stress/test_stress.py``) and the table in
``bench/README.md`` (``python -m tests.stress.cases`` prints it).

A case is a single-DOF oscillator ``m ẍ + c ẋ + k x + f_c = F cos Ωt`` with
a base of ``m = 1``, ``k = 1``, slip force ``1`` (``F`` is then ``Fex/Fn``),
``kt/k = 3``, damping ratio ``ζ = 0.01`` of the free oscillator, ``H = 15``,
swept up over ``[0.3 ω_free, 1.5 ω_stuck]`` (``[0.3 ω_free, 3 ω_free]``
for the rigid Coulomb contact and the cubic spring, whose ``ratio`` is
``F`` and ``stiffness_ratio`` is ``k3/k``).

``law="tensioner"`` is the belt-tensioner rig (``hf.BeltTensioner()``)
forced at ``ratio`` N over 5-100 Hz, checked against the shooting
reference (tension range and both first harmonics) at every
:data:`TENSIONER_EVERY`-th point and at the peak, to the harmonic
tolerance (``1e-4``) when ``harmonics="auto"``.

``law="beam"`` is the calibrated cantilever beam (24 Hz slipping, 87 Hz
stuck) with a Jenkins tip of ``μ = 1.5`` at ``normal_load`` N; ``ratio`` is
the forcing ``F`` in N (not over the slip force: a Jenkins response with
``F`` and ``μ F_n`` scaled alike is the same response scaled), the range
15–110 Hz; ``stiffness_ratio``, ``zeta`` and the scales do not apply.

Unit scales: ``mass_scale`` multiplies the mass and all stiffnesses and
damping (same frequencies, same forces, so displacements shrink by it);
``freq_scale`` multiplies the stiffnesses by its square and the damping by
it (frequencies scale by it); ``force_scale`` multiplies every force (slip
force, forcing) and the mass, stiffnesses and damping with them (same
frequencies, same displacements: a change of the force unit).

A new law is one more entry in :data:`LAWS`.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import asdict, dataclass, replace
from functools import lru_cache

import numpy as np

import hbmfric as hf
from hbmfric.continuation.adaptive import truncation_estimate
from hbmfric.continuation.palc import MAX_STEPS, MIN_STEP, RANGE_END, RANGE_START
from hbmfric.hbm import HBMProblem

#: the coverage criterion: the branch's lowest and highest Ω equal the ends
#: of the asked range to this relative tolerance
COVERAGE_TOL = 1e-9


@dataclass(frozen=True)
class Case:
    law: str = "jenkins"
    ratio: float = 0.5  # Fex / Fn (friction laws) or F (cubic)
    stiffness_ratio: float = 3.0  # kt / k (friction laws) or k3 / k (cubic)
    zeta: float = 0.01
    mass_scale: float = 1.0
    freq_scale: float = 1.0
    force_scale: float = 1.0
    harmonics: int | str = 15
    sweep: str = "up"
    normal_load: float = 5.0  # beam (N) and contact2d (preload, N) only

    @property
    def name(self) -> str:
        base = Case()
        parts = [self.law]
        for key, val in asdict(self).items():
            if key == "law" or val == getattr(base, key):
                continue
            if key == "normal_load" and self.law not in ("beam", "contact2d"):
                continue
            parts.append(f"{key}={val:g}" if isinstance(val, float) else f"{key}={val}")
        return " ".join(parts)


# -- laws: (case, stiffness unit k, slip force f_s) -> contact law ----------


def _jenkins(c: Case, k: float, fs: float):
    return hf.Jenkins(stiffness=c.stiffness_ratio * k, slip_force=fs)


def _cubic(c: Case, k: float, fs: float):
    # k3 x³ keeps its share of the force under a change of units: the
    # displacements shrink by mass_scale, so k3 scales by mass_scale³ (k
    # carries one power of it)
    return hf.Cubic(c.stiffness_ratio * k * c.mass_scale**2)


def _menq(c: Case, k: float, fs: float):
    return hf.Menq.from_stiffness(stiffness=c.stiffness_ratio * k, slip_force=fs)


def _iwan(c: Case, k: float, fs: float):
    return hf.Iwan.segalman(
        stiffness=c.stiffness_ratio * k, slip_force=fs, chi=-0.5, beta=0.5
    )


def _coulomb(c: Case, k: float, fs: float):
    return hf.Coulomb(slip_force=fs)


def _dahl(c: Case, k: float, fs: float):
    # envelopes ±f_s (μ = 1): loops of small amplitude have the stiffness
    # β f_s, the force saturates at ±f_s
    return hf.ModifiedDahl(
        beta=c.stiffness_ratio * k / fs, upper=(0.0, fs), lower=(0.0, -fs)
    )


def _roughness(c: Case, k: float, fs: float):
    # F_n = f_s / μ with μ = 1, F_lim = 8 F_n: the Hertz–Mindlin factor
    # (1/8)^(1/3) = 1/2 halves the adherent stiffness 2 kt to kt
    law = hf.Jenkins(
        stiffness=2.0 * c.stiffness_ratio * k, friction_coefficient=1.0, normal_load=fs
    )
    return hf.Roughness(law, limit_load=8.0 * fs)


#: law name -> (constructor (case, k, f_s) -> law, range top over ω_free:
#: None = 1.5 ω_stuck)
LAWS = {
    "jenkins": (_jenkins, None),
    "cubic": (_cubic, 3.0),
    "menq": (_menq, None),
    "iwan": (_iwan, None),
    "coulomb": (_coulomb, 3.0),
    "dahl": (_dahl, None),
    "roughness": (_roughness, None),
}

#: friction laws (a slip force, a time-integration reference unless noted)
FRICTION = ("jenkins", "menq", "iwan", "coulomb", "dahl", "roughness")
#: laws the time integration cannot take (rigid contact)
NO_REFERENCE = ("coulomb",)

BEAM_MU = 1.5
BEAM_RANGE = (2.0 * math.pi * 15.0, 2.0 * math.pi * 110.0)


@lru_cache(maxsize=1)
def _beam_calibration():
    return hf.CantileverBeam.calibrate(slip_frequency=24.0, stuck_frequency=87.0)


#: ranges of the multi-contact rows (rad/s)
CHAIN_RANGE = (0.02, 0.6)
ELEMENT_RANGE = (40.0, 250.0)


def _contact_chain(c: Case) -> hf.LinearStructure:
    """``law="contacts"``: four unit masses and springs clamped at one end,
    2 % modal damping, forced at the free end; a Jenkins contact to ground
    at the first mass and one between the last two (stiffness
    ``stiffness_ratio``, slip force 1: ``ratio`` is F over it)."""
    n = 4
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    law = hf.Jenkins(stiffness=c.stiffness_ratio, slip_force=1.0)
    return hf.LinearStructure(
        np.eye(n),
        K,
        modal_damping=0.02,
        load={n - 1: 1.0},
        contacts=[hf.Contact(law, 0), hf.Contact(law, n - 2, n - 1)],
    )


#: range of the ``law="blocks"`` rows (rad/s): the chain's first two
#: modes, stuck (0.18, 0.53 at ``stiffness_ratio = 1``) and slipping
BLOCKS_RANGE = (0.02, 0.8)
#: contacts of the ``law="blocks"`` rows
BLOCKS_CONTACTS = 8


def _contact_row(c: Case) -> hf.LinearStructure:
    """``law="blocks"``: ten unit masses and unit springs clamped at one
    end, 2 % modal damping, forced at the free end, with eight Jenkins
    contacts (slip force 1: ``ratio`` is F over it) to ground on the first
    eight masses, their stiffnesses spread log-evenly over two decades,
    ``stiffness_ratio`` / 10 to ``stiffness_ratio`` × 10. At ``H = 15``
    the condensed problem has 8 × 16 = 128 unknowns, over
    :data:`hbmfric.condensation.REUSE_MIN_UNKNOWNS`: its corrector solves
    by GMRES on the harmonic blocks (stop 26)."""
    n = 10
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    spread = c.stiffness_ratio * np.logspace(-1.0, 1.0, BLOCKS_CONTACTS)
    contacts = [
        hf.Contact(hf.Jenkins(stiffness=float(kt), slip_force=1.0), i)
        for i, kt in enumerate(spread)
    ]
    return hf.LinearStructure(
        np.eye(n), K, modal_damping=0.02, load={n - 1: 1.0}, contacts=contacts
    )


USER_CHAIN_RANGE = (8.0, 25.0)


def _user_chain(c: Case) -> hf.LinearStructure:
    """``law="chain3"``: a new user's chain (three 1 kg masses on 1000 N/m
    springs, clamped at one end, 1 % modal damping, forced at the first
    mass) with a Jenkins contact between the second and third masses,
    stiffness ``stiffness_ratio`` × 1000 N/m, slip force 1 N. With
    ``harmonics="auto"`` at 5 N the run kept the point at the onset of slip
    at H = 5 with an estimated error of 0.031 (Newton needed 37 iterations
    to solve it again higher, more than ``max_newton``)."""
    K = 1000.0 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    law = hf.Jenkins(stiffness=1000.0 * c.stiffness_ratio, slip_force=1.0)
    return hf.LinearStructure(
        np.eye(3),
        K,
        modal_damping=0.01,
        load={0: 1.0},
        contacts=[hf.Contact(law, 1, other=2)],
    )


def _element_rig(c: Case) -> hf.LinearStructure:
    """``law="contact2d"``: the 2-DOF rig of ``tests/test_contact2d.py``
    (x tangential, y normal, each 1 kg on 1e4 N/m, 6 N s/m) with the 2D
    element (kt 3e4, kn 2e4 N/m, μ = 0.5) preloaded at ``normal_load`` N
    (negative: a gap), loads 4 and 12 N per unit forcing on x and y."""
    element = hf.Contact2D(3e4, 2e4, friction_coefficient=0.5, preload=c.normal_load)
    return hf.LinearStructure(
        np.eye(2),
        1e4 * np.eye(2),
        6.0 * np.eye(2),
        load={"x": 4.0, "y": 12.0},
        static_load={"y": c.normal_load},
        contacts=[hf.Contact(element, "x", normal="y")],
        dof_names={"x": 0, "y": 1},
    )


#: the tensioner rows check every this many points of the branch
TENSIONER_EVERY = 8
TENSIONER_RANGE = (2.0 * math.pi * 5.0, 2.0 * math.pi * 100.0)


def build(c: Case):
    """System, forcing amplitude and frequency range of a case."""
    if c.law == "tensioner":
        return hf.BeltTensioner(), c.ratio, TENSIONER_RANGE
    if c.law == "contacts":
        return _contact_chain(c), c.ratio, CHAIN_RANGE
    if c.law == "contact2d":
        return _element_rig(c), c.ratio, ELEMENT_RANGE
    if c.law == "blocks":
        return _contact_row(c), c.ratio, BLOCKS_RANGE
    if c.law == "chain3":
        return _user_chain(c), c.ratio, USER_CHAIN_RANGE
    if c.law == "beam":
        cal = _beam_calibration()
        beam = cal.beam.with_contact(
            cal.contact(normal_load=c.normal_load, friction_coefficient=BEAM_MU)
        )
        return beam, c.ratio, BEAM_RANGE
    m = 1.0 * c.mass_scale * c.force_scale
    k = 1.0 * c.mass_scale * c.force_scale * c.freq_scale**2
    fs = 1.0 * c.force_scale
    damping = 2.0 * c.zeta * math.sqrt(k * m)
    make, top = LAWS[c.law]
    law = make(c, k, fs)
    osc = hf.Oscillator(m, damping, k, law)
    w_free = math.sqrt(k / m)
    if top is None:
        w_high = 1.5 * math.sqrt((k + law.stuck_stiffness) / m)
    else:
        w_high = top * w_free
    force = c.ratio * (fs if c.law != "cubic" else c.force_scale)
    return osc, force, (0.3 * w_free, w_high)


def response_dof(system) -> int:
    """The DOF the checks look at: the contact DOF."""
    return int(getattr(system, "contact_dof", 0))


def covered(branch: hf.Branch, omega: tuple[float, float]) -> bool:
    """The branch reaches both ends of the asked range (relative
    :data:`COVERAGE_TOL`), whatever its stop reason says."""
    if not len(branch):
        return False
    lo, hi = omega
    return bool(
        abs(branch.omega.min() - lo) <= COVERAGE_TOL * lo
        and abs(branch.omega.max() - hi) <= COVERAGE_TOL * hi
    )


def single_valued(branch: hf.Branch, i: int) -> bool:
    """True if no part of the branch other than the two segments at point
    ``i`` passes over its Ω: there the periodic solution is unique, and time
    integration started on it cannot settle on another one."""
    w = branch.omega
    lo = np.minimum(w[:-1], w[1:])
    hi = np.maximum(w[:-1], w[1:])
    return int(np.count_nonzero((lo <= w[i]) & (w[i] <= hi))) <= 2


def spot_indices(branch: hf.Branch, dof: int = 0) -> list[int]:
    """Three points on the stable part of the branch: first, peak, last; on
    a branch with folds (where a stretch is unstable and time integration
    would leave it), the first point and two before the first fold, each
    moved back to where the branch is single-valued in Ω (a curve-resolved
    branch also shows the small superharmonic loops below the main
    resonance, whose stretches can be unstable: without a stability
    analysis only a unique solution is a fair check)."""
    n = len(branch)
    if branch.folds.size:
        f = int(branch.folds[0])
        picks = set()
        for i in (0, max(0, f // 2), max(0, f - 3)):
            while i > 0 and not single_valued(branch, i):
                i -= 1
            picks.add(i)
        return sorted(picks)
    amp = branch.amplitude(harmonic=1, dof=dof)
    return sorted({0, int(np.argmax(amp)), n - 1})


#: period budgets of the time-integration reference, tried in turn until it
#: converges (ζ = 1e-4 needs tens of thousands of periods to settle the
#: free ringing a truncated HBM start leaves; far above the free frequency,
#: over a hundred thousand, which the matrix does not afford: such a spot
#: check stays inconclusive and the case is listed as a miss)
REFERENCE_PERIODS = (3000, 30000, 100000)


def spot_check(
    system, force: float, branch: hf.Branch, i: int
) -> tuple[float, str, int]:
    """:func:`reference_check` of branch point ``i``."""
    return reference_check(system, force, branch.point(i))


def reference_check(
    system, force: float, sol: hf.PeriodicSolution
) -> tuple[float, str, int]:
    """Relative first-harmonic difference (at the contact DOF) between a
    periodic solution and the time-integration steady state started on it
    (1024 steps per period), ``""`` and the period budget used — or ``inf``
    and why the reference does not count: a reference that did not converge
    (kernel status, or the period-to-period change still above ``tol``
    after the last budget of :data:`REFERENCE_PERIODS`) never passes."""
    hn = sol.harmonic_numbers
    X = sol.coefficients  # (n_dof, n_coef)
    cols = np.cumsum([0] + [1 if k == 0 else 2 for k in hn[:-1]])
    x0 = sum(X[:, c] for k, c in zip(hn, cols, strict=True))
    v0 = sum(
        sol.omega * k * X[:, c + 1] for k, c in zip(hn, cols, strict=True) if k > 0
    )
    for periods in REFERENCE_PERIODS:
        with warnings.catch_warnings():
            # a budget too short is tried again with a longer one, below
            warnings.simplefilter("ignore", hf.ConvergenceWarning)
            ref = hf.validation.steady_state(
                system,
                force,
                sol.omega,
                steps_per_period=1024,
                initial_state=(x0, v0),
                tol=1e-8,
                max_periods=periods,
            )
        if ref.status != 0:
            return math.inf, f"reference failed (status {ref.status})", periods
        if ref.converged:
            break
    else:
        return (
            math.inf,
            f"reference not converged in {periods} periods (change {ref.change:.1e})",
            periods,
        )
    dof = response_dof(system)
    a = sol.amplitude(harmonic=1, dof=dof)
    return abs(ref.amplitude(harmonic=1, dof=dof) - a) / a, "", periods


def run_case(c: Case, spot: bool = True) -> dict:
    """Trace the branch of a case and check it; returns the findings."""
    system, force, omega = build(c)
    dof = response_dof(system)
    options = hf.ContinuationOptions()
    t = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        b = hf.frf(system, force, omega, c.harmonics, sweep=c.sweep, options=options)
    elapsed = time.perf_counter() - t
    out = {
        "case": c.name,
        "law": c.law,
        "points": len(b),
        "steps": b.n_steps,
        "rejected": b.n_rejected,
        "newton": b.newton_iterations,
        "time_s": elapsed,
        "stop_reason": b.stop_reason,
        "range_end": b.stop_reason == RANGE_END,
        # both: the Ω range of the branch reaches the ends of the asked
        # range, and no gap between separately traced pieces
        "covered": covered(b, omega) and bool(getattr(b, "complete", True)),
        "coverage_warning": any(
            issubclass(w.category, hf.CoverageWarning) for w in caught
        ),
        "finite": bool(
            np.all(np.isfinite(b.coefficients)) and np.all(np.isfinite(b.omega))
        ),
        "zero_force": force == 0.0,
        # harmonics="auto" left a point over its tolerance below the top of
        # the ladder (it could have solved it with more harmonics)
        "auto_gave_up": _auto_gave_up(b, c),
    }
    if force == 0.0:
        # the zero response, exactly, at once; a preloaded system (the
        # tensioner) rests at its static solution: no harmonic above 0
        static = getattr(system, "static_solution", None)
        loaded = getattr(system, "static_load", None)
        if static is not None and b.harmonic_numbers[0] == 0 and len(b):
            mean = b.coefficients[:, :, 0]
            out["exact_zero"] = bool(
                np.all(b.coefficients[:, :, 1:] == 0.0)
                and np.allclose(mean, static()[None, :], rtol=1e-12, atol=0.0)
            )
        elif loaded is not None and b.harmonic_numbers[0] == 0 and len(b):
            # a static load: one static state along the whole branch (the
            # contact2d rows check it against the closed form in
            # tests/test_contact_edges.py)
            mean = b.coefficients[:, :, 0]
            out["exact_zero"] = bool(
                np.all(b.coefficients[:, :, 1:] == 0.0) and np.all(mean == mean[0])
            )
        else:
            out["exact_zero"] = bool(np.all(b.coefficients == 0.0))
    # successive points close in the scaled norm of the continuation
    h_scale = c.harmonics if isinstance(c.harmonics, int) else 15
    problem = HBMProblem(system, force, h_scale)
    scale = problem.amplitude_scale(omega)
    # the continuation's scale follows a tenth of the amplitude once that
    # exceeds 1.5 base scales (Continuation._follow_amplitude): divide by a
    # lower bound of it
    coef = b.coefficients[:, dof]
    amp = np.abs(coef).max(axis=1) if len(b) else np.zeros(0)
    local = np.maximum(scale, 0.1 * np.minimum(amp[1:], amp[:-1]) / 1.5)
    dX = np.abs(np.diff(coef, axis=0)) / local[:, None]
    dW = np.abs(np.diff(b.omega)) / (omega[1] - omega[0])
    gaps = np.maximum(dW, dX.max(axis=1)) if len(b) > 1 else np.zeros(0)
    # no step between two separately traced pieces
    if getattr(b, "pieces", None) is not None and gaps.size:
        starts = b.pieces[(b.pieces > 0) & (b.pieces < len(b))]
        gaps[starts - 1] = 0.0
    out["max_gap"] = float(gaps.max()) if gaps.size else 0.0
    out["gap_bound"] = 3.0 * options.max_step
    out["spot"] = []
    out["spot_skipped"] = ""
    if c.law == "tensioner":
        if force != 0.0 and spot and len(b):
            out["spot"] = tensioner_checks(system, force, b, c)
    elif c.law in NO_REFERENCE:
        out["spot_skipped"] = "no time-integration reference for a rigid contact"
    elif force == 0.0:
        out["spot_skipped"] = "zero forcing (checked exactly instead)"
    elif spot and len(b):
        for i in spot_indices(b, dof):
            # a difference the truncation explains is not a branch jump:
            # allow twice the relative amplitude of the highest harmonic
            X = b.coefficients[i]
            top = truncation_estimate(b.harmonic_numbers, X)
            h = b.harmonics_at(i)
            tol = 0.1 if h < 3 else max(5e-3, 2.0 * top)
            # or the branch's own truncation estimate at that point, which
            # warned already (several contacts at H = 3-15: 0.24 estimated
            # where the reference and H = 63 differ from H = 15 by 0.053)
            if b.truncation_error is not None:
                tol = max(tol, float(b.truncation_error[i]))
            err, why, periods = spot_check(system, force, b, i)
            out["spot"].append((float(b.omega[i]), err, tol, why, periods))
    reasons = [p["stop_reason"] for p in b.info.get("pieces", [])] or [b.stop_reason]
    # stop 28: a piece that turned back onto its own path, or stalled where
    # the other sweep stalled, is cut there (hbmfric.continuation.ends)
    cut = ("turned back onto its own path", "stalled at")
    out["known_stop"] = all(
        r in (RANGE_END, RANGE_START, MAX_STEPS, MIN_STEP) or r.startswith(cut)
        for r in reasons
    )
    return out


def tensioner_checks(system, force: float, branch: hf.Branch, c: Case) -> list:
    """The tensioner rows' check: the tension range and both first
    harmonics at every :data:`TENSIONER_EVERY`-th point and at the peak of
    the tension against the shooting reference started on the branch,
    to ``1e-4`` (the default harmonic tolerance) when ``harmonics="auto"``,
    else ``max(5e-3, 2 x`` the relative top harmonic``)``. Returns the
    ``(Ω, error, tolerance, why, 0)`` records of :func:`failures`."""
    from hbmfric.systems.tensioner_response import branch_tension_range
    from hbmfric.systems.tensioner_shooting import (
        shooting_steady_state,
        state_at_zero,
    )

    tension = branch_tension_range(system, branch)
    index = set(range(0, len(branch), TENSIONER_EVERY))
    index.add(int(np.argmax(tension)))
    records = []
    for i in sorted(index):
        w = float(branch.omega[i])
        start = state_at_zero(
            system, branch.harmonic_numbers, branch.coefficients[i], w
        )
        ref = shooting_steady_state(system, force, w / (2.0 * math.pi), start)
        if not ref.converged:
            records.append((w, math.inf, 0.0, "shooting reference not converged", 0))
            continue
        got = np.array(
            [
                tension[i],
                branch.amplitude(1, "shaker")[i],
                branch.amplitude(1, "pulley")[i],
            ]
        )
        want = np.array([ref.tension_range, *ref.first_harmonic])
        err = float(np.max(np.abs(got / want - 1.0)))
        if c.harmonics == "auto":
            tol = 1e-4
        else:
            top = truncation_estimate(branch.harmonic_numbers, branch.coefficients[i])
            tol = max(5e-3, 2.0 * top)
        records.append((w, err, tol, "", 0))
    return records


def _auto_gave_up(branch: hf.Branch, c: Case) -> str:
    """For ``harmonics="auto"``: a description of the worst point whose
    estimated truncation error exceeds the tolerance although its ``H`` is
    below the top of the harmonic ladder, or ``""``."""
    from hbmfric.continuation.adaptive import LADDER

    errors = branch.truncation_error
    if c.harmonics != "auto" or errors is None or branch.point_harmonics is None:
        return ""
    tol = float(branch.info.get("harmonic_tolerance", 1e-4))
    bad = (errors > tol) & (branch.point_harmonics < LADDER[-1])
    if not np.any(bad):
        return ""
    i = int(np.flatnonzero(bad)[np.argmax(errors[bad])])
    return (
        f"auto left the point at Ω = {branch.omega[i]:.6g} at H = "
        f"{branch.point_harmonics[i]} with estimate {errors[i]:.2g}"
    )


def failures(out: dict) -> list[str]:
    """What is wrong with a case's findings (empty when it passed)."""
    bad = []
    if out.get("auto_gave_up"):
        bad.append(out["auto_gave_up"])
    if not out["finite"]:
        bad.append("non-finite values")
    if not out["covered"]:
        bad.append(
            f"range not covered (stopped: {out['stop_reason']}"
            + (", with CoverageWarning)" if out["coverage_warning"] else ")")
        )
    if out.get("zero_force") and not out.get("exact_zero"):
        bad.append("zero forcing gave a non-zero response")
    if out["max_gap"] > out["gap_bound"]:
        bad.append(f"gap {out['max_gap']:.3f} > {out['gap_bound']:.3f} (branch jump?)")
    for w, err, tol, why, _ in out["spot"]:
        if why:
            bad.append(f"time integration at Ω = {w:.4g}: {why}")
        elif not err <= tol:
            bad.append(f"time integration differs by {err:.1e} at Ω = {w:.4g}")
    return bad


BASE = Case()


def _jenkins_cubic() -> list[Case]:
    """The original matrix: Jenkins and Cubic SDOF (134 cases)."""
    cases = []
    for ratio in (1e-4, 1e-2, 0.5, 10.0, 1e3):
        for kt in (1e-2, 1.0, 1e2, 1e4):
            for zeta in (1e-4, 1e-2, 0.2):
                cases.append(replace(BASE, ratio=ratio, stiffness_ratio=kt, zeta=zeta))
    for ms in (1e-3, 1e3):
        cases.append(replace(BASE, mass_scale=ms))
    for fs in (1e-2, 1e4):
        cases.append(replace(BASE, freq_scale=fs))
    for ms in (1e-3, 1e3):
        for fs in (1e-2, 1e4):
            cases.append(replace(BASE, mass_scale=ms, freq_scale=fs))
    for h in (1, 3, 31, 63):
        cases.append(replace(BASE, harmonics=h))
    downs = [
        replace(c, sweep="down")
        for c in cases
        if c.zeta != 1e-4 and c.ratio in (1e-2, 0.5, 10.0)
    ]
    cases += downs
    for f in (1e-4, 1e-2, 1.0, 10.0):
        for k3 in (1e-2, 1.0, 1e2):
            for zeta in (1e-2, 0.2):
                cases.append(Case(law="cubic", ratio=f, stiffness_ratio=k3, zeta=zeta))
    cases.append(Case(law="cubic", ratio=1.0, stiffness_ratio=1.0, sweep="down"))
    cases.append(Case(law="cubic", ratio=1e-2, stiffness_ratio=1.0, zeta=1e-4))
    return cases


def _other_law(law: str) -> list[Case]:
    """A reasoned subset for one more friction law (about 30 cases): the
    force ratio (stuck, microslip, gross slip, far above) crossed with the
    stiffness ratio at the base damping; the damping extremes at the two
    middle force ratios; both sweeps; H = 3 and 63."""
    base = Case(law=law)
    kts = (3.0,) if law == "coulomb" else (1e-2, 1.0, 1e2, 1e4)
    mid_kts = (3.0,) if law == "coulomb" else (1.0, 1e2)
    cases = []
    for ratio in (1e-2, 0.5, 10.0, 1e3):
        for kt in kts:
            cases.append(replace(base, ratio=ratio, stiffness_ratio=kt))
    if law == "coulomb":  # around the stop regime (F ≈ f_s)
        cases += [replace(base, ratio=r) for r in (0.9, 1.1, 2.0)]
    for ratio in (0.5, 10.0):
        for kt in mid_kts:
            for zeta in (1e-4, 0.2):
                cases.append(replace(base, ratio=ratio, stiffness_ratio=kt, zeta=zeta))
            cases.append(replace(base, ratio=ratio, stiffness_ratio=kt, sweep="down"))
    cases += [replace(base, harmonics=3), replace(base, harmonics=63)]
    return cases


def _auto() -> list[Case]:
    """``harmonics="auto"`` (the default of ``hf.frf``), both sweeps."""
    cases = []
    for law in FRICTION:
        for ratio in (0.5, 10.0):
            cases.append(Case(law=law, ratio=ratio, harmonics="auto"))
        cases.append(Case(law=law, harmonics="auto", sweep="down"))
    return cases


def _extremes() -> list[Case]:
    """Zero forcing, unit scales 1e±15 (mass/stiffness and force units) and
    forces 1e12 × slip force, for every law."""
    cases = []
    for law in (*FRICTION, "cubic"):
        base = Case(law=law)
        cases.append(replace(base, ratio=0.0))
        cases.append(replace(base, ratio=0.0, sweep="down"))
        for s in (1e-15, 1e15):
            cases.append(replace(base, mass_scale=s))
            cases.append(replace(base, force_scale=s))
        if law != "cubic":
            cases.append(replace(base, ratio=1e12))
    return cases


def _beam() -> list[Case]:
    """The calibrated beam, Jenkins tip, F_n = 5, 1, 0.5 N (slip force 7.5,
    1.5, 0.75 N), forcing 0.2, 2 and 20 N."""
    cases = []
    for fn in (5.0, 1.0, 0.5):
        for ratio in (0.2, 2.0, 20.0):
            for sweep in ("up", "down"):
                cases.append(Case(law="beam", normal_load=fn, ratio=ratio, sweep=sweep))
        cases.append(Case(law="beam", normal_load=fn, ratio=2.0, harmonics="auto"))
    cases.append(Case(law="beam", ratio=0.0))
    return cases


def _tensioner() -> list[Case]:
    """The belt-tensioner rig at defaults (``harmonics="auto"``), forcing
    2, 5, 20 and 50 N (the paper's Fig. 5 amplitudes), both sweeps at 5 N
    (where the estimate once carried a ratio across separate stretches of
    one level and let 2.5e-4 pass near 8.4 Hz), and zero forcing."""
    cases = [
        Case(law="tensioner", ratio=f, harmonics="auto") for f in (2.0, 5.0, 20.0, 50.0)
    ]
    cases.append(Case(law="tensioner", ratio=5.0, harmonics="auto", sweep="down"))
    cases.append(Case(law="tensioner", ratio=0.0, harmonics="auto"))
    return cases


#: the harmonic-block GMRES rows (stop 26): eight contacts, 128 condensed
#: unknowns; stuck and slipping, stiff and soft contacts, both sweeps
BLOCKS_ROWS = [
    Case(law="blocks", ratio=0.5, stiffness_ratio=1.0),
    Case(law="blocks", ratio=5.0, stiffness_ratio=1.0),
    Case(law="blocks", ratio=0.5, stiffness_ratio=1e2),
    Case(law="blocks", ratio=0.5, stiffness_ratio=1e-2, sweep="down"),
]


def _several_contacts() -> list[Case]:
    """Several contacts (a chain with a contact to ground and a relative
    one) and the 2D element (preloaded, and open at rest): stuck, slipping
    and far above the slip force, stiff contacts, zero forcing, both
    sweeps, H = 3 and ``"auto"``."""
    cases = []
    for ratio in (0.0, 1e-2, 0.5, 10.0, 1e3):
        for kt in (1e-2, 1.0, 1e2):
            cases.append(Case(law="contacts", ratio=ratio, stiffness_ratio=kt))
    cases.append(Case(law="contacts", ratio=0.5, sweep="down"))
    cases.append(Case(law="contacts", ratio=0.5, harmonics=3))
    cases.append(Case(law="contacts", ratio=0.5, harmonics="auto"))
    cases += BLOCKS_ROWS
    for preload in (10.0, -2.0):
        for ratio in (0.0, 0.01, 0.3, 1.0):
            cases.append(
                Case(law="contact2d", ratio=ratio, normal_load=preload, harmonics=8)
            )
    cases.append(Case(law="contact2d", ratio=1.0, harmonics=8, sweep="down"))
    for sweep in ("up", "down"):
        cases.append(
            Case(
                law="chain3",
                ratio=5.0,
                stiffness_ratio=2.0,
                harmonics="auto",
                sweep=sweep,
            )
        )
    return cases


def matrix() -> list[Case]:
    """The full stress matrix."""
    cases = _jenkins_cubic()
    for law in ("menq", "iwan", "coulomb", "dahl", "roughness"):
        cases += _other_law(law)
    cases += _auto() + _extremes() + _beam() + _tensioner() + _several_contacts()
    seen = set()
    unique = []
    for c in cases:
        if c not in seen:
            seen.add(c)
            unique.append(c)
    return unique


#: a fast subset for the default test run: the extremes of each axis
FAST = [
    Case(ratio=1e-4),
    Case(ratio=1e3),
    Case(stiffness_ratio=1e4, zeta=0.2),
    Case(zeta=1e-4),
    Case(mass_scale=1e3, freq_scale=1e4),
    Case(harmonics=63, sweep="down"),
    Case(law="cubic", ratio=1.0, stiffness_ratio=1.0),
    # former failures: stick arcs of 1e-4 of the amplitude, a resonance
    # that friction cannot bound (the scale follows the amplitude), and a
    # stuck resonance that starts to slip at a right-angled corner
    Case(ratio=10.0, stiffness_ratio=1e4, zeta=1e-4),
    Case(ratio=1e-2, stiffness_ratio=1.0, zeta=1e-4),
    # one case per further law, the beam, harmonics="auto", zero forcing
    Case(law="menq", ratio=10.0),
    Case(law="iwan", ratio=0.5, sweep="down"),
    Case(law="coulomb", ratio=2.0),
    Case(law="dahl", ratio=10.0),
    Case(law="roughness", ratio=0.5, stiffness_ratio=1e2),
    Case(law="beam", normal_load=1.0, ratio=2.0),
    Case(law="jenkins", ratio=10.0, harmonics="auto"),
    Case(law="iwan", ratio=0.0),
]


# -- periodic_solution maps -------------------------------------------------

#: (law, kt/k, force) cases whose branch is compared with periodic_solution
#: at :data:`PSOL_POINTS` frequencies
PSOL_CASES = [
    Case(ratio=0.5),
    Case(ratio=10.0, stiffness_ratio=1e2),
    Case(ratio=1e-2, stiffness_ratio=1.0, zeta=1e-4),
    Case(law="menq", ratio=0.5),
    Case(law="iwan", ratio=10.0),
    Case(law="coulomb", ratio=2.0),
    Case(law="dahl", ratio=0.5),
    Case(law="roughness", ratio=10.0, stiffness_ratio=1e2),
    Case(law="beam", normal_load=0.5, ratio=2.0),
    # harder: folds (several values per Ω), the stop regime of rigid
    # Coulomb, a stiff light-damped stick–slip branch, a stiff Dahl loop
    Case(law="cubic", ratio=1.0, stiffness_ratio=1.0),
    Case(law="coulomb", ratio=1.4, zeta=0.08),
    Case(law="coulomb", ratio=1.0 + 1e-10, sweep="down"),
    Case(ratio=10.0, stiffness_ratio=1e4, zeta=1e-4),
    Case(law="dahl", ratio=1.0, stiffness_ratio=1e3, zeta=1e-3),
]
PSOL_POINTS = 15
#: a converged periodic_solution further than this (relative first-harmonic
#: amplitude) from every branch value at its Ω is a wrong answer
PSOL_TOL = 1e-6
#: ... and more than this times the continuation's displacement scale in
#: absolute terms: ten times Newton's ``tol_step`` (1e-9 of that scale), so
#: two solutions the corrector cannot tell apart are not two answers
PSOL_ABS = 1e-8


def branch_values(system, force, branch: hf.Branch, w: float, harmonics) -> list:
    """First-harmonic amplitudes (contact DOF) of every branch point at Ω = w,
    one per segment of the branch that crosses w, each with its tolerance:
    Newton started on the linear interpolation of the segment's ends (the
    exact branch value, accepted when within the segment's own amplitude
    change of the interpolation), otherwise the interpolation itself with
    that change as tolerance."""
    dof = response_dof(system)
    W = branch.omega
    amp = branch.amplitude(harmonic=1, dof=dof)
    out = []
    for i in range(len(W) - 1):
        if not (W[i] - w) * (W[i + 1] - w) <= 0.0 or W[i] == W[i + 1]:
            continue
        t = (w - W[i]) / (W[i + 1] - W[i])
        a_lin = (1 - t) * amp[i] + t * amp[i + 1]
        spread = abs(amp[i + 1] - amp[i]) + PSOL_TOL * abs(a_lin)
        guess = replace(
            branch.point(i),
            omega=w,
            coefficients=(1 - t) * branch.coefficients[i]
            + t * branch.coefficients[i + 1],
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sol = hf.periodic_solution(system, force, w, harmonics, initial_guess=guess)
        a = sol.amplitude(harmonic=1, dof=dof)
        if sol.converged and abs(a - a_lin) <= spread:
            out.append((a, PSOL_TOL * abs(a)))
        else:
            out.append((a_lin, spread))
    return out


def psol_floor(system, force, omega) -> float:
    """Absolute amplitude difference below which two solutions are the same:
    :data:`PSOL_ABS` of the continuation's displacement scale (at
    ``F = f_s (1 + 1e-10)`` rigid Coulomb moves by 1e-11 m, which Newton's
    tolerances do not resolve)."""
    return PSOL_ABS * HBMProblem(system, force, 15).amplitude_scale(omega)


def coexists(system, force, sol: hf.PeriodicSolution, law: str) -> bool:
    """A converged solution off the traced branch is another steady state
    when time integration started on it stays on it (a stable solution on
    a part of the solution set the branch did not trace: the upper stretch
    of a fold that leaves the range, an isola)."""
    if law in NO_REFERENCE or not sol.amplitude(harmonic=1):
        return False
    X = sol.coefficients
    top = truncation_estimate(sol.harmonic_numbers, X)
    err, why, _ = reference_check(system, force, sol)
    return not why and err <= max(5e-3, 2.0 * top)


def psol_map(c: Case, n: int = PSOL_POINTS) -> dict:
    """``hf.periodic_solution`` (default start) at ``n`` frequencies inside
    the branch's covered range against the branch; every point is ``ok``
    (converged onto a branch value), ``warned`` (not converged, or off
    the branch, with a ConvergenceWarning), ``other`` (converged off the
    branch onto another steady state that time integration confirms,
    :func:`coexists`), ``wrong`` (converged, off every branch value, not
    confirmed, no warning) or ``silent`` (not converged, no warning)."""
    system, force, omega = build(c)
    dof = response_dof(system)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        b = hf.frf(system, force, omega, c.harmonics, sweep=c.sweep)
    lo, hi = float(b.omega.min()), float(b.omega.max())
    floor = psol_floor(system, force, omega)
    points = []
    for j in range(n):
        w = lo + (hi - lo) * (j + 0.5) / n
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            sol = hf.periodic_solution(system, force, w, c.harmonics)
        warned = any(issubclass(x.category, hf.ConvergenceWarning) for x in caught)
        a = sol.amplitude(harmonic=1, dof=dof)
        values = branch_values(system, force, b, w, c.harmonics)
        off = min((abs(a - v) / max(tol, floor) for v, tol in values), default=math.inf)
        on_branch = bool(np.isfinite(a)) and off <= 1.0
        if sol.converged and on_branch:
            verdict = "ok"
        elif warned:
            verdict = "warned"
        elif sol.converged and coexists(system, force, sol, c.law):
            verdict = "other"
        elif sol.converged:
            verdict = "wrong"
        else:
            verdict = "silent"
        rel = min((abs(a - v) / abs(v) for v, _ in values if v), default=math.inf)
        points.append((w, verdict, rel, len(values)))
    return {"case": c.name, "points": points}


def psol_failures(out: dict) -> list[str]:
    """The wrong and the silent points of a map."""
    return [
        f"{verdict} at Ω = {w:.4g} (rel. off {rel:.1e}, {nv} branch values)"
        for w, verdict, rel, nv in out["points"]
        if verdict in ("wrong", "silent")
    ]


# -- tables -----------------------------------------------------------------


def table(rows: list[dict]) -> str:
    """Markdown table of the findings."""
    lines = [
        "| case | covered | stop | points | steps | rejected | Newton evals "
        "| time (ms) | spot-check max rel. diff | problems |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        spot = max((s[1] for s in r["spot"]), default=math.nan)
        lines.append(
            f"| {r['case']} | {'yes' if r['covered'] else 'no'} | "
            f"{r['stop_reason']} | {r['points']} | "
            f"{r['steps']} | {r['rejected']} | {r['newton']} | "
            f"{1e3 * r['time_s']:.1f} | "
            f"{spot:.1e} | {'; '.join(failures(r)) or '—'} |"
        )
    return "\n".join(lines)


def law_summary(rows: list[dict]) -> str:
    """Pass/fail counts per law (markdown)."""
    lines = [
        "| law | cases | pass | fail | range covered | spot checks | "
        f"references needing > {REFERENCE_PERIODS[0]} periods | "
        "references never converged |",
        "|---|---|---|---|---|---|---|---|",
    ]
    laws = list(dict.fromkeys(r["law"] for r in rows))
    for law in [*laws, None]:
        sel = [r for r in rows if r["law"] == law] if law else rows
        n = len(sel)
        ok = sum(1 for r in sel if not failures(r))
        cov = sum(1 for r in sel if r["covered"])
        spots = sum(len(r["spot"]) for r in sel)
        slow = sum(1 for r in sel for s in r["spot"] if s[4] > REFERENCE_PERIODS[0])
        bad_ref = sum(1 for r in sel for s in r["spot"] if s[3])
        row = [n, ok, n - ok, cov, spots, slow, bad_ref]
        name = law or "**all**"
        lines.append(f"| {name} | " + " | ".join(str(v) for v in row) + " |")
    return "\n".join(lines)


def psol_table(maps: list[dict]) -> str:
    """Counts per verdict of the periodic_solution maps (markdown)."""
    lines = [
        "| case | Ω points | ok | warned | other | wrong | silent | problems |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for m in maps:
        v = [p[1] for p in m["points"]]
        lines.append(
            f"| {m['case']} | {len(v)} | {v.count('ok')} | {v.count('warned')} | "
            f"{v.count('other')} | "
            f"{v.count('wrong')} | {v.count('silent')} | "
            f"{'; '.join(psol_failures(m)) or '—'} |"
        )
    return "\n".join(lines)


def all_cases() -> list[Case]:
    """The full matrix and the ``FAST`` cases outside it."""
    cases = matrix()
    return cases + [c for c in FAST if c not in cases]


def main() -> None:
    rows = []
    t0 = time.perf_counter()
    for c in all_cases():
        out = run_case(c)
        rows.append(out)
        print(c.name, "OK" if not failures(out) else failures(out), flush=True)
    n_ok = sum(1 for r in rows if not failures(r))
    n_cov = sum(1 for r in rows if r["covered"])
    print(
        f"\n{n_ok}/{len(rows)} cases pass, {n_cov}/{len(rows)} cover the range "
        f"({time.perf_counter() - t0:.0f} s)\n"
    )
    print(law_summary(rows))
    print("\nMisses:\n")
    for r in rows:
        if failures(r):
            print(f"- {r['case']}: {'; '.join(failures(r))}")
    maps = []
    for c in PSOL_CASES:
        m = psol_map(c)
        maps.append(m)
        print(c.name, psol_failures(m) or "OK", flush=True)
    print("\nperiodic_solution maps:\n")
    print(psol_table(maps))
    print("\nFull table:\n")
    print(table(rows))


if __name__ == "__main__":
    main()
