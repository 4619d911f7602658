"""Reproduction of the results of Chatelet, Michon, Manin & Jacquet (2008),
*Stick/slip phenomena in dynamics: choice of contact model*, Mechanism and
Machine Theory 43, 1211–1224."""

from .scenes import PAPER_SDOF, paper_oscillator
from .sdof import FigureResult, masing_family
from .tensioner import tensioner_frf, tensioner_loop

__all__ = [
    "PAPER_SDOF",
    "FigureResult",
    "masing_family",
    "paper_oscillator",
    "tensioner_frf",
    "tensioner_loop",
]
