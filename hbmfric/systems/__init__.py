"""Mechanical systems: linear structure plus contact laws."""

from typing import TYPE_CHECKING

from .contacts import Contact

# ``craig_bampton`` and ``lap_joint`` name both a submodule and a function:
# imported eagerly, so that the function is the package's attribute even
# after a later ``import hbmfric.systems.lap_joint``.
from .craig_bampton import ReducedStructure, craig_bampton
from .lap_joint import BRAKE_REUSS, LapJoint, lap_joint
from .oscillator import Oscillator
from .structure import LinearStructure

if TYPE_CHECKING:  # for type checkers and the API docs; at run time see _LAZY
    from .beam import CantileverBeam
    from .calibration import BeamCalibration
    from .matrix_files import read_matrices, read_matrix
    from .tensioner import BeltTensioner

#: names loaded on first use (``import hbmfric`` need not compile or run the
#: beam's and the tensioner's modules for an oscillator's FRF)
_LAZY = {
    "BeamCalibration": ".calibration",
    "BeltTensioner": ".tensioner",
    "CantileverBeam": ".beam",
    "read_matrices": ".matrix_files",
    "read_matrix": ".matrix_files",
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


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
