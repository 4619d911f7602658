"""Maps of ``hf.periodic_solution`` against ``hf.frf`` branches.

Run: ``python -m bench.periodic_maps`` (the full map: 3 laws x 3 stiffness
ratios x 20 forces x 151 frequencies; a few minutes) or with options for a
part of it, e.g. ``python -m bench.periodic_maps --laws jenkins --ratios 30
--n-force 5 --n-omega 40``.

Scene: ``m = 1, c = 0.02, k = 1``, slip force ``f_s = 1``, stuck stiffness
``kt = ratio * k`` (Jenkins, Menq with microslip from half the slip force,
Iwan (Segalman, 50 elements)), H = 15. Forces: ``F / f_s`` geometric from
1e-3 (stuck at resonance for every ratio) to 10 (gross slip). Frequencies:
``[0.6, 1.25 sqrt(1 + kt/k)]`` rad/s, from below the slip resonance to
above the stuck one.

Reference per (law, ratio, force): the ``hf.frf`` branch over the same
range with the same settings. At every Ω each crossing of the branch is
interpolated between its two points and refined by Newton at fixed Ω (from
that seed; linear interpolation alone is off by up to ~1e-3 near the peak),
which gives the branch's solutions at Ω exactly (several in a fold region).

A point is a *silent wrong answer* when ``periodic_solution`` returns
``converged=True`` with a first-harmonic amplitude more than ``1e-4``
(relative) away from every branch solution at Ω, or ``converged=False``
without a :class:`~hbmfric.ConvergenceWarning`. Points where the branch
does not reach Ω are counted as "no reference".
"""

from __future__ import annotations

import argparse
import time
import warnings
from collections import Counter

import numpy as np

import hbmfric as hf
from hbmfric.api import _problem
from hbmfric.continuation import Continuation, ContinuationOptions
from hbmfric.kernels.steps import newton as _newton
from hbmfric.signals import harmonic_amplitude

RTOL = 1e-4
H = 15


def law(name: str, kt: float):
    """The contact law ``name`` with stuck stiffness ``kt`` and slip force 1."""
    if name == "jenkins":
        return hf.Jenkins(stiffness=kt, slip_force=1.0)
    if name == "menq":
        return hf.Menq.from_stiffness(stiffness=kt, slip_force=1.0, microslip_onset=0.5)
    if name == "iwan":
        return hf.Iwan.segalman(
            slip_force=1.0, stiffness=kt, chi=-0.5, beta=0.1, n_elements=50
        )
    raise ValueError(name)


def branch_values(osc, force, branch, omegas) -> list[list[float]]:
    """First-harmonic amplitudes of the branch's solutions at each Ω."""
    problem = _problem(osc, force, H, None, None, "auto", None)
    n = problem.n_unknowns
    cont = Continuation(problem, (omegas[0], omegas[-1]), 1, ContinuationOptions())
    w = branch.omega
    X = branch.coefficients[:, 0, :]
    hn = problem.harmonic_numbers

    def amp(x):
        return float(harmonic_amplitude(hn, x, 1))

    out = []
    for om in omegas:
        vals = []
        for j in range(w.size - 1):
            a, b = w[j] - om, w[j + 1] - om
            if a == 0.0 or a * b < 0.0 or (j == w.size - 2 and b == 0.0):
                s = a / (a - b) if a != b else 0.0
                seed = (1.0 - s) * X[j] + s * X[j + 1]
                y, status, _ = cont.solve_at(om, seed[:n], 200)
                if status == _newton.CONVERGED:
                    vals.append(amp(y[:n]))
                else:  # keep the interpolation, marked by a negative sign
                    vals.append(-amp(seed[:n]))
        out.append(vals)
    return out


def run_case(name, ratio, force, n_omega):
    """Counts for one (law, ratio, force) row."""
    osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law(name, ratio))
    lo, hi = 0.6, 1.25 * np.sqrt(1.0 + ratio)
    omegas = np.linspace(lo, hi, n_omega)
    t0 = time.perf_counter()
    branch = hf.frf(osc, force, (lo, hi), harmonics=H)
    t_branch = time.perf_counter() - t0
    refs = branch_values(osc, force, branch, omegas)
    row = Counter()
    methods = Counter()
    t_points = 0.0
    worst = 0.0
    for om, vals in zip(omegas, refs, strict=True):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            t0 = time.perf_counter()
            sol = hf.periodic_solution(osc, force, float(om), harmonics=H)
            t_points += time.perf_counter() - t0
        warned = any(issubclass(c.category, hf.ConvergenceWarning) for c in caught)
        method = getattr(sol, "method", "newton")  # (older versions: no method)
        methods[method] += 1
        row["points"] += 1
        if len(vals) > 1:
            row["multi-valued"] += 1
        if not sol.converged:
            row["warned" if warned else "silent wrong"] += 1
            continue
        if not vals:
            row["no reference"] += 1
            continue
        a = sol.amplitude(harmonic=1)
        err = min(abs(a - abs(v)) / abs(v) for v in vals)
        refined = [v for v in vals if v > 0]
        if refined:
            err = min(abs(a - v) / v for v in refined)
        if err > RTOL:
            row["silent wrong"] += 1
            print(
                f"  WRONG {name} kt/k={ratio} F={force:.4g} Ω={om:.5f}: "
                f"{a:.6g} vs {vals} ({method}, res {sol.residual_norm:.2e})"
            )
        else:
            row["ok"] += 1
            worst = max(worst, err)
    return row, methods, t_branch, t_points, worst, branch.stop_reason


def auto_accuracy(n_omega=30):
    """``harmonics="auto"`` against ``H = 63``: worst relative error of the
    first-harmonic amplitude and of half the peak-to-peak value, per case."""
    print("| law | kt/k | F | worst error / tolerance | levels chosen | warnings |")
    print("|---|---|---|---|---|---|")
    cases = [("jenkins", 3.0), ("jenkins", 30.0), ("menq", 30.0), ("iwan", 30.0)]
    for name, ratio in cases:
        osc = hf.Oscillator(
            mass=1.0, damping=0.02, stiffness=1.0, contact=law(name, ratio)
        )
        for force in (0.05, 0.5, 2.0):
            worst, levels, n_warn = 0.0, Counter(), 0
            for om in np.linspace(0.6, 1.25 * np.sqrt(1.0 + ratio), n_omega):
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    a = hf.periodic_solution(osc, force, float(om), harmonics="auto")
                n_warn += len(caught)
                f = hf.periodic_solution(
                    osc, force, float(om), harmonics=63, initial_guess=a
                )
                for k in (1, None):
                    worst = max(worst, abs(a.amplitude(k) / f.amplitude(k) - 1))
                levels[int(a.harmonic_numbers[-1])] += 1
            lv = ", ".join(f"{h}: {levels[h]}" for h in sorted(levels))
            print(
                f"| {name} | {ratio:g} | {force:g} | {worst / 1e-4:.2f} | {lv} "
                f"| {n_warn} |",
                flush=True,
            )


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--laws", nargs="+", default=["jenkins", "menq", "iwan"])
    p.add_argument("--ratios", nargs="+", type=float, default=[0.3, 3.0, 30.0])
    p.add_argument("--n-force", type=int, default=20)
    p.add_argument("--n-omega", type=int, default=151)
    p.add_argument(
        "--auto", action="store_true", help='harmonics="auto" against H = 63 instead'
    )
    args = p.parse_args(argv)
    if args.auto:
        return auto_accuracy()
    forces = np.geomspace(1e-3, 10.0, args.n_force)
    start = time.perf_counter()
    print(
        "| law | kt/k | points | ok | warned | silent wrong | no reference "
        "| multi-valued | newton / load ramp / from below / from above "
        "| worst rel. diff | frf time | periodic_solution time (per point) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    total = Counter()
    for name in args.laws:
        for ratio in args.ratios:
            rows = Counter()
            methods = Counter()
            t_b = t_p = worst = 0.0
            for force in forces:
                row, meth, tb, tp, w, stop = run_case(name, ratio, force, args.n_omega)
                rows += row
                methods += meth
                t_b += tb
                t_p += tp
                worst = max(worst, w)
            total += rows
            m = " / ".join(
                str(methods[k])
                for k in (
                    "newton",
                    "load ramp",
                    "continuation from below",
                    "continuation from above",
                )
            )
            print(
                f"| {name} | {ratio:g} | {rows['points']} | {rows['ok']} "
                f"| {rows['warned']} | {rows['silent wrong']} "
                f"| {rows['no reference']} | {rows['multi-valued']} | {m} "
                f"| {worst:.1e} | {t_b:.2f} s | {t_p:.2f} s "
                f"({1e3 * t_p / max(rows['points'], 1):.2f} ms) |",
                flush=True,
            )
    elapsed = time.perf_counter() - start
    print(
        f"\ntotal: {total['points']} points, {total['silent wrong']} silent wrong, "
        f"{total['warned']} warned, {total['no reference']} without reference; "
        f"run time {elapsed:.1f} s"
    )
    return total


if __name__ == "__main__":
    main()
