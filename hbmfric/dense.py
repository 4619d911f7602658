"""Dense output of an FRF branch: the branch between its points.

Every traced piece of a :class:`~hbmfric.Branch` is a continuous path through
the points ``y_i = (coefficients_i, Ω_i)``. Between two consecutive points of
one piece the path is the cubic Hermite interpolant in arc length ``s``

    y(s) = h00(u) y_i + h10(u) L_i t_i + h01(u) y_{i+1} + h11(u) L_i t_{i+1},
    u = (s - s_i) / L_i,

with ``t_i = dy/ds`` the unit tangents and ``L_i`` the arc length of the
interval. Arc length is measured in a scaled space where Ω is divided by the
width of the branch's Ω span and every Fourier coefficient by the largest
coefficient magnitude of the branch (dimensionless, so that both weigh
alike); ``L_i`` is the chord times ``(θ/2) / sin(θ/2)`` with ``θ`` the angle
between the two end tangents (exact for a circular arc).

Tangents come from the branch when it stores them (``Branch.tangents``, the
continuation's own: only their directions are used) and otherwise from finite
differences over the neighbouring points of the same piece in arc length
(derivative of the quartic through the five nearest points; fewer in pieces
of less than five points), which keeps the interpolant fourth order.

Nothing is interpolated across the seam between two pieces (a jump of the
path) or over a gap.

Error estimate
--------------
On each interval the Hermite cubic ``H`` is compared with the cubics ``P``
through four consecutive points holding it (``i - 2 .. i + 1``,
``i - 1 .. i + 2`` and ``i .. i + 3``, shifted inward at the ends of a
piece). Both have an error proportional to the fourth derivative of the
path, with node polynomials ``w_H(s) = (s - s_i)² (s - s_{i+1})²`` and
``w_P(s) = prod_j (s - s_j)``, so that

    error_H(s) ≈ (H - P)(s) · w_H(s) / (w_H(s) - w_P(s)).

This is taken on the measured quantity (an amplitude of one DOF) at fixed
Ω: the vertical distance ``dA - (dA/dΩ) dΩ`` between the two interpolants,
relative to the amplitude, at ``u`` = 1/4, 1/2, 3/4; the estimate is the
largest over ``u`` and stencils, times :data:`SAFETY`. Only stencils through
points of one kind are used where the interval has one: a kind is a
harmonic level, stuck (zero ``truncation_error``) or not, since the branch
has a corner where the contact starts to slip and a small jump where
``harmonics="auto"`` changes level, which a cubic through them would take
for curvature. Where the kind changes between the two points of the
interval (the corner lies inside), the distance between ``H`` and the chord
is a floor of the estimate. In pieces of three points ``P`` is the parabola
(its own error dominates: the difference is taken unscaled), in pieces of
two points the straight chord.

The estimate sees the path's smooth part only: structure below the step
(e.g. the curvature ripple of a sampled Menq AFT, 1e-7 to 1e-6) is part of
the points' discretisation error.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._validate import dof_index
from .signals import half_peak_to_peak, harmonic_amplitude

#: the estimate is this multiple of the asymptotic fourth-order estimate
#: (margin for long intervals outside the asymptotic range: on the paper
#: beam at Fn = 1 N the unscaled estimate was 0.5x the true error on one
#: interval; on closed-form curves it is 0.25-1.2x)
SAFETY = 3.0
#: parameters ``u`` in each interval where the estimate is taken
_ESTIMATE_AT = (0.25, 0.5, 0.75)
#: finite-difference tangents use this many neighbouring points
_FD_POINTS = 5


def _resolve_dof(dof, names: dict, n_dof: int) -> int:
    if dof is None:
        dof = names.get("contact", 0)
    elif isinstance(dof, str):
        if dof not in names:
            raise ValueError(
                f"dof name must be one of {sorted(names)} for this system, got {dof!r}"
            )
        dof = names[dof]
    return dof_index(dof, n_dof)


def _amplitude(harmonic_numbers, X: np.ndarray, harmonic) -> np.ndarray:
    if harmonic is None:
        return half_peak_to_peak(harmonic_numbers, X)
    return harmonic_amplitude(harmonic_numbers, X, harmonic)


@dataclass
class DenseSamples:
    """A branch evaluated between its points (:meth:`hbmfric.Branch.evaluate`).

    Attributes
    ----------
    arclength : ndarray, shape (n_samples,)
        Arc-length parameter of every sample (dimensionless, the scale of
        :attr:`hbmfric.Branch.arclength`); NaN where it was not on the branch.
    omega : ndarray, shape (n_samples,)
        Ω, rad/s (NaN off the branch: beyond its ends or in the jump between
        two pieces).
    coefficients : ndarray, shape (n_samples, n_dof, n_coef)
        Fourier coefficients of every DOF, m (NaN off the branch).
    interval : ndarray of int, shape (n_samples,)
        Index ``i`` of the interval (between points ``i`` and ``i + 1``)
        holding each sample; -1 off the branch.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    dof_names : dict
    tangents : str
        Where the tangents came from: ``"stored"`` (``Branch.tangents``) or
        ``"finite differences"``.
    """

    arclength: np.ndarray
    omega: np.ndarray
    coefficients: np.ndarray
    interval: np.ndarray
    harmonic_numbers: np.ndarray
    dof_names: dict = field(default_factory=dict)
    tangents: str = ""

    def __len__(self) -> int:
        return self.omega.size

    def amplitude(self, harmonic: int | None = None, dof=None) -> np.ndarray:
        """Amplitude at every sample, shape (n_samples,), m (as
        :meth:`hbmfric.Branch.amplitude`; NaN off the branch)."""
        X = self.coefficients[
            :, _resolve_dof(dof, self.dof_names, self.coefficients.shape[1])
        ]
        out = np.full(X.shape[0], np.nan)
        ok = np.all(np.isfinite(X), axis=1)
        if np.any(ok):
            out[ok] = _amplitude(self.harmonic_numbers, X[ok], harmonic)
        return out


class DenseBranch:
    """The Hermite interpolant of one branch (built by :func:`dense`).

    Attributes
    ----------
    s : ndarray, shape (n_points,)
        Arc length of every point (the jump between two pieces counts as
        its chord length, so ``s`` increases along the whole path).
    y : ndarray, shape (n_points, n_dof * n_coef + 1)
        Flattened coefficients and Ω of every point.
    t : ndarray, shape (n_points, n_dof * n_coef + 1)
        Unit tangents ``dy/ds`` (physical units per unit arc length).
    length : ndarray, shape (n_points - 1,)
        Arc length of every interval; NaN across a seam between pieces.
    tangent_source : str
    """

    def __init__(self, branch, tangents=None):
        omega = np.asarray(branch.omega, dtype=float)
        coef = np.asarray(branch.coefficients, dtype=float)
        n = omega.size
        self.n_dof, self.n_coef = coef.shape[1], coef.shape[2]
        self.harmonic_numbers = np.asarray(branch.harmonic_numbers)
        self.dof_names = dict(branch.dof_names)
        self.y = np.concatenate(
            (coef.reshape(n, self.n_dof * self.n_coef), omega[:, None]), axis=1
        )
        span = float(np.ptp(omega)) if n else 0.0
        if not span > 0.0:
            span = max(abs(float(omega[0])), 1.0) if n else 1.0
        cmax = float(np.max(np.abs(coef))) if coef.size else 0.0
        if not cmax > 0.0:
            cmax = 1.0
        self.scale = np.full(self.y.shape[1], cmax)
        self.scale[-1] = span
        self.pieces = [(sl.start, sl.stop) for sl in branch.piece_slices()]
        # kind of every point: its harmonic level, negative where the
        # contact is stuck (a linear point: zero truncation error)
        kind = np.full(n, int(self.harmonic_numbers[-1]) if n else 0, dtype=np.int64)
        if getattr(branch, "point_harmonics", None) is not None:
            kind = np.asarray(branch.point_harmonics, dtype=np.int64).copy()
        te = getattr(branch, "truncation_error", None)
        if te is not None:
            kind = np.where(np.asarray(te) == 0.0, -kind - 1, kind)
        self.kind = kind
        z = self.y / self.scale
        chord = np.linalg.norm(np.diff(z, axis=0), axis=1)
        self.s = np.concatenate(([0.0], np.cumsum(chord)))[:n]
        self.valid = np.zeros(max(n - 1, 0), dtype=bool)  # interval inside a piece
        for a, b in self.pieces:
            self.valid[a : b - 1] = True
        if tangents is not None:
            tz = np.asarray(tangents, dtype=float) / self.scale
            self.tangent_source = "stored"
        else:
            tz = self._fd_tangents(z)
            self.tangent_source = "finite differences"
        norm = np.linalg.norm(tz, axis=1)
        tz = tz / np.where(norm > 0.0, norm, 1.0)[:, None]
        tz = self._orient(z, tz)
        # arc length of each interval from the chord and the turn of the
        # tangents (circular-arc correction)
        cos = np.clip(np.sum(tz[:-1] * tz[1:], axis=1), -1.0, 1.0)
        half = 0.5 * np.arccos(cos)
        with np.errstate(invalid="ignore", divide="ignore"):
            factor = np.where(half > 1e-8, half / np.sin(half), 1.0)
        self.length = np.where(self.valid, chord * np.minimum(factor, 2.0), np.nan)
        self.t = tz * self.scale  # dy/ds, physical units

    # ------------------------------------------------------------------
    def _fd_tangents(self, z: np.ndarray) -> np.ndarray:
        """Tangents in scaled space by differentiating the polynomial
        through the nearest points of the same piece in arc length."""
        tz = np.zeros_like(z)
        for a, b in self.pieces:
            m = b - a
            if m < 2:
                continue
            k = min(_FD_POINTS, m)
            for i in range(a, b):
                lo = min(max(i - k // 2, a), b - k)
                nodes = self.s[lo : lo + k]
                w = _derivative_weights(nodes, self.s[i])
                tz[i] = w @ z[lo : lo + k]
        return tz

    def _orient(self, z: np.ndarray, tz: np.ndarray) -> np.ndarray:
        """Point every tangent forward along the path (the chords next to
        it, within its piece)."""
        for a, b in self.pieces:
            if b - a < 2:
                continue
            d = np.diff(z[a:b], axis=0)
            fwd = np.zeros((b - a, z.shape[1]))
            fwd[:-1] += d
            fwd[1:] += d
            sign = np.sign(np.sum(fwd * tz[a:b], axis=1))
            tz[a:b] *= np.where(sign < 0, -1.0, 1.0)[:, None]
        return tz

    # ------------------------------------------------------------------
    def hermite(self, i: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Flattened state at parameters ``u`` in [0, 1] of intervals ``i``,
        shape (len(u), n_dof * n_coef + 1)."""
        i = np.asarray(i, dtype=np.int64)
        u = np.asarray(u, dtype=float)[:, None]
        L = self.length[i][:, None]
        u2, u3 = u * u, u * u * u
        h00 = 2 * u3 - 3 * u2 + 1
        h10 = u3 - 2 * u2 + u
        h01 = -2 * u3 + 3 * u2
        h11 = u3 - u2
        with np.errstate(invalid="ignore"):
            out = (
                h00 * self.y[i]
                + h10 * L * self.t[i]
                + h01 * self.y[i + 1]
                + h11 * L * self.t[i + 1]
            )
        # the points themselves exactly (also a lone point next to a seam)
        at0, at1 = u[:, 0] == 0.0, u[:, 0] == 1.0
        out[at0] = self.y[i[at0]]
        out[at1] = self.y[i[at1] + 1]
        return out

    def omega_cubic(self, i: int) -> np.ndarray:
        """Coefficients ``(a0, a1, a2, a3)`` of Ω(u) = Σ a_k u^k on interval ``i``."""
        L = self.length[i]
        p0, p1 = self.y[i, -1], self.y[i + 1, -1]
        m0, m1 = L * self.t[i, -1], L * self.t[i + 1, -1]
        return np.array(
            [p0, m0, -3 * p0 + 3 * p1 - 2 * m0 - m1, 2 * p0 - 2 * p1 + m0 + m1]
        )

    def locate(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Interval index and ``u`` of arc lengths ``s`` (-1 off the branch)."""
        s = np.asarray(s, dtype=float)
        n = self.s.size
        idx = np.full(s.shape, -1, dtype=np.int64)
        u = np.full(s.shape, np.nan)
        if n < 2:
            if n == 1:
                at = s == 0.0
                idx[at] = 0
                u[at] = 0.0
            return idx, u
        i = np.clip(np.searchsorted(self.s, s, side="right") - 1, 0, n - 2)
        ok = np.isfinite(s) & (s >= self.s[0]) & (s <= self.s[-1])
        # a sample exactly on the last point of a piece belongs to that piece
        back = ok & ~self.valid[i] & (s == self.s[i]) & (i > 0)
        back &= self.valid[np.maximum(i - 1, 0)]
        i = np.where(back, i - 1, i)
        ok &= self.valid[i]
        chord = self.s[i + 1] - self.s[i]
        with np.errstate(invalid="ignore", divide="ignore"):
            uu = np.where(chord > 0, (s - self.s[i]) / chord, 0.0)
        uu = np.where(back, 1.0, uu)
        idx[ok] = i[ok]
        u[ok] = np.clip(uu[ok], 0.0, 1.0)
        return idx, u

    def samples(self, i: np.ndarray, u: np.ndarray) -> DenseSamples:
        ok = i >= 0
        yv = np.full((i.size, self.y.shape[1]), np.nan)
        if np.any(ok):
            if self.s.size == 1:
                yv[ok] = self.y[0]
            else:
                yv[ok] = self.hermite(i[ok], u[ok])
        s = np.full(i.size, np.nan)
        if self.s.size > 1:
            s[ok] = self.s[i[ok]] + u[ok] * (self.s[i[ok] + 1] - self.s[i[ok]])
        else:
            s[ok] = 0.0
        return DenseSamples(
            arclength=s,
            omega=yv[:, -1],
            coefficients=yv[:, :-1].reshape(i.size, self.n_dof, self.n_coef),
            interval=np.where(ok, i, -1),
            harmonic_numbers=self.harmonic_numbers,
            dof_names=self.dof_names,
            tangents=self.tangent_source,
        )

    # ------------------------------------------------------------------
    def _amp(self, yv: np.ndarray, dof: int, harmonic) -> np.ndarray:
        X = yv[:, :-1].reshape(yv.shape[0], self.n_dof, self.n_coef)[:, dof]
        return _amplitude(self.harmonic_numbers, X, harmonic)

    def solve_omega(self, omega: np.ndarray) -> list[list[tuple[int, float]]]:
        """All ``(interval, u)`` where the interpolant passes through each
        Ω of ``omega``, in path order."""
        omega = np.asarray(omega, dtype=float)
        order = np.argsort(omega)
        sorted_w = omega[order]
        hits_seg, hits_q, lo_u, hi_u, rising = [], [], [], [], []
        n_int = self.s.size - 1
        for i in range(max(n_int, 0)):
            if not self.valid[i]:
                continue
            a = self.omega_cubic(i)
            # monotone pieces of Ω(u): split at the roots of Ω'(u) in (0, 1)
            cuts = [0.0]
            roots = np.roots([3 * a[3], 2 * a[2], a[1]]) if np.any(a[1:]) else []
            for r in sorted(
                float(r.real) for r in np.atleast_1d(roots) if abs(r.imag) < 1e-14
            ):
                if 1e-12 < r < 1 - 1e-12:
                    cuts.append(r)
            cuts.append(1.0)
            for ua, ub in zip(cuts[:-1], cuts[1:], strict=True):
                # the end values exactly (a query on a point must hit)
                wa = self.y[i, -1] if ua == 0.0 else np.polyval(a[::-1], ua)
                wb = self.y[i + 1, -1] if ub == 1.0 else np.polyval(a[::-1], ub)
                lo, hi = min(wa, wb), max(wa, wb)
                j0 = np.searchsorted(sorted_w, lo, side="left")
                j1 = np.searchsorted(sorted_w, hi, side="right")
                for j in range(j0, j1):
                    hits_seg.append(i)
                    hits_q.append(order[j])
                    lo_u.append(ua)
                    hi_u.append(ub)
                    rising.append(wb >= wa)
        out = [[] for _ in range(omega.size)]
        # a piece of one point: the queries at its Ω exactly
        for a, b in self.pieces:
            if b - a == 1:
                for j in np.flatnonzero(omega == self.y[a, -1]):
                    i, u = (a, 0.0) if a < self.s.size - 1 else (max(a - 1, 0), 1.0)
                    if self.s.size == 1:
                        i, u = 0, 0.0
                    out[j].append((i, u, float(self.s[a])))
        if not hits_seg:
            return [[(i, u) for i, u, _ in lst] for lst in out]
        seg = np.array(hits_seg)
        q = np.array(hits_q)
        ua = np.array(lo_u)
        ub = np.array(hi_u)
        up = np.array(rising)
        target = omega[q]
        A = np.array([self.omega_cubic(i) for i in range(n_int)])[seg]
        for _ in range(60):  # bisection on the monotone part
            mid = 0.5 * (ua + ub)
            w = ((A[:, 3] * mid + A[:, 2]) * mid + A[:, 1]) * mid + A[:, 0]
            below = (w < target) == up
            ua = np.where(below, mid, ua)
            ub = np.where(below, ub, mid)
        u = 0.5 * (ua + ub)
        s = self.s[seg] + u * (self.s[seg + 1] - self.s[seg])
        tol = 1e-10 * max(float(self.s[-1]), 1e-300)
        for k in np.argsort(s, kind="stable"):
            lst = out[q[k]]
            if lst and abs(lst[-1][2] - s[k]) <= tol:
                continue  # the same root seen from both sides of a point
            lst.append((int(seg[k]), float(u[k]), float(s[k])))
        return [[(i, u) for i, u, _ in sorted(lst, key=lambda r: r[2])] for lst in out]

    def error_estimate(self, dof: int, harmonic) -> np.ndarray:
        """Estimated largest relative error of the amplitude at fixed Ω on
        every interval, shape (n_points - 1,) (NaN across seams)."""
        n_int = self.s.size - 1
        est = np.full(max(n_int, 0), np.nan)
        # only the DOF's coefficients and Ω enter
        cols = np.append(np.arange(dof * self.n_coef, (dof + 1) * self.n_coef), -1)
        y, t = self.y[:, cols], self.t[:, cols]

        def amp(v):
            return _amplitude(self.harmonic_numbers, v[..., :-1], harmonic)

        for a, b in self.pieces:
            m = b - a
            if m < 2:
                continue
            i = np.arange(a, b - 1)
            L = self.length[i][:, None]
            k = min(m, 4)
            # every k-point stencil holding the interval
            offsets = (-2, -1, 0) if k == 4 else (0,)
            starts = [np.clip(i + o, a, b - k) for o in offsets]
            # a stencil through points of one kind only (all stuck or all
            # slipping, one harmonic level) where there is one: the branch
            # has a corner where the contact starts to slip and a small jump
            # where the level changes, which a cubic through them would
            # take for curvature
            uniform = [
                np.all(
                    self.kind[lo[:, None] + np.arange(k)] == self.kind[lo][:, None],
                    axis=1,
                )
                for lo in starts
            ]
            any_uniform = np.any(uniform, axis=0)
            corner = self.kind[i] != self.kind[i + 1]
            usable = [u_ | ~any_uniform for u_ in uniform]
            worst = np.zeros(i.size)
            for u in _ESTIMATE_AT:
                uu = np.array([u - 1e-4, u, u + 1e-4])[None, :, None]
                h00 = 2 * uu**3 - 3 * uu**2 + 1
                h10 = uu**3 - 2 * uu**2 + uu
                h01 = -2 * uu**3 + 3 * uu**2
                h11 = uu**3 - uu**2
                yh = (
                    h00 * y[i][:, None]
                    + h10 * (L * t[i])[:, None]
                    + h01 * y[i + 1][:, None]
                    + h11 * (L * t[i + 1])[:, None]
                )  # (n_int, 3, n_cols)
                amps = amp(yh)
                ah = amps[:, 1]
                dw = yh[:, 2, -1] - yh[:, 0, -1]
                with np.errstate(divide="ignore", invalid="ignore"):
                    slope = np.where(dw != 0.0, (amps[:, 2] - amps[:, 0]) / dw, np.inf)
                scale = np.where(ah != 0.0, np.abs(ah), 1.0)
                sv = self.s[i] + u * (self.s[i + 1] - self.s[i])
                # an interval where the kind changes holds the corner: the
                # cubic's distance from the chord bounds its error there
                yc = (1.0 - u) * y[i] + u * y[i + 1]
                d_om = yc[:, -1] - yh[:, 1, -1]
                with np.errstate(invalid="ignore"):
                    vert = np.abs(
                        (amp(yc) - ah) - np.where(d_om != 0.0, slope * d_om, 0.0)
                    )
                worst = np.maximum(worst, np.where(corner, vert / scale, 0.0))
                for lo, use in zip(starts, usable, strict=True):
                    idx = lo[:, None] + np.arange(k)
                    nodes = self.s[idx]  # (n_int, k)
                    w = _lagrange_weights_many(nodes, sv)
                    yp = np.einsum("ij,ijc->ic", w, y[idx])
                    ap = amp(yp)
                    d_om = yp[:, -1] - yh[:, 1, -1]
                    with np.errstate(invalid="ignore"):
                        vert = np.where(
                            d_om != 0.0,
                            np.abs((ap - ah) - slope * d_om),
                            np.abs(ap - ah),
                        )
                    if k == 4:
                        w_h = ((sv - self.s[i]) * (sv - self.s[i + 1])) ** 2
                        den = w_h - np.prod(sv[:, None] - nodes, axis=1)
                        with np.errstate(divide="ignore", invalid="ignore"):
                            ratio = np.where(den != 0.0, np.abs(w_h / den), 1.0)
                        vert = vert * SAFETY * np.minimum(ratio, 1.0)
                    worst = np.maximum(worst, np.where(use, vert / scale, 0.0))
            est[i] = worst
        return est


def _lagrange_weights_many(nodes: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Row-wise :func:`_lagrange_weights`: ``nodes`` shape (n, k), ``x``
    shape (n,); returns shape (n, k)."""
    n, k = nodes.shape
    w = np.ones((n, k))
    for j in range(k):
        for m in range(k):
            if m != j:
                w[:, j] *= (x - nodes[:, m]) / (nodes[:, j] - nodes[:, m])
    return w


def _lagrange_weights(nodes: np.ndarray, x: float) -> np.ndarray:
    """Weights ``w`` with ``p(x) = w @ values`` for the interpolating
    polynomial through ``nodes``."""
    k = nodes.size
    w = np.ones(k)
    for j in range(k):
        for m in range(k):
            if m != j:
                w[j] *= (x - nodes[m]) / (nodes[j] - nodes[m])
    return w


def _derivative_weights(nodes: np.ndarray, x: float) -> np.ndarray:
    """Weights ``w`` with ``p'(x) = w @ values`` for the interpolating
    polynomial through ``nodes``."""
    k = nodes.size
    w = np.zeros(k)
    for j in range(k):
        denom = 1.0
        for m in range(k):
            if m != j:
                denom *= nodes[j] - nodes[m]
        total = 0.0
        for m in range(k):
            if m == j:
                continue
            prod = 1.0
            for r in range(k):
                if r != j and r != m:
                    prod *= x - nodes[r]
            total += prod
        w[j] = total / denom
    return w


def dense(branch) -> DenseBranch:
    """The dense output of ``branch`` (its stored tangents when it has
    them, finite differences otherwise)."""
    return DenseBranch(branch, getattr(branch, "tangents", None))


def dense_curve_error(branch, reference_omega, reference_amplitude, dof=None):
    """The curve error (:mod:`hbmfric.validation.curve`) of a branch's
    dense output: at each reference ``(Ω_r, a_r)`` the dense first-harmonic
    amplitude at Ω_r closest to ``a_r`` (several where the branch passes
    Ω_r more than once), relative error ``|a - a_r| / a_r``; infinite where
    the branch does not reach Ω_r.

    Parameters
    ----------
    branch : Branch
    reference_omega, reference_amplitude : array_like, shape (n_ref,)
        Reference pulsations (rad/s) and first-harmonic amplitudes (m, > 0).
    dof : int, str or None
        Output DOF (None: the contact DOF).

    Returns
    -------
    hbmfric.validation.curve.CurveError
    """
    from .validation.curve import CurveError

    wr = np.asarray(reference_omega, dtype=float).ravel()
    ar = np.asarray(reference_amplitude, dtype=float).ravel()
    if wr.shape != ar.shape:
        raise ValueError("reference_omega and reference_amplitude differ in shape")
    if not np.all(ar > 0):
        raise ValueError("reference amplitudes must be > 0")
    amp = branch.amplitude_at(wr, harmonic=1, dof=dof)
    dist = np.abs(amp - ar[:, None])
    value = np.full(wr.size, np.nan)
    reached = np.any(np.isfinite(dist), axis=1)
    if np.any(reached):
        pick = np.nanargmin(
            np.where(np.isfinite(dist[reached]), dist[reached], np.inf), axis=1
        )
        value[reached] = amp[reached][np.arange(pick.size), pick]
    error = np.where(np.isnan(value), np.inf, np.abs(value - ar) / ar)
    return CurveError(
        omega=wr,
        reference=ar,
        value=value,
        error=error,
        uncovered=np.flatnonzero(np.isnan(value)),
    )
