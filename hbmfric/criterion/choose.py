"""The contact-model choice criterion of Chatelet et al. (2008, Sec. 3.1
conclusion; docs/criterion.md), read from a family of FRFs."""

from __future__ import annotations

import json
import math
import time
import warnings
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from statistics import NormalDist

import numpy as np
from scipy.ndimage import maximum_filter1d

from .._validate import finite_float, positive_int
from ..errors import CoverageWarning, DataWarning
from .records import FRFRecord
from .smoothing import (
    interp_log,
    interpolation_error,
    left_crossing,
    noise_level,
    peak,
    smooth_grid,
    smoothed_noise,
    smoothing_bias,
    without_dips,
)

MODELS = ("macroslip", "microslip", "undecided")
#: two records whose bands' two ends lie within this relative distance of
#: 2π times each other's, or a ``stuck_frequency`` within it of 2π (or
#: 1/2π) times the stuck reference's own interior peak, are read as a
#: mix of Hz and rad/s and refused
TWO_PI_RTOL = 0.02
#: below this log-amplitude noise the curves are compared unsmoothed
AUTO_NOISE_FLOOR = 0.002
AUTO_WIDTH_FACTOR = 0.5
#: largest smoothing half width, fraction of the band
AUTO_MAX_WIDTH = 0.05
#: fraction of the band kept in the ratio-invariance RMS (the worst 20 % of
#: grid points, a sharp peak missed by a coarse grid, are left out; a
#: difference confined to that 20 % is caught by the local test,
#: :data:`LOCAL_FACTOR`)
TRIM_KEEP = 0.8
#: step 2's gain check: below this fraction of the stuck resonance a mostly
#: stuck curve is still stuck (linear) and equals the stuck reference; a
#: uniform factor between them there is a gain (calibration) difference
LOW_STRETCH = 0.6
#: step 1's local test: two curves at equal ratio that the (trimmed) spread
#: finds equal must not differ anywhere both are resolved by more than this
#: multiple of the spread threshold, beyond the noise and the chord error
LOCAL_FACTOR = 3.0
#: the ratio-invariance threshold is at least this multiple of the noise
NOISE_SPREAD_FACTOR = 2.5
#: mostly stuck curves have Fex/Fn at most this fraction of the flattest
#: peak's ratio (closer to it, a Masing curve slips enough to soften and
#: rise a little above the stuck envelope)
MOSTLY_STUCK_FRACTION = 0.4
#: a test decides only when its indicator lies at least this many noise units
#: (standard deviations of the indicator's noise) beyond its threshold
MARGIN_Z = 3.0
#: the stuck reference's peak must rise this many noise units above its
#: lowest point below the peak (pure noise wanders about 5 units)
RESONANCE_Z = 10.0
#: one-sided probability of a Gaussian beyond MARGIN_Z
MARGIN_TAIL = NormalDist().cdf(-MARGIN_Z)
#: smallest noise unit of a smoothed log amplitude (interpolation and
#: round-off error of clean curves)
NOISE_UNIT_FLOOR = 1e-3
#: largest common grid (the smoother holds n_grid x window values per curve)
N_GRID_MAX = 5_000


@dataclass(frozen=True, eq=False)
class CriterionResult:
    """Verdict of :func:`choose_contact_model` with its evidence.

    Attributes
    ----------
    model : {"macroslip", "microslip", "undecided"}
        "macroslip" or "microslip" only when every test on the way lies at
        least ``MARGIN_Z`` (3) noise units clear of its threshold;
        "undecided" when the family lacks something a step needs
        (``indicators["undecided_reason"] == "data"``) or when an
        indicator sits within the noise of its threshold (``"noise"``).
    roughness : bool
        True when FRFs at equal ``Fex/Fn`` differ (step 1); False when they
        coincide or when no pair could be compared (then ``model`` is
        "undecided" and ``indicators["roughness_assessed"]`` is False).
        Meaningful only when ``model`` is not "undecided" (or when
        ``indicators["margin"]["ratio_spread"]`` is beyond ±3).
    indicators : dict
        Every number the decision used, with its threshold and its margin
        in noise units (``indicators["margin"]``; see
        :func:`choose_contact_model`).
    explanation : str
        A paragraph saying what was compared, what was found and why.
    grid : ndarray, shape (n_grid,)
        Common frequency grid of the smoothed curves.
    records : tuple of FRFRecord
        The family as given.
    evidence : dict
        Smoothed log normalised amplitudes on ``grid`` (``"smoothed"``, one
        per record), the curves of step 2 and the roles given to them; read by
        :meth:`plot`.
    """

    model: str
    roughness: bool
    indicators: dict
    explanation: str
    grid: np.ndarray
    records: tuple
    evidence: dict = field(default_factory=dict)

    @property
    def verdict(self) -> str:
        """``"macroslip without roughness"``, …, or ``"undecided"``."""
        if self.model == "undecided":
            return "undecided"
        return f"{self.model} {'with' if self.roughness else 'without'} roughness"

    def __str__(self) -> str:
        return f"{self.verdict}: {self.explanation}"

    def to_dict(self) -> dict:
        """Verdict, explanation and indicators as JSON-compatible data
        (dictionary keys that are ratios become strings)."""

        def plain(x):
            if isinstance(x, dict):
                return {
                    (k if isinstance(k, str) else f"{k:.12g}"): plain(v)
                    for k, v in x.items()
                }
            if isinstance(x, list | tuple):
                return [plain(v) for v in x]
            if isinstance(x, np.generic):
                return x.item()
            return x

        return {
            "model": self.model,
            "roughness": self.roughness,
            "verdict": self.verdict,
            "explanation": self.explanation,
            "indicators": plain(self.indicators),
        }

    def save(self, path) -> Path:
        """Write :meth:`to_dict` to ``path`` as JSON (no pickle)."""
        path = Path(path)
        path.write_text(json.dumps(self.to_dict(), indent=1))
        return path

    def plot(self, fig=None):
        """Draw the evidence (matplotlib, imported here).

        Left: every FRF normalised by its force (dots: data; lines: smoothed),
        coloured by ``Fex/Fn``; curves at equal ratio share a colour, so
        ratio invariance shows as overlapping lines. Right: the stuck
        reference, the mostly stuck curves of step 2 with their peaks, and in
        red where they rise above the stuck envelope.

        Returns
        -------
        matplotlib.figure.Figure
        """
        import matplotlib.pyplot as plt

        if fig is None:
            fig = plt.figure(figsize=(11.0, 4.4))
        ax1, ax2 = fig.subplots(1, 2)
        ev = self.evidence
        ratios = sorted({g["ratio"] for g in ev.get("groups", [])})
        cmap = plt.get_cmap("viridis")
        colour = {r: cmap(i / max(len(ratios) - 1, 1)) for i, r in enumerate(ratios)}
        for rec, s, gr in zip(
            self.records, ev.get("smoothed", []), ev.get("group_of", []), strict=False
        ):
            c = colour.get(gr, "grey")
            ax1.semilogy(rec.omega, rec.normalised, ".", ms=2, color=c, alpha=0.4)
            ax1.semilogy(self.grid, np.exp(s), "-", lw=1, color=c)
        for r in ratios:
            ax1.plot([], [], "-", color=colour[r], label=f"Fex/Fn = {r:.3g}")
        spread = self.indicators.get("ratio_spread")
        ax1.set_title(
            "step 1: ratio invariance"
            + (f" (spread {spread:.3g})" if spread is not None else " (no pair)")
        )
        ax1.set_xlabel("frequency")
        ax1.set_ylabel("amplitude / Fex")
        if ratios:
            ax1.legend(fontsize=7)
        ref = ev.get("reference")
        if ref is not None:
            ax2.semilogy(self.grid, np.exp(ref), "k-", lw=1.5, label="stuck reference")
            for name, curve, pk in ev.get("mostly_stuck", []):
                (line,) = ax2.semilogy(self.grid, np.exp(curve), lw=1, label=name)
                above = np.isfinite(curve) & np.isfinite(ref) & (curve > ref)
                ax2.fill_between(
                    self.grid,
                    np.exp(ref),
                    np.exp(curve),
                    where=above,
                    color="red",
                    alpha=0.3,
                )
                ax2.plot(pk[0], math.exp(pk[1]), "v", color=line.get_color())
            w_ref = self.indicators.get("stuck_frequency")
            if w_ref is not None:
                ax2.axvline(w_ref, color="k", ls=":", lw=1)
            ax2.legend(fontsize=7)
        margin = self.indicators.get("margin", {}).get("envelope_excess")
        ax2.set_title(
            f"step 2 → {self.verdict}"
            + (f" (margin {margin:+.2g} σ)" if margin is not None else "")
        )
        ax2.set_xlabel("frequency")
        fig.tight_layout()
        return fig


def _near_two_pi(ratio: float) -> bool:
    """``ratio`` within :data:`TWO_PI_RTOL` of 2π."""
    return abs(ratio / (2.0 * math.pi) - 1.0) <= TWO_PI_RTOL


def _check_units(pool: tuple[FRFRecord, ...]) -> None:
    """Refuse a family whose records are in different frequency units: the
    units they state (``FRFRecord.omega_unit``) differ, or one record's
    band is 2π times another's at both ends (the same sweep exported once
    in Hz and once in rad/s). Records in different units are compared
    where their bands happen to overlap, or not at all (stop 31: a record
    in Hz among rad/s ones left step 1 without it, silently)."""
    stated: dict[str, list[str]] = {}
    for r in pool:
        if r.omega_unit is not None:
            stated.setdefault(r.omega_unit, []).append(r.name)
    if len(stated) > 1:
        parts = [
            f"{unit}: {', '.join(names[:3])}{' ...' if len(names) > 3 else ''}"
            for unit, names in stated.items()
        ]
        raise ValueError(
            "the records state different frequency units ("
            + "; ".join(parts)
            + "): convert them to one unit"
        )
    for a in pool:
        for b in pool:
            if _near_two_pi(a.omega[0] / b.omega[0]) and _near_two_pi(
                a.omega[-1] / b.omega[-1]
            ):
                raise ValueError(
                    f"record {a.name!r} spans {a.omega[0]:.5g}-{a.omega[-1]:.5g}, "
                    f"2π times the band of record {b.name!r} "
                    f"({b.omega[0]:.5g}-{b.omega[-1]:.5g}): one is in rad/s and "
                    "the other in Hz? Convert them to one unit"
                )


def _warn_gaps(pool: tuple[FRFRecord, ...]) -> None:
    """One :class:`~hbmfric.CoverageWarning` naming the records with gaps
    (:attr:`FRFRecord.gaps`): their samples are joined across each gap by
    a straight line, so a resonance there is missing from every step,
    and a verdict (or its "undecided" reason) may be about the chord."""
    gapped = [r for r in pool if r.gaps]
    if not gapped:
        return
    first = gapped[0]
    spans = ", ".join(f"[{lo:.6g}, {hi:.6g}]" for lo, hi in first.gaps)
    warnings.warn(
        f"{len(gapped)} of {len(pool)} records have gaps in their data (first: "
        f"{first.name!r}, no data in {spans}): the criterion joins their samples "
        "across a gap by a straight line, which misses a resonance there; "
        "trace those branches complete (hf.frf's CoverageWarning says why "
        "they stopped) or measure there",
        CoverageWarning,
        stacklevel=3,
    )


def _groups(ratios: np.ndarray, rtol: float) -> list[list[int]]:
    order = np.argsort(ratios, kind="stable")
    groups: list[list[int]] = []
    for i in order:
        if groups and ratios[i] <= ratios[groups[-1][0]] * (1.0 + rtol):
            groups[-1].append(int(i))
        else:
            groups.append([int(i)])
    return groups


def _kept_samples(
    record: FRFRecord, grid: np.ndarray, width: float, noise: float
) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies and log amplitudes of ``record`` without its deep dips
    (:func:`hbmfric.criterion.smoothing.without_dips`)."""
    y = np.log(record.normalised)
    keep = without_dips(record.omega, y, grid, width, noise)
    return record.omega[keep], y[keep]


def _auto_width(noise: float, spacing: float, band: float) -> float:
    """Half width of the smoothing window for a family with log-amplitude
    noise ``noise`` sampled every ``spacing`` over ``band``: none for clean
    data, enough samples to bring the noise to about 0.5 % otherwise (at
    most 5 % of the band)."""
    if noise < AUTO_NOISE_FLOOR:
        return 0.0
    n_avg = (noise / 0.005) ** 2
    return float(min(AUTO_WIDTH_FACTOR * n_avg * spacing, AUTO_MAX_WIDTH * band))


def _envelope_shift(grid, curve, ref, pk, w_ref) -> float | None:
    """Largest distance, as a fraction of ``w_ref``, by which the rising flank
    of ``curve`` lies to the left of the stuck reference's rising flank, over
    amplitude levels from half the curve's peak to just under it (negative:
    inside the envelope)."""
    best = None
    for f in np.linspace(0.5, 0.97, 25):
        level = pk[1] + math.log(f)
        wc = left_crossing(grid, curve, level, pk[0])
        wr = left_crossing(grid, ref, level, w_ref)
        if math.isfinite(wc) and math.isfinite(wr):
            d = (wr - wc) / w_ref
            best = d if best is None else max(best, d)
    return best


def _spread_noise(grid, smoothed, sd, ia, ib, corr) -> float:
    """Standard deviation of the RMS log difference of curves ``ia`` and
    ``ib`` due to their noise: the RMS noise of the difference over the
    ``n`` independent stretches (length ``corr``) of the common band, divided
    by ``sqrt(2 n)`` (RMS of ``n`` Gaussian values)."""
    ok = np.isfinite(smoothed[ia]) & np.isfinite(smoothed[ib])
    u = math.sqrt(np.mean(sd[ia][ok] ** 2 + sd[ib][ok] ** 2))
    band = np.count_nonzero(ok) * (grid[1] - grid[0])
    return u / math.sqrt(2.0 * max(band / corr, 1.0))


def _shrunk(distance: float, bound: float) -> float:
    """``distance`` moved towards 0 by ``bound`` (0 when within it): the
    part of an indicator's distance to its threshold that the chord error
    ``bound`` cannot explain."""
    return math.copysign(max(abs(distance) - bound, 0.0), distance)


def _chord_rms(smoothed, chord, ia, ib) -> float:
    """Bound on the change of the RMS difference of curves ``ia`` and ``ib``
    due to the chords between their samples: the RMS of the sum of their
    chord errors over their common band. Not trimmed as the spread is: the
    smoothing spreads a straddled peak's error over a window (trimmed, two
    samplings of one Menq curve at 40 frequencies read roughness at a
    margin of 104, stop 34)."""
    ok = np.isfinite(smoothed[ia]) & np.isfinite(smoothed[ib])
    e = chord[ia][ok] + chord[ib][ok]
    return float(np.sqrt(np.mean(np.where(np.isfinite(e), e, 0.0) ** 2)))


def _gain_offset(a: np.ndarray, b: np.ndarray) -> float:
    """Median of the log difference ``a - b`` over their common band: the
    log of a uniform factor (a gain) between two curves."""
    ok = np.isfinite(a) & np.isfinite(b)
    if not np.any(ok):
        return 0.0
    return float(np.median(a[ok] - b[ok]))


def _local_difference(grid, a, b, sd_a, sd_b, bound, bias_a, bias_b, level, corr):
    """Step 1's local test for two smoothed curves ``a`` and ``b`` (log
    amplitudes on ``grid``): the largest ``(|a - b| - bound - level) /
    noise`` over the grid points where both are *resolved* (their
    smoothing bias, :func:`hbmfric.criterion.smoothing.smoothing_bias`,
    stays below ``level / LOCAL_FACTOR`` within one correlation length
    ``corr``; a peak narrower than the smoothing window is flattened
    differently by every sampling of it, and its samples on the flanks are
    dropped as dips, so two noisy copies of one sharp peak differ there by
    up to 0.8 in log amplitude at 2 % noise).

    Parameters
    ----------
    grid : ndarray, shape (n_grid,)
    a, b, sd_a, sd_b, bias_a, bias_b : ndarray, shape (n_grid,)
        The curves, their noise (standard deviation) and smoothing bias.
    bound : ndarray, shape (n_grid,)
        Their summed chord error.
    level : float
        Difference (log amplitude) the test looks for.
    corr : float
        Correlation length of the smoothed noise (unit of ``grid``).

    Returns
    -------
    z : float
        The largest margin (-inf when no point is resolved).
    omega : float
        Where it lies.
    difference : float
        ``|a - b|`` there (log amplitude).
    stretches : float
        Independent stretches (length ``corr``) of the resolved band.
    """
    dx = grid[1] - grid[0]
    half = max(int(round(corr / dx)), 1)

    def resolved(bias):
        bias = np.where(np.isfinite(bias), bias, np.inf)
        widest = maximum_filter1d(bias, 2 * half + 1, mode="nearest")
        return widest < level / LOCAL_FACTOR

    d = a - b
    ok = np.isfinite(d) & resolved(bias_a) & resolved(bias_b)
    if not np.any(ok):
        return -math.inf, math.nan, math.nan, 0.0
    with np.errstate(invalid="ignore"):
        z = np.where(ok, (np.abs(d) - bound - level) / np.hypot(sd_a, sd_b), -np.inf)
    z = np.where(np.isnan(z), -np.inf, z)
    k = int(np.argmax(z))
    return (
        float(z[k]),
        float(grid[k]),
        float(abs(d[k])),
        max(np.count_nonzero(ok) * dx / corr, 1.0),
    )


def _local_search(grid, smoothed, sd, chord, bias, pairs, level, corr, offsets=None):
    """:func:`_local_difference` over ``pairs`` of curve indices, each with
    its log gain ``offsets[j]`` taken from the first curve: the largest
    margin as ``(z, omega, difference, ia, ib)`` (None without pairs) and
    the independent stretches searched."""
    best = None
    n_stretch = 0.0
    for j, (_, ia, ib) in enumerate(pairs):
        z, w, d, n = _local_difference(
            grid,
            smoothed[ia] - (0.0 if offsets is None else offsets[j]),
            smoothed[ib],
            sd[ia],
            sd[ib],
            chord[ia] + chord[ib],
            bias[ia],
            bias[ib],
            level,
            corr,
        )
        n_stretch += n
        if best is None or z > best[0]:
            best = (z, w, d, ia, ib)
    return best, n_stretch


def _z_local(n_stretch: float) -> float:
    """Margin a local difference needs when ``n_stretch`` independent
    stretches were searched (as microslip's ``margin_z_leave``)."""
    return max(MARGIN_Z, -NormalDist().inv_cdf(MARGIN_TAIL / max(n_stretch, 1.0)))


def _rms(a: np.ndarray, b: np.ndarray, min_points: int) -> float | None:
    ok = np.isfinite(a) & np.isfinite(b)
    if np.count_nonzero(ok) < min_points:
        return None
    d2 = np.sort((a[ok] - b[ok]) ** 2)
    keep = d2[: max(1, int(math.ceil(TRIM_KEEP * d2.size)))]
    return float(np.sqrt(np.mean(keep)))


def _pair_name(recs, ia, ib) -> str:
    a, b = recs[ia], recs[ib]
    return (
        f"Fex/Fn = {a.ratio:.3g} (Fex = {a.force:.3g}, Fn = {a.normal_load:.3g}; "
        f"Fex = {b.force:.3g}, Fn = {b.normal_load:.3g})"
    )


def _check_gain(
    ind,
    text,
    missing,
    unclear,
    recs,
    grid,
    smoothed,
    sd,
    chord,
    bias,
    pairs,
    threshold,
    corr,
    min_overlap,
) -> None:
    """Step 1 found the curves at some ratio different: is it only a
    uniform factor? Each pair's log difference less its median (the log of
    the pair's gain ratio) is measured as the spread is; when no pair
    differs once its uniform factor is removed, the curves differ by a
    gain (a calibration of force or response), not by roughness, which
    changes the contact's stiffness and so the shape of the FRF near the
    resonances (a uniform factor holds on the stuck stretch, the resonance
    and the mass line alike, which no contact law does). Adds the reason
    to ``missing`` (undecided, ``"data"``) and warns, or to ``unclear``
    when the shape's spread is inside the noise."""
    gains = {}
    worst = None
    for gr, ia, ib in pairs:
        c = _gain_offset(smoothed[ia], smoothed[ib])
        s = _rms(smoothed[ia] - c, smoothed[ib], min_overlap)
        if s is None:
            continue
        key = (gr, ia, ib)
        gains[key] = c
        if worst is None or s > worst[0]:
            worst = (
                s,
                key,
                _spread_noise(grid, smoothed, sd, ia, ib, corr),
                _chord_rms(smoothed, chord, ia, ib),
            )
    if worst is None:
        return
    ind["gain_ratio_by_pair"] = {
        f"{recs[ia].name} / {recs[ib].name}": math.exp(c)
        for (_, ia, ib), c in gains.items()
    }
    m_shape = _shrunk(worst[0] - threshold, worst[3]) / worst[2]
    ind["ratio_spread_shape"] = worst[0]
    ind["margin"]["ratio_spread_shape"] = m_shape
    if m_shape >= MARGIN_Z:
        return
    big = sorted(gains.items(), key=lambda kv: -abs(kv[1]))[:3]
    listed = "; ".join(
        f"{_pair_name(recs, ia, ib)}: factor {math.exp(c):.4g}"
        for (_, ia, ib), c in big
    )
    if m_shape <= -MARGIN_Z:
        # a gain only if the curves also coincide locally once it is removed
        # (a curve of another law differs near its resonance only); if they
        # do not, the local test's answer, as when the spread reads no
        # roughness
        kept = list(gains)
        if _check_local(
            ind,
            text,
            missing,
            recs,
            grid,
            smoothed,
            sd,
            chord,
            bias,
            kept,
            threshold,
            corr,
            offsets=[gains[k] for k in kept],
            gain_text=listed,
        ):
            return
        reason = (
            "the curves at equal Fex/Fn differ by a uniform factor across the "
            f"band ({listed}); with that factor removed they coincide (spread "
            f"{worst[0]:.3g}, margin {m_shape:+.3g} noise units). A factor "
            "uniform over the stuck stretch, the resonance and the mass line "
            "is a gain (calibration) difference between the measurements, not "
            "roughness, which changes the FRF's shape near the resonances: "
            "check the calibration of force and response"
        )
        missing.append(reason)
        warnings.warn("choose_contact_model: " + reason, DataWarning, stacklevel=3)
        text[-1] += (
            " But the difference is a uniform factor, a gain: roughness is not shown."
        )
    else:
        unclear.append(
            "step 1's difference is mostly a uniform factor (a gain: "
            f"{listed}); with it removed, the spread lies {m_shape:+.2g} noise "
            "units from its threshold, so whether roughness or a calibration "
            "error separates the curves cannot be told"
        )


def _check_local(
    ind,
    text,
    missing,
    recs,
    grid,
    smoothed,
    sd,
    chord,
    bias,
    pairs,
    threshold,
    corr,
    offsets=None,
    gain_text=None,
) -> bool:
    """Step 1 found the curves at every ratio equal (the trimmed spread
    leaves out the worst 20 % of the band): do two of them differ
    somewhere beyond ``LOCAL_FACTOR`` times the threshold, past their
    noise and chord error, where both are resolved? The margin needed
    is raised for the number of independent stretches searched, as for
    microslip's envelope test. Adds the reason to ``missing`` (undecided,
    ``"data"``), warns and returns True when one does. With ``offsets``
    (each pair's log gain, removed first; ``gain_text`` lists the factors),
    the spread was a uniform factor's."""
    level = LOCAL_FACTOR * threshold
    best, n_stretch = _local_search(
        grid, smoothed, sd, chord, bias, pairs, level, corr, offsets
    )
    if best is None:
        return False
    z_local = _z_local(n_stretch)
    ind["local_difference"] = best[2] if math.isfinite(best[0]) else None
    ind["local_difference_frequency"] = best[1]
    # None when no point of any pair is resolved (JSON has no infinity)
    ind["margin"]["local_difference"] = best[0] if math.isfinite(best[0]) else None
    ind["margin_z_local"] = z_local
    if best[0] < z_local:
        return False
    z, w, d, ia, ib = best
    reason = (
        (
            f"the curves at equal Fex/Fn differ by a uniform factor ({gain_text}) "
            "and, with it removed, "
            if gain_text
            else ""
        )
        + f"the curves at {_pair_name(recs, ia, ib)} coincide over most of the "
        f"band but differ by {d:.3g} (log amplitude) at {w:.5g}, {z:.3g} noise "
        f"units beyond {level:.3g} where both are resolved ({z_local:.2g} "
        "needed): ratio invariance fails there only. Step 1 leaves out the "
        "worst 20 % of the band and so cannot say whether this is roughness or "
        "one curve measured under other conditions (another contact state or "
        "law): check that curve"
    )
    missing.append(reason)
    warnings.warn("choose_contact_model: " + reason, DataWarning, stacklevel=3)
    text[-1] += " But one pair differs locally (see below)."
    return True


def choose_contact_model(
    records: Iterable[FRFRecord],
    *,
    stuck: FRFRecord | None = None,
    stuck_frequency: float | None = None,
    ratio_rtol: float = 0.02,
    spread_threshold: float = 0.05,
    excess_threshold: float = 0.1,
    stuck_tolerance: float = 0.1,
    smoothing: float | None = None,
    n_grid: int = 600,
) -> CriterionResult:
    """Choose between a macroslip and a microslip contact model, with or
    without roughness, from a family of FRFs (docs/criterion.md).

    Every curve is divided by its force, interpolated (linearly in log
    amplitude) onto a common uniform frequency grid and, when the data are
    noisy, smoothed there by local quadratic regression; the same operator
    acts on every curve, so stretches where two curves coincide stay equal.

    Steps (Chatelet et al. 2008, end of Sec. 3.1):

    1. **Ratio invariance.** Curves whose ``Fex/Fn`` agree to ``ratio_rtol``
       but whose normal loads differ are compared: the RMS difference of
       their log amplitudes over the common band (the worst 20 % of grid
       points left out, so that a sharp peak missed by a coarse grid does not
       count) is the *spread*. Above the threshold (``spread_threshold``, at
       least 2.5 × the estimated noise) the FRFs are not a function of
       ``Fex/Fn`` alone: roughness effects matter — unless a uniform factor
       per pair (its median log difference, a gain or calibration error)
       explains it: then "undecided" with an ``hf.DataWarning``. Below the
       threshold, a *local test* looks for a pair that differs, where both
       curves are resolved (:func:`hbmfric.criterion.smoothing.smoothing_bias`
       below the threshold), by more than ``LOCAL_FACTOR`` (3) times the
       threshold past the chord error and the noise, the margin raised for
       the stretches searched (a curve of another law swapped in differs
       near its resonance only, inside the 20 % left out): "undecided" with
       an ``hf.DataWarning`` naming the pair.
    2. **Mostly stuck peaks.** One curve per ratio: the mean of the group's
       curves without roughness, the curve at the highest normal load with
       roughness (step 3: asperities crushed). The *stuck reference* is
       ``stuck`` when given, otherwise the curve of the lowest ratio (at its
       highest normal load). The curve with the flattest (lowest) normalised
       peak marks the optimal-damping ratio; curves of lower ratio that
       differ from the reference by more than ``stuck_tolerance`` somewhere
       are *mostly stuck* (curves within it are as stuck as the reference).
       For each, the *envelope excess* is ``max(A − A_ref) / max(A)`` over the
       band below the stuck resonance. If a mostly stuck curve rises there
       above the stuck envelope by more than ``excess_threshold`` of its own
       peak (it moved to lower frequency), the contact is **microslip**; if
       all stay inside, **macroslip** (unless they rise above the envelope
       on the high-frequency side, which fits neither model).

    **Noise and margins.** The noise of each record is estimated (robust
    scatter of each sample about the line through its neighbours, in log
    amplitude) and carried, exactly, through the interpolation and the
    smoothing: every point of every smoothed curve has its own noise
    (standard deviation, at least 0.1 %). Each test is then read as a
    *margin*: how far its indicator lies from its threshold in units of the
    indicator's own noise (positive: past the threshold). A test decides only
    when its margin is at least ``MARGIN_Z`` = 3 either way:

    * step 1: (spread − threshold) / noise of the spread (the RMS noise of
      the difference divided by √(2 n), n the number of independent
      stretches of the band, each a smoothing window or a sample spacing
      long);
    * the stuck reference's peak must rise at least ``RESONANCE_Z`` = 10
      noise units above its lowest point below the peak (a resonance at
      all; pure noise reaches about 5);
    * a curve is mostly stuck when somewhere its distance from the
      reference exceeds ``stuck_tolerance`` by 3 noise units, stuck when it
      stays 3 units inside everywhere (in between it is left out);
    * step 2: the largest of (excess − ``excess_threshold``) / noise of the
      excess over the band below the stuck resonance. ≤ −3 (and the same
      above the stuck resonance) → **macroslip**: every point is inside.
      **Microslip** claims that *some* point is outside, found by searching
      n independent stretches (smoothing windows) of the band, so the
      margin it needs, ``indicators["margin_z_leave"]``, is raised until
      the chance that Gaussian noise alone reaches it somewhere equals the
      chance of one point passing 3 (3.6 for 10 stretches, 3.8 for 20).

    **Sparse samples.** The chords between a record's samples cut its
    resonance peak by an amount the noise estimate does not see
    (:func:`hbmfric.criterion.smoothing.interpolation_error`: the change
    when every other sample is left out). It is a bound, not noise: each
    distance above is first shrunk by it (step 1: the RMS of the pair's
    summed errors, ``indicators["ratio_spread_chord_error"]``; stuck /
    mostly stuck and the envelope test: counted against the claim,
    pointwise), and an "undecided" it causes says to measure more
    frequencies near the peaks. Before stop 34, curves at 15-40 uneven
    frequencies each read the other law or roughness in 70 of 432 draws.

    The noise model is Gaussian in log amplitude. The magnitude of a noisy
    measurement is not: where the noise is a sizeable fraction of the
    signal its logarithm has a heavy lower tail (samples near zero). Such
    dips, deeper than 3.5 noise units below the smoothed curve, are dropped
    before the curves are compared (``indicators["dropped_dips"]`` counts
    them; :func:`hbmfric.criterion.smoothing.without_dips`); peaks are never
    dropped. Without this, 30 % noise of that kind made the rough Masing
    family read microslip in 2 of 40 runs; with it, 0 of 320 runs of the
    paper's four families read a wrong model.

    The verdicts are therefore

    ``"macroslip"`` / ``"microslip"`` (with or without roughness)
        Every test on the way is clear of its threshold by 3 noise units.
    ``"undecided"``, ``indicators["undecided_reason"] == "data"``
        The family cannot answer a step, and the explanation says what is
        missing (no records, a single ratio, no two normal loads at the same
        ratio, no mostly stuck curve, a stuck resonance outside the measured
        band, curves leaving the envelope above the stuck resonance), or
        the curves at one ratio are inconsistent in a way that is not
        roughness (a uniform factor, a local difference; step 1 above).
    ``"undecided"``, ``indicators["undecided_reason"] == "noise"``
        The data cannot tell: some margin is inside ±3 noise units (or the
        stuck resonance does not stand out of the noise); the explanation
        names the test and its margin. More points per curve, repeated
        measurements or a lower noise turn it into a verdict.

    Parameters
    ----------
    records : iterable of FRFRecord
        The family (measured or computed, any frequency grids).
    stuck : FRFRecord, optional
        The fully stuck (linear) FRF, e.g. measured at a very high normal
        load or computed with the contact bonded. Default: the family's
        lowest-ratio curve (at its highest normal load with roughness); it
        should be (nearly) fully stuck.
    stuck_frequency : float, optional
        Stuck resonance frequency (unit of ``omega``); peak shifts are
        measured from it, and it replaces the reference's peak when that
        lies outside the band. Default: the peak of the stuck reference.
    ratio_rtol : float, default 0.02
        Relative tolerance for equal ``Fex/Fn``.
    spread_threshold : float, default 0.05
        Step 1 threshold on the RMS log difference (0.05 is about 5 %).
    excess_threshold : float, default 0.1
        Step 2 threshold, fraction of the curve's own peak.
    stuck_tolerance : float, default 0.1
        Largest log difference from the reference of a curve counted as
        stuck (linear) rather than mostly stuck.
    smoothing : float, optional
        Half width of the smoothing window as a fraction of the frequency
        band; 0 turns smoothing off. Default: none when the estimated noise
        is below 0.2 %, otherwise a window holding about
        ``(noise / 0.005)**2`` samples (at most 5 % of the band).
    n_grid : int, default 600
        Points of the common frequency grid, 50 to ``N_GRID_MAX`` = 5000
        (the smoother holds ``n_grid`` × window values per curve).

    Returns
    -------
    CriterionResult
        ``indicators`` holds ``ratio_spread`` (with
        ``ratio_spread_threshold``, ``ratio_spread_by_ratio``, ``n_pairs``),
        ``stuck_frequency``, ``flattest_ratio``, ``mostly_stuck_ratios``,
        ``peak_shift`` (relative shift of each mostly stuck peak from the
        stuck resonance, negative = lower frequency), ``envelope_excess``
        (largest below the stuck resonance, with
        ``envelope_excess_by_ratio``, ``envelope_excess_frequency`` and
        ``envelope_excess_threshold``; ``envelope_excess_above`` the same
        above it), ``envelope_shift`` (largest distance by which a curve's
        rising flank lies left of the reference's, over levels from 50 to
        97 % of its peak, fraction of the stuck resonance; about 0 or
        negative = inside), ``noise`` (robust estimate of the data's noise
        in log amplitude, median over records), ``noise_smoothed`` (median
        noise left on the smoothed curves), ``smoothing_half_width``,
        ``n_records``, ``n_grid`` and ``elapsed`` (wall time, s).
        ``margin`` holds the margins in noise units: ``ratio_spread``,
        ``stuck_rise``, ``mostly_stuck`` (by ratio), ``envelope_excess``
        and ``envelope_excess_above``; ``margin_z`` the margin a verdict
        needs (3), ``margin_z_leave`` the one microslip needs below the
        stuck resonance, ``ratio_spread_noise`` and ``envelope_excess_noise`` the
        noise units of step 1 and of the largest excess, ``stuck_rise`` the
        reference's rise (log amplitude), ``unclear_stuck_ratios`` the
        curves left out as neither stuck nor mostly stuck, and
        ``undecided_reason`` None, "data" or "noise". After step 1:
        ``gain_ratio_by_pair`` and ``ratio_spread_shape`` (with
        ``margin["ratio_spread_shape"]``, the spread with each pair's
        uniform factor removed) when it read roughness;
        ``local_difference`` (log amplitude), ``local_difference_frequency``,
        ``margin["local_difference"]`` (None when no point is resolved)
        and ``margin_z_local`` (the margin the local test needs) when it
        did not. Step 2:
        ``stuck_stretch_gain`` (each mostly stuck curve's factor to the
        stuck reference below ``LOW_STRETCH`` (0.6) times the stuck
        resonance, where both are stuck) and ``verdict_without_gains``
        (whether the verdict holds with the factors that stand out of the
        noise removed; if not, "undecided" with an ``hf.DataWarning``).

    Raises
    ------
    ValueError
        A record that is not an :class:`FRFRecord`, an option out of its
        range (the message names it and the range), ``n_grid`` outside
        [50, 5000].
    """
    start = time.perf_counter()
    recs = tuple(records)
    for i, r in enumerate(recs):
        if not isinstance(r, FRFRecord):
            raise ValueError(
                f"records[{i}] must be an FRFRecord, got {type(r).__name__}"
            )
    if stuck is not None and not isinstance(stuck, FRFRecord):
        raise ValueError(f"stuck must be an FRFRecord, got {type(stuck).__name__}")
    _check_units(recs + ((stuck,) if stuck is not None else ()))
    _warn_gaps(recs + ((stuck,) if stuck is not None else ()))
    if stuck_frequency is not None:
        stuck_frequency = finite_float(
            "stuck_frequency", stuck_frequency, low=0.0, low_open=True
        )
    ratio_rtol = finite_float("ratio_rtol", ratio_rtol, low=0.0, high=0.5)
    spread_threshold = finite_float(
        "spread_threshold", spread_threshold, low=0.0, low_open=True
    )
    excess_threshold = finite_float(
        "excess_threshold", excess_threshold, low=0.0, low_open=True
    )
    stuck_tolerance = finite_float(
        "stuck_tolerance", stuck_tolerance, low=0.0, low_open=True
    )
    if smoothing is not None:
        smoothing = finite_float("smoothing", smoothing, low=0.0, high=0.2)
    n_grid = positive_int("n_grid", n_grid, low=50)
    if n_grid > N_GRID_MAX:
        raise ValueError(
            f"n_grid must be an integer in [50, {N_GRID_MAX}], got {n_grid} (the "
            "smoother holds n_grid x window values per curve; 600 resolves "
            "resonances of 0.5 % damping over a band of twice their frequency)"
        )

    ind: dict = {
        "n_records": len(recs),
        "ratio_rtol": ratio_rtol,
        "ratio_spread": None,
        "ratio_spread_threshold": spread_threshold,
        "ratio_spread_by_ratio": {},
        "n_pairs": 0,
        "roughness_assessed": False,
        "envelope_excess": None,
        "envelope_excess_threshold": excess_threshold,
        "stuck_tolerance": stuck_tolerance,
        "margin_z": MARGIN_Z,
        "margin": {},
        "undecided_reason": None,
    }
    if not recs:
        ind["undecided_reason"] = "data"
        return CriterionResult(
            "undecided", False, ind, "No FRF was given.", np.zeros(0), recs
        )
    pool = recs + ((stuck,) if stuck is not None else ())
    lo = min(float(r.omega[0]) for r in pool)
    hi = max(float(r.omega[-1]) for r in pool)
    grid = np.linspace(lo, hi, n_grid)
    noise = [noise_level(r.omega, np.log(r.normalised)) for r in recs]
    ind["noise"] = float(np.median(noise))
    spacing = float(np.median([np.median(np.diff(r.omega)) for r in recs]))
    if smoothing is None:
        width = _auto_width(ind["noise"], spacing, hi - lo)
    else:
        width = smoothing * (hi - lo)
    ind["smoothing_half_width"] = width
    samples = [
        _kept_samples(r, grid, width, nz) for r, nz in zip(recs, noise, strict=True)
    ]
    ind["dropped_dips"] = int(
        sum(r.omega.size - w.size for r, (w, _) in zip(recs, samples, strict=True))
    )
    raw = [interp_log(w, y, grid) for w, y in samples]
    smoothed = [smooth_grid(grid, y, width) for y in raw]
    # noise left on each smoothed curve, pointwise (log amplitude)
    sd = [
        np.hypot(smoothed_noise(w, grid, width, nz), NOISE_UNIT_FLOOR)
        for (w, _), nz in zip(samples, noise, strict=True)
    ]
    # error of the chords between the samples (a peak the samples straddle),
    # a bound each test's distance to its threshold must exceed before the
    # noise is counted (stop 34)
    chord = [
        interpolation_error(w, y, grid, width, nz)
        for (w, y), nz in zip(samples, noise, strict=True)
    ]
    ind["noise_smoothed"] = float(np.nanmedian(np.concatenate(sd)))
    ratios = np.array([r.ratio for r in recs])
    loads = np.array([r.normal_load for r in recs])
    groups = _groups(ratios, ratio_rtol)
    group_ratio = [float(f"{np.exp(np.mean(np.log(ratios[g]))):.12g}") for g in groups]
    group_of = [0.0] * len(recs)
    for g, gr in zip(groups, group_ratio, strict=True):
        for i in g:
            group_of[i] = gr
    evidence: dict = {
        "smoothed": smoothed,
        "group_of": group_of,
        "groups": [
            {"ratio": gr, "members": g}
            for g, gr in zip(groups, group_ratio, strict=True)
        ],
    }
    missing: list[str] = []
    text: list[str] = []

    # -- step 1: ratio invariance ------------------------------------------
    # correlation length of the smoothed noise: the smoothing window, or the
    # sample spacing when that is wider
    corr = max(2.0 * width, spacing)
    min_overlap = max(10, n_grid // 10)
    worst = None
    pairs: list[tuple[float, int, int]] = []
    for g, gr in zip(groups, group_ratio, strict=True):
        best = None
        for a in range(len(g)):
            for b in range(a + 1, len(g)):
                ia, ib = g[a], g[b]
                hi_l, lo_l = max(loads[ia], loads[ib]), min(loads[ia], loads[ib])
                if hi_l <= lo_l * (1.0 + ratio_rtol):
                    continue  # same level repeated: says nothing about levels
                s = _rms(smoothed[ia], smoothed[ib], min_overlap)
                if s is None:
                    continue
                ind["n_pairs"] += 1
                pairs.append((gr, ia, ib))
                if best is None or s > best[0]:
                    best = (
                        s,
                        _spread_noise(grid, smoothed, sd, ia, ib, corr),
                        _chord_rms(smoothed, chord, ia, ib),
                    )
        if best is not None:
            ind["ratio_spread_by_ratio"][gr] = best[0]
            if worst is None or best[0] > worst[0]:
                worst = (best[0], gr, best[1], best[2])
    roughness = False
    unclear: list[str] = []
    if worst is None:
        missing.append(
            "no two curves share a value of Fex/Fn at different normal loads, so "
            "ratio invariance (step 1, roughness) cannot be checked: measure at "
            "least one ratio at two force levels"
        )
        text.append("Step 1 (ratio invariance) could not be run.")
    else:
        ind["roughness_assessed"] = True
        ind["ratio_spread"] = worst[0]
        # two noisy copies of one curve differ by about sqrt(2) x noise
        threshold = max(spread_threshold, NOISE_SPREAD_FACTOR * ind["noise"])
        ind["ratio_spread_threshold"] = threshold
        roughness = worst[0] > threshold
        # the chords may move the spread by up to worst[3] either way
        margin = _shrunk(worst[0] - threshold, worst[3]) / worst[2]
        ind["ratio_spread_chord_error"] = worst[3]
        ind["margin"]["ratio_spread"] = margin
        ind["ratio_spread_noise"] = worst[2]
        text.append(
            f"Step 1: {ind['n_pairs']} pair(s) of curves at equal Fex/Fn and "
            f"different normal loads were compared after division by Fex; the "
            f"largest RMS log difference is {worst[0]:.3g} (at Fex/Fn = "
            f"{worst[1]:.3g}; threshold {threshold:.3g}, data noise "
            f"{ind['noise']:.2g}, noise of the difference {worst[2]:.2g}: "
            f"margin {margin:+.3g} noise units), so the FRFs "
        )
        if abs(margin) < MARGIN_Z:
            text[-1] += (
                "may or may not depend on Fex/Fn alone: the spread is within "
                f"{MARGIN_Z:g} noise units of its threshold."
            )
            unclear.append(
                "step 1 cannot tell whether roughness matters (ratio spread "
                f"{margin:+.2g} noise units from its threshold"
                + (
                    f", after the error of the chords between the samples, up "
                    f"to {worst[3]:.2g}: measure more frequencies near the peaks)"
                    if abs(worst[0] - threshold) > MARGIN_Z * worst[2]
                    else ")"
                )
            )
        else:
            text[-1] += (
                "are not a function of Fex/Fn alone: roughness effects matter, "
                "and step 2 uses the highest normal load of each ratio."
                if roughness
                else "depend on Fex/Fn only: no roughness effects."
            )
        if abs(margin) >= MARGIN_Z:
            bias = [
                smoothing_bias(w, y, grid, width, nz)
                for (w, y), nz in zip(samples, noise, strict=True)
            ]
        if margin >= MARGIN_Z:
            _check_gain(
                ind,
                text,
                missing,
                unclear,
                recs,
                grid,
                smoothed,
                sd,
                chord,
                bias,
                pairs,
                threshold,
                corr,
                min_overlap,
            )
        elif margin <= -MARGIN_Z:
            _check_local(
                ind,
                text,
                missing,
                recs,
                grid,
                smoothed,
                sd,
                chord,
                bias,
                pairs,
                threshold,
                corr,
            )
    ind["roughness"] = roughness

    # -- step 2 (3 with roughness): one curve per ratio --------------------
    curves = []
    for g, gr in zip(groups, group_ratio, strict=True):
        if roughness:
            i = max(g, key=lambda j: loads[j])
            c, c_sd, c_chord = smoothed[i], sd[i], chord[i]
            name = f"Fex/Fn = {gr:.3g} (Fn = {loads[i]:.3g})"
        else:
            stack = np.array([smoothed[j] for j in g])
            var = np.array([sd[j] ** 2 for j in g])
            with np.errstate(invalid="ignore"):
                counts = np.sum(np.isfinite(stack), axis=0)
                c = np.where(counts > 0, np.nansum(stack, axis=0) / counts, np.nan)
                # mean of independent curves: noise / sqrt(count)
                c_sd = np.where(
                    counts > 0, np.sqrt(np.nansum(var, axis=0)) / counts, np.nan
                )
                # mean of the members' chord errors (a bound, not averaged out)
                c_chord = np.where(
                    counts > 0,
                    np.nansum(np.array([chord[j] for j in g]), axis=0) / counts,
                    np.nan,
                )
            name = f"Fex/Fn = {gr:.3g}"
        curves.append(
            {"ratio": gr, "curve": c, "sd": c_sd, "chord": c_chord, "name": name}
        )
    for c in curves:
        c["peak"] = peak(grid, c["curve"])

    if stuck is not None:
        stuck_noise = noise_level(stuck.omega, np.log(stuck.normalised))
        w_stuck, y_stuck = _kept_samples(stuck, grid, width, stuck_noise)
        ref = smooth_grid(grid, interp_log(w_stuck, y_stuck, grid), width)
        ref_sd = np.hypot(
            smoothed_noise(w_stuck, grid, width, stuck_noise), NOISE_UNIT_FLOOR
        )
        ref_chord = interpolation_error(w_stuck, y_stuck, grid, width, stuck_noise)
        ref_name = f"the given stuck FRF ({stuck.name})"
        candidates = curves
    else:
        ref, ref_sd = curves[0]["curve"], curves[0]["sd"]
        ref_chord = curves[0]["chord"]
        ref_name = f"the lowest-ratio curve ({curves[0]['name']})"
        candidates = curves[1:]
    evidence["reference"] = ref
    ref_peak = peak(grid, ref)
    if stuck_frequency is not None and ref_peak[2]:
        ratio = stuck_frequency / ref_peak[0]
        if _near_two_pi(ratio) or _near_two_pi(1.0 / ratio):
            raise ValueError(
                f"stuck_frequency = {stuck_frequency:.5g} is {ratio:.4g} times the "
                f"peak of the stuck reference ({ref_name}) at {ref_peak[0]:.5g}: "
                "given in Hz for records in rad/s, or the other way round? Give it "
                "in the unit of the records' omega"
            )
    if stuck_frequency is not None and stuck_frequency <= grid[0]:
        # step 2 reads the curves below the stuck resonance: none here
        w_ref = None
        missing.append(
            f"stuck_frequency = {stuck_frequency:.5g} lies below the band of the "
            f"records ({grid[0]:.5g}-{grid[-1]:.5g}), so no curve is measured "
            "below the stuck resonance (is it in the unit of the records' "
            "omega?)"
        )
    elif stuck_frequency is not None:
        w_ref = stuck_frequency
    elif ref_peak[2]:
        w_ref = ref_peak[0]
    else:
        w_ref = None
        missing.append(
            f"the stuck reference, {ref_name}, peaks at the edge of the band, so "
            "the stuck resonance is not in the data: widen the band or pass "
            "stuck_frequency"
        )
    ind["stuck_frequency"] = w_ref
    ind["stuck_reference"] = ref_name
    if w_ref is not None:
        # a resonance must stand out of the noise: the peak's rise above the
        # lowest point below it, in noise units of that difference
        k = int(np.nanargmax(ref))
        k_low = int(np.nanargmin(ref[: k + 1]))
        rise = float(ref[k] - ref[k_low])
        rise_margin = rise / float(np.hypot(ref_sd[k], ref_sd[k_low]))
        ind["stuck_rise"] = rise
        ind["margin"]["stuck_rise"] = rise_margin
        if rise_margin < RESONANCE_Z:
            unclear.append(
                f"the stuck reference's peak rises {rise:.3g} (log amplitude) "
                f"above its lowest point below it, {rise_margin:.3g} noise units: "
                f"no resonance stands out of the noise (at least {RESONANCE_Z:g} "
                "needed)"
            )

    mostly: list[dict] = []
    ind["margin"]["mostly_stuck"] = {}
    ambiguous: list[float] = []
    if len(curves) < 2 and stuck is None:
        missing.append(
            "a single value of Fex/Fn: step 2 needs a stuck reference and at "
            "least one mostly stuck curve"
        )
    elif candidates:
        flattest = min(curves, key=lambda c: c["peak"][1])
        ind["flattest_ratio"] = flattest["ratio"]
        for c in candidates:
            if c["ratio"] > MOSTLY_STUCK_FRACTION * flattest["ratio"] * (
                1.0 + ratio_rtol
            ):
                continue
            ok = np.isfinite(c["curve"]) & np.isfinite(ref)
            if np.count_nonzero(ok) < min_overlap:
                continue
            # largest distance beyond the tolerance, in noise units
            dev = np.abs(c["curve"][ok] - ref[ok])
            unit = np.hypot(c["sd"][ok], ref_sd[ok])
            bound = c["chord"][ok] + ref_chord[ok]
            # stuck: inside the tolerance everywhere even if the chords
            # hide up to ``bound``; mostly stuck: outside somewhere even so
            m_stuck = float(np.max((dev + bound - stuck_tolerance) / unit))
            m_out = float(np.max((dev - bound - stuck_tolerance) / unit))
            m = m_out if m_out >= MARGIN_Z else m_stuck
            ind["margin"]["mostly_stuck"][c["ratio"]] = m
            if m_stuck <= -MARGIN_Z:
                continue  # linear: as stuck as the reference
            if m_out < MARGIN_Z:
                ambiguous.append(c["ratio"])  # stuck or not: inside the noise
                continue
            mostly.append(c)
    ind["mostly_stuck_ratios"] = [c["ratio"] for c in mostly]
    ind["unclear_stuck_ratios"] = ambiguous
    if not mostly and ambiguous and not missing:
        unclear.append(
            "the curves at Fex/Fn = "
            + ", ".join(f"{r:.3g}" for r in ambiguous)
            + " differ from the stuck reference by about the stuck tolerance "
            f"({stuck_tolerance:g}), within {MARGIN_Z:g} noise units: mostly stuck "
            "or stuck cannot be told"
        )
    if not mostly and not missing and not unclear:
        missing.append(
            "no mostly stuck curve: none lies between the stuck reference and "
            "0.4 times the ratio of the flattest peak (add values of Fex/Fn "
            "below 0.4 times the one that flattens the peak most, but above the "
            "fully stuck one)"
        )

    # -- the envelope test ---------------------------------------------------
    ind["peak_shift"] = {}
    ind["envelope_excess_by_ratio"] = {}
    ind["envelope_shift"] = {}
    # per side: largest excess (value, frequency, ratio, its noise) and largest
    # margin (excess - threshold) / noise (value, frequency, ratio)
    worst = {"below": None, "above": None}
    # margins with the chord error counted against the claim: "inside
    # everywhere" (excess + bound) and "outside somewhere" (excess - bound)
    best_margin = {"below": None, "above": None}
    best_out = {"below": None, "above": None}
    # a curve "leaves the envelope" if any point does: the margin that claim
    # needs grows with the number of independent stretches searched
    stretches = {"below": 0.0, "above": 0.0}
    evidence["mostly_stuck"] = []
    # step 2's gain check: the margins once each mostly stuck curve's gain
    # relative to the reference (read on the stuck stretch) is removed
    ind["stuck_stretch_gain"] = {}
    gains_seen: list[tuple[float, float]] = []
    margin_g = {"below": -math.inf, "above": -math.inf}
    out_gain = {"below": -math.inf, "above": -math.inf}
    for c in mostly if w_ref is not None else []:
        y = c["curve"]
        ok = np.isfinite(y) & np.isfinite(ref)
        top = c["peak"][1]
        excess = np.full(grid.shape, -np.inf)
        excess[ok] = (np.exp(y[ok]) - np.exp(ref[ok])) / math.exp(top)
        # noise of the excess (first order in the log-amplitude noise)
        unit = np.full(grid.shape, np.inf)
        unit[ok] = np.hypot(
            np.exp(y[ok]) * c["sd"][ok], np.exp(ref[ok]) * ref_sd[ok]
        ) / math.exp(top)
        for side, mask in (("below", grid < w_ref), ("above", grid >= w_ref)):
            span = np.count_nonzero(mask & ok) * (grid[1] - grid[0])
            stretches[side] += max(span / corr, 1.0)
        bound = np.zeros(grid.shape)
        bound[ok] = (
            np.exp(y[ok]) * c["chord"][ok] + np.exp(ref[ok]) * ref_chord[ok]
        ) / math.exp(top)
        ratio_m = np.full(grid.shape, -np.inf)
        ratio_m[ok] = (excess[ok] + bound[ok] - excess_threshold) / unit[ok]
        out_m = np.full(grid.shape, -np.inf)
        out_m[ok] = (excess[ok] - bound[ok] - excess_threshold) / unit[ok]
        # the same margins with the curve's gain relative to the reference
        # removed, the gain read far below the resonance where both are stuck
        ratio_g, out_g = ratio_m, out_m
        low = ok & (grid < LOW_STRETCH * w_ref)
        n_low = np.count_nonzero(low) * (grid[1] - grid[0]) / corr
        if n_low >= 1.0:
            g_log = float(np.median(y[low] - ref[low]))
            g_unit = float(np.median(np.hypot(c["sd"][low], ref_sd[low])))
            ind["stuck_stretch_gain"][c["ratio"]] = math.exp(g_log)
            if abs(g_log) > MARGIN_Z * g_unit / math.sqrt(n_low):
                gains_seen.append((c["ratio"], math.exp(g_log)))
                yg = y - g_log
                excess_g = np.full(grid.shape, -np.inf)
                excess_g[ok] = (np.exp(yg[ok]) - np.exp(ref[ok])) / math.exp(
                    top - g_log
                )
                unit_g = np.full(grid.shape, np.inf)
                unit_g[ok] = np.hypot(
                    np.exp(yg[ok]) * c["sd"][ok], np.exp(ref[ok]) * ref_sd[ok]
                ) / math.exp(top - g_log)
                bound_g = np.zeros(grid.shape)
                bound_g[ok] = (
                    np.exp(yg[ok]) * c["chord"][ok] + np.exp(ref[ok]) * ref_chord[ok]
                ) / math.exp(top - g_log)
                ratio_g = np.full(grid.shape, -np.inf)
                ratio_g[ok] = (excess_g[ok] + bound_g[ok] - excess_threshold) / unit_g[
                    ok
                ]
                out_g = np.full(grid.shape, -np.inf)
                out_g[ok] = (excess_g[ok] - bound_g[ok] - excess_threshold) / unit_g[ok]
        for side, mask in (("below", grid < w_ref), ("above", grid >= w_ref)):
            if np.any(mask & ok):
                m = float(np.max(np.where(mask & ok, ratio_g, -np.inf)))
                margin_g[side] = max(margin_g[side], m)
                m = float(np.max(np.where(mask & ok, out_g, -np.inf)))
                out_gain[side] = max(out_gain[side], m)
        for side, mask in (("below", grid < w_ref), ("above", grid >= w_ref)):
            if not np.any(mask & ok):
                continue
            k = int(np.argmax(np.where(mask, excess, -np.inf)))
            e = float(excess[k])
            if side == "below":
                ind["envelope_excess_by_ratio"][c["ratio"]] = e
            if worst[side] is None or e > worst[side][0]:
                worst[side] = (e, float(grid[k]), c["ratio"], float(unit[k]))
            k = int(np.argmax(np.where(mask & ok, ratio_m, -np.inf)))
            m = float(ratio_m[k])
            if best_margin[side] is None or m > best_margin[side][0]:
                best_margin[side] = (m, float(grid[k]), c["ratio"])
            k = int(np.argmax(np.where(mask & ok, out_m, -np.inf)))
            m = float(out_m[k])
            if best_out[side] is None or m > best_out[side][0]:
                best_out[side] = (m, float(grid[k]), c["ratio"])
        ind["peak_shift"][c["ratio"]] = (c["peak"][0] - w_ref) / w_ref
        ind["envelope_shift"][c["ratio"]] = _envelope_shift(
            grid, y, ref, c["peak"], w_ref
        )
        evidence["mostly_stuck"].append((c["name"], y, c["peak"]))

    model = "undecided"
    if worst["below"] is not None:
        e, w_e, r_e, u_e = worst["below"]
        m_below, w_m, r_m = best_margin["below"]
        ind["envelope_excess"] = e
        ind["envelope_excess_frequency"] = w_e
        ind["envelope_excess_noise"] = u_e
        ind["margin"]["envelope_excess"] = m_below
        ind["envelope_margin_frequency"] = w_m
        m_above = -math.inf
        # margin needed to say that a curve leaves the envelope somewhere
        z_leave = {
            side: max(MARGIN_Z, -NormalDist().inv_cdf(MARGIN_TAIL / max(n, 1.0)))
            for side, n in stretches.items()
        }
        ind["margin_z_leave"] = z_leave["below"]
        # leaving the envelope is claimed on the margin with the chord error
        # counted against it
        leaves_below = best_out["below"][0] >= z_leave["below"]
        leaves_above = False
        if leaves_below:
            m_below, w_m, r_m = best_out["below"]
            ind["margin"]["envelope_excess"] = m_below
            ind["envelope_margin_frequency"] = w_m
        if worst["above"] is not None:
            ind["envelope_excess_above"] = worst["above"][0]
            ind["envelope_excess_above_frequency"] = worst["above"][1]
            m_above = best_margin["above"][0]
            leaves_above = best_out["above"][0] >= z_leave["above"]
            if leaves_above:
                m_above = best_out["above"][0]
            ind["margin"]["envelope_excess_above"] = m_above
        shifts = ", ".join(
            f"{100 * s:+.2f} % at Fex/Fn = {r:.3g}"
            for r, s in ind["peak_shift"].items()
        )
        text.append(
            f"Step 2: the stuck reference is {ref_name}, resonance at {w_ref:.4g}. "
            f"Mostly stuck curves (at most 0.4 times the ratio of the flattest "
            f"peak, "
            f"Fex/Fn = "
            f"{ind['flattest_ratio']:.3g}): "
            + ", ".join(f"{c['ratio']:.3g}" for c in mostly)
            + f"; their peaks move by {shifts} from the stuck resonance. Below "
            f"the stuck resonance, the largest rise above the stuck envelope is "
            f"{100 * e:.2f} % of the curve's peak (Fex/Fn = {r_e:.3g}, at "
            f"{w_e:.4g}; noise {100 * u_e:.2g} %; threshold "
            f"{100 * excess_threshold:.3g} %); measured in noise units, the "
            f"excess comes closest to or goes furthest past the threshold at "
            f"{w_m:.4g} (Fex/Fn = {r_m:.3g}), margin {m_below:+.3g} (inside by "
            f"{MARGIN_Z:g} everywhere says macroslip; past by {z_leave['below']:.2g} "
            f"somewhere, {MARGIN_Z:g} raised for the "
            f"{stretches['below']:.0f} independent stretches searched, says "
            "microslip)"
        )
        above = ind.get("envelope_excess_above", -np.inf)
        if leaves_below:
            model = "microslip"
            text[-1] += (
                ": the mostly stuck peaks leave the stuck envelope towards lower "
                "frequency, the signature of partial slip in a stuck contact "
                "(microslip)."
            )
        elif leaves_above:
            text[-1] += (
                f", but above it the curves rise {100 * above:.2f} % over the "
                f"envelope (margin {m_above:+.3g} noise units), which is not a "
                "friction softening signature: the data do not fit either model."
            )
            missing.append(
                "the curves leave the stuck envelope on the high-frequency side"
            )
        elif m_below <= -MARGIN_Z and m_above <= -MARGIN_Z:
            model = "macroslip"
            text[-1] += (
                ": the mostly stuck curves stay inside the fully stuck envelope, "
                "as a macroslip (Masing) contact does."
            )
        else:
            text[-1] += "."
            side = "below" if m_below > -MARGIN_Z else "above"
            m_side = m_below if side == "below" else m_above
            m_out = best_out[side][0] if best_out[side] is not None else -math.inf
            if m_side > 0.0 and m_out < m_side:
                unclear.append(
                    f"{side} the stuck resonance the envelope excess lies "
                    f"{m_side:+.2g} noise units from its threshold counting the "
                    "error of the chords between the samples for it, "
                    f"{m_out:+.2g} counting it against it: the samples are too "
                    "sparse near the peaks to tell whether the mostly stuck "
                    "peaks leave the stuck envelope (measure more frequencies "
                    "there)"
                )
            else:
                unclear.append(
                    f"{side} the stuck resonance the envelope excess lies "
                    f"{m_side:+.2g} noise units from its threshold: the data "
                    "cannot tell whether the mostly stuck peaks leave the stuck "
                    "envelope"
                )
    if model != "undecided" and gains_seen:
        # a verdict must not hang on a gain between the mostly stuck curves
        # and the stuck reference: read again with the gains removed
        if model == "microslip":
            holds = out_gain["below"] >= z_leave["below"]
        else:
            holds = (
                margin_g["below"] <= -MARGIN_Z
                and margin_g["above"] <= -MARGIN_Z
                and out_gain["above"] < z_leave["above"]
            )
        ind["verdict_without_gains"] = holds
        if not holds:
            listed = ", ".join(f"{g:.4g} at Fex/Fn = {r:.3g}" for r, g in gains_seen)
            reason = (
                "the mostly stuck curves differ from the stuck reference by a "
                f"uniform factor below {LOW_STRETCH:g} times the stuck resonance, "
                f"where both are stuck ({listed}): a gain (calibration) "
                f"difference, and with it removed step 2 does not read {model}; "
                "check the calibration of force and response"
            )
            missing.append(reason)
            warnings.warn("choose_contact_model: " + reason, DataWarning, stacklevel=2)
    if model == "undecided" and not missing and not unclear:
        # no verdict leaves without its reason (stop 31: a stuck_frequency
        # below the band ended in "Verdict: undecided" and no reason)
        missing.append(
            "no mostly stuck curve has points below the stuck resonance "
            f"({w_ref:.5g}), where step 2 compares them with the stuck envelope"
            if w_ref is not None
            else "the stuck resonance is not known"
        )
    if missing:
        model = "undecided"
        ind["undecided_reason"] = "data"
        text.append("Undecided: " + "; ".join(missing) + ".")
    elif unclear:
        model = "undecided"
        ind["undecided_reason"] = "noise"
        text.append("Undecided within the noise: " + "; ".join(unclear) + ".")
    else:
        text.append(f"Verdict: {model} {'with' if roughness else 'without'} roughness.")
    ind["n_grid"] = n_grid
    ind["elapsed"] = time.perf_counter() - start
    return CriterionResult(
        model, bool(roughness), ind, " ".join(text), grid, recs, evidence
    )
