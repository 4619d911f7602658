"""Identification of the modified Dahl model from a measured hysteresis loop
(paper Sec. 2, Fig. 3).

Three stages:

1. **Envelope lines.** The record is smoothed (Savitzky–Golay), split into
   loading (``u̇ > 0``) and unloading parts, and straight lines are fitted by
   least squares to the part of each branch away from its reversal (the far
   half of the stroke, where the branch has converged to its asymptote).
   For ``μ = 1`` these asymptotes are ``h_u − a/β`` and ``h_l + d/β``, not
   the envelopes themselves.
2. **β from the dissipated energy.** The measured loop area per cycle and
   the closed form ``W = 2 G (X − tanh(βX)/β)`` (``G`` the gap between the
   fitted asymptotes at the mean displacement, ``X`` the half stroke) give
   β by a scalar root; the envelope offsets follow as
   ``b = b' + a/β``, ``e = e' − d/β``.
3. **Loop fit.** The model force simulated along the (smoothed) measured
   path is fitted to the measured force by nonlinear least squares over all
   parameters (a, b, d, e, β, the starting force, and μ if asked), from the
   start above.
"""

from __future__ import annotations

import csv
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._validate import finite_array, finite_float
from .errors import AccuracyWarning
from .kernels.aft.dahl import dahl_march
from .laws import ModifiedDahl

#: fewest samples per cycle and complete cycles a record must hold
MIN_SAMPLES_PER_CYCLE = 40
MIN_CYCLES = 1.0
#: the force noise (std) must stay below this fraction of the loop width
MAX_NOISE_TO_WIDTH = 0.2
#: a fit whose residual exceeds the force noise by a systematic part (the
#: root of the difference of their squares) above this fraction of the force
#: range does not describe the record: warned (a Jenkins loop fitted by the
#: law leaves 2.3-4.9 %, loops of the law with 1-5 % force noise 0-0.8 %)
MAX_MISFIT = 0.012
#: ... provided the residual also exceeds the noise by this factor (the
#: noise estimate reads the noise of those loops within 8 %)
MISFIT_OVER_NOISE = 1.1


@dataclass(frozen=True)
class DahlIdentification:
    """Result of :func:`modified_dahl`.

    Attributes
    ----------
    upper, lower : (float, float)
        ``(a, b)`` and ``(d, e)`` of the envelopes ``h_u = a u + b`` and
        ``h_l = d u + e``: N/m, N.
    beta : float
        ``β``.
    exponent : float
        ``μ``.
    law : ModifiedDahl
        The identified law.
    start : dict
        Stage 1–2 estimates (``upper``, ``lower``, ``beta``) before the loop
        fit.
    residual_rms : float
        Root-mean-square of measured minus model force, N.
    residual_relative : float
        ``residual_rms`` over the force range of the record.
    noise_estimate : float
        Force noise estimated from the record before fitting, N.
    n_cycles : float
        Cycles in the record.
    n_evaluations : int
        Model simulations done by the loop fit.
    u, force, model : ndarray, shape (n,)
        Measured displacement (m), measured force and model force (N).
    """

    upper: tuple[float, float]
    lower: tuple[float, float]
    beta: float
    exponent: float
    law: ModifiedDahl
    start: dict
    residual_rms: float
    residual_relative: float
    noise_estimate: float
    n_cycles: float
    n_evaluations: int
    u: np.ndarray = field(repr=False)
    force: np.ndarray = field(repr=False)
    model: np.ndarray = field(repr=False)

    def plot(self, ax=None, path: str | Path | None = None):
        """Measured and model loops with the envelope lines (paper Fig. 3).

        Parameters
        ----------
        ax : matplotlib Axes, optional
        path : str or Path, optional
            Save the figure there (PNG).

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6.0, 4.4))
        ax.plot(self.u * 1e3, self.force, ".", ms=2, color="0.6", label="measured")
        ax.plot(self.u * 1e3, self.model, "-", lw=1.2, color="C3", label="model")
        span = np.array([self.u.min(), self.u.max()])
        a, b = self.upper
        d, e = self.lower
        ax.plot(span * 1e3, a * span + b, "--", color="C0", label="h_u = a u + b")
        ax.plot(span * 1e3, d * span + e, "--", color="C2", label="h_l = d u + e")
        ax.set_xlabel("displacement u (mm)")
        ax.set_ylabel("force F (N)")
        ax.set_title(
            f"modified Dahl: β = {self.beta:.4g}, μ = {self.exponent:.3g}, "
            f"rms residual {100 * self.residual_relative:.2f} %"
        )
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        if path is not None:
            ax.figure.tight_layout()
            ax.figure.savefig(path, dpi=120)
        return ax


def read_loop_csv(
    path: str | Path, u_column: int | str = 0, force_column: int | str = 1
) -> tuple[np.ndarray, np.ndarray]:
    """Read a measured loop from a CSV file (one header row allowed).

    Parameters
    ----------
    path : str or Path
    u_column, force_column : int or str
        Column indices, or names from the header row.

    Returns
    -------
    u, force : ndarray, shape (n,)
    """
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    if not rows:
        raise ValueError(f"{path}: no rows")
    header = None
    try:
        [float(c) for c in rows[0]]
    except ValueError:
        header = [c.strip() for c in rows[0]]
        rows = rows[1:]

    def index(col, name):
        if isinstance(col, str):
            if header is None or col not in header:
                raise ValueError(f"{name}={col!r} is not a column of {path}")
            return header.index(col)
        return int(col)

    iu, iforce = index(u_column, "u_column"), index(force_column, "force_column")
    try:
        data = np.array([[float(r[iu]), float(r[iforce])] for r in rows])
    except (ValueError, IndexError):
        raise ValueError(f"{path}: non-numeric or missing values") from None
    return data[:, 0], data[:, 1]


def modified_dahl_csv(
    path: str | Path, u_column: int | str = 0, force_column: int | str = 1, **kwargs
) -> DahlIdentification:
    """:func:`modified_dahl` on a loop read by :func:`read_loop_csv`."""
    u, force = read_loop_csv(path, u_column, force_column)
    return modified_dahl(u, force, **kwargs)


def modified_dahl(
    u, force, exponent: float | None = 1.0, *, smoothing: int | None = None
) -> DahlIdentification:
    """Identify the modified Dahl law from a measured loop ``F(u)``.

    Parameters
    ----------
    u : array_like, shape (n,)
        Displacement record (equidistant in time, periodic-like excitation,
        any mean, any number of cycles >= 1), m.
    force : array_like, shape (n,)
        Force record, N.
    exponent : float or None
        Fixed ``μ >= 1`` (default 1), or None to fit it as well.
    smoothing : int, optional
        Savitzky–Golay window (odd, samples) for the displacement; default
        a fifth of a cycle.

    Returns
    -------
    DahlIdentification

    Raises
    ------
    ValueError
        Invalid input, a record too short (< 1 cycle or too few samples per
        cycle) or too noisy (force noise above 20 % of the loop width, or a
        loop fit that leaves more than that).

    Warns
    -----
    AccuracyWarning
        When the fit leaves a residual that the record's noise does not
        explain (a systematic part above ``MAX_MISFIT`` = 1.2 % of the force
        range): the record is not a modified-Dahl loop and the parameters
        are the best compromise of a law that does not describe it.
    """
    from scipy.optimize import brentq, least_squares
    from scipy.signal import savgol_filter

    u = finite_array("u", u)
    force = finite_array("force", force)
    if u.shape != force.shape:
        raise ValueError(
            f"u and force must have the same shape, got {u.shape}, {force.shape}"
        )
    fixed_mu = exponent is not None
    if fixed_mu:
        exponent = finite_float("exponent", exponent, low=1.0)
    n = u.size
    if n < 2 * MIN_SAMPLES_PER_CYCLE:
        raise ValueError(
            f"loop too short to identify: {n} samples (need at least "
            f"{2 * MIN_SAMPLES_PER_CYCLE})"
        )
    # --- cycles, from the zero crossings of the centred displacement -------
    centred = u - 0.5 * (np.percentile(u, 2) + np.percentile(u, 98))
    ups, downs = _crossings(centred)
    n_cycles, samples_per_cycle = 0.0, 0.0
    if len(ups) >= 2:
        samples_per_cycle = float(np.mean(np.diff(ups)))
        n_cycles = n / samples_per_cycle
    if n_cycles < MIN_CYCLES or samples_per_cycle < MIN_SAMPLES_PER_CYCLE:
        raise ValueError(
            f"loop too short to identify: {n_cycles:.2f} cycles of "
            f"{samples_per_cycle:.0f} samples (need >= {MIN_CYCLES:g} cycle of "
            f">= {MIN_SAMPLES_PER_CYCLE} samples)"
        )
    window = int(smoothing) if smoothing else int(samples_per_cycle / 5)
    window = max(5, min(window | 1, n if n % 2 else n - 1))
    us = _monotone_path(savgol_filter(u, window, 3, mode="interp"), ups, downs)
    velocity = np.gradient(us)
    noise = _noise_level(force)
    # --- stage 1: asymptote lines away from reversals ---------------------
    lo, hi = np.percentile(us, 1), np.percentile(us, 99)
    stroke = hi - lo
    loading = (velocity > 0) & (us > lo + 0.5 * stroke)
    unloading = (velocity < 0) & (us < hi - 0.5 * stroke)
    if loading.sum() < 10 or unloading.sum() < 10:
        raise ValueError("loop too short to identify: too few samples on a branch")
    a1, b1 = np.polyfit(us[loading], force[loading], 1)
    d1, e1 = np.polyfit(us[unloading], force[unloading], 1)
    u_mid = 0.5 * (lo + hi)
    gap = (a1 - d1) * u_mid + b1 - e1
    if not gap > 0:
        raise ValueError(
            "no hysteresis: the loading branch does not lie above the unloading "
            "one (check the signs of u and force)"
        )
    if noise > MAX_NOISE_TO_WIDTH * gap:
        raise ValueError(
            f"loop too noisy to identify: force noise {noise:.3g} N is "
            f"{noise / gap:.0%} of the loop width {gap:.3g} N (limit "
            f"{MAX_NOISE_TO_WIDTH:.0%})"
        )
    # --- stage 2: β from the loop area ------------------------------------
    half = 0.5 * stroke
    area = _area_per_cycle(us, force, ups)
    ratio = area / (2.0 * gap)  # = X - tanh(βX)/β, in (0, X)
    if not 0.0 < ratio < half:
        beta0 = 4.0 / half
    else:
        beta0 = brentq(
            lambda lb: half - np.tanh(math.exp(lb) * half) / math.exp(lb) - ratio,
            math.log(1e-3 / half),
            math.log(1e6 / half),
        )
        beta0 = math.exp(beta0)
    mu0 = exponent if fixed_mu else 1.0
    start = {
        "upper": (a1, b1 + a1 / beta0),
        "lower": (d1, e1 - d1 / beta0),
        "beta": beta0,
    }
    # --- stage 3: least-squares fit of the simulated loop -----------------
    f_scale = max(gap, 1e-300)
    u_scale = max(stroke, 1e-300)
    p0 = np.array(
        [
            a1 * u_scale / f_scale,
            (b1 + a1 / beta0) / f_scale,
            d1 * u_scale / f_scale,
            (e1 - d1 / beta0) / f_scale,
            math.log(beta0 * u_scale),
            force[0] / f_scale,
        ]
    )
    if not fixed_mu:
        p0 = np.append(p0, 0.0)
    model = np.empty(n)
    counter = [0]

    def unpack(p):
        a = p[0] * f_scale / u_scale
        b = p[1] * f_scale
        d = p[2] * f_scale / u_scale
        e = p[3] * f_scale
        mu = mu0 if fixed_mu else 1.0 + p[6] ** 2
        # scaled so that p[4] keeps its μ = 1 meaning near the loop middle
        beta = math.exp(p[4]) / u_scale / f_scale ** (mu - 1.0)
        return a, b, d, e, beta, mu, p[5] * f_scale

    def residual(p):
        a, b, d, e, beta, mu, f0 = unpack(p)
        params = np.array([beta, mu, a, b, d, e])
        dahl_march(params, us, f0, model)
        counter[0] += 1
        return (model - force) / f_scale

    if not fixed_mu:
        p0[6] = 0.3  # start off μ = 1, where the derivative in p[6] vanishes
    fit = least_squares(residual, p0, method="lm", xtol=1e-12, ftol=1e-12)
    a, b, d, e, beta, mu, f0 = unpack(fit.x)
    if not b > e:
        raise ValueError("loop fit failed: the fitted envelopes cross (b <= e)")
    params = np.array([beta, mu, a, b, d, e])
    dahl_march(params, us, f0, model)
    rms = float(np.sqrt(np.mean((model - force) ** 2)))
    if rms > MAX_NOISE_TO_WIDTH * gap * 1.5:
        raise ValueError(
            f"loop fit failed: rms residual {rms:.3g} N is "
            f"{rms / gap:.0%} of the loop width; the record is too noisy or not "
            f"a modified-Dahl loop"
        )
    law = ModifiedDahl(beta=beta, exponent=mu, upper=(a, b), lower=(d, e))
    _warn_misfit(rms, noise, float(np.ptp(force)))
    return DahlIdentification(
        upper=(float(a), float(b)),
        lower=(float(d), float(e)),
        beta=float(beta),
        exponent=float(mu),
        law=law,
        start=start,
        residual_rms=rms,
        residual_relative=rms / float(np.ptp(force)),
        noise_estimate=float(noise),
        n_cycles=float(n_cycles),
        n_evaluations=counter[0],
        u=u.copy(),
        force=force.copy(),
        model=model.copy(),
    )


def _warn_misfit(rms: float, noise: float, force_range: float) -> None:
    """Warn when the loop fit leaves a residual the record's noise does not
    explain: the record is not a modified-Dahl loop (a Jenkins loop with
    its sharp corners, for instance), and the fitted parameters are the
    best compromise of a law that does not describe it (a Jenkins loop of
    flat slip plateaus gave envelope slopes of -2e4 N/m), not the record's
    own.

    Parameters
    ----------
    rms, noise, force_range : float
        Residual root-mean-square, estimated force noise and force range of
        the record, N.
    """
    systematic = math.sqrt(max(rms * rms - noise * noise, 0.0))
    if not (systematic > MAX_MISFIT * force_range and rms > MISFIT_OVER_NOISE * noise):
        return
    warnings.warn(
        f"the modified Dahl law does not describe this loop: the fit leaves "
        f"a systematic residual of {systematic:.3g} N ({systematic / force_range:.1%} "
        f"of the force range; rms residual {rms:.3g} N against a force noise of "
        f"{noise:.3g} N estimated from the record), so the identified "
        "parameters are a compromise, not the record's (compare the loops: "
        "result.plot())",
        AccuracyWarning,
        stacklevel=3,
    )


def _crossings(centred: np.ndarray) -> tuple[list[int], list[int]]:
    """Indices where the centred displacement crosses upwards and downwards
    (a Schmitt trigger at ±30 % of the amplitude, so noise adds none)."""
    amp = np.percentile(np.abs(centred), 90)
    state = 0
    ups: list[int] = []
    downs: list[int] = []
    for i, x in enumerate(centred):
        if x > 0.3 * amp and state <= 0:
            if state < 0:
                ups.append(i)
            state = 1
        elif x < -0.3 * amp and state >= 0:
            if state > 0:
                downs.append(i)
            state = -1
    return ups, downs


def _monotone_path(us: np.ndarray, ups: list[int], downs: list[int]) -> np.ndarray:
    """The smoothed path with the residual noise wiggles between reversals
    removed: one reversal per half cycle (the extreme between two
    crossings), monotone in between (isotonic least-squares fit of each
    stroke). The law is rate independent, so only this path matters, and
    noise wiggles would otherwise act as spurious small loops."""
    marks = sorted([(i, 1) for i in ups] + [(i, -1) for i in downs])
    reversals = [0]
    for (i0, s0), (i1, _) in zip(marks[:-1], marks[1:], strict=True):
        seg = us[i0:i1]
        # after an upward crossing the next extreme is a maximum
        k = int(np.argmax(seg) if s0 > 0 else np.argmin(seg))
        reversals.append(i0 + k)
    reversals.append(us.size - 1)
    from scipy.optimize import isotonic_regression

    out = us.copy()
    for r0, r1 in zip(reversals[:-1], reversals[1:], strict=True):
        seg = us[r0 : r1 + 1]
        rising = bool(seg[-1] >= seg[0])
        fit = isotonic_regression(seg, increasing=rising).x
        # keep the reversal samples themselves (the ends of the segment)
        out[r0 + 1 : r1] = fit[1:-1]
    return out


def _noise_level(force: np.ndarray) -> float:
    """Standard deviation of the force noise, N: the robust spread (MAD) of
    second differences, ``Var(Δ²ε) = 6 σ²`` for white noise."""
    d2 = np.diff(force, 2)
    mad = np.median(np.abs(d2 - np.median(d2)))
    return float(1.4826 * mad / math.sqrt(6.0))


def _area_per_cycle(us: np.ndarray, force: np.ndarray, ups: list[int]) -> float:
    """Loop area ``∮ F du`` per cycle over the whole cycles of the record, J."""
    i0, i1 = ups[0], ups[-1]
    seg_u = us[i0 : i1 + 1]
    seg_f = force[i0 : i1 + 1]
    area = np.sum(0.5 * (seg_f[1:] + seg_f[:-1]) * np.diff(seg_u))
    return float(area / (len(ups) - 1))
