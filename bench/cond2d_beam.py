"""The new user's beam with a 2D element (issue 15, stop 33, branch cond2d):
one FRF condensed onto the contact coordinates against the full harmonic
balance, CPU time in the process.

An 81-DOF clamped-free steel beam (L 0.6 m, 40 x 6 mm, E 210 GPa, rho 7800,
40 Euler-Bernoulli elements, 80 DOFs after the clamp) plus a pad DOF
(0.05 kg on 1e5 N/m) as the normal DOF of a 2D element; Rayleigh (2 1/s,
2e-5 s); a Jenkins tip-ground (2e3 N/m, 1 N), a Jenkins between the
transverse DOFs of nodes 20 and 30 (5e3 N/m, 0.5 N), a Contact2D (3e3, 1e5
N/m, mu 0.3, preload 5 N) from node 25's transverse DOF against the pad;
0.3 N at node 10; 10-28 Hz given in rad/s (bench/README.md, "new user").

Usage: ``python -m bench.cond2d_beam [condense] [harmonics]`` with
``condense`` one of ``none`` (default: condensed), ``false``; ``harmonics``
``auto`` (default) or an integer.
"""

import sys
import time
import warnings

import numpy as np

import hbmfric as hf


def beam_structure() -> hf.LinearStructure:
    n_el, length, b, h = 40, 0.6, 0.04, 0.006
    E, rho = 210e9, 7800.0
    A, I = b * h, b * h**3 / 12.0
    le = length / n_el
    ke = (E * I / le**3) * np.array(
        [
            [12, 6 * le, -12, 6 * le],
            [6 * le, 4 * le**2, -6 * le, 2 * le**2],
            [-12, -6 * le, 12, -6 * le],
            [6 * le, 2 * le**2, -6 * le, 4 * le**2],
        ]
    )
    me = (rho * A * le / 420.0) * np.array(
        [
            [156, 22 * le, 54, -13 * le],
            [22 * le, 4 * le**2, 13 * le, -3 * le**2],
            [54, 13 * le, 156, -22 * le],
            [-13 * le, -3 * le**2, -22 * le, 4 * le**2],
        ]
    )
    n = 2 * (n_el + 1)
    K = np.zeros((n, n))
    M = np.zeros((n, n))
    for e in range(n_el):
        s = slice(2 * e, 2 * e + 4)
        K[s, s] += ke
        M[s, s] += me
    K, M = K[2:, 2:], M[2:, 2:]  # clamp node 0
    # the pad DOF
    K = np.pad(K, ((0, 1), (0, 1)))
    M = np.pad(M, ((0, 1), (0, 1)))
    K[-1, -1] = 1e5
    M[-1, -1] = 0.05

    def w(node):  # transverse DOF of a node (node 0 clamped)
        return 2 * (node - 1)

    pad = K.shape[0] - 1
    element = hf.Contact2D(
        tangential_stiffness=3e3,
        normal_stiffness=1e5,
        friction_coefficient=0.3,
        preload=5.0,
    )
    return hf.LinearStructure(
        M,
        K,
        rayleigh=(2.0, 2e-5),
        load={w(10): 1.0},
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=2e3, slip_force=1.0), w(40)),
            hf.Contact(hf.Jenkins(stiffness=5e3, slip_force=0.5), w(20), w(30)),
            hf.Contact(element, w(25), normal=pad),
        ],
    )


def main() -> None:
    condense = {"none": None, "false": False}[(sys.argv[1:] or ["none"])[0]]
    harmonics = (sys.argv[2:] or ["auto"])[0]
    harmonics = harmonics if harmonics == "auto" else int(harmonics)
    s = beam_structure()
    band = (2 * np.pi * 10.0, 2 * np.pi * 28.0)
    t = time.process_time()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        branch = hf.frf(s, 0.3, band, harmonics=harmonics, condense=condense)
    cpu = time.process_time() - t
    amp = branch.amplitude()
    i = int(np.argmax(amp))
    print(
        f"condense={condense} harmonics={harmonics}: {cpu:.2f} s CPU, "
        f"{branch.omega.size} points, condensed={branch.info['condensed']}, "
        f"H {branch.harmonic_numbers[-1]}, peak {amp[i]:.9e} m at "
        f"{branch.omega[i]:.6f} rad/s, complete={branch.complete}, "
        f"max curve error {np.nanmax(branch.curve_errors):.2e}, "
        f"warnings {[type(c.message).__name__ for c in caught]}"
    )


if __name__ == "__main__":
    main()
