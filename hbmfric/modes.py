"""Nonlinear modes by the extended periodic motion concept (EPMC).

The unforced system ``M ẍ + C ẋ + K x + f_nl(x) = p0`` (``p0`` a static
load, if the system has one) has no periodic motion when it dissipates
energy. Krack (2015) adds the negative mass-proportional damping term
``-ξ M ẋ``, ``ξ = 2 D ω``, that feeds back exactly the energy the structure
dissipates per cycle:

    M ẍ + (C - 2 D ω M) ẋ + K x + f_nl(x) = p0.

Its periodic motions of frequency ``ω`` form the nonlinear mode; ``D`` is
the mode's equivalent (modal) damping ratio. Harmonic balance of this
equation with the HBM residual of the forced problem
(:mod:`hbmfric.kernels.residuals.hbm`, its AFT of every law with the analytic
Jacobian) gives ``n_dof n_coef`` equations for the coefficients ``X``,
``ω`` and ``D``; two more close the system:

* amplitude normalisation: the fundamental harmonic in the mass norm,
  ``Xc1ᵀ M Xc1 + Xs1ᵀ M Xs1 = a²`` (``a`` the modal amplitude: for a
  single DOF of mass ``m``, ``a = √m`` times the first-harmonic amplitude;
  for a mass-normalised linear mode ``φ``, ``x = a φ cos ωt``), m √kg;
* phase condition: ``φᵀ M Xs1 = 0`` with ``φ`` the linear mode the
  nonlinear one starts from: the fundamental is a cosine in the direction
  of the linear mode.

The unknowns are solved scaled, ``Y = X / a``, so that Newton sees the same
magnitudes at every amplitude.

Damping convention: the structure's own damping ``C`` is kept (Krack 2015;
also NLvib's EPMC): ``D`` is the damping ratio of the whole mode, the
structure's and the contacts' dissipation together, so that in the linear
limit (stuck contact) with modal damping ``D`` is the modal damping ratio
``ζ_j`` and ``ω`` the undamped natural pulsation ``ω_j``, exactly. With
``structural_damping=False`` ``C`` is dropped and ``D`` is the contacts'
share alone. In both cases ``D`` is defined by the energy balance of the
fundamental: per cycle, the added term supplies ``2π D ω² a²`` (for a
motion ``a φ cos ωt``), the dissipated energy ``W`` so that
``D = W / (2π ω² a²)``.

Continuation: natural, in ``log a`` on the requested grid of amplitudes,
with a secant predictor; a step is halved when Newton fails (a line
search follows the first plain iterations), when ω or D land more than
``MAX_CORRECTION`` from the predictor, or when the fundamental shape
correlates with the previous point's below ``MAC_TOLERANCE`` (modal
assurance criterion: another mode). Along most modes ω and D are functions
of the amplitude; a friction backbone can nevertheless turn back in
amplitude (the paper beam's mode 1, twice, near the stick limit). Where
the natural step fails for good, a pseudo-arclength continuation in
``(z, log a)`` (:func:`_pass_folds`) follows the path around the turns
until it climbs past the failure, and the grid resumes from there; the
turning points are reported (``NonlinearMode.folds``, a
:class:`~hbmfric.HbmfricWarning`). A path on which a higher harmonic
``k`` grows to ``RESONANCE_RATIO`` times the fundamental has left the mode
for a ``k:1`` internal resonance and stops with that reason (the spring
chain of issue 16); so does a path that turned and then fails after a
higher harmonic outgrew the fundamental on it. When the run stops on the
path past a turning point, the mode beyond it is continued down from the
top of the range, starting from the linear mode of the structure with its
contacts slipping (:func:`_descend`): two pieces and the gap between them
(``NonlinearMode.pieces``, ``gaps``). A run that stops short is reported
by a :class:`~hbmfric.CoverageWarning`, never a quietly short result.

Reference: M. Krack, *Nonlinear modal analysis of nonconservative systems:
extension of the periodic motion concept*, Computers & Structures 154
(2015) 59–71.
"""

from __future__ import annotations

import csv
import json
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._npz import (
    READ_ERRORS,
    check_harmonics,
    check_npz_sizes,
    field_error,
    optional_array,
    stored_array,
)
from ._validate import finite_float, positive_int
from .errors import (
    AccuracyWarning,
    ConvergenceWarning,
    CoverageWarning,
    HbmfricWarning,
)
from .hbm import HBMProblem, _stuck_stiffnesses
from .kernels.dlft.coulomb import COULOMB
from .kernels.residuals.hbm import hbm_residual
from .signals import coefficient_columns
from .stability import derivative_operator
from .systems.craig_bampton import warn_above_cutoff
from .systems.protocol import check_load, check_system

#: the truncation estimate's basis: ``PROBE_FACTOR * H + 1``
PROBE_FACTOR = 2
#: dense matrices of order ``n`` (the unknowns of a level) an EPMC level
#: holds at once (:meth:`_EPMC.equations`: the HBM Jacobian, the EPMC
#: Jacobian, two temporaries of its block, ``md`` and the solve's copy);
#: a 60-DOF chain with a 2D element at ``H = 7`` peaked at 143 MB above
#: its start, 5.2 matrices of its probe level's order (stop 34)
EPMC_MATRICES = 6


def _check_memory(epmc, probe: bool) -> None:
    """A ``MemoryError`` before any work when the levels of a nonlinear
    mode (``epmc``'s and, with ``probe``, the truncation estimate's at
    ``2H + 1``) need more than :func:`hbmfric._memory.budget` for their
    dense matrices (:data:`EPMC_MATRICES` each). Before stop 34 nothing
    was checked: a model too large was killed by the operating system
    after its continuation, when the probe level was built."""
    from . import _memory

    p = epmc.problem
    need = _memory.dense_bytes(epmc.n + 2, EPMC_MATRICES)
    if probe:
        h = PROBE_FACTOR * int(p.harmonics) + 1
        n_probe = _memory.unknowns(epmc.n_dof, h, p.odd)
        need += _memory.dense_bytes(n_probe + 2, EPMC_MATRICES)
    room = _memory.budget()
    if need > room:
        raise MemoryError(
            f"nonlinear_mode ({epmc.n} unknowns at H = {int(p.harmonics)}"
            f"{', its truncation estimate at H = ' + str(h) if probe else ''}) "
            f"needs about {_memory.gigabytes(need)} for its dense matrices, "
            f"more than the {_memory.gigabytes(room / _memory.MEMORY_SHARE)} "
            f"this machine can give it ({_memory.MEMORY_SHARE:.0%} of the memory "
            "available now). Reduce the model (hf.craig_bampton, keeping the "
            "contact DOFs), use fewer harmonics, or skip the estimate "
            "(harmonic_tolerance=None)"
        )


#: format tag of :meth:`NonlinearMode.save` files
FORMAT = "hbmfric.NonlinearMode/1"
#: :meth:`NonlinearMode.resonances`: largest share of the harmonics above
#: the first in ``Σ_k k² (Xc_kᵀ M Xc_k + Xs_kᵀ M Xs_k)`` (the weight of the
#: supplied energy) at a resonance before it warns: the energy balance takes
#: the mode's motion for the forced one, but the EPMC's damping term also
#: drives the higher harmonics, which the forcing does not (one-DOF Jenkins,
#: share 0.33 % at most: amplitudes within 0.75 % of the FRF peaks; the
#: issue-16 spring chain past its 3:1 internal resonance, 9 % and 59 %:
#: 15 % and 4.4 times off, bench/README.md stop 28)
HIGHER_SHARE_TOL = 0.02
#: a resonance of :meth:`NonlinearMode.resonances` whose interpolated
#: amplitude may be off by more than this (relative; the estimate of
#: :func:`_crossing_spread`) is warned about: the balance bends sharply
#: about the two points (a stick/slip change; a
#: Jenkins contact slipping just past its onset at the peak read 3.4 % low
#: with 241 points over 1e-6 to 1e-1, and without a word before stop 33)
RESONANCE_SPREAD_TOL = 0.01
#: ... a change of the balance over a neighbouring interval more than this
#: factor from its change over the crossing one marks a kink there (smooth
#: stretches: 0.78-1.34 at 8 points per decade; the onset of slip of a
#: Jenkins contact: 34-840; an Iwan element's, 3.2)
KINK_RATIO = 2.0
#: Newton: relative size of the last correction below which a point counts
#: as converged
STEP_TOLERANCE = 1e-11
#: Newton: largest residual accepted, relative to ``a`` times the largest
#: stiffness entry (the force scale of the mode)
RESIDUAL_TOLERANCE = 1e-8
#: Newton: full steps before the line search starts
PLAIN_ITERATIONS = 6
#: Newton: residual below which the line search takes the full step
#: (rounding level: the residual cannot decrease any more)
RESIDUAL_FLOOR = 1e-13
#: Newton: smallest fraction of the correction the line search tries
MIN_LAMBDA = 1.0 / 1024.0
#: Newton: corrections that stop shrinking below this size mark the
#: rounding floor, where the point is accepted (if its residual is)
STALL_TOLERANCE = 1e-9
MAX_ITERATIONS = 30
#: smallest fraction of a grid interval (in log a) a step may shrink to
MIN_STEP_FRACTION = 1.0 / 1024.0
#: smallest modal assurance criterion between the fundamental shapes of
#: two successive points: below it the step is taken for a jump to another
#: mode (mass-orthogonal linear modes have 0; the paper beam's whole
#: stuck-to-free change of mode 1 has 0.89) and is rejected
MAC_TOLERANCE = 0.5
#: largest change of ω (relative) and of D (absolute) between the
#: predictor and the solution of an accepted step; a larger one halves the
#: step, so that sharp turns are resolved and the path does not jump to
#: another solution
MAX_CORRECTION = 0.02
#: most pseudo-arclength steps around the folds of one failed step
ARCLENGTH_MAX_STEPS = 1000
#: pseudo-arclength: smallest cosine between the chords of successive
#: steps; a sharper bend halves the step
ARCLENGTH_MIN_COSINE = 0.8
#: pseudo-arclength: largest step (scaled: log a in grid spacings, ω
#: relative to the linear ω, the unknowns Y and D as they are), unless the
#: last natural step was larger
ARCLENGTH_MAX_STEP = 0.25
#: a fold-passing path on which a higher harmonic grows to this multiple of
#: the fundamental (mass norm) has turned into a k:1 internal resonance
#: (a higher mode at k ω; the fundamental tends to 0 along it) and is not
#: followed further; loops of the path about a near-resonance reach about
#: 1.3 (the spring chain of issue 16 with kt = 500)
RESONANCE_RATIO = 4.0
#: a fold-passing path that fails (Newton, at a kink of the path) after a
#: higher harmonic has outgrown the fundamental by this factor (mass norm)
#: has entered a k:1 internal resonance: the run stops with that reason
#: (the spring chain of issue 16 with kt = 5e4: harmonic 5 up to 2.6 times
#: the fundamental, then a kink at a = 1.95e-4 that the path cannot pass)
RESONANCE_FAILED_RATIO = 1.0
#: the upper piece's start (the slipped linear mode, D from its energy
#: balance) is kept when its D lands within this fraction of the contacts'
#: estimated share of D from the guess; else it starts 10 times higher
SLIPPED_START_TOLERANCE = 0.1
#: most fold passages along one mode
MAX_FOLDS = 8
#: relative distance between the first point's ω and the linear pulsation
#: of the mode above which the start is reported (:func:`_start_notes`):
#: a step may move ω by ``MAX_CORRECTION`` at most, so the mode at ``a``
#: low has already left the linear one there, or never tends to it (a
#: contact that touches at rest: the bilinear motion, bench/README.md
#: stop 28, 126.79 rad/s against 100)
START_OMEGA_TOL = 0.05
#: how far below the first amplitude the start may back off (factor 10 per
#: try) when the linear mode is not a good enough guess there
START_BACKOFF = 8


@dataclass
class NonlinearMode:
    """A nonlinear mode: frequency and damping ratio against amplitude.

    Attributes
    ----------
    amplitude : ndarray, shape (n_points,)
        Modal amplitude ``a`` (fundamental harmonic in the mass norm,
        ``√(Xc1ᵀ M Xc1 + Xs1ᵀ M Xs1)``), m √kg (for one DOF of mass
        1 kg: m).
    omega : ndarray, shape (n_points,)
        Pulsation of the periodic motion, rad/s.
    damping_ratio : ndarray, shape (n_points,)
        Equivalent modal damping ratio ``D`` (dimensionless).
    coefficients : ndarray, shape (n_points, n_dof, n_coef)
        Fourier coefficients of every DOF, m (layout of
        :mod:`hbmfric.kernels.fourier.dft`).
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    mode : int
        Number of the linear mode (1 = lowest, of the structure with the
        contacts stuck) the nonlinear mode starts from.
    linear_omega, linear_damping_ratio : float
        That linear mode's undamped pulsation (rad/s) and its damping ratio
        ``φᵀ C φ / (2 ω)`` (0 with ``structural_damping=False``).
    requested : tuple of float
        The asked amplitude range ``(low, high)``.
    stop_reason : str
        ``"range reached"`` or why the continuation stopped.
    newton_iterations : ndarray of int, shape (n_points,)
        Newton iterations of each point's last solve.
    n_steps, n_rejected : int
        Continuation steps taken and rejected (sub-steps included).
    elapsed : float
        Wall time, s.
    info : dict
        Description of the run (harmonics, n_time, AFT scheme, damping
        convention).
    dof_names : dict
        Named DOFs of the system.
    folds : ndarray, shape (n_folds,)
        Modal amplitudes of the turning points of the backbone in ``a``
        (where it has several solutions at one amplitude), found and passed
        by pseudo-arclength continuation; empty for none.
    fold_path : ndarray, shape (n_path, 3)
        The points of that pseudo-arclength continuation around the folds,
        columns ``a``, ``ω`` (rad/s), ``D``, in path order (the grid
        points hold one solution per amplitude; these show the others).
    pieces : ndarray of int, shape (n_pieces,), optional
        Index of the first point of each continued piece, increasing in
        amplitude; None for one piece. Two pieces when the continuation
        from the stuck side stopped at an internal resonance and the upper
        branch was continued down from the top of the range
        (``upper_branch=True``): :attr:`gaps` holds the amplitudes between
        them, which no point covers.
    truncation_error : ndarray, shape (n_points,), optional
        Estimated truncation error of each point: the larger of the
        relative error of ω and the absolute error of D (both errors of
        the mode's eigenvalue ``-Dω ± iω`` relative to ω), from one Newton
        step of the EPMC equations in the basis ``2H + 1``; 0 for a linear
        point. None when not estimated (``harmonic_tolerance=None``).
    load_vector : ndarray of complex, shape (n_dof,), optional
        The system's load per unit forcing amplitude, ``Re(p e^{iΩt})``,
        for :meth:`resonances`; None when the system has none.
    """

    amplitude: np.ndarray
    omega: np.ndarray
    damping_ratio: np.ndarray
    coefficients: np.ndarray
    harmonic_numbers: np.ndarray
    mode: int
    linear_omega: float
    linear_damping_ratio: float
    requested: tuple
    stop_reason: str
    newton_iterations: np.ndarray
    n_steps: int
    n_rejected: int
    elapsed: float
    info: dict = field(default_factory=dict)
    dof_names: dict = field(default_factory=dict)
    load_vector: np.ndarray | None = None
    truncation_error: np.ndarray | None = None
    folds: np.ndarray = field(default_factory=lambda: np.empty(0))
    fold_path: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))
    pieces: np.ndarray | None = None
    #: the mass matrix, shape (n_dof, n_dof), kg (for the energies)
    _mass: np.ndarray | None = field(default=None, repr=False, compare=False)

    def __len__(self) -> int:
        return int(self.amplitude.size)

    @property
    def frequency(self) -> np.ndarray:
        """Frequency of the periodic motion, Hz, shape (n_points,)."""
        return self.omega / (2.0 * np.pi)

    @property
    def complete(self) -> bool:
        """The points cover the requested amplitude range (one piece, no
        gap)."""
        return self.stop_reason == "range reached"

    def piece_slices(self) -> list[slice]:
        """The points of each piece (see :attr:`pieces`), in amplitude
        order."""
        n = len(self)
        starts = [0] if self.pieces is None else [int(i) for i in self.pieces]
        ends = starts[1:] + [n]
        return [slice(a, b) for a, b in zip(starts, ends, strict=True)]

    @property
    def gaps(self) -> list[tuple[float, float]]:
        """Parts ``(low, high)`` of the requested amplitude range that no
        piece covers, m √kg, increasing (a piece covers the amplitudes
        between its first and last point): between two pieces, and above
        the last point of a run that stopped short. Empty when complete."""
        lo, hi = self.requested
        if len(self) == 0:
            return [(lo, hi)]
        gaps, edge = [], lo
        for sl in self.piece_slices():
            a0, a1 = float(self.amplitude[sl][0]), float(self.amplitude[sl][-1])
            if a0 > edge * (1.0 + 1e-12):
                gaps.append((edge, a0))
            edge = max(edge, a1)
        if hi > edge * (1.0 + 1e-12):
            gaps.append((edge, hi))
        return gaps

    def dof_amplitude(self, dof=None, harmonic: int = 1) -> np.ndarray:
        """Amplitude of one harmonic of one DOF along the mode, m.

        Parameters
        ----------
        dof : int, str or None
            DOF index or name; None: the contact DOF.
        harmonic : int
            Harmonic number (0: the mean, absolute value).

        Returns
        -------
        ndarray, shape (n_points,)
        """
        if dof is None:
            d = int(self.info.get("contact_dof", 0))
        elif isinstance(dof, str):
            if dof not in self.dof_names:
                raise ValueError(
                    f"unknown DOF name {dof!r}; known: {sorted(self.dof_names)}"
                )
            d = self.dof_names[dof]
        else:
            d = int(dof)
        n_dof = self.coefficients.shape[1]
        if not 0 <= d < n_dof:
            raise ValueError(f"dof must be in [0, {n_dof}), got {d}")
        cols = coefficient_columns(self.harmonic_numbers)
        if harmonic not in cols:
            raise ValueError(
                f"harmonic {harmonic} is not among the solved harmonics "
                f"{self.harmonic_numbers.tolist()}"
            )
        c = cols[harmonic]
        X = self.coefficients[:, d]
        if harmonic == 0:
            return np.abs(X[:, c])
        return np.hypot(X[:, c], X[:, c + 1])

    def supplied_energy(self) -> np.ndarray:
        """Energy the EPMC term ``2 D ω M ẋ`` supplies per cycle, J, shape
        (n_points,): ``2π D ω² Σ_k k² (Xc_kᵀ M Xc_k + Xs_kᵀ M Xs_k)``, equal
        to what the structure (or, with ``structural_damping=False``, the
        contacts) dissipate along the motion."""
        out = np.zeros(len(self))
        col = 0
        for k in self.harmonic_numbers:
            if k == 0:
                col += 1
                continue
            for c in (col, col + 1):
                X = self.coefficients[:, :, c]
                out += k * k * np.einsum("pi,ij,pj->p", X, self._mass, X)
            col += 2
        return 2.0 * np.pi * self.damping_ratio * self.omega**2 * out

    def resonances(self, force: float) -> tuple[np.ndarray, np.ndarray]:
        """Resonances of the forced system predicted from the mode.

        Under the load ``force * Re(p e^{iΩt})`` (``p`` = :attr:`load_vector`), a
        phase resonance on the mode does the most work per cycle,
        ``π a force |pᴴ ψ|`` (``ψ = (Xc1 − i Xs1) / a``), and that balances
        the dissipated energy (:meth:`supplied_energy`). The amplitudes
        where the two are equal (linear interpolation in ``log a`` between
        the points) are the FRF peaks of a lightly damped system, at the
        backbone's ``ω`` there.

        Parameters
        ----------
        force : float
            Forcing amplitude ``F``, N.

        Returns
        -------
        omega : ndarray, shape (n_found,)
            Pulsations of the resonances, rad/s.
        amplitude : ndarray, shape (n_found,)
            Their modal amplitudes, m √kg (increasing).

        Warns
        -----
        CoverageWarning
            When none is found: the resonance lies outside the mode's
            amplitudes (the message gives the forces balanced there); or
            when the energy balance changes sign across a gap between two
            pieces (:attr:`gaps`), where a resonance may lie that no point
            locates (not returned).
        AccuracyWarning
            When at a resonance found the harmonics above the first carry
            more than :data:`HIGHER_SHARE_TOL` of ``Σ_k k² |X_k|²_M``: the
            prediction assumes a nearly harmonic mode.
        """
        force = finite_float("force", force, low=0.0, low_open=True)
        if self.load_vector is None or not np.any(self.load_vector):
            raise ValueError("the system has no load vector: no resonance")
        if len(self) < 2:
            return np.empty(0), np.empty(0)
        col = coefficient_columns(self.harmonic_numbers)[1]
        psi = (
            self.coefficients[:, :, col] - 1j * self.coefficients[:, :, col + 1]
        ) / self.amplitude[:, None]
        modal = np.abs(psi @ np.conj(self.load_vector))
        with np.errstate(divide="ignore"):
            needed = self.supplied_energy() / (np.pi * self.amplitude * modal)
        g = needed - force
        s = np.log(self.amplitude)
        higher = self._higher_share()
        omega, amp, in_gaps, shares, spreads = [], [], [], [], []
        # no interpolation across the gap between two pieces (but a sign
        # change there is said: a resonance may lie in the gap)
        slices = self.piece_slices()
        last = {sl.stop - 1 for sl in slices}
        for i in np.flatnonzero(np.sign(g[1:]) != np.sign(g[:-1])):
            if not (np.isfinite(g[i]) and np.isfinite(g[i + 1])):
                continue
            if i in last:
                in_gaps.append((float(self.amplitude[i]), float(self.amplitude[i + 1])))
                continue
            u = g[i] / (g[i] - g[i + 1])
            amp.append(float(np.exp(s[i] + u * (s[i + 1] - s[i]))))
            omega.append(float(self.omega[i] + u * (self.omega[i + 1] - self.omega[i])))
            shares.append(float(max(higher[i], higher[i + 1])))
            piece = next(sl for sl in slices if sl.start <= i < sl.stop)
            spreads.append(_crossing_spread(g, i, float(s[i + 1] - s[i]), piece))
        if in_gaps:
            where = ", ".join(f"{a0:.4g} to {a1:.4g}" for a0, a1 in in_gaps)
            warnings.warn(
                f"at force = {force:.6g} N the balance of supplied and "
                f"dissipated energy changes sign across the gap a = {where} "
                "between the mode's pieces, which no point covers: a resonance "
                f"may lie there and is not returned ({len(omega)} found "
                "elsewhere); trace the forced response there with hf.frf",
                CoverageWarning,
                stacklevel=2,
            )
        elif not omega:
            finite = needed[np.isfinite(needed)]
            span = (
                f"{np.min(finite):.4g} to {np.max(finite):.4g} N"
                if finite.size
                else "not finite"
            )
            warnings.warn(
                f"no resonance at force = {force:.6g} N within the mode's "
                f"amplitudes {self.amplitude[0]:.4g} to {self.amplitude[-1]:.4g} "
                f"(the forces balanced there: {span}); extend the amplitude "
                "range of hf.nonlinear_mode",
                CoverageWarning,
                stacklevel=2,
            )
        if spreads and max(spreads) > RESONANCE_SPREAD_TOL:
            worst = int(np.argmax(spreads))
            k = int(np.searchsorted(self.amplitude, amp[worst]))
            a0 = self.amplitude[max(k - 1, 0)]
            a1 = self.amplitude[min(k, len(self) - 1)]
            warnings.warn(
                f"at force = {force:.6g} N the resonance at a = {amp[worst]:.4g} "
                f"(Ω = {omega[worst]:.6g} rad/s) lies where the energy balance "
                f"bends sharply between the mode's points a = {a0:.4g} and "
                f"{a1:.4g} (a change of the contacts' stick/slip state near it, "
                "or points too sparse for the bend): "
                f"the interpolated amplitude may be off by up to {spreads[worst]:.1%} "
                "(the whole interval at a kink of the balance); "
                "give hf.nonlinear_mode more points there (or a narrower "
                "amplitude range), or check it with hf.frf",
                AccuracyWarning,
                stacklevel=2,
            )
        if shares and max(shares) > HIGHER_SHARE_TOL:
            worst = int(np.argmax(shares))
            warnings.warn(
                f"at force = {force:.6g} N the resonance at a = {amp[worst]:.4g} "
                f"(Ω = {omega[worst]:.6g} rad/s) lies where the harmonics above "
                f"the first carry {shares[worst]:.0%} of the mode's supplied "
                "energy weight Σ k² |X_k|²: the EPMC's damping term drives them "
                "too, the forcing does not, so the predicted amplitude may be "
                "far off (an internal resonance, or strongly non-harmonic "
                "motion); check it with hf.frf or hf.periodic_solution",
                AccuracyWarning,
                stacklevel=2,
            )
        return np.array(omega), np.array(amp)

    def _higher_share(self) -> np.ndarray:
        """Share of the harmonics above the first in ``Σ_k k² (Xc_kᵀ M Xc_k
        + Xs_kᵀ M Xs_k)`` at each point, shape (n_points,) (0 where the
        sum is 0)."""
        total = np.zeros(len(self))
        first = np.zeros(len(self))
        col = 0
        for k in self.harmonic_numbers:
            if k == 0:
                col += 1
                continue
            term = np.zeros(len(self))
            for c in (col, col + 1):
                X = self.coefficients[:, :, c]
                term += k * k * np.einsum("pi,ij,pj->p", X, self._mass, X)
            total += term
            if k == 1:
                first += term
            col += 2
        out = np.zeros(len(self))
        np.divide(total - first, total, out=out, where=total > 0.0)
        return out

    def save(self, path: str | Path) -> Path:
        """Write the mode to ``path`` (``.npz``, no pickle); returns the
        path written."""
        path = Path(path)
        meta = {
            "format": FORMAT,
            "mode": self.mode,
            "linear_omega": self.linear_omega,
            "linear_damping_ratio": self.linear_damping_ratio,
            "requested": list(self.requested),
            "stop_reason": self.stop_reason,
            "n_steps": self.n_steps,
            "n_rejected": self.n_rejected,
            "elapsed": self.elapsed,
            "info": self.info,
            "dof_names": self.dof_names,
        }
        arrays = {
            "amplitude": self.amplitude,
            "omega": self.omega,
            "damping_ratio": self.damping_ratio,
            "coefficients": self.coefficients,
            "harmonic_numbers": self.harmonic_numbers,
            "newton_iterations": self.newton_iterations,
            "meta": np.array(json.dumps(meta)),
        }
        if self.load_vector is not None:
            arrays["load_vector"] = self.load_vector
        if self.truncation_error is not None:
            arrays["truncation_error"] = self.truncation_error
        arrays["folds"] = self.folds
        arrays["fold_path"] = self.fold_path
        if self.pieces is not None:
            arrays["pieces"] = self.pieces
        if self._mass is not None:
            arrays["mass"] = self._mass
        np.savez(path, **arrays)
        return path if path.suffix == ".npz" else path.with_suffix(path.suffix + ".npz")

    @classmethod
    def load(cls, path: str | Path) -> NonlinearMode:
        """Read a mode written by :meth:`save` (no pickle).

        Raises
        ------
        ValueError
            If ``path`` is not a readable nonlinear-mode file.
        """
        check_npz_sizes(path, "nonlinear-mode")
        try:
            with np.load(Path(path), allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                if not isinstance(meta, dict) or meta.get("format") != FORMAT:
                    raise ValueError("wrong format tag")
                mode = cls(
                    amplitude=stored_array(data, "amplitude", np.float64),
                    omega=stored_array(data, "omega", np.float64),
                    damping_ratio=stored_array(data, "damping_ratio", np.float64),
                    coefficients=stored_array(data, "coefficients", np.float64),
                    harmonic_numbers=stored_array(data, "harmonic_numbers", np.int64),
                    mode=int(meta["mode"]),
                    linear_omega=float(meta["linear_omega"]),
                    linear_damping_ratio=float(meta["linear_damping_ratio"]),
                    requested=tuple(float(v) for v in meta["requested"]),
                    stop_reason=str(meta["stop_reason"]),
                    newton_iterations=stored_array(data, "newton_iterations", np.int64),
                    n_steps=int(meta["n_steps"]),
                    n_rejected=int(meta["n_rejected"]),
                    elapsed=float(meta["elapsed"]),
                    info=dict(meta["info"]),
                    dof_names={str(k): int(v) for k, v in meta["dof_names"].items()},
                    load_vector=optional_array(data, "load_vector", np.complex128),
                    folds=optional_array(data, "folds", np.float64, np.empty(0)),
                    fold_path=optional_array(
                        data, "fold_path", np.float64, np.empty((0, 3))
                    ),
                    pieces=optional_array(data, "pieces", np.int64),
                    truncation_error=optional_array(
                        data, "truncation_error", np.float64
                    ),
                    _mass=optional_array(data, "mass", np.float64),
                )
        except READ_ERRORS as exc:
            raise ValueError(
                f"path {str(path)!r} is not an hbmfric nonlinear-mode file, or is "
                f"damaged ({exc})"
            ) from None
        _check_mode_arrays(path, mode)
        return mode

    def plot(self, axes=None, hz: bool = False, **kwargs):
        """Frequency and damping ratio against the modal amplitude
        (logarithmic amplitude axis); returns the two axes.

        Parameters
        ----------
        axes : sequence of two matplotlib axes, optional
            Where to draw; new figure with two panels when None.
        hz : bool
            Frequency in Hz instead of rad/s.
        **kwargs
            Passed to ``Axes.plot`` for both curves.
        """
        import matplotlib.pyplot as plt

        if axes is None:
            _, axes = plt.subplots(2, 1, sharex=True)
        ax_w, ax_d = axes
        w = self.frequency if hz else self.omega
        color = kwargs.pop("color", None)
        for i, sl in enumerate(self.piece_slices()):
            # one line per piece (the gap between them stays empty), in
            # one colour, one legend entry
            kw = dict(kwargs) if i == 0 else {**kwargs, "label": "_nolegend_"}
            if color is not None:
                kw["color"] = color
            (line,) = ax_w.plot(self.amplitude[sl], w[sl], **kw)
            color = line.get_color()
            ax_d.plot(
                self.amplitude[sl], self.damping_ratio[sl], **{**kw, "color": color}
            )
        ax_w.set_xscale("log")
        ax_d.set_xscale("log")
        ax_w.set_ylabel("frequency (Hz)" if hz else "ω (rad/s)")
        ax_d.set_ylabel("damping ratio D")
        ax_d.set_xlabel("modal amplitude a (m √kg)")
        ax_w.set_title(f"nonlinear mode {self.mode}")
        return ax_w, ax_d

    def to_csv(self, path: str | Path) -> Path:
        """Write amplitude, ω (rad/s), frequency (Hz), damping ratio, the
        first-harmonic amplitude of the contact DOF (m) and the piece number
        (0, or 1 for the upper branch past an internal resonance), one row
        per point; returns the path."""
        path = Path(path)
        contact = self.dof_amplitude(None, 1) if len(self) else np.empty(0)
        with path.open("w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(
                [
                    "amplitude",
                    "omega_rad_s",
                    "frequency_hz",
                    "damping_ratio",
                    "contact_dof_amplitude",
                    "piece",
                ]
            )
            piece = np.zeros(len(self), dtype=int)
            for i, sl in enumerate(self.piece_slices()):
                piece[sl] = i
            for i, row in enumerate(
                zip(
                    self.amplitude,
                    self.omega,
                    self.frequency,
                    self.damping_ratio,
                    contact,
                    strict=True,
                )
            ):
                writer.writerow([repr(float(v)) for v in row] + [int(piece[i])])
        return path


def _crossing_spread(g: np.ndarray, i: int, width: float, piece: slice) -> float:
    """Estimated error of the chord's zero of the balance ``g`` between
    points ``i`` and ``i + 1``, in ``log a`` (about the relative error of
    the amplitude).

    Where the change of ``g`` over a neighbouring interval (``i − 1, i`` or
    ``i + 1, i + 2``) differs from its change over the crossing interval by
    more than a factor :data:`KINK_RATIO` (or in sign), the balance has a
    kink about the interval (a contact starting to slip: no friction loss
    below, a steep rise above) and the zero can lie anywhere in it: the
    whole ``width`` is returned. (A kink in a neighbouring interval counts
    too: four points cannot tell where it is.) Else the balance is taken as
    smooth and the chord's error as twice that of a parabola,
    ``u (1 − u) width · max|Δ²g| / |Δg|`` (``u`` the chord's zero within
    the interval, ``Δ²g`` the second differences about it). 0 when the
    piece has no neighbouring interval.

    Parameters
    ----------
    g : ndarray, shape (n_points,)
        The balance (needed minus applied force), N, on the mode's
        log-spaced amplitudes.
    i : int
        The crossing interval.
    width : float
        ``log a[i + 1] − log a[i]``.
    piece : slice
        The points of the piece that holds the interval.

    Returns
    -------
    float
    """
    change = g[i + 1] - g[i]
    if not abs(change) > 0.0:
        return 0.0
    sides = [
        g[j + 1] - g[j]
        for j in (i - 1, i + 1)
        if j >= piece.start and j + 1 < piece.stop and np.isfinite(g[j])
    ]
    sides = [d for d in sides if np.isfinite(d)]
    if not sides:
        return 0.0
    for d in sides:
        ratio = d / change
        if not 1.0 / KINK_RATIO <= ratio <= KINK_RATIO:
            return float(width)
    u = g[i] / (g[i] - g[i + 1])
    bend = max(abs(d - change) for d in sides)
    return float(min(width, u * (1.0 - u) * width * bend / abs(change)))


def _stuck_stiffness(problem: HBMProblem) -> np.ndarray:
    """``K`` plus the stuck stiffness of every contact, shape (n_dof, n_dof)."""
    K = problem._matrices[2].copy()
    for law, a, b, a_n, b_n in problem._contacts:
        for k, (p, q) in zip(
            _stuck_stiffnesses(law), ((a, b), (a_n, b_n)), strict=False
        ):
            if p < 0:
                continue
            K[p, p] += k
            if q >= 0:
                K[q, q] += k
                K[p, q] -= k
                K[q, p] -= k
    return K


class _EPMC:
    """The EPMC equations of a system: residual and Jacobian in the scaled
    unknowns ``z = [Y, ω, D]`` (``Y = X / a``) at a given amplitude ``a``."""

    def __init__(self, system, mode, harmonics, n_time, aft, structural_damping):
        import scipy.linalg

        data = check_system(system)
        problem = HBMProblem(system, 0.0, harmonics, n_time, None, aft, _checked=data)
        if any(c[0].code == COULOMB for c in problem._contacts):
            raise ValueError(
                "nonlinear modes of a rigid Coulomb contact (DLFT) are not "
                "available: the stuck contact has no linear mode to start from; "
                "use an elastic law (hf.Jenkins with a large stiffness)"
            )
        self.problem = problem
        try:
            self.load = check_load(system, 1.0, data.n_dof, data.load_phase)
        except (AttributeError, TypeError, ValueError):
            self.load = None
        kp = problem.kernel_problem
        mass, damping = kp[1], kp[2]
        if not structural_damping:
            damping = np.zeros_like(damping)
            fields = (*kp[:2], damping, *kp[3:])
            # keep the problem's type (an AFT family's compiles less)
            kp = type(kp)(*fields) if hasattr(kp, "_fields") else fields
        self.kernel_problem = kp
        self.n_dof = problem.n_dof
        self.n_coef = problem.n_coef
        self.n = problem.n_unknowns
        n_dof, n_coef = self.n_dof, self.n_coef
        hn = problem.harmonic_numbers
        self.md = np.kron(mass, derivative_operator(hn, 1.0))
        col1 = coefficient_columns(hn)[1]
        self.cos1 = np.arange(n_dof) * n_coef + col1
        self.sin1 = self.cos1 + 1
        self.mass = mass
        K = _stuck_stiffness(problem)
        try:
            w2, vecs = scipy.linalg.eigh(K, mass)
        except (np.linalg.LinAlgError, ValueError) as exc:
            raise ValueError(
                "the linear modes of the stuck structure cannot be computed "
                f"(mass matrix not positive definite?): {exc}"
            ) from None
        if mode > n_dof:
            raise ValueError(f"mode must be <= n_dof = {n_dof}, got {mode}")
        w2_j = float(w2[mode - 1])
        if not w2_j > 0.0:
            raise ValueError(
                f"linear mode {mode} of the stuck structure has ω² = {w2_j:.3g}: "
                "a rigid-body mode has no nonlinear mode"
            )
        phi = vecs[:, mode - 1]
        phi = phi / np.sqrt(phi @ mass @ phi)
        if phi[np.argmax(np.abs(phi))] < 0.0:
            phi = -phi
        self.phi = phi
        self.m_phi = mass @ phi
        self.linear_omega = float(np.sqrt(w2_j))
        #: pulsations of all linear modes of the stuck structure, rad/s
        self.stuck_omegas = np.sqrt(np.clip(w2, 0.0, None))
        self.harmonic_columns = coefficient_columns(hn)
        self.linear_damping = float(phi @ damping @ phi) / (2.0 * self.linear_omega)
        self.K_stuck = K
        self.force_scale = float(np.max(np.abs(K)))
        # the static equilibrium the mode vibrates about: the system's own
        # (``static_solution`` hook), else 0 (a static load may be held by
        # the contacts' preload, which K alone does not know); Newton finds
        # the mean from there
        # the same mode of the structure with its contacts slipping freely
        # (no contact stiffness): the large-amplitude limit, where the upper
        # piece of a mode cut by an internal resonance starts
        self.slipped_phi = None
        w2_free, vecs_free = scipy.linalg.eigh(problem._matrices[2], mass)
        if float(w2_free[mode - 1]) > 0.0:
            psi = vecs_free[:, mode - 1]
            psi = psi / np.sqrt(psi @ mass @ psi)
            if psi @ self.m_phi < 0.0:
                psi = -psi
            self.slipped_phi = psi
            self.slipped_omega = float(np.sqrt(w2_free[mode - 1]))
            self.slipped_damping = float(psi @ damping @ psi) / (
                2.0 * self.slipped_omega
            )
        self.static = None
        hook = getattr(system, "static_solution", None)
        if problem._static is not None and hn[0] == 0 and hook is not None:
            self.static = np.asarray(hook(), dtype=float).reshape(n_dof)

    def linear_guess(self, a: float) -> np.ndarray:
        """``z`` of the linear mode at amplitude ``a``."""
        z = np.zeros(self.n + 2)
        z[self.cos1] = self.phi
        if self.static is not None:
            z[: self.n : self.n_coef] = self.static / a
        z[self.n] = self.linear_omega
        z[self.n + 1] = self.linear_damping
        return z

    def slipped_guess(self, a: float) -> np.ndarray:
        """``z`` of the linear mode of the structure with the contacts
        slipping freely at amplitude ``a`` (needs ``slipped_phi``)."""
        n = self.n
        z = self.linear_guess(a)
        z[self.cos1] = self.slipped_phi
        z[n] = self.slipped_omega
        z[n + 1] = self.slipped_damping
        # D from the energy balance of that motion (the HBM rows projected
        # on its velocity): the contacts' dissipation can be many times the
        # structure's, and Newton from the structural D alone may cycle
        F, _, state = self.equations(z, a)
        v = (self.md @ z[:n]) * a
        vv = float(v @ v)
        if state >= 0 and np.all(np.isfinite(F)) and vv > 0.0:
            s = 1.0 / (a * self.force_scale)
            w2 = z[n] ** 2
            rhs = F[:n] / s + 2.0 * z[n + 1] * w2 * v
            z[n + 1] = float(v @ rhs) / (2.0 * w2 * vv)
        return z

    def equations(self, z: np.ndarray, a: float):
        """Residual (shape (n + 2,)) and Jacobian (shape (n + 2, n + 2)) at
        ``z = [Y, ω, D]``; the HBM rows divided by ``a`` times the force
        scale. Returns ``(F, J, state)``."""
        n = self.n
        y = np.empty(n + 1)
        y[:n] = a * z[:n]
        omega, ratio = z[n], z[n + 1]
        y[n] = omega
        R = np.empty(n)
        Jh = np.empty((n, n + 1))
        state = int(hbm_residual(y, self.kernel_problem, R, Jh))
        v = self.md @ y[:n]
        F = np.empty(n + 2)
        J = np.zeros((n + 2, n + 2))
        s = 1.0 / (a * self.force_scale)
        F[:n] = (R - 2.0 * ratio * omega**2 * v) * s
        J[:n, :n] = (Jh[:, :n] - 2.0 * ratio * omega**2 * self.md) * (a * s)
        J[:n, n] = (Jh[:, n] - 4.0 * ratio * omega * v) * s
        J[:n, n + 1] = -2.0 * omega**2 * v * s
        yc, ys = z[self.cos1], z[self.sin1]
        mc, ms = self.mass @ yc, self.mass @ ys
        F[n] = yc @ mc + ys @ ms - 1.0
        J[n, self.cos1] = 2.0 * mc
        J[n, self.sin1] = 2.0 * ms
        F[n + 1] = self.m_phi @ ys
        J[n + 1, self.sin1] = self.m_phi
        return F, J, state

    def padded(self, z: np.ndarray, small: _EPMC) -> np.ndarray:
        """``z`` of ``small`` (a smaller basis of the same system) in this
        basis, the extra harmonics 0."""
        out = np.zeros(self.n + 2)
        big = coefficient_columns(self.problem.harmonic_numbers)
        cols = coefficient_columns(small.problem.harmonic_numbers)
        Y = z[: small.n].reshape(small.n_dof, small.n_coef)
        W = out[: self.n].reshape(self.n_dof, self.n_coef)
        for k, c in cols.items():
            width = 1 if k == 0 else 2
            W[:, big[k] : big[k] + width] = Y[:, c : c + width]
        out[self.n :] = z[small.n :]
        return out

    def truncation_error(self, z: np.ndarray, a: float, small: _EPMC) -> float:
        """Estimated truncation error of the point ``z`` of ``small`` at
        amplitude ``a``: the change of ω (relative) and D (absolute) in one
        Newton step in this (larger) basis; inf if the step fails."""
        zp = self.padded(z, small)
        F, J, state = self.equations(zp, a)
        if state < 0 or not np.all(np.isfinite(F)):
            return np.inf
        try:
            dz = np.linalg.solve(J, -F)
        except np.linalg.LinAlgError:
            return np.inf
        n = self.n
        err = max(abs(dz[n]) / zp[n], abs(dz[n + 1]))
        return float(err) if np.isfinite(err) else np.inf

    def solve_arclength(self, u_pred, tangent, scale):
        """Newton on the EPMC equations plus the pseudo-arclength condition
        ``tangentᵀ ((u − u_pred) · scale) = 0`` in ``u = [z, log a]``:
        ``(u, iterations)``, ``u`` None when it does not converge."""
        n = self.n
        big = np.zeros((n + 3, n + 3))
        rhs = np.empty(n + 3)

        def system(u):
            """The bordered residual ``rhs = -[F, arclength]`` and matrix
            at ``u``; None where the AFT fails or ``log a`` ran off."""
            if not -700.0 < u[n + 2] < 700.0:
                return None
            F, J, state = self.equations(u[: n + 2], float(np.exp(u[n + 2])))
            if state < 0 or not np.all(np.isfinite(F)):
                return None
            big[: n + 2, : n + 2] = J
            big[: n + 2, n + 2] = 0.0
            # d/d(log a) of the HBM rows F = R(aY) / (a f): J_YY Y - F
            big[:n, n + 2] = J[:n, :n] @ u[:n] - F[:n]
            big[n + 2] = tangent * scale
            rhs[: n + 2] = -F
            rhs[n + 2] = -float(tangent @ ((u - u_pred) * scale))
            return float(np.max(np.abs(rhs)))

        u = u_pred.copy()
        res = system(u)
        if res is None:
            return None, 0
        previous = np.inf
        for it in range(1, MAX_ITERATIONS + 1):
            try:
                du = np.linalg.solve(big, rhs)
            except np.linalg.LinAlgError:
                return None, it
            if not np.all(np.isfinite(du)):
                return None, it
            # as in solve: plain steps first, then a backtracking line
            # search (at a change of the stick/slip pattern the Jacobian
            # jumps and plain Newton cycles between two corrections)
            lam = 1.0
            while True:
                u_try = u + lam * du
                res_try = system(u_try)
                if res_try is not None and (
                    it <= PLAIN_ITERATIONS
                    or res_try <= (1.0 - 1e-4 * lam) * res
                    or res <= RESIDUAL_FLOOR
                ):
                    break
                if lam <= MIN_LAMBDA:
                    # no descent along the correction (a kink of the
                    # residual): the point stands if its residual does,
                    # else give up (not 30 more full line searches)
                    ok = res <= RESIDUAL_TOLERANCE and u[n] > 0.0
                    return (u if ok else None), it
                lam *= 0.5
            u, res = u_try, res_try
            size = lam * float(np.max(np.abs(du * scale)))
            if size <= STEP_TOLERANCE or (
                size <= STALL_TOLERANCE and size > 0.5 * previous
            ):
                ok = res <= RESIDUAL_TOLERANCE and u[n] > 0.0
                return (u if ok else None), it
            previous = size
        return None, MAX_ITERATIONS

    def dominant_harmonic(self, z: np.ndarray) -> tuple[int, float]:
        """The higher harmonic (``k >= 2``) of largest mass-norm amplitude
        at the point ``z`` and that amplitude relative to the fundamental's
        (``√(Yc_kᵀ M Yc_k + Ys_kᵀ M Ys_k)``; the fundamental's is 1):
        ``(k, ratio)``, ``(0, 0.0)`` for a single-harmonic basis."""
        Y = z[: self.n].reshape(self.n_dof, self.n_coef)
        best, ratio = 0, 0.0
        for k, c in self.harmonic_columns.items():
            if k < 2:
                continue
            yc, ys = Y[:, c], Y[:, c + 1]
            r = float(np.sqrt(yc @ self.mass @ yc + ys @ self.mass @ ys))
            if r > ratio:
                best, ratio = int(k), r
        return best, ratio

    def resonance_reason(self, z: np.ndarray, a: float, k: int, ratio: float) -> str:
        """Why a path whose harmonic ``k`` grew to ``ratio`` times the
        fundamental at ``(z, a)`` stops: a ``k:1`` internal resonance,
        naming the linear mode of the stuck structure nearest to ``k ω``."""
        omega = float(z[self.n])
        j = int(np.argmin(np.abs(self.stuck_omegas - k * omega)))
        return (
            f"{k}:1 internal resonance: past the turning point the path "
            f"follows harmonic {k}, which grows to {ratio:.2g} times "
            f"the fundamental at a = {a:.4g} ({k} ω = {k * omega:.5g} rad/s; "
            f"linear mode {j + 1} of the stuck structure: "
            f"{self.stuck_omegas[j]:.5g} rad/s), "
            "towards another mode rather than to larger amplitudes"
        )

    def correlation(self, z1: np.ndarray, z2: np.ndarray) -> float:
        """Modal assurance criterion of the fundamental shapes of two
        points, ``|ψ1ᴴ M ψ2|²`` (each of unit mass norm): 1 for the same
        shape, 0 for mass-orthogonal ones."""
        p1 = z1[self.cos1] - 1j * z1[self.sin1]
        p2 = z2[self.cos1] - 1j * z2[self.sin1]
        return float(abs(np.conj(p1) @ (self.mass @ p2)) ** 2)

    def solve(self, z0: np.ndarray, a: float):
        """Newton with a backtracking line search from ``z0`` at amplitude
        ``a``: ``(z, iterations)``, ``z`` None when it does not converge.

        After ``PLAIN_ITERATIONS`` full steps (the first one may well raise
        the residual: the normalisation is quadratic) a line search halves
        the correction until the largest residual decreases: near a change
        of the contacts' stick/slip pattern the Jacobian jumps and a plain
        Newton iteration can cycle.
        """
        z = z0.copy()
        n = self.n
        F, J, state = self.equations(z, a)
        if state < 0 or not np.all(np.isfinite(F)):
            return None, 0
        res = float(np.max(np.abs(F)))
        previous = np.inf
        for it in range(1, MAX_ITERATIONS + 1):
            try:
                dz = np.linalg.solve(J, -F)
            except np.linalg.LinAlgError:
                return None, it
            if not np.all(np.isfinite(dz)):
                return None, it
            lam = 1.0
            while True:
                z_try = z + lam * dz
                F_try, J_try, state = self.equations(z_try, a)
                good = state >= 0 and bool(np.all(np.isfinite(F_try)))
                if good:
                    res_try = float(np.max(np.abs(F_try)))
                    if (
                        it <= PLAIN_ITERATIONS
                        or res_try <= (1.0 - 1e-4 * lam) * res
                        or res <= RESIDUAL_FLOOR
                        or lam <= MIN_LAMBDA
                    ):
                        break
                elif lam <= MIN_LAMBDA:
                    return None, it
                lam *= 0.5
            z, F, J, res = z_try, F_try, J_try, res_try
            y_size = max(float(np.max(np.abs(z[:n]))), 1e-300)
            size = lam * max(
                float(np.max(np.abs(dz[:n]))) / y_size,
                abs(dz[n]) / abs(z[n]),
                abs(dz[n + 1]),
            )
            # converged, or at the rounding floor (the corrections stop
            # shrinking below STALL_TOLERANCE: e.g. a small vibration about
            # a large static preload)
            if size <= STEP_TOLERANCE or (
                size <= STALL_TOLERANCE and size > 0.5 * previous
            ):
                ok = res <= RESIDUAL_TOLERANCE and z[n] > 0.0
                return (z if ok else None), it
            previous = size
        return None, MAX_ITERATIONS


def _pass_folds(epmc: _EPMC, history, s_fail: float, width: float):
    """Pseudo-arclength continuation in ``(z, log a)`` from the last two
    points of ``history`` until the path has turned back to increasing
    amplitudes beyond ``s_fail`` (where the natural continuation failed).

    Returns ``(path, folds, steps, rejected, reason)``: the points
    ``(s, z)`` of the path (None if it could not pass), the amplitudes of
    its turning points, the work, and why it stopped short (None when it
    passed, or failed before turning): a path on which a higher harmonic
    outgrows the fundamental has left the mode for an internal resonance (a
    higher mode whose frequency is a multiple of ω) and is not followed
    further; a path that turned and then fails (Newton, at a kink: the
    spring chain of issue 16 with kt = 5e4, or kt = 5e3 at 0.1 % damping)
    is named with its turning point, and with the internal resonance when
    a higher harmonic outgrew the fundamental on it
    (``RESONANCE_FAILED_RATIO``).
    """
    n = epmc.n
    scale = np.ones(n + 3)
    scale[n] = 1.0 / epmc.linear_omega
    scale[n + 2] = 1.0 / width
    (s0, z0), (s1, z1) = history[-2], history[-1]
    u_prev = np.append(z0, s0)
    u_last = np.append(z1, s1)
    chord = (u_last - u_prev) * scale
    # the last natural steps have shrunk before the turn: start from their
    # size, but let the steps grow to ARCLENGTH_MAX_STEP
    h = float(np.linalg.norm(chord))
    h_min = MIN_STEP_FRACTION * h
    h_max = max(h, ARCLENGTH_MAX_STEP)
    tangent = chord / h
    path, folds = [], []
    steps = rejected = 0
    # the largest higher harmonic met along the path: (ratio, k, u)
    strongest = (0.0, 0, u_last)

    def failed():
        """The stop of a path that cannot go on past its turning points:
        an internal resonance when a higher harmonic had outgrown the
        fundamental; None when it turned nowhere."""
        if not folds:
            return None, folds, steps, rejected, None
        ratio, k, u = strongest
        reason = f"the backbone turns back at a = {folds[0]:.4g}; "
        if ratio >= RESONANCE_FAILED_RATIO:
            a_k = float(np.exp(u[n + 2]))
            reason += epmc.resonance_reason(u[: n + 2], a_k, k, ratio) + "; "
        reason += (
            f"the path past the turning point fails at a = "
            f"{np.exp(u_last[n + 2]):.4g} (Newton, at a kink of the path)"
        )
        return None, folds, steps, rejected, reason

    while steps < ARCLENGTH_MAX_STEPS:
        u_pred = u_last + h * tangent / scale
        u_new, its = epmc.solve_arclength(u_pred, tangent, scale)
        steps += 1
        ok = u_new is not None and (
            epmc.correlation(u_last[: n + 2], u_new[: n + 2]) >= MAC_TOLERANCE
        )
        if not ok:
            rejected += 1
            h *= 0.5
            if h < h_min:
                return failed()
            continue
        chord = (u_new - u_last) * scale
        new_tangent = chord / np.linalg.norm(chord)
        if new_tangent @ tangent < ARCLENGTH_MIN_COSINE and h > 2.0 * h_min:
            # a sharp bend: resolve it with shorter steps
            rejected += 1
            h *= 0.5
            continue
        if np.sign(new_tangent[n + 2]) != np.sign(tangent[n + 2]):
            folds.append(float(np.exp(u_last[n + 2])))
        tangent, u_last = new_tangent, u_new
        path.append((float(u_new[n + 2]), u_new[: n + 2].copy()))
        if u_new[n + 2] > s_fail and tangent[n + 2] > 0.0:
            return path, folds, steps, rejected, None
        k, ratio = epmc.dominant_harmonic(u_new)
        if ratio > strongest[0]:
            strongest = (ratio, k, u_new)
        if ratio > RESONANCE_RATIO:
            reason = epmc.resonance_reason(
                u_new, float(np.exp(u_new[n + 2])), k, RESONANCE_RATIO
            )
            if folds:
                reason = f"the backbone turns back at a = {folds[0]:.4g}; {reason}"
            return None, folds, steps, rejected, reason
        if its <= 4:
            h = min(2.0 * h, h_max)
    return failed()


def _descend(epmc: _EPMC, grid: np.ndarray, floor: float):
    """Natural continuation of the upper piece: from the slipped linear
    mode at the top of ``grid`` (log a, increasing) down the grid, not
    below ``floor`` (log a; grid points at or below it are left to the
    lower piece). Same step control as the upward continuation, no fold
    passage: it stops at the first step that fails for good (in the
    spring chain of issue 16: a turning point of the upper branch).

    The start must land near the slipped guess (D within
    ``SLIPPED_START_TOLERANCE`` of the contacts' estimated share, ω within
    ``MAX_CORRECTION``): near an internal resonance the EPMC has other
    solutions close by. Otherwise it starts 10, 100, … times higher, where
    the contacts perturb the slipped mode less, and continues down to the
    top of the grid first.

    Returns ``(s, z, iterations, steps, rejected, reason)``: the points in
    increasing amplitude, the work, and why it stopped above the floor
    (None when it reached it)."""
    n = epmc.n
    width = grid[1] - grid[0]
    targets = [t for t in grid[::-1] if t > floor + 1e-9 * width]
    if not targets:
        return [], [], [], 0, 0, None
    steps = rejected = 0
    z = None
    for k in range(START_BACKOFF + 1):
        s0 = grid[-1] + k * np.log(10.0)
        a0 = float(np.exp(s0))
        guess = epmc.slipped_guess(a0)
        z, its = epmc.solve(guess, a0)
        steps += 1
        share = abs(guess[n + 1] - epmc.slipped_damping)
        if z is not None and (
            abs(z[n + 1] - guess[n + 1]) <= SLIPPED_START_TOLERANCE * share
            and abs(z[n] - guess[n]) <= MAX_CORRECTION * guess[n]
        ):
            break
        rejected += 1
        z = None
    if z is None:
        return (
            [],
            [],
            [],
            steps,
            rejected,
            f"no solution near the slipped mode at a = {np.exp(grid[-1]):.4g} "
            f"to {a0:.4g}",
        )
    # above the grid: spaced like it, not returned
    above = [s0 - i * width for i in range(int(np.ceil((s0 - grid[-1]) / width)))]
    path = [t for t in above if t > grid[-1] + 1e-9 * width] + targets
    out_s, out_z, out_it = [], [], []
    if s0 == targets[0]:
        out_s, out_z, out_it = [s0], [z], [its]
    history = [(s0, z)]
    step = width
    reason = None
    for target in path[1:] if s0 == path[0] else path:
        s = history[-1][0]
        while s > target:
            h = -min(step, s - target)
            z_last = history[-1][1]
            if len(history) >= 2:
                s_prev, z_prev = history[-2]
                pred = z_last + (z_last - z_prev) * h / (s - s_prev)
            else:
                pred = z_last.copy()
            z_new, its = epmc.solve(pred, float(np.exp(s + h)))
            steps += 1
            bad = (
                z_new is None
                or epmc.correlation(z_last, z_new) < MAC_TOLERANCE
                or abs(z_new[n] - pred[n]) > MAX_CORRECTION * pred[n]
                or abs(z_new[n + 1] - pred[n + 1]) > MAX_CORRECTION
            )
            if bad:
                rejected += 1
                step = 0.5 * abs(h)
                if step < MIN_STEP_FRACTION * width:
                    reason = (
                        f"coming down from a = {np.exp(s0):.4g}, the "
                        f"continuation fails at a = {np.exp(s + h):.4g} (a "
                        "turning point of the upper branch, or another jump)"
                    )
                    break
                continue
            history = [history[-1], (s + h, z_new)]
            s = s + h
            if its <= 4:
                step = min(2.0 * abs(h), width)
        if reason is not None:
            break
        if target <= grid[-1] + 1e-9 * width:
            out_s.append(target)
            out_z.append(history[-1][1])
            out_it.append(its)
    return out_s[::-1], out_z[::-1], out_it[::-1], steps, rejected, reason


def _amplitude_range(amplitude) -> tuple[float, float]:
    try:
        lo, hi = amplitude
    except (TypeError, ValueError):
        raise ValueError(
            f"amplitude must be a pair (low, high) of modal amplitudes, got "
            f"{amplitude!r}"
        ) from None
    lo = finite_float("amplitude[0]", lo, low=0.0, low_open=True)
    hi = finite_float("amplitude[1]", hi, low=0.0, low_open=True)
    if not hi > lo:
        raise ValueError(
            f"amplitude range must be increasing (low < high), got ({lo}, {hi})"
        )
    return lo, hi


def _check_mode_arrays(path, mode: NonlinearMode) -> None:
    """Check that the arrays of a loaded mode agree with each other;
    ``ValueError`` naming the file and the field otherwise."""
    bad = field_error(path)
    a = mode.amplitude
    if a.ndim != 1 or not np.all(np.isfinite(a)) or np.any(a <= 0.0):
        raise bad("amplitude", "must be 1-d, finite and positive")
    n = a.size
    for name in ("omega", "damping_ratio", "newton_iterations", "truncation_error"):
        value = getattr(mode, name)
        if value is None:
            continue
        if value.shape != (n,):
            raise bad(name, f"must have shape ({n},) like amplitude, got {value.shape}")
        if not np.all(np.isfinite(value)):
            raise bad(name, "has non-finite values")
    n_coef = check_harmonics(bad, mode.harmonic_numbers)
    c = mode.coefficients
    if c.ndim != 3 or c.shape[0] != n or c.shape[2] != n_coef:
        raise bad(
            "coefficients",
            f"has shape {c.shape}; amplitude ({n} points) and harmonic_numbers "
            f"({n_coef} coefficients) ask for ({n}, n_dof, {n_coef})",
        )
    if not np.all(np.isfinite(c)):
        raise bad("coefficients", "has non-finite values")
    n_dof = c.shape[1]
    if mode.load_vector is not None and mode.load_vector.shape != (n_dof,):
        raise bad("load_vector", f"must have shape ({n_dof},)")
    if mode._mass is not None and mode._mass.shape != (n_dof, n_dof):
        raise bad("mass", f"must have shape ({n_dof}, {n_dof})")
    p = mode.pieces
    if p is not None and (
        p.ndim != 1 or p.size < 2 or p[0] != 0 or np.any(np.diff(p) <= 0) or p[-1] >= n
    ):
        raise bad("pieces", f"must start at 0 and increase below {n}")
    for name, index in mode.dof_names.items():
        if not 0 <= index < n_dof:
            raise bad("dof_names", f"maps {name!r} to {index}, not in [0, {n_dof - 1}]")


#: relative distance of two linear pulsations below which
#: :func:`_repeated_note` calls them a repeated pair (eigh's rounding of a
#: pair of a symmetric structure is ~1e-15)
REPEATED_TOL = 1e-9


def _repeated_partners(omegas: np.ndarray, mode: int) -> list[int]:
    """The other linear modes (1-based) with the pulsation of ``mode``
    within ``REPEATED_TOL`` relative."""
    w = np.asarray(omegas, dtype=float)
    j = mode - 1
    return [
        i + 1
        for i in range(w.size)
        if i != j and abs(w[i] - w[j]) <= REPEATED_TOL * max(w[j], 1e-300)
    ]


def _repeated_note(omegas: np.ndarray, mode: int) -> str:
    """Why the start failed when linear mode ``mode`` (1-based) of the
    stuck structure is one of a repeated pair (a symmetric structure, e.g.
    cyclic): every motion in the pair's plane is a linear mode, the EPMC's
    phase condition fixes none of them and its Newton matrix is singular
    (ring of three masses: no point at all, ``tests/test_hunt_modes.py``).
    Empty otherwise."""
    same = _repeated_partners(omegas, mode)
    if not same:
        return ""
    return (
        f"; linear mode {same[0]} has the same pulsation (a repeated pair, as "
        "in a symmetric structure): the phase condition does not fix a motion "
        "in the pair's plane, so the EPMC has no isolated solution; break the "
        "symmetry slightly (e.g. one stiffness by 1e-6 relative) to follow "
        "one mode of the pair"
    )


def _touching_contacts(epmc: _EPMC, z: np.ndarray) -> list[int]:
    """Indices (in the system's contact list) of the 2D elements that touch
    at rest without load (``preload == 0``: open at rest, closed by any
    closing motion) and whose normal DOF moves in the fundamental of ``z``
    (more than 1e-6 of the largest DOF)."""
    from .laws.contact2d import Contact2D

    cos1, sin1 = z[epmc.cos1], z[epmc.sin1]
    shape = np.hypot(cos1, sin1)
    big = float(np.max(shape)) if shape.size else 0.0
    out = []
    for i, (law, _a, _b, a_n, b_n) in enumerate(epmc.problem._contacts):
        if not isinstance(law, Contact2D) or law.preload != 0.0 or a_n < 0:
            continue
        rel_c = cos1[a_n] - (cos1[b_n] if b_n >= 0 else 0.0)
        rel_s = sin1[a_n] - (sin1[b_n] if b_n >= 0 else 0.0)
        if np.hypot(rel_c, rel_s) > 1e-6 * big:
            out.append(i)
    return out


def _start_notes(
    epmc: _EPMC, mode: int, a0: float, z0: np.ndarray, dof_names: dict
) -> list[str]:
    """What is wrong with the start of a mode (its first solved point
    ``z0``, at amplitude ``a0``, reached by Newton from the linear mode):
    a 2D element touching at rest whose normal DOF moves, with ω far from
    the linear pulsation (``START_OMEGA_TOL``; far alone is no fault: a
    range may start where the contacts slip), a shape that is
    not the linear mode's (``MAC_TOLERANCE``), a linear mode of a repeated
    pair (the eigensolver's choice of a motion in the pair's plane; DOFs
    named by ``dof_names``). Empty when the start is the linear mode's."""
    n = epmc.n
    notes = []
    w0, wl = float(z0[n]), epmc.linear_omega
    mac = epmc.correlation(epmc.linear_guess(a0), z0)
    touching = _touching_contacts(epmc, z0)
    # a start in slip with the linear mode's shape is that mode's
    # continuation at a0 (a range that starts where the contacts act, on
    # purpose): not reported; the touching element's bilinear motion is
    if touching and abs(w0 - wl) > START_OMEGA_TOL * wl:
        contacts = ", ".join(str(i) for i in touching)
        notes.append(
            f"its first point (a = {a0:.4g}) has ω = {w0:.6g} rad/s, "
            f"{abs(w0 - wl) / wl:.3g} relative from the linear pulsation "
            f"{wl:.6g} rad/s (NonlinearMode.linear_omega): contact {contacts} "
            "(Contact2D, preload 0) touches at rest: open at rest, it closes on "
            "any motion of its normal DOF, so a mode that moves that DOF is "
            "piecewise linear from a = 0 and never tends to the linear mode of "
            "the open contact (one normal DOF: the bilinear pulsation "
            "2 ω_open ω_closed / (ω_open + ω_closed)); a small positive preload "
            "gives the limit of a contact held closed"
        )
    if mac < MAC_TOLERANCE:
        notes.append(
            f"the shape of its first point is not the linear mode's (modal "
            f"assurance criterion {mac:.3g}): Newton from the linear mode reached "
            "another mode"
        )
    same = _repeated_partners(epmc.stuck_omegas, mode)
    if same:
        names = {i: name for name, i in dof_names.items()}
        shape = np.hypot(z0[epmc.cos1], z0[epmc.sin1])
        top = int(np.argmax(shape))
        notes.append(
            f"linear mode {same[0]} has the same pulsation (a repeated pair): "
            "the motion followed is "
            f"the one of the pair's plane the eigensolver picked (largest at DOF "
            f"{names.get(top, top)!r}), another mode number may give another; "
            "break the symmetry slightly to choose"
        )
    return notes


def nonlinear_mode(
    system,
    mode: int = 1,
    amplitude=(1e-6, 1e-2),
    *,
    points: int = 40,
    harmonics: int = 7,
    n_time: int | None = None,
    aft: str = "auto",
    structural_damping: bool = True,
    harmonic_tolerance: float | None = 1e-3,
    upper_branch: bool = True,
) -> NonlinearMode:
    """A nonlinear mode by the extended periodic motion concept (EPMC).

    Frequency and equivalent damping ratio of the periodic motions of the
    unforced system with the energy its damping and contacts dissipate fed
    back by ``-2 D ω M ẋ`` (:mod:`hbmfric.modes`), at ``points`` modal
    amplitudes spaced logarithmically over ``amplitude``.

    Parameters
    ----------
    system : Oscillator, CantileverBeam, LinearStructure or compatible
        Any system of the system protocol; its load is ignored (a static
        load is kept).
    mode : int
        Which linear mode (1 = lowest) of the structure with its contacts
        stuck the nonlinear mode continues.
    amplitude : (float, float)
        Modal amplitudes ``(low, high)``, ``0 < low < high``: the
        fundamental harmonic in the mass norm, m √kg (for one DOF of mass
        ``m``: ``√m`` times the displacement amplitude).
    points : int
        Number of amplitudes (>= 2), log-spaced, ends included.
    harmonics : int
        Highest harmonic ``H``; odd harmonics only for a symmetric system.
    n_time : int, optional
        AFT samples per period; default as for :func:`hbmfric.frf`.
    aft : {"auto", "events", "samples"}
        AFT scheme (:class:`~hbmfric.hbm.HBMProblem`).
    structural_damping : bool
        Keep the structure's damping matrix ``C`` (default: ``D`` is the
        damping ratio of the mode, structure and contacts) or drop it
        (``D`` is the contacts' share).
    harmonic_tolerance : float or None
        Tolerance of the estimated truncation error of each point
        (``NonlinearMode.truncation_error``: relative error of ω, absolute
        error of D); an :class:`~hbmfric.AccuracyWarning` when a point
        exceeds it. The estimate costs one residual and one LU in the basis
        ``2H + 1`` per point; None skips it.
    upper_branch : bool
        When the continuation from the stuck side stops on the path past a
        turning point (at an internal resonance, or at a kink of the path
        it cannot pass), continue the mode down from ``high``, starting from the
        same linear mode of the structure with its contacts slipping
        freely (default), to the amplitudes above the stop: the result then
        has two :attr:`~NonlinearMode.pieces` and a gap between them
        (:attr:`~NonlinearMode.gaps`). False: the lower piece alone.

    Returns
    -------
    NonlinearMode

    Warns
    -----
    CoverageWarning
        When the continuation stops before the end of the range (the
        result holds the points it found).
    ConvergenceWarning
        When no point at all could be found.
    AccuracyWarning
        When the estimated truncation error of a point exceeds
        ``harmonic_tolerance``; and for a structure reduced by
        :func:`~hbmfric.craig_bampton` when the mode's linear (stuck)
        pulsation lies above the pulsation the reduction stands for
        (``valid_below``).
    HbmfricWarning
        When the first point (Newton from the linear mode) does not lie on
        that linear mode: a 2D element that touches at rest (preload 0)
        makes the mode piecewise linear from a = 0, so that it never tends
        to the linear one (ω more than ``START_OMEGA_TOL``, 5 %, from
        ``linear_omega``; a start in slip alone is not reported), a
        fundamental shape with a modal assurance criterion below
        ``MAC_TOLERANCE`` against the linear mode's, or a linear mode of a
        repeated pair (the eigensolver chose the motion in the pair's plane).
        The notes are also in ``info["start_notes"]``.

    Examples
    --------
    >>> import hbmfric as hf
    >>> osc = hf.Oscillator(1.0, 4.0, 1e4, hf.Jenkins(stiffness=3e4, slip_force=1.0))
    >>> nm = hf.nonlinear_mode(osc, amplitude=(1e-6, 1e-2), harmonics=1)
    >>> round(float(nm.omega[0]), 6), round(float(nm.omega[-1]), 2)
    (200.0, 100.05)
    """
    start = time.perf_counter()
    mode = positive_int("mode", mode, low=1)
    points = positive_int("points", points, low=2)
    lo, hi = _amplitude_range(amplitude)
    if not isinstance(structural_damping, bool | np.bool_):
        raise ValueError(
            f"structural_damping must be True or False, got {structural_damping!r}"
        )
    if harmonic_tolerance is not None:
        harmonic_tolerance = finite_float(
            "harmonic_tolerance", harmonic_tolerance, low=0.0, low_open=True
        )
    epmc = _EPMC(system, mode, harmonics, n_time, aft, bool(structural_damping))
    _check_memory(epmc, harmonic_tolerance is not None)
    warn_above_cutoff(
        system,
        epmc.linear_omega,
        f"the linear (stuck) pulsation of mode {mode}",
        stacklevel=2,
    )
    n = epmc.n
    grid = np.linspace(np.log(lo), np.log(hi), points)
    width = grid[1] - grid[0]
    n_steps = n_rejected = 0

    # first point: from the linear mode, backing off to smaller amplitudes
    # (and continuing up to ``lo``) when the linear guess is too far
    z, its = epmc.solve(epmc.linear_guess(lo), lo)
    n_steps += 1
    history: list[tuple[float, np.ndarray]] = []
    if z is not None:
        history.append((grid[0], z))
    else:
        n_rejected += 1
        for k in range(1, START_BACKOFF + 1):
            s0 = grid[0] - k * np.log(10.0)
            a0 = float(np.exp(s0))
            z0, _ = epmc.solve(epmc.linear_guess(a0), a0)
            n_steps += 1
            if z0 is not None:
                history.append((s0, z0))
                break
            n_rejected += 1
    start_notes = (
        _start_notes(
            epmc,
            mode,
            float(np.exp(history[0][0])),
            history[0][1],
            dict(getattr(system, "dof_names", {}) or {}),
        )
        if history
        else []
    )
    out_s, out_z, out_it = [], [], []
    # the run stopped on the path past a turning point (an internal
    # resonance, or a kink it cannot pass): the upper branch is sought
    turned_back = False
    folds: list[float] = []
    fold_path: list[tuple[float, np.ndarray]] = []
    stop_reason = "range reached"
    if not history:
        stop_reason = (
            f"no solution near the linear mode {mode} "
            f"({epmc.linear_omega / (2.0 * np.pi):.4g} Hz with the contacts "
            f"stuck) at or below a = {lo:.3g}"
        ) + _repeated_note(epmc.stuck_omegas, mode)
    else:
        targets = list(grid) if z is None else list(grid[1:])
        if z is not None:
            out_s.append(grid[0])
            out_z.append(z)
            out_it.append(its)
        step = width
        for target in targets:
            s = history[-1][0]
            reached = False
            while not reached:
                # h < 0 after a fold passed beyond the target
                h = min(step, target - s)
                z_last = history[-1][1]
                if len(history) >= 2 and h != 0.0:
                    s_prev, z_prev = history[-2]
                    pred = z_last + (z_last - z_prev) * h / (s - s_prev)
                else:
                    pred = z_last.copy()
                s_new = s + h
                z_new, its = epmc.solve(pred, float(np.exp(s_new)))
                n_steps += 1
                jumped = (
                    z_new is not None
                    and epmc.correlation(z_last, z_new) < MAC_TOLERANCE
                )
                # a corrector far from the predictor: a sharp turn of the
                # backbone to resolve, or another solution (the EPMC of a
                # friction contact can have several near the stick limit)
                far = z_new is not None and (
                    abs(z_new[n] - pred[n]) > MAX_CORRECTION * pred[n]
                    or abs(z_new[n + 1] - pred[n + 1]) > MAX_CORRECTION
                )
                if z_new is None or jumped or far:
                    n_rejected += 1
                    step = 0.5 * abs(h)
                    if (
                        step < MIN_STEP_FRACTION * width
                        and not jumped
                        and len(history) >= 2
                        and len(folds) < MAX_FOLDS
                    ):
                        # a turning point in a: follow the path around it
                        path, found, k, r, why = _pass_folds(
                            epmc, history, s_new, width
                        )
                        n_steps += k
                        n_rejected += r
                        if why is not None:
                            stop_reason = why
                            turned_back = True
                            break
                        if path is not None and found:
                            folds.extend(found)
                            fold_path.extend(path)
                            history = [history[-1], *path][-2:]
                            s = history[-1][0]
                            step = width
                            continue
                    if step < MIN_STEP_FRACTION * width:
                        if jumped:
                            what = (
                                "the mode shape jumped (modal assurance "
                                f"criterion below {MAC_TOLERANCE:g}: another "
                                "mode, an internal resonance?)"
                            )
                        elif far:
                            what = (
                                "the backbone jumped (ω or D moved by more than "
                                f"{MAX_CORRECTION:g} from the predictor)"
                            )
                        else:
                            what = "Newton failed"
                        stop_reason = (
                            f"{what} at a = {np.exp(s_new):.4g} with the "
                            f"step below its minimum ({MIN_STEP_FRACTION:g} of "
                            "the grid spacing)"
                        )
                        break
                    continue
                history.append((s_new, z_new))
                history = history[-2:]
                s = s_new
                if its <= 4:
                    step = min(2.0 * abs(h) if h != 0 else width, width)
                if abs(s_new - target) <= 1e-14 * max(1.0, abs(target)) or (
                    s_new > target
                ):
                    reached = True
                    out_s.append(target)
                    out_z.append(z_new)
                    out_it.append(its)
            if not reached:
                break
    pieces = None
    upper_reason = None
    if turned_back and upper_branch and epmc.slipped_phi is not None:
        # the backbone beyond the internal resonance: from the top of the
        # range down, starting from the slipped structure's linear mode
        up_s, up_z, up_it, k, r, upper_reason = _descend(epmc, grid, out_s[-1])
        n_steps += k
        n_rejected += r
        if up_s:
            pieces = np.array([0, len(out_s)], dtype=np.int64)
            out_s += up_s
            out_z += up_z
            out_it += up_it
            low_end, up_start = np.exp(out_s[pieces[1] - 1]), np.exp(up_s[0])
            stop_reason += (
                "; the upper branch, continued down from the linear mode with "
                f"the contacts slipping at a >= {hi:.4g}, reaches a = {up_start:.4g}"
                f": not computed between a = {low_end:.4g} and {up_start:.4g}"
            )
            if upper_reason is not None:
                stop_reason += f" ({upper_reason})"
        elif upper_reason is not None:
            stop_reason += f"; no upper branch: {upper_reason}"
    amps = np.exp(np.array(out_s, dtype=float))
    if amps.size:  # the asked ends exactly, not through exp(log(.))
        amps[0] = lo if out_s[0] == grid[0] else amps[0]
        amps[-1] = hi if out_s[-1] == grid[-1] else amps[-1]
    Z = np.array(out_z, dtype=float).reshape(-1, n + 2)
    coefficients = (Z[:, :n] * amps[:, None]).reshape(-1, epmc.n_dof, epmc.n_coef)
    problem = epmc.problem
    errors = None
    if harmonic_tolerance is not None:
        probe = _EPMC(
            system,
            mode,
            PROBE_FACTOR * problem.harmonics + 1,
            None,
            aft,
            bool(structural_damping),
        )
        errors = np.array(
            [probe.truncation_error(z, a, epmc) for z, a in zip(Z, amps, strict=True)]
        )
    result = NonlinearMode(
        amplitude=amps,
        omega=Z[:, n].copy(),
        damping_ratio=Z[:, n + 1].copy(),
        coefficients=coefficients,
        harmonic_numbers=problem.harmonic_numbers.copy(),
        mode=mode,
        linear_omega=epmc.linear_omega,
        linear_damping_ratio=epmc.linear_damping,
        requested=(lo, hi),
        stop_reason=stop_reason,
        newton_iterations=np.array(out_it, dtype=np.int64),
        n_steps=n_steps,
        n_rejected=n_rejected,
        elapsed=time.perf_counter() - start,
        info={
            "harmonics": problem.harmonics,
            "odd_only": problem.odd,
            "n_time": problem.n_time,
            "aft": problem.aft,
            "structural_damping": bool(structural_damping),
            "contact_dof": int(getattr(system, "contact_dof", 0)),
        },
        dof_names=dict(getattr(system, "dof_names", {}) or {}),
        load_vector=epmc.load,
        truncation_error=errors,
        folds=np.array(folds, dtype=float),
        pieces=pieces,
        fold_path=np.array(
            [[np.exp(sp), zp[n], zp[n + 1]] for sp, zp in fold_path], dtype=float
        ).reshape(-1, 3),
        _mass=epmc.mass,
    )
    if start_notes:
        result.info["start_notes"] = list(start_notes)
        warnings.warn(
            f"nonlinear mode {mode} does not start on linear mode {mode} "
            f"({epmc.linear_omega:.6g} rad/s with the contacts stuck): "
            + "; ".join(start_notes),
            HbmfricWarning,
            stacklevel=2,
        )
    if folds:
        warnings.warn(
            f"nonlinear mode {mode}: the backbone turns in amplitude at a = "
            f"{', '.join(f'{f:.4g}' for f in folds)}; between the turning points "
            "it has several solutions at one amplitude (the points follow the "
            "path past them; NonlinearMode.fold_path holds the others)",
            HbmfricWarning,
            stacklevel=2,
        )
    if not result.complete:
        covered = f"up to a = {amps[-1]:.4g}" if amps.size else "no point"
        if pieces is not None:
            covered = "gaps " + ", ".join(
                f"({g0:.4g}, {g1:.4g})" for g0, g1 in result.gaps
            )
        cls = CoverageWarning if amps.size else ConvergenceWarning
        warnings.warn(
            f"nonlinear mode {mode}: {covered} of the range ({lo:.4g}, {hi:.4g}); "
            f"{stop_reason}",
            cls,
            stacklevel=2,
        )
    if errors is not None and np.any(errors > harmonic_tolerance):
        worst = int(np.argmax(errors))
        warnings.warn(
            f"nonlinear mode {mode}: estimated truncation error {errors[worst]:.2g} "
            f"exceeds harmonic_tolerance={harmonic_tolerance:g} at "
            f"{int(np.sum(errors > harmonic_tolerance))} of {errors.size} points "
            f"(worst at a = {amps[worst]:.4g}, H = {problem.harmonics}); raise "
            "harmonics; per-point estimates in NonlinearMode.truncation_error",
            AccuracyWarning,
            stacklevel=2,
        )
    return result
