"""The numerical stress matrix: case definitions and the checks of one case.

Shared by the tests (``tests/stress/test_stress.py``) and the table in
``bench/README.md`` (``python -m tests.stress.cases`` prints it).

A case is a single-DOF oscillator ``m ẍ + c ẋ + k x + f_c = F cos Ωt`` with
a base of ``m = 1``, ``k = 1``, slip force ``1`` (``F`` is then ``Fex/Fn``),
``kt/k = 3``, damping ratio ``ζ = 0.01`` of the free oscillator, ``H = 15``,
swept up over ``[0.3 ω_free, 1.5 ω_stuck]``. Unit scales: ``mass_scale``
multiplies the mass and all stiffnesses and damping (same frequencies, same
forces, so displacements shrink by it); ``freq_scale`` multiplies the
stiffnesses by its square and the damping by it (frequencies scale by it).
A new law is one more entry in :data:`LAWS`.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, replace

import numpy as np

import hbmfric as hf
from hbmfric.continuation.adaptive import truncation_estimate
from hbmfric.continuation.palc import MAX_STEPS, MIN_STEP, RANGE_END, RANGE_START
from hbmfric.hbm import HBMProblem


@dataclass(frozen=True)
class Case:
    law: str = "jenkins"
    ratio: float = 0.5  # Fex / Fn (Jenkins) or F (cubic)
    stiffness_ratio: float = 3.0  # kt / k (Jenkins) or k3 / k (cubic)
    zeta: float = 0.01
    mass_scale: float = 1.0
    freq_scale: float = 1.0
    harmonics: int = 15
    sweep: str = "up"

    @property
    def name(self) -> str:
        base = Case()
        parts = [self.law]
        for key, val in asdict(self).items():
            if key != "law" and val != getattr(base, key):
                parts.append(
                    f"{key}={val:g}" if isinstance(val, float) else f"{key}={val}"
                )
        return " ".join(parts)


def _jenkins(c: Case, m: float, k: float):
    return hf.Jenkins(stiffness=c.stiffness_ratio * k, slip_force=1.0)


def _cubic(c: Case, m: float, k: float):
    return hf.Cubic(c.stiffness_ratio * k)


#: law name -> (constructor (case, m, k) -> law, stuck stiffness factor)
LAWS = {"jenkins": (_jenkins, True), "cubic": (_cubic, False)}


def build(c: Case):
    """System, forcing amplitude and frequency range of a case."""
    m = 1.0 * c.mass_scale
    k = 1.0 * c.mass_scale * c.freq_scale**2
    damping = 2.0 * c.zeta * math.sqrt(k * m)
    make, stuck = LAWS[c.law]
    law = make(c, m, k)
    osc = hf.Oscillator(m, damping, k, law)
    w_free = math.sqrt(k / m)
    w_high = math.sqrt((k + law.stuck_stiffness) / m) if stuck else 2.0 * w_free
    return osc, c.ratio, (0.3 * w_free, 1.5 * w_high)


def spot_indices(branch: hf.Branch) -> list[int]:
    """Three points on the stable part of the branch: first, peak, last; on
    a branch with folds (where a stretch is unstable and time integration
    would leave it), the first point and two before the first fold."""
    n = len(branch)
    if branch.folds.size:
        f = int(branch.folds[0])
        return sorted({0, max(0, f // 2), max(0, f - 3)})
    amp = branch.amplitude(harmonic=1)
    return sorted({0, int(np.argmax(amp)), n - 1})


def spot_check(osc, force: float, branch: hf.Branch, i: int) -> float:
    """Relative first-harmonic difference between the HBM point and the
    time-integration steady state started on it (1024 steps per period)."""
    sol = branch.point(i)
    hn = sol.harmonic_numbers
    X = sol.coefficients[0]
    cols = np.cumsum([0] + [1 if k == 0 else 2 for k in hn[:-1]])
    x0 = sum(X[c] for k, c in zip(hn, cols, strict=True))
    v0 = sum(sol.omega * k * X[c + 1] for k, c in zip(hn, cols, strict=True) if k > 0)
    ref = hf.validation.steady_state(
        osc,
        force,
        sol.omega,
        steps_per_period=1024,
        initial_state=(x0, v0),
        tol=1e-8,
        max_periods=3000,
    )
    if ref.status != 0:
        return math.inf
    a = sol.amplitude(harmonic=1)
    return abs(ref.amplitude(harmonic=1) - a) / a


def run_case(c: Case, spot: bool = True) -> dict:
    """Trace the branch of a case and check it; returns the findings."""
    osc, force, omega = build(c)
    options = hf.ContinuationOptions()
    t = time.perf_counter()
    b = hf.frf(osc, force, omega, c.harmonics, sweep=c.sweep, options=options)
    elapsed = time.perf_counter() - t
    out = {
        "case": c.name,
        "points": len(b),
        "steps": b.n_steps,
        "rejected": b.n_rejected,
        "newton": b.newton_iterations,
        "time_s": elapsed,
        "stop_reason": b.stop_reason,
        # the range covered (a run that left by its starting end after a
        # fold is retraced from the other end by ``frf``)
        "completed": b.complete,
        "finite": bool(
            np.all(np.isfinite(b.coefficients)) and np.all(np.isfinite(b.omega))
        ),
    }
    # successive points close in the scaled norm of the continuation
    problem = HBMProblem(osc, force, c.harmonics)
    scale = problem.amplitude_scale(omega)
    # the continuation's scale follows a tenth of the amplitude once that
    # exceeds 1.5 base scales (Continuation._follow_amplitude): divide by a
    # lower bound of it
    amp = np.abs(b.coefficients.reshape(len(b), -1)).max(axis=1)
    local = np.maximum(scale, 0.1 * np.minimum(amp[1:], amp[:-1]) / 1.5)
    dX = np.abs(np.diff(b.coefficients[:, 0], axis=0)) / local[:, None]
    dW = np.abs(np.diff(b.omega)) / (omega[1] - omega[0])
    gaps = np.maximum(dW, dX.max(axis=1)) if len(b) > 1 else np.zeros(0)
    # no step between two separately traced pieces
    if b.pieces is not None:
        starts = b.pieces[(b.pieces > 0) & (b.pieces < len(b))]
        gaps[starts - 1] = 0.0
    out["max_gap"] = float(gaps.max()) if gaps.size else 0.0
    out["gap_bound"] = 3.0 * options.max_step
    # the run must end on a boundary of the range (after folds, a branch
    # may leave through the end it started from)
    width = omega[1] - omega[0]
    out["end_error"] = (
        min(abs(b.omega[-1] - omega[0]), abs(b.omega[-1] - omega[1])) / width
        if len(b)
        else math.inf
    )
    out["spot"] = []
    if spot and len(b):
        for i in spot_indices(b):
            # a difference the truncation explains is not a branch jump:
            # allow twice the relative amplitude of the highest harmonic
            X = b.coefficients[i]
            top = truncation_estimate(b.harmonic_numbers, X)
            tol = 0.1 if c.harmonics < 3 else max(5e-3, 2.0 * top)
            out["spot"].append((float(b.omega[i]), spot_check(osc, force, b, i), tol))
    reasons = [p["stop_reason"] for p in b.info.get("pieces", [])] or [b.stop_reason]
    out["known_stop"] = all(
        r in (RANGE_END, RANGE_START, MAX_STEPS, MIN_STEP) for r in reasons
    )
    return out


def failures(out: dict) -> list[str]:
    """What is wrong with a case's findings (empty when it passed)."""
    bad = []
    if not out["finite"]:
        bad.append("non-finite values")
    if not out["completed"]:
        bad.append(f"stopped: {out['stop_reason']}")
    elif out["end_error"] > 1e-9:
        bad.append(f"last point {out['end_error']:.1e} off the range end")
    if out["max_gap"] > out["gap_bound"]:
        bad.append(f"gap {out['max_gap']:.3f} > {out['gap_bound']:.3f} (branch jump?)")
    for w, err, tol in out["spot"]:
        if not err <= tol:
            bad.append(f"time integration differs by {err:.1e} at Ω = {w:.4g}")
    return bad


BASE = Case()


def matrix() -> list[Case]:
    """The full stress matrix."""
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
]


def table(rows: list[dict]) -> str:
    """Markdown table of the findings."""
    lines = [
        "| case | completed | points | steps | rejected | Newton evals | time (ms) "
        "| spot-check max rel. diff | problems |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        spot = max((e for _, e, _ in r["spot"]), default=math.nan)
        lines.append(
            f"| {r['case']} | {'yes' if r['completed'] else 'no'} | {r['points']} | "
            f"{r['steps']} | {r['rejected']} | {r['newton']} | "
            f"{1e3 * r['time_s']:.1f} | "
            f"{spot:.1e} | {'; '.join(failures(r)) or '—'} |"
        )
    return "\n".join(lines)


def main() -> None:
    rows = []
    for c in matrix():
        out = run_case(c)
        rows.append(out)
        print(c.name, "OK" if not failures(out) else failures(out), flush=True)
    n_ok = sum(1 for r in rows if not failures(r))
    print(f"\n{n_ok}/{len(rows)} cases pass\n")
    print(table(rows))


if __name__ == "__main__":
    main()
