"""Harmonic balance condensed onto the contact DOF: the plain-Python layer
that builds the modal data of :mod:`hbmfric.kernels.condensed` and recovers
the response of every DOF afterwards."""

from __future__ import annotations

import numpy as np
import scipy.linalg

from .hbm import HBMProblem
from .kernels.condensed import (
    AFT_EVENTS,
    AFT_SAMPLES,
    CondensedProblem,
    condensed_modal_coefficients,
    condensed_recover,
    condensed_residual,
)
from .kernels.dlft import COULOMB
from .signals import coefficient_columns

#: largest off-diagonal term of Φᵀ C Φ, relative to its diagonal, accepted
#: as classical (modal) damping
_CLASSICAL_TOL = 1e-8


def system_modes(system) -> tuple[np.ndarray, np.ndarray]:
    """Natural pulsations (rad/s) and mass-normalised mode shapes (columns)
    of the system without contact: ``system.modes()`` when it has one, else
    the generalised eigenproblem ``K φ = ω² M φ``."""
    if hasattr(system, "modes"):
        return system.modes()
    M, _, K = system.matrices()
    w2, shapes = scipy.linalg.eigh(K, M)
    return np.sqrt(np.maximum(w2, 0.0)), shapes


def can_condense(system) -> bool:
    """True when condensation is possible and pays: several DOFs, a contact,
    positive definite stiffness and classical damping."""
    if system.contact is None or int(system.n_dof) < 2:
        return False
    if system.contact.code == COULOMB:  # DLFT is not in the condensed kernel
        return False
    try:
        _modal_data(system)
    except ValueError:
        return False
    return True


def _modal_data(system):
    M, C, K = (np.asarray(a, dtype=float) for a in system.matrices())
    omega, shapes = system_modes(system)
    modal_c = shapes.T @ C @ shapes
    diag = np.diag(modal_c).copy()
    off = modal_c - np.diag(diag)
    scale = max(float(np.max(np.abs(diag))), 1e-300)
    if float(np.max(np.abs(off))) > _CLASSICAL_TOL * scale:
        raise ValueError(
            "condensation by modal superposition needs classical (modal or "
            "Rayleigh) damping; use condense=False for this system"
        )
    if not np.all(omega > 0.0):
        raise ValueError(
            "condensation needs a positive definite stiffness (no rigid-body "
            "mode); use condense=False for this system"
        )
    return omega, shapes, diag


class CondensedHBMProblem(HBMProblem):
    """HBM with the unknowns at the contact DOF only.

    Same parameters and interface as :class:`~hbmfric.hbm.HBMProblem`
    (``n_unknowns``, ``kernel_problem``, ``residual``, ``linear_response``,
    ``amplitude_scale``, ``initial_guesses``); the unknowns are the
    ``n_coef`` coefficients of the contact DOF. The linear DOFs are
    eliminated per harmonic by modal superposition with all modes (exact
    for classical damping); :meth:`full_coefficients` recovers every DOF.
    """

    condensed = True

    def __init__(
        self,
        system,
        force: float,
        harmonics: int = 15,
        n_time: int | None = None,
        symmetry: bool | None = None,
        aft: str = "auto",
    ) -> None:
        super().__init__(system, force, harmonics, n_time, symmetry, aft)
        if system.contact is None:
            raise ValueError("condensation needs a contact law on the system")
        if system.contact.code == COULOMB:
            raise ValueError(
                "a rigid Coulomb contact (DLFT) is solved on the full system "
                "only; use condense=False"
            )
        omega, shapes, modal_c = _modal_data(system)
        self.shapes = np.ascontiguousarray(shapes)
        self.contact_dof = int(system.contact_dof)
        hn = self.kernel_problem[0]
        law_code, law_params, aft_code = self.kernel_problem[6:9]
        inverse, forward, derivative = self.kernel_problem[9:12]
        load = self.load.reshape(self.n_dof, self.n_coef)
        self.full_kernel_problem = self.kernel_problem
        self.kernel_problem = CondensedProblem(
            hn,
            np.ascontiguousarray(shapes[self.contact_dof]),
            np.ascontiguousarray(omega**2),
            np.ascontiguousarray(modal_c),
            np.ascontiguousarray(shapes.T @ load),
            np.int64(law_code),
            law_params,
            np.int64(AFT_EVENTS if aft_code == AFT_EVENTS else AFT_SAMPLES),
            inverse,
            forward,
            derivative,
        )
        self.n_unknowns = self.n_coef

    # ------------------------------------------------------------------
    def residual(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
        """Condensed residual (N) and Jacobian at ``y = [X_c, Ω]``."""
        y = np.ascontiguousarray(y, dtype=np.float64)
        R = np.empty(self.n_unknowns)
        J = np.empty((self.n_unknowns, self.n_unknowns + 1))
        state = condensed_residual(y, self.kernel_problem, R, J)
        return R, J, int(state)

    def receptance(self, omega) -> tuple[np.ndarray, np.ndarray]:
        """Contact receptance ``G_cc(ω)`` (m/N) and the contact response to
        the first-harmonic load (m, complex), at pulsation(s) ``omega``."""
        w = np.atleast_1d(np.asarray(omega, dtype=float))[:, None]
        p = self.kernel_problem
        col1 = coefficient_columns(self.harmonic_numbers)[1]
        q = p.modal_load[:, col1] - 1j * p.modal_load[:, col1 + 1]
        d = p.omega_squared - w**2 + 1j * w * p.modal_damping
        g = np.sum(p.contact_shapes**2 / d, axis=1)
        x = np.sum(p.contact_shapes * q / d, axis=1)
        return g, x

    def linear_response(self, omega, contact: str = "stuck") -> np.ndarray:
        """First-harmonic response of the contact DOF of the linearised
        system (see :meth:`HBMProblem.linear_response`), shape (n_coef,) or
        (n_omega, n_coef)."""
        g, x = self.receptance(omega)
        if contact == "stuck":
            x = x / (1.0 + self.system.contact.stuck_stiffness * g)
        col1 = coefficient_columns(self.harmonic_numbers)[1]
        X = np.zeros((x.size, self.n_coef))
        X[:, col1] = x.real
        X[:, col1 + 1] = -x.imag
        return X[0] if np.ndim(omega) == 0 else X

    def full_coefficients(self, points: np.ndarray) -> np.ndarray:
        """Coefficients of every DOF at condensed solutions.

        Parameters
        ----------
        points : ndarray, shape (n_points, n_coef + 1)
            ``[X_c, Ω]`` per point.

        Returns
        -------
        ndarray, shape (n_points, n_dof, n_coef), m
        """
        points = np.ascontiguousarray(np.atleast_2d(points), dtype=np.float64)
        n_modes = self.shapes.shape[1]
        modal = np.empty((points.shape[0], n_modes, self.n_coef))
        condensed_modal_coefficients(points, self.kernel_problem, modal)
        return np.matmul(self.shapes, modal)

    def contact_force(self, y: np.ndarray) -> np.ndarray:
        """Contact-force coefficients (N) at ``y = [X_c, Ω]``, shape (n_coef,)."""
        X = np.empty((self.n_dof, self.n_coef))
        F = np.empty(self.n_coef)
        condensed_recover(
            np.ascontiguousarray(y, dtype=np.float64),
            self.kernel_problem,
            self.shapes,
            X,
            F,
        )
        return F

    def unknowns_from_full(self, X: np.ndarray) -> np.ndarray:
        """The unknowns (contact-DOF coefficients) of full coefficients
        ``X`` of shape (n_dof, n_coef)."""
        return np.ascontiguousarray(X[self.contact_dof], dtype=np.float64)
