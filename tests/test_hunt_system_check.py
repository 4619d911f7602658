"""A system passed to the stability of a result must be the one it solves
(issue 14). A loaded branch given another system (a stiffer contact, the
same DOFs) returned Hill's verdicts for points that are no solutions of it,
without a word; one with another number of DOFs failed in a NumPy
broadcast."""

import numpy as np
import pytest

import hbmfric as hf

JENKINS3 = hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0))


@pytest.fixture(scope="module")
def loaded(tmp_path_factory):
    branch = hf.frf(JENKINS3, 0.5, (0.5, 3.0), harmonics=5)
    path = branch.save(tmp_path_factory.mktemp("hunt") / "branch.npz")
    return hf.Branch.load(path)


def test_the_right_system_is_accepted(loaded):
    assert loaded.stability(JENKINS3).stable.shape == (len(loaded),)
    assert loaded.point(3).stability(JENKINS3).stable.shape == (1,)


@pytest.mark.parametrize(
    "other",
    [
        hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=30.0, slip_force=1.0)),
        hf.Oscillator(1.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=0.5)),
        hf.Oscillator(2.0, 0.02, 1.0, hf.Jenkins(stiffness=3.0, slip_force=1.0)),
    ],
    ids=["stiffer contact", "lower slip force", "heavier"],
)
def test_another_system_is_refused(loaded, other):
    with pytest.raises(ValueError, match="does not solve this system"):
        loaded.stability(other)
    with pytest.raises(ValueError, match="does not solve this system"):
        loaded.special_points(other)
    with pytest.raises(ValueError, match="does not solve this system"):
        loaded.point(len(loaded) // 2).stability(other)


def test_another_number_of_dofs_is_refused(loaded):
    chain = hf.LinearStructure(
        np.eye(2),
        np.array([[2.0, -1.0], [-1.0, 1.0]]),
        contact=hf.Jenkins(3.0, 1.0),
        contact_dof=1,
    )
    with pytest.raises(ValueError, match="2 DOFs but the result 1"):
        loaded.stability(chain)


def test_period_doubled_branch_refuses_another_system(tmp_path):
    """Given the loaded branch of the preloaded Duffing and the system with
    a preload 10 % higher, the switch returned a 9-point "period-doubled
    branch" of the wrong system without a word."""
    from stability_cases import preloaded_duffing

    branch = hf.frf(preloaded_duffing(), 0.5, (2.5, 3.6), harmonics=9)
    doubling = next(p for p in branch.special_points() if p.kind == "period doubling")
    loaded = hf.Branch.load(branch.save(tmp_path / "duffing.npz"))
    with pytest.raises(ValueError, match="does not solve this system"):
        hf.period_doubled_branch(loaded, doubling, system=preloaded_duffing(1.1))
