"""Adaptive harmonics: continuation that picks the highest harmonic ``H``
along the branch from an estimate of the truncation error.

Estimate: the amplitude of the highest retained harmonic relative to the
first-harmonic amplitude (largest over the DOFs). For dry friction the
harmonics of the displacement decay like a power of their order (about
``k^-4`` for a Jenkins contact in gross slip), so the highest retained one
bounds the relative error of the first-harmonic amplitude and of the
peak-to-peak value made by dropping the rest (``bench/pareto.py`` measures
the ratio against time integration; it stays below about 1.2). A contact
that sticks over the whole period is linear: its higher harmonics vanish
and the estimate is 0.

After every accepted point: if the estimate exceeds the tolerance, ``H`` is
raised to the smallest level of the ladder at which a ``k^-3`` decay (a
conservative rate) predicts half the tolerance, and the point is solved
again at fixed Ω in the larger basis (the previous coefficients padded with
zeros as the guess); if it falls below a twentieth of the tolerance, ``H`` is
lowered to the smallest level predicted to stay under a quarter of it (the
gap between the two thresholds keeps ``H`` from flapping). Stuck stretches
thus run at the lowest level and stick–slip stretches at the level their
accuracy needs. Arc length, step size and counters carry over across a
change (the scaled variables do not depend on ``H``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np

from ..kernels import newton as _newton
from ..signals import synthesis_matrix
from .options import ContinuationOptions
from .palc import NO_START, Continuation, ContinuationState

#: harmonic levels the adaptive run moves between
LADDER = (3, 5, 7, 11, 15, 21, 31, 45, 63)
#: thresholds relative to the tolerance
RAISE_TARGET = 0.5
LOWER_BELOW = 0.05
LOWER_TARGET = 0.25
#: decay exponent assumed to predict the estimate at another level
DECAY = 3.0
#: the change estimate times this bounds the error (harmonics beyond the
#: next level; the ratio of error to change reaches about 3.5 near a
#: slipping resonance of the SDOF Jenkins problem)
TAIL_FACTOR = 4.0
#: low estimates in a row before a slipping stretch goes down one level
LOWER_PATIENCE = 3
#: points between fresh change estimates on one level
RECHECK = 4


def truncation_estimate(harmonic_numbers: np.ndarray, X: np.ndarray) -> float:
    """Relative amplitude of the highest retained harmonic.

    Parameters
    ----------
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    X : ndarray, shape (n_dof, n_coef)
        Coefficients per DOF, m.

    Returns
    -------
    float
        ``max_d |X_d,H| / max_d |X_d,1|`` (0 if the first harmonic is 0).
    """
    hn = np.asarray(harmonic_numbers)
    if hn[-1] < 2:
        return math.inf  # nothing to compare with
    cols = np.cumsum([0] + [1 if k == 0 else 2 for k in hn[:-1]])
    c1 = int(cols[int(np.searchsorted(hn, 1))])
    ct = int(cols[-1])
    a1 = float(np.max(np.hypot(X[:, c1], X[:, c1 + 1])))
    top = float(np.max(np.hypot(X[:, ct], X[:, ct + 1])))
    if a1 == 0.0:
        return 0.0 if top == 0.0 else math.inf
    return top / a1


def next_level(current: int, estimate: float, tolerance: float, ladder) -> int:
    """Harmonic level for the next points, given the estimate at ``current``."""
    if estimate > tolerance:
        need = current * (estimate / (RAISE_TARGET * tolerance)) ** (1.0 / DECAY)
        for h in ladder:
            if h > current and h >= need:
                return h
        return max(ladder[-1], current)
    if estimate < LOWER_BELOW * tolerance:
        need = current * (estimate / (LOWER_TARGET * tolerance)) ** (1.0 / DECAY)
        for h in ladder:
            if h >= need:
                return min(h, current)
    return current


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
        self.tolerance = float(tolerance)
        self.ladder = tuple(ladder)
        self._conts: dict[int, Continuation] = {}
        self._cols: dict[int, dict] = {}
        self._maps: dict[tuple[int, int], tuple] = {}
        self._probes: dict[int, tuple] = {}
        self._synth: dict[int, np.ndarray] = {}
        self._ratio: dict[int, tuple[float, int]] = {}
        self._low_count = 0
        if amplitude_scale is None:
            amplitude_scale = self._cont(self.ladder[0]).scale[0]
        self.amplitude_scale = float(amplitude_scale)
        self.n_switches = 0

    def _cont(self, h: int) -> Continuation:
        if h not in self._conts:
            scale = getattr(self, "amplitude_scale", None)
            self._conts[h] = Continuation(
                self.make_problem(h),
                self.omega_range,
                self.direction,
                self.options,
                scale,
            )
        return self._conts[h]

    def _columns(self, h: int) -> dict:
        """Flat index of the first coefficient of each harmonic, per DOF."""
        if h not in self._cols:
            p = self._cont(h).problem
            start = np.cumsum([0] + [1 if k == 0 else 2 for k in p.harmonic_numbers])
            # DOFs among the unknowns (1 for a problem condensed on a contact)
            base = np.arange(p.n_unknowns // p.n_coef)[:, None] * p.n_coef
            self._cols[h] = {
                int(k): (base + start[i]).ravel()
                for i, k in enumerate(p.harmonic_numbers)
            }
        return self._cols[h]

    def _samples(self, h: int) -> np.ndarray:
        """Synthesis matrix of level ``h`` on ``max(64, 8 h)`` instants."""
        if h not in self._synth:
            hn = self._cont(h).problem.harmonic_numbers
            n = max(64, 8 * int(hn[-1]))
            self._synth[h] = synthesis_matrix(hn, 2.0 * np.pi * np.arange(n) / n)
        return self._synth[h]

    def _index_map(self, h_src: int, h_dst: int) -> tuple[np.ndarray, np.ndarray]:
        key = (h_src, h_dst)
        if key not in self._maps:
            cs, cd = self._columns(h_src), self._columns(h_dst)
            src, dst = [], []
            for k, idx in cd.items():
                if k in cs:
                    width = 1 if k == 0 else 2
                    for w in range(width):
                        src.append(cs[k] + w)
                        dst.append(idx + w)
            self._maps[key] = (
                np.concatenate(src) if src else np.zeros(0, np.int64),
                np.concatenate(dst) if dst else np.zeros(0, np.int64),
            )
        return self._maps[key]

    def pad(self, v: np.ndarray, h_src: int, h_dst: int) -> np.ndarray:
        """Map ``[X, Ω]`` (or a tangent) from level ``h_src`` to ``h_dst``:
        shared harmonics copied, new ones zero, dropped ones cut."""
        src, dst = self._index_map(h_src, h_dst)
        out = np.zeros(self._cont(h_dst).problem.n_unknowns + 1)
        out[dst] = v[src]
        out[-1] = v[-1]
        return out

    def _estimate(self, h: int, y: np.ndarray) -> float:
        """:func:`truncation_estimate` of the point ``y`` at level ``h``."""
        if h not in self._probes:
            cols = self._columns(h)
            first = cols.get(1)
            self._probes[h] = (
                None if first is None or h < 2 else first.tolist(),
                cols[max(cols)].tolist(),
            )
        first, top_cols = self._probes[h]
        if first is None:
            return math.inf
        a1 = 0.0
        for i in first:
            a1 = max(a1, math.hypot(y[i], y[i + 1]))
        top = 0.0
        for i in top_cols:
            top = max(top, math.hypot(y[i], y[i + 1]))
        if a1 == 0.0:
            return 0.0 if top == 0.0 else math.inf
        return top / a1

    def _change_estimate(self, h: int, y: np.ndarray) -> float:
        """Relative change of the response if ``H`` grew to the next level.

        The Newton correction ``dX`` at fixed Ω from ``y`` padded with zeros
        gives, to first order, the change of the first-harmonic amplitude
        and of half the peak-to-peak value (the change of an extreme is
        ``dx`` at the instant of the extreme, located on the AFT samples);
        the larger relative change, largest over the DOFs."""
        up = [level for level in self.ladder if level > h]
        if not up:
            return self._estimate(h, y)
        h_up = up[0]
        problem = self._cont(h_up).problem
        y_up = self.pad(y, h, h_up)
        R, J, status = problem.residual(y_up)
        if status < 0:
            return math.inf
        try:
            dX = np.linalg.solve(J[:, :-1], -R)
        except np.linalg.LinAlgError:
            return math.inf
        n_coef = problem.n_coef
        n_dof = problem.n_unknowns // n_coef
        X = y_up[:-1].reshape(n_dof, n_coef)
        D = dX.reshape(n_dof, n_coef)
        inverse = self._samples(h_up)
        x = X @ inverse.T  # (n_dof, n_time) samples
        dx = D @ inverse.T
        rows = np.arange(n_dof)
        i_max = np.argmax(x, axis=1)
        i_min = np.argmin(x, axis=1)
        hpp = 0.5 * (x[rows, i_max] - x[rows, i_min])
        dhpp = 0.5 * (dx[rows, i_max] - dx[rows, i_min])
        c1 = self._columns(h_up)[1] - rows * n_coef
        a1 = np.hypot(X[rows, c1], X[rows, c1 + 1])
        a1_new = np.hypot(X[rows, c1] + D[rows, c1], X[rows, c1 + 1] + D[rows, c1 + 1])
        ref = np.max(a1)
        if not ref > 0.0:
            return math.inf
        # DOFs that barely move are measured against the largest amplitude
        e1 = np.abs(a1_new - a1) / np.maximum(a1, 1e-3 * ref)
        epp = np.abs(dhpp) / np.maximum(hpp, 1e-3 * ref)
        # the change to the next level misses the harmonics beyond it
        return TAIL_FACTOR * float(max(np.max(e1), np.max(epp)))

    def _calibrated(self, h: int, y: np.ndarray, cheap: float) -> float:
        """The change estimate, computed afresh every ``RECHECK`` points and
        at every new level, in between the cheap estimate times the ratio
        of the two at the last calibration (it varies slowly along a
        branch)."""
        ratio, age = self._ratio.get(h, (0.0, RECHECK))
        if age >= RECHECK:
            change = max(cheap, self._change_estimate(h, y))
            self._ratio = {h: (change / cheap, 1)}
            return change
        self._ratio[h] = (ratio, age + 1)
        return cheap * ratio

    def _switch(self, state, h, h_new):
        """Solve the current point again at level ``h_new``; returns the new
        level actually in use."""
        dst = self._cont(h_new)
        guess = self.pad(state.y, h, h_new)
        y, status, it = dst.solve_at(float(state.y[-1]), guess[:-1])
        state.n_newton += it
        if status != _newton.CONVERGED or not np.all(np.isfinite(y)):
            return h
        previous = self.pad(state.tangent, h, h_new)
        t = dst._tangent(previous)
        if not np.all(np.isfinite(t)):
            return h
        state.y = y
        state.tangent = t
        state.J = dst._J
        state.points[-1] = y.copy()
        self.n_switches += 1
        return h_new

    def _level_estimate(self, h: int, y: np.ndarray) -> float:
        est = self._estimate(h, y)
        if est > 0.0:  # not a linear (stuck) response
            est = self._calibrated(h, y, est)
        return est

    def _adapt(self, state, h: int, levels: list) -> int:
        """Move the current (last) point to the level its estimate asks for.

        Raising is immediate (and checked again at the new level). Lowering
        a slipping response waits for ``LOWER_PATIENCE`` low estimates in a
        row, goes down one level, and is undone if the estimate at the lower
        level exceeds the tolerance (convergence in ``H`` is not monotone
        near a resonance). A stuck response (estimate 0) drops at once.
        """
        est = self._level_estimate(h, state.y)
        h_new = next_level(h, est, self.tolerance, self.ladder)
        if h_new < h:
            if est > 0.0:
                self._low_count += 1
                if self._low_count < LOWER_PATIENCE:
                    return h
                h_new = max(h_new, max(lv for lv in self.ladder if lv < h))
            self._low_count = 0
            got = self._switch(state, h, h_new)
            if got == h:
                return h
            levels[-1] = h = got
            est = self._level_estimate(h, state.y)
        else:
            self._low_count = 0
        for _ in range(len(self.ladder)):
            if est <= self.tolerance:
                break
            h_new = next_level(h, est, self.tolerance, self.ladder)
            if h_new <= h:
                break
            got = self._switch(state, h, h_new)
            if got == h:
                break
            levels[-1] = h = got
            est = self._level_estimate(h, state.y)
        return h

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
        h = self.ladder[0]
        state = self._cont(h).init()
        levels = [h] * len(state.points)
        if state.stop_reason == NO_START:
            return state, state.points, levels, time.perf_counter() - start
        h = self._adapt(state, h, levels)
        while not state.finished:
            before = len(state.points)
            state = self._cont(h).step(state)
            if len(state.points) > before:
                levels.append(h)
                h = self._adapt(state, h, levels)
        return state, state.points, levels, time.perf_counter() - start
