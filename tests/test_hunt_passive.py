"""The energy-proof shortcut of Hill's signs (``stability._passive``)
accepts exactly the systems its proof covers (docs/stability.md, "Jenkins
branches"): one DOF, ``m``, ``c``, ``k > 0``, every contact a Jenkins
element to ground evaluated by the event AFT, odd points with ``Ω > 0``.
A system outside those conditions (no damping, negative damping of a
system of the user's own, no stiffness, another law mixed in, the sampled
AFT, an even harmonic, ``Ω <= 0``) must take the computed signs.

Where it accepts, the signs it claims (+1 for the odd and the even block)
are those of the LU of the Jacobian at the points, computed here with
NumPy (``slogdet``) on the blocks of the dense Jacobian."""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf
from hbmfric import stability
from hbmfric.stability import _stability_problem

JENKINS = hf.Jenkins(stiffness=3.0, slip_force=1.0)


class _OwnOscillator:
    """A one-DOF system of the user's own (the system protocol), whose
    damping and stiffness are not checked for sign."""

    n_dof = 1
    contact_dof = 0

    def __init__(self, m, c, k, contacts):
        self._m = np.array([[m]], dtype=float)
        self._c = np.array([[c]], dtype=float)
        self._k = np.array([[k]], dtype=float)
        self.contacts = contacts
        self.contact = contacts[0].law

    def matrices(self):
        return self._m, self._c, self._k

    def load_vector(self, force):
        return np.array([force], dtype=float)


def _points(problem, omega=1.0, even=0.0) -> np.ndarray:
    """Three points (3, n + 1): first cosines 0.1, 1 and 3 (a stuck, a
    slipping and a far-slipping motion), a third harmonic, an even
    harmonic's cosine ``even``, pulsation ``omega``."""
    n = problem.n_unknowns
    pts = np.zeros((3, n + 1))
    pts[:, 1] = [0.1, 1.0, 3.0]  # cos θ (column 0 is the constant)
    pts[:, 5] = [0.0, 0.05, 0.2]  # cos 3θ
    pts[:, 3] = even  # cos 2θ
    pts[:, -1] = omega
    return pts


def _own(c=0.02, k=1.0, laws=(JENKINS,)):
    return _OwnOscillator(1.0, c, k, [hf.Contact(law, 0) for law in laws])


@pytest.mark.parametrize(
    "label, system, aft",
    [
        ("no damping", _own(c=0.0), "auto"),
        ("negative damping", _own(c=-0.02), "auto"),
        ("no stiffness", _own(k=0.0), "auto"),
        ("negative stiffness", _own(k=-0.5), "auto"),
        ("Jenkins and a cubic spring", _own(laws=(JENKINS, hf.Cubic(1.0))), "auto"),
        ("the sampled AFT", _own(), "samples"),
        (
            "Jenkins and a Menq element (event AFT too)",
            _own(laws=(JENKINS, hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0))),
            "auto",
        ),
    ],
)
def test_passive_refuses_what_the_proof_does_not_cover(label, system, aft):
    problem = _stability_problem(system, 0.5, 7, None, aft, 1)
    assert not stability._passive(problem, _points(problem)), label


def test_passive_refuses_even_harmonics_and_non_positive_omega():
    problem = _stability_problem(_own(), 0.5, 7, None, "auto", 1)
    assert stability._passive(problem, _points(problem))
    assert not stability._passive(problem, _points(problem, even=1e-3))
    assert not stability._passive(problem, _points(problem, omega=0.0))
    assert not stability._passive(problem, _points(problem, omega=-1.0))


@pytest.mark.parametrize(
    "laws",
    [(JENKINS,), (JENKINS, hf.Jenkins(stiffness=300.0, slip_force=0.1))],
    ids=["one Jenkins", "two Jenkins"],
)
def test_passive_signs_are_the_jacobians(laws):
    """Where the shortcut accepts, ``det`` of the odd and of the even
    block of the HBM Jacobian is positive at every point (NumPy's
    ``slogdet`` of the blocks of the dense Jacobian)."""
    problem = _stability_problem(_own(laws=laws), 0.5, 7, None, "auto", 1)
    pts = _points(problem)
    assert stability._passive(problem, pts)
    hn = problem.harmonic_numbers
    per = np.repeat(hn, np.where(hn == 0, 1, 2))
    odd = per % 2 == 1
    for y in pts:
        J = problem.residual(y)[1][:, :-1]
        for rows in (odd, ~odd):
            sign, _ = np.linalg.slogdet(J[np.ix_(rows, rows)])
            assert sign == 1.0
