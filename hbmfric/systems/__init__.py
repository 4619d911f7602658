"""Mechanical systems: linear structure plus contact laws."""

from .oscillator import Oscillator
from .tensioner import BeltTensioner

__all__ = ["BeltTensioner", "Oscillator"]
