"""FRF records for the contact-model criterion: one measured or computed
curve tagged with its excitation force and normal load, and a CSV reader."""

from __future__ import annotations

import codecs
import csv
import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._validate import finite_float
from ..errors import DataWarning

#: accepted CSV column names (first match wins), lower case
COLUMNS = {
    "force": ("force", "force_n", "fex", "excitation_force"),
    "normal_load": ("normal_load", "normal_load_n", "fn"),
    "omega": ("omega", "omega_rad_s", "frequency", "frequency_hz", "freq"),
    "amplitude": ("amplitude", "amplitude_h1_m", "amplitude_m", "amp"),
    "curve": ("curve", "label", "record"),
}

#: frequency units the column name of ``omega`` states (lower case); the
#: other names (``omega``, ``frequency``, ``freq``) state none
COLUMN_UNITS = {"omega_rad_s": "rad/s", "frequency_hz": "Hz"}

#: accepted values of :attr:`FRFRecord.omega_unit` (besides None)
OMEGA_UNITS = ("rad/s", "Hz")


@dataclass(frozen=True, eq=False)
class FRFRecord:
    """One forced-response curve of a family: amplitude against frequency
    at a given excitation force and normal load.

    Parameters
    ----------
    force : float
        Excitation amplitude ``Fex``, N, > 0.
    normal_load : float
        Normal load ``Fn`` on the contact, N, > 0.
    omega : array_like, shape (n,)
        Excitation frequencies, > 0, distinct, any order (stored sorted).
        Any unit (rad/s or Hz) works if every record of a family uses it.
    amplitude : array_like, shape (n,)
        Response amplitude at each frequency, > 0 (any unit, the same for
        the whole family); the criterion divides it by ``force``.
    label : str, optional
        Name of the curve (plots and explanations).
    omega_unit : {None, "rad/s", "Hz"}, optional
        The unit of ``omega`` when it is known (:func:`read_frfs` takes it
        from a column named ``omega_rad_s`` or ``frequency_Hz``,
        :meth:`from_branch` gives ``"rad/s"``); None: not stated.
        :func:`~hbmfric.criterion.choose_contact_model` refuses a family
        whose records state different units.

    Raises
    ------
    ValueError
        Non-finite or non-positive force, load, frequency or amplitude,
        arrays of different lengths, fewer than 5 points, a repeated
        frequency, or an unknown ``omega_unit``.
    """

    force: float
    normal_load: float
    omega: np.ndarray
    amplitude: np.ndarray
    label: str = ""
    omega_unit: str | None = None

    def __post_init__(self) -> None:
        force = finite_float("force", self.force, low=0.0, low_open=True)
        load = finite_float("normal_load", self.normal_load, low=0.0, low_open=True)
        omega = _vector("omega", self.omega)
        amp = _vector("amplitude", self.amplitude)
        if omega.size != amp.size:
            raise ValueError(
                f"omega and amplitude must have the same length, got {omega.size} "
                f"and {amp.size}"
            )
        if omega.size < 5:
            raise ValueError(f"a record needs at least 5 points, got {omega.size}")
        if np.any(omega <= 0.0):
            raise ValueError("omega must be > 0 everywhere")
        if np.any(amp <= 0.0):
            raise ValueError("amplitude must be > 0 everywhere (it is compared in log)")
        order = np.argsort(omega, kind="stable")
        omega, amp = omega[order], amp[order]
        if np.any(np.diff(omega) == 0.0):
            i = int(np.nonzero(np.diff(omega) == 0.0)[0][0])
            raise ValueError(
                f"omega has a repeated value ({omega[i]:g}); average repeated "
                "measurements before building the record"
            )
        omega.flags.writeable = False
        amp.flags.writeable = False
        object.__setattr__(self, "force", force)
        object.__setattr__(self, "normal_load", load)
        object.__setattr__(self, "omega", omega)
        object.__setattr__(self, "amplitude", amp)
        object.__setattr__(self, "label", str(self.label))
        unit = self.omega_unit
        if unit is not None:
            known = {u.lower(): u for u in OMEGA_UNITS}
            if not isinstance(unit, str) or unit.strip().lower() not in known:
                raise ValueError(
                    f"omega_unit must be None, 'rad/s' or 'Hz', got {unit!r}"
                )
            object.__setattr__(self, "omega_unit", known[unit.strip().lower()])

    @property
    def ratio(self) -> float:
        """``Fex / Fn``, dimensionless."""
        return self.force / self.normal_load

    @property
    def normalised(self) -> np.ndarray:
        """Amplitude per unit force, shape (n,)."""
        return self.amplitude / self.force

    @property
    def name(self) -> str:
        """The label, or ``Fex=…, Fn=…`` when there is none."""
        return self.label or f"Fex={self.force:g}, Fn={self.normal_load:g}"

    @classmethod
    def from_branch(
        cls,
        branch,
        normal_load: float,
        harmonic: int | None = 1,
        dof=None,
        resample: int | None = 8,
    ) -> FRFRecord:
        """A record from a computed :class:`hbmfric.Branch`.

        Parameters
        ----------
        branch : Branch
            The FRF (its ``force`` is the excitation amplitude).
        normal_load : float
            Normal load of the run, N.
        harmonic : int or None, default 1
            Amplitude measure (see :meth:`Branch.amplitude`).
        dof : int, str or None
            Response DOF (index or name); default: the contact DOF.
        resample : int or None, default 8
            The record samples the branch's dense output
            (:meth:`Branch.resample`) at this many arc lengths per interval
            between computed points, so that the criterion, which joins a
            record's samples by straight lines, follows the branch between
            its points; None: the computed points alone.

        Warns
        -----
        AccuracyWarning
            When the branch turns back in Ω (folds: the record, one
            amplitude per frequency sorted by frequency, interleaves the
            sheets between the folds) or leaves gaps inside its span (the
            record joins across them by a straight line).
        """
        if resample is None:
            omega = np.asarray(branch.omega, dtype=np.float64)
            amp = branch.amplitude(harmonic=harmonic, dof=dof)
        else:
            dense = branch.resample(resample)
            omega = np.asarray(dense.omega, dtype=np.float64)
            amp = dense.amplitude(harmonic=harmonic, dof=dof)
        _warn_not_a_function(branch)
        # repeated abscissae (a sample on a point of two pieces): keep the first
        _, keep = np.unique(omega, return_index=True)
        return cls(
            branch.force, normal_load, omega[keep], amp[keep], omega_unit="rad/s"
        )


def _vector(name: str, value) -> np.ndarray:
    try:
        a = np.array(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 1-d array of numbers") from None
    if np.ndim(value) != 1:
        raise ValueError(f"{name} must be a 1-d array, got shape {np.shape(value)}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must contain only finite values (no NaN or inf)")
    return a


def _decode(path: Path, data: bytes) -> tuple[str, str]:
    """Text of a CSV file and the name of its encoding: UTF-8 (with or
    without the byte-order mark Excel writes for "CSV UTF-8"), UTF-16 with a
    byte-order mark, otherwise Windows-1252 or Latin-1 (every byte is a
    character there)."""
    if data.startswith(codecs.BOM_UTF8):
        candidates = [("utf-8-sig", "UTF-8 with byte-order mark")]
    elif data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        candidates = [("utf-16", "UTF-16")]
    else:
        candidates = [
            ("utf-8", "UTF-8"),
            ("cp1252", "Windows-1252"),
            ("latin-1", "Latin-1"),
        ]
    for codec, name in candidates:
        try:
            text = data.decode(codec)
        except UnicodeDecodeError as err:
            last = (name, err)
            continue
        if "\x00" in text:
            raise ValueError(
                f"{path}: the file holds NUL characters (read as {name}); UTF-16 "
                "without a byte-order mark is not supported: save it as CSV "
                "UTF-8"
            )
        return text, name
    name, err = last
    raise ValueError(
        f"{path}: not valid {name} (byte {err.start}: {err.reason}); save the "
        "file as CSV UTF-8"
    )


def read_frfs(path: str | Path) -> list[FRFRecord]:
    """Read a family of FRFs from a long-format CSV file.

    One row per measured point, a header row naming the columns (case and
    surrounding spaces ignored; lines starting with ``#`` are comments):

    ``force``
        Excitation amplitude Fex, N (alias ``force_N``, ``Fex``).
    ``normal_load``
        Normal load Fn, N (alias ``normal_load_N``, ``Fn``).
    ``omega``
        Excitation frequency (alias ``omega_rad_s``, ``frequency``,
        ``frequency_Hz``); rad/s or Hz, the same for every row. The names
        ``omega_rad_s`` and ``frequency_Hz`` state the unit
        (``FRFRecord.omega_unit``), and ``choose_contact_model`` refuses a
        family that mixes the two; under the other names the unit is not
        known, and records read from files in different units would be
        compared as if in one: name the column, or convert.
    ``amplitude``
        Response amplitude at that frequency, > 0 (alias
        ``amplitude_h1_m``, ``amplitude_m``); not divided by the force.
    ``curve`` (optional)
        A name per curve. Without it, rows with the same ``(force,
        normal_load)`` form one curve.

    Extra columns are ignored, so the CSV files written by ``hbmfric
    paper`` can be read back. Rows may come in any order; frequencies may
    be unevenly spaced and differ between curves.

    Encoding: UTF-8, with or without the byte-order mark of Excel's "CSV
    UTF-8", or UTF-16 with a byte-order mark; any other file is read as
    Windows-1252, or Latin-1 (ISO 8859-1) when it is not valid Windows-1252.
    Separator: a comma, or a semicolon or tab when the header has no comma
    (numbers must use a decimal point either way). A quoted field cannot
    span lines.

    Returns
    -------
    list of FRFRecord
        In order of first appearance in the file, with ``omega_unit`` as
        the column name states it (else None).

    Warns
    -----
    DataWarning
        A column of whole numbers followed, on every row, by a column of
        digits that nothing reads: decimal commas hidden by a spare column
        (``2,300,50,1,5e-3`` under a header with a fifth column).

    Raises
    ------
    ValueError
        A missing column, a row with too few fields, a value that is not a
        finite number, or a curve whose rows disagree on force or normal load
        (the message names the file and the line, counted from 1 in the
        file), or a file that cannot be decoded (the message names the
        encoding tried).
    """
    path = Path(path)
    text, encoding = _decode(path, path.read_bytes())
    numbered = [
        (n, ln)
        for n, ln in enumerate(text.splitlines(), start=1)
        if ln.strip() and not ln.lstrip().startswith("#")
    ]
    if not numbered:
        raise ValueError(f"{path}: empty file")
    head_line = numbered[0][1]
    delimiter = ","
    if "," not in head_line:
        delimiter = max(";\t", key=head_line.count)
        if delimiter not in head_line:
            delimiter = ","
    header = [
        h.strip().lower() for h in next(csv.reader([head_line], delimiter=delimiter))
    ]
    index = {}
    for key, names in COLUMNS.items():
        for n in names:
            if n in header:
                index[key] = header.index(n)
                break
        else:
            if key != "curve":
                raise ValueError(
                    f"{path}: no column for {key!r} (accepted names: "
                    f"{', '.join(names)}); header (line {numbered[0][0]}, read as "
                    f"{encoding}) is {header}"
                )
    omega_unit = COLUMN_UNITS.get(header[index["omega"]])
    numeric = ("force", "normal_load", "omega", "amplitude")
    needed = max(index.values()) + 1
    curves: dict[str, dict] = {}
    rows: list[tuple[int, list[str]]] = []
    for lineno, line in numbered[1:]:
        row = next(csv.reader([line], delimiter=delimiter), [])
        if not any(c.strip() for c in row):
            continue
        rows.append((lineno, row))
        if len(row) < needed:
            raise ValueError(
                f"{path}: line {lineno}: {len(row)} field(s), but the header has "
                f"{len(header)} and the columns "
                f"{', '.join(header[index[k]] for k in index)} need at least "
                f"{needed}: {line.strip()!r}"
            )
        if any(c.strip() for c in row[len(header) :]):
            # decimal commas in a comma-separated file split each number in
            # two: "10,5" read as omega = 10 and amplitude = 5 (stop 29)
            raise ValueError(
                f"{path}: line {lineno}: {len(row)} field(s), but the header has "
                f"{len(header)} (decimal commas in a comma-separated file? "
                f"numbers must use a decimal point): {line.strip()!r}"
            )
        vals = {}
        for k in numeric:
            cell = row[index[k]].strip()
            try:
                v = float(cell)
            except ValueError:
                raise ValueError(
                    f"{path}: line {lineno}: column {header[index[k]]!r} must be a "
                    f"number, got {cell!r}"
                ) from None
            if not math.isfinite(v):
                raise ValueError(
                    f"{path}: line {lineno}: column {header[index[k]]!r} must be "
                    f"finite, got {cell!r}"
                )
            vals[k] = v
        if "curve" in index:
            key = row[index["curve"]].strip()
        else:
            key = f"Fex={vals['force']:g}, Fn={vals['normal_load']:g}"
        c = curves.setdefault(
            key,
            {
                "force": vals["force"],
                "normal_load": vals["normal_load"],
                "w": [],
                "a": [],
            },
        )
        for q in ("force", "normal_load"):
            if not math.isclose(c[q], vals[q], rel_tol=1e-9):
                raise ValueError(
                    f"{path}: line {lineno}: curve {key!r} has {q} "
                    f"{vals[q]:g} but earlier rows say {c[q]:g}"
                )
        c["w"].append(vals["omega"])
        c["a"].append(vals["amplitude"])
    if not curves:
        raise ValueError(f"{path}: no data rows")
    if delimiter == ",":
        _warn_hidden_decimal_commas(path, header, index, numeric, rows)
    records = []
    for key, c in curves.items():
        try:
            records.append(
                FRFRecord(
                    c["force"],
                    c["normal_load"],
                    c["w"],
                    c["a"],
                    label=key,
                    omega_unit=omega_unit,
                )
            )
        except ValueError as err:
            raise ValueError(f"{path}: curve {key!r}: {err}") from None
    return records


_INTEGER = re.compile(r"[-+]?\d+")
_FRACTION_DIGITS = re.compile(r"\d+([eE][-+]?\d+)?")


def _warn_hidden_decimal_commas(path, header, index, numeric, rows) -> None:
    """Decimal commas in a comma-separated file whose header has a spare
    column: ``2,300,50,1,5e-3`` under ``force,normal_load,frequency_Hz,
    amplitude,note`` has as many fields as the header and reads as amplitude
    1 with "5e-3" as the note. Said (a :class:`~hbmfric.DataWarning`) when a
    numeric column holds whole numbers only and the column after it, which
    nothing reads, holds digits (a fraction's digits, with an optional
    exponent) on every row. (A decimal comma further left shifts the
    frequencies into a column that repeats on every row of a curve, which
    the record refuses.) A warning, not an error: a whole-number load
    followed by a run number looks the same."""
    used = set(index.values())
    for key in numeric:
        j = index[key]
        if j + 1 >= len(header) or j + 1 in used:
            continue
        cells = [(n, r[j].strip(), r[j + 1].strip()) for n, r in rows if len(r) > j + 1]
        if len(cells) < len(rows) or not cells:
            continue
        if all(
            _INTEGER.fullmatch(a) and _FRACTION_DIGITS.fullmatch(b) for _, a, b in cells
        ):
            n, a, b = cells[0]
            warnings.warn(
                f"{path}: column {header[j]!r} holds whole numbers only and the "
                f"column after it, {header[j + 1]!r}, which is not read, digits on "
                f"every row (line {n}: {a!r} then {b!r}): decimal commas in a "
                f"comma-separated file ({a},{b} read as {a})? Numbers must use a "
                "decimal point.",
                DataWarning,
                stacklevel=3,
            )
            return


def write_frfs(path: str | Path, records) -> Path:
    """Write records to a CSV file that :func:`read_frfs` reads back
    (columns ``curve, force, normal_load, omega, amplitude``; the frequency
    column is ``omega_rad_s`` or ``frequency_Hz`` when every record states
    that unit, so that it is read back).

    Raises
    ------
    ValueError
        Records that state different frequency units.
    """
    path = Path(path)
    records = list(records)
    units = {r.omega_unit for r in records}
    if len(units - {None}) > 1:
        raise ValueError(
            "the records state different frequency units "
            f"({', '.join(sorted(units - {None}))}): convert them to one"
        )
    column = "omega"
    if len(units) == 1 and None not in units:
        column = {"rad/s": "omega_rad_s", "Hz": "frequency_Hz"}[units.pop()]
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["curve", "force", "normal_load", column, "amplitude"])
        for r in records:
            for om, a in zip(r.omega, r.amplitude, strict=True):
                w.writerow(
                    [
                        r.name,
                        f"{r.force:.12g}",
                        f"{r.normal_load:.12g}",
                        f"{om:.12g}",
                        f"{a:.12g}",
                    ]
                )
    return path


def _warn_not_a_function(branch) -> None:
    """An :class:`~hbmfric.errors.AccuracyWarning` when a branch is not one
    amplitude per Ω over a covered interval, what a record is: it turns
    back in Ω within a piece (folds), or its pieces leave a gap between
    them."""
    from ..errors import AccuracyWarning

    w = np.asarray(branch.omega, dtype=np.float64)
    notes = []
    turns = []
    for piece in branch.piece_slices():
        d = np.diff(w[piece])
        d = d[d != 0.0]
        flips = np.flatnonzero(np.sign(d[1:]) != np.sign(d[:-1]))
        turns += [float(w[piece][1:][d != 0.0][i]) for i in flips]
    if turns:
        notes.append(
            f"it turns back in Ω at {len(turns)} fold(s) (Ω = "
            + ", ".join(f"{x:.6g}" for x in turns[:4])
            + (", ..." if len(turns) > 4 else "")
            + " rad/s): sorted by Ω, the record interleaves the sheets between "
            "them"
        )
    if len(w):
        inner = [
            (a, b)
            for a, b in getattr(branch, "gaps", [])
            if a > w.min() and b < w.max()
        ]
        if inner:
            notes.append(
                "its pieces leave "
                + ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in inner)
                + " rad/s uncovered: the record joins across by a straight line"
            )
    if notes:
        warnings.warn(
            "FRFRecord.from_branch: a record holds one amplitude per frequency, "
            "but " + "; and ".join(notes) + "; build the record from the points "
            "of one sheet (FRFRecord(force, normal_load, omega, amplitude))",
            AccuracyWarning,
            stacklevel=3,
        )
