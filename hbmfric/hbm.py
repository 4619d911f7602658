"""Harmonic-balance discretisation of a system: the plain-Python layer that
validates the input, chooses the harmonics and samples, and packs the flat
problem tuple that the kernels see."""

from __future__ import annotations

import math

import numpy as np

from ._validate import finite_float, positive_int
from .kernels.dlft.coulomb import COULOMB
from .kernels.dlft.tail import tail_length
from .kernels.fourier.dft import fourier_matrices
from .kernels.laws.updates import JENKINS, MASING
from .kernels.linalg.linear_response import first_harmonic_response
from .kernels.residuals.hbm import (
    AFT_EVENTS,
    AFT_SAMPLES,
    FAMILY_TYPES,
    CoulombProblem,
    aft_family,
    hbm_residual,
)
from .laws import Contact2D
from .signals import coefficient_columns
from .systems.contacts import contact_arrays
from .systems.protocol import check_load, check_system

AFT_SCHEMES = ("auto", "events", "samples")
#: default DLFT penalty of a rigid Coulomb contact, in units of the static
#: stiffness of the structure at the contact DOF, ``1 / (K⁻¹)_cc`` (the
#: other DOFs free; for one DOF ``K[c, c]``). Measured on the Coulomb
#: oscillator, H = 31: with 1 Newton converges in the stop and non-stop
#: regimes; at 10 and more it fails at some stop-regime points
#: (tests/test_coulomb.py). On the 39-DOF beam the diagonal entry
#: ``K[c, c]`` is 8800 times ``1 / (K⁻¹)_cc``: the penalty times the
#: ringing of the truncated displacement in a stick phase (2e-7 m) then
#: swamps the slip force and the stick-end decision flips the topology
#: (tests/test_coulomb_beam.py).
DEFAULT_PENALTY_FACTOR = 1.0


#: DFT matrices per (highest harmonic, odd only, n_time), shared by every
#: problem of that discretisation (the kernels only read them)
_DFT_CACHE: dict = {}


def _fourier_matrices(harmonic_numbers: np.ndarray, odd: bool, n_time: int):
    """:func:`~hbmfric.kernels.fourier.dft.fourier_matrices`, computed once per
    discretisation."""
    key = (int(harmonic_numbers[-1]), bool(odd), int(n_time))
    if key not in _DFT_CACHE:
        if len(_DFT_CACHE) >= 64:
            _DFT_CACHE.clear()
        _DFT_CACHE[key] = fourier_matrices(harmonic_numbers, n_time)
    return _DFT_CACHE[key]


#: :func:`~hbmfric.signals.coefficient_columns` per ``(H, first harmonic)``
#: of :func:`select_harmonics` (read, never changed, by ``_discretise``)
_COLUMNS_CACHE: dict = {}


def _columns(harmonic_numbers: np.ndarray) -> dict[int, int]:
    """:func:`~hbmfric.signals.coefficient_columns` of harmonic numbers of
    :func:`select_harmonics` (``0 … H`` or ``1, 3, … H``), built once per
    layout (the caller must not change it)."""
    key = (int(harmonic_numbers[-1]), int(harmonic_numbers[0]), harmonic_numbers.size)
    columns = _COLUMNS_CACHE.get(key)
    if columns is None:
        if len(_COLUMNS_CACHE) >= 256:
            _COLUMNS_CACHE.clear()
        columns = _COLUMNS_CACHE[key] = coefficient_columns(harmonic_numbers)
    return columns


def select_harmonics(harmonics: int, odd: bool) -> np.ndarray:
    """Harmonic numbers ``0 … H`` or, for a symmetric scene, ``1, 3, … ≤ H``."""
    harmonics = positive_int("harmonics", harmonics, low=1)
    if odd:
        return np.arange(1, harmonics + 1, 2, dtype=np.int64)
    return np.arange(0, harmonics + 1, dtype=np.int64)


def default_n_time(harmonic_numbers: np.ndarray, aft: str, masing: bool = False) -> int:
    """Default samples per period.

    ``events``: the samples only detect stick/slip events (Jenkins) or
    reversal points (Masing laws); two reversals inside one sample interval
    would go unseen, so take 8 samples per period of the highest harmonic
    (at least 32). With a Masing law (``masing``: Menq, Iwan) 16: its
    reversals are located but not the kinks of its force between them (an
    Iwan element's slip onset), whose sampling error is second order in
    ``n_time`` (a two-element Iwan 7.4e-4 off its two Jenkins elements at
    ``H = 7`` with 8 per harmonic, 1.0e-4 with 16); with 8 the adaptive run
    paid for it in harmonics (a chain with an Iwan contact: median ``H`` 45,
    209 ms; with 16: ``H`` 15, 88 ms; ``tests/test_masing_sampling.py``).
    ``samples``: ``16 H`` rounded to a multiple of 8, alias-free for a
    cubic law and keeping the friction aliasing small (the modified Dahl
    law's AFT locates the reversals of the displacement between samples,
    :func:`hbmfric.kernels.aft.dahl.aft_dahl`).
    """
    h_max = int(harmonic_numbers[-1])
    if aft == "events":
        return max(32, (16 if masing else 8) * h_max)
    return max(32, 8 * ((16 * h_max + 7) // 8))


def _stuck_stiffnesses(law) -> tuple[float, ...]:
    """Stiffness of a stuck contact, N/m: the law's, or for the 2D element
    the tangential and the normal one (0 when open at rest)."""
    if isinstance(law, Contact2D):
        closed = law.preload > 0.0
        return (
            law.tangential_stiffness if closed else 0.0,
            law.normal_stiffness if closed else 0.0,
        )
    return (law.stuck_stiffness,)


def _plain_tuple(*fields) -> tuple:
    return fields


#: :meth:`HBMProblem.amplitude_scale` leaves out a sample of a linear
#: response more than this many times the larger of the samples beside it
#: on its grid: a pulsation on an undamped natural pulsation within
#: rounding (a two-contact chain asked at Ω = √2, its stuck pulsation,
#: sampled there exactly: 1.1e12 m beside 1.6e-2 m, and every step and
#: curve test in units of it passed a branch that leapt over a resonance of
#: 1.0 m as 6e-3 m with a curve estimate of 5.5e-11); a damped peak sampled
#: on its top reads at most about (grid spacing) / (ζ Ω) times the samples
#: beside it, kept down to ζ ≈ 1e-8
POLE_HIT = 1e6


class HBMProblem:
    """A system under harmonic forcing, discretised by harmonic balance.

    Parameters
    ----------
    system : Oscillator or compatible
        Follows the system protocol (:mod:`hbmfric.systems.protocol`:
        ``matrices()``, ``load_vector(force)``, ``contact``, ``contact_dof``,
        ``n_dof``, optionally ``symmetric``), checked on entry.
    force : float
        Forcing amplitude ``F`` of ``F cos Ωt``, N.
    harmonics : int
        Highest harmonic ``H`` (>= 1).
    n_time : int or None
        Samples per period for the AFT, ``> 2 H``; None picks a default.
    symmetry : bool or None
        Solve for odd harmonics only. None: when the system allows it.
    aft : {"auto", "events", "samples"}
        AFT scheme; "auto" uses event location for Jenkins (exact Fourier
        integrals) and for the Masing laws Menq and Iwan (located reversal
        points, :mod:`hbmfric.kernels.aft.masing`), samples otherwise. A rigid
        :class:`~hbmfric.Coulomb` contact is solved by DLFT: "auto" and
        "events" with located reversals and the holding force
        (:func:`hbmfric.kernels.dlft.coulomb.dlft_located`; with the reversals
        located on the velocity including the linear tail of the response,
        :mod:`hbmfric.kernels.dlft.tail`, when the law has
        ``linear_tail=True`` and the mass matrix is invertible), "samples" by
        the classic sampled DLFT (:func:`hbmfric.kernels.dlft.coulomb.dlft_contact`).
    subharmonic : int
        ``ν >= 1``: the unknowns are harmonics of ``Ω/ν`` (the Ω of ``y``
        is then the fundamental ``Ω/ν``) and the forcing sits on harmonic
        ``ν``; ``ν = 1`` is the usual ``T``-periodic balance.

    Notes
    -----
    Optional system hooks (read with defaults, so plain systems need none):
    ``static_load() -> p0`` of shape (n_dof,), N, a constant load on
    harmonic 0 (a system with one is never solved for odd harmonics only);
    ``load_phase`` (rad), the forcing being ``p cos(Ωt − φ)`` (π/2 for
    ``p sin Ωt``); ``static_solution() -> x0`` of shape (n_dof,), m, added
    to the linear starting guesses.
    """

    def __init__(
        self,
        system,
        force: float,
        harmonics: int = 15,
        n_time: int | None = None,
        symmetry: bool | None = None,
        aft: str = "auto",
        subharmonic: int = 1,
        _checked=None,
    ) -> None:
        # ``_checked``: the SystemData of a caller that has just checked it
        data = _checked if _checked is not None else check_system(system)
        self.system = system
        self.force = finite_float("force", force)
        self.subharmonic = positive_int("subharmonic", subharmonic, low=1)
        static = data.static_load
        if static is not None and not np.any(static):
            static = None
        self.load_phase = data.load_phase
        symmetric = (
            bool(getattr(system, "symmetric", False))
            and static is None
            and subharmonic == 1
        )
        if symmetry is None:
            symmetry = symmetric
        elif symmetry and not symmetric:
            raise ValueError(
                "symmetry=True (odd harmonics only) needs a symmetric system; "
                "this contact law is not odd"
            )
        self.odd = bool(symmetry)
        if aft not in AFT_SCHEMES:
            raise ValueError(f"aft must be one of {AFT_SCHEMES}, got {aft!r}")
        contacts = data.contacts
        self._contacts = contacts
        law = data.contact
        rigid = any(c[0].code == COULOMB for c in contacts)
        self._rigid = rigid
        # Masing laws sample their force more finely by default
        # (:func:`default_n_time`)
        self._masing = any(c[0].code in MASING for c in contacts)
        located = bool(contacts) and all(
            c[0].code in (JENKINS, COULOMB) or c[0].code in MASING for c in contacts
        )
        if rigid:
            aft = "samples" if aft == "samples" else "events"
        elif aft == "auto":
            aft = "events" if located else "samples"
        if aft == "events" and not located:
            aft = "samples"
        self.aft = aft
        self.n_dof = data.n_dof
        mass, damping, stiffness = data.mass, data.damping, data.stiffness
        self._matrices = (mass, damping, stiffness)
        self._static = static
        self._amplitude = check_load(system, self.force, self.n_dof, data.load_phase)
        if rigid:
            eps = self._penalty(law, stiffness)
            m_cc = float(mass[system.contact_dof, system.contact_dof])
            # damping of the penalty oscillator (M_cc, η, ε): critical
            self._dlft_params = np.array(
                [law.slip_force, eps, 2.0 * np.sqrt(eps * m_cc)]
            )
        self._discretise(harmonics, n_time)

    def with_harmonics(self, harmonics: int) -> HBMProblem:
        """The same problem (system, force, symmetry, AFT scheme) with
        highest harmonic ``harmonics`` and its default ``n_time``.

        Shares the system's matrices and everything else that does not
        depend on the harmonics with ``self`` (the adaptive-harmonics run
        builds one problem per level this way).
        """
        # ``copy.copy`` of a plain instance (no slots, no copy hooks) without
        # its reduce protocol: the same shallow copy, a third of the time
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new._discretise(harmonics, None)
        return new

    def _discretise(self, harmonics: int, n_time: int | None) -> None:
        """Harmonics, samples, DFT matrices, load layout and kernel tuple."""
        system = self.system
        self.presolve_iterations = 0
        self.harmonic_numbers = select_harmonics(harmonics, self.odd)
        self.harmonics = int(harmonics)
        if self.subharmonic > self.harmonics:
            raise ValueError(
                f"harmonics must be >= subharmonic = {self.subharmonic} (the "
                f"forcing is harmonic ν of Ω/ν), got {self.harmonics}"
            )
        aft = self.aft
        if n_time is None:
            n_time = default_n_time(self.harmonic_numbers, aft, self._masing)
            if self.subharmonic > 1:
                # samples invariant under the shift by T = νT/ν: a T-periodic
                # response stays an exact solution of the sampled balance
                step = math.lcm(8, self.subharmonic)
                n_time = step * -(-n_time // step)
        n_time = positive_int("n_time", n_time, low=1)
        if n_time <= 2 * self.harmonics:
            raise ValueError(
                f"n_time must be > 2 * harmonics = {2 * self.harmonics}, got {n_time}"
            )
        self.n_time = n_time
        inverse, forward, derivative = _fourier_matrices(
            self.harmonic_numbers, self.odd, n_time
        )
        self.n_coef = inverse.shape[1]
        self.n_unknowns = self.n_dof * self.n_coef
        mass, damping, stiffness = self._matrices
        load = np.zeros((self.n_dof, self.n_coef))
        columns = _columns(self.harmonic_numbers)
        col1 = columns[self.subharmonic]
        # Re(q e^{iΩt}) = Re(q) cos Ωt - Im(q) sin Ωt
        load[:, col1] = self._amplitude.real
        load[:, col1 + 1] = -self._amplitude.imag
        if self._static is not None:
            load[:, columns[0]] = self._static
        self.load = load.reshape(-1)
        params = None
        if self._rigid:
            mu, n_tail = self._tail(system.contact, mass, aft)
            params = [np.append(self._dlft_params, [mu, n_tail])]
            self._coulomb_params = params[0]
        if params is None:
            # the laws' own parameters: the same arrays at every level (a
            # copy made by ``with_harmonics`` shares them, as it shares the
            # matrices; the kernels only read them)
            arrays = self.__dict__.get("_contact_arrays")
            if arrays is None or arrays[0] is not self._contacts:
                arrays = (self._contacts, *contact_arrays(self._contacts))
                self._contact_arrays = arrays
            pairs, codes, law_params = arrays[1:]
        else:
            pairs, codes, law_params = contact_arrays(self._contacts, params)
        aft_scheme = np.int64(AFT_EVENTS if aft == "events" else AFT_SAMPLES)
        # a rigid Coulomb contact gets its own problem type, whose residual
        # alone compiles the DLFT kernels; contacts of one AFT family get
        # that family's type, whose residual compiles that AFT alone (a
        # plain tuple, every law's AFT, otherwise)
        if self._rigid:
            kind = CoulombProblem
        else:
            kind = FAMILY_TYPES.get(aft_family(codes, aft_scheme), _plain_tuple)
        self.kernel_problem = kind(
            self.harmonic_numbers,
            mass,
            damping,
            stiffness,
            self.load,
            pairs,
            codes,
            law_params,
            aft_scheme,
            inverse,
            forward,
            derivative,
        )

    def _tail(self, law, mass: np.ndarray, aft: str) -> tuple[float, float]:
        """``((M⁻¹)_cc, K)`` of the linear tail of a rigid Coulomb contact
        (:mod:`hbmfric.kernels.dlft.tail`); ``K = 0`` (no tail) for
        ``aft="samples"``, ``linear_tail=False`` or a singular mass matrix."""
        if aft != "events" or not law.linear_tail:
            return 0.0, 0.0
        c = int(self.system.contact_dof)
        try:
            mu = float(np.linalg.inv(mass)[c, c])
        except np.linalg.LinAlgError:
            return 0.0, 0.0
        if not (np.isfinite(mu) and mu > 0.0):
            return 0.0, 0.0
        return mu, float(tail_length(int(self.harmonic_numbers[-1])))

    def _penalty(self, law, stiffness: np.ndarray) -> float:
        """DLFT penalty ``ε`` of a rigid Coulomb contact, N/m: the law's own,
        else ``DEFAULT_PENALTY_FACTOR`` times the static stiffness of the
        structure at the contact DOF, ``1 / (K⁻¹)_cc`` (the force per unit
        displacement of the contact DOF with the other DOFs free to
        follow); ``K[c, c]`` if ``K`` is singular."""
        if law.penalty is not None:
            return float(law.penalty)
        c = int(self.system.contact_dof)
        k_cc = float(stiffness[c, c])
        unit = np.zeros(stiffness.shape[0])
        unit[c] = 1.0
        try:
            flexibility = float(np.linalg.solve(stiffness, unit)[c])
        except np.linalg.LinAlgError:
            flexibility = 0.0
        if np.isfinite(flexibility) and flexibility > 0.0:
            k_cc = min(k_cc, 1.0 / flexibility)
        if not k_cc > 0.0:
            raise ValueError(
                "hf.Coulomb on a contact DOF without static stiffness (K[c, c] = "
                f"{k_cc}): give the DLFT penalty explicitly, hf.Coulomb(..., "
                "penalty=eps) in N/m, of the order of the dynamic stiffness "
                "m Ω² at the contact"
            )
        return DEFAULT_PENALTY_FACTOR * k_cc

    @property
    def penalty(self) -> float | None:
        """DLFT penalty ``ε`` (N/m) of a rigid Coulomb contact, else None."""
        if not self._rigid:
            return None
        return float(self._coulomb_params[1])

    # ------------------------------------------------------------------
    def residual(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
        """Residual and Jacobian at ``y = [X, Ω]`` (for checks and tests).

        Returns
        -------
        R : ndarray, shape (n_unknowns,)
        J : ndarray, shape (n_unknowns, n_unknowns + 1)
        state : int
            Contact-state code of the AFT.
        """
        y = np.ascontiguousarray(y, dtype=np.float64)
        R = np.empty(self.n_unknowns)
        J = np.empty((self.n_unknowns, self.n_unknowns + 1))
        state = hbm_residual(y, self.kernel_problem, R, J)
        return R, J, int(state)

    def rounding_level(self) -> float:
        """Rounding level (N) of the last residual evaluated beyond the
        generic floor of its terms (:func:`hbmfric.kernels.steps.newton.
        rounding_floor`): 0 here; a problem condensed onto several contact
        coordinates reports the one of its receptance inverse."""
        return 0.0

    def full_coefficients(self, points: np.ndarray) -> np.ndarray:
        """Coefficients of every DOF, shape (n_points, n_dof, n_coef), from
        solutions ``points = [X, Ω]`` of shape (n_points, n_unknowns + 1)
        (a condensed problem recovers the eliminated DOFs here)."""
        points = np.atleast_2d(points)
        X = points[:, : self.n_unknowns]
        return X.reshape(-1, self.n_dof, self.n_coef).copy()

    def unknowns_from_full(self, X: np.ndarray) -> np.ndarray:
        """The unknowns from coefficients ``X`` of shape (n_dof, n_coef)."""
        return np.ascontiguousarray(X, dtype=np.float64).reshape(-1)

    def linear_response(self, omega, contact: str = "stuck") -> np.ndarray:
        """First-harmonic response of the linearised system.

        Parameters
        ----------
        omega : float or ndarray, shape (n_omega,)
            Pulsation(s), rad/s.
        contact : {"stuck", "free"}
            ``"stuck"`` adds the law's stuck stiffness at the contact DOF
            (a rigid Coulomb contact holds the contact DOF at 0),
            ``"free"`` leaves the contact out.

        Returns
        -------
        ndarray, shape (n_unknowns,) or (n_omega, n_unknowns)
            Coefficients ``X`` (only the first-harmonic ones are non-zero).
        """
        w = self.subharmonic * np.atleast_1d(np.asarray(omega, dtype=float))
        mass, damping, stiffness = self.kernel_problem[1:4]
        K = stiffness.copy()
        c = self.system.contact_dof
        pinned = contact == "stuck" and self._rigid
        if contact == "stuck" and not pinned:
            for law, a, b, a_n, b_n in self._contacts:
                for k, (p, q) in zip(
                    _stuck_stiffnesses(law), ((a, b), (a_n, b_n)), strict=False
                ):
                    K[p, p] += k
                    if q >= 0:
                        K[q, q] += k
                        K[p, q] -= k
                        K[q, p] -= k
        col1 = coefficient_columns(self.harmonic_numbers)[self.subharmonic]
        load = self.load.reshape(self.n_dof, self.n_coef)
        p_cos = load[:, col1].copy()
        p_sin = load[:, col1 + 1].copy()
        M, C = mass, damping
        if pinned:
            # x_c = 0: replace the contact DOF's equation by x_c = 0
            M, C = mass.copy(), damping.copy()
            for a in (M, C, K):
                a[c, :] = 0.0
                a[:, c] = 0.0
            K[c, c] = 1.0
            p_cos[c] = p_sin[c] = 0.0
        cs = np.empty((w.size, 2, self.n_dof))
        first_harmonic_response(w, M, C, K, p_cos, p_sin, cs)
        X = np.zeros((w.size, self.n_dof, self.n_coef))
        X[:, :, col1] = cs[:, 0]
        X[:, :, col1 + 1] = cs[:, 1]
        X = X.reshape(w.size, -1)
        return X[0] if np.ndim(omega) == 0 else X

    def amplitude_scale(self, omega_range: tuple[float, float]) -> float:
        """Typical displacement amplitude over the frequency range, m: the
        peak first-harmonic response of the stuck and free linearisations."""
        grid = np.linspace(omega_range[0], omega_range[1], 65)
        peak = 0.0
        for contact in ("stuck", "free"):
            response = np.abs(self.linear_response(grid, contact))
            samples = np.max(response.reshape(grid.size, -1), axis=1)
            samples = np.where(np.isfinite(samples), samples, np.inf)
            # a sample on an undamped pole within rounding is no typical
            # amplitude (1e12 m where the samples beside it read 1e-2 m):
            # left out
            beside = np.maximum(
                np.concatenate(([0.0], samples[:-1])),
                np.concatenate((samples[1:], [0.0])),
            )
            typical = np.isfinite(samples) & (samples <= POLE_HIT * beside)
            if np.any(typical):
                peak = max(peak, float(np.max(samples[typical])))
        if not np.isfinite(peak) or peak <= 0.0:
            peak = 1.0
        return peak

    def initial_guesses(self, omega: float) -> list[np.ndarray]:
        """Starting points ``y = [X, Ω]`` for Newton at fixed Ω.

        The stuck and the free linearisations; for a rigid Coulomb contact
        first the point a long backtracked Newton iteration reaches from
        them (the DLFT residual has a seam at every stick/slip change; from
        a linear guess in the stop regime Newton needs tens of backtracked
        steps, more than a continuation corrector allows).
        """
        guesses = []
        static = getattr(self.system, "static_solution", None)
        for contact in ("stuck", "free"):
            y = np.empty(self.n_unknowns + 1)
            y[:-1] = self.linear_response(omega, contact)
            if static is not None and self.harmonic_numbers[0] == 0:
                self._add_static(y, np.asarray(static(), dtype=float))
            y[-1] = omega
            guesses.append(y)
        if self._rigid:
            for g in list(guesses):
                y = self._presolve(g)
                if y is not None:
                    guesses.insert(0, y)
                    break
        return guesses

    def _add_static(self, y: np.ndarray, static: np.ndarray) -> None:
        """Add the static solution ``static`` (shape (n_dof,), m) to the mean
        coefficients of the guess ``y``."""
        y[: self.n_unknowns : self.n_coef] += static

    def _presolve(
        self, y: np.ndarray, max_iter: int = 300, tol: float = 1e-10
    ) -> np.ndarray | None:
        """Backtracked Newton at fixed Ω from ``y``; the point or None.

        Its iterations add up in ``self.presolve_iterations``.
        """
        n = self.n_unknowns
        y = y.copy()
        R, J, _ = self.residual(y)
        res = float(np.max(np.abs(R)))
        target = tol * max(float(np.max(np.abs(self.load))), 1e-300)
        for _ in range(max_iter):
            if res <= target:
                return y
            self.presolve_iterations += 1
            try:
                dx = np.linalg.solve(J[:, :n], -R)
            except np.linalg.LinAlgError:
                return None
            lam = 1.0
            for _ls in range(14):
                y_try = y.copy()
                y_try[:n] += lam * dx
                R_try, J_try, _ = self.residual(y_try)
                res_try = float(np.max(np.abs(R_try)))
                if res_try < (1.0 - 1e-4 * lam) * res:
                    break
                lam *= 0.5
            if not np.isfinite(res_try):
                return None
            y, R, J, res = y_try, R_try, J_try, res_try
        return y if res <= target else None
