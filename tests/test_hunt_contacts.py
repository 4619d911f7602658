"""A 2D contact element whose tangential and normal DOFs overlap was
accepted and solved (issue 14): one scalar DOF has one direction, so it
cannot carry both the slip and the gap of the same element; the branch was
a number for a mechanism that does not exist."""

from types import SimpleNamespace

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.systems.contacts import check_contacts

ELEMENT = hf.Contact2D(
    tangential_stiffness=3e4,
    normal_stiffness=1e5,
    friction_coefficient=0.4,
    preload=50.0,
)
M = np.eye(3)
K = np.array([[2e4, -1e4, 0.0], [-1e4, 2e4, -1e4], [0.0, -1e4, 2e4]])

OVERLAPS = [
    {"dof": 0, "normal": 0},
    {"dof": 0, "other": 1, "normal": 1},
    {"dof": 0, "normal": 1, "normal_other": 0},
    {"dof": 0, "other": 1, "normal": 0, "normal_other": 1},
]


@pytest.mark.parametrize("dofs", OVERLAPS, ids=str)
def test_overlapping_tangential_and_normal_dofs_are_refused(dofs):
    with pytest.raises(ValueError, match="both tangentially and normally"):
        hf.LinearStructure(
            M,
            K,
            load={0: 1.0},
            static_load={2: 50.0},
            contacts=[hf.Contact(ELEMENT, **dofs)],
        )
    # a system of the protocol (not a LinearStructure) is checked alike
    contact = SimpleNamespace(
        **{"law": ELEMENT, "other": None, "normal_other": None, **dofs}
    )
    with pytest.raises(ValueError, match="both tangentially and normally"):
        check_contacts(SimpleNamespace(contacts=[contact]), 3)


def test_distinct_dofs_are_accepted():
    s = hf.LinearStructure(
        M,
        K,
        load={0: 1.0},
        static_load={2: 50.0},
        contacts=[hf.Contact(ELEMENT, 0, other=1, normal=2)],
    )
    assert s.contacts[0].normal == 2


@pytest.mark.parametrize("n_modes", [0, 1, 3])
def test_craig_bampton_is_accurate_below_its_cutoff(n_modes):
    """Every natural frequency of the reduced chain below half its
    ``cutoff_frequency`` is within 1 % of the full chain's. A Guyan
    reduction (no modes) reported ``inf`` and was 7 % off at the first
    mode."""
    n = 10
    k = 1e4 * (2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    k[-1, -1] = 1e4
    s = hf.LinearStructure(
        np.eye(n), k, contact=hf.Jenkins(3e4, 1.0), contact_dof=9, load={0: 1.0}
    )
    full = s.natural_frequencies()
    reduced = hf.craig_bampton(s, [0, 9], n_modes)
    f = reduced.natural_frequencies()
    below = f < 0.5 * reduced.cutoff_frequency
    np.testing.assert_allclose(f[below], full[: f.size][below], rtol=1e-2)
    everything = hf.craig_bampton(s, list(range(n)), 0)
    assert everything.cutoff_frequency == np.inf
    np.testing.assert_allclose(everything.natural_frequencies(), full, rtol=1e-12)
