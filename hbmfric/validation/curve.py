"""The error of the curve a user draws: a branch's points joined by straight
lines, against reference solutions between them.

Every point of a branch can be exact and the polyline through them still be
far from the true response where the step is long (a linear or stuck
stretch near a sharp peak). :func:`polyline_error` measures that curve in
the plane users plot, Ω against the first-harmonic amplitude of one DOF,
relative to the local amplitude (as read off a log axis).
:func:`curve_references` builds the reference points: exact event-driven
periodic solutions (:func:`~hbmfric.validation.exact_branch`, a Jenkins
contact) or, for other laws, converged time integration
(:func:`~hbmfric.validation.steady_state`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceWarning, HbmfricWarning

#: fewest pulsations of an exact (event-driven) reference set
MIN_EXACT = 100
#: fewest pulsations of a time-integration reference set
MIN_INTEGRATED = 40


@dataclass
class CurveError:
    """Error of a branch's polyline against references.

    Attributes
    ----------
    omega : ndarray, shape (n_ref,)
        Reference pulsations Ω_r, rad/s.
    reference : ndarray, shape (n_ref,)
        Reference first-harmonic amplitudes a_r, m.
    value : ndarray, shape (n_ref,)
        The polyline's amplitude at Ω_r closest to a_r (NaN where no
        segment covers Ω_r), m.
    error : ndarray, shape (n_ref,)
        ``|value - a_r| / a_r``; inf where no segment covers Ω_r.
    uncovered : ndarray of int
        Indices of the reference pulsations no segment covers.
    """

    omega: np.ndarray
    reference: np.ndarray
    value: np.ndarray
    error: np.ndarray
    uncovered: np.ndarray

    @property
    def max(self) -> float:
        """Largest relative error (inf if some Ω_r is not covered)."""
        return float(np.max(self.error)) if self.error.size else 0.0

    @property
    def worst_omega(self) -> float:
        """Ω_r of the largest error, rad/s."""
        return float(self.omega[int(np.argmax(self.error))])


def polyline_error(
    omega, amplitude, reference_omega, reference_amplitude, pieces=None
) -> CurveError:
    """Error of straight lines between a branch's points at reference
    pulsations.

    For each reference ``(Ω_r, a_r)``, every segment of the polyline
    ``(omega[i], amplitude[i]) → (omega[i+1], amplitude[i+1])`` whose Ω
    interval contains Ω_r (ends included) is interpolated linearly at Ω_r;
    of those values (several where the branch folds back over Ω_r) the one
    closest to ``a_r`` is kept, and its relative error ``|a - a_r| / a_r``
    is the error at Ω_r. No segment joins two separately traced pieces.
    A reference that no segment covers gets an infinite error (and is
    listed in ``uncovered``): the curve is missing there.

    Parameters
    ----------
    omega, amplitude : array_like, shape (n_points,)
        The branch in path order: Ω (rad/s) and the first-harmonic
        amplitude of the output DOF (m), e.g. ``branch.omega`` and
        ``branch.amplitude(harmonic=1)``.
    reference_omega, reference_amplitude : array_like, shape (n_ref,)
        Reference pulsations (rad/s) and amplitudes (m, > 0).
    pieces : array_like of int, optional
        First point of each piece (``Branch.pieces``); None: one piece.

    Returns
    -------
    CurveError
    """
    w = np.asarray(omega, dtype=float).ravel()
    a = np.asarray(amplitude, dtype=float).ravel()
    wr = np.asarray(reference_omega, dtype=float).ravel()
    ar = np.asarray(reference_amplitude, dtype=float).ravel()
    if w.shape != a.shape:
        raise ValueError(f"omega and amplitude differ in shape: {w.shape}, {a.shape}")
    if wr.shape != ar.shape:
        raise ValueError("reference_omega and reference_amplitude differ in shape")
    if not np.all(ar > 0):
        raise ValueError("reference amplitudes must be > 0")
    joined = np.ones(max(w.size - 1, 0), dtype=bool)
    if pieces is not None:
        for p in np.asarray(pieces, dtype=np.int64).ravel():
            if 0 < p <= joined.size:
                joined[p - 1] = False
    w0, w1 = w[:-1][joined], w[1:][joined]
    a0, a1 = a[:-1][joined], a[1:][joined]
    lo, hi = np.minimum(w0, w1), np.maximum(w0, w1)
    value = np.full(wr.size, np.nan)
    for j, (x, target) in enumerate(zip(wr, ar, strict=True)):
        sel = (lo <= x) & (x <= hi)
        if not np.any(sel):
            continue
        d = w1[sel] - w0[sel]
        frac = np.where(d != 0.0, (x - w0[sel]) / np.where(d != 0.0, d, 1.0), 0.5)
        cand = a0[sel] + frac * (a1[sel] - a0[sel])
        value[j] = cand[np.argmin(np.abs(cand - target))]
    error = np.where(np.isnan(value), np.inf, np.abs(value - ar) / ar)
    return CurveError(
        omega=wr,
        reference=ar,
        value=value,
        error=error,
        uncovered=np.flatnonzero(np.isnan(value)),
    )


def branch_curve_error(branch, reference_omega, reference_amplitude, dof=None):
    """:func:`polyline_error` of a :class:`~hbmfric.Branch`: its Ω and
    first-harmonic amplitude at ``dof`` (index, name or None: the contact
    DOF), its pieces kept apart."""
    return polyline_error(
        branch.omega,
        branch.amplitude(harmonic=1, dof=dof),
        reference_omega,
        reference_amplitude,
        pieces=branch.pieces,
    )


def chord_midpoints(omega) -> np.ndarray:
    """Ω at the middle of every chord of a branch (where a straight line
    between points is furthest from a smooth curve), sorted, rad/s."""
    w = np.asarray(omega, dtype=float).ravel()
    return np.sort(0.5 * (w[:-1] + w[1:]))


def reference_omegas(omega_range, n: int, branch=None) -> np.ndarray:
    """``n`` evenly spaced pulsations over ``omega_range`` (ends included),
    with the chord midpoints of ``branch`` added when given; sorted,
    unique, rad/s."""
    lo, hi = float(omega_range[0]), float(omega_range[1])
    w = np.linspace(lo, hi, int(n))
    if branch is not None:
        w = np.concatenate((w, chord_midpoints(branch.omega)))
    return np.unique(w)


def curve_references(
    system,
    force: float,
    omegas,
    *,
    method: str = "exact",
    dof=None,
    harmonics: int = 15,
    steps_per_period: int = 2048,
    tol: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Reference first-harmonic amplitudes at the pulsations ``omegas``.

    Parameters
    ----------
    system : Oscillator or compatible
    force : float
        Forcing amplitude, N.
    omegas : array_like, shape (n_ref,)
        Pulsations, rad/s: at least ``MIN_EXACT`` (100) for
        ``method="exact"``, ``MIN_INTEGRATED`` (40) for ``"integrate"``;
        :func:`reference_omegas` adds a branch's chord midpoints.
    method : {"exact", "integrate"}
        ``"exact"``: event-driven exact periodic solutions
        (:func:`~hbmfric.validation.exact_branch`; linear structure with
        one Jenkins contact), each converged to ``tol`` (default 1e-12).
        ``"integrate"``: steady state of time integration
        (:func:`~hbmfric.validation.steady_state`, ``steps_per_period``
        steps, each started from the stuck linear solution), any law; each
        must converge (``tol`` default 1e-10).
    dof : int, str or None
        Output DOF (None: the contact DOF).
    harmonics : int
        Harmonics kept by the time integration.

    Returns
    -------
    omega : ndarray, shape (n_ref,)
        The pulsations, rad/s.
    amplitude : ndarray, shape (n_ref,)
        First-harmonic amplitude at ``dof``, m.

    Raises
    ------
    ValueError
        Too few pulsations, or a reference did not converge.
    """
    from .exact import exact_branch
    from .steady_state import steady_state

    w = np.asarray(omegas, dtype=float).ravel()
    if method == "exact":
        if w.size < MIN_EXACT:
            raise ValueError(f"exact references need >= {MIN_EXACT} pulsations")
        with warnings.catch_warnings():
            warnings.simplefilter("error", HbmfricWarning)
            sols = exact_branch(
                system,
                force,
                w,
                tol=1e-12 if tol is None else tol,
                on_failure="raise",
            )
        amp = np.array([s.amplitude(harmonic=1, dof=dof) for s in sols])
        return w, amp
    if method != "integrate":
        raise ValueError(f"method must be 'exact' or 'integrate', got {method!r}")
    if w.size < MIN_INTEGRATED:
        raise ValueError(f"time-integration references need >= {MIN_INTEGRATED}")
    amp = np.empty(w.size)
    for i, omega in enumerate(w):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            ss = steady_state(
                system,
                force,
                float(omega),
                harmonics=harmonics,
                steps_per_period=steps_per_period,
                tol=1e-10 if tol is None else tol,
                initial_state="linear",
            )
        if not ss.converged:
            raise ValueError(
                f"time integration did not converge at omega={omega:g} ({ss.message})"
            )
        amp[i] = ss.amplitude(harmonic=1, dof=dof)
    return w, amp
