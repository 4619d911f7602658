"""Mechanical systems: linear structure plus contact laws."""

from .beam import CantileverBeam
from .calibration import BeamCalibration
from .contacts import Contact
from .craig_bampton import ReducedStructure, craig_bampton
from .matrix_files import read_matrices, read_matrix
from .oscillator import Oscillator
from .structure import LinearStructure
from .tensioner import BeltTensioner

__all__ = [
    "BeamCalibration",
    "BeltTensioner",
    "CantileverBeam",
    "Contact",
    "LinearStructure",
    "Oscillator",
    "ReducedStructure",
    "craig_bampton",
    "read_matrices",
    "read_matrix",
]
