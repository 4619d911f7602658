"""Mechanical systems: linear structure plus contact laws."""

from .beam import CantileverBeam
from .calibration import BeamCalibration
from .oscillator import Oscillator
from .tensioner import BeltTensioner

__all__ = ["BeamCalibration", "BeltTensioner", "CantileverBeam", "Oscillator"]
