"""Mechanical systems: linear structure plus contact laws."""

from .oscillator import Oscillator

__all__ = ["Oscillator"]
