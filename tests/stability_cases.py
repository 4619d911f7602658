"""Systems shared by the stability tests (test_stability, test_stability_sparse,
test_monodromy, test_period_doubling, test_stability_hysteretic)."""

import numpy as np

import hbmfric as hf

#: Duffing oscillator with a Jenkins contact on the same DOF (light
#: friction: slip force 0.05 against 0.2 forcing), hardening enough to fold
FRICTION_DUFFING = dict(c=0.05, k3=0.1, kt=0.5, fs=0.05, force=0.2)


def friction_duffing(second_mass: float | None = None):
    """The friction Duffing (two folds at F = 0.2 over 0.5-2.5 rad/s); with
    ``second_mass``, a light second DOF hung on it (stiffness 2, damping
    0.01), so that it has several DOFs."""
    d = FRICTION_DUFFING
    contacts = [
        hf.Contact(hf.Cubic(d["k3"]), 0),
        hf.Contact(hf.Jenkins(stiffness=d["kt"], slip_force=d["fs"]), 0),
    ]
    if second_mass is None:
        return hf.LinearStructure(
            np.eye(1), np.eye(1), d["c"] * np.eye(1), load={0: 1.0}, contacts=contacts
        )
    return hf.LinearStructure(
        np.diag([1.0, second_mass]),
        np.array([[3.0, -2.0], [-2.0, 2.0]]),
        np.diag([d["c"], 0.01]),
        load={0: 1.0},
        contacts=contacts,
    )


def preloaded_duffing(preload: float = 1.0):
    """``ẍ + 0.02 ẋ + x + x³ = preload + F cos Ωt``: a period-doubling
    stretch near twice the linearised frequency (2.9965-3.1782 rad/s at
    preload 1, F = 0.5)."""
    return hf.LinearStructure(
        np.eye(1),
        np.eye(1),
        0.02 * np.eye(1),
        load={0: 1.0},
        static_load={0: preload},
        contacts=[hf.Contact(hf.Cubic(1.0), 0)],
    )


def fold_cluster_chain():
    """Two DOFs (M = I, K = [[2, -1], [-1, 1]], 1 % modal damping, load 1 on
    DOF 1), Jenkins kt = 2, f_s = 0.3 to ground at DOF 0 and a cubic
    k3 = 0.5 at DOF 1: at F = 0.3, H = 5 over 0.3-2.2 rad/s its branch
    has a cluster of seven folds (points 557-592) where the monodromy's
    verdicts were once snapped across computed points (issue 16, stop 27)."""
    return hf.LinearStructure(
        np.eye(2),
        np.array([[2.0, -1.0], [-1.0, 1.0]]),
        load={1: 1.0},
        modal_damping=0.01,
        contacts=[
            hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.3), 0),
            hf.Contact(hf.Cubic(0.5), 1),
        ],
    )
