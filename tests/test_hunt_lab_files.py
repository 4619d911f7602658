"""Measured FRF files as a lab exports them (stop 29 hunt).

A comma-separated file whose numbers carry decimal commas ("10,5" for
10.5, as a spreadsheet in a German or French locale writes them) split
every number in two; the reader took the first fields in order and read
``omega = 10`` and ``amplitude = 5`` from the row ``1,5,10,5,1,25`` with no
word. A row with more non-empty fields than the header is refused now; a
trailing empty field (a separator at the end of a row) is still read.
"""

from __future__ import annotations

import warnings

import pytest

import hbmfric as hf
from hbmfric.criterion import read_frfs

HEADER = "force,normal_load,omega,amplitude"


def test_decimal_commas_in_a_comma_separated_file_are_refused(tmp_path):
    p = tmp_path / "komma.csv"
    # force 1, normal load 5, omega 10.5 .. 14.5, amplitude 1.25 .. 3.75
    body = ["1,5,10,5,1,25", "1,5,11,5,2,5", "1,5,12,5,3,75", "1,5,13,5,2,5"]
    p.write_text("\n".join([HEADER, *body, "1,5,14,5,1,25"]) + "\n")
    with pytest.raises(ValueError, match=r"komma\.csv: line 2: 6 field\(s\).*decimal"):
        read_frfs(p)


def test_trailing_separator_is_read(tmp_path):
    p = tmp_path / "trailing.csv"
    amplitudes = (1, 2, 3, 2, 1)
    rows = [f"1,5,{w},{a}," for w, a in zip(range(10, 15), amplitudes, strict=True)]
    p.write_text("\n".join([HEADER + ",", *rows]) + "\n")
    (rec,) = read_frfs(p)
    assert list(rec.omega) == [10.0, 11.0, 12.0, 13.0, 14.0]
    assert list(rec.amplitude) == [1.0, 2.0, 3.0, 2.0, 1.0]


def test_decimal_commas_hidden_by_a_spare_column_are_said(tmp_path):
    """Stop 33 hunt: amplitudes 1,5e-3 .. 3,5e-3 written with decimal commas
    under a header with a trailing note column have as many fields as the
    header; they read as amplitude 1, 2, 3 (the fraction taken for the
    note) with no word. Now a DataWarning names the columns."""
    p = tmp_path / "note.csv"
    rows = [
        f"2,300,{w},{a},5e-3"
        for w, a in zip(range(50, 55), (1, 2, 3, 2, 1), strict=True)
    ]
    p.write_text("\n".join(["force,normal_load,frequency_Hz,amplitude,note", *rows]))
    with pytest.warns(hf.DataWarning, match=r"'amplitude'.*'note'.*decimal commas"):
        (rec,) = read_frfs(p)
    assert list(rec.amplitude) == [1.0, 2.0, 3.0, 2.0, 1.0]  # what the file says


def test_a_decimal_comma_further_left_is_refused(tmp_path):
    """Force 2,5 N with a decimal comma: every later value moves one column
    right (normal load 5, the normal load 300 read as the frequency of every
    row, amplitude 50..54): the repeated frequency is refused."""
    p = tmp_path / "shift.csv"
    rows = [f"2,5,300,{w},1.5e-3" for w in range(50, 55)]
    p.write_text("\n".join(["force,normal_load,frequency_Hz,amplitude,note", *rows]))
    with pytest.raises(ValueError, match=r"omega has a repeated value \(300\)"):
        read_frfs(p)


AMPS = ("1.5e-3", "2.5e-3", "3.5e-3", "2.5e-3", "1.5e-3")


@pytest.mark.parametrize("note", ["repeat", "7", ""], ids=["text", "number", "empty"])
def test_a_spare_column_beside_decimal_points_is_read_quietly(tmp_path, note):
    p = tmp_path / "ok.csv"
    rows = [f"2,300,{w},{a},{note}" for w, a in zip(range(50, 55), AMPS, strict=True)]
    p.write_text("\n".join(["force,normal_load,frequency_Hz,amplitude,note", *rows]))
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        (rec,) = read_frfs(p)
    assert list(rec.amplitude) == [float(a) for a in AMPS]
