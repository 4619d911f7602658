"""Adaptive harmonics: continuation that picks the highest harmonic ``H``
along the branch from an estimate of the truncation error.

Estimate. The error is that of the first-harmonic amplitude and of half the
peak-to-peak value of the watched output: by default the contact DOF's
displacement (where the higher harmonics are made; the linear structure
filters them elsewhere: on the beam the error at the tip is at most 0.12
times the one at the contact), or the linear combination of displacements
and velocities a system names (``output_weights``, see
:mod:`hbmfric.systems.protocol`; the belt tensioner's tension, whose
relative change near 92 Hz at H = 5 was 30-250 times the pulley's). A
problem condensed onto the contact watches the contact. The free measure
below is the output's too (read from the contact DOF alone, the ratio it
carries drifted 8-fold within 32 points where the tension's first harmonic
nearly vanishes, 93 Hz at f1 = 2 N). Their change when the basis grows
to the probe level (:func:`probe_level`: two rungs of the ladder up, about
``2 H``) is computed to first order by
:func:`hbmfric.kernels.steps.truncation.truncation_change` (one residual and one
LU in the larger basis at the zero-padded point: about one Newton
iteration there). That calibration runs every ``RECALIBRATE`` points and
before a decision (at most once in ``MIN_GAP`` points); at every other
point the change is carried by a free measure of the same point,
``H max(|X_H|, (K'/H)^4 |X_K'|) / |X_1|`` (the highest retained harmonics,
``K'`` the one below ``H``, which guards against a top harmonic near a zero
of the spectrum), times their ratio at the last calibration. The estimate is

    ``CHANGE_FACTOR * change``

(``CHANGE_FACTOR`` is the safety factor ``SAFETY = 2`` measured against
exact references, see the constants); an estimate below ``ONSET`` times
the tolerance is not carried (the next point calibrates).

Why ``2 H``. The truncation error of a friction contact does not fall
monotonically with ``H``: the change to the next rung (``1.4 H``) nearly
cancels at some points (there the true error was 5-90 times that change on
the paper's scenes), which needed a safety factor of 2.5 on 1.5 times that
change and a floor on the free measure, and put the estimate 4-10 times
above the true error at the points that decide the level (the beam at
Fn = 0.5 N ran at H = 63 where H = 45 has a true error of 2e-5). The
change to ``2 H`` leaves only the error of ``2 H``: over whole branches of
the SDOF Fex/Fn = 10 and 0.5 scenes and the beam at Fn = 0.5 N (fixed
H = 5-45, ``bench/estimate_study.py``) the true error was 1.0 times it in
the median and at most 1.8 times it where the error is within 3 times of
the branch's largest. A contact stuck over the whole period is linear: the
higher harmonics vanish and the estimate is 0.

Decisions, after every accepted point (the estimate at the next point is
extrapolated from the last two at the same level). Most points need none:
between calibrations, a point whose carried estimate is clear of both
thresholds (or a linear point at the lowest level) keeps the level inside
the compiled continuation (:func:`hbmfric.kernels.steps.arclength.stays`,
the whole rule of :meth:`AdaptiveContinuation._adapt` but its actions: due
calibrations, the carried estimate right after one and the count of points
below the lower threshold run there too), so the run returns to Python
only to act: a raise, a lowering, a point solved again, a linear response
above the lowest level (P1 at F = 0.5: 8 times in 280 points, 21 before
the count and the near-threshold decisions moved into the compiled
stretch):

* raise when the estimate ahead exceeds ``RAISE_AT`` times the tolerance, to
  the smallest level at which a ``H^-DECAY`` law predicts ``TARGET`` times
  it (one rung up instead broke the stiff Menq branch of
  ``tests/test_coverage.py``). The next step starts at the new level from
  the zero-padded point and tangent (the corrector adds the new
  harmonics); only if the current point itself exceeds the tolerance is it
  solved again at the new level, so every stored point meets its estimate;
* lower one rung after ``LOWER_PATIENCE`` points in a row whose estimate,
  moved to the rung below by a ``H^-LOWER_DECAY`` law, stays below
  ``LOWER_AT`` times the tolerance (the gap to ``RAISE_AT`` keeps ``H``
  from flapping), by truncation; a linear (stuck) response drops to the
  lowest level at once (the point itself too: its dropped harmonics are
  zero);
* at the end (:meth:`AdaptiveContinuation.settle`) every point whose final
  estimate exceeds the tolerance is solved again one rung higher. The final
  estimate keeps the run's own calibrations (the compiled stretch reports
  each; no point is calibrated twice) and calibrates every point whose
  carried estimate exceeds the tolerance, so only points over it by their
  own calibration are solved again (bench/README.md "Issue 14, stop 24").

The lowest level is ``H = 3``, not 1: a stuck point costs about as much
at both (SDOF Jenkins, compiled continuation: 9.7 µs at H = 1, 10.9 µs at
H = 3, 15.9 µs at H = 15), and at ``H = 1`` the estimate would need an
evaluation in the larger basis at every point (5 µs), which costs more
than it saves. The run starts at ``LADDER[START]`` (H = 7): from the
linear guesses Newton needs 52 iterations for a gross-slip first point at
H = 3 and 19 at H = 7.

Arc length, step size and counters carry over across a change (the scaled
variables do not depend on ``H``). Each level's problem (derived from the
first one: :meth:`hbmfric.hbm.HBMProblem.with_harmonics` shares the
system's matrices and modes), work arrays and continuation are built once
per run, on first use; the compiled kernels take the level's arrays, so no
level compiles anything. ``bench/README.md``
(section "Adaptive harmonics") has the run time against fixed ``H``.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable

import numpy as np

from ..kernels.residuals.pointer import chain_problem, residual_address
from ..kernels.steps import arclength as _arclength
from ..kernels.steps import newton as _newton
from ..kernels.steps.truncation import output_measure, truncation_change
from ..systems.protocol import output_weights
from .options import ContinuationOptions
from .palc import MIN_STEP, NO_START, Continuation, ContinuationState

#: index in the ladder of the level of the first point
START = 2
#: harmonic levels the adaptive run moves between (successive ratios about
#: 1.2-1.4, inside the factor the thresholds below leave between raise and
#: lower)
LADDER = (3, 5, 7, 11, 15, 21, 31, 45, 63)
#: the calibration measures the first-order change to the level
#: ``PROBE_STEPS`` rungs above the point's own (``H`` to about ``2 H``:
#: 3 -> 7, 11 -> 21, 31 -> 63, beyond the ladder 1.4 times per rung). The
#: change to the next rung alone (``H`` to about ``1.4 H``) is no estimate:
#: the truncation error of a friction contact does not fall monotonically
#: with ``H``, and the two errors nearly cancel at some points (true error
#: up to 5-12 times that change on the paper's scenes), while the change to
#: ``2 H`` leaves only the error of ``2 H`` (a quarter to an eighth of the
#: one at ``H``) and was within 0.7-1.8 times the true error wherever that
#: is within 3 times of its largest value (``bench/estimate_study.py``)
PROBE_STEPS = 2
#: growth of ``H`` per rung beyond the top of the ladder
GROWTH = 1.4
#: safety factor of the estimate: against the exact event-driven references
#: (``hbmfric.validation.exact``, bench/README.md "Issue 14") the true error
#: of the first harmonic or half peak-to-peak exceeded the change to the
#: probe level by at most 1.78 times at points within 3 times of the
#: branch's largest error (fixed H = 5-45 on the SDOF scenes Fex/Fn = 10
#: and 0.5 and the beam at Fn = 0.5 N; median 1.0, 90th percentile
#: 1.1-1.4)
SAFETY = 2.0
#: the error estimate per first-order change to the probe level
CHANGE_FACTOR = SAFETY
#: between calibrations the estimate is the free measure times the ratio
#: ``estimate / measure`` of the last calibration, unless that estimate was
#: below this fraction of the tolerance at the lowest level (where a
#: response that stops being linear starts): then the next point
#: calibrates. A
#: point at the onset of slip has a ratio 100 times below the points a step
#: or two further into slip; carried, it kept H = 3 over stretches up to 6
#: times over the tolerance (SDOF F = 0.5, tolerance 1e-3). (A floor of
#: 0.125 on the carried ratio, as the former estimate had, also caught it
#: but sent every point of the Fex/Fn = 10 scene, where the ratio is
#: 0.01-0.03, to a calibration in Python: auto 2-4 times slower.)
ONSET = 0.05
#: least carried ratio in the estimate of a fixed-``H`` branch
#: (:mod:`hbmfric.continuation.accuracy`; its carried estimates over the
#: tolerance are calibrated anyway)
CARRY_FLOOR = 0.0
#: decay exponent of the estimate with ``H`` used to predict other levels
DECAY = 3.5
#: ... and to decide a lowering (more cautious: between rungs the error of
#: the condensed beam and of the Fex/Fn = 10 scene fell as H^-2 to H^-2.5
#: only, and a lowering predicted by H^-3.5 was undone at once by a raise,
#: which then blocked lowering for ``COOLDOWN`` points)
LOWER_DECAY = 2.0
#: raise when the estimate ahead exceeds this fraction of the tolerance
RAISE_AT = 1.0
#: a raise aims at this fraction of the tolerance
TARGET = 0.5
#: lower when a lower level is predicted below this fraction
LOWER_AT = 0.2
#: points in a row below ``LOWER_AT`` before lowering
LOWER_PATIENCE = 3
#: an estimate below this fraction of the tolerance means a linear response
LINEAR = 1e-6
#: a raise within this many points of a lowering returns to the level left
FLAP_WINDOW = 10
#: ... and then no lowering for this many points
COOLDOWN = 50
#: the estimate ahead grows by at most this factor per step
MAX_GROWTH = 4.0
#: share of the requested tolerance the points aim at: every decision of
#: the run and of :meth:`AdaptiveContinuation.settle` compares the
#: estimate with ``AIM`` times the tolerance. The estimate is smooth since
#: stop 24 (extremes located on the series, not on 64 samples whose
#: sampling noise used to raise ``H`` by chance) and on its own left
#: points at up to 1.1 times the tolerance against independent references
#: (the belt tensioner at 5 N, 52 Hz, against shooting; bench/README.md
#: "Issue 14, stop 25"): ``SAFETY`` covers the estimate's spread at one
#: point, this the carried estimate between calibrations and the drawn
#: line between points
AIM = 0.7
#: the final pass (:meth:`AdaptiveContinuation.settle`) calibrates every
#: ``SETTLE_EVERY``-th point of each stretch besides the run's own
#: calibrations: those can be ``RECALIBRATE`` points apart, and a ratio
#: carried over that many points read 4-10 times low on the beam at
#: Fn = 1 N, 112-122 rad/s (H = 21, carried 2.5e-5 to 5.5e-5 where the
#: points' own estimates were 7e-5 to 3.1e-4 and the half peak-to-peak
#: 1.6e-4 off the exact reference; bench/README.md "Issue 14, stop 25").
#: Every 8th point meets 1e-4 there too and costs less (beam at Fn = 1 N:
#: 1.40 against 1.46 times the smallest fixed H meeting 1e-4)
SETTLE_EVERY = 8
#: rounds of :meth:`AdaptiveContinuation.join_levels` after the final pass
#: (each raises the lower end of every interval between two levels whose
#: chord estimate exceeds ``curve_tolerance``; a raised point can make a
#: new such interval with its other neighbour)
JOIN_ROUNDS = 4
#: points between calibrations of the free measure on one level
RECALIBRATE = 16
#: between calibrations, stay only if the estimate ahead is this factor
#: clear of the raise threshold (the lower side needs no margin)
MARGIN = 1.25
#: points after a calibration during which decisions use the carried ratio
MIN_GAP = 4
#: index of the predictor's history among a continuation's work arrays
HISTORY = 7
#: carry the previous point across a level change (off: it saved about 1 %
#: of the evaluations on P1 but made the points depend on rounding-level
#: differences, 2e-9 in Ω between the same oscillator in units scaled by
#: 1e15 instead of 1e-10, tests/test_extremes.py)
CARRY_HISTORY = False
#: most points of one compiled stretch (calibrations run inside it)
TRACE_CAPACITY = 256


def next_level(harmonics: int, ladder=LADDER) -> int:
    """The rung above ``harmonics``: the next level of ``ladder``, beyond its
    top ``GROWTH`` times ``harmonics`` rounded up to odd."""
    for h in ladder:
        if h > harmonics:
            return int(h)
    h = int(math.ceil(GROWTH * harmonics))
    return h + 1 if h % 2 == 0 else h


def probe_level(harmonics: int, ladder=LADDER) -> int:
    """Level whose basis calibrates the estimate at ``harmonics``:
    ``PROBE_STEPS`` rungs up (:func:`next_level`)."""
    h = int(harmonics)
    try:
        return _probe_level(h, ladder)
    except TypeError:  # a ladder that is no tuple
        return _probe_level(h, tuple(int(k) for k in ladder))


@functools.lru_cache(maxsize=512)
def _probe_level(h: int, ladder: tuple) -> int:
    """:func:`probe_level` of an int and a tuple (read many times per run:
    every rung of the memory plan and every level's probe)."""
    for _ in range(PROBE_STEPS):
        h = next_level(h, ladder)
    return h


def truncation_estimate(harmonic_numbers: np.ndarray, X: np.ndarray) -> float:
    """Relative amplitude of the highest retained harmonic,
    ``max_d |X_d,H| / max_d |X_d,1|`` (0 if the first harmonic is 0, inf if
    ``H <= 1``): the size of a difference truncation can explain (used by the
    stress checks, ``tests/stress``).

    Parameters
    ----------
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    X : ndarray, shape (n_dof, n_coef)
        Coefficients per DOF, m.
    """
    hn = [int(k) for k in harmonic_numbers]
    if hn[-1] < 2:
        return math.inf
    X = np.atleast_2d(X)
    cols = np.cumsum([0] + [1 if k == 0 else 2 for k in hn])
    c1, ct = int(cols[hn.index(1)]), int(cols[-2])
    a1 = float(np.max(np.hypot(X[:, c1], X[:, c1 + 1])))
    top = float(np.max(np.hypot(X[:, ct], X[:, ct + 1])))
    if a1 == 0.0:
        return 0.0 if top == 0.0 else math.inf
    return top / a1


def top_measure(harmonic_numbers: np.ndarray, X: np.ndarray) -> float:
    """Free truncation measure ``H max(|X_H|, (K'/H)^4 |X_K'|) / |X_1|``.

    Parameters
    ----------
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    X : ndarray, shape (n_dof, n_coef)
        Coefficients per DOF, m.

    Returns
    -------
    float
        Largest over the DOFs, relative to the largest first harmonic (0 if
        the first harmonic is 0); inf if ``H <= 1``.
    """
    hn = [int(k) for k in harmonic_numbers]
    if hn[-1] < 2:
        return math.inf  # nothing to compare with
    X = np.atleast_2d(X)
    cols = np.cumsum([0] + [1 if k == 0 else 2 for k in hn])

    def amp(k: int) -> np.ndarray:
        c = cols[hn.index(k)]
        return np.hypot(X[:, c], X[:, c + 1])

    a1 = float(np.max(amp(1)))
    top = amp(hn[-1])
    if len(hn) >= 2 and hn[-2] > 1:
        top = np.maximum(top, (hn[-2] / hn[-1]) ** 4 * amp(hn[-2]))
    top = float(np.max(top))
    if a1 == 0.0:
        return 0.0 if top == 0.0 else math.inf
    return hn[-1] * top / a1


def level_for(estimate: float, current: int, goal: float, ladder, decay=DECAY) -> int:
    """Smallest level of ``ladder`` at which ``estimate`` (measured at
    ``current``) is predicted to fall to ``goal`` by the ``H^-decay`` law
    (the top level if none does)."""
    for h in ladder:
        if estimate * (current / h) ** decay <= goal:
            return h
    return ladder[-1]


#: thinned synthesis matrices of :meth:`_Level.work`, keyed by the ``id``
#: of the synthesis matrix they thin (which the entry keeps alive; the
#: matrices are shared by every problem of one discretisation,
#: ``hbm._fourier_matrices``): ``id -> (matrix, every, thinned)``
_THINNED: dict = {}


def _thinned(inverse: np.ndarray, every: int) -> np.ndarray:
    """``inverse[::every]`` as a C-contiguous copy, made once per matrix
    and step (the kernels only read it)."""
    entry = _THINNED.get(id(inverse))
    if entry is None or entry[0] is not inverse or entry[1] != every:
        if len(_THINNED) >= 16:
            _THINNED.clear()
        entry = (inverse, every, np.ascontiguousarray(inverse[::every]))
        _THINNED[id(inverse)] = entry
    return entry[2]


class _Level:
    """One harmonic level: its problem, its continuation (built on first
    use) and the flat indices the free measure reads.

    The harmonics of a lower level are a prefix of those of a higher one
    (``1, 3, 5, …`` or ``0, 1, 2, …``), so a point moves between levels by
    copying the leading coefficients of every DOF."""

    def __init__(self, problem, make_cont: Callable) -> None:
        p = problem
        self.problem = p
        self._make_cont = make_cont
        self._cont = None
        self.n = p.n_unknowns
        self.n_coef = p.n_coef
        hn = p.harmonic_numbers
        self.h = int(hn[-1])
        self.n_dof = p.n_unknowns // p.n_coef  # 1 for a problem condensed on a contact
        # the contact DOF (1 DOF: the only one): the free measure and the
        # linear test read it
        self.dof = int(getattr(p.system, "contact_dof", 0)) if self.n_dof > 1 else 0
        # the output whose change the calibration measures (the system's
        # ``output_weights``; a problem condensed onto the contact watches it)
        if self.n_dof == int(getattr(p.system, "n_dof", self.n_dof)):
            self.output = output_weights(p.system, self.n_dof, self.dof)
        else:
            self.output = np.ones((2, 1))
            self.output[1, 0] = 0.0
        first = 1 if hn[0] == 0 else 0  # column of the first harmonic
        # harmonic number of each column (for the velocity weights): the
        # constant's column, then a cosine and a sine per harmonic
        self.rates = np.zeros(p.n_coef)
        self.rates[first:] = np.repeat(np.asarray(hn[first:], dtype=float), 2)
        base = [self.dof * p.n_coef]
        self.first_column = first
        self.first = [b + first for b in base]
        top, prev = p.n_coef - 2, p.n_coef - 4
        self.top = [b + top for b in base] if self.h > 1 else []
        k_prev = int(hn[-2]) if hn.size >= 2 else 0
        self.prev = [b + prev for b in base] if k_prev > 1 else []
        self.prev_weight = (k_prev / self.h) ** 4 if k_prev > 1 else 0.0
        #: columns within a DOF of the first, the highest and the
        #: second-highest harmonic (-1: none) for the free measure
        self.columns = (
            first,
            top if self.h > 1 else -1,
            prev if k_prev > 1 else -1,
        )
        self._work = None
        #: level-only part of the watch array and the next level's
        #: calibration arguments (:meth:`AdaptiveContinuation._watch`)
        self.watch = None
        self.calibration = None

    @property
    def cont(self) -> Continuation:
        if self._cont is None:
            self._cont = self._make_cont(self.problem)
        return self._cont

    def measure(self, y: np.ndarray) -> float:
        """Free measure of the watched output at ``y`` (this level's
        layout; :func:`~hbmfric.kernels.steps.truncation.output_measure`, the
        compiled run's own arithmetic); inf for ``H = 1``."""
        first, top, prev = self.columns
        return float(
            output_measure(
                y,
                self.output,
                self.rates,
                first,
                top,
                prev,
                float(self.h),
                self.prev_weight,
            )
        )

    def work(self) -> tuple:
        """The calibration arguments of this level (as the next level of
        another): ``(kernel problem, address of its residual, synthesis,
        weights, rates, y, R, J, A, dX)`` of :func:`truncation_change`,
        allocated once (the address is this process's: the tuple is never
        pickled)."""
        if self._work is None:
            n = self.n
            # the AFT's own synthesis samples, thinned to about 4 H
            kp = getattr(
                self.problem, "full_kernel_problem", self.problem.kernel_problem
            )
            inverse = kp[9]
            every = max(1, inverse.shape[0] // max(64, 4 * self.h))
            self._work = (
                chain_problem(self.problem.kernel_problem),
                residual_address(self.problem.kernel_problem),
                _thinned(inverse, every),
                self.output,
                self.rates,
                np.empty(n + 1),
                np.empty(n),
                np.empty((n, n + 1)),
                np.empty((n, n)),
                np.empty(n),
            )
        return self._work

    def change(self, x: np.ndarray) -> float:
        """:func:`truncation_change` of a point ``x`` of a lower level."""
        problem, residual_at, synthesis, weights, rates, y, R, J, A, dX = self.work()
        return float(
            truncation_change(
                x,
                problem,
                residual_at,
                weights,
                rates,
                self.first_column,
                synthesis,
                y,
                R,
                J,
                A,
                dX,
            )
        )


class AdaptiveContinuation:
    """Pseudo-arclength continuation with the harmonic count chosen along
    the branch.

    Parameters
    ----------
    make_problem : callable
        ``H -> HBMProblem`` (same system, force and options, highest
        harmonic ``H``).
    omega_range, direction, options, amplitude_scale
        As in :class:`~hbmfric.continuation.Continuation`.
    tolerance : float
        Target relative truncation error (> 0).
    ladder : sequence of int
        Allowed levels of ``H``, increasing.

    Attributes
    ----------
    n_switches : int
        Level changes (each a zero-padding or truncation of the point).
    n_resolves : int
        Points solved again at a higher level because they exceeded the
        tolerance (in the run or in :meth:`settle`).
    n_settled : int
        Of those, the ones solved again by :meth:`settle` (each rung
        counted).
    n_calibrations : int
        Change estimates computed (each one residual and LU in the next
        level's basis).
    """

    def __init__(
        self,
        make_problem: Callable,
        omega_range: tuple[float, float],
        direction: int,
        options: ContinuationOptions,
        amplitude_scale: float | None,
        tolerance: float,
        ladder=LADDER,
    ) -> None:
        self.make_problem = make_problem
        self.omega_range = omega_range
        self.direction = direction
        self.options = options
        #: the requested tolerance; the run aims at ``AIM`` times it
        self.requested = float(tolerance)
        self.tolerance = AIM * self.requested
        self.ladder = tuple(ladder)
        self._levels: dict[int, _Level] = {}
        self._probes: dict[int, _Level] = {}
        self.amplitude_scale = amplitude_scale
        if amplitude_scale is None:
            start = self.ladder[min(START, len(self.ladder) - 1)]
            self.amplitude_scale = float(self._level(start).cont.scale[0])
        self.n_switches = 0
        self.n_resolves = 0
        self.n_calibrations = 0
        self.n_settled = 0
        self._lowered = (0, 0)  # level left by the last lowering, and where
        # change computed by a trace for its last point, not yet decided on
        self._pending_change = math.nan
        self._no_lower_before = 0  # point count before which no lowering
        # (level, point, tangent, point count) before the last move
        self._moved = None
        #: per stored point, its estimate where the run calibrated it at
        #: its level (NaN elsewhere): reused by :meth:`settle`
        self._fresh: list[float] = []
        self._reset()

    def _reset(self) -> None:
        """Forget the estimate history (after a level change)."""
        self._last = math.nan  # previous estimate at this level
        self._low = 0  # points in a row that could go lower
        self._age = RECALIBRATE  # points since the last calibration
        self._factor = math.nan  # estimate per free measure at the last one

    # ------------------------------------------------------------------
    def _level(self, h: int) -> _Level:
        if h not in self._levels:
            # a probe level of a lower rung may already hold this problem
            # (its roles share nothing: continuation and watch as a level,
            # calibration work arrays as a probe)
            level = self._probes.get(h)
            if level is None:
                level = _Level(self.make_problem(h), self._make_cont)
            below = [lv for lv in self.ladder if lv < h]
            # the estimate (per tolerance) under which a lower level would do
            level.lower_below = (
                LOWER_AT * (below[-1] / h) ** LOWER_DECAY if below else -math.inf
            )
            self._levels[h] = level
        return self._levels[h]

    def _probe(self, h: int) -> _Level:
        """The level that calibrates the estimate at ``h``
        (:func:`probe_level`; may lie beyond the ladder), built once."""
        hp = probe_level(h, self.ladder)
        if hp not in self._probes:
            level = self._levels.get(hp)
            if level is None:
                level = _Level(self.make_problem(hp), self._make_cont)
            self._probes[hp] = level
        return self._probes[hp]

    def _make_cont(self, problem) -> Continuation:
        return Continuation(
            problem,
            self.omega_range,
            self.direction,
            self.options,
            getattr(self, "amplitude_scale", None),
        )

    def _cont(self, h: int) -> Continuation:
        return self._level(h).cont

    def pad(self, v: np.ndarray, h_src: int, h_dst: int) -> np.ndarray:
        """Map ``[X, Ω]`` (or a tangent) from level ``h_src`` to ``h_dst``:
        shared harmonics copied, new ones zero, dropped ones cut."""
        src, dst = self._level(h_src), self._level(h_dst)
        out = np.zeros(dst.n + 1)
        m = min(src.n_coef, dst.n_coef)
        out[:-1].reshape(dst.n_dof, dst.n_coef)[:, :m] = v[:-1].reshape(
            src.n_dof, src.n_coef
        )[:, :m]
        out[-1] = v[-1]
        return out

    # ------------------------------------------------------------------
    def _calibrate(self, h: int, y: np.ndarray, measure: float) -> float:
        """Fresh error estimate from the change to the next level; stores
        its ratio to the free measure."""
        self._age = 0
        self.n_calibrations += 1
        change = self._pending_change
        if math.isnan(change):
            change = self._probe(h).change(y)
        self._pending_change = math.nan
        est = CHANGE_FACTOR * change
        # ``y`` is the last stored point (a decision after it): its estimate
        # at this level, for the final pass
        if self._fresh:
            self._fresh[-1] = est
        # not carried from the onset of slip (:data:`ONSET`)
        if est >= ONSET * self.tolerance or h != self.ladder[0]:
            self._factor = est / max(measure, 1e-300)
        else:
            self._factor = math.inf
        return est

    def _linear(self, h: int, y: np.ndarray) -> bool:
        """Whether every harmonic above the lowest level vanishes at the
        contact DOF (a stuck contact, a linear response): then the lowest
        level is exact. A vanishing top harmonic alone is not enough (a
        cubic spring's harmonics decay geometrically)."""
        level, lowest = self._levels[h], self._level(self.ladder[0])
        block = y[level.dof * level.n_coef : (level.dof + 1) * level.n_coef]
        rest = float(np.max(np.abs(block[lowest.n_coef :]), initial=0.0))
        i = level.first[0]
        a1 = math.hypot(y[i], y[i + 1])
        return rest <= LINEAR * self.tolerance * a1

    def _move(self, state: ContinuationState, h: int, h_new: int) -> None:
        """Continue from the current point at level ``h_new``: point and
        tangent zero-padded or truncated (the stored point keeps level
        ``h``)."""
        # what :meth:`_rescue` needs if the new level cannot step from here
        self._moved = (h, state.y.copy(), state.tangent.copy(), len(state.points))
        t = self.pad(state.tangent, h, h_new)
        # the second-order predictor's previous point comes along (its
        # history, kernels.steps.arclength.predict), if the current point is
        # the one the last step accepted
        src = self._cont(h)._work[HISTORY]
        dst = self._cont(h_new)._work[HISTORY]
        carried = CARRY_HISTORY and np.array_equal(src[1], state.y)
        state.y = self.pad(state.y, h, h_new)
        if carried:
            dst[0] = self.pad(src[0], h, h_new)
            dst[1] = state.y
        else:
            dst[1, -1] = math.nan
        state.tangent = t / float(np.linalg.norm(t))
        state.J = self._cont(h_new)._J
        self.n_switches += 1
        self._reset()

    def _rescue(self, state: ContinuationState, h: int, levels: list) -> int | None:
        """After the step collapsed at level ``h`` right after a move to it
        (no point accepted there), the padded or truncated point was too
        far from a solution of the new basis for the corrector (a raise of
        several levels on a strongly nonlinear response, or a lowering the
        ``H^-DECAY`` law allowed on a cubic spring, whose harmonics decay
        geometrically). Solve the last point again at level ``h`` (with the
        budget of a first point); failing that, after a lowering, return to
        the level left and keep from lowering for ``COOLDOWN`` points.
        Returns the level to go on at (the run goes on), or None."""
        if self._moved is None or self._moved[3] != len(state.points):
            return None
        h_old, y_old, t_old, _ = self._moved
        self._moved = None
        dst = self._cont(h)
        budget = max(8 * self.options.max_newton, 100)
        guess = self.pad(y_old, h_old, h)
        y, status, it = dst.solve_at(float(y_old[-1]), guess[:-1], budget)
        state.n_newton += it
        t = np.full(1, np.nan)
        if status == _newton.CONVERGED and np.all(np.isfinite(y)):
            t = dst._tangent(self.pad(t_old, h_old, h))
        if np.all(np.isfinite(t)):
            state.y = y
            state.tangent = t
            state.J = dst._J
            state.points[-1] = y.copy()
            state.tangents[-1] = t * dst.scale
            levels[-1] = h
            if self._fresh:
                self._fresh[-1] = math.nan
            self.n_resolves += 1
        elif h < h_old:
            state.y = y_old
            state.tangent = t_old
            state.J = self._cont(h_old)._J
            self._no_lower_before = len(levels) + COOLDOWN
            h = h_old
        else:
            return None
        self._reset()
        state.step = self.options.initial_step
        state.finished = False
        state.stop_reason = ""
        return h

    def _resolve(
        self,
        state: ContinuationState,
        h: int,
        h_new: int,
        max_iter: int | None = None,
    ) -> bool:
        """Solve the current (last) point again at level ``h_new`` (Newton
        with at most ``max_iter`` iterations, default ``max_newton``)."""
        dst = self._cont(h_new)
        guess = self.pad(state.y, h, h_new)
        y, status, it = dst.solve_at(float(state.y[-1]), guess[:-1], max_iter)
        state.n_newton += it
        if status != _newton.CONVERGED or not np.all(np.isfinite(y)):
            return False
        t = dst._tangent(self.pad(state.tangent, h, h_new))
        if not np.all(np.isfinite(t)):
            return False
        if len(state.points) == 1 and t[-1] * state.tangent[-1] < 0.0:
            # the first point: its tangent keeps the sweep's direction (the
            # orientation by the old tangent can reverse it where the point
            # moved and Ω is a small part of the tangent: a stiff Menq at
            # 0.3 rad/s, H 7 -> 63, turned back at once)
            t = -t
        state.y = y
        state.tangent = t
        state.J = dst._J
        state.points[-1] = y.copy()
        state.tangents[-1] = t * dst.scale
        if self._fresh:
            self._fresh[-1] = math.nan  # the caller calibrates it again
        self.n_switches += 1
        self.n_resolves += 1
        self._reset()
        return True

    def _climb(self, state: ContinuationState, h: int, h_new: int) -> int | None:
        """Solve the current point again at ``h_new``: Newton from the
        padded level-``h`` solution with the usual budget, then (a point at
        the onset of slip, where the AFT Jacobian changes between stick and
        slip across the iterations, may need 40-60 iterations) with the
        first point's budget. ``h_new``, or None if both fail."""
        if self._resolve(state, h, h_new):
            return h_new
        budget = max(8 * self.options.max_newton, 100)
        if self._resolve(state, h, h_new, budget):
            return h_new
        return None

    def _adapt(self, state: ContinuationState, h: int, levels: list) -> int:
        """Choose the level for the next step after the current (last)
        point; returns it (``levels[-1]`` is updated if the point is solved
        again)."""
        tol = self.tolerance
        level = self._levels[h]
        measure = level.measure(state.y)
        lowest = self.ladder[0]
        if measure <= LINEAR * tol and self._linear(h, state.y):
            # linear response: the lowest level is exact
            self._last = 0.0
            if h != lowest:
                self._move(state, h, lowest)
                # the dropped harmonics are zero: the point is the lowest
                # level's solution too
                state.points[-1] = state.y.copy()
                state.tangents[-1] = self.pad(state.tangents[-1], h, lowest)
                levels[-1] = lowest
                if self._fresh:
                    self._fresh[-1] = math.nan
                return lowest
            return h
        last = self._last
        self._age += 1
        stale = self._factor * measure
        if self._age < RECALIBRATE:
            # the free measure times the last ratio: enough to decide to stay
            ahead = stale
            if last > 0.0 and stale > last:
                ahead = stale * min(stale / last, MAX_GROWTH)
            if MARGIN * ahead <= RAISE_AT * tol and stale >= self._lower_limit(
                level, len(levels) < self._no_lower_before
            ):
                self._last = stale
                self._low = 0
                return h
        est = None
        if self._age < MIN_GAP and stale <= tol and math.isnan(self._pending_change):
            # calibrated a moment ago (and no fresh change from the compiled
            # stretch): decide on the carried one, unless it asks for a
            # raise. Then this point's own estimate is computed:
            # the ratio carried from a point at the onset of slip (tiny
            # change, small free measure) can be 100 times below the one a
            # point a step further into slip has, and the point must meet
            # the tolerance itself (else it is solved again higher)
            ahead = stale
            if last > 0.0 and stale > last:
                ahead = stale * min(stale / last, MAX_GROWTH)
            if ahead <= RAISE_AT * tol:
                est = stale
        if est is None:
            est = self._calibrate(h, state.y, measure)
        # a point over the tolerance: solve it again higher (rare: the
        # estimate ahead normally raises the level one step earlier)
        for _ in range(len(self.ladder)):
            if est <= tol or h == self.ladder[-1]:
                break
            h_new = self._raise_to(est, h, len(levels))
            h_new = self._climb(state, h, h_new)
            if h_new is None:
                break
            levels[-1] = h = h_new
            level = self._levels[h]
            measure = level.measure(state.y)
            if measure <= LINEAR * tol and self._linear(h, state.y):
                return h
            est = self._calibrate(h, state.y, measure)
            last = math.nan
        ahead = est
        if last > 0.0 and est > last:
            ahead = est * min(est / last, MAX_GROWTH)
        self._last = est
        if ahead > RAISE_AT * tol:
            h_new = self._raise_to(ahead, h, len(levels))
            if h_new > h:
                self._move(state, h, h_new)
            return max(h_new, h)
        if est < level.lower_below * tol and len(levels) >= self._no_lower_before:
            self._low += 1
            if self._low >= LOWER_PATIENCE:
                # one rung at a time (each checked by the next decisions): a
                # jump of several rungs by a decay law was undone at once on
                # the gross-slip SDOF branch (its error falls faster than
                # H^-3.5 there, the beam's as H^-2)
                h_new = max((lv for lv in self.ladder if lv < h), default=h)
                if h_new < h:
                    self._move(state, h, h_new)
                    self._lowered = (h, len(levels))
                    return h_new
                self._low = 0
        else:
            self._low = 0
        return h

    def _watch(self, h: int, levels: list) -> np.ndarray:
        """The stay rule of :meth:`_adapt` at level ``h`` with the current
        calibration, as the watch array of
        :func:`hbmfric.kernels.steps.arclength.trace` (same thresholds, same
        arithmetic: the compiled stretch keeps the level exactly where
        :meth:`_adapt` would). Sets the stretch's capacity and calibration
        arguments."""
        a = _arclength
        level = self._levels[h]
        if level.watch is None:
            self._watch_template(level)
        w = level.watch.copy()
        w[a.W_FACTOR] = self._factor
        w[a.W_LAST] = self._last
        w[a.W_AGE] = self._age
        # while lowering is blocked (the k-th point of the stretch is
        # decided with len(levels) + k points), no lower threshold; the
        # stretch then ends where the block does
        blocked = self._no_lower_before - len(levels) - 1
        self._capacity = (
            min(blocked, TRACE_CAPACITY) if blocked >= 1 else TRACE_CAPACITY
        )
        w[a.W_LOWER] = self._lower_limit(level, blocked >= 1)
        w[a.W_LOW] = self._low
        self._calibration = level.calibration
        return w

    def _watch_template(self, level: _Level) -> None:
        """The parts of the watch array that depend on the level only, and
        the next level's calibration arguments (built once per level)."""
        a = _arclength
        tol = self.tolerance
        w = np.empty(a.N_WATCH)
        w[a.WATCH_ACTIVE] = 1.0
        w[a.W_RECALIBRATE] = RECALIBRATE
        w[a.W_RAISE] = RAISE_AT * tol
        w[a.W_MARGIN] = MARGIN
        w[a.W_MAX_GROWTH] = MAX_GROWTH
        w[a.W_LINEAR] = LINEAR * tol
        w[a.W_H] = level.h
        w[a.W_PREV_WEIGHT] = level.prev_weight
        w[a.W_FIRST], w[a.W_TOP], w[a.W_PREV] = level.columns
        w[a.W_LOWEST] = float(level.h == self.ladder[0])
        w[a.W_CALIBRATE] = 1.0  # every level has a probe level
        w[a.W_CHANGE_FACTOR] = CHANGE_FACTOR
        # the onset of slip is met at the lowest level (a linear response
        # drops there at once); elsewhere a small estimate is carried
        w[a.W_TOP_FLOOR] = ONSET * tol if level.h == self.ladder[0] else 0.0
        w[a.W_CALIBRATIONS] = 0.0
        w[a.W_CHANGE] = math.nan
        w[a.W_PATIENCE] = LOWER_PATIENCE
        w[a.W_TOL] = tol
        w[a.W_MIN_GAP] = MIN_GAP
        probe = self._probe(level.h)
        w[a.W_N_DOF] = probe.n_dof
        w[a.W_DOF] = probe.dof
        w[a.W_FIRST_COLUMN] = probe.first_column
        level.calibration = probe.work()
        level.watch = w

    def _lower_limit(self, level: _Level, blocked: bool) -> float:
        """Estimate under which a point needs a decision about lowering
        (none while lowering is blocked after a flap). No margin on this
        side: staying on a stale estimate can only delay a lowering, which
        costs time, not accuracy (with a margin, a branch whose estimate
        sits just above the threshold asked for a decision, and a
        calibration every few points, at 25 points in a row)."""
        if blocked:
            return -math.inf
        return level.lower_below * self.tolerance

    def _raise_to(self, est: float, h: int, n_points: int) -> int:
        """Level to raise to from ``h``. Soon after lowering from a level
        (the ``H^-DECAY`` law was wrong: a cubic spring's harmonics decay
        geometrically), go back to it and do not lower again for
        ``COOLDOWN`` points."""
        left, at = self._lowered
        if left > h and n_points - at <= FLAP_WINDOW:
            self._no_lower_before = n_points + COOLDOWN
            self._lowered = (0, 0)
            return left
        h_new = level_for(est, h, TARGET * self.tolerance, self.ladder)
        if h_new > h:
            return h_new
        return min((lv for lv in self.ladder if lv > h), default=h)

    def settle(
        self,
        points: list[np.ndarray],
        levels: list[int],
        estimate: Callable,
        tangents: list[np.ndarray] | None = None,
    ) -> np.ndarray:
        """Per-point estimates of the finished branch, each point over the
        tolerance solved again one rung higher (in place in ``points`` and
        ``levels``) until it meets it or the ladder ends.

        Between calibrations the run decides on a carried estimate; the
        final estimate (``estimate(problem, points, tolerance, stretch,
        max_confirmed, known, every, probe, amplitude_scale=..., level=...)``,
        :func:`hbmfric.continuation.accuracy.truncation_errors`, relative to
        at least ``CURVE_REST`` of the run's amplitude scale, with its
        implausible first-order changes confirmed by probe solves: a stuck
        rigid tip's round-off amplitude read 5.3e3 and sent linear points to
        the top of the ladder, bench/README.md "stop 30") reuses the
        run's calibrations (``known``; they can be ``RECALIBRATE`` points
        apart on a level, over which a carried ratio can read 10 times
        low), calibrates every ``SETTLE_EVERY``-th point and the first and
        last point of each stretch, the two of largest free measure per
        level and
        every point whose carried estimate exceeds the tolerance (no bound
        on their number: a carried estimate can be several times the fresh
        one, and a point solved again costs more than a calibration), so
        only points whose own calibration fails are solved again. It can
        find points the run let through (where the estimate rose between
        two calibrations of the run). Such a point is solved at fixed Ω
        from its zero-padded self (a few Newton iterations); the points
        solved again at one level are estimated together (one compiled
        call, each its own stretch: each is calibrated).

        ``tangents`` (unit tangents in physical units, ``tangent * scale``,
        one per point at its level), when given, are replaced in place at
        every point solved again by the tangent of the new level there
        (oriented by the old one). The zero-padded old tangent would
        belong to another branch: the points move by their truncation
        error, whose slope along Ω is not small where the level had to
        rise, and the chord estimate (:attr:`hbmfric.Branch.curve_errors`)
        from a moved point with the old tangent read 2.2e-4 on the beam at
        Fn = 1 N, 120-125 rad/s, where the drawn lines are within 9e-5 of
        the exact response (bench/README.md "Issue 18, stop 26").

        Returns
        -------
        ndarray, shape (n_points,)
            The estimate of every point at its (final) level.
        """
        tol = self.tolerance
        errors = np.zeros(len(points))
        levels_array = np.array(levels, dtype=np.int64)
        # stretches of consecutive points at one level: a level's ratio to
        # the free measure is carried only within one
        stretch = np.cumsum(np.diff(levels_array, prepend=-1) != 0)
        # the run's own calibrations (at most RECALIBRATE points apart on a
        # level) count as calibrated points: no periodic ones on top
        known = np.full(len(points), np.nan)
        if len(self._fresh) == len(points):
            known[:] = self._fresh
        for h in np.unique(levels_array):
            idx = np.flatnonzero(levels_array == h)
            errors[idx] = estimate(
                self._level(int(h)).problem,
                np.array([points[i] for i in idx.tolist()]),
                tol,
                stretch[idx],
                len(idx),
                known[idx],
                SETTLE_EVERY,
                self._probe(int(h)),
                amplitude_scale=self.amplitude_scale,
                level=self._level(int(h)),
            )
        self._climb_failing(
            [int(i) for i in np.flatnonzero(errors > tol)],
            points,
            levels,
            errors,
            estimate,
            tangents,
        )
        return errors

    def _solve_higher(
        self,
        i: int,
        h_new: int,
        points: list[np.ndarray],
        levels: list[int],
        tangents: list[np.ndarray] | None,
    ) -> bool:
        """Solve point ``i`` of a finished branch again at level ``h_new``
        (fixed Ω, Newton from its zero-padded self), in place in ``points``,
        ``levels`` and ``tangents`` (the new level's tangent, oriented by
        the old one). False, nothing changed, if Newton fails.

        With ``tangents``, where Newton at fixed Ω fails the point is
        corrected on the hyperplane through its zero-padded self normal
        to its tangent (the continuation's own corrector, Ω free; kept
        only inside the range). At a fold (a turning point in Ω) the
        higher level's fold can lie at a lower Ω than the point: there is
        no solution at its Ω nearby. The README's several-contacts example
        had its point at the fold, 45.021259 rad/s, H = 15, left there
        with an estimate of 7.4e-3 (bench/README.md "Issue 18, stop 32"):
        on that hyperplane H = 21, 31, 63 and 127 have their solutions at
        45.021229, 45.021202, 45.021206 and 45.021206 rad/s (3 Newton
        iterations each), and the H = 15 point is within 1.7e-5 of the
        H = 127 one on every DOF's first harmonic."""
        h = levels[i]
        dst = self._cont(h_new)
        guess = self.pad(points[i], h, h_new)
        y, status, _ = dst.solve_at(float(points[i][-1]), guess[:-1])
        old = None
        if tangents is not None:
            old = self.pad(tangents[i], h, h_new) / dst.scale
            old = old / float(np.linalg.norm(old))
        if status != _newton.CONVERGED and old is not None and np.all(np.isfinite(old)):
            y = guess.copy()
            status, _ = dst._correct(y, guess.copy(), old)
            if not dst.low <= y[-1] <= dst.high:
                return False
        if status != _newton.CONVERGED or not np.all(np.isfinite(y)):
            return False
        if old is not None:
            t = dst._tangent(old)
            t = t * dst.scale if np.all(np.isfinite(t)) else None
            tangents[i] = self.pad(tangents[i], h, h_new) if t is None else t
        points[i], levels[i] = y, h_new
        self.n_resolves += 1
        self.n_settled += 1
        return True

    def _estimate_solved(
        self,
        solved: dict[int, list[int]],
        points: list[np.ndarray],
        errors: np.ndarray,
        estimate: Callable,
    ) -> list[int]:
        """Estimates of the points solved again (``level -> indices``), each
        calibrated (its own stretch), into ``errors``; the ones over the
        tolerance."""
        failing = []
        for h_new, idx in solved.items():
            errors[idx] = estimate(
                self._level(h_new).problem,
                np.array([points[i] for i in idx]),
                self.tolerance,
                np.arange(len(idx)),
                len(idx),
                None,
                None,
                self._probe(h_new),
                amplitude_scale=self.amplitude_scale,
                level=self._level(h_new),
            )
            failing += [i for i in idx if errors[i] > self.tolerance]
        return failing

    def _climb_failing(
        self,
        failing: list[int],
        points: list[np.ndarray],
        levels: list[int],
        errors: np.ndarray,
        estimate: Callable,
        tangents: list[np.ndarray] | None,
    ) -> None:
        """Each point of ``failing`` one rung up, then one estimate per
        level, until all meet the tolerance or the ladder ends."""
        while failing:
            solved: dict[int, list[int]] = {}
            for i in failing:
                h = levels[i]
                if h >= self.ladder[-1]:
                    continue
                h_new = min(lv for lv in self.ladder if lv > h)
                if self._solve_higher(i, h_new, points, levels, tangents):
                    solved.setdefault(h_new, []).append(i)
            failing = self._estimate_solved(solved, points, errors, estimate)

    def join_levels(
        self,
        joins: np.ndarray,
        points: list[np.ndarray],
        levels: list[int],
        errors: np.ndarray,
        estimate: Callable,
        tangents: list[np.ndarray] | None = None,
    ) -> int:
        """Solve the lower end of each interval ``joins[k]`` (points ``i``
        and ``i + 1`` at two harmonic levels) again at the level of the
        other end, in place as :meth:`settle` (``errors`` updated, a point
        then over the tolerance climbs on). Returns the number raised.

        The caller passes the joins whose chord estimate
        (:attr:`hbmfric.Branch.curve_errors`) exceeds ``curve_tolerance``.
        Across a join the estimate compares the tangents of two
        truncations. Near a contact transition their slopes differ by more
        than the branch bends: the README's several-contacts example left
        an H = 5 point between two points :meth:`settle` had raised to
        H = 7 (27.963-27.969 rad/s); its tangent's slope (d ln a / d ln Ω)
        read 32.4 against 26.5 and 30.0 at its H = 7 neighbours, and the
        estimate 1.2e-4 where the line is 6.0e-5 off solves at H = 31
        (bench/README.md "Issue 18, stop 31"). At one level the estimate
        compares tangents of one curve again."""
        solved: dict[int, list[int]] = {}
        for i in np.asarray(joins, dtype=np.int64):
            i = int(i)
            lo, hi = (i, i + 1) if levels[i] < levels[i + 1] else (i + 1, i)
            h_new = levels[hi]
            if levels[lo] >= h_new or any(lo in v for v in solved.values()):
                continue
            if self._solve_higher(lo, h_new, points, levels, tangents):
                solved.setdefault(h_new, []).append(lo)
        failing = self._estimate_solved(solved, points, errors, estimate)
        self._climb_failing(failing, points, levels, errors, estimate, tangents)
        return sum(len(v) for v in solved.values())

    def run(self) -> tuple[ContinuationState, list[np.ndarray], list[int], float]:
        """Trace the branch.

        Returns
        -------
        state : ContinuationState
            Final state (points of varying length).
        points : list of ndarray
            ``[X, Ω]`` per point, each in the basis of its level.
        levels : list of int
            ``H`` used at each point.
        elapsed : float
            Wall time, s.
        """
        start = time.perf_counter()
        # start in the middle of the ladder: from the linear guesses Newton
        # reaches a slipping first point in 15-20 iterations at H >= 5, 52
        # at H = 3 (SDOF Jenkins, F = 2); a stuck one drops at once
        h = self.ladder[min(START, len(self.ladder) - 1)]
        state = self._cont(h).init()
        levels = [h] * len(state.points)
        self._fresh = [math.nan] * len(state.points)
        if state.stop_reason == NO_START:
            return state, state.points, levels, time.perf_counter() - start
        h = self._adapt(state, h, levels)
        while not state.finished:
            # compiled stretch: stops at the first point that needs an
            # action (raise, lowering, solved again, linear response)
            before = len(state.points)
            cont = self._levels[h].cont
            watch = self._watch(h, levels)
            # the points' share of the curve budget (kernels.steps.arclength.
            # chord_target): the current point's estimate; unknown right
            # after a level change, where the raise aimed at TARGET. Not
            # charged when the harmonic tolerance exceeds the curve's (the
            # points may then take more than the whole budget: the chord
            # keeps all of it, as with a fixed H)
            last = self._last
            share = last if last >= 0.0 else TARGET * self.tolerance
            curve = self.options.curve_tolerance or 0.0
            # nor when the point's own estimate exceeds the curve tolerance
            # (the top of the ladder cannot meet it, a rigid Coulomb contact
            # in stick-slip: the points are warned about; a quarter of the
            # budget for the chord would only double its points there)
            cont._settings[_arclength.CURVE_POINT] = (
                share if self.requested <= curve and share <= curve else -1.0
            )
            state = cont._trace(state, watch, self._capacity, self._calibration)
            new = len(state.points) - before
            levels.extend([h] * new)
            # the compiled stretch's calibrations (its accepted points come
            # first; a point landed on the boundary or bridged after them)
            fresh = cont.trace_estimates.tolist()[:new]
            self._fresh.extend(fresh + [math.nan] * (new - len(fresh)))
            self._last = float(watch[_arclength.W_LAST])
            self._age = int(watch[_arclength.W_AGE])
            self._factor = float(watch[_arclength.W_FACTOR])
            self.n_calibrations += int(watch[_arclength.W_CALIBRATIONS])
            self._pending_change = float(watch[_arclength.W_CHANGE])
            if state.stop_reason == MIN_STEP:
                rescued = self._rescue(state, h, levels)
                if rescued is not None:
                    h = rescued
                    self._pending_change = math.nan
                    continue
            decide = cont.trace_outcome == _arclength.WATCH_STOP
            # points below the lower threshold in a row (the stretch counts
            # them as _adapt does; the stopping point is not counted yet)
            self._low = int(watch[_arclength.W_LOW])
            if decide and not state.finished:
                h = self._adapt(state, h, levels)
            self._pending_change = math.nan
        return state, state.points, levels, time.perf_counter() - start
