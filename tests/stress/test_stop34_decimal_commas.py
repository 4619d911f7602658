"""Stress rows for stop 34 (lead): lab files with decimal commas hidden by a
spare column.

A comma-separated file whose numbers carry decimal commas splits each
number with a fraction in two. With as many spare columns in the header as
split numbers, every row has the header's number of fields, and before
stop 34 ``read_frfs`` read the whole-number part as the value and the
fraction's digits as the spare column, with no word: amplitude 1 for 1,5e-3.
Each row writes such a file (several layouts, units and spare-column
names) and requires a loud answer: a :class:`hbmfric.DataWarning` (or a
``ValueError`` where the shifted values break a record) and never a quiet
read. The same files with decimal points read quietly and exactly.

Run with ``python -m pytest -m stress tests/stress/test_stop34_decimal_commas.py``.
"""

from __future__ import annotations

import warnings

import pytest

import hbmfric as hf
from hbmfric.criterion import read_frfs

pytestmark = pytest.mark.stress

#: amplitudes of one curve, as (whole part, fraction digits)
LAYOUTS = {
    "mantissa-exponent": [
        ("1", "5e-3"),
        ("2", "5e-3"),
        ("3", "25e-3"),
        ("2", "5e-3"),
        ("1", "75e-3"),
    ],
    "mm": [("1", "25"), ("2", "5"), ("3", "75"), ("2", "5"), ("1", "125")],
    "micrometres": [("12", "5"), ("40", "25"), ("97", "0"), ("41", "5"), ("13", "05")],
}
HEADERS = {
    "note": "force,normal_load,frequency_Hz,amplitude,note",
    "comment-upper": "Force,Normal_Load,Omega,Amplitude,Comment",
    "curve-first": "curve,force,normal_load,omega_rad_s,amplitude,spare",
}


def _rows(header: str, amps, point: bool) -> list[str]:
    rows = []
    for w, (whole, frac) in zip(range(50, 55), amps, strict=True):
        a = f"{whole}.{frac}" if point else f"{whole},{frac}"
        body = f"2,300,{w},{a}" + ("," if point else "")
        rows.append(("c1," if header.startswith("curve") else "") + body)
    return rows


@pytest.mark.parametrize("layout", sorted(LAYOUTS))
@pytest.mark.parametrize("header", sorted(HEADERS))
def test_hidden_decimal_commas_are_never_read_quietly(tmp_path, layout, header):
    p = tmp_path / "lab.csv"
    p.write_text(
        "\n".join([HEADERS[header], *_rows(HEADERS[header], LAYOUTS[layout], False)])
    )
    with pytest.warns(hf.DataWarning, match="decimal commas"):
        read_frfs(p)


@pytest.mark.parametrize("layout", sorted(LAYOUTS))
@pytest.mark.parametrize("header", sorted(HEADERS))
def test_the_same_files_with_decimal_points_read_quietly(tmp_path, layout, header):
    p = tmp_path / "lab.csv"
    p.write_text(
        "\n".join([HEADERS[header], *_rows(HEADERS[header], LAYOUTS[layout], True)])
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        (rec,) = read_frfs(p)
    assert list(rec.amplitude) == [float(f"{w}.{f}") for w, f in LAYOUTS[layout]]
