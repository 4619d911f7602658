"""hbmfric: harmonic balance and arc-length continuation for structures with
dry-friction contacts, with Numba-compiled AFT kernels.

>>> import hbmfric as hf
>>> law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
>>> osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)
>>> branch = hf.frf(osc, force=0.5, omega=(0.5, 3.0), harmonics=15)
"""

from typing import TYPE_CHECKING

from .api import frf
from .continuation import ContinuationOptions
from .errors import (
    AccuracyWarning,
    CacheWarning,
    ConvergenceError,
    ConvergenceWarning,
    CostWarning,
    CoverageWarning,
    DataWarning,
    HbmfricWarning,
    SingularPointWarning,
    StudyWarning,
)
from .laws import (
    Contact2D,
    ContactLaw,
    Coulomb,
    Cubic,
    Iwan,
    Jenkins,
    Menq,
    ModifiedDahl,
    Roughness,
    hertz_mindlin_stiffness,
)
from .results import Branch, PeriodicSolution
from .study import StudyResult, grid, study
from .systems import (
    Contact,
    LapJoint,
    LinearStructure,
    Oscillator,
    ReducedStructure,
    craig_bampton,
    lap_joint,
)

if TYPE_CHECKING:  # for type checkers and the API docs; at run time see _LAZY
    from .modes import NonlinearMode, nonlinear_mode
    from .periodic import periodic_solution
    from .switching import period_doubled_branch
    from .systems import (
        BeamCalibration,
        BeltTensioner,
        CantileverBeam,
        read_matrices,
        read_matrix,
    )

__version__ = "0.1.0"

#: names loaded on first use: ``import hbmfric`` (and a first FRF after it)
#: need not pay for the modules only they use (the subpackages ``criterion``,
#: ``identify``, ``validation`` import scipy modules; the others are
#: Python to compile or load). ``hf.study`` stays eager: the submodule of the
#: same name would shadow the function once imported.
_LAZY = {
    "criterion": (".criterion", None),
    "identify": (".identify", None),
    "validation": (".validation", None),
    "periodic_solution": (".periodic", "periodic_solution"),
    "NonlinearMode": (".modes", "NonlinearMode"),
    "nonlinear_mode": (".modes", "nonlinear_mode"),
    "period_doubled_branch": (".switching", "period_doubled_branch"),
    "BeamCalibration": (".systems", "BeamCalibration"),
    "BeltTensioner": (".systems", "BeltTensioner"),
    "CantileverBeam": (".systems", "CantileverBeam"),
    "read_matrices": (".systems", "read_matrices"),
    "read_matrix": (".systems", "read_matrix"),
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        module_name, attr = _LAZY[name]
        module = importlib.import_module(module_name, __name__)
        value = module if attr is None else getattr(module, attr)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "AccuracyWarning",
    "CacheWarning",
    "ConvergenceError",
    "ConvergenceWarning",
    "CoverageWarning",
    "CostWarning",
    "DataWarning",
    "HbmfricWarning",
    "SingularPointWarning",
    "StudyWarning",
    "BeamCalibration",
    "BeltTensioner",
    "Branch",
    "CantileverBeam",
    "Contact",
    "Contact2D",
    "ContactLaw",
    "ContinuationOptions",
    "Coulomb",
    "Cubic",
    "Iwan",
    "Jenkins",
    "LapJoint",
    "LinearStructure",
    "NonlinearMode",
    "Menq",
    "ModifiedDahl",
    "Oscillator",
    "PeriodicSolution",
    "ReducedStructure",
    "Roughness",
    "StudyResult",
    "craig_bampton",
    "criterion",
    "frf",
    "grid",
    "hertz_mindlin_stiffness",
    "identify",
    "lap_joint",
    "nonlinear_mode",
    "period_doubled_branch",
    "periodic_solution",
    "read_matrices",
    "read_matrix",
    "study",
    "validation",
]
