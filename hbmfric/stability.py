"""Stability of periodic solutions by Hill's method on the HBM Jacobian.

A periodic solution ``x_p(t)`` of ``M ẍ + C ẋ + K x + f_nl(x) = p(t)`` is
perturbed by ``e^{λt} q(t)`` with ``q`` periodic of the same period. In the
real Fourier basis of :mod:`hbmfric.kernels.dft` (per DOF ``[a0, a1, b1, a2,
b2, …]``), the time derivative is the block-diagonal operator ``D``
(``D[a_k, b_k] = kΩ``, ``D[b_k, a_k] = -kΩ``) and
``d/dt (e^{λt} q) = e^{λt} (λ + D) q``, so the linearised balance of the
perturbation's coefficients ``Q`` is the quadratic eigenproblem

    (Δ0 + λ Δ1 + λ² Δ2) Q = 0,
    Δ0 = ∂R/∂X (the HBM Jacobian at the solution),
    Δ1 = C ⊗ I + 2 M ⊗ D,   Δ2 = M ⊗ I,

since ``M (λ + D)² + C (λ + D) + K + ∂F/∂X = Δ0 + λ Δ1 + λ² Δ2``.

What the contact part ``∂F/∂X`` (the AFT Jacobian) means here:

* A memoryless law (``hf.Cubic``, the Duffing case): ``f_nl`` depends on
  ``x(t)`` alone, its linearisation is ``f'(x_p(t)) y(t)`` and the Galerkin
  projection of ``f'(x_p) e^{λt} q`` is ``e^{λt} ∂F/∂X Q`` for every λ:
  Hill's problem is exact up to the truncation in ``H`` (and the AFT's
  sampling).
* A hysteretic law (Jenkins, Menq, Iwan, Dahl): the force depends on the
  history. The AFT Jacobian is the derivative of the periodic force with
  respect to a periodic displacement, the linearisation along the periodic
  motion for ``λ = 0``. For ``λ ≠ 0`` the memory of a stick phase that
  began at ``t_s`` weighs the perturbation at ``t_s`` by ``e^{λ t_s}``, not
  ``e^{λ t}``, which the λ-independent ``∂F/∂X`` cannot represent; and at
  the stick/slip transitions the law is not differentiable, the AFT
  Jacobian being a one-sided linearisation. So for hysteretic laws the
  exponents are exact where they cross zero (``Δ0`` singular: folds and
  branch points) and an approximation elsewhere (a Neimark–Sacker or
  period-doubling crossing is located approximately).
* A rigid Coulomb contact (DLFT) has no force linearisation (its Jacobian
  carries the penalty); it is refused.

Selection of the Floquet exponents: the truncated problem has
``2 n_dof n_coef`` eigenvalues; the exact ones come in families
``λ_j + i m Ω`` (``m`` integer, the same perturbation with its harmonics
shifted) and each family's Floquet multiplier ``exp(λ_j T)`` is the same.
We keep the ``2 n_dof`` eigenvalues whose imaginary parts are closest to 0
(the *imaginary-part sorting* criterion): the member of each family in the
strip ``|Im λ| ≤ Ω/2``, which the truncation approximates best (the
eigenvalues the truncation spoils belong to the highest harmonics, where
``|Im λ| ≈ HΩ``). Its convergence with ``H`` is checked in
``tests/test_stability.py``.

Symmetric (odd-harmonic) solutions: the branch of a symmetric system is
solved for odd harmonics only, but its perturbations may also carry even
harmonics (a symmetry-breaking perturbation). The stability problem is
always posed in the full basis ``0, 1, …, H``. Along an odd solution of an
odd system, the Jacobian couples no odd to even harmonic (the linearisation
is ``T/2``-periodic), so the full problem splits exactly into its odd block
(symmetry-preserving perturbations) and its even block
(symmetry-breaking); both are solved (each four times cheaper than the
whole) and the union is sorted. The odd block alone contains every Floquet
multiplier too (shifted by ``iΩ``), but a real exponent of an even
(symmetry-breaking) perturbation sits there at ``Im λ = ±Ω``, on the edge
of the sorting strip, where the selection is ambiguous; hence both.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

#: relative size (to the Jacobian's largest entry) below which the
#: odd-even coupling of a symmetric solution counts as zero
SPLIT_TOLERANCE = 1e-10


@dataclass
class Stability:
    """Floquet exponents of the points of a branch (or of one solution).

    Attributes
    ----------
    exponents : ndarray of complex, shape (n_points, 2 n_dof)
        Floquet exponents λ (1/s), imaginary parts in ``[-Ω/2, Ω/2]``
        (modulo ``iΩ``), sorted by decreasing real part.
    multipliers : ndarray of complex, shape (n_points, 2 n_dof)
        Floquet multipliers ``exp(λ T)``, ``T = 2π/Ω``.
    stable : ndarray of bool, shape (n_points,)
        Every exponent has a negative real part.
    max_real : ndarray, shape (n_points,)
        Largest real part of the exponents, 1/s.
    omega : ndarray, shape (n_points,)
        Ω of the points (the fundamental), rad/s.
    harmonics : ndarray of int, shape (n_points,)
        Highest harmonic of the full basis of the perturbation (each
        point's ``H``, or ``perturbation_harmonics`` when smaller).
    elapsed : float
        Wall time of the computation, s.
    criterion : str
        Selection of the exponents among the Hill eigenvalues
        (``"imaginary"``: the ``2 n_dof`` whose imaginary parts are
        closest to 0).
    """

    exponents: np.ndarray
    multipliers: np.ndarray
    stable: np.ndarray
    max_real: np.ndarray
    omega: np.ndarray
    harmonics: np.ndarray
    elapsed: float
    criterion: str = "imaginary"

    def changes(self) -> np.ndarray:
        """Indices ``i`` where stability changes between points ``i - 1``
        and ``i``."""
        return np.flatnonzero(self.stable[1:] != self.stable[:-1]) + 1


def derivative_operator(harmonic_numbers: np.ndarray, omega: float) -> np.ndarray:
    """The time derivative in the real coefficient basis, shape (n_coef,
    n_coef): ``d/dt`` of ``a cos kΩt + b sin kΩt`` has the coefficients
    ``(kΩ b, -kΩ a)``."""
    n_coef = int(np.sum(np.where(harmonic_numbers == 0, 1, 2)))
    D = np.zeros((n_coef, n_coef))
    col = 0
    for k in harmonic_numbers:
        if k == 0:
            col += 1
            continue
        D[col, col + 1] = k * omega
        D[col + 1, col] = -k * omega
        col += 2
    return D


def hill_matrices(
    jacobian: np.ndarray,
    mass: np.ndarray,
    damping: np.ndarray,
    harmonic_numbers: np.ndarray,
    omega: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``Δ0, Δ1, Δ2`` of Hill's quadratic eigenproblem.

    Parameters
    ----------
    jacobian : ndarray, shape (n_dof * n_coef, n_dof * n_coef)
        ``∂R/∂X`` of the HBM residual at the solution (DOF-major layout).
    mass, damping : ndarray, shape (n_dof, n_dof)
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    omega : float
        Fundamental pulsation Ω, rad/s.

    Returns
    -------
    d0, d1, d2 : ndarray, shape (n_dof * n_coef, n_dof * n_coef)
    """
    n_coef = jacobian.shape[0] // mass.shape[0]
    eye = np.eye(n_coef)
    D = derivative_operator(harmonic_numbers, omega)
    d1 = np.kron(damping, eye) + 2.0 * np.kron(mass, D)
    d2 = np.kron(mass, eye)
    return jacobian, d1, d2


def _companion_eigenvalues(d0, d1, d2, mass_inverse) -> np.ndarray:
    """Eigenvalues of the pencils ``d0[i] + λ d1[i] + λ² d2`` (stacked,
    shape (n_points, m, m)) by the companion linearisation: one stacked
    standard eigenvalue call when ``d2`` is invertible (``mass_inverse``
    its inverse), else generalised problems point by point. Returns shape
    (n_points, 2 m); infinite eigenvalues (singular ``d2``) as ``inf``."""
    p, m = d0.shape[0], d0.shape[1]
    if mass_inverse is not None:
        A = np.zeros((p, 2 * m, 2 * m))
        A[:, :m, m:] = np.eye(m)
        A[:, m:, :m] = -mass_inverse @ d0
        A[:, m:, m:] = -mass_inverse @ d1
        return np.linalg.eigvals(A)
    import scipy.linalg

    out = np.empty((p, 2 * m), dtype=complex)
    B = np.eye(2 * m)
    B[m:, m:] = d2
    for i in range(p):
        A = np.zeros((2 * m, 2 * m))
        A[:m, m:] = np.eye(m)
        A[m:, :m] = -d0[i]
        A[m:, m:] = -d1[i]
        lam = scipy.linalg.eigvals(A, B)
        out[i] = np.where(np.isfinite(lam), lam, np.inf)
    return out


def select_exponents(eigenvalues: np.ndarray, count: int, omega) -> np.ndarray:
    """The ``count`` Hill eigenvalues whose imaginary parts are closest to
    0, one per family ``λ + i m Ω``, imaginary parts folded into
    ``[-Ω/2, Ω/2]``, sorted by decreasing real part.

    A real negative Floquet multiplier (after a period doubling) has a
    family whose two members nearest the strip are the conjugates
    ``σ ± iΩ/2``, equally close to it: sorting alone takes both and drops
    another family (the stability of a period-doubled stretch read
    "stable"). Where the sorted choice holds two eigenvalues ``Ω`` apart
    in the imaginary part with equal real parts (relative
    ``FAMILY_TOLERANCE``), the choice is made again one family at a time.

    Parameters
    ----------
    eigenvalues : ndarray of complex, shape (n_eig,) or (n_points, n_eig)
    count : int
    omega : float or ndarray, shape (n_points,)

    Returns
    -------
    ndarray of complex, shape (count,) or (n_points, count)
    """
    eig = np.atleast_2d(eigenvalues)
    w = np.broadcast_to(np.asarray(omega, dtype=float), (eig.shape[0],))[:, None]
    key = np.where(np.isfinite(eig), np.abs(eig.imag), np.inf)
    order = np.argsort(key, axis=1, kind="stable")
    lam = np.take_along_axis(eig, order[:, :count], axis=1)
    # rows where two chosen eigenvalues may be members of one family
    suspect = np.flatnonzero(
        np.any(
            key[np.arange(eig.shape[0])[:, None], order[:, :count]] > 0.25 * w, axis=1
        )
    )
    for row in suspect:
        lam[row] = _one_per_family(eig[row, order[row]], count, float(w[row, 0]))
    lam = lam.real + 1j * (lam.imag - w * np.round(lam.imag / w))
    lam = np.take_along_axis(lam, np.argsort(-lam.real, axis=1, kind="stable"), 1)
    return lam[0] if np.ndim(eigenvalues) == 1 else lam


#: relative distance (to Ω) under which two Hill eigenvalues ``i m Ω``
#: apart (m ≠ 0) count as members of one family
FAMILY_TOLERANCE = 1e-6


def _one_per_family(ordered: np.ndarray, count: int, omega: float) -> np.ndarray:
    """The first ``count`` of ``ordered`` (eigenvalues by increasing
    ``|Im|``) that are not members of the family of one taken before."""
    chosen: list[complex] = []
    for lam in ordered:
        if not np.isfinite(lam):
            break
        for c in chosen:
            shift = (lam.imag - c.imag) / omega
            m = round(shift)
            if (
                m != 0
                and abs(shift - m) <= FAMILY_TOLERANCE
                and abs(lam.real - c.real) <= FAMILY_TOLERANCE * omega
            ):
                break
        else:
            chosen.append(lam)
            if len(chosen) == count:
                break
    while len(chosen) < count:  # too few finite eigenvalues: as before
        chosen.append(complex(np.inf))
    return np.array(chosen)


def _parity_blocks(harmonic_numbers: np.ndarray, n_dof: int):
    """Indices (DOF-major layout) of the odd and of the even harmonics'
    coefficients."""
    n_coef = int(np.sum(np.where(harmonic_numbers == 0, 1, 2)))
    per = np.repeat(harmonic_numbers, np.where(harmonic_numbers == 0, 1, 2))
    odd = np.concatenate(
        [d * n_coef + np.flatnonzero(per % 2 == 1) for d in range(n_dof)]
    )
    even = np.concatenate(
        [d * n_coef + np.flatnonzero(per % 2 == 0) for d in range(n_dof)]
    )
    return odd, even


def floquet_exponents(
    jacobian: np.ndarray,
    mass: np.ndarray,
    damping: np.ndarray,
    harmonic_numbers: np.ndarray,
    omega,
    split: bool = False,
) -> np.ndarray:
    """Floquet exponents of periodic solutions by Hill's method.

    Parameters
    ----------
    jacobian : ndarray, shape (n_dof * n_coef, n_dof * n_coef) or (n_points, same)
        ``∂R/∂X`` at the solution(s) in the full basis ``0 … H``.
    mass, damping : ndarray, shape (n_dof, n_dof)
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
        ``0, 1, …, H``.
    omega : float or ndarray, shape (n_points,)
        Fundamental pulsation(s), rad/s.
    split : bool
        Solve the odd and even harmonic blocks separately (exact when the
        Jacobian does not couple them: an odd solution of an odd system;
        checked, else the whole problem is solved).

    Returns
    -------
    ndarray of complex, shape (2 n_dof,) or (n_points, 2 n_dof)
        Exponents (1/s), see :func:`select_exponents`.
    """
    single = np.ndim(jacobian) == 2
    J = np.atleast_3d(jacobian) if not single else jacobian[None]
    p = J.shape[0]
    w = np.broadcast_to(np.asarray(omega, dtype=float), (p,))
    n_dof = mass.shape[0]
    n = J.shape[1]
    n_coef = n // n_dof
    eye = np.eye(n_coef)
    d1_damp = np.kron(damping, eye)
    d1_mass = 2.0 * np.kron(mass, derivative_operator(harmonic_numbers, 1.0))
    d1 = d1_damp[None] + w[:, None, None] * d1_mass[None]
    d2 = np.kron(mass, eye)
    try:
        minv = np.linalg.inv(mass)
        if not np.all(np.isfinite(minv)):
            minv = None
    except np.linalg.LinAlgError:
        minv = None
    groups = [np.arange(n)]
    if split and harmonic_numbers.size > 1:
        odd, even = _parity_blocks(harmonic_numbers, n_dof)
        coupling = max(
            float(np.max(np.abs(J[:, odd][:, :, even]), initial=0.0)),
            float(np.max(np.abs(J[:, even][:, :, odd]), initial=0.0)),
        )
        if coupling <= SPLIT_TOLERANCE * float(np.max(np.abs(J))):
            groups = [odd, even]
    eigs = []
    for idx in groups:
        mi = None if minv is None else np.kron(minv, eye)[np.ix_(idx, idx)]
        eigs.append(
            _companion_eigenvalues(
                J[:, idx][:, :, idx],
                d1[:, idx][:, :, idx],
                d2[np.ix_(idx, idx)],
                mi,
            )
        )
    lam = select_exponents(np.concatenate(eigs, axis=1), 2 * n_dof, w)
    return lam[0] if single else lam


def _stability_problem(system, force, harmonics, n_time, aft, subharmonic):
    """The full-basis, uncondensed HBM problem whose Jacobian Hill's
    method needs."""
    from .hbm import HBMProblem
    from .kernels.dlft import COULOMB

    problem = HBMProblem(
        system,
        force,
        harmonics,
        n_time,
        symmetry=False,
        aft=aft,
        subharmonic=subharmonic,
    )
    if any(c[0].code == COULOMB for c in problem._contacts):
        raise ValueError(
            "stability of a rigid Coulomb contact (DLFT) is not available: its "
            "Jacobian carries the DLFT penalty, not a force linearisation; use "
            "an elastic law (hf.Jenkins with a large stiffness)"
        )
    return problem


def _jacobian(problem, coefficients: np.ndarray, omega: float) -> np.ndarray:
    """``∂R/∂X`` of ``problem`` (full basis) at coefficients given on
    the harmonics ``0 … H`` or a subset (padded with zeros)."""
    y = np.zeros(problem.n_unknowns + 1)
    y[:-1] = coefficients.reshape(-1)
    y[-1] = omega
    _, J, state = problem.residual(y)
    if state < 0:
        raise ValueError(f"the AFT failed at Ω = {omega:.6g} rad/s (code {state})")
    return J[:, :-1]


def _to_full_basis(
    harmonic_numbers: np.ndarray, coefficients: np.ndarray, harmonics: int
) -> np.ndarray:
    """Coefficients (n_dof, n_coef) on ``harmonic_numbers`` placed in the
    full basis ``0 … harmonics`` (shape (n_dof, 2 harmonics + 1)); higher
    harmonics are dropped."""
    n_dof = coefficients.shape[0]
    out = np.zeros((n_dof, 2 * harmonics + 1))
    col = 0
    for k in harmonic_numbers:
        width = 1 if k == 0 else 2
        if k <= harmonics:
            dst = 0 if k == 0 else 2 * k - 1
            out[:, dst : dst + width] = coefficients[:, col : col + width]
        col += width
    return out


def stability_of_points(
    system,
    force: float,
    omega: np.ndarray,
    harmonic_numbers: np.ndarray,
    coefficients: np.ndarray,
    point_harmonics: np.ndarray,
    *,
    n_time: int | None = None,
    aft: str = "auto",
    subharmonic: int = 1,
    symmetric: bool = False,
    perturbation_harmonics: int | None = None,
) -> Stability:
    """Hill's stability of periodic solutions of ``system``.

    Parameters
    ----------
    system : Oscillator or compatible
    force : float
        Forcing amplitude, N.
    omega : ndarray, shape (n_points,)
        Fundamental pulsations, rad/s.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (n_points, n_dof, n_coef)
        Coefficients of every DOF, m.
    point_harmonics : ndarray of int, shape (n_points,)
        Highest harmonic ``H`` of each point (its stability basis is
        ``0 … H``).
    n_time : int, optional
        AFT samples; default: the default for each ``H``.
    aft : str
        AFT scheme of :class:`~hbmfric.hbm.HBMProblem`.
    subharmonic : int
    symmetric : bool
        The solutions have odd harmonics and the system is odd: solve the
        odd and even blocks separately (checked point by point).
    perturbation_harmonics : int, optional
        Highest harmonic ``Hp`` of the perturbation: the Jacobian is
        evaluated at the solution with all its harmonics, and Hill's
        problem keeps the rows and columns of the harmonics ``0 … Hp``
        (a Galerkin truncation of the perturbation alone). Default: each
        point's ``H``. Smaller is cheaper (the eigenvalue solves grow like
        ``Hp³``) and less accurate (``tests/test_stability.py``).

    Returns
    -------
    Stability
    """
    start = time.perf_counter()
    n_points = omega.size
    n_dof = coefficients.shape[1]
    exps = np.zeros((n_points, 2 * n_dof), dtype=complex)
    levels = np.asarray(point_harmonics, dtype=np.int64)
    used = levels.copy()
    for h in np.unique(levels):
        h = int(h)
        nt = n_time if n_time is not None and n_time > 2 * h else None
        problem = _stability_problem(system, force, h, nt, aft, subharmonic)
        idx = np.flatnonzero(levels == h)
        J = np.empty((idx.size, problem.n_unknowns, problem.n_unknowns))
        for j, i in enumerate(idx):
            full = _to_full_basis(harmonic_numbers, coefficients[i], h)
            J[j] = _jacobian(problem, full, float(omega[i]))
        mass, damping = problem.kernel_problem[1], problem.kernel_problem[2]
        hn = problem.harmonic_numbers
        if perturbation_harmonics is not None and perturbation_harmonics < h:
            hn = hn[hn <= perturbation_harmonics]
            keep = np.concatenate(
                [d * problem.n_coef + np.arange(2 * hn[-1] + 1) for d in range(n_dof)]
            )
            J = J[:, keep][:, :, keep]
        used[idx] = hn[-1]
        exps[idx] = floquet_exponents(J, mass, damping, hn, omega[idx], symmetric)
    period = 2.0 * np.pi / omega
    max_real = exps.real.max(axis=1) if n_points else np.zeros(0)
    return Stability(
        exponents=exps,
        multipliers=np.exp(exps * period[:, None]),
        stable=max_real < 0.0,
        max_real=max_real,
        omega=omega.copy(),
        harmonics=used,
        elapsed=time.perf_counter() - start,
    )
