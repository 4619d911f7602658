"""Trust hunt, stop 28: a free-floating structure (rigid-body mode) held
together by friction joints, as a new user would condense it.

Reference: the full (uncondensed) harmonic balance of the same branch."""

import warnings

import numpy as np
import pytest

import hbmfric as hf


def _free_chain() -> hf.LinearStructure:
    """Four unit masses, free–free, 1e3 N/m between neighbours (ω = 0,
    24.2, 44.7, 58.4 rad/s), Jenkins joints 1–2 and 2–3, load on mass 0."""
    n = 4
    K = np.zeros((n, n))
    for i in range(n - 1):
        K[np.ix_([i, i + 1], [i, i + 1])] += 1e3 * np.array([[1, -1], [-1, 1]])
    law = hf.Jenkins(stiffness=500.0, slip_force=0.2)
    return hf.LinearStructure(
        np.eye(n),
        K,
        modal_damping=0.02,
        load={0: 1.0},
        contacts=[hf.Contact(law, 1, other=2), hf.Contact(law, 2, other=3)],
    )


@pytest.mark.parametrize("condense", ["state", "modal"])
def test_receptances_that_need_no_rigid_body_mode_are_refused_naming_the_remedy(
    condense,
):
    """The messages named ``receptance='direct'``, which hf.frf has not."""
    with pytest.raises(ValueError, match="condense='direct'"):
        hf.frf(_free_chain(), 0.5, (10.0, 80.0), harmonics=5, condense=condense)


def test_direct_condensation_of_a_free_chain_against_full():
    """Odd harmonics only (no static receptance needed): the direct
    receptance's drawn curve meets the full one within the curve tolerance
    1e-4 at every DOF (measured 2.5e-5; the direct receptance's curve rule
    watches the first coordinate, not the DOF drawn)."""
    s = _free_chain()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.HbmfricWarning)
        full = hf.frf(s, 0.5, (10.0, 80.0), harmonics=5)
        direct = hf.frf(s, 0.5, (10.0, 80.0), harmonics=5, condense="direct")
    assert not full.info["condensed"] and direct.info["receptance"] == "direct"
    grid = np.linspace(10.1, 79.9, 80)
    for dof in range(4):
        a = direct.amplitude_at(grid, dof=dof)
        b = full.amplitude_at(grid, dof=dof)
        assert a.shape == b.shape
        assert np.nanmax(np.abs(a - b) / b) < 1e-4
