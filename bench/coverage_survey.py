"""How often a branch stops short of its frequency range: 150 random valid
single-DOF systems (Jenkins, Menq, Iwan, Coulomb, Cubic), seed fixed.

``python -m bench.coverage_survey [--no-retrace] [--harmonics auto]
[--out file.json]`` prints per law the number of incomplete branches.
Coverage is computed here from the points (it also runs on versions without
``Branch.complete``): complete when the points reach both ends of the range
to 1e-9 of its width and the path ended at the far end.
"""

from __future__ import annotations

import argparse
import json
import math
import time
import warnings

import numpy as np

import hbmfric as hf

LAWS = ("jenkins", "menq", "iwan", "coulomb", "cubic")


def system(rng: np.random.Generator):
    """One random valid system: ``(name, oscillator, force, omega, sweep)``.

    m = 1, k = 1, damping ratio log-uniform in [1e-3, 0.1]; contact
    stiffness ratio kt/k log-uniform in [0.1, 1e4]; force over slip force
    log-uniform in [0.1, 10]; range [0.3 ω_free, 1.5 ω_stuck]."""
    law = LAWS[int(rng.integers(len(LAWS)))]
    zeta = 10 ** rng.uniform(-3, -1)
    kt = 10 ** rng.uniform(-1, 4)
    ratio = 10 ** rng.uniform(-1, 1)
    sweep = "up" if rng.uniform() < 0.5 else "down"
    if law == "jenkins":
        contact = hf.Jenkins(stiffness=kt, slip_force=1.0)
    elif law == "menq":
        onset = rng.uniform(0.2, 0.9)
        contact = hf.Menq.from_stiffness(
            stiffness=kt, slip_force=1.0, microslip_onset=onset
        )
    elif law == "iwan":
        contact = hf.Iwan.segalman(
            slip_force=1.0,
            stiffness=kt,
            chi=rng.uniform(-0.8, -0.1),
            beta=10 ** rng.uniform(-2, 0),
            n_elements=40,
        )
    elif law == "coulomb":
        contact = hf.Coulomb(slip_force=1.0)
    else:
        contact = hf.Cubic(kt)
    osc = hf.Oscillator(1.0, 2.0 * zeta, 1.0, contact)
    if law == "cubic":
        high = 1.5 * 2.0
    elif law == "coulomb":
        high = 1.5 * 3.0
    else:
        high = 1.5 * math.sqrt(1.0 + kt)
    name = f"{law} zeta={zeta:.3g} kt={kt:.3g} F={ratio:.3g} {sweep}"
    return law, name, osc, ratio, (0.3, high), sweep


def covered(branch, omega) -> bool:
    lo, hi = omega
    tol = 1e-9 * (hi - lo)
    if len(branch) == 0:
        return False
    complete = getattr(branch, "complete", None)
    if complete is not None:
        return bool(complete)
    far = hi if branch.info.get("sweep", "up") == "up" else lo
    return bool(
        branch.omega.min() <= lo + tol
        and branch.omega.max() >= hi - tol
        and abs(branch.omega[-1] - far) <= tol
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--n", type=int, default=150)
    parser.add_argument("--seed", type=int, default=14)
    parser.add_argument("--no-retrace", action="store_true")
    parser.add_argument("--harmonics", default="15", help='an integer or "auto"')
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    harmonics = args.harmonics if args.harmonics == "auto" else int(args.harmonics)
    rng = np.random.default_rng(args.seed)
    counts = {law: [0, 0] for law in LAWS}
    rows = []
    for _ in range(args.n):
        law, name, osc, force, omega, sweep = system(rng)
        kw = {}
        if "retrace" in hf.frf.__code__.co_varnames:
            kw["retrace"] = not args.no_retrace
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            b = hf.frf(osc, force, omega, harmonics, sweep=sweep, **kw)
        ok = covered(b, omega)
        counts[law][0] += 1
        counts[law][1] += int(not ok)
        rows.append(
            {
                "case": name,
                "complete": ok,
                "coverage": [float(b.omega.min()), float(b.omega.max())]
                if len(b)
                else None,
                "stop_reason": b.stop_reason,
                "time_s": time.perf_counter() - start,
            }
        )
        if not ok:
            print("incomplete:", name, rows[-1]["coverage"], b.stop_reason, flush=True)
    for law, (n, bad) in counts.items():
        print(f"{law}: {bad}/{n} incomplete")
    print(f"total: {sum(b for _, b in counts.values())}/{args.n} incomplete")
    if args.out:
        with open(args.out, "w") as fh:
            json.dump({"counts": counts, "rows": rows}, fh, indent=1)


if __name__ == "__main__":
    main()
