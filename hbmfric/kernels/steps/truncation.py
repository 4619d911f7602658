"""Truncation-error estimate of a harmonic-balance solution: the first-order
change of the response when more harmonics are admitted, measured on one
output, a linear combination of the DOFs' displacements and velocities
(the system's ``output_weights``; by default the contact DOF).

Used by the adaptive-harmonics continuation
(:mod:`hbmfric.continuation.adaptive`).
"""

import numpy as np
from numba.extending import overload

from ..._jit import jit
from ..linalg.blocks import block_work, gmres_pattern
from ..linalg.krylov import (
    GMRES_CONVERGED,
    REUSE_FACTORISATIONS,
    REUSE_FALLBACKS,
    REUSE_PRODUCTS,
    REUSE_SOLVES,
    REUSE_TOL,
)
from ..linalg.lu import lu_factor, lu_solve, solve_inplace
from ..residuals.dispatch import _on_coordinates
from ..residuals.hbm import JIT_OPTIONS
from ..residuals.pointer import call_residual

#: GMRES iterations at most of the probe solve (:func:`probe_solve`)
PROBE_KRYLOV = 60


#: pivot columns per panel of :func:`probe_factor` (their updates of the
#: trailing rows are applied in one pass over each row; the fused pass is
#: written for four)
PANEL = 4


@jit
def probe_factor(A, piv):
    """LU factorisation with partial pivoting, in place: the factors and
    pivots of :func:`hbmfric.kernels.linalg.lu.lu_factor` bit for bit, in
    about half its time from order 64 (the probe systems: orders 46-90).

    The same eliminations, grouped: the ``PANEL`` pivot columns of a
    panel are eliminated first (pivot search and row swaps as in
    ``lu_factor``), then the panel's rows of ``U`` right of it, then each
    trailing row takes the panel's ``PANEL`` updates in one pass, each
    entry in pivot order. Every entry sees the same operations in the same
    order as in ``lu_factor`` (a multiplier that is zero skips its update
    there and here), so the factors are the same to the last bit; the
    contiguous inner loops vectorise, each trailing entry is read and
    written once per panel instead of once per pivot, and two trailing
    rows share each pass over the panel's rows of ``U`` (``lu_factor``:
    176-182 µs at order 90, 68-69 at 64, 28 at 46; this: 75 / 34 / 18,
    load 5-10; no gain below order 33, slower below 23).

    Parameters
    ----------
    A : ndarray, shape (m, m), C-contiguous
        In: the matrix. Out: ``L`` (unit diagonal, below) and ``U``.
    piv : ndarray of int64, shape (m,)
        Out: row ``k`` was swapped with row ``piv[k]`` at step ``k``.

    Returns
    -------
    bool
        False if a pivot is zero or not finite.
    """
    m = A.shape[0]
    if not A.flags.c_contiguous:
        return lu_factor(A, piv)
    flat = A.reshape(m * m)
    big_all = 0.0
    for i in range(m * m):
        a = abs(flat[i])
        if not a <= big_all:
            big_all = a
    if not np.isfinite(big_all):
        return False
    tiny = 1e-300 + big_all * 1e-15
    for k0 in range(0, m, PANEL):
        k1 = min(k0 + PANEL, m)  # the panel: pivot columns k0 .. k1 - 1
        for k in range(k0, k1):
            p = k
            big = abs(flat[k * m + k])
            for i in range(k + 1, m):
                a = abs(flat[i * m + k])
                if a > big:
                    big = a
                    p = i
            piv[k] = p
            if not big > tiny:
                return False
            if p != k:
                # rows k and p carry the same updates (those of the pivots
                # before k on the panel's columns, before k0 elsewhere)
                rk = flat[k * m : (k + 1) * m]
                rp = flat[p * m : (p + 1) * m]
                for j in range(m):
                    t = rk[j]
                    rk[j] = rp[j]
                    rp[j] = t
            inv = 1.0 / flat[k * m + k]
            for i in range(k + 1, m):
                f = flat[i * m + k] * inv
                flat[i * m + k] = f
                if f != 0.0:
                    for j in range(k + 1, k1):
                        flat[i * m + j] -= f * flat[k * m + j]
        if k1 == m:
            break
        w = m - k1
        # the panel's rows of U right of the panel
        for k in range(k0 + 1, k1):
            a = flat[k * m + k1 : (k + 1) * m]
            for kk in range(k0, k):
                f = flat[k * m + kk]
                if f != 0.0:
                    u = flat[kk * m + k1 : (kk + 1) * m]
                    for j in range(w):
                        a[j] -= f * u[j]
        # the trailing rows: the panel's updates, in pivot order per entry;
        # two rows per pass where all eight multipliers are nonzero (each
        # row of U read once for both), else one row per pass
        full = k1 - k0 == PANEL
        u0 = flat[k0 * m + k1 : (k0 + 1) * m]
        u1 = flat[(k0 + 1) * m + k1 : (k0 + 2) * m] if full else u0
        u2 = flat[(k0 + 2) * m + k1 : (k0 + 3) * m] if full else u0
        u3 = flat[(k0 + 3) * m + k1 : (k0 + 4) * m] if full else u0
        i = k1
        while i < m:
            a = flat[i * m + k1 : (i + 1) * m]
            if full:
                f0 = flat[i * m + k0]
                f1 = flat[i * m + k0 + 1]
                f2 = flat[i * m + k0 + 2]
                f3 = flat[i * m + k0 + 3]
                nonzero = f0 != 0.0 and f1 != 0.0 and f2 != 0.0 and f3 != 0.0
                if nonzero and i + 1 < m:
                    g0 = flat[(i + 1) * m + k0]
                    g1 = flat[(i + 1) * m + k0 + 1]
                    g2 = flat[(i + 1) * m + k0 + 2]
                    g3 = flat[(i + 1) * m + k0 + 3]
                    if g0 != 0.0 and g1 != 0.0 and g2 != 0.0 and g3 != 0.0:
                        c = flat[(i + 1) * m + k1 : (i + 2) * m]
                        for j in range(w):
                            x0 = u0[j]
                            x1 = u1[j]
                            x2 = u2[j]
                            x3 = u3[j]
                            v = a[j] - f0 * x0
                            v = v - f1 * x1
                            v = v - f2 * x2
                            a[j] = v - f3 * x3
                            q = c[j] - g0 * x0
                            q = q - g1 * x1
                            q = q - g2 * x2
                            c[j] = q - g3 * x3
                        i += 2
                        continue
                if nonzero:
                    for j in range(w):
                        v = a[j] - f0 * u0[j]
                        v = v - f1 * u1[j]
                        v = v - f2 * u2[j]
                        a[j] = v - f3 * u3[j]
                    i += 1
                    continue
            for kk in range(k0, k1):
                f = flat[i * m + kk]
                if f != 0.0:
                    u = flat[kk * m + k1 : (kk + 1) * m]
                    for j in range(w):
                        a[j] -= f * u[j]
            i += 1
    return True


@jit
def probe_dense_solve(A, b):
    """:func:`~hbmfric.kernels.linalg.lu.solve_inplace` with the factors
    of :func:`probe_factor` (the same ``x`` bit for bit)."""
    piv = np.empty(b.size, dtype=np.int64)
    if not probe_factor(A, piv):
        return False
    lu_solve(A, piv, b)
    return np.isfinite(b).all()


@jit
def probe_square(J, A):
    """``A = J[:, :n]`` (the probe system's matrix, shape (n, n), from the
    residual's Jacobian, shape (n, n + 1))."""
    n = A.shape[0]
    for i in range(n):
        for j in range(n):
            A[i, j] = J[i, j]


def probe_solve(problem, J, A, b, n_dof, n_coef, first):
    """Solve the probe level's Newton system ``J[:, :n] x = b`` of
    :func:`truncation_change` (``b`` holds ``x`` on return; ``J`` is not
    modified, ``A``, shape (n, n), is work space and may be overwritten);
    False if singular or not finite. Callable from jitted code only.

    Dispatched at compile time on the type of ``problem``: a condensed
    problem large enough to carry kept-factor work arrays (``solver``,
    several contacts, see :data:`hbmfric.condensation.REUSE_MIN_UNKNOWNS`)
    solves by GMRES preconditioned by the harmonic blocks
    (:func:`hbmfric.kernels.linalg.blocks.gmres_pattern`: the blocks and
    the nonzeros read from ``J`` at the places of its pattern, no dense
    copy; ``O(m²)`` per iteration instead of the ``O(m³)`` LU, 9-20
    iterations on the lap joint), falling back to the dense LU of ``J``'s
    copy in ``A`` if GMRES does not converge; its counters
    (``problem.solver[3]``, :mod:`hbmfric.kernels.linalg.krylov`) record
    GMRES solves, products, fallbacks and the dense factorisations of the
    fallbacks, and its relative residual (2-norm) is
    ``state[REUSE_TOL]``. Any other problem factors the copy in ``A``
    (:func:`probe_dense_solve`: the factors of
    :func:`~hbmfric.kernels.linalg.lu.solve_inplace` bit for bit, in about
    half its time at the probe orders).
    """
    raise NotImplementedError("probe_solve is for jit code")


@overload(probe_solve, jit_options=JIT_OPTIONS)
def _probe_solve(problem, J, A, b, n_dof, n_coef, first):
    # one contact to ground carries no solver arrays (order 0): dense
    if _on_coordinates(problem):

        def condensed(problem, J, A, b, n_dof, n_coef, first):
            state = problem.solver[3]
            m = b.size
            if problem.solver[0].shape[0] > 0 and n_dof * n_coef == m:
                arrays = block_work(n_dof, n_coef, first, m, np.int64(PROBE_KRYLOV))
                x = np.empty(m)
                status, products = gmres_pattern(
                    J, b, x, n_dof, n_coef, first, state[REUSE_TOL], arrays
                )
                state[REUSE_PRODUCTS] += products
                if status == GMRES_CONVERGED:
                    state[REUSE_SOLVES] += 1.0
                    for i in range(m):
                        b[i] = x[i]
                    return True
                state[REUSE_FALLBACKS] += 1.0
                state[REUSE_FACTORISATIONS] += 1.0
            probe_square(J, A)
            return solve_inplace(A, b)

        return condensed

    def full(problem, J, A, b, n_dof, n_coef, first):
        probe_square(J, A)
        return probe_dense_solve(A, b)

    return full


@jit
def output_coefficients(X, base_stride, weights, rates, omega, first, out):
    """Fourier coefficients of the watched output ``sum_d a_d x_d + b_d ẋ_d``.

    Parameters
    ----------
    X : ndarray, shape (n_dof * n_coef (+ 1),)
        Coefficients per DOF (``X[d * base_stride + k]``), m; a trailing
        ``Ω`` is ignored.
    base_stride : int
        ``n_coef``, the columns per DOF.
    weights : ndarray, shape (2, n_dof)
        Displacement weights ``a`` (row 0) and velocity weights ``b`` (row
        1, s) of the output.
    rates : ndarray, shape (n_coef,)
        Harmonic number of each column (0 for the constant).
    omega : float
        Fundamental pulsation of the basis, rad/s.
    first : int
        Column of the first cosine coefficient (1 with a constant, else 0).
    out : ndarray, shape (n_coef,)
        The output's coefficients on return. In the cos/sin basis the pair
        ``(c, s)`` of harmonic ``h`` differentiates to ``h Ω (s, −c)``.
    """
    n_coef = base_stride
    n_dof = weights.shape[1]
    for k in range(n_coef):
        out[k] = 0.0
    for d in range(n_dof):
        a = weights[0, d]
        if a != 0.0:
            for k in range(n_coef):
                out[k] += a * X[d * n_coef + k]
        b = weights[1, d]
        if b != 0.0:
            for k in range(first, n_coef - 1, 2):
                w = b * rates[k] * omega
                c = X[d * n_coef + k]
                s = X[d * n_coef + k + 1]
                out[k] += w * s
                out[k + 1] -= w * c


@jit
def output_amplitude(y, weights, rates, column):
    """Amplitude of one harmonic of the watched output at the point ``y``.

    Parameters
    ----------
    y : ndarray, shape (n_dof * n_coef + 1,)
        ``[X, Ω]``.
    weights : ndarray, shape (2, n_dof)
        Displacement and velocity weights (:func:`output_coefficients`).
    rates : ndarray, shape (n_coef_rates,)
        Harmonic number per column (of this basis or of a larger one whose
        harmonics extend it: the columns coincide).
    column : int
        Column of the harmonic's cosine coefficient within a DOF.

    Returns
    -------
    float
        ``sqrt(c² + s²)`` of the output's coefficients of that harmonic.
    """
    n_dof = weights.shape[1]
    n_coef = (y.size - 1) // n_dof
    w = rates[column] * y[y.size - 1]
    c = 0.0
    s = 0.0
    for d in range(n_dof):
        i = d * n_coef + column
        a = weights[0, d]
        if a != 0.0:
            c += a * y[i]
            s += a * y[i + 1]
        b = weights[1, d]
        if b != 0.0:
            c += b * w * y[i + 1]
            s -= b * w * y[i]
    return np.hypot(c, s)


@jit
def output_measure(y, weights, rates, first, top, prev, h, prev_weight):
    """Free truncation measure ``H max(|Z_H|, w |Z_K'|) / |Z_1|`` of the
    watched output ``Z`` at the point ``y`` (``K'`` the harmonic below
    ``H``, ``w = (K'/H)^4``).

    Parameters
    ----------
    y : ndarray, shape (n_dof * n_coef + 1,)
        ``[X, Ω]``.
    weights, rates
        As in :func:`output_amplitude`.
    first, top, prev : int
        Columns within a DOF of the first, the highest and the
        second-highest harmonic (``top < 0``: none above the first;
        ``prev < 0``: no ``K' > 1``).
    h : float
        ``H``.
    prev_weight : float
        ``w``.

    Returns
    -------
    float
        inf without a harmonic above the first; 0 for an output at rest.
    """
    if top < 0:
        return np.inf
    a1 = output_amplitude(y, weights, rates, first)
    t = output_amplitude(y, weights, rates, top)
    if prev >= 0:
        a = prev_weight * output_amplitude(y, weights, rates, prev)
        if a > t:
            t = a
    if a1 == 0.0:
        return 0.0 if t == 0.0 else np.inf
    return h * t / a1


@jit
def series_at(z, rates, first, theta):
    """Value and first two ``θ``-derivatives of the series ``z`` at one
    angle.

    Parameters
    ----------
    z : ndarray, shape (n_coef,)
        Coefficients ``[Z0, Zc1, Zs1, ...]`` (``Z0`` only if ``first = 1``).
    rates : ndarray, shape (n_coef_rates,)
        Harmonic number of each column (``n_coef_rates >= n_coef``).
    first : int
        Column of the first cosine coefficient (1 with a constant, else 0).
    theta : float
        Angle ``Ω t``, rad.

    Returns
    -------
    value, first_derivative, second_derivative : float
        Units of ``z``, per rad and per rad².
    """
    value = z[0] if first == 1 else 0.0
    d1 = 0.0
    d2 = 0.0
    for col in range(first, z.size - 1, 2):
        k = rates[col]
        ck = np.cos(k * theta)
        sk = np.sin(k * theta)
        a = z[col]
        b = z[col + 1]
        value += a * ck + b * sk
        d1 += k * (b * ck - a * sk)
        d2 -= k * k * (a * ck + b * sk)
    return value, d1, d2


#: relative rounding allowed in the comparison of two values of a series
#: (:func:`_extreme`), per unit of the sum of its coefficients' magnitudes
ROUNDING = 1e-12


@jit
def _extreme(z, rates, first, theta0, spacing, sign):
    """Angle of the maximum (``sign = 1``) or minimum (``-1``) of the series
    ``z`` near the sample angle ``theta0``: Newton on ``z' = 0``, each step
    at most one sample ``spacing`` and the whole move too. Converged on the
    root of ``z'`` (to rounding: the values alone place a flat extreme only
    to the square root of it, which moved the change read there by 4e-7
    between two equivalent coordinate systems); ``theta0`` if Newton
    leaves the interval, meets the wrong curvature or ends below the
    sample by more than rounding (``ROUNDING`` times the sum of the
    coefficients' magnitudes: a test of the values alone was decided by
    rounding where the extreme lies within about 1e-7 rad of the sample,
    and the instant returned then moved by up to 1.4e-8 rad when all the
    coefficients were scaled, 1e-15 to 1e15)."""
    magnitude = 0.0
    for col in range(z.size):
        magnitude += abs(z[col])
    v0, d1, d2 = series_at(z, rates, first, theta0)
    v = v0
    theta = theta0
    for _ in range(12):
        if not sign * d2 < 0.0:
            return theta0  # not curved towards an extreme here
        step = -d1 / d2
        if step > spacing:
            step = spacing
        elif step < -spacing:
            step = -spacing
        theta += step
        if abs(theta - theta0) > spacing:
            return theta0
        v, d1, d2 = series_at(z, rates, first, theta)
        if abs(step) < 1e-13:
            break
    if sign * (v - v0) < -ROUNDING * magnitude:
        return theta0
    return theta


@jit
def _sample_extremes(synthesis, z):
    """Rows of the largest and of the smallest sample ``synthesis[s, :m] @ z``
    (``m = z.size``; the first row of each on ties), the sums of four rows
    side by side (each in the same order as one row alone: the same bits;
    the sums are chains of dependent additions)."""
    n_samples = synthesis.shape[0]
    m = z.size
    x_max = -np.inf
    x_min = np.inf
    s_max = 0
    s_min = 0
    s = 0
    while s < n_samples:
        rows = min(4, n_samples - s)
        x0 = 0.0
        x1 = 0.0
        x2 = 0.0
        x3 = 0.0
        if rows == 4:
            for k in range(m):
                zk = z[k]
                x0 += synthesis[s, k] * zk
                x1 += synthesis[s + 1, k] * zk
                x2 += synthesis[s + 2, k] * zk
                x3 += synthesis[s + 3, k] * zk
        else:
            for k in range(m):
                x0 += synthesis[s, k] * z[k]
            if rows > 1:
                for k in range(m):
                    x1 += synthesis[s + 1, k] * z[k]
            if rows > 2:
                for k in range(m):
                    x2 += synthesis[s + 2, k] * z[k]
        for r in range(rows):
            xs = x0 if r == 0 else (x1 if r == 1 else (x2 if r == 2 else x3))
            if xs > x_max:
                x_max = xs
                s_max = s + r
            if xs < x_min:
                x_min = xs
                s_min = s + r
        s += rows
    return s_max, s_min


@jit
def truncation_change(
    x, problem, residual_at, weights, rates, first, synthesis, y, R, J, A, dX
):
    """Relative change of the first-harmonic amplitude and of half the
    peak-to-peak value of the watched output when a solution gains
    harmonics.

    ``x`` is a solution of a smaller basis; zero-padded into the basis of
    ``problem`` (whose harmonics extend those of ``x``), one Newton step at
    fixed Ω in that basis gives the change ``dX`` to first order. The
    output is a linear combination of the DOFs' displacements and
    velocities (``weights``; by default the contact DOF's displacement,
    where the higher harmonics are made). The change of an extreme of the
    output is its change at the instant of the extreme (located on the
    samples of ``synthesis``).

    Parameters
    ----------
    x : ndarray, shape (n_dof * n_coef_small + 1,)
        ``[X, Ω]`` in the smaller basis.
    problem : tuple or CondensedProblem
        Kernel problem of the larger basis
        (:func:`hbmfric.kernels.residuals.dispatch.residual`).
    residual_at : int
        Address of the residual compiled for ``problem``'s type
        (:func:`hbmfric.kernels.residuals.pointer.residual_address`).
    weights : ndarray, shape (2, n_dof)
        Displacement (row 0) and velocity (row 1, s) weights of the output
        per DOF among the unknowns (``n = n_dof * n_coef``).
    rates : ndarray, shape (n_coef,)
        Harmonic number of each column of the larger basis.
    first : int
        Column of the first-harmonic cosine coefficient within a DOF.
    synthesis : ndarray, shape (n_samples, n_coef)
        Basis functions at ``n_samples`` instants of the period.
    y, R, J, A, dX : ndarray
        Work arrays, shapes (n + 1,), (n,), (n, n + 1), (n, n), (n,); ``y``
        holds the padded point on return.

    Returns
    -------
    float
        The larger of the two relative changes (0 for an output at rest);
        inf if the residual or the solve fails.
    """
    n = y.size - 1
    n_dof = weights.shape[1]
    n_coef = n // n_dof
    n_small = (x.size - 1) // n_dof
    for d in range(n_dof):
        for k in range(n_coef):
            y[d * n_coef + k] = x[d * n_small + k] if k < n_small else 0.0
    y[n] = x[x.size - 1]
    status = call_residual(residual_at, y, problem, R, J)
    if status < 0:
        return np.inf
    for i in range(n):
        dX[i] = -R[i]
    if not probe_solve(problem, J, A, dX, n_dof, n_coef, first):
        return np.inf
    z = np.empty(n_coef)
    dz = np.empty(n_coef)
    output_coefficients(y, n_coef, weights, rates, y[n], first, z)
    output_coefficients(dX, n_coef, weights, rates, y[n], first, dz)
    c = first
    a1 = np.hypot(z[c], z[c + 1])
    if a1 == 0.0:
        return 0.0
    a1_new = np.hypot(z[c] + dz[c], z[c + 1] + dz[c + 1])
    worst = abs(a1_new - a1) / a1
    # the extremes of the output: the nearest samples of ``synthesis``,
    # then the instants themselves (Newton on the series). The change is
    # read at the instant: ``dz`` carries harmonics up to the larger basis,
    # which turn within one sample spacing (64 samples at 2 H = 15: up to
    # 0.7 rad), so read at the sample it swung with the extreme's place
    # between the samples (belt tensioner at 2 N, H = 7, 40-42 Hz: 2e-6 to
    # 1.2e-4 every 4 points where the true error rose smoothly 2.6e-5 to
    # 4.4e-5)
    # ``z`` is the padded point's output: its columns from ``n_small`` on
    # are zero, and a zero term leaves a sum as it is (but for the sign of
    # a zero sum, which no comparison below sees), so the series of ``z``
    # are summed over its first ``n_small`` columns only
    zs = z[:n_small]
    s_max, s_min = _sample_extremes(synthesis, zs)
    spacing = 2.0 * np.pi / synthesis.shape[0]
    t_max = _extreme(
        zs,
        rates,
        first,
        np.arctan2(synthesis[s_max, c + 1], synthesis[s_max, c]),
        spacing,
        1.0,
    )
    t_min = _extreme(
        zs,
        rates,
        first,
        np.arctan2(synthesis[s_min, c + 1], synthesis[s_min, c]),
        spacing,
        -1.0,
    )
    x_max = series_at(zs, rates, first, t_max)[0]
    x_min = series_at(zs, rates, first, t_min)[0]
    dx_max = series_at(dz, rates, first, t_max)[0]
    dx_min = series_at(dz, rates, first, t_min)[0]
    hpp = 0.5 * (x_max - x_min)
    e = abs(0.5 * (dx_max - dx_min)) / hpp
    if e > worst:
        worst = e
    if not np.isfinite(worst):
        return np.inf
    return worst


@jit
def truncation_changes(
    points,
    rows,
    problem,
    residual_at,
    weights,
    rates,
    first,
    synthesis,
    y,
    R,
    J,
    A,
    dX,
    out,
):
    """:func:`truncation_change` of several points of one branch in one
    call (one dispatch instead of one per point).

    Parameters
    ----------
    points : ndarray, shape (n_points, n_dof * n_coef_small + 1)
        ``[X, Ω]`` per point in the smaller basis.
    rows : ndarray of int64, shape (n_rows,)
        The points to evaluate.
    problem, residual_at, weights, rates, first, synthesis, y, R, J, A, dX
        As in :func:`truncation_change`.
    out : ndarray, shape (n_rows,)
        The change of each point of ``rows`` on return.
    """
    for q in range(rows.size):
        out[q] = truncation_change(
            points[rows[q]],
            problem,
            residual_at,
            weights,
            rates,
            first,
            synthesis,
            y,
            R,
            J,
            A,
            dX,
        )


#: calibrations of carried estimates over the tolerance that confirm it
#: before the rest keep their carried value
MAX_CONFIRMED = 8


@jit
def branch_truncation(
    points,
    known,
    stretch,
    columns,
    weights,
    every,
    n_worst,
    tolerance,
    max_confirmed,
    problem,
    residual_at,
    output,
    rates,
    first,
    synthesis,
    y,
    R,
    J,
    A,
    dX,
    errors,
):
    """Truncation estimate of every point of a fixed-``H`` branch
    (:func:`hbmfric.continuation.accuracy.truncation_errors`, whose rule
    this is, compiled in one call).

    Parameters
    ----------
    points : ndarray, shape (n_points, n + 1)
        ``[X, Ω]`` per point in the branch's basis.
    known : ndarray, shape (n_points,)
        Estimates already calibrated (by the adaptive run, with the same
        probe level), NaN elsewhere: such a point counts as calibrated
        with that value (no second calibration).
    stretch : ndarray of int64, shape (n_points,)
        Label of the stretch of consecutive branch points each point
        belongs to (non-decreasing). A ratio is carried only within a
        stretch: the points of one level of an adaptive run lie on
        separate stretches of the branch, where the ratio differs up to
        100-fold (the belt tensioner at 5 N: 0.014 at 5 Hz, 0.23-0.47 at
        8.3-8.5 Hz, 0.004 at 15 Hz, all at H = 11).
    columns : ndarray of int64, shape (3,)
        Columns within a DOF of the cosine coefficient of the first, the
        highest and the second-highest harmonic (-1: none), for the free
        measure of the output (:func:`output_measure`).
    weights : ndarray, shape (5,)
        ``H``, the weight ``(K'/H)^4`` of the second-highest harmonic, the
        free measure under which a point is linear, the estimate per change
        (``CHANGE_FACTOR``) and the least carried ratio (``CARRY_FLOOR``).
    every, n_worst : int
        Calibrate every ``every``-th non-linear point of each stretch
        (counted from the last ``known`` point, if one came since: the
        adaptive run's own calibrations, up to 16 points apart, took a
        second calibration between them every 8 points on the plain grid,
        and now one), the first and last one of each stretch and the
        ``n_worst`` of largest free measure.
    tolerance : float
        A point whose carried estimate exceeds it is calibrated too
        (``inf``: none), until ``max_confirmed`` calibrations have exceeded
        it (the branch is then known to miss it; the rest keep their
        carried estimate, a bound on the cost of a branch far above it).
    max_confirmed : int
        That bound (``MAX_CONFIRMED`` for a fixed-``H`` branch; the final
        pass of an adaptive run, which solves every point over the
        tolerance again, calibrates them all: a carried estimate can be
        far above the fresh one).
    problem, residual_at, output, rates, first, synthesis, y, R, J, A, dX
        The probe level, as in :func:`truncation_change` (``output`` is
        its ``weights``).
    errors : ndarray, shape (n_points,)
        The estimate of each point on return (0 for a linear point).
    """
    n_points = points.shape[0]
    c1, ct, cp = columns[0], columns[1], columns[2]
    h, w, linear, factor, floor = (
        weights[0],
        weights[1],
        weights[2],
        weights[3],
        weights[4],
    )
    measure = np.empty(n_points)
    nonlinear = np.empty(n_points, dtype=np.int64)
    n_nl = 0
    for i in range(n_points):
        m = output_measure(points[i], output, rates, c1, ct, cp, h, w)
        measure[i] = m
        errors[i] = 0.0
        if m > linear:
            nonlinear[n_nl] = i
            n_nl += 1
    if n_nl == 0:
        return
    chosen = np.zeros(n_points, dtype=np.bool_)
    count = 0  # non-linear points since the stretch began
    for q in range(n_nl):
        i = nonlinear[q]
        if q == 0 or stretch[i] != stretch[nonlinear[q - 1]]:
            count = 0
            if q > 0:
                chosen[nonlinear[q - 1]] = True  # last of the stretch before
        if np.isfinite(known[i]):
            # a calibration already made: the count starts again from it
            # (no two calibrated points further apart than ``every``, as
            # on the plain grid)
            count = 0
        if count % every == 0:
            chosen[i] = True
        count += 1
    chosen[nonlinear[n_nl - 1]] = True
    picked = np.zeros(n_points, dtype=np.bool_)
    for _ in range(min(n_worst, n_nl)):
        best = -1
        for q in range(n_nl):
            i = nonlinear[q]
            if not picked[i] and (best < 0 or measure[i] > measure[best]):
                best = i
        picked[best] = True
        chosen[best] = True
    ratio = np.zeros(n_points)
    for q in range(n_nl):
        i = nonlinear[q]
        if np.isfinite(known[i]):
            chosen[i] = True
            errors[i] = known[i]
        elif chosen[i]:
            change = truncation_change(
                points[i],
                problem,
                residual_at,
                output,
                rates,
                first,
                synthesis,
                y,
                R,
                J,
                A,
                dX,
            )
            errors[i] = factor * change
        if chosen[i]:
            ratio[i] = max(errors[i] / max(measure[i], 1e-300), floor)
    # carried: the larger ratio of the calibrated neighbours on either side
    # within the stretch (its first and last non-linear points are
    # calibrated, so both exist)
    left = -1
    confirmed = 0
    for q in range(n_nl):
        i = nonlinear[q]
        if chosen[i]:
            left = i
            continue
        right = -1
        for r in range(q + 1, n_nl):
            if chosen[nonlinear[r]]:
                right = nonlinear[r]
                break
        if left >= 0 and stretch[left] != stretch[i]:
            left = -1
        if right >= 0 and stretch[right] != stretch[i]:
            right = -1
        carried = 0.0
        if left >= 0:
            carried = ratio[left]
        if right >= 0 and ratio[right] > carried:
            carried = ratio[right]
        errors[i] = carried * measure[i]
        if errors[i] > tolerance and confirmed < max_confirmed:
            change = truncation_change(
                points[i],
                problem,
                residual_at,
                output,
                rates,
                first,
                synthesis,
                y,
                R,
                J,
                A,
                dX,
            )
            errors[i] = factor * change
            if errors[i] > tolerance:
                confirmed += 1
