"""The lap joint's Contact2D variant (docs/lap-joint.md, "Contact2D
variant"), condensed onto its elements' coordinates against the full
harmonic balance (issue 15, stop 33, branch cond2d): one FRF at Fex = 36 N
over 125-185 Hz, H = 9 (every harmonic), the model reduced to 8 modes.

Usage: ``python -m bench.cond2d_lap N condense`` with ``condense`` one of
``none`` (default: condensed) or ``false``. Prints the CPU time
(``time.process_time()``), points, the drive peak and the receptance used.
"""

import sys
import time
import warnings

import numpy as np

import hbmfric as hf


def main() -> None:
    n_pairs = int((sys.argv[1:] or ["10"])[0])
    condense = {"none": None, "false": False}[(sys.argv[2:] or ["none"])[0]]
    joint = hf.LapJoint(n_pairs=n_pairs)
    s = joint.reduced(8, contact="contact2d")
    band = (2 * np.pi * 125.0, 2 * np.pi * 185.0)
    t = time.process_time()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = hf.frf(s, 36.0, band, harmonics=9, condense=condense)
    cpu = time.process_time() - t
    amp = branch.amplitude(dof="drive") / 36.0
    i = int(np.argmax(amp))
    print(
        f"N={n_pairs} n_dof={s.n_dof} condense={condense}: {cpu:.2f} s CPU, "
        f"{branch.omega.size} points, condensed={branch.info['condensed']}, "
        f"receptance={branch.info.get('receptance')}, drive peak {amp[i]:.9e} "
        f"m/N at {branch.omega[i] / (2 * np.pi):.6f} Hz, "
        f"complete={branch.complete}, "
        f"max curve error {np.nanmax(branch.curve_errors):.2e}, "
        f"warnings {sorted({type(c.message).__name__ for c in caught})}"
    )


if __name__ == "__main__":
    main()
