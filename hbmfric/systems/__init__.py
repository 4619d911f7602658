"""Mechanical systems: linear structure plus contact laws."""

from .beam import CantileverBeam
from .calibration import BeamCalibration
from .oscillator import Oscillator

__all__ = ["BeamCalibration", "CantileverBeam", "Oscillator"]
