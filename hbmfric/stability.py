"""Stability of periodic solutions by Hill's method on the HBM Jacobian.

A periodic solution ``x_p(t)`` of ``M ẍ + C ẋ + K x + f_nl(x) = p(t)`` is
perturbed by ``e^{λt} q(t)`` with ``q`` periodic of the same period. In the
real Fourier basis of :mod:`hbmfric.kernels.fourier.dft` (per DOF ``[a0, a1, b1, a2,
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

Eigenvalues at a few points (``exponents="auto"``, a symmetric branch of
one DOF): the stability changes where a selected exponent crosses the
imaginary axis. A real one crossing 0 is a sign change of ``det Δ0 = det
Δ2 Π(-λ_j)`` (complex pairs contribute ``|λ_j|² > 0``; ``det Δ2 = m^n >
0``), i.e. of the determinant of the HBM Jacobian (of each block), which
an LU gives at every point for a small share of an eigenvalue solve. A
complex crossing (period doubling at ``Im λ = Ω/2``, Neimark–Sacker)
changes no determinant on the real axis, and the truncated problem pins
the period-doubling exponent to ``Im λ = Ω/2`` only up to its truncation
(the shift by ``iΩ`` maps the truncated basis out of itself), so no real
determinant of the integer-harmonic pencil detects it exactly; the
half-harmonic basis would, with a second Jacobian of twice the size per
point, for another truncation. On a symmetric solution of one DOF a
smooth law has no complex crossing (Liouville's formula on the half-period
map, :func:`stability_of_points`), so the signs of the odd and even blocks
see every change; a branch without the symmetry solves every point.
Hill's exponents of a hysteretic law do not obey Liouville's formula
(their sum on P1 reaches -0.96 against ``-c/m = -0.02``): for them Hill's
eigenvalues at every ``ANCHOR_SPACING``-th point and a bisection wherever
two computed points disagree are the safeguard; an even number of complex
crossings between two computed points with no real crossing between them
is what it cannot see. On a branch of Jenkins contacts to ground (event
AFT) no sign is computed: every block's determinant is positive by proof
(:func:`_passive`).

The time-domain monodromy (``method="monodromy"``) is computed at a few
points as well (:func:`_monodromy_stability`): a Jenkins structure with
symmetric definite matrices is stable by proof
(:func:`_incrementally_passive`), any other is scheduled on Hill's signs
and verdicts.
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from .errors import AccuracyWarning, CostWarning

#: relative size (to the Jacobian's largest entry) below which the
#: odd-even coupling of a symmetric solution counts as zero
SPLIT_TOLERANCE = 1e-10


class Stability:
    """Floquet exponents of the points of a branch (or of one solution).

    ``stable`` is known at every point as soon as the object exists. On a
    symmetric branch of one DOF, Hill's eigenvalues are computed at a few
    points only (:func:`stability_of_points`, ``exponents="auto"``), and so
    is the monodromy on a branch whose stability comes from it:
    ``computed`` marks them, and the first access to ``exponents``, ``multipliers`` or
    ``max_real`` computes the others (each point's full Hill problem, as
    ``exponents="all"`` would have).

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
        Wall time of the computation of ``stable`` (and of the exponents
        of the ``computed`` points), s.
    criterion : str
        Selection of the exponents among the Hill eigenvalues
        (``"imaginary"``: the ``2 n_dof`` whose imaginary parts are
        closest to 0), or ``"monodromy"``: the exponents ``log(μ)/T`` of
        the time-domain monodromy's multipliers, one per state entry
        (``2 n_dof`` plus one per contact force with memory; a slider
        locked by slip has ``μ = 0``, exponent ``-inf``), ``stable`` when
        every ``|μ| <= 1 + 1e-6`` (a stuck slider's 1 is neutral).
    computed : ndarray of bool, shape (n_points,)
        Points whose Hill eigenvalues (or monodromy) have been computed so far (all of
        them once ``exponents`` has been read); a point whose contacts
        provably stick (stable by proof, :func:`_stuck_everywhere`) is
        not computed until then.
    """

    def __init__(
        self,
        exponents: np.ndarray,
        multipliers: np.ndarray,
        stable: np.ndarray,
        max_real: np.ndarray,
        omega: np.ndarray,
        harmonics: np.ndarray,
        elapsed: float,
        criterion: str = "imaginary",
        *,
        computed: np.ndarray | None = None,
        fill=None,
    ) -> None:
        self._exponents = exponents
        self._multipliers = multipliers
        self._max_real = max_real
        self.stable = stable
        self.omega = omega
        self.harmonics = harmonics
        self.elapsed = elapsed
        self.criterion = criterion
        self.computed = (
            np.ones(stable.shape, dtype=bool) if computed is None else computed
        )
        # callable: indices -> exponents (k, 2 n_dof), for the others
        self._fill = fill

    def __repr__(self) -> str:
        return (
            f"Stability(n_points={self.stable.size}, "
            f"unstable={int(np.count_nonzero(~self.stable))}, "
            f"computed={int(np.count_nonzero(self.computed))}, "
            f"elapsed={self.elapsed:.3g})"
        )

    def __getstate__(self) -> dict:
        self._complete()
        state = self.__dict__.copy()
        state["_fill"] = None
        return state

    def _complete(self) -> None:
        """Compute the exponents of the points not computed yet."""
        missing = np.flatnonzero(~self.computed)
        if missing.size == 0 or self._fill is None:
            return
        lam = self._fill(missing)
        if isinstance(lam, tuple):  # exponents and multipliers (monodromy)
            lam, mu = lam
        else:
            mu = np.exp(lam * (2.0 * np.pi / self.omega[missing])[:, None])
        self._exponents[missing] = lam
        self._multipliers[missing] = mu
        self._max_real[missing] = lam.real.max(axis=1)
        self.computed[missing] = True
        self._fill = None
        own = self._verdict(lam, mu)
        wrong = missing[own != self.stable[missing]]
        if wrong.size:
            # a filled verdict the point's own multipliers contradict (an
            # even number of changes between two computed points that no
            # indicator saw): the multipliers decide, loudly
            self.stable[wrong] = own[own != self.stable[missing]]
            warnings.warn(
                f"stability: {wrong.size} point(s) filled between computed ones "
                f"(first index {int(wrong[0])}, Ω = {self.omega[wrong[0]]:.6g} "
                "rad/s) had the other verdict from their own exponents when "
                "they were computed; `stable` now holds theirs (the schedule "
                'missed a change: exponents="all" computes every point)',
                AccuracyWarning,
                stacklevel=3,
            )

    def _verdict(self, lam: np.ndarray, mu: np.ndarray) -> np.ndarray:
        """Stability of points from their exponents (Hill: every real part
        negative) or multipliers (monodromy: every ``|μ| <= 1 +
        NEUTRAL_TOLERANCE``), shape (k,)."""
        if self.criterion == "monodromy":
            return np.abs(mu).max(axis=1, initial=0.0) <= 1.0 + NEUTRAL_TOLERANCE
        return lam.real.max(axis=1) < 0.0

    @property
    def exponents(self) -> np.ndarray:
        self._complete()
        return self._exponents

    @property
    def multipliers(self) -> np.ndarray:
        self._complete()
        return self._multipliers

    @property
    def max_real(self) -> np.ndarray:
        self._complete()
        return self._max_real

    def changes(self) -> np.ndarray:
        """Indices ``i`` where stability changes between points ``i - 1``
        and ``i``."""
        return np.flatnonzero(self.stable[1:] != self.stable[:-1]) + 1


def derivative_operator(harmonic_numbers: np.ndarray, omega: float) -> np.ndarray:
    """The time derivative in the real coefficient basis, shape (n_coef,
    n_coef): ``d/dt`` of ``a cos kΩt + b sin kΩt`` has the coefficients
    ``(kΩ b, -kΩ a)``."""
    hn = np.asarray(harmonic_numbers)
    width = np.where(hn == 0, 1, 2)
    n_coef = int(width.sum())
    D = np.zeros((n_coef, n_coef))
    k = hn[hn != 0]
    col = (np.cumsum(width) - width)[hn != 0]  # the cosine of each pair
    D[col, col + 1] = k * omega
    D[col + 1, col] = -k * omega
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


def _parity_of_rows(harmonic_numbers: np.ndarray, n_dof: int) -> np.ndarray:
    """Parity (0 even, 1 odd) of the harmonic of each row (DOF-major
    layout), shape (n_dof * n_coef,), int64."""
    per = np.repeat(harmonic_numbers, np.where(harmonic_numbers == 0, 1, 2))
    return np.tile(per % 2, n_dof).astype(np.int64)


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
    J = np.asarray(jacobian, dtype=float)
    J = J[None] if single else J
    w = np.broadcast_to(np.asarray(omega, dtype=float), (J.shape[0],))
    groups = _groups(J, harmonic_numbers, mass.shape[0], split)
    lam = _pencil_exponents(J, mass, damping, harmonic_numbers, w, groups)
    return lam[0] if single else lam


def _groups(J: np.ndarray, harmonic_numbers, n_dof: int, split: bool) -> list:
    """Index blocks of Hill's problem for the Jacobians ``J`` (n_points, n,
    n): the odd and even harmonics' when ``split`` and no Jacobian couples
    them, else the whole."""
    groups = [np.arange(J.shape[1])]
    if split and harmonic_numbers.size > 1:
        odd, even = _parity_blocks(harmonic_numbers, n_dof)
        coupling = max(
            float(np.max(np.abs(J[:, odd][:, :, even]), initial=0.0)),
            float(np.max(np.abs(J[:, even][:, :, odd]), initial=0.0)),
        )
        if coupling <= SPLIT_TOLERANCE * float(np.max(np.abs(J), initial=0.0)):
            groups = [odd, even]
    return groups


def _pencil_blocks(mass, damping, harmonic_numbers, groups) -> list:
    """Per Hill block (``groups``: index arrays): its indices, the damping
    and Ω-proportional parts of ``Δ1`` (``Δ1 = d1_damp + Ω d1_mass``),
    ``Δ2`` and the inverse of ``Δ2`` (None when the mass is singular).

    Built entry by entry on the block's rows (row ``r`` of the DOF-major
    layout is coefficient ``r % n_coef`` of DOF ``r // n_coef``):
    ``(A ⊗ B)[r, s] = A[dof_r, dof_s] B[coef_r, coef_s]``."""
    n_coef = sum(g.size for g in groups) // mass.shape[0]
    D = derivative_operator(harmonic_numbers, 1.0)
    try:
        minv = np.linalg.inv(mass)
        if not np.all(np.isfinite(minv)):
            minv = None
    except np.linalg.LinAlgError:
        minv = None
    blocks = []
    for idx in groups:
        dof, coef = np.divmod(idx, n_coef)
        pair_dof = np.ix_(dof, dof)
        same = np.equal.outer(coef, coef).astype(float)
        d1_damp = damping[pair_dof] * same
        d1_mass = 2.0 * mass[pair_dof] * D[np.ix_(coef, coef)]
        d2 = mass[pair_dof] * same
        mi = None if minv is None else minv[pair_dof] * same
        blocks.append((idx, d1_damp, d1_mass, d2, mi))
    return blocks


def _pencil_exponents(J, mass, damping, harmonic_numbers, w, groups) -> np.ndarray:
    """Selected exponents (n_points, 2 n_dof) of the Jacobians ``J``
    (n_points, n, n) at the pulsations ``w`` (n_points,), Hill's problem
    solved block by block (``groups``: index arrays, or the blocks of
    :func:`_pencil_blocks`)."""
    if not isinstance(groups[0], tuple):
        groups = _pencil_blocks(mass, damping, harmonic_numbers, groups)
    # the companion matrices (order 2 m: four times a Jacobian's terms)
    # of at most _CHUNK_BYTES at once
    m = max(g[0].size for g in groups)
    step = max(1, _CHUNK_BYTES // (32 * m * m))
    out = []
    for a in range(0, J.shape[0], step):
        part = slice(a, a + step)
        eigs = []
        for idx, d1_damp, d1_mass, d2, mi in groups:
            d1 = d1_damp[None] + w[part, None, None] * d1_mass[None]
            Jp = J[part]
            Jg = Jp if idx.size == J.shape[1] else Jp[:, idx][:, :, idx]
            eigs.append(_companion_eigenvalues(Jg, d1, d2, mi))
        out.append(
            select_exponents(np.concatenate(eigs, axis=1), 2 * mass.shape[0], w[part])
        )
    if not out:
        return np.zeros((0, 2 * mass.shape[0]), dtype=complex)
    return np.concatenate(out, axis=0)


def _stability_problem(system, force, harmonics, n_time, aft, subharmonic):
    """The full-basis, uncondensed HBM problem whose Jacobian Hill's
    method needs."""
    from .hbm import HBMProblem
    from .kernels.dlft.coulomb import COULOMB

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


def _to_full_basis(
    harmonic_numbers: np.ndarray, coefficients: np.ndarray, harmonics: int
) -> np.ndarray:
    """Coefficients (..., n_dof, n_coef) on ``harmonic_numbers`` placed in
    the full basis ``0 … harmonics`` (shape (..., n_dof, 2 harmonics +
    1)); higher harmonics are dropped."""
    out = np.zeros(coefficients.shape[:-1] + (2 * harmonics + 1,))
    col = 0
    for k in harmonic_numbers:
        width = 1 if k == 0 else 2
        if k <= harmonics:
            dst = 0 if k == 0 else 2 * k - 1
            out[..., dst : dst + width] = coefficients[..., col : col + width]
        col += width
    return out


class _Level:
    """The points of one harmonic level ``H`` of a stability computation:
    their HBM problem (full basis ``0 … H``), unknowns and Hill blocks.

    With ``signs``, the signs of ``det Δ0`` of each Hill block at every
    point are computed too (:meth:`determinant_signs`)."""

    def __init__(
        self,
        problem,
        idx,
        points,
        harmonic_numbers,
        keep,
        split,
        signs,
        reflect=False,
        kept_before: float = 0.0,
    ):
        self.problem = problem
        self.reflect = reflect  # measure the symmetry of Δ0 (one DOF)
        self._asymmetry = None  # relative asymmetry when measured
        self.idx = idx  # indices of the points in the whole set
        self.points = points  # (k, n_unknowns + 1): [X in the full basis, Ω]
        self.harmonic_numbers = harmonic_numbers  # of the perturbation
        self.keep = keep  # rows/columns kept (perturbation harmonics) or None
        self.mass = problem.kernel_problem[1]
        self.damping = problem.kernel_problem[2]
        self.n_dof = self.mass.shape[0]
        n = problem.n_unknowns if keep is None else keep.size
        self.n = n
        self.chunk = max(1, _CHUNK_BYTES // (8 * n * n))
        whole = np.arange(n)
        candidates = [whole]
        if split and harmonic_numbers.size > 1:
            candidates = list(_parity_blocks(harmonic_numbers, self.n_dof))
        # refused before any Jacobian when even the blocks asked for do not
        # fit (checked again below if the split is refused)
        h_level = int(problem.harmonic_numbers[-1])
        self.kept_bytes = check_hill_memory(
            kept_before, n, [c.size for c in candidates], idx.size, h_level, self.n_dof
        )
        # the Jacobians of all points while the computation runs, when
        # they fit in one chunk (dropped by release()), and the signs of
        # the candidate blocks computed with them
        self._all = None
        self._signs = None
        self._extremes = None  # (coupling, largest) measured with them
        # points stable by proof (contacts stuck, :func:`_stuck_everywhere`)
        self.proven = np.zeros(idx.size, dtype=bool)
        # every point stable by the energy proof (one DOF, Jenkins contacts
        # to ground, c > 0: :func:`_passive`, docs/stability.md)
        self.passive = False
        if signs and reflect and len(candidates) == 2 and _memoryless(problem, keep):
            # signs from the tangent stiffness's spectrum; the Jacobians
            # of the few computed points are evaluated when asked for
            self._signs, self._extremes = _memoryless_signs(problem, points, candidates)
            self._asymmetry = 0.0  # symmetric by construction (W-weighted)
        elif signs and len(candidates) == 2 and _passive(problem, points):
            # every contact a Jenkins element: every block's determinant is
            # positive at every point by proof (:func:`_passive`), and an odd
            # solution of the odd law couples no odd to even harmonic; no
            # AFT until the computed points' Jacobians are asked for
            self._signs = np.ones((idx.size, 2), dtype=np.int64)
            self._extremes = (0.0, 1.0)
            self.proven = None  # the stuck test at the points asked (proven_at)
            self.passive = True
        elif signs and (stuck := _stuck_everywhere(problem, points, keep, self.chunk)):
            # points whose contacts provably stick over the whole period:
            # their Jacobians are linear, every block's sign is +1 and
            # nothing couples; the AFT runs on the others only (their
            # Jacobians, and the computed points', are evaluated when asked)
            self._signs, self._extremes = self._signs_around(
                stuck, candidates, len(candidates) == 2
            )
        elif idx.size <= self.chunk:
            self._all, self._signs = self._evaluate(
                np.arange(idx.size), candidates if signs else None, len(candidates) == 2
            )
        self.groups = self._decide_groups(candidates)
        if self._signs is not None and len(self.groups) != len(candidates):
            self._signs = None  # the split was refused: signs of the whole
        if len(self.groups) != len(candidates):
            self.kept_bytes = check_hill_memory(
                kept_before, n, [n], idx.size, h_level, self.n_dof
            )
        if self._all is not None:
            self.kept_bytes += self._all.nbytes  # held until release()
        self.blocks = _pencil_blocks(
            self.mass, self.damping, harmonic_numbers, self.groups
        )

    def proven_at(self, local: np.ndarray) -> np.ndarray:
        """Whether the level's points ``local`` are stable by proof (every
        contact stuck, :func:`_stuck_everywhere`), bool (k,); tested at
        those points only when the level was built without the test."""
        if self.proven is not None:
            return self.proven[local]
        stuck = _stuck_everywhere(
            self.problem, self.points[local], self.keep, local.size
        )
        return np.zeros(local.size, dtype=bool) if stuck is None else stuck[2]

    def release(self) -> None:
        """Drop the Jacobians held (later calls evaluate them again)."""
        self._all = None

    def jacobians(self, local: np.ndarray) -> np.ndarray:
        """``∂R/∂X`` (k, n, n) at the level's points ``local`` (indices
        into ``self.points``)."""
        if self._all is not None:
            k = self._all.shape[0]
            if local.size == k and np.array_equal(local, np.arange(k)):
                return self._all
            return self._all[local]
        return self._evaluate(local)[0]

    def _evaluate(
        self,
        local: np.ndarray,
        groups=None,
        coupling: bool = False,
        hold: bool = True,
    ):
        """``∂R/∂X`` at the points ``local``, one compiled loop, and the
        signs (k, n_groups) of the determinants of the blocks ``groups``
        (None: not computed); ``hold=False``: the Jacobians are not kept
        (one slot, the returned array holds at most the last point's).
        With ``coupling`` (and every row kept), the
        largest odd-even coupling and entry are measured in the same loop
        (``self._extremes``, for :meth:`_decide_groups`)."""
        from .kernels.stability.hill import hill_jacobians

        problem = self.problem
        n_full = problem.n_unknowns
        # hold=False: one slot, the Jacobians are not kept (signs only)
        J = np.empty((local.size if hold else min(local.size, 1), n_full, n_full))
        status = np.empty(local.size, dtype=np.int64)
        blocks, sizes = _block_table(groups or [], self.keep)
        signs = np.empty((local.size, sizes.size), dtype=np.int64)
        parity = np.zeros(0, dtype=np.int64)
        if coupling and self.keep is None:
            parity = _parity_of_rows(self.harmonic_numbers, self.n_dof)
        skew = np.zeros((0, 0))
        weight = np.zeros(0)
        if self.reflect and groups:
            # rows of harmonic 0 carry half the Galerkin weight of the
            # others: W = diag(2 there, 1 elsewhere) makes the AFT
            # Jacobian of a memoryless law symmetric
            per = np.repeat(
                problem.harmonic_numbers,
                np.where(problem.harmonic_numbers == 0, 1, 2),
            )
            weight = np.tile(np.where(per == 0, 2.0, 1.0), self.n_dof)
            skew = 2.0 * np.kron(
                problem.kernel_problem[2],
                derivative_operator(problem.harmonic_numbers, 1.0),
            )
            skew *= weight[:, None]
        extremes = np.zeros(3)
        hill_jacobians(
            np.ascontiguousarray(self.points[local]),
            problem.kernel_problem,
            J,
            status,
            blocks,
            sizes,
            signs,
            parity,
            weight,
            skew,
            SPLIT_TOLERANCE,
            extremes,
        )
        bad = np.flatnonzero(status < 0)
        if bad.size:
            j = int(bad[0])
            omega = float(self.points[local[j], -1])
            raise ValueError(
                f"the AFT failed at Ω = {omega:.6g} rad/s (code {int(status[j])})"
            )
        if parity.size:
            self._extremes = (float(extremes[0]), float(extremes[1]))
        if skew.size:
            self._asymmetry = float(extremes[2])
        if self.keep is not None:
            J = J[:, self.keep][:, :, self.keep]
        return J, (signs if groups else None)

    def _signs_around(self, stuck, groups: list, coupling: bool):
        """Signs (k, n_groups) of the blocks ``groups`` at every point and
        the (coupling, largest) pair of :meth:`_decide_groups`, with the
        points of ``stuck`` (``(mask, largest entry)`` of
        :func:`_stuck_everywhere`) taken as ``+1`` without an AFT (their
        Jacobians are symmetric in the sense of
        :meth:`reflection_symmetric` and couple nothing); one compiled
        loop over the others."""
        mask, stuck_largest, self.proven = stuck
        signs = np.ones((self.idx.size, len(groups)), dtype=np.int64)
        others = np.flatnonzero(~mask)
        extremes = (0.0, float(stuck_largest.max(initial=0.0)))
        if self.reflect:
            self._asymmetry = 0.0
        if others.size:
            _, signs[others] = self._evaluate(others, groups, coupling, hold=False)
            if self._extremes is not None:
                extremes = (
                    max(extremes[0], self._extremes[0]),
                    max(extremes[1], self._extremes[1]),
                )
        return signs, extremes

    def _chunks(self):
        k = self.idx.size
        for a in range(0, k, self.chunk):
            local = np.arange(a, min(k, a + self.chunk))
            yield local, self.jacobians(local)

    def _decide_groups(self, candidates: list) -> list:
        """Hill's blocks, decided on every point of the level (as one
        :func:`floquet_exponents` call on all of them would): the odd and
        even ones when ``candidates`` holds them and no Jacobian couples
        them, else the whole."""
        if len(candidates) == 1:
            return candidates
        from .kernels.stability.hill import split_extremes

        odd, even = candidates
        if self._extremes is not None:
            coupling, largest = self._extremes  # measured with the Jacobians
        else:
            coupling, largest = 0.0, 0.0
            for _, J in self._chunks():
                c, g = split_extremes(J, odd, even)
                coupling, largest = max(coupling, c), max(largest, g)
        if np.isfinite(largest) and coupling <= SPLIT_TOLERANCE * largest:
            return candidates
        return [np.arange(self.n)]

    def reflection_symmetric(self) -> bool:
        """Whether ``W (Δ0 - Ω C ⊗ D₁)`` was found symmetric (relative
        ``SPLIT_TOLERANCE`` to each point's largest entry; ``W``: 2 on the
        rows of harmonic 0, 1 elsewhere) at every point of the level
        (measured with the Jacobians when ``reflect``; False when not
        measured)."""
        if self._asymmetry is None:
            return False
        return bool(self._asymmetry <= SPLIT_TOLERANCE)

    def exponents(self, local: np.ndarray) -> np.ndarray:
        """Selected exponents (k, 2 n_dof) at the level's points ``local``."""
        out = np.empty((local.size, 2 * self.n_dof), dtype=complex)
        for a in range(0, local.size, self.chunk):
            part = local[a : a + self.chunk]
            out[a : a + part.size] = _pencil_exponents(
                self.jacobians(part),
                self.mass,
                self.damping,
                self.harmonic_numbers,
                self.points[part, -1],
                self.blocks,
            )
        return out

    def determinant_signs(self) -> np.ndarray:
        """Signs (k, n_groups) of ``det Δ0`` of each Hill block at every
        point of the level (0: numerically singular)."""
        if self._signs is not None:
            return self._signs
        from .kernels.stability.hill import block_determinant_signs

        blocks, sizes = _block_table(self.groups, None)
        signs = np.empty((self.idx.size, sizes.size), dtype=np.int64)
        for local, J in self._chunks():
            out = np.empty((local.size, sizes.size), dtype=np.int64)
            block_determinant_signs(J, blocks, sizes, out)
            signs[local] = out
        return signs


#: a block's determinant sign counts as 0 (a flip on both sides of the
#: point) where its smallest LU pivot is below this share of its largest:
#: the spectral Jacobian of :func:`_memoryless_signs` equals the AFT's up to
#: rounding only, and a sign taken that close to singular could differ
SIGN_GUARD = 1e-11


def _full_problem(kernel_problem) -> bool:
    """Whether a kernel problem is the full harmonic balance's: the plain
    tuple, or one of its per-law-family types (not condensed, not rigid
    Coulomb)."""
    from .kernels.residuals.hbm import FAMILY_TYPES

    return type(kernel_problem) is tuple or type(kernel_problem) in tuple(
        FAMILY_TYPES.values()
    )


def _memoryless(problem, keep) -> bool:
    """Whether the Jacobians of ``problem`` can come from the spectrum of
    the tangent stiffness (:func:`hbmfric.kernels.stability.hill.memoryless_jacobians`):
    one DOF, every row kept, every contact memoryless (``Cubic``) between
    the DOF and ground, one fundamental (no subharmonic)."""
    from .kernels.laws.updates import CUBIC

    kp = problem.kernel_problem
    if keep is not None or kp[1].shape[0] != 1 or not _full_problem(kp):
        return False
    if getattr(problem, "subharmonic", 1) not in (None, 1):
        return False
    pairs, codes = np.asarray(kp[5]), np.asarray(kp[6])
    hn = np.asarray(kp[0])
    return bool(
        np.all(codes == CUBIC)
        and (pairs.size == 0 or (np.all(pairs[:, 0] == 0) and np.all(pairs[:, 1] < 0)))
        and np.array_equal(hn, np.arange(hn.size))
    )


def _memoryless_signs(problem, points: np.ndarray, groups: list):
    """Signs (k, n_groups) of the blocks ``groups`` of the Jacobians at
    ``points`` (k, n + 1), and the (coupling, largest) pair of
    :meth:`_Level._decide_groups`, from the tangent stiffness's spectrum."""
    from .kernels.stability.hill import memoryless_jacobians

    kp = problem.kernel_problem
    hn = np.asarray(kp[0])
    n_time = kp[9].shape[0]
    theta = 2.0 * np.pi * np.arange(n_time) / n_time
    m = np.arange(2 * int(hn[-1]) + 1)[:, None]
    structure = np.array([kp[1][0, 0], kp[2][0, 0], kp[3][0, 0]], dtype=float)
    blocks, sizes = _block_table(groups, None)
    signs = np.empty((points.shape[0], sizes.size), dtype=np.int64)
    extremes = np.zeros(2)
    n = problem.n_unknowns
    memoryless_jacobians(
        np.ascontiguousarray(points),
        hn.astype(np.int64),
        structure,
        np.asarray(kp[6], dtype=np.int64),
        np.ascontiguousarray(kp[7], dtype=float),
        np.cos(m * theta),
        np.sin(m * theta),
        np.empty((n, n)),
        blocks,
        sizes,
        signs,
        _parity_of_rows(hn, 1),
        SIGN_GUARD,
        True,  # Cubic, the only memoryless law, is odd
        extremes,
    )
    return signs, (float(extremes[0]), float(extremes[1]))


#: relative margin of the amplitude bound against the slip limit in
#: :func:`_stuck_everywhere` (the AFT's extremes are rounded evaluations)
STUCK_MARGIN = 1e-9
#: factor by which :func:`_stuck_everywhere` asks the smallest pivot to
#: clear the LU's zero-pivot test (1e-15 of the largest entry)
PIVOT_SLACK = 1e3
#: a stuck point's stability is taken without eigenvalues when ``c/2m``
#: exceeds this share of ``1 + (largest entry)/m`` (the size of the
#: companion matrix whose eigenvalues the other route computes)
PROVEN_MARGIN = 1e-6


def _passive(problem, points: np.ndarray) -> bool:
    """Whether every diagonal block of harmonics of the HBM Jacobian at
    ``points`` has a positive determinant by proof: one DOF (mass ``m``,
    damping ``c > 0``, stiffness ``k > 0``) whose contacts are all Jenkins
    elements to ground evaluated by the event AFT, every point odd (no even
    harmonic) with ``Ω > 0``.

    Why (``docs/stability.md``, "Jenkins branches"): the event AFT's
    Jacobian is the exact Galerkin projection of the Jenkins linearisation
    ``δf = kt (δu(θ) - δu(θ_s))`` on each stick segment starting at
    ``θ_s`` (0 in slip), so for any perturbation ``δu`` in a set of
    harmonics ``∫ δu' δf dθ = Σ kt (δu(θ_e) - δu(θ_s))² / 2 >= 0`` (one
    term per stick segment ``[θ_s, θ_e]``). If the block ``J_S`` of a set
    ``S`` of harmonics maps ``δU`` to 0, testing the residual with ``δu'``
    (in the span of ``S`` as well) leaves ``c Ω ∫ δu'² + Σ kt (…)² / 2 =
    0``: ``δu`` is constant, and then ``k δu = 0``. So ``J_S`` is regular,
    and so is ``J_lin + τ (J_S - J_lin)`` for every ``τ`` in [0, 1] (the
    contact part scaled by ``τ >= 0`` keeps its sign); ``det`` of the
    linear block ``J_lin`` is ``k Π ((k - m j²Ω²)² + (c jΩ)²)`` (up to the
    rows' positive normalisation) ``> 0``, hence ``det J_S > 0``. An odd
    ``u`` of an odd law gives a linearisation that repeats after half a
    period: no coupling of odd and even harmonics.
    """
    from .kernels.laws.updates import JENKINS
    from .kernels.residuals.hbm import AFT_EVENTS

    kp = problem.kernel_problem
    if not _full_problem(kp) or kp[1].shape[0] != 1:
        return False
    pairs, codes, params = np.asarray(kp[5]), np.asarray(kp[6]), np.asarray(kp[7])
    hn = np.asarray(kp[0])
    c, k = float(kp[2][0, 0]), float(kp[3][0, 0])
    if (
        int(kp[8]) != AFT_EVENTS
        or codes.size == 0
        or not np.all(codes == JENKINS)
        or not (np.all(pairs[:, 0] == 0) and np.all(pairs[:, 1] < 0))
        or not (c > 0.0 and k > 0.0 and np.isfinite(float(kp[1][0, 0])))
        or not np.all(np.isfinite(params[:, :2]))
        or not (np.all(params[:, 0] >= 0.0) and np.all(params[:, 1] >= 0.0))
        or not np.array_equal(hn, np.arange(hn.size))
    ):
        return False
    per = np.repeat(hn, np.where(hn == 0, 1, 2))
    even = per % 2 == 0
    return bool(
        np.all(points[:, :-1][:, even] == 0.0)
        and np.all(np.isfinite(points))
        and np.all(points[:, -1] > 0.0)
    )


def _stuck_everywhere(problem, points: np.ndarray, keep, chunk: int):
    """Points at which every contact provably sticks over the whole
    period, so that the HBM Jacobian is the linear one plus the contact
    stiffnesses on the diagonal, and the sign of the determinant of every
    diagonal block of harmonics is +1.

    Applies to one DOF whose contacts are all Jenkins elements to ground
    evaluated by the event AFT (every row kept, positive mass, damping
    and slip forces); returns None otherwise.

    Why: with ``|u(θ)| <= A = |a_0| + Σ_k hypot(a_k, b_k)`` and ``kt A <=
    f_s`` for each contact, the AFT finds the contact stuck with its
    slider at 0 (``kt (u_max - u_min) <= 2 f_s``, neither extreme beyond
    ``f_s / kt``), whose ``dF/dX`` is ``kt I`` exactly. The Jacobian is
    then block diagonal: ``k + Σ kt`` for harmonic 0 and ``[[a, cw],
    [-cw, a]]`` (``a = k - m w² + Σ kt``, ``w = jΩ``) for harmonic ``j``.
    The LU with partial pivoting of such a block (any union of
    harmonics) eliminates within each pair only, with pivots ``a + (cw)²/a``
    and ``a`` (or ``-cw`` and ``cw + a²/(cw)`` after the swap), of equal
    signs, never cancelling, each at least ``cw`` in modulus: sign ``+1``
    when ``k + Σ kt > 0`` and both it and ``cΩ`` clear the LU's zero-pivot
    test (1e-15 of the largest entry) by ``PIVOT_SLACK``.

    At such a point Hill's pencil is that of the linear oscillator with
    the stiffness ``k + Σ kt``, harmonic by harmonic, and its eigenvalues
    are the families ``r + ijΩ`` of the roots ``r`` of ``m r² + c r + k +
    Σ kt``: every one has a negative real part (``-c/2m``, or both roots
    real and negative), whatever the selection, so the point is stable.

    Returns
    -------
    (mask, largest, proven) or None
        ``mask`` (n_points,) bool: the stuck points; ``largest``
        (n_stuck,): the largest entry of each one's Jacobian, N/m;
        ``proven`` (n_points,) bool: the stuck points whose stability
        needs no eigenvalues (``c/2m`` above ``PROVEN_MARGIN (1 +
        largest/m)``, far above the error of the eigenvalues the other
        route would compute). None also when no point is stuck or more
        than ``chunk`` are not (the chunked route of :class:`_Level` then
        runs as before).
    """
    from .kernels.laws.updates import JENKINS
    from .kernels.residuals.hbm import AFT_EVENTS

    kp = problem.kernel_problem
    if keep is not None or not _full_problem(kp) or kp[1].shape[0] != 1:
        return None
    pairs, codes, params = np.asarray(kp[5]), np.asarray(kp[6]), np.asarray(kp[7])
    hn = np.asarray(kp[0])
    m, c, k = float(kp[1][0, 0]), float(kp[2][0, 0]), float(kp[3][0, 0])
    if (
        int(kp[8]) != AFT_EVENTS
        or codes.size == 0
        or not np.all(codes == JENKINS)
        or not (np.all(pairs[:, 0] == 0) and np.all(pairs[:, 1] < 0))
        or not np.array_equal(hn, np.arange(hn.size))
        or not (m > 0.0 and c > 0.0)
    ):
        return None
    kt, fs = params[:, 0].astype(float), params[:, 1].astype(float)
    if not (np.all(kt > 0.0) and np.all(fs > 0.0)):
        return None
    X = points[:, :-1]
    omega = points[:, -1]
    amplitude = np.abs(X[:, 0]) + np.hypot(X[:, 1::2], X[:, 2::2]).sum(axis=1)
    stuck = np.all(
        kt[None, :] * amplitude[:, None] * (1.0 + STUCK_MARGIN) <= fs[None, :], axis=1
    )
    k_total = k + float(kt.sum())
    w = hn[None, 1:] * omega[:, None]
    largest = np.maximum(
        abs(k_total),
        np.maximum(np.abs(k - m * w * w + kt.sum()), c * w).max(axis=1, initial=0.0),
    )
    # the smallest pivot (cΩ, or k + Σ kt) well clear of the LU's test
    floor = PIVOT_SLACK * 1e-15 * largest
    stuck &= (c * omega > floor) & (k_total > floor)
    stuck &= np.all(np.isfinite(points), axis=1)
    if not np.any(stuck) or np.count_nonzero(~stuck) > chunk:
        return None
    # every eigenvalue of Hill's pencil of a linear Jacobian has the real
    # part -c/2m (or, overdamped, two negative real families): stable,
    # with a margin far above an eigenvalue solver's error
    proven = stuck & (c / (2.0 * m) > PROVEN_MARGIN * (1.0 + largest / m))
    return stuck, largest[stuck], proven


def _block_table(groups: list, keep) -> tuple[np.ndarray, np.ndarray]:
    """Index blocks as a padded table (n_blocks, m_max) and their sizes,
    mapped through ``keep`` (indices of the kept rows in the full
    matrix) when given."""
    sizes = np.array([g.size for g in groups], dtype=np.int64)
    blocks = np.zeros((sizes.size, int(sizes.max(initial=0))), dtype=np.int64)
    for b, g in enumerate(groups):
        blocks[b, : g.size] = g if keep is None else keep[g]
    return blocks, sizes


#: bytes of Jacobians held at once (larger sets are processed in chunks)
_CHUNK_BYTES = 1 << 25
#: dense float64 matrices of a Hill block's order ``g`` kept per block
#: while a level's eigenvalues are computed (``Δ1``'s two parts, ``Δ2`` and
#: its inverse, :func:`_pencil_blocks`)
BLOCK_MATRICES = 4
#: ... and held by one block's eigenvalue solve, per point solved at once:
#: its companion matrix (order ``2 g``: 4) and what ``numpy.linalg.eigvals``
#: holds beside it (measured peaks: 7 at orders 930 and 1860, 9 kept as a
#: margin; ``tests/test_stability_memory.py``)
SOLVE_MATRICES = 9


def hill_bytes(n: int, block_orders, n_points: int) -> tuple[float, float]:
    """Bytes of Hill's problem on one harmonic level: ``(kept, working)``.

    Parameters
    ----------
    n : int
        Order of a point's Jacobian (the level's unknowns kept in the
        perturbation basis).
    block_orders : sequence of int
        Orders of Hill's blocks (``n`` alone, or the odd and even blocks).
    n_points : int
        Points of the level.

    Returns
    -------
    kept : float
        The blocks' matrices, kept until the stability is returned.
    working : float
        The Jacobians of one chunk and one eigenvalue solve of the largest
        block, held while a chunk is solved.
    """
    n_points = max(1, int(n_points))
    kept = 8.0 * BLOCK_MATRICES * sum(float(g) ** 2 for g in block_orders)
    jac_chunk = min(n_points, max(1, _CHUNK_BYTES // (8 * n * n)))
    g = float(max(block_orders))
    solve_chunk = min(n_points, max(1, int(_CHUNK_BYTES // (32.0 * g * g))))
    working = 8.0 * n * n * jac_chunk + 8.0 * SOLVE_MATRICES * g * g * solve_chunk
    return kept, working


def check_hill_memory(
    kept_before: float, n: int, block_orders, n_points: int, h: int, n_dof: int
) -> float:
    """Raise :class:`MemoryError` before any eigenvalue work when Hill's
    problem of a level (:func:`hill_bytes`), with what the levels before it
    keep (``kept_before``, bytes), does not fit in
    :func:`hbmfric._memory.budget`; return the bytes kept with this level.
    """
    from . import _memory

    kept, working = hill_bytes(n, block_orders, n_points)
    need = kept_before + kept + working
    room = _memory.budget()
    if need <= room:
        return kept_before + kept
    available = room / _memory.MEMORY_SHARE
    raise MemoryError(
        f"Hill's stability at H = {h} ({n} unknowns per point, {n_points} "
        f"points) needs about {_memory.gigabytes(need)} for its dense matrices, "
        f"more than the {_memory.gigabytes(available)} this machine can give "
        f"it ({_memory.MEMORY_SHARE:.0%} of the memory available now). Use "
        'method="monodromy" (the time-domain monodromy: matrices of order '
        f"2 x {n_dof} DOFs per point), a smaller perturbation_harmonics (the "
        "cost grows like its square; docs/stability.md), or a reduced model "
        "(hf.craig_bampton)"
    )


#: ``exponents="auto"`` computes Hill's eigenvalues at every
#: ``ANCHOR_SPACING``-th point at least (see :func:`stability_of_points`)
ANCHOR_SPACING = 64
#: relative tolerance (to ``c/m`` plus the largest ``|Re λ|``) of the
#: pairing ``Re(λ₁ + λ₂) = -c/m`` of the two exponents of one DOF that
#: lets a reflection-symmetric branch go without anchors
REFLECTION_TOLERANCE = 1e-8


def _exponents_at(levels: list, level_of: np.ndarray, local_of, where) -> np.ndarray:
    """Exponents of the points ``where`` (global indices)."""
    out = None
    for lv_id in np.unique(level_of[where]):
        lv = levels[int(lv_id)]
        sel = np.flatnonzero(level_of[where] == lv_id)
        lam = lv.exponents(local_of[where[sel]])
        if out is None:
            out = np.empty((where.size, lam.shape[1]), dtype=complex)
        out[sel] = lam
    return out


def _sparse_schedule(
    n_points: int,
    flips: np.ndarray,
    verdict,
    anchor_spacing: int,
    cluster: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """Points at which to compute Hill's eigenvalues, and the verdict of
    every point.

    ``flips[i]`` (i >= 1): an indicator changes between points ``i - 1``
    and ``i``. Computed: the first and last points, both ends of every
    flip, every ``anchor_spacing``-th point; then, between two computed
    points with different verdicts, the middle one, until every such pair
    is adjacent. ``verdict(where)`` returns the stability of the points
    ``where``. Every other point takes the verdict of the computed points
    around it (equal by construction).

    ``anchor_spacing = 0`` (the verdict can change only at a flip): one
    point per stretch between flips, the two ends of every flip (the
    first point if there is no flip), and no anchors.

    ``cluster > 0``: every point between two flips at most ``cluster``
    points apart is computed too (a cluster of folds, where the verdict
    can change and change back between two flips that the indicators
    do not see: :data:`FOLD_CLUSTER`).
    """
    want = np.zeros(n_points, dtype=bool)
    f = np.flatnonzero(flips)
    if anchor_spacing > 0:
        want[[0, n_points - 1]] = True
        want[::anchor_spacing] = True
    elif f.size == 0:
        want[0] = True
    want[f] = True
    want[f - 1] = True
    if cluster > 0 and f.size > 1:
        for a, b in zip(f[:-1], f[1:], strict=True):
            if b - a <= cluster:
                want[a - 1 : b + 1] = True
    computed = np.zeros(n_points, dtype=bool)
    stable = np.zeros(n_points, dtype=bool)
    while True:
        new = np.flatnonzero(want & ~computed)
        if new.size == 0:
            break
        stable[new] = verdict(new)
        computed[new] = True
        c = np.flatnonzero(computed)
        gap = (np.diff(c) > 1) & (stable[c[1:]] != stable[c[:-1]])
        want[(c[:-1][gap] + c[1:][gap]) // 2] = True
    c = np.flatnonzero(computed)
    nearest = c[np.searchsorted(c, np.arange(n_points), side="right") - 1]
    return computed, stable[nearest]


def _level_problems(system, force, point_harmonics, n_time, aft, subharmonic):
    """``(H, problem)`` of each harmonic level of the points, ascending."""
    out = []
    for h in (int(v) for v in np.unique(np.asarray(point_harmonics))):
        nt = n_time if n_time is not None and n_time > 2 * h else None
        out.append((h, _stability_problem(system, force, h, nt, aft, subharmonic)))
    return out


def _build_levels(
    problems,
    omega,
    harmonic_numbers,
    coefficients,
    point_harmonics,
    perturbation_harmonics,
    symmetric,
    signs,
    reflect=None,
):
    """The :class:`_Level` of each harmonic level (``problems`` of
    :func:`_level_problems`), with the level and the local index of each
    point and the highest harmonic of each point's perturbation
    (``reflect``: measure the reflection symmetry; default ``signs``)."""
    reflect = signs if reflect is None else reflect
    n_points = omega.size
    n_dof = coefficients.shape[1]
    levels_of = np.asarray(point_harmonics, dtype=np.int64)
    used = levels_of.copy()
    levels: list[_Level] = []
    level_of = np.zeros(n_points, dtype=np.int64)
    local_of = np.zeros(n_points, dtype=np.int64)
    for h, problem in problems:
        idx = np.flatnonzero(levels_of == h)
        points = np.empty((idx.size, problem.n_unknowns + 1))
        points[:, :-1] = _to_full_basis(harmonic_numbers, coefficients[idx], h).reshape(
            idx.size, -1
        )
        points[:, -1] = omega[idx]
        hn = problem.harmonic_numbers
        keep = None
        if perturbation_harmonics is not None and perturbation_harmonics < h:
            hn = hn[hn <= perturbation_harmonics]
            keep = np.concatenate(
                [d * problem.n_coef + np.arange(2 * hn[-1] + 1) for d in range(n_dof)]
            )
        used[idx] = hn[-1]
        level_of[idx] = len(levels)
        local_of[idx] = np.arange(idx.size)
        kept = levels[-1].kept_bytes if levels else 0.0
        levels.append(
            _Level(
                problem,
                idx,
                points,
                hn,
                keep,
                symmetric,
                signs,
                reflect=reflect,
                kept_before=kept,
            )
        )
    return levels, level_of, local_of, used


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
    exponents: str = "auto",
    method: str = "auto",
) -> Stability:
    """Hill's stability of periodic solutions of ``system`` (or, for
    hysteretic contacts on several DOFs, the time-domain monodromy).

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
        odd and even blocks separately (checked on the points of each
        ``H``).
    perturbation_harmonics : int, optional
        Highest harmonic ``Hp`` of the perturbation: the Jacobian is
        evaluated at the solution with all its harmonics, and Hill's
        problem keeps the rows and columns of the harmonics ``0 … Hp``
        (a Galerkin truncation of the perturbation alone). Default: each
        point's ``H``. Smaller is cheaper (the eigenvalue solves grow like
        ``Hp³``) and less accurate (``tests/test_stability.py``).
    exponents : {"auto", "all"}
        ``"all"``: Hill's eigenvalues at every point. ``"auto"``: the same,
        except on a symmetric branch (``symmetric``, the odd/even split
        confirmed) of one DOF with positive mass and damping, where they
        are computed at a few points only (the others' exponents when
        first read, :class:`Stability`): the sign of ``det Δ0`` of the
        odd and of the even block is tracked at every point (an LU of the
        HBM Jacobian; it changes exactly where an odd number of real
        exponents crosses zero: folds, symmetric and symmetry-breaking
        branch points), and the eigenvalues are computed at both ends of
        every sign change, at the first and last points, at every
        ``ANCHOR_SPACING``-th point, and, between two computed points of
        different stability, at the middle point until they are adjacent.
        A stretch between computed points with no sign change takes their
        (equal) stability. Why symmetric only: the period map of a
        symmetric solution is ``G²`` (``G``: half a period and the sign
        flip); a multiplier -1 or a complex pair of it needs a complex
        pair of ``G`` on the unit circle, which Liouville's formula
        (product of ``G``'s multipliers ``exp(-(c/m) T/2) < 1``) rules out
        for a smooth law, so only real crossings remain. Hill's exponents
        of a hysteretic law do not obey Liouville's formula; for them the
        anchors and the bisection are the safeguard, and what can be
        missed is an even number of complex crossings between two
        computed points with no real crossing between them. Where every
        contact (Jenkins elements to ground) provably sticks over the
        whole period, the Jacobian is linear: its signs are +1 and the
        point is stable without an AFT, an LU or eigenvalues
        (:func:`_stuck_everywhere`). A branch
        without the symmetry can double its period (a complex crossing
        no determinant of the integer-harmonic pencil sees): every point.
        On a one-DOF branch whose contacts are all Jenkins elements to
        ground (event AFT), every sign is +1 by proof (:func:`_passive`): no
        AFT runs for the signs. With the monodromy, ``"auto"`` computes
        it at a few points too (:func:`_monodromy_stability`): a system of
        Jenkins contacts with symmetric definite matrices is stable by
        proof (:func:`_incrementally_passive`, the monodromy at anchors as
        a check), any other is scheduled on Hill's signs and verdicts
        (:func:`_hill_flips`).
    method : {"auto", "hill", "monodromy"}
        ``"hill"``: Hill's method. ``"monodromy"``: the monodromy matrix
        of the time-integration reference (at every point with
        ``exponents="all"``, else at a few, see ``exponents``)
        (:func:`hbmfric.validation.monodromy`: central differences of its
        period map, 2048 steps per period), exponents ``log(μ)/T``;
        contacts with a finite state only (Jenkins, modified Dahl, Cubic).
        ``"auto"``: the monodromy for a contact with memory on a system of
        several DOFs and for a modified Dahl contact on one DOF (at every
        point, :func:`_automatic_method`), else Hill. Why: Hill's linearisation
        of a hysteretic law is exact only where an exponent crosses zero, and
        on the paper beam (Jenkins tip, 39 DOFs) it reads every slipping point
        unstable (|μ| 2.5-7.3) where the time-domain monodromy finds 0.69-0.94
        and time integration settles on the solution
        (``tests/test_stability_hysteretic.py``). On one DOF its verdicts agree
        with the monodromy's on Jenkins branches (not on the modified Dahl
        law's, ``tests/test_dahl_stability.py``). Where the monodromy cannot be
        formed (Menq, Iwan, the 2D element on several DOFs) Hill is used with
        an :class:`~hbmfric.AccuracyWarning`.

    Returns
    -------
    Stability
    """
    if exponents not in ("auto", "all"):
        raise ValueError(f'exponents must be "auto" or "all", got {exponents!r}')
    if method not in ("auto", "hill", "monodromy"):
        raise ValueError(
            f'method must be "auto", "hill" or "monodromy", got {method!r}'
        )
    omega = np.asarray(omega, dtype=float)
    if method == "auto":
        method = _automatic_method(system, coefficients.shape[1])
    if method == "monodromy":

        def flips() -> np.ndarray:
            return _hill_flips(
                system,
                force,
                omega,
                harmonic_numbers,
                coefficients,
                point_harmonics,
                n_time,
                aft,
                subharmonic,
                symmetric,
            )

        return _monodromy_stability(
            system,
            force,
            omega,
            harmonic_numbers,
            coefficients,
            point_harmonics,
            subharmonic,
            exponents=exponents,
            # Hill's flips leave out the memory of a Dahl law (its verdicts
            # can be wrong, _automatic_method): no schedule on them, the
            # monodromy at every point
            flips=None if _has_dahl(system) else flips,
        )
    start = time.perf_counter()
    n_points = omega.size
    n_dof = coefficients.shape[1]
    problems = _level_problems(system, force, point_harmonics, n_time, aft, subharmonic)
    sparse = bool(
        exponents == "auto"
        and symmetric
        and n_points > 2
        and n_dof == 1
        and problems[0][1].kernel_problem[1][0, 0] > 0.0
        and problems[0][1].kernel_problem[2][0, 0] > 0.0
    )
    levels, level_of, local_of, used = _build_levels(
        problems,
        omega,
        harmonic_numbers,
        coefficients,
        point_harmonics,
        perturbation_harmonics,
        symmetric,
        sparse,
    )

    def exponents_at(where: np.ndarray) -> np.ndarray:
        return _exponents_at(levels, level_of, local_of, where)

    exps = np.full((n_points, 2 * n_dof), np.nan + 0j)
    # the Jacobians couple odd and even harmonics somewhere: not a
    # symmetric solution after all, a period doubling is possible
    sparse = sparse and all(len(lv.groups) == 2 for lv in levels)
    if sparse:
        # columns: the sign of each block (at most two; +1 where unused),
        # then the level
        signs = np.ones((n_points, 3), dtype=np.int64)
        for lv_id, lv in enumerate(levels):
            s = lv.determinant_signs()
            signs[lv.idx, : s.shape[1]] = s
            signs[lv.idx, 2] = lv_id
        zero = np.any(signs[:, :2] == 0, axis=1)
        flips = np.zeros(n_points, dtype=bool)
        flips[1:] = np.any(signs[1:] != signs[:-1], axis=1) | zero[1:] | zero[:-1]

        # Δ0 - Ω C ⊗ D₁ symmetric at every point (a memoryless law): the
        # pencil's eigenvalues pair as λ, -c/m - λ, the verdict changes
        # only at a flip (stability_of_points); checked on the computed
        # points' exponents, anchors again where it fails
        c_over_m = float(
            problems[0][1].kernel_problem[2][0, 0]
            / problems[0][1].kernel_problem[1][0, 0]
        )
        reflected = subharmonic == 1 and all(lv.reflection_symmetric() for lv in levels)
        paired = [True]
        # stable by proof (every contact stuck: a linear oscillator's
        # pencil, _stuck_everywhere): a verdict without eigenvalues
        proven = np.zeros(n_points, dtype=bool)
        for lv in levels:
            if lv.proven is not None:  # else tested at the points asked only
                proven[lv.idx] = lv.proven
        solved = np.zeros(n_points, dtype=bool)
        lazy = [lv_id for lv_id, lv in enumerate(levels) if lv.proven is None]

        def verdict(where: np.ndarray) -> np.ndarray:
            out = np.ones(where.size, dtype=bool)
            for lv_id in lazy:
                sel = where[level_of[where] == lv_id]
                if sel.size:
                    proven[sel] = levels[lv_id].proven_at(local_of[sel])
            need = ~proven[where]
            todo = where[need]
            if todo.size == 0:
                return out
            lam = exponents_at(todo)
            exps[todo] = lam
            solved[todo] = True
            total = lam.real.sum(axis=1)
            size = c_over_m + np.abs(lam.real).max(axis=1)
            paired[0] &= bool(
                np.all(np.abs(total + c_over_m) <= REFLECTION_TOLERANCE * size)
            )
            out[need] = lam.real.max(axis=1) < 0.0
            return out

        # one DOF whose contacts are all Jenkins elements to ground (c > 0):
        # the energy of the difference of two motions never grows
        # (_incrementally_passive), so no exponent can cross into the right
        # half-plane between points; the verdict cannot change and needs no
        # anchors (the computed point's exponents still give it)
        passive = all(lv.passive for lv in levels)
        spacing = 0 if reflected or passive else ANCHOR_SPACING
        _, stable = _sparse_schedule(n_points, flips, verdict, spacing)
        if passive and not stable.all():
            # a computed verdict against the proof (the truncated pencil):
            # the numerics decide, at the anchors as on any other branch
            _, stable = _sparse_schedule(n_points, flips, verdict, ANCHOR_SPACING)
        elif spacing == 0 and not paired[0] and not passive:
            _, stable = _sparse_schedule(n_points, flips, verdict, ANCHOR_SPACING)
        computed = solved
    else:
        computed = np.ones(n_points, dtype=bool)
        _warn_cost(levels, n_dof, perturbation_harmonics)
        if n_points:
            exps[:] = exponents_at(np.arange(n_points))
        stable = exps.real.max(axis=1) < 0.0 if n_points else np.zeros(0, bool)
    period = 2.0 * np.pi / omega
    max_real = exps.real.max(axis=1) if n_points else np.zeros(0)
    for lv in levels:
        lv.release()
    fill = None
    if not computed.all():
        fill = exponents_at
    return Stability(
        exponents=exps,
        multipliers=np.exp(exps * period[:, None]),
        stable=stable,
        max_real=max_real,
        omega=omega.copy(),
        harmonics=used,
        elapsed=time.perf_counter() - start,
        computed=computed,
        fill=fill,
    )


#: seconds per cubed order of one eigenvalue solve of a companion matrix
#: (``numpy.linalg.eigvals``, one thread: 0.3-1.8 ns on the project's
#: machines for orders 256-2032), for :func:`hill_seconds`
EIGVALS_SECONDS = 1e-9
#: estimated seconds above which Hill's stability warns before its work
#: (:class:`~hbmfric.CostWarning`)
COST_WARNING_SECONDS = 60.0


def hill_seconds(point_orders) -> float:
    """Rough CPU seconds of Hill's eigenvalue solves: ``point_orders`` is an
    iterable of ``(points, block_orders)`` pairs (a level's points and the
    orders of its Hill blocks); each block costs one eigenvalue solve of its
    companion matrix (order ``2 g``) per point."""
    return float(
        sum(
            k * sum(EIGVALS_SECONDS * (2.0 * g) ** 3 for g in orders)
            for k, orders in point_orders
        )
    )


def _warn_cost(levels: list, n_dof: int, perturbation_harmonics) -> None:
    """Warn (:class:`~hbmfric.CostWarning`) before Hill's eigenvalues at
    every point of ``levels`` when they would take more than
    :data:`COST_WARNING_SECONDS`, with the time a smaller perturbation
    basis would take."""
    seconds = hill_seconds((lv.idx.size, [g.size for g in lv.groups]) for lv in levels)
    if seconds <= COST_WARNING_SECONDS:
        return
    n_points = sum(lv.idx.size for lv in levels)
    order = max(lv.n for lv in levels)
    h_top = max(int(lv.harmonic_numbers[-1]) for lv in levels)
    cheaper = ["the points you need only (hbmfric.stability.stability_of_points)"]
    for hp in (31, 15, 7):
        if hp >= h_top or (perturbation_harmonics or h_top) <= hp:
            continue
        seconds_hp = hill_seconds(
            (lv.idx.size, [n_dof * (2 * min(hp, int(lv.harmonic_numbers[-1])) + 1)])
            for lv in levels
        )
        if seconds_hp <= 2.0 * COST_WARNING_SECONDS or hp == 7:
            cheaper.insert(
                0,
                f"perturbation_harmonics={hp} (about {_duration(seconds_hp)}; a "
                "truncated perturbation basis, less accurate: docs/stability.md)",
            )
            break
    warnings.warn(
        f"Hill's stability at {n_points} points, Jacobians of order up to "
        f"{order} ({n_dof} DOFs, H up to {h_top}): about {_duration(seconds)} "
        f"of eigenvalue solves (a rough estimate). Cheaper: {', or '.join(cheaper)}",
        CostWarning,
        stacklevel=3,
    )


def _duration(seconds: float) -> str:
    """``seconds`` as a rounded duration for a message."""
    if seconds < 90.0:
        return f"{seconds:.0f} s"
    if seconds < 5400.0:
        return f"{seconds / 60.0:.0f} minutes"
    return f"{seconds / 3600.0:.1f} hours"


def _has_dahl(system) -> bool:
    """Whether a contact of ``system`` is a modified Dahl law."""
    from .kernels.laws.updates import DAHL
    from .systems.protocol import check_system

    return any(c[0].code == DAHL for c in check_system(system).contacts)


def _automatic_method(system, n_dof: int) -> str:
    """``"monodromy"`` for contacts with memory on several DOFs, and for a
    modified Dahl law on any number of DOFs, when the time-domain
    monodromy can be formed, else ``"hill"`` (with an
    :class:`~hbmfric.AccuracyWarning` when Hill's verdicts are then
    approximate).

    Hill's ``λ``-independent ``∂F/∂X`` leaves out the memory of the law.
    For Jenkins on one DOF its verdicts are those of the monodromy (by
    proof where the branch is symmetric, ``docs/stability.md``); for the
    modified Dahl law they were not (stop 33, m 1, c 0.01, k 1): with
    ``ModifiedDahl(beta=1, upper=(5, 1), lower=(5, -1))``, whose loops give
    energy, Hill called the 30 points of F = 0.5 above 3.9 rad/s stable
    where the monodromy reads 1.08-1.14 and time integration from the orbit
    leaves it 100-4000-fold; with the dissipating ``ModifiedDahl(beta=1,
    exponent=2, upper=(4, 2.2), lower=(1, -1))`` Hill called F = 2,
    4.6 rad/s stable (|μ| 0.993) where the monodromy reads 1.10 and time
    integration from the orbit grows 7.7-fold in 1000 periods."""
    from .kernels.laws.updates import CUBIC, DAHL, JENKINS
    from .systems.protocol import check_system

    contacts = check_system(system).contacts
    dahl = any(c[0].code == DAHL for c in contacts)
    if n_dof <= 1 and not dahl:
        return "hill"
    memory = [c for c in contacts if c[3] >= 0 or c[0].code != CUBIC]
    if not memory:
        return "hill"
    if all(c[3] < 0 and c[0].code in (JENKINS, DAHL, CUBIC) for c in contacts):
        return "monodromy"
    if dahl:
        warnings.warn(
            "Hill's stability with a modified Dahl law leaves out the law's "
            "memory and can call an unstable orbit stable, and the time-domain "
            "monodromy cannot be formed for this system (a law between two "
            "DOFs, or beside Menq, Iwan, roughness or a 2D element); check a "
            "verdict by time integration (hf.validation.steady_state)",
            AccuracyWarning,
            stacklevel=4,
        )
        return "hill"
    warnings.warn(
        "Hill's stability of a hysteretic contact (Menq, Iwan, roughness over "
        "them, the 2D element) on several DOFs is approximate: its linearisation "
        "of the law is exact only where an exponent crosses zero, and on the paper "
        "beam with a Jenkins tip it read stable slipping points unstable; "
        "check a verdict by time integration (hf.validation.steady_state)",
        AccuracyWarning,
        stacklevel=4,
    )
    return "hill"


#: |μ| up to which a multiplier counts as on the unit circle (a stuck
#: Jenkins contact's slider is neutral: exactly 1)
NEUTRAL_TOLERANCE = 1e-6


def monodromy_multipliers(
    system, force, harmonic_numbers, coefficients, omega, subharmonic=1
) -> np.ndarray:
    """Floquet multipliers of one harmonic-balance solution by the
    time-domain monodromy (:func:`hbmfric.validation.monodromy`, its
    defaults), sorted by decreasing modulus.

    Parameters
    ----------
    system : Oscillator or compatible
    force : float
        Forcing amplitude, N.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (n_dof, n_coef)
        The solution, m.
    omega : float
        Ω of the solution (its fundamental), rad/s.
    subharmonic : int
        Order ``ν``: the map runs over ``ν`` forcing periods of ``ν Ω``.

    Returns
    -------
    ndarray of complex, shape (n_state,)
    """
    from .results import PeriodicSolution
    from .validation.period_map import monodromy

    nu = int(subharmonic or 1)
    # the solution itself as the start: its state at t = 0 and, for a law
    # with memory, the law's state on its hysteresis loop
    solution = PeriodicSolution(
        omega=float(omega),
        force=float(force),
        harmonic_numbers=np.asarray(harmonic_numbers),
        coefficients=np.asarray(coefficients, dtype=np.float64),
        converged=True,
        newton_iterations=0,
        residual_norm=0.0,
        _source={"subharmonic": nu},
    )
    result = monodromy(
        system, solution, force=force, omega=nu * float(omega), periods=nu
    )
    return result.multipliers


#: ``exponents="auto"`` on a monodromy branch that no proof covers: the
#: monodromy at every ``MONODROMY_SPACING``-th point at least
#: (:func:`_monodromy_stability`)
MONODROMY_SPACING = 16
#: ``exponents="auto"`` on an incrementally passive branch (stable by
#: proof, :func:`_incrementally_passive`): the monodromy at every
#: ``PASSIVE_SPACING``-th point, a check of the proof against the numerics
PASSIVE_SPACING = 64
#: ``exponents="auto"`` on a monodromy branch scheduled on Hill's flips:
#: every point between two flips at most this many points apart is
#: computed (a cluster of folds: between two of them a multiplier near 1
#: can leave and re-enter the unit circle with no indicator flip, issue
#: 16, stop 27; the same reach as ``results.FOLD_SNAP``)
FOLD_CLUSTER = 12
#: the indicators of :func:`_hill_flips` (Hill's eigenvalues at every
#: point) are used up to this many unknowns per point (``n_dof (2H + 1)``),
#: where they cost a small share of a monodromy (about 5 ms per point at
#: 62 unknowns against 0.2-0.3 s, growing like the cube); a larger branch
#: that no proof covers computes the monodromy at every point
HILL_FLIPS_MAX_UNKNOWNS = 128
#: relative size (to the largest entry) of the asymmetry of ``M``, ``K``
#: and of the negative eigenvalues of ``(C + Cᵀ)/2`` that
#: :func:`_incrementally_passive` accepts as rounding
PASSIVE_TOLERANCE = 1e-12


def _incrementally_passive(system) -> bool:
    """Whether every periodic solution of ``system`` is stable in the
    monodromy's sense (every ``|μ| <= 1``) by proof: every contact a
    Jenkins element (between two DOFs or to ground), ``M`` and ``K``
    symmetric positive definite, ``(C + Cᵀ)/2`` positive semi-definite
    (asymmetries and negative eigenvalues up to ``PASSIVE_TOLERANCE`` of
    the largest entry, rounding).

    Why (``docs/stability.md``, "Monodromy branches"): for two motions of
    the system under the same forcing, with ``δ`` their difference, the
    energy ``E = ½ δẋᵀ M δẋ + ½ δxᵀ K δx + Σ δf² / (2 kt)`` (``f = kt (w
    - z)`` each contact's force on its relative displacement ``w``, ``z``
    its slider) changes at the rate ``-δẋᵀ C δẋ - Σ δf δż``, and each
    ``δf δż = (f₁ - f₂)(ż₁ - ż₂) >= 0`` since a slider moves only in the
    direction of its force at ``|f| = f_s`` (``ż₁ (f₁ - f₂) >= 0``,
    ``ż₂ (f₂ - f₁) >= 0``). So ``E`` never grows: the period map is
    non-expansive in the norm ``√E`` of the state ``(x, ẋ, f)``, and
    its derivative, the monodromy, has a spectral radius of at most 1.
    """
    from .kernels.laws.updates import JENKINS
    from .systems.protocol import check_system

    data = check_system(system)
    contacts = data.contacts
    if not contacts or any(
        c[0].code != JENKINS or (len(c) > 3 and c[3] >= 0) for c in contacts
    ):
        return False
    M, C, K = data.mass, data.damping, data.stiffness
    if not all(np.all(np.isfinite(A)) for A in (M, C, K)):
        return False

    def symmetric_definite(A, semi: bool) -> bool:
        size = float(np.abs(A).max(initial=0.0))
        if size == 0.0:
            return semi
        if not semi and float(np.abs(A - A.T).max()) > PASSIVE_TOLERANCE * size:
            return False
        low = float(np.linalg.eigvalsh(0.5 * (A + A.T)).min())
        # definite: clear of rounding (a singular K reads ±1e-13 here)
        return (
            low >= -PASSIVE_TOLERANCE * size
            if semi
            else low > 1e3 * (PASSIVE_TOLERANCE * size)
        )

    return (
        symmetric_definite(M, False)
        and symmetric_definite(K, False)
        and symmetric_definite(C, True)
    )


def _hill_flips(
    system,
    force,
    omega,
    harmonic_numbers,
    coefficients,
    point_harmonics,
    n_time,
    aft,
    subharmonic,
    symmetric,
) -> np.ndarray:
    """Where a cheap indicator changes between points ``i - 1`` and ``i``
    (shape (n_points,), bool, ``[0]`` False): the sign of ``det Δ0`` of a
    Hill block (a real multiplier through +1: folds and branch points; a
    sign of 0 flips both sides), or Hill's verdict (its exponents at every
    point: a hint of the period doublings and Neimark–Sacker points, exact
    for memoryless laws and stuck contacts). All True where they cannot
    be formed."""
    n_points = omega.size
    flips = np.zeros(n_points, dtype=bool)
    if n_points < 2:
        return flips
    try:
        problems = _level_problems(
            system, force, point_harmonics, n_time, aft, subharmonic
        )
        levels, level_of, local_of, _ = _build_levels(
            problems,
            omega,
            harmonic_numbers,
            coefficients,
            point_harmonics,
            None,
            symmetric,
            True,
            reflect=False,
        )
        signs = np.ones((n_points, 3), dtype=np.int64)
        for lv_id, lv in enumerate(levels):
            sg = lv.determinant_signs()
            signs[lv.idx, : sg.shape[1]] = sg
            signs[lv.idx, 2] = lv_id
        lam = _exponents_at(levels, level_of, local_of, np.arange(n_points))
        for lv in levels:
            lv.release()
    except (ValueError, np.linalg.LinAlgError):
        flips[1:] = True
        return flips
    hill = lam.real.max(axis=1) < 0.0
    zero = np.any(signs[:, :2] == 0, axis=1)
    flips[1:] = (
        np.any(signs[1:] != signs[:-1], axis=1)
        | zero[1:]
        | zero[:-1]
        | (hill[1:] != hill[:-1])
    )
    return flips


def _monodromy_stability(
    system,
    force,
    omega,
    harmonic_numbers,
    coefficients,
    point_harmonics,
    subharmonic,
    exponents: str = "all",
    flips=None,
) -> Stability:
    """:class:`Stability` from the time-domain monodromy.

    ``exponents="all"`` (or two points or fewer): the monodromy of every
    point. ``"auto"``: of a few points, the others' exponents computed when
    first read (``Stability.computed``):

    * an incrementally passive system (:func:`_incrementally_passive`:
      Jenkins contacts, symmetric definite matrices) is stable at every
      point by proof; the monodromy is computed at the first and last
      points and every ``PASSIVE_SPACING``-th, and if one of them reads
      unstable (the numerics disagree with the proof), at every point;
    * any other of at most ``HILL_FLIPS_MAX_UNKNOWNS`` unknowns per point
      (else every point): the points of :func:`_sparse_schedule` with
      ``MONODROMY_SPACING`` and the indicators ``flips()`` (a callable
      returning the flips of :func:`_hill_flips`): both ends of each flip,
      the anchors, and a bisection between computed points of different
      verdicts. What it can miss is an even number of changes between two
      computed points with no indicator flip between them.
    """
    start = time.perf_counter()
    n = omega.size
    rows: dict[int, np.ndarray] = {}
    doubts: dict[int, str] = {}

    def solve(where) -> None:
        for i in (int(j) for j in where):
            if i not in rows:
                # the monodromy's doubts about its start, gathered: one
                # warning per call, not one per point
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always", AccuracyWarning)
                    rows[i] = np.asarray(
                        monodromy_multipliers(
                            system,
                            force,
                            harmonic_numbers,
                            coefficients[i],
                            float(omega[i]),
                            subharmonic,
                        ),
                        dtype=complex,
                    )
                for w in caught:
                    if issubclass(w.category, AccuracyWarning):
                        doubts.setdefault(i, str(w.message))
                    else:
                        warnings.warn_explicit(
                            w.message, w.category, w.filename, w.lineno
                        )

    def stable_at(where) -> np.ndarray:
        solve(where)
        return np.array(
            [
                np.abs(rows[int(i)]).max(initial=0.0) <= 1.0 + NEUTRAL_TOLERANCE
                for i in where
            ],
            dtype=bool,
        )

    computed = np.ones(n, dtype=bool)
    stable = None
    if exponents == "auto" and n > 2:
        if _incrementally_passive(system):
            anchors = np.zeros(n, dtype=bool)
            anchors[::PASSIVE_SPACING] = True
            anchors[[0, n - 1]] = True
            where = np.flatnonzero(anchors)
            if stable_at(where).all():
                computed, stable = anchors, np.ones(n, dtype=bool)
        elif (
            flips is not None
            and coefficients.shape[1] * (2 * int(np.max(point_harmonics)) + 1)
            <= HILL_FLIPS_MAX_UNKNOWNS
        ):
            computed, stable = _sparse_schedule(
                n, flips(), stable_at, MONODROMY_SPACING, FOLD_CLUSTER
            )
    if stable is None:
        computed = np.ones(n, dtype=bool)
        stable = stable_at(np.arange(n))

    reported: set[int] = set()

    def report() -> None:
        fresh = sorted(set(doubts) - reported)
        if not fresh:
            return
        reported.update(fresh)
        w = omega[fresh]
        warnings.warn(
            f"the monodromy doubted its start at {len(fresh)} of the {n} points "
            f"({w.min():g}-{w.max():g} rad/s); at {w[0]:g} rad/s: "
            f"{doubts[fresh[0]]}",
            AccuracyWarning,
            stacklevel=5,
        )

    def exponents_of(where: np.ndarray):
        solve(where)
        report()
        mu = np.array([rows[int(i)] for i in where], dtype=complex)
        mu = mu.reshape(where.size, -1)
        w = omega[where]
        period = 2.0 * np.pi / w  # the map's duration: ν forcing periods
        # a multiplier exactly 0 (a slipping Jenkins element forgets its
        # state over the period) has the exponent -inf + 0j: the complex
        # division read log(0) / T as -inf + nan j, with a RuntimeWarning
        zero = mu == 0
        lam = np.log(np.where(zero, 1.0, mu)) / period[:, None]
        lam[zero] = -np.inf
        lam = lam.real + 1j * (lam.imag - w[:, None] * np.round(lam.imag / w[:, None]))
        order = np.argsort(-lam.real, axis=1, kind="stable")
        return (
            np.take_along_axis(lam, order, axis=1),
            np.take_along_axis(mu, order, axis=1),
        )

    report()
    done = np.flatnonzero(computed)
    width = rows[int(done[0])].size if done.size else 0
    lam = np.full((n, width), np.nan + 0j)
    mu = np.full((n, width), np.nan + 0j)
    if done.size:
        lam[done], mu[done] = exponents_of(done)
    fill = None
    if not computed.all():
        fill = exponents_of
    return Stability(
        exponents=lam,
        multipliers=mu,
        stable=stable,
        max_real=lam.real.max(axis=1) if width else np.zeros(n),
        omega=omega.copy(),
        harmonics=np.asarray(point_harmonics, dtype=np.int64).copy(),
        elapsed=time.perf_counter() - start,
        criterion="monodromy",
        computed=computed.copy(),
        fill=fill,
    )
