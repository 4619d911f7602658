"""Exact, event-driven periodic references for a linear structure with one
Jenkins contact (elastic–perfectly-plastic spring, Masing macroslip).

The system is ``M ẍ + C ẋ + K x + e_c f_c = p cos Ωt`` (``p`` the load
vector, ``e_c`` the contact DOF). The Jenkins force is ``f_c = k_t (x_c -
w)`` while stuck (slider ``w`` fixed, ``|f_c| < f_s``) and ``f_c = ±f_s``
while slipping (the slider follows ``x_c``). Between events the motion is a
linear ODE with harmonic forcing, solved here in closed form:

* the state is ``y = (q, p, φ)``: modal coordinates of the structure
  without contact (``x = Φ q``, all modes, ``Φ`` mass-normalised), modal
  velocities scaled by the natural pulsations (``q̇ = diag(ω) p``) and the
  spring deflection ``φ = f_c / k_t``; ``φ̇ = ẋ_c`` while stuck, ``φ̇ = 0``
  while slipping, so one linear system per phase (``A_stick``,
  ``A_slip``) covers both slip directions;
* in a phase, ``y(t) = Re(P e^{iΩt}) + Re(V e^{Λ(t - t_a)} c)``: the
  harmonic particular solution plus the homogeneous one through the
  eigen-decomposition of the phase matrix, evaluated at any instant in
  ``O(n)`` operations;
* events: stick → slip when ``|φ|`` reaches ``δ = f_s / k_t``; slip → stick
  when ``ẋ_c`` turns against the slip direction. Each is bracketed on a fine
  sub-grid of the phase (sign changes, and extremes of the event function
  for near-grazing dips) and located by Brent's method to rounding;
* the periodic steady state is found by shooting from an instant ``t_0``
  in the middle of a stick phase, where the period map is smooth in all
  of ``y``: Newton on ``y(t_0 + T) - y(t_0) = 0`` with the exact monodromy
  (product of the phase propagators, the saltation matrix at stick → slip
  zeroing the ``φ`` component, the identity at slip → stick), started from
  an HBM solution or a neighbouring reference.

A response that never slips is the linear stuck one (slider centred); a
zero slip force gives the linear response without contact. Harmonics are
integrated exactly phase by phase; half the peak-to-peak value is found by
Brent's method on the velocity.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from .._validate import finite_float, positive_int
from ..errors import ConvergenceError, ConvergenceWarning, HbmfricWarning
from ..systems.protocol import check_load

__all__ = [
    "BranchErrors",
    "ExactSolution",
    "branch_errors",
    "exact_branch",
    "exact_periodic_solution",
]

STICK, SLIP = 0, 1
#: sub-grid of a phase for bracketing events and extremes, points per period
_SCAN = 1024
#: grid points per period of a phase's fastest free oscillation, at least:
#: a stiff stuck mode (Jenkins kt = 1e6 N/m on an oscillator of 1 N/m, at
#: Ω = 3 rad/s: 1000 rad/s) rang about three times per grid step of
#: ``_SCAN``, and the scan missed the stick phase's end (the force reached
#: 3.9 times the slip force, period-map residual 6e-14, no warning)
_SCAN_FAST = 16
#: a mode's part in a phase's event function below this fraction of the
#: function's scale is not resolved by the scan: a crossing such a ripple
#: alone could make shifts an event by about this fraction of the slip
#: limit over the slope (the paper beam's 100 references: 1.7e-14 from the
#: scan of stop 31, 69.6 s against 65.2 s of CPU; with every mode resolved
#: 268 s; with 1e-10, 106 s)
_SEEN = 1e-6


# ----------------------------------------------------------------------------
# the linear model in modal coordinates
# ----------------------------------------------------------------------------
class _Model:
    """Phase matrices, eigen-decompositions and particular solutions of one
    system at one forcing (``force``, ``omega``)."""

    def __init__(self, system, force: float, omega: float):
        M, C, K = (np.asarray(a, dtype=float) for a in system.matrices())
        n = M.shape[0]
        law = system.contact
        self.kt = float(law.stiffness)
        self.fs = float(law.slip_force)
        self.delta = self.fs / self.kt
        self.omega = omega
        self.period = 2.0 * math.pi / omega
        w2, phi = scipy.linalg.eigh(K, M)  # K > 0 checked by _check_system
        wn = np.sqrt(w2)
        self.n = n
        self.size = 2 * n + 1
        self.shapes = phi
        self.wn = wn
        cm = phi.T @ C @ phi
        ac = phi[system.contact_dof]  # x_c = ac . q
        pf = phi.T @ _cosine_load(system, force)
        # y = (q, p, φ): q' = W p, p' = -W q - W⁻¹ Cm W p - W⁻¹ ac kt φ + W⁻¹ pf cos
        A = np.zeros((self.size, self.size))
        A[:n, n : 2 * n] = np.diag(wn)
        A[n : 2 * n, :n] = -np.diag(wn)
        A[n : 2 * n, n : 2 * n] = -(cm * wn[None, :]) / wn[:, None]
        A[n : 2 * n, 2 * n] = -self.kt * ac / wn
        slip = A.copy()
        A[2 * n, n : 2 * n] = ac * wn  # φ' = v_c while stuck
        g = np.zeros(self.size)
        g[n : 2 * n] = pf / wn
        self.row_xc = np.zeros(self.size)
        self.row_xc[:n] = ac
        self.row_vc = np.zeros(self.size)
        self.row_vc[n : 2 * n] = ac * wn
        self.row_phi = np.zeros(self.size)
        self.row_phi[2 * n] = 1.0
        self.phases = [_Phase(A, g, omega), _Phase(slip, g, omega)]

    def dof_rows(self, dof: int) -> tuple[np.ndarray, np.ndarray]:
        """Rows giving ``x_dof`` and ``ẋ_dof`` from the state."""
        rx = np.zeros(self.size)
        rv = np.zeros(self.size)
        rx[: self.n] = self.shapes[dof]
        rv[self.n : 2 * self.n] = self.shapes[dof] * self.wn
        return rx, rv

    def state(self, x: np.ndarray, v: np.ndarray, fc: float) -> np.ndarray:
        """State ``y`` from physical displacements, velocities and force."""
        # Φ⁻¹ = Φᵀ M is avoided: solve with Φ (square, well conditioned)
        q = np.linalg.solve(self.shapes, x)
        qd = np.linalg.solve(self.shapes, v)
        return np.concatenate((q, qd / self.wn, [fc / self.kt]))


class _Phase:
    """``ẏ = A y + g cos Ωt``: eigen-decomposition and particular solution."""

    def __init__(self, A: np.ndarray, g: np.ndarray, omega: float):
        self.A = A
        lam, V = scipy.linalg.eig(A)
        self.lam = lam
        self.V = V
        self.Vinv = np.linalg.inv(V)
        self.omega = omega
        self._rows = {}
        # particular solution Re(P e^{iΩt})
        self.P = np.linalg.solve(1j * omega * np.eye(A.shape[0]) - A, g.astype(complex))

    def particular(self, t) -> np.ndarray:
        """``Re(P e^{iΩt})``, shape (size,) or (size, n_t)."""
        e = np.exp(1j * self.omega * np.asarray(t, dtype=float))
        return np.real(np.multiply.outer(self.P, e))

    def coefficients(self, ta: float, ya: np.ndarray) -> np.ndarray:
        """Modal amplitudes ``c`` of the homogeneous part from ``y(t_a)``."""
        return self.Vinv @ (ya - self.particular(ta))

    def _projected(self, row: np.ndarray) -> tuple[np.ndarray, complex]:
        """``row V`` and ``row P``, cached per row."""
        key = row.tobytes()
        hit = self._rows.get(key)
        if hit is None:
            hit = self._rows[key] = (row @ self.V, complex(row @ self.P))
        return hit

    def fastest_seen(self, row: np.ndarray, c: np.ndarray, level: float) -> float:
        """Largest free pulsation among the modes that ``row · y`` sees
        from the modal amplitudes ``c``, rad/s: a mode counts when its part
        ``|row V_j c_j|`` exceeds ``_SEEN`` times the largest part, the
        forced part or ``level`` (the slip limit of a stick phase). The
        scan of a phase need not resolve modes its event function does not
        see: the paper beam's stiff modes (a grid for all of them made its
        exact references 5 times slower)."""
        rv, rp = self._projected(row)
        part = np.abs(rv * c)
        scale = max(float(np.max(part)) if part.size else 0.0, abs(rp), level)
        seen = part > _SEEN * scale
        if not np.any(seen):
            return 0.0
        return float(np.max(np.abs(self.lam.imag[seen])))

    def evaluate(self, row: np.ndarray, ta: float, c: np.ndarray, t) -> np.ndarray:
        """``row · y(t)`` and its time derivative at the instants ``t``."""
        t = np.asarray(t, dtype=float)
        rv, rp = self._projected(row)
        a = rv * c
        e = np.exp(np.multiply.outer(t - ta, self.lam))  # (n_t, size)
        hom = e @ a
        dhom = e @ (a * self.lam)
        ep = np.exp(1j * self.omega * t)
        return np.real(hom + rp * ep), np.real(dhom + 1j * self.omega * rp * ep)

    def propagate(self, ta: float, c: np.ndarray, t: float) -> np.ndarray:
        """The full state at the instant ``t``."""
        hom = self.V @ (np.exp(self.lam * (t - ta)) * c)
        return np.real(hom) + self.particular(t)

    def transition(self, tau: float) -> np.ndarray:
        """``exp(A τ)``, real, shape (size, size)."""
        return np.real((self.V * np.exp(self.lam * tau)) @ self.Vinv)


# ----------------------------------------------------------------------------
# event location
# ----------------------------------------------------------------------------
def _root(f, a: float, b: float) -> float:
    """Zero of ``f`` in ``[a, b]`` by Brent's method to rounding; when
    rounding has made the end values agree in sign (a zero at an end), the
    end nearer to zero."""
    fa, fb = f(a), f(b)
    if fa == 0.0 or fb == 0.0 or (fa > 0.0) == (fb > 0.0):
        return a if abs(fa) <= abs(fb) else b
    from scipy.optimize import brentq  # lazy: keeps ``import hbmfric`` light

    return brentq(f, a, b, xtol=1e-16 * max(abs(a), abs(b)), rtol=1e-15)


def _first_down_crossing(func, ta: float, tb: float, n_grid: int):
    """First instant in ``(t_a, t_b]`` where ``h`` goes from > 0 to <= 0.

    ``func(t) -> (h, h')`` vectorised. Sign changes on a grid are located by
    Brent's method; a positive grid value next to a dip (``h'`` changing
    sign from - to +) is checked at the dip's bottom, so that a crossing
    between two grid points is not missed. Returns None if there is none.
    """
    t = np.linspace(ta, tb, max(n_grid, 3))
    h, dh = func(t)
    start_level = 1e-9 * np.max(np.abs(h))

    def f(s):
        return float(func(np.array([s]))[0][0])

    def df(s):
        return float(func(np.array([s]))[1][0])

    pos = h > 0.0
    if h[0] <= start_level and not pos[1]:
        # the phase starts on the boundary and is outside it at the first
        # grid point: it may have gone inside and come back within that
        # step (a stick phase of a stiff contact entered at a velocity
        # reversal far from the static slip load lasts 2 f_s / (k_t |ẍ|),
        # shorter than the grid step of its stuck mode's period / 16: Jenkins
        # k_t = 1e6 on 1 N/m at the resonance, the contact force then stayed
        # stuck at 72 f_s with a period-map residual of 7e-16). Look inside
        # that step on instants closing in on the start geometrically.
        width = t[1] - t[0]
        for k in range(1, 60):
            s = t[0] + width * 2.0**-k
            if s <= t[0]:
                break
            if f(s) > 0.0:
                return _root(f, s, t[1])
    cross = pos[:-1] & ~pos[1:]
    dip = pos[:-1] & pos[1:] & (dh[:-1] < 0.0) & (dh[1:] > 0.0)
    if dip.size and h[0] <= start_level:
        dip[0] = False  # the phase starts on the boundary: not a dip
    for i in np.flatnonzero(cross | dip):
        if cross[i]:
            if h[i + 1] == 0.0:
                return t[i + 1]
            return _root(f, t[i], t[i + 1])
        tm = _root(df, t[i], t[i + 1])
        if f(tm) <= 0.0:
            return _root(f, t[i], tm)
    return None


@dataclass
class _Segment:
    """One phase piece of the trajectory: ``[t_a, t_b]``, mode, amplitudes."""

    ta: float
    tb: float
    mode: int
    c: np.ndarray
    ending: str  # "slip", "stick" or "end"


def _simulate(model: _Model, t0: float, y0: np.ndarray, jacobian: bool = False):
    """One period from ``(t_0, y_0)``: segments, end state, monodromy."""
    T = model.period
    t_end = t0 + T
    delta = model.delta
    size = model.size
    phi_index = size - 1
    t, y = t0, y0.copy()
    if abs(y[phi_index]) < delta:
        mode = STICK
    else:
        y[phi_index] = math.copysign(delta, y[phi_index])
        mode = SLIP if y[phi_index] * (model.row_vc @ y) > 0.0 else STICK
    segments = []
    J = np.eye(size) if jacobian else None
    guard = 0
    while t < t_end:
        guard += 1
        if guard > 10000:
            raise RuntimeError("too many events in one period")
        phase = model.phases[mode]
        c = phase.coefficients(t, y)
        row = model.row_phi if mode == STICK else model.row_vc
        fastest = phase.fastest_seen(row, c, delta if mode == STICK else 0.0)
        per_period = max(_SCAN, _SCAN_FAST * fastest / model.omega)
        n_grid = int(math.ceil(per_period * (t_end - t) / T)) + 2
        if mode == STICK:

            def h(s, phase=phase, c=c, ta=t):
                f, df = phase.evaluate(model.row_phi, ta, c, s)
                # distance to the nearer slip limit, > 0 inside
                return delta - np.abs(f), -np.sign(f) * df

        else:
            sign = 1.0 if y[phi_index] > 0.0 else -1.0

            def h(s, phase=phase, c=c, ta=t, sign=sign):
                f, df = phase.evaluate(model.row_vc, ta, c, s)
                return sign * f, sign * df

        te = _first_down_crossing(h, t, t_end, n_grid)
        tb = t_end if te is None else te
        yb = phase.propagate(t, c, tb)
        if jacobian:
            J = phase.transition(tb - t) @ J
        if te is None:
            segments.append(_Segment(t, tb, mode, c, "end"))
        elif mode == STICK:
            yb[phi_index] = math.copysign(delta, yb[phi_index])
            if jacobian:
                J[phi_index, :] = 0.0  # saltation: slip locks φ
            segments.append(_Segment(t, tb, mode, c, "slip"))
            mode = SLIP
        else:
            segments.append(_Segment(t, tb, mode, c, "stick"))
            mode = STICK
        t, y = tb, yb
    return segments, y, J


def _stick_middle(segments) -> float | None:
    """Middle instant of the longest stick phase (joining the pieces cut at
    the ends of the period), or None without stick."""
    if not segments:
        return None
    T = segments[-1].tb - segments[0].ta
    best, t_mid = 0.0, None
    pieces = [(s.ta, s.tb) for s in segments if s.mode == STICK]
    if not pieces:
        return None
    # join the last piece with the first when the period starts and ends stuck
    if len(pieces) > 1 and segments[0].mode == STICK and segments[-1].mode == STICK:
        first = pieces.pop(0)
        last = pieces.pop()
        pieces.append((last[0], first[1] + T))
    for a, b in pieces:
        if b - a > best:
            best, t_mid = b - a, 0.5 * (a + b)
    return t_mid


# ----------------------------------------------------------------------------
# result
# ----------------------------------------------------------------------------
@dataclass
class ExactSolution:
    """Exact periodic steady state of a linear structure with one Jenkins
    contact.

    Attributes
    ----------
    omega : float
        Forcing pulsation Ω, rad/s.
    force : float
        Forcing amplitude, N.
    kind : str
        ``"stick-slip"``, ``"stuck"`` (linear, never slips; slider centred),
        ``"free"`` (zero slip force: linear without contact) or ``"failed"``
        (no iterate could be simulated over a period; residual inf, no
        time history).
    residual : float
        Period-map residual ``max|y(t_0 + T) - y(t_0)|`` relative to the
        state's size (``"stick-slip"``; 0 for the linear kinds).
    newton_iterations : int
    events : int
        Stick ↔ slip transitions per period.
    stick_fraction : float
        Fraction of the period spent stuck.
    elapsed : float
        Wall time, s.
    dof_names : dict
        Named DOFs of the system → index.
    """

    omega: float
    force: float
    kind: str
    residual: float
    newton_iterations: int
    events: int
    stick_fraction: float
    elapsed: float
    dof_names: dict = field(default_factory=dict)
    _model: _Model | None = field(default=None, repr=False)
    _segments: list = field(default_factory=list, repr=False)
    _linear: tuple | None = field(default=None, repr=False)
    _contact_dof: int = field(default=0, repr=False)
    _t0: float = field(default=0.0, repr=False)

    @property
    def period(self) -> float:
        """``T = 2π/Ω``, s."""
        return 2.0 * math.pi / self.omega

    def _dof(self, dof) -> int:
        if dof is None:
            return self._contact_dof
        if isinstance(dof, str):
            if dof not in self.dof_names:
                raise ValueError(f"unknown DOF name {dof!r}; known: {self.dof_names}")
            return int(self.dof_names[dof])
        return int(dof)

    # -- evaluation -----------------------------------------------------------
    def _pieces(self, dof: int):
        """Per piece: (t_a, t_b, f) with ``f(t) -> (x, ẋ)`` vectorised."""
        if self._linear is not None:
            X = self._linear[0][dof]
            w = self.omega

            def f(t):
                e = np.exp(1j * w * np.asarray(t, dtype=float))
                return np.real(X * e), np.real(1j * w * X * e)

            return [(0.0, self.period, f)]
        model = self._model
        rx, _ = model.dof_rows(dof)
        out = []
        for s in self._segments:
            phase = model.phases[s.mode]

            def f(t, phase=phase, s=s):
                # the time derivative of x_dof is its velocity
                return phase.evaluate(rx, s.ta, s.c, t)

            out.append((s.ta, s.tb, f))
        return out

    def time_response(self, n: int = 256, dof=None) -> tuple[np.ndarray, np.ndarray]:
        """``(t, x)`` at ``n`` equidistant instants ``t_k = k T / n`` of one
        period (s, m), ``t = 0`` a zero of the forcing phase."""
        n = positive_int("n", n, low=2)
        j = self._dof(dof)
        t = self.period * np.arange(n) / n
        x = np.empty(n)
        pieces = self._pieces(j)
        T = self.period
        t0 = pieces[0][0]
        tt = t0 + np.mod(t - t0, T)
        for i, (a, b, f) in enumerate(pieces):
            sel = (tt >= a) & ((tt < b) if i < len(pieces) - 1 else (tt <= b + 1e-300))
            if np.any(sel):
                x[sel] = f(tt[sel])[0]
        return t, x

    def _state_fourier(self, k: int) -> np.ndarray:
        """Complex Fourier coefficient of the state ``y``, shape (size,)."""
        model = self._model
        nu = k * self.omega
        w = self.omega
        total = np.zeros(model.size, dtype=complex)
        for s in self._segments:
            phase = model.phases[s.mode]
            tau = s.tb - s.ta
            # homogeneous part Re(V (c e^{λ (t - t_a)})), integrated exactly
            e = np.exp(-1j * nu * s.ta)
            total += 0.5 * e * (phase.V @ (s.c * _expint(phase.lam - 1j * nu, tau)))
            total += (
                0.5
                * e
                * (
                    np.conj(phase.V)
                    @ (np.conj(s.c) * _expint(np.conj(phase.lam) - 1j * nu, tau))
                )
            )
            # particular part Re(P e^{iΩt})
            total += (
                0.5
                * phase.P
                * (np.exp(1j * (w - nu) * s.ta) * _expint(1j * (w - nu), tau))
            )
            total += (
                0.5
                * np.conj(phase.P)
                * (np.exp(-1j * (w + nu) * s.ta) * _expint(-1j * (w + nu), tau))
            )
        return total / self.period * (1.0 if k == 0 else 2.0)

    def _fourier_all(self, k: int) -> np.ndarray:
        """``X_k`` of every DOF, shape (n_dof,)."""
        if self._linear is not None:
            X = self._linear[0]
            return X.astype(complex) if k == 1 else np.zeros(X.shape, dtype=complex)
        y = self._state_fourier(k)
        return self._model.shapes @ y[: self._model.n]

    def fourier(self, harmonic: int, dof=None) -> complex:
        """Complex Fourier coefficient ``X_k`` with ``x ≈ Σ Re(X_k e^{ikΩt})``
        (``X_0`` the mean), m; ``Xc_k = Re X_k``, ``Xs_k = -Im X_k``.
        Integrated exactly phase by phase."""
        k = int(harmonic)
        if k < 0:
            raise ValueError(f"harmonic must be >= 0, got {harmonic}")
        return complex(self._fourier_all(k)[self._dof(dof)])

    def coefficients(self, harmonic_numbers) -> np.ndarray:
        """Fourier coefficients of every DOF in the layout of
        :class:`hbmfric.PeriodicSolution`.

        Parameters
        ----------
        harmonic_numbers : array_like of int, shape (n_harmonics,)
            Harmonics ``k >= 0`` (e.g. a solution's ``harmonic_numbers``).

        Returns
        -------
        ndarray, shape (n_dof, n_coef)
            ``[X0]`` for ``k = 0``, ``[Xc_k, Xs_k]`` otherwise, with
            ``x(t) = Σ Xc_k cos kΩt + Xs_k sin kΩt``, m.
        """
        cols = []
        for k in np.asarray(harmonic_numbers, dtype=int).ravel():
            if k < 0:
                raise ValueError(f"harmonic numbers must be >= 0, got {k}")
            X = self._fourier_all(int(k))
            cols += [X.real] if k == 0 else [X.real, -X.imag]
        return np.column_stack(cols)

    def amplitude(self, harmonic: int | None = None, dof=None) -> float:
        """``|X_k|`` of one harmonic ``k``, or by default (
        ``harmonic=None``) half the peak-to-peak of ``x(t)``, m. ``dof``:
        index, name or None (the contact DOF)."""
        if harmonic is not None:
            return abs(self.fourier(harmonic, dof))
        j = self._dof(dof)
        hi, lo = -np.inf, np.inf
        for a, b, f in self._pieces(j):
            n_grid = max(int(math.ceil(2 * _SCAN * (b - a) / self.period)), 8)
            t = np.linspace(a, b, n_grid)
            x, v = f(t)
            hi, lo = max(hi, x.max()), min(lo, x.min())
            for i in np.flatnonzero(v[:-1] * v[1:] < 0.0):
                tm = _root(lambda s, f=f: float(f(np.array([s]))[1][0]), t[i], t[i + 1])
                xm = float(f(np.array([tm]))[0][0])
                hi, lo = max(hi, xm), min(lo, xm)
        return 0.5 * (hi - lo)

    @property
    def event_times(self) -> np.ndarray:
        """Instants of the stick ↔ slip transitions within one period, s,
        increasing, in ``[t_0, t_0 + T)`` (``t_0`` the shooting instant,
        inside a stick phase); empty for the linear kinds."""
        return np.array([s.tb for s in self._segments if s.ending != "end"])

    def states(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Displacements, velocities and contact force at the instants ``t``.

        Parameters
        ----------
        t : array_like, shape (n_t,)
            Instants, s (any; taken modulo the period).

        Returns
        -------
        x, v : ndarray, shape (n_dof, n_t)
            m and m/s.
        fc : ndarray, shape (n_t,)
            Contact force, N.
        """
        t = np.atleast_1d(np.asarray(t, dtype=float))
        w = self.omega
        if self._linear is not None:
            X, fc = self._linear
            e = np.exp(1j * w * t)
            return (
                np.real(np.multiply.outer(X, e)),
                np.real(np.multiply.outer(1j * w * X, e)),
                np.real(fc * e),
            )
        model = self._model
        T = self.period
        t0 = self._segments[0].ta
        tt = t0 + np.mod(t - t0, T)
        y = np.empty((model.size, t.size))
        for i, s in enumerate(self._segments):
            last = i == len(self._segments) - 1
            sel = (tt >= s.ta) & ((tt < s.tb) if not last else (tt <= s.tb + T))
            if np.any(sel):
                phase = model.phases[s.mode]
                e = np.exp(np.multiply.outer(phase.lam, tt[sel] - s.ta))
                y[:, sel] = np.real(phase.V @ (e * s.c[:, None]))
                y[:, sel] += phase.particular(tt[sel])
        n = model.n
        x = model.shapes @ y[:n]
        v = model.shapes @ (y[n : 2 * n] * model.wn[:, None])
        return x, v, model.kt * y[2 * n]

    def contact_force(self, n: int = 256) -> tuple[np.ndarray, np.ndarray]:
        """``(t, f_c)`` at ``n`` equidistant instants of one period (s, N)."""
        n = positive_int("n", n, low=2)
        t = self.period * np.arange(n) / n
        if self._linear is not None:
            fc = self._linear[1]
            return t, np.real(fc * np.exp(1j * self.omega * t))
        model = self._model
        T = self.period
        t0 = self._segments[0].ta
        tt = t0 + np.mod(t - t0, T)
        out = np.empty(n)
        for i, s in enumerate(self._segments):
            last = i == len(self._segments) - 1
            sel = (tt >= s.ta) & ((tt < s.tb) if not last else (tt <= s.tb))
            if np.any(sel):
                phase = model.phases[s.mode]
                out[sel] = phase.evaluate(model.row_phi, s.ta, s.c, tt[sel])[0]
        return t, model.kt * out

    def monodromy(self) -> np.ndarray:
        """Exact monodromy matrix of the periodic solution: the derivative
        of the state after one period with respect to the state at the
        start, in the state ``y = (q, p, φ)`` of the module docstring
        (modal coordinates, scaled modal velocities, spring deflection).

        Stick-slip: the product of the phase propagators over one period
        from an instant inside a stick phase, with the saltation matrix at
        each stick → slip transition (it locks ``φ`` at ``±δ``, so one
        multiplier is 0) and the identity at slip → stick; checked against
        finite differences of the period map in
        ``tests/test_exact_reference.py``. Stuck: ``exp(A_stick T)``.
        Free (zero slip force): ``exp(A_slip T)`` (the slider's multiplier
        is 1: it is neutral).

        Returns
        -------
        ndarray, shape (2 n_dof + 1, 2 n_dof + 1)

        Raises
        ------
        ValueError
            For a ``"failed"`` solution.
        """
        model = self._model
        if self.kind == "failed" or model is None:
            raise ValueError("a failed exact solution has no monodromy matrix")
        if self.kind == "stuck":
            return model.phases[STICK].transition(model.period)
        if self.kind == "free":
            return model.phases[SLIP].transition(model.period)
        t0 = self._segments[0].ta
        x, v, fc = self.states(np.array([t0]))
        y0 = model.state(x[:, 0], v[:, 0], fc[0])
        return _simulate(model, t0, y0, jacobian=True)[2]

    def floquet_multipliers(self) -> np.ndarray:
        """Eigenvalues of :meth:`monodromy`, sorted by decreasing modulus,
        shape (2 n_dof + 1,). The solution is asymptotically stable when
        every modulus is below 1 (for stick-slip, the slider's multiplier
        is 0; for a stuck or free response, the slider's is 1 and does not
        decide: the slider offset is neutral)."""
        mu = np.linalg.eigvals(self.monodromy())
        return mu[np.argsort(-np.abs(mu), kind="stable")]

    def friction_dissipation(self) -> float:
        """Energy dissipated by the slider per period, ``f_s Σ |Δx_c|`` over
        the slip phases, J."""
        if self._linear is not None:
            return 0.0
        model = self._model
        total = 0.0
        for s in self._segments:
            if s.mode == SLIP:
                phase = model.phases[s.mode]
                xa = phase.evaluate(model.row_xc, s.ta, s.c, np.array([s.ta, s.tb]))[0]
                total += abs(xa[1] - xa[0])
        return model.fs * total


def _expint(z: np.ndarray, tau: float) -> np.ndarray:
    """``∫_0^τ e^{z s} ds = (e^{zτ} - 1)/z``, accurate for small ``|z τ|``."""
    z = np.asarray(z, dtype=complex)
    zt = z * tau
    out = np.empty_like(zt)
    small = np.abs(zt) < 1e-3
    big = ~small
    out[big] = (np.exp(zt[big]) - 1.0) / z[big]
    s = zt[small]
    series = 1.0 + s / 4.0 * (1.0 + s / 5.0)
    out[small] = tau * (1.0 + s / 2.0 * (1.0 + s / 3.0 * series))
    return out


# ----------------------------------------------------------------------------
# solvers
# ----------------------------------------------------------------------------
def _check_system(system):
    from ..laws import Jenkins

    if not isinstance(getattr(system, "contact", None), Jenkins):
        raise ValueError(
            "the exact reference needs a system with one hf.Jenkins contact, got "
            f"{type(getattr(system, 'contact', None)).__name__}"
        )
    contacts = getattr(system, "contacts", None)
    if contacts is not None and (
        len(contacts) != 1 or getattr(contacts[0], "other", None) is not None
    ):
        got = (
            f"{len(contacts)} contacts"
            if len(contacts) != 1
            else f"a contact between DOFs {contacts[0].dof} and {contacts[0].other}"
        )
        raise ValueError(
            "the exact reference needs a system with one hf.Jenkins contact to "
            f"ground, got {got}; use hbmfric.validation.steady_state (time "
            "integration) for this system"
        )
    M, _, K = system.matrices()
    if scipy.linalg.eigvalsh(K, M)[0] <= 0.0:
        raise ValueError(
            "the exact reference needs a positive definite stiffness matrix "
            "(a structure held without the contact)"
        )


def _cosine_load(system, force) -> np.ndarray:
    """The load vector of a cosine forcing ``p cos Ωt``, shape (n_dof,);
    ValueError for loads with a phase (not implemented here)."""
    q = check_load(
        system, force, int(system.n_dof), float(getattr(system, "load_phase", 0.0))
    )
    if np.any(q.imag):
        raise ValueError(
            "the exact reference takes cosine loads p cos(Ωt) only; this system's "
            "load has a phase (load_phase or a complex load_vector)"
        )
    return q.real.copy()


def _linear_response(system, force, omega, extra_stiffness):
    M, C, K = (np.asarray(a, dtype=float) for a in system.matrices())
    K = K.copy()
    K[system.contact_dof, system.contact_dof] += extra_stiffness
    p = _cosine_load(system, force)
    X = np.linalg.solve(K - omega**2 * M + 1j * omega * C, p.astype(complex))
    return X


def _guess_from_signal(model: _Model, system, t_samples, x, v):
    """Start of the shooting from sampled displacements/velocities of all
    DOFs over one period (``x, v`` shape (n_dof, n_t)): the Jenkins force by
    running the law twice over the contact displacement, then the middle of
    the longest stick stretch."""
    xc = x[system.contact_dof]
    kt, fs = model.kt, model.fs
    n_t = xc.size
    fc = np.empty(n_t)
    w = 0.0
    stuck = np.zeros(n_t, dtype=bool)
    for rep in range(2):
        for i in range(n_t):
            trial = kt * (xc[i] - w)
            if trial > fs:
                w = xc[i] - fs / kt
                trial = fs
            elif trial < -fs:
                w = xc[i] + fs / kt
                trial = -fs
            elif rep == 1:
                stuck[i] = True
            fc[i] = trial
    if not np.any(stuck):
        i0 = 0
    else:
        # longest circular run of stuck samples
        best, i0 = -1, 0
        start = int(np.argmin(stuck)) if not np.all(stuck) else 0
        run = 0
        for j in range(n_t + 1):
            i = (start + j) % n_t
            if j < n_t and stuck[i]:
                run += 1
            else:
                if run > best:
                    best, i0 = run, (start + j - run // 2 - 1) % n_t
                run = 0
    t0 = float(t_samples[i0])
    y0 = model.state(x[:, i0], v[:, i0], fc[i0])
    return t0, y0


def exact_periodic_solution(
    system,
    force: float,
    omega: float,
    *,
    initial_guess=None,
    tol: float = 1e-12,
    max_iterations: int = 30,
    on_failure: str = "warn",
) -> ExactSolution:
    """Exact periodic steady state under ``force cos(Ω t)``.

    Parameters
    ----------
    system : Oscillator, CantileverBeam or compatible
        Linear structure (``matrices() -> (M, C, K)``, ``load_vector``,
        ``contact_dof``) with an :class:`hbmfric.Jenkins` contact; ``K``
        positive definite.
    force : float
        Forcing amplitude, N.
    omega : float
        Forcing pulsation Ω, rad/s, > 0.
    initial_guess : PeriodicSolution, ExactSolution, Branch point or None
        Start of the shooting: an HBM solution (``coefficients`` of every
        DOF, shape (n_dof, n_coef), with ``harmonic_numbers``) or an exact
        solution at a nearby frequency (its state at the same forcing
        phase). Default: ``hf.periodic_solution`` at ``harmonics=15``.
    tol : float
        Newton tolerance on the period-map residual, relative to the size
        of the state.
    max_iterations : int
        Newton iterations at most.
    on_failure : {"warn", "raise"}
        What to do when Newton does not meet ``tol``:
        :class:`~hbmfric.ConvergenceWarning` or
        :class:`~hbmfric.ConvergenceError`.

    Returns
    -------
    ExactSolution
    """
    start = time.perf_counter()
    _check_system(system)
    force = finite_float("force", force)
    omega = finite_float("omega", omega, low=0.0, low_open=True)
    tol = finite_float("tol", tol, low=0.0, low_open=True)
    max_iterations = positive_int("max_iterations", max_iterations, low=1)
    if on_failure not in ("warn", "raise"):
        raise ValueError(f"on_failure must be 'warn' or 'raise', got {on_failure!r}")
    law = system.contact
    names = dict(getattr(system, "dof_names", {}))
    common = {
        "omega": omega,
        "force": force,
        "dof_names": names,
        "_contact_dof": int(system.contact_dof),
    }
    if law.slip_force == 0.0:
        X = _linear_response(system, force, omega, 0.0)
        return ExactSolution(
            kind="free", residual=0.0, newton_iterations=0, events=0,
            stick_fraction=0.0, elapsed=time.perf_counter() - start,
            _linear=(X, 0.0j), _model=_Model(system, force, omega), **common,
        )  # fmt: skip
    X = _linear_response(system, force, omega, law.stiffness)
    fc = law.stiffness * X[system.contact_dof]
    if abs(fc) <= law.slip_force:
        return ExactSolution(
            kind="stuck", residual=0.0, newton_iterations=0, events=0,
            stick_fraction=1.0, elapsed=time.perf_counter() - start,
            _linear=(X, fc), _model=_Model(system, force, omega), **common,
        )  # fmt: skip
    sol = _shoot(system, force, omega, initial_guess, tol, max_iterations, common)
    if not sol.residual <= tol:
        # many stick-slip cycles per period (a stiff, lightly damped stuck
        # mode) can leave the HBM start outside Newton's basin: start from
        # time integration instead
        seed = _time_integration_guess(system, force, omega)
        for guess, recentre in ((seed, True), (seed, False), (initial_guess, False)):
            again = _shoot(
                system, force, omega, guess, tol, max_iterations, common, recentre
            )
            if again.residual < sol.residual:
                sol = again
            if sol.residual <= tol:
                break
    sol.elapsed = time.perf_counter() - start
    if not sol.residual <= tol:
        _fail(sol, tol, on_failure)
    return sol


def _fail(sol: ExactSolution, tol: float, on_failure: str) -> None:
    msg = (
        f"exact reference at omega={sol.omega:.9g} rad/s: period-map residual "
        f"{sol.residual:.3g} > tol={tol:.3g} after {sol.newton_iterations} "
        "Newton iterations"
    )
    if on_failure == "raise":
        raise ConvergenceError(msg)
    warnings.warn(msg, ConvergenceWarning, stacklevel=3)


def _period_residual(model, t0, y0, scale, jacobian=False):
    """Period-map residual ``max|y(t_0 + T) - y_0| / scale`` (inf when the
    period cannot be simulated), with the segments, end state and
    monodromy."""
    try:
        segments, y1, J = _simulate(model, t0, y0, jacobian=jacobian)
    except RuntimeError:  # an iterate chattering without end
        return math.inf, None, None, None
    res = float(np.max(np.abs(y1 - y0)) / scale)
    return (res if np.isfinite(res) else math.inf), segments, y1, J


def _shoot(
    system, force, omega, guess, tol, max_iterations, common, recentre=True
) -> ExactSolution:
    """Newton on the period map from ``guess``, with backtracking on the
    residual; the result carries its residual (no warning here)."""
    model = _Model(system, force, omega)
    t0, y0 = _initial_state(model, system, force, omega, guess)
    # a fixed scale: relative to the iterate itself, a diverging iterate
    # would look ever better
    floor = max(np.max(np.abs(y0)), model.delta)
    it = 0
    res, segments, y1, J = _period_residual(model, t0, y0, floor, jacobian=True)
    for it in range(1, max_iterations + 1):
        if res <= tol or J is None:
            break
        A = J - np.eye(model.size)
        r = y1 - y0
        try:
            dy = np.linalg.solve(A, -r)
        except np.linalg.LinAlgError:
            # an iterate that never slips: the slider offset is free
            dy = np.linalg.lstsq(A, -r, rcond=None)[0]
        step = 1.0
        for _ in range(30):
            y_try = y0 + step * dy
            res_try, seg_try, _, _ = _period_residual(model, t0, y_try, floor)
            if res_try < res:
                break
            step *= 0.5
        else:
            break  # no decrease along the Newton direction
        y0 = y_try
        if res_try <= tol:
            # converged: keep this start (re-centring it moves the state by
            # a propagation whose rounding can cost the digits just won)
            res, segments = res_try, seg_try
            break
        t_kept = t0
        if recentre and (it <= 3 or not abs(y0[-1]) < 0.9 * model.delta):
            # re-centre t_0 in the middle of the longest stick phase
            tm = _stick_middle(seg_try)
            if tm is not None:
                tw = _wrap(tm, seg_try)
                seg = next(s for s in seg_try if s.ta <= tw <= s.tb)
                y0 = model.phases[seg.mode].propagate(seg.ta, seg.c, tw)
                t0 = math.fmod(tw, model.period)
        res, segments, y1, J = _period_residual(model, t0, y0, floor, jacobian=True)
        if t0 != t_kept and not res <= 10.0 * res_try:
            # the re-centred start lost what the step won (a stick phase a
            # fraction of a percent of the period long, events resolved
            # differently from the new start): keep the step's own start
            t0, y0 = t_kept, y_try
            res, segments, y1, J = _period_residual(model, t0, y0, floor, jacobian=True)
    if segments is None:
        return ExactSolution(
            kind="failed", residual=math.inf, newton_iterations=it, events=0,
            stick_fraction=0.0, elapsed=0.0, _model=model, **common,
        )  # fmt: skip
    # reported relative to the solution's own size
    residual = res * floor / max(np.max(np.abs(y0)), model.delta)
    stuck_time = sum(s.tb - s.ta for s in segments if s.mode == STICK)
    n_events = sum(1 for s in segments if s.ending in ("slip", "stick"))
    return ExactSolution(
        kind="stick-slip",
        residual=residual,
        newton_iterations=it,
        events=n_events,
        stick_fraction=stuck_time / model.period,
        elapsed=0.0,
        _model=model,
        _segments=segments,
        _t0=t0,
        **common,
    )


def _wrap(t: float, segments) -> float:
    """``t`` moved by whole periods into the span of ``segments``."""
    a = segments[0].ta
    T = segments[-1].tb - a
    return a + math.fmod(t - a, T) if t - a >= 0 else a + T + math.fmod(t - a, T)


@dataclass
class _SignalGuess:
    """Sampled displacements and velocities over one period (a start)."""

    t: np.ndarray  # (n_t,)
    x: np.ndarray  # (n_dof, n_t)
    v: np.ndarray  # (n_dof, n_t)


def _time_integration_guess(system, force: float, omega: float) -> _SignalGuess:
    """A start from the time-integration steady state (velocities by the
    spectral derivative of the sampled displacements)."""
    from .steady_state import steady_state

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HbmfricWarning)  # only a start
        ss = steady_state(system, force, omega, steps_per_period=2048, tol=1e-9)
    x = np.asarray(ss.samples, dtype=float)
    n_t = x.shape[1]
    X = np.fft.rfft(x, axis=1)
    k = np.arange(X.shape[1])
    dX = 1j * k * omega * X
    if n_t % 2 == 0:
        dX[:, -1] = 0.0  # Nyquist term: no derivative
    v = np.fft.irfft(dX, n=n_t, axis=1)
    return _SignalGuess(2.0 * math.pi / omega * np.arange(n_t) / n_t, x, v)


def _initial_state(model, system, force, omega, guess):
    n_t = 2048
    if isinstance(guess, _SignalGuess):
        return _guess_from_signal(model, system, guess.t, guess.x, guess.v)
    if guess is None:
        from ..api import periodic_solution

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", HbmfricWarning)  # only a start
            guess = periodic_solution(system, force, omega, 15)
    if isinstance(guess, ExactSolution):
        if guess._linear is None:
            # same forcing phase: the state at θ_0 = Ω_old t_0
            theta0 = guess.omega * guess._t0
            old = guess._model
            seg = next(s for s in guess._segments if s.ta <= guess._t0 <= s.tb)
            y = old.phases[seg.mode].propagate(seg.ta, seg.c, guess._t0)
            # the modal basis is the same (same system); rescale velocities
            y = y.copy()
            y[model.n : 2 * model.n] *= omega / guess.omega
            return theta0 / omega, y
        theta = 2.0 * math.pi * np.arange(n_t) / n_t
        X = guess._linear[0]
        x = np.real(np.multiply.outer(X, np.exp(1j * theta)))
        v = np.real(np.multiply.outer(1j * omega * X, np.exp(1j * theta)))
        return _guess_from_signal(model, system, theta / omega, x, v)
    from ..signals import synthesis_matrix

    h = np.asarray(guess.harmonic_numbers)
    coef = np.asarray(guess.coefficients, dtype=float)
    theta = 2.0 * math.pi * np.arange(n_t) / n_t
    S = synthesis_matrix(h, theta)
    # derivative of the basis: d/dθ (cos kθ, sin kθ) = k (-sin kθ, cos kθ)
    dS = np.zeros_like(S)
    col = 0
    for k in h:
        if k == 0:
            col += 1
            continue
        dS[:, col] = -k * np.sin(k * theta)
        dS[:, col + 1] = k * np.cos(k * theta)
        col += 2
    x = coef @ S.T
    v = omega * (coef @ dS.T)
    return _guess_from_signal(model, system, theta / omega, x, v)


def exact_branch(
    system,
    force: float,
    omegas,
    *,
    tol: float = 1e-12,
    on_failure: str = "warn",
) -> list[ExactSolution]:
    """Exact references at the pulsations ``omegas`` (rad/s), in the order
    given.

    Each point is started from the HBM solution there (``harmonics=15``,
    itself continued from the previous point's), which is closer than the
    previous exact solution at another frequency; if Newton fails from it,
    again from the previous exact solution.

    Parameters
    ----------
    system, force, tol, on_failure
        As in :func:`exact_periodic_solution`.
    omegas : array_like, shape (n_points,)
        Pulsations, rad/s, > 0.

    Returns
    -------
    list of ExactSolution, one per pulsation.
    """
    from ..api import periodic_solution

    omegas = np.asarray(omegas, dtype=float).ravel()
    if omegas.size == 0 or not np.all(np.isfinite(omegas)) or np.any(omegas <= 0):
        raise ValueError("omegas must be a non-empty sequence of positive floats")
    if on_failure not in ("warn", "raise"):
        raise ValueError(f"on_failure must be 'warn' or 'raise', got {on_failure!r}")
    out = []
    hbm = previous = None
    for w in omegas:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", HbmfricWarning)  # only a start
            hbm = periodic_solution(system, force, float(w), 15, initial_guess=hbm)
        seeds = [hbm] if hbm.converged else []
        if previous is not None:
            seeds.append(previous)
        best = None
        for seed in seeds or [None]:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                sol = exact_periodic_solution(
                    system, force, float(w), initial_guess=seed, tol=tol
                )
            if best is None or sol.residual < best.residual:
                best = sol
            if sol.residual <= tol:
                break
        if not best.residual <= tol:
            _fail(best, tol, on_failure)
        out.append(best)
        previous = best if best.kind == "stick-slip" else previous
        if not hbm.converged:
            hbm = None
    return out


@dataclass
class BranchErrors:
    """Errors of an HBM branch against exact references at its own points.

    Attributes
    ----------
    index : ndarray of int, shape (n_points,)
        Indices of the compared branch points.
    omega : ndarray, shape (n_points,)
        Their pulsations, rad/s.
    reference_h1, reference_hpp : ndarray, shape (n_points,)
        Exact first-harmonic amplitude and half peak-to-peak value at
        ``dof``, m.
    error_h1, error_hpp : ndarray, shape (n_points,)
        Relative errors of the branch's values.
    references : list of ExactSolution
    elapsed : float
        Wall time of the references, s.
    """

    index: np.ndarray
    omega: np.ndarray
    reference_h1: np.ndarray
    reference_hpp: np.ndarray
    error_h1: np.ndarray
    error_hpp: np.ndarray
    references: list
    elapsed: float


def branch_errors(
    branch,
    system,
    *,
    dof=None,
    every: int = 1,
    tol: float = 1e-12,
    on_failure: str = "warn",
) -> BranchErrors:
    """Relative errors of every point of an FRF branch (``hf.frf``) against
    the exact reference at that point's pulsation.

    Parameters
    ----------
    branch : Branch
        Traced for ``system`` (its ``force`` is used).
    system : Oscillator, CantileverBeam or compatible
        As in :func:`exact_periodic_solution`.
    dof : int, str or None
        DOF compared (default: the contact DOF).
    every : int
        Compare every ``every``-th point only (the first and the last
        always), to thin long branches.
    tol, on_failure
        As in :func:`exact_periodic_solution`.

    Returns
    -------
    BranchErrors
    """
    if on_failure not in ("warn", "raise"):
        raise ValueError(f"on_failure must be 'warn' or 'raise', got {on_failure!r}")
    every = positive_int("every", every, low=1)
    start = time.perf_counter()
    index = np.unique(np.append(np.arange(0, len(branch), every), len(branch) - 1))
    refs = []
    previous = None
    for i in index:
        w = float(branch.omega[i])
        best = None
        for seed in (branch.point(int(i)), previous):
            if seed is None:
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                sol = exact_periodic_solution(
                    system, branch.force, w, initial_guess=seed, tol=tol
                )
            if best is None or sol.residual < best.residual:
                best = sol
            if sol.residual <= tol:
                break
        if not best.residual <= tol:
            _fail(best, tol, on_failure)
        refs.append(best)
        if best.kind == "stick-slip":
            previous = best
    r1 = np.array([r.amplitude(harmonic=1, dof=dof) for r in refs])
    rpp = np.array([r.amplitude(dof=dof) for r in refs])
    a1 = np.asarray(branch.amplitude(harmonic=1, dof=dof))[index]
    app = np.asarray(branch.amplitude(dof=dof))[index]
    return BranchErrors(
        index=index,
        omega=np.asarray(branch.omega, dtype=float)[index],
        reference_h1=r1,
        reference_hpp=rpp,
        error_h1=np.abs(a1 - r1) / r1,
        error_hpp=np.abs(app - rpp) / rpp,
        references=refs,
        elapsed=time.perf_counter() - start,
    )
