"""hbmfric: harmonic balance and arc-length continuation for structures with
dry-friction contacts, with Numba-compiled AFT kernels.

>>> import hbmfric as hf
>>> law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
>>> osc = hf.Oscillator(mass=1.0, damping=0.02, stiffness=1.0, contact=law)
>>> branch = hf.frf(osc, force=0.5, omega=(0.5, 3.0), harmonics=15)
"""

from . import criterion, identify, validation
from .api import frf, periodic_solution
from .continuation import ContinuationOptions
from .coulomb import Coulomb
from .dahl import ModifiedDahl
from .errors import (
    AccuracyWarning,
    CacheWarning,
    ConvergenceError,
    ConvergenceWarning,
    CoverageWarning,
    HbmfricWarning,
    StudyWarning,
)
from .laws import (
    Contact2D,
    ContactLaw,
    Cubic,
    Iwan,
    Jenkins,
    Menq,
    Roughness,
    hertz_mindlin_stiffness,
)
from .results import Branch, PeriodicSolution
from .study import StudyResult, grid, study
from .systems import (
    BeamCalibration,
    BeltTensioner,
    CantileverBeam,
    Contact,
    LapJoint,
    LinearStructure,
    Oscillator,
    ReducedStructure,
    craig_bampton,
    lap_joint,
    read_matrices,
    read_matrix,
)

__version__ = "0.1.0"

__all__ = [
    "AccuracyWarning",
    "CacheWarning",
    "ConvergenceError",
    "ConvergenceWarning",
    "CoverageWarning",
    "HbmfricWarning",
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
    "periodic_solution",
    "read_matrices",
    "read_matrix",
    "study",
    "validation",
]
