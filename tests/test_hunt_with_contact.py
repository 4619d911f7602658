"""``LinearStructure.with_contact`` on a structure built with ``contacts=``
(stop 35, hunt37).

It set ``contacts`` to None and put the new law on ``contact_dof``: a
contact between DOFs 1 and 2 became a contact from DOF 1 to ground, and of
two contacts one was dropped, without a word. Reference: the structure
built directly with the new law where the old one acted.
"""

from __future__ import annotations

import numpy as np
import pytest

import hbmfric as hf

N = 4
K = 1e4 * (2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1))
K[-1, -1] = 1e4
M = 0.1 * np.eye(N)


def chain(contacts):
    return hf.LinearStructure(
        M, K, modal_damping=0.01, load={0: 1.0}, contacts=contacts
    )


@pytest.mark.filterwarnings("ignore::hbmfric.errors.AccuracyWarning")
def test_relative_contact_keeps_its_two_dofs():
    old, new = hf.Jenkins(5e3, 1.0), hf.Jenkins(5e3, 0.2)
    swapped = chain([hf.Contact(old, 1, other=2)]).with_contact(new)
    direct = chain([hf.Contact(new, 1, other=2)])
    w1 = 2 * np.pi * direct.natural_frequencies(1)[0]
    for omega in (0.8 * w1, 1.0 * w1, 1.1 * w1):
        a = hf.periodic_solution(swapped, 1.0, omega, harmonics=5, condense=False)
        b = hf.periodic_solution(direct, 1.0, omega, harmonics=5, condense=False)
        np.testing.assert_allclose(a.coefficients, b.coefficients, atol=1e-12)
        # against ground (what main built) it is another structure
        ground = chain([hf.Contact(new, 1)])
        g = hf.periodic_solution(ground, 1.0, omega, harmonics=5, condense=False)
        assert np.max(np.abs(g.coefficients - b.coefficients)) > 1e-3 * np.max(
            np.abs(b.coefficients)
        )


def test_several_contacts_refused_and_none_is_the_linear_structure():
    law = hf.Jenkins(5e3, 1.0)
    s = chain([hf.Contact(law, 3), hf.Contact(law, 1, other=2)])
    with pytest.raises(ValueError, match="has 2 contacts"):
        s.with_contact(hf.Jenkins(5e3, 2.0))
    bare = s.with_contact(None)
    assert bare.contact is None and bare.contacts is None


def test_contact_dof_for_a_relative_contact_refused():
    s = chain([hf.Contact(hf.Jenkins(5e3, 1.0), 1, other=2)])
    with pytest.raises(ValueError, match="acts between DOFs"):
        s.with_contact(hf.Jenkins(5e3, 2.0), 3)
