"""Measured FRF files as a lab exports them (stop 29 hunt).

A comma-separated file whose numbers carry decimal commas ("10,5" for
10.5, as a spreadsheet in a German or French locale writes them) split
every number in two; the reader took the first fields in order and read
``omega = 10`` and ``amplitude = 5`` from the row ``1,5,10,5,1,25`` with no
word. A row with more non-empty fields than the header is refused now; a
trailing empty field (a separator at the end of a row) is still read.
"""

from __future__ import annotations

import pytest

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
