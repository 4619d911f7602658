"""A modified Dahl law whose loops give energy is said to be so (stop 32).

``ModifiedDahl(beta=1, upper=(5, 1), lower=(5, -1))`` was accepted without
a word, and ``Branch.stability()`` (Hill) called its orbits above
4.27 rad/s stable where the monodromy reads multipliers 1.08-1.14. The
construction now warns exactly when the law's loops have a negative
energy per cycle: checked here against the loop area ``∮ F du`` of the
law's own steady loop (:func:`hbmfric.laws.dahl.loop_area`, the compiled
march), not against the closed form the check uses.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.laws.dahl import loop_area

# (beta, exponent, upper, lower)
LAWS = [
    (1.0, 1.0, (5.0, 1.0), (5.0, -1.0)),  # stop 32's law: active
    (900.0, 1.0, (1.5e4, 300.0), (1.5e4, 150.0)),  # the tensioner: passive
    (3.0, 1.0, (0.5, 2.0), (0.3, -0.5)),  # unsymmetric, passive
    (2.0, 1.0, (3.0, 1.0), (1.0, 0.2)),  # unsymmetric, active: 0.8 < 2
    (2.0, 1.0, (0.0, 1.0), (0.0, -1.0)),  # flat envelopes: passive
    (1.0, 2.0, (4.0, 1.0), (4.0, -1.0)),  # mu = 2, equal slopes: active
    (4.0, 2.0, (1.0, 1.5), (1.0, -1.5)),  # mu = 2, equal slopes: passive
    (1.0, 2.0, (4.0, 1.0), (1.0, -1.0)),  # mu = 2, unequal slopes: active, 2 < 3
    (1.0, 2.0, (4.0, 2.2), (1.0, -1.0)),  # mu = 2, unequal slopes: passive, 3.2 > 3
    (2.0, 1.5, (3.0, 1.0), (0.5, 0.2)),  # mu = 1.5, unequal: active, 0.8 < 1.71
    (2.0, 1.5, (3.0, 2.0), (0.5, 0.2)),  # mu = 1.5, unequal: passive, 1.8 > 1.71
]


def _construct(beta, exponent, upper, lower):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        law = hf.ModifiedDahl(beta=beta, exponent=exponent, upper=upper, lower=lower)
    said = [w for w in caught if issubclass(w.category, hf.AccuracyWarning)]
    return law, said


@pytest.mark.parametrize("beta, exponent, upper, lower", LAWS)
def test_warned_exactly_when_loops_give_energy(beta, exponent, upper, lower):
    law, said = _construct(beta, exponent, upper, lower)
    # amplitudes from small to large against the law's own scale 1/beta
    amplitudes = np.array([0.3, 3.0, 30.0]) / beta
    if exponent != 1.0:
        amplitudes = amplitudes[-1:]  # the check speaks of large loops
    areas = [loop_area(law, float(x), 2048) for x in amplitudes]
    gives_energy = all(area < 0.0 for area in areas)
    dissipates = all(area > 0.0 for area in areas)
    assert gives_energy or dissipates  # each case is one or the other
    assert bool(said) == gives_energy, (areas, [str(w.message) for w in said])
    if said:
        assert "energy" in str(said[0].message)
        assert "monodromy" in str(said[0].message)
