"""``hf.nonlinear_mode`` checks its memory before any work (hunt35, stop 34).

The EPMC levels are dense (``n = n_dof × n_coef`` unknowns, about
:data:`hbmfric.modes.EPMC_MATRICES` matrices of that order at once, and the
truncation estimate's level at ``2H + 1`` four times larger each); before
stop 34 ``nonlinear_mode`` checked nothing (``frf`` and
``periodic_solution`` did since stop 33): a model too large for the
machine was killed by the operating system after its continuation, when
the estimate's level was built. The budget is replaced here by one just
below or above the plan; the reference for the sizes is the problem's own
count of unknowns.
"""

import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric import _memory
from hbmfric.modes import EPMC_MATRICES


def _chain():
    k = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]])
    return hf.LinearStructure(
        mass=np.eye(3),
        stiffness=k,
        damping=0.02 * k,
        contacts=[hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.3), 1)],
        load={2: 1.0},
    )


def _need(harmonics: int, probe: bool) -> float:
    # symmetric chain: odd harmonics; 3 DOFs
    n = _memory.unknowns(3, harmonics, True)
    need = _memory.dense_bytes(n + 2, EPMC_MATRICES)
    if probe:
        n_probe = _memory.unknowns(3, 2 * harmonics + 1, True)
        need += _memory.dense_bytes(n_probe + 2, EPMC_MATRICES)
    return need


def test_nonlinear_mode_too_large_raises_before_any_work(monkeypatch):
    system = _chain()
    need = _need(7, True)
    monkeypatch.setattr(_memory, "budget", lambda: 0.9 * need)
    with pytest.raises(MemoryError, match="nonlinear_mode .* H = 15"):
        hf.nonlinear_mode(system, amplitude=(1e-3, 1.0), points=4, harmonics=7)
    # without the estimate its level is not planned: it fits
    assert _need(7, False) < 0.9 * need
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hf.AccuracyWarning)
        nm = hf.nonlinear_mode(
            system,
            amplitude=(1e-3, 1.0),
            points=4,
            harmonics=7,
            harmonic_tolerance=None,
        )
        assert np.all(np.isfinite(nm.omega))
        monkeypatch.setattr(_memory, "budget", lambda: 1.01 * need)
        nm = hf.nonlinear_mode(system, amplitude=(1e-3, 1.0), points=4, harmonics=7)
    assert np.all(np.isfinite(nm.omega))
