"""Reproduction of the results of Chatelet, Michon, Manin & Jacquet (2008),
*Stick/slip phenomena in dynamics: choice of contact model*, Mechanism and
Machine Theory 43, 1211–1224."""

from .beam import (
    PAPER_BEAM_SCENE,
    BeamFamily,
    BeamValidation,
    beam_criterion_family,
    beam_normal_load_family,
    beam_ratio_family,
    beam_validation,
    paper_beam,
    paper_calibration,
    ratio_collapse,
)
from .lap_joint import LAP_JOINT_SCENE, LapJointFamily, lap_joint_family
from .scenes import PAPER_SDOF, paper_oscillator
from .sdof import (
    FigureResult,
    iter_sdof_figures,
    masing_family,
    menq_family,
    rough_masing_family,
    rough_menq_family,
    sdof_family,
    sdof_figures,
)
from .tensioner import tensioner_frf, tensioner_loop

__all__ = [
    "BeamFamily",
    "BeamValidation",
    "PAPER_BEAM_SCENE",
    "PAPER_SDOF",
    "FigureResult",
    "LAP_JOINT_SCENE",
    "LapJointFamily",
    "beam_criterion_family",
    "beam_normal_load_family",
    "beam_ratio_family",
    "beam_validation",
    "iter_sdof_figures",
    "lap_joint_family",
    "masing_family",
    "menq_family",
    "paper_beam",
    "paper_calibration",
    "paper_oscillator",
    "ratio_collapse",
    "rough_masing_family",
    "rough_menq_family",
    "sdof_family",
    "sdof_figures",
    "tensioner_frf",
    "tensioner_loop",
]
