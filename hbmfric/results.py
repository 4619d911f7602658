"""Results: a periodic solution and an FRF branch, with their work counters,
amplitude measures, plots (matplotlib imported lazily) and ``.npz``
persistence without pickle."""

from __future__ import annotations

import json
import math
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
from ._validate import dof_index
from .signals import half_peak_to_peak, harmonic_amplitude, synthesis_matrix

#: relative tolerance (of the range width) of :attr:`Branch.complete` and
#: :attr:`Branch.gaps`
COVERAGE_RTOL = 1e-9
#: fractions of a chord where :attr:`Branch.curve_errors` compares the
#: cubic through its ends with it (the extremes of an S and of a bow)
CHORD_FRACTIONS = (0.21132486540518713, 0.5, 0.7886751345948129)
#: near a fold the vertical distance is bounded by this factor times the
#: distance perpendicular to the chord
FOLD_CAP = 1e3
#: amplitudes below this fraction of the displacement scale count as at
#: rest in :attr:`Branch.curve_errors` (errors relative to that floor; the
#: compiled rule's ``kernels.steps.arclength.CURVE_REST``)
CURVE_REST = 1e-4


def _resolve_dof(dof, names: dict, n_dof: int) -> int:
    """Index of ``dof``: an index, a name of ``names`` (such as ``"tip"``,
    ``"force"``) or None for the contact DOF (0 when unnamed)."""
    if dof is None:
        dof = names.get("contact", 0)
    elif isinstance(dof, str):
        if dof not in names:
            raise ValueError(
                f"dof name must be one of {sorted(names)} for this system, got {dof!r}"
            )
        dof = names[dof]
    return dof_index(dof, n_dof)


@dataclass
class PeriodicSolution:
    """One periodic HBM solution.

    Attributes
    ----------
    omega : float
        Forcing pulsation Ω, rad/s.
    force : float
        Forcing amplitude, N.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (n_dof, n_coef)
        Fourier coefficients per DOF, m.
    converged : bool
    newton_iterations : int
    residual_norm : float
        ``max |R|`` at the solution, N.
    elapsed : float
        Wall time, s.
    contact_state : str
    dof_names : dict
        Named DOFs of the system (e.g. ``"tip"``, ``"force"``) → index.
    method : str
        How :func:`~hbmfric.periodic_solution` obtained it: ``"newton"``,
        ``"load ramp"``, ``"continuation from below"``, ``"continuation
        from above"``, ``"zero force"`` or ``"failed"`` (not converged);
        ``"branch point"`` for :meth:`Branch.point`.
    """

    omega: float
    force: float
    harmonic_numbers: np.ndarray
    coefficients: np.ndarray
    converged: bool
    newton_iterations: int
    residual_norm: float
    elapsed: float = 0.0
    contact_state: str = ""
    dof_names: dict = field(default_factory=dict)
    method: str = ""
    #: the system and discretisation it was solved with (for
    #: :meth:`stability`; not saved)
    _source: dict | None = field(default=None, repr=False, compare=False)
    _stability: object = field(default=None, repr=False, compare=False)
    _method: str = field(default="auto", repr=False, compare=False)

    def __getstate__(self) -> dict:
        return _picklable_state(self)

    def amplitude(self, harmonic: int | None = None, dof=None) -> float:
        """Amplitude of ``x_dof``: of one harmonic (``sqrt(Xc² + Xs²)``), or
        with ``harmonic=None`` half the peak-to-peak of ``x(t)``, m.

        ``dof``: index, name from ``dof_names`` or None (the contact DOF)."""
        X = self.coefficients[
            _resolve_dof(dof, self.dof_names, self.coefficients.shape[0])
        ]
        if harmonic is None:
            return float(half_peak_to_peak(self.harmonic_numbers, X))
        return float(harmonic_amplitude(self.harmonic_numbers, X, harmonic))

    def stability(self, system=None, method: str = "auto"):
        """Floquet exponents of this solution by Hill's method
        (:mod:`hbmfric.stability`), computed once and cached.

        Parameters
        ----------
        system : Oscillator or compatible, optional
            The system solved; default: the one
            :func:`~hbmfric.periodic_solution` or the branch recorded.
        method : {"auto", "hill", "monodromy"}
            As in :meth:`Branch.stability` (``"auto"``: the time-domain
            monodromy for a contact with memory on several DOFs and for a
            modified Dahl contact on one DOF).

        Returns
        -------
        Stability
            With one point: ``exponents`` of shape (1, 2 n_dof),
            ``stable`` of shape (1,).
        """
        if self._stability is None or system is not None or method != self._method:
            src = _stability_source(self._source, system)
            if system is not None:
                check_system_solves(
                    system,
                    self.force,
                    np.array([self.omega]),
                    self.harmonic_numbers,
                    self.coefficients[None],
                    np.array([int(self.harmonic_numbers[-1])]),
                    {
                        "n_time": src.get("n_time"),
                        "aft": src.get("aft", "auto"),
                        "subharmonic": src.get("subharmonic", 1),
                        "odd_only": bool(self.harmonic_numbers[0] % 2 == 1),
                    },
                )
            from .stability import stability_of_points

            h = int(self.harmonic_numbers[-1])
            self._stability = stability_of_points(
                src["system"],
                self.force,
                np.array([self.omega]),
                self.harmonic_numbers,
                self.coefficients[None],
                np.array([h]),
                n_time=src.get("n_time"),
                aft=src.get("aft", "auto"),
                subharmonic=src.get("subharmonic", 1),
                symmetric=bool(self.harmonic_numbers[0] % 2 == 1),
                method=method,
            )
            self._method = method
        return self._stability

    @property
    def stable(self) -> bool:
        """Whether the solution is stable (:meth:`stability`)."""
        return bool(self.stability().stable[0])

    def time_response(self, n: int = 256, dof=None) -> tuple[np.ndarray, np.ndarray]:
        """``(t, x)`` over one period at ``n`` equidistant instants (s, m)
        of the displacement of ``dof`` (index, name from ``dof_names``, or
        None: the contact DOF)."""
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 2:
            raise ValueError(f"n must be an integer >= 2, got {n!r}")
        X = self.coefficients[
            _resolve_dof(dof, self.dof_names, self.coefficients.shape[0])
        ]
        theta = 2.0 * np.pi * np.arange(n) / n
        return theta / self.omega, synthesis_matrix(self.harmonic_numbers, theta) @ X


@dataclass
class Branch:
    """A branch of periodic solutions traced by continuation (an FRF).

    Attributes
    ----------
    omega : ndarray, shape (n_points,)
        Ω in path order, rad/s (non-monotone across folds).
    coefficients : ndarray, shape (n_points, n_dof, n_coef)
        Fourier coefficients of every DOF at every point, m.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    force : float
        Forcing amplitude, N.
    folds : ndarray of int
        Index ``i`` of each fold: the turning point lies between points
        ``i - 1`` and ``i``.
    stop_reason : str
    n_steps, n_rejected, newton_iterations : int
        Work counters.
    elapsed : float
        Wall time of the continuation, s.
    info : dict
        Description of the run (system, law, options), JSON-serialisable.
    point_harmonics : ndarray of int, shape (n_points,), optional
        Highest harmonic used at each point (``harmonics="auto"``); None
        when the whole branch used ``harmonic_numbers``.
    dof_names : dict
        Named DOFs of the system (e.g. ``"tip"``, ``"force"``) → index.
    truncation_error : ndarray, shape (n_points,), optional
        Estimated relative truncation error of each point: of the
        first-harmonic amplitude and of half the peak-to-peak value of the
        watched output (the contact DOF, or the system's ``output_weights``;
        :mod:`hbmfric.continuation.accuracy`); 0 at a linear
        (stuck) point. None for branches saved before it existed.
    pieces : ndarray of int, shape (n_pieces,), optional
        Index of the first point of each separately traced piece (the first
        entry 0), when a run that stopped short was retraced from the other
        end of the range (:func:`hbmfric.frf`); None for one piece. Each
        piece is a continuous path; between pieces the path jumps.
    tangents : ndarray, shape (n_points, n_dof * n_coef + 1), optional
        Unit tangent of the branch at every point, in path direction, in
        physical units: ``tangents[:, :-1].reshape(n_points, n_dof, n_coef)``
        is ``d(coefficients)/ds`` (m) and ``tangents[:, -1]`` is ``dΩ/ds``
        (rad/s), with ``s`` the arc length of the scaled variables
        ``(X / info["amplitude_scale"], Ω / (high - low))`` (coefficients
        of the solved unknowns: every DOF, or the contact DOF of a
        condensed problem; ``high - low`` the width of ``omega_range``), so
        that the solved unknowns' part has unit norm in those variables.
        Harmonics a point did not use (``harmonics="auto"``) have zero
        entries. None for branches saved before it existed.

    Notes
    -----
    :attr:`coverage`, :attr:`gaps` and :attr:`complete` say which part of
    the asked range (:attr:`omega_range`) the points cover; ``frf`` warns
    (:class:`hbmfric.CoverageWarning`) when a branch is not complete.
    """

    omega: np.ndarray
    coefficients: np.ndarray
    harmonic_numbers: np.ndarray
    force: float
    folds: np.ndarray
    stop_reason: str
    n_steps: int
    n_rejected: int
    newton_iterations: int
    elapsed: float
    info: dict = field(default_factory=dict)
    point_harmonics: np.ndarray | None = None
    dof_names: dict = field(default_factory=dict)
    truncation_error: np.ndarray | None = None
    pieces: np.ndarray | None = None
    tangents: np.ndarray | None = None
    #: the system and discretisation of the run (for :meth:`stability`;
    #: not saved)
    _source: dict | None = field(default=None, repr=False, compare=False)
    _stability: object = field(default=None, repr=False, compare=False)
    _hp: int | None = field(default=None, repr=False, compare=False)
    _method: str = field(default="auto", repr=False, compare=False)
    #: the system the cached stability was computed for (a call passing
    #: that same object again reuses it)
    _stability_system: object = field(default=None, repr=False, compare=False)

    def __getstate__(self) -> dict:
        return _picklable_state(self)

    def __len__(self) -> int:
        return self.omega.size

    @property
    def n_points(self) -> int:
        return self.omega.size

    # ------------------------------------------------------------------
    # coverage of the asked range
    @property
    def omega_range(self) -> tuple[float, float] | None:
        """Frequency range asked for, ``(low, high)`` in rad/s (None when
        the branch does not record it)."""
        rng = self.info.get("omega_range")
        if rng is None:
            return None
        return float(rng[0]), float(rng[1])

    @property
    def coverage(self) -> tuple[float, float]:
        """``(omega_low, omega_high)``: the smallest and largest Ω of the
        points, rad/s (NaN, NaN without points). With several
        :attr:`pieces` there may be :attr:`gaps` in between."""
        if self.omega.size == 0:
            return math.nan, math.nan
        return float(np.min(self.omega)), float(np.max(self.omega))

    def piece_slices(self) -> list[slice]:
        """The points of each traced piece (see ``pieces``), in path order."""
        n = self.omega.size
        starts = [0] if self.pieces is None else [int(i) for i in self.pieces]
        ends = starts[1:] + [n]
        return [slice(a, b) for a, b in zip(starts, ends, strict=True)]

    def _tolerance(self) -> float:
        lo, hi = self.omega_range
        return COVERAGE_RTOL * (hi - lo)

    @property
    def gaps(self) -> list[tuple[float, float]]:
        """Parts ``(low, high)`` of :attr:`omega_range` that no piece covers,
        rad/s, in increasing order (a piece covers the interval between its
        smallest and largest Ω: its path is continuous). Intervals shorter
        than ``COVERAGE_RTOL`` times the range are not gaps. Empty when the
        branch does not record the range."""
        rng = self.omega_range
        if rng is None:
            return []
        lo, hi = rng
        tol = self._tolerance()
        covered = sorted(
            (float(np.min(self.omega[s])), float(np.max(self.omega[s])))
            for s in self.piece_slices()
            if s.stop > s.start
        )
        gaps = []
        edge = lo
        for a, b in covered:
            if a - edge > tol:
                gaps.append((edge, min(a, hi)))
            edge = max(edge, b)
        if hi - edge > tol:
            gaps.append((edge, hi))
        return gaps

    @property
    def complete(self) -> bool:
        """Whether the points cover the whole asked range (to
        ``COVERAGE_RTOL`` times its width): no :attr:`gaps` and, for one
        piece, the path ended at the far end of the sweep (not by turning
        back to the end it started from). False when the branch does not
        record the range."""
        rng = self.omega_range
        if rng is None or self.omega.size == 0 or self.gaps:
            return False
        if self.pieces is not None and len(self.pieces) > 1:
            return True
        far = rng[0] if self.info.get("sweep") == "down" else rng[1]
        return abs(float(self.omega[-1]) - far) <= self._tolerance()

    def amplitude(self, harmonic: int | None = None, dof=None) -> np.ndarray:
        """Amplitude at every point, shape (n_points,), m.

        ``harmonic=k``: ``sqrt(Xc_k² + Xs_k²)`` (``|X0|`` for k = 0);
        ``harmonic=None``: half the peak-to-peak of ``x(t)`` over the period.
        ``dof``: index, name from ``dof_names`` (``"tip"``, ``"force"`` for
        the beam) or None (the contact DOF).
        """
        X = self.coefficients[
            :, _resolve_dof(dof, self.dof_names, self.coefficients.shape[1])
        ]
        if harmonic is None:
            return half_peak_to_peak(self.harmonic_numbers, X)
        return harmonic_amplitude(self.harmonic_numbers, X, harmonic)

    # ------------------------------------------------------------------
    # the curve between the points
    def _arc_metric(self) -> tuple[np.ndarray, float, float] | None:
        """DOFs whose coefficients the arc length of :attr:`tangents`
        measures, and its amplitude and Ω scales (None if unknown)."""
        scale = self.info.get("amplitude_scale")
        rng = self.omega_range
        if self.tangents is None or scale is None or rng is None:
            return None
        n_dof = self.coefficients.shape[1]
        if self.info.get("condensed") and n_dof > 1:
            dofs = np.array([_resolve_dof(None, self.dof_names, n_dof)])
        else:
            dofs = np.arange(n_dof)
        return dofs, float(scale), float(rng[1] - rng[0])

    @property
    def curve_errors(self) -> np.ndarray | None:
        """Estimated largest distance between the branch and the straight
        line joining each pair of consecutive points, shape
        (n_points - 1,): relative error of the first-harmonic amplitude of
        the contact DOF at equal Ω (amplitudes below ``CURVE_REST`` times
        the amplitude scale count as that), from the points and
        their :attr:`tangents` (the cubic Hermite curve through both
        points against the chord, as
        :func:`hbmfric.kernels.steps.arclength.chord_error`). 0 between two
        pieces (no line is drawn there). None without tangents.

        The chord is the straight line in the plane of Ω and the amplitude
        themselves: what ``plot(curve="polyline")`` on linear axes, linear
        interpolation or a line chart of :meth:`to_csv` draw. On log-log
        axes a segment between the same points is straight in the
        logarithms and lies further off where the amplitude falls or rises
        steeply: on the README oscillator (F 0.5, the default tolerance
        1e-4) the chords are within 8.0e-5 of the exact solution (this
        estimate: 8.05e-5) but the log-log segments within 4.0e-4 (28 of
        279 over 1e-4). The dense output (:meth:`resample`, ``plot``'s
        default) stays within 1.8e-5 there (60 frequencies; the points' own
        error is 2e-5).

        The step control bounds this estimate for the watched output
        alone; :meth:`curve_errors_of` gives it for any other DOF."""
        return self.curve_errors_of(None)

    def curve_errors_of(self, dof=None) -> np.ndarray | None:
        """:attr:`curve_errors` of the first-harmonic amplitude of ``dof``
        (index, name from ``dof_names`` or None: the contact DOF), shape
        (n_points - 1,).

        The step control of :func:`hbmfric.frf` keeps the chords of the
        watched output (the contact DOF) within ``curve_tolerance``; another
        DOF can have longer chords relative to its own amplitude (the load
        DOF of the paper beam: 4.4e-4 where the tip's are 4.1e-5; where a
        rigid tip sticks, its chords are not bounded at all).
        ``plot(dof=..., curve="polyline")`` and the CSV of ``hbmfric run``
        warn (:class:`~hbmfric.errors.AccuracyWarning`) when it exceeds
        ``curve_tolerance`` for the DOF they draw. None without tangents."""
        metric = self._arc_metric()
        if metric is None:
            return None
        dofs, scale, width = metric
        n = self.omega.size
        if n < 2:
            return np.zeros(0)
        n_dof, n_coef = self.coefficients.shape[1:]
        k = self.harmonic_numbers
        if 1 not in k:
            return np.zeros(n - 1)
        col = int(np.sum(np.where(k[: int(np.flatnonzero(k == 1)[0])] == 0, 1, 2)))
        dof = _resolve_dof(dof, self.dof_names, n_dof)
        dc = self.tangents[:, :-1].reshape(n, n_dof, n_coef)
        w = self.omega
        c, sn = self.coefficients[:, dof, col], self.coefficients[:, dof, col + 1]
        amp = np.hypot(c, sn)
        with np.errstate(divide="ignore", invalid="ignore"):
            da = np.where(
                amp > 0.0, (c * dc[:, dof, col] + sn * dc[:, dof, col + 1]) / amp, 0.0
            )
        dw = self.tangents[:, -1]
        d = np.diff(self.coefficients[:, dofs, :], axis=0) / scale
        length = np.sqrt(
            np.sum(d.reshape(n - 1, -1) ** 2, axis=1) + (np.diff(w) / width) ** 2
        )
        # relative units: Ω by the mean of the ends, a by the smaller one
        rw = 0.5 * (w[:-1] + w[1:])
        ra = np.minimum(amp[:-1], amp[1:])
        rest = ~(ra > 0.0)
        ra = np.where(rest, 1.0, np.maximum(ra, CURVE_REST * scale))
        ex, el = np.diff(w) / rw, np.diff(amp) / ra
        ax, al = length * dw[:-1] / rw - ex, length * da[:-1] / ra - el
        bx, bl = length * dw[1:] / rw - ex, length * da[1:] / ra - el
        chord = np.hypot(ex, el)
        run = np.maximum(np.abs(ex), chord / FOLD_CAP)
        run = np.where((dw[:-1] > 0.0) != (dw[1:] > 0.0), chord, run)
        worst = np.zeros(n - 1)
        for tau in CHORD_FRACTIONS:
            f = tau * (1.0 - tau)
            px = f * ((1.0 - tau) * ax - tau * bx)
            pl = f * ((1.0 - tau) * al - tau * bl)
            with np.errstate(divide="ignore", invalid="ignore"):
                e = np.abs(pl * ex - px * el) / run
            worst = np.fmax(worst, e)
        worst[rest] = 0.0
        worst[chord == 0.0] = 0.0
        worst = np.nan_to_num(worst, nan=0.0)
        if self.pieces is not None:
            for p in self.pieces:
                if 0 < p < n:
                    worst[p - 1] = 0.0
        return worst

    def _unwatched_excess(self, dof) -> tuple[float, int, int, float] | None:
        """How far the straight lines between the points of ``dof`` exceed
        the ``curve_tolerance`` of the :func:`hbmfric.frf` call, when
        ``dof`` is not the DOF the step control watched.

        Returns
        -------
        tuple or None
            ``(worst, interval, n_over, tolerance)``: the largest estimate
            of :meth:`curve_errors_of`, the interval where it is, the
            number of intervals over the tolerance, and the tolerance;
            None when ``dof`` is the watched DOF, the run had no curve
            tolerance, there are fewer than two points or no estimate, or
            no interval is over.
        """
        tolerance = self.info.get("curve_tolerance")
        if not tolerance or self.n_points < 2:
            return None
        n_dof = self.coefficients.shape[1]
        k = _resolve_dof(dof, self.dof_names, n_dof)
        if k == _resolve_dof(None, self.dof_names, n_dof):
            return None
        errors = self.curve_errors_of(k)
        if errors is None or errors.size == 0:
            return None
        worst = int(np.argmax(errors))
        if not errors[worst] > tolerance:
            return None
        n_over = int(np.count_nonzero(errors > tolerance))
        return float(errors[worst]), worst, n_over, float(tolerance)

    def _warn_unwatched(self, dof, stacklevel: int = 3) -> None:
        """An :class:`~hbmfric.errors.AccuracyWarning` when the straight
        lines between the points of ``dof``, a DOF the step control did not
        watch (the watched one ``frf`` warns about), are estimated
        (:meth:`curve_errors_of`) further from the branch than the
        ``curve_tolerance`` of the :func:`hbmfric.frf` call.

        The dense output is not checked: its estimate
        (:meth:`dense_error`) reads up to 15 times its error measured
        against fixed-frequency solves on such DOFs (the lap joint's drive
        DOF: 1.03e-4 against 7.1e-6), which stayed within 2.3e-5 where the
        straight lines were 2.5e-4 and 4.3e-4 off (bench/README.md "stop
        30")."""
        excess = self._unwatched_excess(dof)
        if excess is None:
            return
        error, worst, n_over, tolerance = excess
        n_intervals = self.n_points - 1
        k = _resolve_dof(dof, self.dof_names, self.coefficients.shape[1])
        import warnings

        from .errors import AccuracyWarning

        label = dof if isinstance(dof, str) else k
        warnings.warn(
            f"the straight lines between the points of DOF {label!r} are "
            f"estimated {error:.2g} off (relative amplitude), over "
            f"curve_tolerance={tolerance:g} on "
            f"{n_over} of {n_intervals} "
            f"intervals (worst between omega={self.omega[worst]:.6g} and "
            f"{self.omega[worst + 1]:.6g} rad/s): the step control bounds the "
            "lines of the watched contact DOF only; the dense output "
            "(Branch.resample, plot's default) follows the branch between "
            "them; per-interval estimates in Branch.curve_errors_of",
            AccuracyWarning,
            stacklevel=stacklevel,
        )

    @property
    def curve_error(self) -> float | None:
        """Largest of :attr:`curve_errors` (estimated relative amplitude
        error of the straight lines between the points); None without
        tangents, 0 for fewer than two points."""
        errors = self.curve_errors
        if errors is None:
            return None
        return float(np.max(errors, initial=0.0))

    # ------------------------------------------------------------------
    # stability (hbmfric/stability.py)
    def stability(
        self,
        system=None,
        perturbation_harmonics: int | None = None,
        exponents: str = "auto",
        method: str = "auto",
    ):
        """Floquet exponents of every point by Hill's method
        (:mod:`hbmfric.stability`), computed on the first call and cached
        (nothing is computed while tracing).

        Each point's stability problem uses the full harmonic basis
        ``0 … H`` of its own ``H`` (symmetric branches: the odd and even
        blocks separately) and every DOF (a condensed branch's recovered
        coefficients with the full matrices).

        Parameters
        ----------
        system : Oscillator or compatible, optional
            The system traced; default: the one :func:`~hbmfric.frf`
            recorded (a loaded branch needs it).
        perturbation_harmonics : int, optional
            Highest harmonic of the perturbation basis (the Jacobian still
            sees every harmonic of the solution): cheaper, less accurate;
            default each point's ``H``. See
            :func:`hbmfric.stability.stability_of_points`.
        exponents : {"auto", "all"}
            ``"auto"``: on a symmetric branch of one DOF, and on a branch
            whose stability comes from the monodromy, ``stable`` is
            decided at every point while the eigenvalues (multipliers) are
            computed at a few points only (``Stability.computed``); the others' are
            computed when ``exponents``, ``multipliers`` or ``max_real`` is
            first read. ``"all"``: at every point now. Both give the same
            ``stable`` (:func:`hbmfric.stability.stability_of_points`).
        method : {"auto", "hill", "monodromy"}
            ``"auto"``: Hill's method, except for a contact with memory
            (Jenkins, Dahl) on several DOFs, where Hill's linearisation of
            the hysteretic law misreads slipping points (the paper beam),
            and for a modified Dahl contact on one DOF (Hill left out its
            memory, docs/laws.md): the time-domain monodromy is used
            (with ``exponents="auto"`` at a few points: Jenkins structures
            are stable by proof, others are scheduled on Hill's signs and
            verdicts; a Dahl contact at every point;
            :func:`hbmfric.stability.stability_of_points`).

        Returns
        -------
        Stability
            ``exponents`` (n_points, 2 n_dof), ``multipliers``, ``stable``
            (n_points,), ``max_real``.

        Raises
        ------
        ValueError
            Without a system, for a rigid Coulomb contact, for another
            ``exponents``, or for a ``system`` whose harmonic balance the
            points do not solve (:func:`check_system_solves`: a loaded
            branch given another system).
        """
        if exponents not in ("auto", "all"):
            raise ValueError(f'exponents must be "auto" or "all", got {exponents!r}')
        key = perturbation_harmonics
        if system is not None and system is self._stability_system:
            system = None  # the system the cached result was computed for
        if (
            self._stability is None
            or system is not None
            or key != self._hp
            or method != self._method
        ):
            from ._validate import positive_int

            if key is not None:
                key = positive_int("perturbation_harmonics", key, low=1)
            src = _stability_source(self._source, system)
            if system is not None:
                self._check_system(system)
            from .stability import stability_of_points

            h = (
                self.point_harmonics
                if self.point_harmonics is not None
                else np.full(self.n_points, int(self.harmonic_numbers[-1]))
            )
            n_time = self.info.get("n_time")
            if self.point_harmonics is not None:
                n_time = None  # each level's default, as the run used
            self._stability = stability_of_points(
                src["system"],
                self.force,
                self.omega,
                self.harmonic_numbers,
                self.coefficients,
                h,
                n_time=n_time,
                aft=self.info.get("aft", "auto"),
                subharmonic=int(self.info.get("subharmonic", 1)),
                symmetric=bool(self.info.get("odd_only", False)),
                perturbation_harmonics=key,
                exponents=exponents,
                method=method,
            )
            if self._stability.criterion == "monodromy":
                _snap_to_folds(
                    self._stability.stable, self.folds, self._stability.computed
                )
            self._method = method
            self._hp = key
            self._stability_system = src["system"]
        if exponents == "all":
            self._stability.exponents  # noqa: B018 - computes the missing ones
        return self._stability

    def _check_system(self, system) -> None:
        """ValueError unless ``system`` is the one this branch solves (its
        residual at the first, middle and last points)."""
        h = (
            self.point_harmonics
            if self.point_harmonics is not None
            else np.full(self.n_points, int(self.harmonic_numbers[-1]))
        )
        info = dict(self.info)
        if self.point_harmonics is not None:
            info["n_time"] = None  # each level's default, as the run used
        check_system_solves(
            system,
            self.force,
            self.omega,
            self.harmonic_numbers,
            self.coefficients,
            h,
            info,
        )

    def special_points(self, system=None, stability: bool = True) -> list:
        """Folds and stability changes, each located between the two branch
        points that bracket it (:mod:`hbmfric.bifurcation`: a root search
        on the Ω tangent or on the largest Floquet exponent along the
        solutions between the points, each a full Newton solve). Where the
        stability comes from the time-domain monodromy (``criterion ==
        "monodromy"``), a change away from a fold is located on the
        monodromy's largest multiplier instead.

        Parameters
        ----------
        system : Oscillator or compatible, optional
            The system traced; default: the one :func:`~hbmfric.frf`
            recorded.
        stability : bool
            Also locate the stability changes (computes :meth:`stability`
            if needed; refused for a rigid Coulomb contact). With False,
            only the folds.

        Returns
        -------
        list of :class:`~hbmfric.bifurcation.SpecialPoint`
            In path order: ``kind`` (``"fold"``, ``"branch point"``,
            ``"period doubling"``, ``"Neimark-Sacker"``), ``omega``
            (rad/s), ``index``, the solution's ``coefficients`` and the
            crossing ``multiplier``. A fold where the stability changes
            carries the Ω of that change in ``stability_omega``.

        Warns
        -----
        ConvergenceWarning
            For an interval whose point could not be located (it is left
            out).
        """
        from .bifurcation import locate_special_points

        src = _stability_source(self._source, system)
        changes, method = None, "hill"
        if stability:
            stab = self.stability(system)  # the cached one unless given another
            changes = stab.changes()
            if stab.criterion == "monodromy":
                method = "monodromy"
        h = (
            self.point_harmonics
            if self.point_harmonics is not None
            else np.full(self.n_points, int(self.harmonic_numbers[-1]))
        )
        n_time = None if self.point_harmonics is not None else self.info.get("n_time")
        return locate_special_points(
            src["system"],
            self.force,
            self.omega,
            self.harmonic_numbers,
            self.coefficients,
            h,
            self.folds,
            changes,
            n_time=n_time,
            aft=self.info.get("aft", "auto"),
            subharmonic=int(self.info.get("subharmonic", 1)),
            symmetric=bool(self.info.get("odd_only", False)),
            stability_method=method,
        )

    @property
    def stable(self) -> np.ndarray:
        """Whether each point is stable, shape (n_points,) (computes
        :meth:`stability` on first use, or returns the last one computed)."""
        if self._stability is not None:
            return self._stability.stable
        return self.stability().stable

    def harmonics_at(self, index: int) -> int:
        """Highest harmonic used at point ``index``."""
        if self.point_harmonics is not None:
            return int(self.point_harmonics[index])
        return int(self.harmonic_numbers[-1])

    def point(self, index: int) -> PeriodicSolution:
        """The periodic solution at one point of the branch."""
        return PeriodicSolution(
            omega=float(self.omega[index]),
            force=self.force,
            harmonic_numbers=self.harmonic_numbers,
            coefficients=self.coefficients[index].copy(),
            converged=True,
            newton_iterations=0,
            residual_norm=float("nan"),
            dof_names=dict(self.dof_names),
            method="branch point",
            _source=(
                None
                if self._source is None
                else {
                    **self._source,
                    "aft": self.info.get("aft", "auto"),
                    "n_time": (
                        self.info.get("n_time")
                        if self.point_harmonics is None
                        else None
                    ),
                    "subharmonic": int(self.info.get("subharmonic", 1)),
                }
            ),
        )

    def plot(
        self,
        ax=None,
        harmonic: int | None = None,
        dof=None,
        curve: str = "dense",
        per_interval: int = 8,
        **kwargs,
    ):
        """Draw amplitude against Ω (folds marked, each piece its own
        line); returns the axes.

        ``curve``: ``"dense"`` (default) draws the dense output
        (:meth:`resample` with ``per_interval`` samples per interval),
        ``"polyline"`` the points joined by straight lines, ``"points"``
        the computed points alone (markers).

        Warns (:class:`~hbmfric.CoverageWarning`) when the branch does not
        cover its asked range (not :attr:`complete`): the axes span the
        points, not the range.

        When :meth:`stability` has been computed, unstable stretches are
        drawn dashed (``"points"``: hollow markers); each sample of the
        curve takes the stability of the nearer of its interval's ends.

        The horizontal axis is the forcing pulsation Ω: for a subharmonic
        branch (``info["subharmonic"] = ν > 1``, e.g.
        :func:`hbmfric.period_doubled_branch`, whose ``omega`` is ``Ω/ν``)
        that is ``ν * omega``, so that it lands on its parent branch's
        plot where it was born."""
        import matplotlib.pyplot as plt

        if curve not in ("dense", "polyline", "points"):
            raise ValueError(
                f"curve must be 'dense', 'polyline' or 'points', got {curve!r}"
            )
        if ax is None:
            _, ax = plt.subplots()
        amp = self.amplitude(harmonic=harmonic, dof=dof)
        if curve == "polyline":
            self._warn_unwatched(dof)
        # the axes show the points' Ω span, not the range asked for
        self._warn_coverage("the plot draws")
        nearest = np.arange(self.n_points)
        if curve == "dense" and self.n_points >= 2:
            samples, parts = self._resample(per_interval)
            x, y = samples.omega, samples.amplitude(harmonic=harmonic, dof=dof)
            idx, uu, _ = self._resample_indices(per_interval)
            nearest = idx + (uu >= 0.5)
        else:
            x, y = self.omega, amp
            parts = self.piece_slices()
        # the forcing pulsation: omega is Ω/ν on a subharmonic branch
        nu = int(self.info.get("subharmonic", 1) or 1)
        x = nu * np.asarray(x)
        if curve == "points":
            kwargs = {"ls": "", "marker": "o", "ms": 3, **kwargs}
        stable = None
        if self._stability is not None:
            stable = np.asarray(self._stability.stable, dtype=bool)[nearest]
        line = None
        for piece in parts:  # no line across the jump between pieces
            for run, ok in _stability_runs(piece, stable, curve != "points"):
                if line is not None:
                    kwargs = {**kwargs, "color": line.get_color()}
                    kwargs.pop("label", None)
                style = {}
                if not ok:
                    style = {"mfc": "none"} if curve == "points" else {"ls": "--"}
                (line,) = ax.plot(x[run], y[run], **{**kwargs, **style})
        if self.folds.size:
            ax.plot(
                nu * self.omega[self.folds],
                amp[self.folds],
                "x",
                color=line.get_color(),
            )
        ax.set_xlabel("Ω (rad/s)")
        label = "amplitude" if harmonic is None else f"harmonic {harmonic} amplitude"
        ax.set_ylabel(f"{label} (m)")
        return ax

    # ------------------------------------------------------------------
    # dense output: the branch between its points (hbmfric/dense.py)
    def _dense(self):
        from .dense import dense

        return dense(self)

    @property
    def arclength(self) -> np.ndarray:
        """Arc length of every point along the path, shape (n_points,),
        dimensionless: the sum of the chords in a space where Ω is divided
        by the width of the branch's Ω span and the coefficients by their
        largest magnitude (the jump between two pieces counts as its chord,
        but nothing is interpolated there). The parameter of
        :meth:`evaluate`."""
        return self._dense().s.copy()

    def evaluate(self, arclength):
        """The branch at arc-length parameters between its points.

        Cubic Hermite interpolation in arc length from the tangents at the
        points (``tangents`` when stored, else finite differences over the
        neighbouring points of the same piece); see :mod:`hbmfric.dense`.

        Parameters
        ----------
        arclength : array_like, shape (n_samples,)
            Parameters on the scale of :attr:`arclength` (0 at the first
            point, ``arclength[-1]`` at the last).

        Returns
        -------
        DenseSamples
            Ω (rad/s), coefficients (m) and ``amplitude()`` of every sample;
            NaN for parameters off the branch (outside ``[0,
            arclength[-1]]`` or in the jump between two pieces).
        """
        from ._validate import finite_array

        s = np.asarray(arclength, dtype=float)
        if s.ndim == 0:
            s = s.reshape(1)
        s = finite_array("arclength", s)
        d = self._dense()
        i, u = d.locate(s)
        return d.samples(i, u)

    def resample(self, per_interval: int = 8):
        """The dense output at ``per_interval`` evenly spaced arc lengths
        per interval between points (the points themselves included), in
        path order: ``(n_points - n_pieces) * per_interval + n_pieces``
        samples, no sample in the jump between pieces.

        Returns
        -------
        DenseSamples
        """
        from ._validate import positive_int

        per_interval = positive_int("per_interval", per_interval, low=1)
        return self._resample(per_interval)[0]

    def _resample(self, per_interval: int):
        """:meth:`resample` and the slice of the samples of every piece."""
        d = self._dense()
        idx, uu, parts = self._resample_indices(per_interval)
        if idx is None:
            single = np.zeros(self.n_points, dtype=np.int64)
            return d.samples(single, np.zeros(self.n_points)), parts
        return d.samples(idx, uu), parts

    def _resample_indices(self, per_interval: int):
        """Interval index and parameter ``u`` in [0, 1] of every sample of
        :meth:`resample`, and the slice of the samples of every piece;
        ``(None, None, [all points])`` below two points."""
        idx, uu, parts = [], [], []
        count = 0
        for sl in self.piece_slices():
            n = sl.stop - sl.start
            if n == 0:
                continue
            if n == 1:
                # a lone point: the start of the (one-point) interval after
                # it, or the end of the one before
                i0, u0 = (
                    (sl.start, 0.0)
                    if sl.start < self.n_points - 1
                    else (
                        sl.start - 1,
                        1.0,
                    )
                )
                idx.append(np.array([i0]))
                uu.append(np.array([u0]))
            else:
                k = np.arange(sl.start, sl.stop - 1)
                u = np.arange(per_interval) / per_interval
                idx.append(np.append(np.repeat(k, per_interval), sl.stop - 2))
                uu.append(np.append(np.tile(u, k.size), 1.0))
            parts.append(slice(count, count + idx[-1].size))
            count += idx[-1].size
        if not idx or self.n_points < 2:
            return None, None, [slice(0, self.n_points)]
        return np.concatenate(idx), np.concatenate(uu), parts

    def amplitude_at(
        self,
        omega,
        harmonic: int | None = 1,
        dof=None,
        *,
        return_error: bool = False,
    ):
        """Amplitude of the dense output at given Ω, all its values where
        the branch passes several times (past folds, or pieces overlapping).

        Parameters
        ----------
        omega : array_like, shape (n_omega,)
            Pulsations, rad/s.
        harmonic : int or None, default 1
            As in :meth:`amplitude`.
        dof : int, str or None
            As in :meth:`amplitude`.
        return_error : bool
            Also return the estimated relative error of every value
            (:meth:`dense_error` of its interval).

        Returns
        -------
        amplitude : ndarray, shape (n_omega, n_values)
            ``amplitude[j, :]``: the values at ``omega[j]`` in path order,
            padded with NaN; ``n_values`` is the largest number of passes
            (at least 1). A row of NaN: the branch does not reach that Ω.
        error : ndarray, shape (n_omega, n_values)
            Only with ``return_error``.
        """
        from ._validate import finite_array

        w = np.asarray(omega, dtype=float)
        if w.ndim == 0:
            w = w.reshape(1)
        w = finite_array("omega", w)
        d = self._dense()
        k = _resolve_dof(dof, self.dof_names, self.coefficients.shape[1])
        roots = d.solve_omega(w)
        width = max([1] + [len(r) for r in roots])
        amp = np.full((w.size, width), np.nan)
        idx = np.array([i for r in roots for i, _ in r], dtype=np.int64)
        uu = np.array([u for r in roots for _, u in r], dtype=float)
        if idx.size:
            values = d.samples(idx, uu).amplitude(harmonic=harmonic, dof=k)
            rows = np.repeat(np.arange(w.size), [len(r) for r in roots])
            cols = np.concatenate([np.arange(len(r)) for r in roots if r])
            amp[rows, cols] = values
        if not return_error:
            return amp
        err = np.full_like(amp, np.nan)
        if idx.size:
            est = d.error_estimate(k, harmonic)
            err[rows, cols] = est[idx]
        return amp, err

    def dense_error(self, harmonic: int | None = 1, dof=None) -> np.ndarray:
        """Estimated error of the dense output on every interval.

        The largest relative error of the amplitude at fixed Ω between
        points ``i`` and ``i + 1`` (interpolation only: the points' own
        error is :attr:`truncation_error`), from the difference between the
        Hermite cubic and the cubics through four neighbouring points
        (:mod:`hbmfric.dense`).

        Returns
        -------
        ndarray, shape (n_points - 1,)
            NaN for the jump between two pieces.
        """
        k = _resolve_dof(dof, self.dof_names, self.coefficients.shape[1])
        return self._dense().error_estimate(k, harmonic)

    # ------------------------------------------------------------------
    def to_csv(self, path: str | Path, dof=None) -> Path:
        """Write one DOF's FRF as CSV, the columns of ``hbmfric run``'s:
        ``omega`` (rad/s, path order; on a subharmonic branch such as
        :func:`hbmfric.period_doubled_branch`'s its ``omega``, Ω/ν, and
        ``amplitude`` that of the Ω/ν harmonic, while :meth:`plot` draws
        against the forcing Ω), ``amplitude`` (first-harmonic
        amplitude of ``dof``, index or name, default the contact DOF, m)
        and ``truncation_error`` (the per-point estimate of the output the
        harmonic control watches; empty estimates as ``nan``).

        Warns (:class:`~hbmfric.AccuracyWarning`) as :meth:`plot` with
        ``curve="polyline"`` does when ``dof`` is not the DOF the step
        control watched and its straight lines stray beyond the curve
        tolerance. Everything else of the branch: :meth:`save`.

        A branch of several :attr:`pieces` gets a row of ``nan`` between
        two pieces (the path jumps there: a line drawn through the rows
        breaks at it, as :meth:`plot` draws no line across). A branch that
        does not cover its asked range (not :attr:`complete`) warns
        (:class:`~hbmfric.CoverageWarning`), naming the covered parts and
        the gaps, which the file cannot show (a period-doubled branch that
        returned to its parent or reached an end of the range is whole
        where it exists: no warning, as from
        :func:`hbmfric.period_doubled_branch`)."""
        import csv

        path = Path(path)
        amp = self.amplitude(harmonic=1, dof=dof)
        # the lines a reader draws through these points, for a DOF the step
        # control did not watch
        self._warn_unwatched(dof, stacklevel=3)
        self._warn_coverage("the CSV holds", stacklevel=3)
        err = (
            self.truncation_error
            if self.truncation_error is not None
            else np.full(len(self), np.nan)
        )
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["omega", "amplitude", "truncation_error"])
            for k, piece in enumerate(self.piece_slices()):
                if k:  # the jump between two pieces: no line across it
                    w.writerow(["nan", "nan", "nan"])
                for om, a, e in zip(
                    self.omega[piece], amp[piece], err[piece], strict=True
                ):
                    w.writerow([f"{om:.12g}", f"{a:.12g}", f"{e:.3g}"])
        return path

    def _warn_coverage(self, what: str, stacklevel: int = 3) -> None:
        """A :class:`~hbmfric.CoverageWarning` when the branch does not
        cover its asked range (:attr:`complete`), for an output (``what``:
        "the CSV holds") that does not show the range itself. Silent when
        the branch does not record its range, and for a period-doubled
        branch that returned to its parent or reached an end of the range
        (it exists only from its birth on)."""
        rng = self.omega_range
        if rng is None or self.complete:
            return
        if self.info.get("born_at") is not None:
            from .continuation.palc import RANGE_END, RANGE_START

            # a period-doubled branch exists from its birth on: it has said
            # all it could not cover when it stopped otherwise (as
            # period_doubled_branch warns)
            if self.stop_reason in (RANGE_END, RANGE_START) or (
                self.stop_reason.startswith("returned to the period-T branch")
            ):
                return
        import warnings

        from .errors import CoverageWarning

        covered = ", ".join(
            f"[{self.omega[p].min():.6g}, {self.omega[p].max():.6g}]"
            for p in self.piece_slices()
            if p.stop > p.start
        )
        gaps = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in self.gaps)
        warnings.warn(
            f"{what} a branch that covers only {covered or 'nothing'} of its "
            f"asked range [{rng[0]:.6g}, {rng[1]:.6g}] rad/s"
            + (f" (gaps: {gaps})" if gaps else " (it turned back before the end)")
            + f"; stop: {self.stop_reason}",
            CoverageWarning,
            stacklevel=stacklevel,
        )

    def save(self, path: str | Path) -> Path:
        """Write the branch to ``path`` (``.npz``, no pickle)."""
        path = Path(path)
        meta = {
            "force": self.force,
            "stop_reason": self.stop_reason,
            "n_steps": self.n_steps,
            "n_rejected": self.n_rejected,
            "newton_iterations": self.newton_iterations,
            "elapsed": self.elapsed,
            "info": self.info,
            "dof_names": self.dof_names,
            "format": "hbmfric.Branch/1",
        }
        arrays = {
            "omega": self.omega,
            "coefficients": self.coefficients,
            "harmonic_numbers": self.harmonic_numbers,
            "folds": self.folds,
            "meta": np.array(json.dumps(meta)),
        }
        if self.point_harmonics is not None:
            arrays["point_harmonics"] = self.point_harmonics
        if self.truncation_error is not None:
            arrays["truncation_error"] = self.truncation_error
        if self.pieces is not None:
            arrays["pieces"] = self.pieces
        if self.tangents is not None:
            arrays["tangents"] = self.tangents
        np.savez(path, **arrays)
        return path if path.suffix == ".npz" else path.with_suffix(path.suffix + ".npz")

    @classmethod
    def load(cls, path: str | Path) -> Branch:
        """Read a branch written by :meth:`save` (no pickle).

        Raises
        ------
        ValueError
            If ``path`` is not a readable hbmfric branch file.
        """
        check_npz_sizes(path, "branch")
        try:
            with np.load(Path(path), allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                if (
                    not isinstance(meta, dict)
                    or meta.get("format") != "hbmfric.Branch/1"
                ):
                    raise ValueError("wrong format tag")
                branch = cls(
                    omega=stored_array(data, "omega", np.float64),
                    coefficients=stored_array(data, "coefficients", np.float64),
                    harmonic_numbers=stored_array(data, "harmonic_numbers", np.int64),
                    force=float(meta["force"]),
                    folds=stored_array(data, "folds", np.int64),
                    stop_reason=str(meta["stop_reason"]),
                    n_steps=int(meta["n_steps"]),
                    n_rejected=int(meta["n_rejected"]),
                    newton_iterations=int(meta["newton_iterations"]),
                    elapsed=float(meta["elapsed"]),
                    info=dict(meta["info"]),
                    dof_names={
                        str(k): int(v) for k, v in meta.get("dof_names", {}).items()
                    },
                    point_harmonics=optional_array(data, "point_harmonics", np.int64),
                    truncation_error=optional_array(
                        data, "truncation_error", np.float64
                    ),
                    pieces=optional_array(data, "pieces", np.int64),
                    tangents=optional_array(data, "tangents", np.float64),
                )
        except READ_ERRORS as exc:
            raise ValueError(
                f"path {str(path)!r} is not an hbmfric branch file, or is damaged "
                f"({exc})"
            ) from None
        _check_branch_arrays(path, branch)
        info = branch.info
        nu = int(info.get("subharmonic", 1) or 1)
        if (
            info.get("born_at") is not None
            and nu > 1
            and "forcing_omega_range" not in info
            and info.get("omega_range") is not None
        ):
            # a period-doubled branch saved before its range was recorded in
            # the units of its omega (Ω/2): it held the forcing range
            lo, hi = (float(v) for v in info["omega_range"])
            info["forcing_omega_range"] = [lo, hi]
            info["omega_range"] = [lo / nu, hi / nu]
        return branch


def _picklable_state(obj) -> dict:
    """``obj.__dict__`` for pickling, without the recorded system when that
    cannot be pickled (a branch returned by a worker process then needs
    the system passed to ``stability``)."""
    import pickle

    state = obj.__dict__.copy()
    try:
        pickle.dumps(state.get("_source"))
    except Exception:  # noqa: BLE001 - any pickling failure drops it
        state["_source"] = None
        state["_stability"] = None
        if "_stability_system" in state:
            state["_stability_system"] = None
    return state


def _stability_runs(piece: slice, stable: np.ndarray | None, join: bool = True):
    """Consecutive samples of ``piece`` with the same stability, as
    ``(slice, stable)``; with ``join`` a run ends on the first sample of
    the next one so that the drawn line has no gap. One stable run when
    ``stable`` is None."""
    if stable is None or piece.stop - piece.start < 1:
        return [(piece, True)]
    flags = stable[piece]
    cuts = np.flatnonzero(flags[1:] != flags[:-1]) + 1
    starts = np.concatenate(([0], cuts))
    ends = np.concatenate((cuts, [flags.size]))
    return [
        (
            slice(piece.start + a, piece.start + min(b + int(join), flags.size)),
            bool(flags[a]),
        )
        for a, b in zip(starts, ends, strict=True)
    ]


#: points within which a stability change of the time-domain monodromy is
#: moved onto a fold of the branch (across points whose multipliers were
#: not computed only, :func:`_snap_to_folds`)
FOLD_SNAP = 12


def _snap_to_folds(
    stable: np.ndarray, folds: np.ndarray, computed: np.ndarray | None = None
) -> None:
    """Move a change of ``stable`` found within ``FOLD_SNAP`` points of a
    fold onto that fold, in place, where no computed point is crossed.

    At a fold a real multiplier crosses +1, so the stability changes there
    (Hill's exponents are exact at it), while the verdict of points filled
    between computed ones is only as close as the schedule put them. Each
    change found in ``stable`` as given moves at most once, onto its
    nearest fold, and only when that fold has no other change within
    ``FOLD_SNAP`` points, the change is not on a fold already, and no point
    whose verdict it would flip is ``computed``: a verdict never
    contradicts the multipliers computed at its point (issue 16, stop 27:
    in a cluster of seven folds the changes were carried from fold to fold
    across a computed unstable stretch). ``computed`` None: no point is.

    Parameters
    ----------
    stable : ndarray of bool, shape (n_points,)
        Verdicts, changed in place.
    folds : ndarray of int
        Indices of the folds (:attr:`Branch.folds`).
    computed : ndarray of bool, shape (n_points,), optional
        Points whose verdict comes from their own multipliers.
    """
    folds = np.unique(np.asarray(folds, dtype=np.int64))
    if folds.size == 0 or stable.size < 2:
        return
    original = stable.copy()
    changes = np.flatnonzero(original[1:] != original[:-1]) + 1
    for c in (int(v) for v in changes):
        distance = np.abs(folds - c)
        f = int(folds[np.argmin(distance)])
        if f == c or abs(f - c) > FOLD_SNAP:
            continue
        if np.count_nonzero(np.abs(changes - f) <= FOLD_SNAP) != 1:
            continue
        lo, hi = (f, c) if f < c else (c, f)
        if computed is not None and computed[lo:hi].any():
            continue
        stable[lo:hi] = original[c] if f < c else original[c - 1]


def _stability_source(source: dict | None, system) -> dict:
    """The system and discretisation for a stability computation:
    ``source`` recorded by the run, ``system`` overriding its system."""
    src = dict(source or {})
    if system is not None:
        src["system"] = system
    if src.get("system") is None:
        raise ValueError(
            "stability needs the system: this result does not record it (a "
            "loaded branch?); pass it, e.g. branch.stability(system)"
        )
    return src


#: largest residual, relative to the load, of a point checked against a
#: system passed for it (a traced point's is about 1e-10)
SYSTEM_CHECK_TOL = 1e-6


def check_system_solves(
    system, force, omega, harmonic_numbers, coefficients, harmonics, info
) -> None:
    """Check that points of a result solve ``system``'s harmonic balance.

    A system passed for a loaded (or any) result must be the one it was
    traced for; Hill's or the monodromy's verdicts on points that solve
    another system mean nothing. The first, middle and last points are
    checked (the full, uncondensed residual).

    Parameters
    ----------
    system : Oscillator or compatible
    force : float
        Forcing amplitude, N.
    omega : ndarray, shape (n_points,)
        Pulsations, rad/s.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (n_points, n_dof, n_coef)
        Fourier coefficients, m.
    harmonics : ndarray of int, shape (n_points,)
        Highest harmonic of every point.
    info : mapping
        ``n_time``, ``aft``, ``subharmonic`` and ``odd_only`` of the run.

    Raises
    ------
    ValueError
        Another number of DOFs, or a residual above
        :data:`SYSTEM_CHECK_TOL` times the load.
    """
    from .api import _problem

    n_points = int(np.size(omega))
    n_dof = int(np.shape(coefficients)[1])
    for i in sorted({0, n_points // 2, n_points - 1}) if n_points else []:
        problem = _problem(
            system,
            force,
            int(harmonics[i]),
            info.get("n_time"),
            bool(info.get("odd_only", False)),
            info.get("aft", "auto"),
            False,
            int(info.get("subharmonic", 1) or 1),
        )
        if problem.n_dof != n_dof:
            raise ValueError(
                f"the system has {problem.n_dof} DOFs but the result {n_dof}: "
                "pass the system the result was computed for"
            )
        source = {}
        col = 0
        for k in harmonic_numbers:
            width = 1 if k == 0 else 2
            source[int(k)] = slice(col, col + width)
            col += width
        X = np.zeros((n_dof, problem.n_coef))
        col = 0
        for k in problem.harmonic_numbers:
            width = 1 if k == 0 else 2
            if int(k) in source:
                X[:, col : col + width] = coefficients[i][:, source[int(k)]]
            col += width
        y = np.append(problem.unknowns_from_full(X), float(omega[i]))
        residual, _, status = problem.residual(y)
        load = max(float(np.max(np.abs(problem.load))), 1e-300)
        worst = float(np.max(np.abs(residual))) if status >= 0 else math.inf
        if not worst <= SYSTEM_CHECK_TOL * load:
            raise ValueError(
                f"point {i} (omega = {float(omega[i]):.6g} rad/s) does not solve "
                f"this system's harmonic balance (residual {worst:.3g}, load "
                f"{load:.3g}): pass the system the result was computed for"
            )


def _check_branch_arrays(path, branch: Branch) -> None:
    """Check that the arrays of a loaded branch agree with each other;
    ``ValueError`` naming the file and the field otherwise."""
    bad = field_error(path)

    n = branch.omega.size
    if branch.omega.ndim != 1:
        raise bad("omega", f"must be 1-d, has shape {branch.omega.shape}")
    if not np.all(np.isfinite(branch.omega)):
        raise bad("omega", "has non-finite values")
    n_coef = check_harmonics(bad, branch.harmonic_numbers)
    c = branch.coefficients
    if c.ndim != 3 or c.shape[0] != n or c.shape[2] != n_coef:
        raise bad(
            "coefficients",
            f"has shape {c.shape}; omega ({n} points) and harmonic_numbers "
            f"({n_coef} coefficients) ask for ({n}, n_dof, {n_coef})",
        )
    if not np.all(np.isfinite(c)):
        raise bad("coefficients", "has non-finite values")
    folds = branch.folds
    if folds.ndim != 1 or np.any(folds < 0) or np.any(folds > n):
        raise bad("folds", f"must be point indices in [0, {n}], got {folds}")
    ph = branch.point_harmonics
    if ph is not None and ph.shape != (n,):
        raise bad("point_harmonics", f"must have shape ({n},), got {ph.shape}")
    te = branch.truncation_error
    if te is not None and te.shape != (n,):
        raise bad("truncation_error", f"must have shape ({n},), got {te.shape}")
    pc = branch.pieces
    if pc is not None and (
        pc.ndim != 1
        or pc.size == 0
        or pc[0] != 0
        or np.any(np.diff(pc) < 0)
        or pc[-1] > n
    ):
        raise bad("pieces", f"must be increasing point indices from 0, got {pc}")
    n_dof = c.shape[1]
    tg = branch.tangents
    if tg is not None and tg.shape != (n, n_dof * n_coef + 1):
        raise bad(
            "tangents", f"must have shape ({n}, {n_dof * n_coef + 1}), got {tg.shape}"
        )
    if tg is not None and not np.all(np.isfinite(tg)):
        raise bad("tangents", "has non-finite values")
    for name, index in branch.dof_names.items():
        if not 0 <= index < n_dof:
            raise bad("dof_names", f"maps {name!r} to {index}, not in [0, {n_dof - 1}]")


def join_pieces(first: Branch, second: Branch, stop_reason: str) -> Branch:
    """One branch of two pieces of the same range traced from its two ends.

    The points are those of ``first`` in path order, then those of
    ``second`` reversed (so that the combined Ω runs from the start of the
    first sweep, through the ends where the pieces stopped, to the start of
    the second); ``pieces`` marks where the second begins. Work counters
    and times are summed; fold indices are carried over.

    Parameters
    ----------
    first, second : Branch
        Pieces with the same DOFs; the harmonic numbers of one must be a
        prefix of the other's (fixed ``H``: equal), the shorter ones'
        coefficients are padded with zeros.
    stop_reason : str
        Stop reason of the combined branch.
    """
    hn1, hn2 = first.harmonic_numbers, second.harmonic_numbers
    longer = hn1 if hn1.size >= hn2.size else hn2
    shorter = hn2 if hn1.size >= hn2.size else hn1
    if not np.array_equal(longer[: shorter.size], shorter):
        raise ValueError("pieces with unrelated harmonic numbers cannot be joined")
    n_dof = first.coefficients.shape[1]
    n_coef = int(sum(1 if k == 0 else 2 for k in longer))

    def padded(b: Branch, order) -> np.ndarray:
        out = np.zeros((b.omega.size, n_dof, n_coef))
        out[:, :, : b.coefficients.shape[2]] = b.coefficients[order]
        return out

    n1, n2 = first.omega.size, second.omega.size
    back = slice(None, None, -1)
    # a fold between points i - 1 and i of the second piece lies between
    # its reversed points n2 - i - 1 and n2 - i
    folds = np.concatenate((first.folds, n1 + n2 - second.folds[::-1])).astype(np.int64)

    def harmonics_of(b: Branch) -> np.ndarray:
        if b.point_harmonics is not None:
            return b.point_harmonics
        return np.full(b.omega.size, int(b.harmonic_numbers[-1]), dtype=np.int64)

    def padded_tangents(b: Branch, order, sign: float) -> np.ndarray:
        out = np.zeros((b.omega.size, n_dof * n_coef + 1))
        m = b.coefficients.shape[2]
        t = b.tangents[order]
        out[:, :-1].reshape(-1, n_dof, n_coef)[:, :, :m] = sign * t[:, :-1].reshape(
            -1, n_dof, m
        )
        out[:, -1] = sign * t[:, -1]
        return out

    tangents = None
    if first.tangents is not None and second.tangents is not None:
        # the second piece runs backwards: its tangents turn round
        tangents = np.concatenate(
            (
                padded_tangents(first, slice(None), 1.0),
                padded_tangents(second, back, -1.0),
            )
        )
    truncation_error = None
    if first.truncation_error is not None and second.truncation_error is not None:
        truncation_error = np.concatenate(
            (first.truncation_error, second.truncation_error[back])
        )
    point_harmonics = None
    if first.point_harmonics is not None or second.point_harmonics is not None:
        point_harmonics = np.concatenate(
            (harmonics_of(first), harmonics_of(second)[back])
        )
    info = dict(first.info)
    for key in (
        "bridges",
        "harmonic_switches",
        "harmonic_resolves",
        "harmonic_settled",
        "harmonic_calibrations",
    ):
        if key in first.info and key in second.info:
            info[key] = first.info[key] + second.info[key]
    info["pieces"] = [
        {
            "sweep": b.info.get("sweep"),
            "stop_reason": b.stop_reason,
            "coverage": list(b.coverage) if b.omega.size else None,
            "n_points": int(b.omega.size),
        }
        for b in (first, second)
    ]
    return Branch(
        omega=np.concatenate((first.omega, second.omega[back])),
        coefficients=np.concatenate((padded(first, slice(None)), padded(second, back))),
        harmonic_numbers=longer.copy(),
        force=first.force,
        folds=folds,
        stop_reason=stop_reason,
        n_steps=first.n_steps + second.n_steps,
        n_rejected=first.n_rejected + second.n_rejected,
        newton_iterations=first.newton_iterations + second.newton_iterations,
        elapsed=first.elapsed + second.elapsed,
        info=info,
        point_harmonics=point_harmonics,
        dof_names=dict(first.dof_names),
        pieces=np.array([0, n1], dtype=np.int64),
        truncation_error=truncation_error,
        tangents=tangents,
        _source=first._source,
    )
