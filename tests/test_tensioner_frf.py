"""``hf.frf`` on the belt-tensioner rig: the common engine path (defaults,
coverage, DOF names) against an independent time-domain reference."""

import math
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem, can_condense

RIG = hf.BeltTensioner()
BAND_HZ = (5.0, 100.0)
BAND = (2.0 * math.pi * BAND_HZ[0], 2.0 * math.pi * BAND_HZ[1])


def test_frf_covers_the_band_at_default_settings():
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CoverageWarning)
        branch = hf.frf(RIG, 20.0, BAND)
    assert branch.complete and len(branch) > 50
    assert branch.coefficients.shape[1] == 2
    assert branch.info["harmonics"] == "auto"
    # the DOF names of the rig, the pulley (u2) by default
    np.testing.assert_array_equal(branch.amplitude(1, "pulley"), branch.amplitude(1))
    assert not np.array_equal(branch.amplitude(1, "shaker"), branch.amplitude(1))


def test_rig_held_only_by_its_tensioner_is_not_condensed():
    # K of the belt alone is singular (the rig floats without the
    # tensioner): no static receptance, so no condensation
    assert not can_condense(RIG)
    with pytest.raises(ValueError, match="rigid-body mode"):
        CondensedHBMProblem(RIG, 20.0, harmonics=5)
