"""The time-integration reference's problems: a structure and its
contacts as the flat arrays the Newmark kernels take, and the integration
to a periodic steady state, period by period.

* :class:`SingleContact`: at most one contact to ground
  (:mod:`hbmfric.validation.integrator`);
* :class:`SeveralContacts`: any number of 1D contacts (to ground or between
  two DOFs) and 2D elements (:mod:`hbmfric.validation.multi_integrator`).

:func:`SingleContact.build` returns whichever a system needs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import finite_float
from ..kernels.aft.contact2d import contact2d_step
from ..kernels.dlft.coulomb import COULOMB
from ..kernels.laws.updates import DAHL, law_init, state_size
from ..systems.protocol import check_load, check_system
from .integrator import NO_CONTACT, OK, newmark_periods, record_period
from .multi_integrator import (
    ELEMENT_2D,
    LAW_1D,
    newmark_periods_multi,
    record_period_multi,
)
from .orbit_state import loop_state

#: periods per kernel call: first call, and bounds of the adaptive size
_FIRST_CHUNK = 4
_MIN_CHUNK = 2
_MAX_CHUNK = 32
#: changes used to fit the decay rate
_RATE_WINDOW = 16

#: the integrated first harmonic follows the stuck structure's when within
#: this fraction of its largest DOF (:meth:`_TimeProblem.scheme_error`)
STUCK_MATCH = 0.05

#: periods the laws are marched around an orbit (:meth:`SingleContact.loop_law_state`)
LOOPS = 2


def scheme_pulsation(omega: float, steps: int) -> float:
    """``Ω̃ = (2/h) tan(Ωh/2)``, ``h = 2π/(NΩ)``: the pulsation at which
    the trapezoidal rule's periodic response is the exact linear one,
    rad/s."""
    h = 2.0 * np.pi / (omega * steps)
    return float((2.0 / h) * np.tan(0.5 * omega * h))


@dataclass(frozen=True)
class _Run:
    """Outcome of one integration to the steady state."""

    status: int
    periods: int
    newton_iterations: int
    converged: bool
    change: float
    samples: np.ndarray
    contact_force: np.ndarray


class _TimeProblem:
    """What the two problem types share: the start state and the
    integration to the steady state (subclasses provide ``load``,
    ``linear_steady_state``, ``kernel_system`` and ``kernels``)."""

    @property
    def n_dof(self) -> int:
        return self.load.size

    def _step_operators(self, omega: float, steps: int, columns: np.ndarray):
        """The parts of one Newmark step of ``h = T/N`` that every problem
        type shares: ``Aᵀ``, ``Bᵀ``, ``q``, ``q₀``, ``K_eff⁻¹ columns``,
        ``cos_sum`` and ``2/h`` (:mod:`hbmfric.validation.integrator`)."""
        n = self.n_dof
        h = 2.0 * np.pi / (omega * steps)
        k_eff = (4.0 / h**2) * self.mass + (2.0 / h) * self.damping + self.stiffness
        static = np.zeros(n) if self.static_load is None else self.static_load
        rhs = np.column_stack(
            (
                self.stiffness,
                self.mass,
                self.load.real,
                -self.load.imag,
                static,
                columns.reshape(n, -1),
            )
        )
        try:
            solved = np.linalg.solve(k_eff, rhs)
        except np.linalg.LinAlgError:
            raise ValueError(
                "the effective stiffness (4/h²) M + (2/h) C + K is singular; "
                "check the system matrices"
            ) from None
        # the kernels take the transposes (column-wise products)
        A_t = np.ascontiguousarray(-2.0 * solved[:, :n].T)
        B_t = np.ascontiguousarray((4.0 / h) * solved[:, n : 2 * n].T)
        q = np.ascontiguousarray(solved[:, 2 * n : 2 * n + 2].T)
        q0 = np.ascontiguousarray(2.0 * solved[:, 2 * n + 2])
        extra = np.ascontiguousarray(solved[:, 2 * n + 3 :])
        phase = 2.0 * np.pi * np.arange(steps + 1) / steps
        samples = np.stack((np.cos(phase), np.sin(phase)))
        cos_sum = np.ascontiguousarray(samples[:, :-1] + samples[:, 1:])
        return A_t, B_t, q, q0, extra, cos_sum, 2.0 / h

    def scheme_error(
        self, omega: float, steps: int, first_harmonic: np.ndarray
    ) -> tuple[float, int]:
        """Error of the scheme where the motion is the stuck structure's.

        The trapezoidal rule's periodic response to ``Re(p e^{iΩt})`` is the
        linear FRF at ``Ω̃ = (2/h) tan(Ωh/2)`` instead of ``Ω``
        (:meth:`linear_steady_state`); near a lightly damped resonance the
        relative change ``(Ω̃ - Ω)/Ω ≈ (Ωh)²/12`` is amplified by about
        ``1/(2ζ)``. It is the result's error only where the integrated
        motion follows the stuck structure (a slipping contact adds its own
        damping and stiffness, and this error no longer applies: a stuck
        resonance of 0.01 % damping read 7.8e-3 where the slipping motion
        was 1.2e-6 off).

        Parameters
        ----------
        omega : float
            Forcing pulsation, rad/s.
        steps : int
            Steps per period.
        first_harmonic : ndarray of complex, shape (n_dof,)
            The integrated motion's first harmonic ``Xc - i Xs``, m.

        Returns
        -------
        error : float
            ``max_d |X̃_d - X_d| / max(|X_d|, CURVE_REST max|X|)``, the
            stuck structure's first harmonic at ``Ω̃`` against ``Ω``; NaN
            where ``first_harmonic`` is more than ``STUCK_MATCH`` (relative
            to its largest DOF) from the stuck structure's Newmark response
            ``X̃``, with a modified Dahl law (no stuck state), or where the
            stuck structure is singular.
        dof : int
            The DOF of the largest error (0 with NaN).
        """
        from ..results import CURVE_REST

        if self.has_dahl():
            # a modified Dahl law has no stuck state: its small-loop tangent
            # is not a structure the motion rests in (and the tensioner's
            # references are checked against shooting instead)
            return math.nan, 0
        omega_h = scheme_pulsation(omega, steps)
        k = self.stuck_stiffness_matrix()
        out = []
        for w in (omega, omega_h):
            try:
                out.append(
                    np.linalg.solve(
                        k - w**2 * self.mass + 1j * w * self.damping, self.load
                    )
                )
            except np.linalg.LinAlgError:
                return math.nan, 0
        X, X_h = out
        size = np.abs(X)
        scale = float(np.max(size))
        if not (scale > 0.0 and np.all(np.isfinite(X_h))):
            return math.nan, 0
        run = np.asarray(first_harmonic)
        if not np.max(np.abs(run - X_h)) <= STUCK_MATCH * float(np.max(np.abs(X_h))):
            return math.nan, 0
        rel = np.abs(X_h - X) / np.maximum(size, CURVE_REST * scale)
        d = int(np.argmax(rel))
        return float(rel[d]), d

    def initial_state(
        self, state, omega: float, steps: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(x0, v0)`` as fresh float64 arrays of shape (n_dof,)."""
        n = self.n_dof
        if state is None:
            return np.zeros(n), np.zeros(n)
        if isinstance(state, str):
            if state != "linear":
                raise ValueError(
                    f"initial_state must be None, 'linear' or a pair (x0, v0), "
                    f"got {state!r}"
                )
            return self.linear_steady_state(omega, steps)
        try:
            x0, v0 = state
        except (TypeError, ValueError):
            raise ValueError(
                f"initial_state must be None, 'linear' or a pair (x0, v0), "
                f"got {state!r}"
            ) from None
        out = []
        for name, value in (("x0", x0), ("v0", v0)):
            try:
                a = np.broadcast_to(np.asarray(value, dtype=np.float64), (n,))
            except (TypeError, ValueError):
                raise ValueError(
                    f"initial_state {name} must be a scalar or an array of shape "
                    f"({n},), got {value!r}"
                ) from None
            if not np.all(np.isfinite(a)):
                raise ValueError(f"initial_state {name} must be finite, got {value!r}")
            out.append(np.array(a))
        return out[0], out[1]

    def integrate(self, omega, steps, tol, max_periods, x, v, f) -> _Run:
        """Integrate from ``(x, v, f)`` (advanced in place) until the change
        over a period is below ``tol`` or ``max_periods`` are done.

        Python checks the convergence: the kernel returns the state at every
        period start, and the number of periods of the next kernel call is
        predicted from the decay rate of the last changes. The last period
        of every call is recorded at the step instants, so the period that
        passes the test is the one analysed.
        """
        system = self.kernel_system(omega, steps)
        periods_kernel, record_kernel = self.kernels()
        n = self.n_dof
        work = np.empty(n)
        samples = np.empty((n, steps))
        contact_force = np.empty(steps)
        record_peaks = np.empty((1, 3))
        periods = 0
        iterations = 0
        converged = False
        change = math.inf
        chunk = _FIRST_CHUNK
        history: list[float] = []
        while True:
            # a chunk: (chunk - 1) plain periods, then one recorded period whose
            # change decides convergence
            chunk = min(chunk, max_periods - periods)
            if chunk > 1:
                starts = np.empty((chunk, 2 * n + 1))
                peaks = np.empty((chunk - 1, 3))
                status, done, its = periods_kernel(system, x, v, f, work, starts, peaks)
                periods += int(done)
                iterations += int(its)
                if status != OK:
                    return self._failed(status, periods, iterations, steps)
                history.extend(_period_changes(starts, peaks, n).tolist())
            before = np.concatenate((x, v, f[:1]))
            status, its = record_kernel(
                system, x, v, f, work, record_peaks[0], samples, contact_force
            )
            periods += 1
            iterations += int(its)
            if status != OK:
                return self._failed(status, periods, iterations, steps)
            after = np.concatenate((x, v, f[:1]))
            change = float(
                _period_changes(np.vstack((before, after)), record_peaks, n)[0]
            )
            history.append(change)
            if change <= tol:
                converged = True
                break
            if periods >= max_periods:
                break
            chunk = _next_chunk(history, tol)
        return _Run(OK, periods, iterations, converged, change, samples, contact_force)

    def _failed(self, status, periods, iterations, steps) -> _Run:
        nan = np.full((self.n_dof, steps), np.nan)
        return _Run(status, periods, iterations, False, math.nan, nan, nan[0].copy())


@dataclass(frozen=True)
class SingleContact(_TimeProblem):
    """A structure with at most one contact to ground, as flat float64
    arrays for :mod:`hbmfric.validation.integrator`."""

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    load: np.ndarray
    contact_dof: int
    law_code: int
    law_params: np.ndarray
    stuck_stiffness: float
    #: constant load ``p₀`` (system hook ``static_load()``), N, and the phase
    #: φ of the forcing ``p cos(Ωt − φ)`` (system attribute ``load_phase``),
    #: already applied to ``load``, the complex amplitude ``q`` of the forcing
    #: ``Re(q e^{iΩt})``
    static_load: np.ndarray | None = None
    load_phase: float = 0.0

    @classmethod
    def build(cls, system, force) -> SingleContact | SeveralContacts:
        data = check_system(system)
        force = finite_float("force", force)
        law = data.contact
        load = check_load(system, force, data.n_dof, data.load_phase)
        if len(data.contacts) > 1 or any(max(c[2:]) >= 0 for c in data.contacts):
            return SeveralContacts.build(data, load)
        if law is None:
            code, params, k_stuck = NO_CONTACT, np.zeros(1), 0.0
        elif law.code == COULOMB:
            raise ValueError(
                "the time-integration reference has no rigid Coulomb contact "
                "(hf.Coulomb is solved by harmonic balance only); use a stiff "
                "hf.Jenkins element here, e.g. stiffness = 1e3-1e4 times the "
                "structure's stiffness at the contact, with the same slip force"
            )
        else:
            code = int(law.code)
            params = np.ascontiguousarray(law.params, dtype=np.float64)
            if params.ndim != 1 or not np.all(np.isfinite(params)):
                raise ValueError("system.contact.params must be a finite 1-d array")
            k_stuck = float(law.stuck_stiffness)
        return cls(
            data.mass,
            data.damping,
            data.stiffness,
            load,
            data.contact_dof,
            code,
            params,
            k_stuck,
            data.static_load,
            data.load_phase,
        )

    def linear_steady_state(
        self, omega: float, steps: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """Periodic Newmark solution of the stuck linearisation at ``t = 0``.

        The trapezoidal rule maps ``x_k = Re(X e^{iΩ t_k})`` to
        ``v_k = Re(iΩ̃ X e^{iΩ t_k})`` with ``Ω̃ = (2/h) tan(Ωh/2)``, so its
        periodic response is the linear FRF at the modified pulsation.
        """
        omega_h = scheme_pulsation(omega, steps)
        k = self.stuck_stiffness_matrix()
        dynamic = k - omega_h**2 * self.mass + 1j * omega_h * self.damping
        try:
            X = np.linalg.solve(dynamic, self.load)
        except np.linalg.LinAlgError:
            raise ValueError(
                "initial_state='linear': the stuck linearisation is singular at "
                f"omega={omega} (undamped resonance); give (x0, v0) instead"
            ) from None
        return np.ascontiguousarray(X.real), np.ascontiguousarray(-omega_h * X.imag)

    def has_dahl(self) -> bool:
        """The contact is a modified Dahl law."""
        return self.law_code == DAHL

    def stuck_stiffness_matrix(self) -> np.ndarray:
        """``K`` with the contact held by its stuck stiffness, N/m."""
        k = np.array(self.stiffness, dtype=float)
        c = self.contact_dof
        k[c, c] += self.stuck_stiffness
        return k

    def initial_law_state(self, x: np.ndarray) -> np.ndarray:
        """Virgin contact-law state at 0 moved to ``x[c]`` (``[0]`` the
        force, N)."""
        if self.law_code == NO_CONTACT:
            return np.zeros(1)
        code = np.int64(self.law_code)
        state = np.empty(int(state_size(code, self.law_params)))
        law_init(code, self.law_params, float(x[self.contact_dof]), state)
        return state

    def loop_law_state(self, samples: np.ndarray) -> np.ndarray:
        """The contact-law state at the first of ``samples`` (shape
        (n_dof, n_samples): one period of a periodic orbit) on the orbit's
        hysteresis loop (:func:`hbmfric.validation.orbit_state.loop_state`)."""
        if self.law_code == NO_CONTACT:
            return np.zeros(1)
        code = np.int64(self.law_code)
        state = np.empty(int(state_size(code, self.law_params)))
        coordinate = np.ascontiguousarray(samples[self.contact_dof], dtype=np.float64)
        loop_state(code, self.law_params, coordinate, np.int64(LOOPS), state)
        return state

    def operators(self, omega: float, steps: int):
        """Newmark operators ``(Aᵀ, Bᵀ, q, q₀, g, cos_sum, 2/h)`` for ``h = T/N``
        (see :mod:`hbmfric.validation.integrator`)."""
        unit = np.zeros(self.n_dof)
        unit[self.contact_dof] = 1.0
        A_t, B_t, q, q0, g, cos_sum, two_over_h = self._step_operators(
            omega, steps, unit
        )
        g = np.ascontiguousarray(g[:, 0])
        if self.law_code != NO_CONTACT and not g[self.contact_dof] > 0.0:
            raise ValueError(
                "the effective stiffness must be positive definite at the contact "
                "DOF; check the system matrices"
            )
        return A_t, B_t, q, q0, g, cos_sum, two_over_h

    def kernel_system(self, omega: float, steps: int) -> tuple:
        """The kernels' ``system`` tuple for ``h = T/N``
        (:func:`hbmfric.validation.integrator.newmark_periods`)."""
        A_t, B_t, q, q0, g, cos_sum, two_over_h = self.operators(omega, steps)
        return (
            A_t,
            B_t,
            q,
            q0,
            g,
            cos_sum,
            np.int64(self.contact_dof),
            np.int64(self.law_code),
            self.law_params,
            two_over_h,
        )

    def kernels(self):
        """The period and recording kernels."""
        return newmark_periods, record_period


@dataclass(frozen=True)
class SeveralContacts(_TimeProblem):
    """Several contacts (to ground or between two DOFs, any law but the
    rigid Coulomb, and 2D elements) for
    :mod:`hbmfric.validation.multi_integrator`: the contact coordinates'
    rows, the laws' codes, parameters and state layout."""

    mass: np.ndarray
    damping: np.ndarray
    stiffness: np.ndarray
    load: np.ndarray
    static_load: np.ndarray | None
    load_phase: float
    #: (m, 2) DOF pairs ``(a, b)`` of the coordinates ``x_a - x_b`` (``b``
    #: -1: against ground)
    rows: np.ndarray
    #: per contact: ``LAW_1D`` or ``ELEMENT_2D``, law code, first coordinate,
    #: offset and size of its law state
    kinds: np.ndarray
    codes: np.ndarray
    first: np.ndarray
    state_at: np.ndarray
    sizes: np.ndarray
    #: the laws' parameters, contact ``k``'s at ``params[param_at[k]:param_at[k+1]]``
    params: np.ndarray
    param_at: np.ndarray
    #: stuck (or closed) stiffness of every coordinate, N/m
    coordinate_stiffness: np.ndarray
    #: length of the law state: the coordinate forces, then each law's state
    state_length: int

    @classmethod
    def build(cls, data, load) -> SeveralContacts:
        rows, kinds, codes, first, stiff = [], [], [], [], []
        params, param_at, state_at, sizes = [], [0], [], []
        n_coord = sum(2 if c[3] >= 0 else 1 for c in data.contacts)
        offset = n_coord
        for law, a, b, a_n, b_n in data.contacts:
            if law.code == COULOMB:
                raise ValueError(
                    "the time-integration reference has no rigid Coulomb contact "
                    "(hf.Coulomb is solved by harmonic balance only); use a stiff "
                    "hf.Jenkins element here"
                )
            p = np.ascontiguousarray(law.params, dtype=np.float64)
            if p.ndim != 1 or not np.all(np.isfinite(p)):
                raise ValueError("every contact law's params must be finite 1-d")
            first.append(len(rows))
            rows.append((a, b))
            if a_n >= 0:  # the 2D element: tangential and normal coordinates
                kinds.append(ELEMENT_2D)
                rows.append((a_n, b_n))
                closed = law.preload > 0.0
                kt, kn = law.tangential_stiffness, law.normal_stiffness
                stiff += [kt, kn] if closed else [0.0, 0.0]
                size = 1
            else:
                kinds.append(LAW_1D)
                stiff.append(float(law.stuck_stiffness))
                size = int(state_size(np.int64(law.code), p))
            codes.append(int(law.code))
            params.append(p)
            param_at.append(param_at[-1] + p.size)
            state_at.append(offset)
            sizes.append(size)
            offset += size
        return cls(
            mass=data.mass,
            damping=data.damping,
            stiffness=data.stiffness,
            load=load,
            static_load=data.static_load,
            load_phase=data.load_phase,
            rows=np.array(rows, dtype=np.int64),
            kinds=np.array(kinds, dtype=np.int64),
            codes=np.array(codes, dtype=np.int64),
            first=np.array(first, dtype=np.int64),
            state_at=np.array(state_at, dtype=np.int64),
            sizes=np.array(sizes, dtype=np.int64),
            params=np.concatenate(params),
            param_at=np.array(param_at, dtype=np.int64),
            coordinate_stiffness=np.array(stiff),
            state_length=offset,
        )

    def reader(self) -> np.ndarray:
        """``Bc``, shape (m, n_dof): the coordinates from ``x``."""
        B = np.zeros((self.rows.shape[0], self.n_dof))
        for i, (a, b) in enumerate(self.rows):
            B[i, a] += 1.0
            if b >= 0:
                B[i, b] -= 1.0
        return B

    def linear_steady_state(self, omega: float, steps: int):
        """As :meth:`SingleContact.linear_steady_state` with every coordinate
        held by its law's stuck stiffness (a 2D element's tangential and
        normal stiffness when preloaded, none when open at rest)."""
        omega_h = scheme_pulsation(omega, steps)
        B = self.reader()
        k = self.stuck_stiffness_matrix()
        dynamic = k - omega_h**2 * self.mass + 1j * omega_h * self.damping
        try:
            X = np.linalg.solve(dynamic, self.load)
        except np.linalg.LinAlgError:
            raise ValueError(
                "initial_state='linear': the stuck linearisation is singular at "
                f"omega={omega} (undamped resonance); give (x0, v0) instead"
            ) from None
        x0 = np.ascontiguousarray(X.real)
        v0 = np.ascontiguousarray(-omega_h * X.imag)
        if self.static_load is not None:
            x0 = x0 + np.linalg.solve(
                self.stiffness + B.T @ (self.coordinate_stiffness[:, None] * B),
                self.static_load - B.T @ self._rest_forces(),
            )
        return x0, v0

    def has_dahl(self) -> bool:
        """Some 1D contact is a modified Dahl law."""
        return bool(np.any((self.kinds == LAW_1D) & (self.codes == DAHL)))

    def stuck_stiffness_matrix(self) -> np.ndarray:
        """``K`` with every coordinate held by its law's stuck stiffness
        (as :meth:`linear_steady_state`), N/m."""
        B = self.reader()
        return self.stiffness + B.T @ (self.coordinate_stiffness[:, None] * B)

    def _rest_forces(self) -> np.ndarray:
        """Coordinate forces at ``x = 0`` (a 2D element's preload)."""
        f = np.zeros(self.rows.shape[0])
        for k, kind in enumerate(self.kinds):
            if kind == ELEMENT_2D:
                a = self.param_at[k]
                f[self.first[k] + 1] = max(self.params[a + 3], 0.0)
        return f

    def initial_law_state(self, x: np.ndarray) -> np.ndarray:
        """Every law virgin at 0 moved to its coordinate at ``x`` (a 2D
        element's slider at its tangential coordinate); the coordinate
        forces first."""
        c = self.reader() @ x
        state = np.zeros(self.state_length)
        for k, kind in enumerate(self.kinds):
            j, s = self.first[k], self.state_at[k]
            p = self.params[self.param_at[k] : self.param_at[k + 1]]
            if kind == LAW_1D:
                block = state[s : s + self.sizes[k]]
                law_init(np.int64(self.codes[k]), p, float(c[j]), block)
                state[j] = block[0]
            else:
                state[s] = c[j]
                t, n, _, _ = contact2d_step(
                    p[0], p[1], p[2], p[3], c[j], c[j], c[j + 1]
                )
                state[j], state[j + 1] = t, n
        return state

    def loop_law_state(self, samples: np.ndarray) -> np.ndarray:
        """The laws' state at the first of ``samples`` (shape (n_dof,
        n_samples): one period of a periodic orbit), each 1D law on the
        orbit's hysteresis loop
        (:func:`hbmfric.validation.orbit_state.loop_state`); a 2D element
        as :meth:`initial_law_state` puts it."""
        state = self.initial_law_state(samples[:, 0])
        coordinates = self.reader() @ samples
        for k, kind in enumerate(self.kinds):
            if kind != LAW_1D:
                continue
            j, s = self.first[k], self.state_at[k]
            p = self.params[self.param_at[k] : self.param_at[k + 1]]
            block = np.empty(self.sizes[k])
            loop_state(
                np.int64(self.codes[k]),
                p,
                np.ascontiguousarray(coordinates[j], dtype=np.float64),
                np.int64(LOOPS),
                block,
            )
            state[s : s + self.sizes[k]] = block
            state[j] = block[0]
        return state

    def kernel_system(self, omega: float, steps: int) -> tuple:
        B = self.reader()
        A_t, B_t, q, q0, G, cos_sum, two_over_h = self._step_operators(
            omega, steps, B.T
        )
        Gc = np.ascontiguousarray(B @ G)
        return (
            A_t,
            B_t,
            q,
            q0,
            G,
            cos_sum,
            Gc,
            self.kinds,
            self.codes,
            self.params,
            self.first,
            self.state_at,
            np.zeros(self.rows.shape[0]),
            self.sizes,
            self.rows,
            two_over_h,
            self.param_at,
            np.zeros((self.rows.shape[0], self.rows.shape[0])),
            np.zeros((self.rows.shape[0], self.rows.shape[0])),
        )

    def kernels(self):
        return newmark_periods_multi, record_period_multi


def _period_changes(starts: np.ndarray, peaks: np.ndarray, n: int) -> np.ndarray:
    """Relative change of ``[x, v, f]`` over each period, shape (n_periods,).

    ``starts`` has shape (n_periods + 1, 2 n + 1), ``peaks`` (n_periods, 3).
    Each part is measured against its own peak over the period; a part that
    is zero throughout counts as unchanged.
    """
    diff = np.abs(np.diff(starts, axis=0))
    parts = np.column_stack(
        (diff[:, :n].max(axis=1), diff[:, n : 2 * n].max(axis=1), diff[:, 2 * n])
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(parts == 0.0, 0.0, parts / peaks)
    return ratio.max(axis=1)


def _next_chunk(history: list[float], tol: float) -> int:
    """Periods for the next kernel call.

    The decay rate of the changes, fitted (least squares on their logarithm,
    which smooths the ripple of a transient seen once per period) over the
    last periods, predicts how many periods remain, so that little is
    integrated past convergence.
    """
    recent = np.asarray(history[-_RATE_WINDOW:])
    recent = recent[recent > 0]
    if recent.size < 3:
        return _FIRST_CHUNK
    slope = np.polyfit(np.arange(recent.size), np.log(recent), 1)[0]
    if not slope < 0.0:
        return _MAX_CHUNK
    remaining = math.log(tol / recent[-1]) / slope
    if not remaining < _MAX_CHUNK:
        return _MAX_CHUNK
    return min(_MAX_CHUNK, max(_MIN_CHUNK, math.ceil(remaining) + 1))
