"""Mechanical systems: linear structure plus contact laws."""

from .beam import CantileverBeam
from .calibration import BeamCalibration
from .contacts import Contact
from .craig_bampton import ReducedStructure, craig_bampton
from .lap_joint import BRAKE_REUSS, LapJoint, lap_joint
from .matrix_files import read_matrices, read_matrix
from .oscillator import Oscillator
from .structure import LinearStructure
from .tensioner import BeltTensioner

__all__ = [
    "BeamCalibration",
    "BeltTensioner",
    "CantileverBeam",
    "BRAKE_REUSS",
    "Contact",
    "LapJoint",
    "LinearStructure",
    "Oscillator",
    "ReducedStructure",
    "craig_bampton",
    "lap_joint",
    "read_matrices",
    "read_matrix",
]
