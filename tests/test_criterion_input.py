"""Input edges of the contact-model criterion: the size of the common grid
and CSV files as spreadsheets write them (byte-order mark, Latin-1,
semicolons, short rows, non-finite values)."""

from __future__ import annotations

import codecs

import numpy as np
import pytest

from hbmfric.criterion import FRFRecord, choose_contact_model, read_frfs

HEADER = "force,normal_load,omega,amplitude"


def small_family():
    w = np.linspace(1.0, 3.0, 40)
    return [
        FRFRecord(f, f / r, w, f / np.abs(4.0 - w**2 + 0.1j * w))
        for f in (1.0, 10.0)
        for r in (1.0, 0.1, 0.001)
    ]


def rows(force=1.0, load=2.0, n=6):
    return [f"{force},{load},{w},{0.5 + w}" for w in range(1, n + 1)]


def test_huge_n_grid_is_refused_before_any_allocation():
    # 10**8 grid points would need ~1 GB per curve and far more for the
    # smoother; the error must come before anything is allocated
    with pytest.raises(ValueError, match=r"n_grid must be an integer in \[50, 5000\]"):
        choose_contact_model(small_family(), n_grid=10**8)
    with pytest.raises(ValueError, match=r"n_grid.*\[50, 5000\]"):
        choose_contact_model(small_family(), n_grid=5_001)
    res = choose_contact_model(small_family(), n_grid=5_000)
    assert res.grid.size == 5_000


def test_excel_csv_utf8_with_byte_order_mark(tmp_path):
    p = tmp_path / "bom.csv"
    p.write_bytes(codecs.BOM_UTF8 + "\n".join([HEADER, *rows()]).encode("utf-8"))
    (rec,) = read_frfs(p)
    assert (rec.force, rec.normal_load) == (1.0, 2.0)
    np.testing.assert_array_equal(rec.omega, np.arange(1.0, 7.0))


def test_utf16_with_byte_order_mark_and_tabs(tmp_path):
    # Excel's "Unicode text": UTF-16 with a byte-order mark, tab separated
    p = tmp_path / "utf16.txt"
    text = "\n".join(
        [HEADER.replace(",", "\t")] + [r.replace(",", "\t") for r in rows()]
    )
    p.write_bytes(text.encode("utf-16"))
    (rec,) = read_frfs(p)
    np.testing.assert_array_equal(rec.amplitude, np.arange(1.5, 7.5))


def test_latin1_file(tmp_path):
    p = tmp_path / "latin1.csv"
    lines = [
        "# Prüfstand, 20 °C",
        "curve," + HEADER,
        *(f"Fn = 2 N (µ-test),{r}" for r in rows()),
    ]
    p.write_bytes("\n".join(lines).encode("latin-1"))
    (rec,) = read_frfs(p)
    assert rec.label == "Fn = 2 N (µ-test)"


def test_semicolon_separated(tmp_path):
    p = tmp_path / "semicolon.csv"
    p.write_text(
        "\n".join([HEADER.replace(",", ";")] + [r.replace(",", ";") for r in rows()])
    )
    (rec,) = read_frfs(p)
    assert rec.normal_load == 2.0


def test_short_row_names_file_and_line(tmp_path):
    p = tmp_path / "short.csv"
    lines = ["# a comment", HEADER + ",curve", *(r + ",a" for r in rows())]
    lines.insert(4, "1,2,3.5,4")  # line 5 of the file, no curve field
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"short\.csv: line 5: 4 field\(s\)"):
        read_frfs(p)


def test_bad_value_line_numbers_count_comments(tmp_path):
    p = tmp_path / "bad.csv"
    lines = ["# one", "# two", HEADER, *rows()]
    lines[5] = "1,2,3,x"  # line 6 of the file
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"bad\.csv: line 6: column 'amplitude'"):
        read_frfs(p)


def test_non_finite_value_names_the_line(tmp_path):
    p = tmp_path / "nan.csv"
    lines = [HEADER, *rows()]
    lines[3] = "1,2,3,nan"
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"nan\.csv: line 4: .*finite"):
        read_frfs(p)


def test_utf16_without_byte_order_mark_is_a_clear_error(tmp_path):
    p = tmp_path / "utf16le.csv"
    p.write_bytes("\n".join([HEADER, *rows()]).encode("utf-16-le"))
    with pytest.raises(ValueError, match="UTF-16 without a byte-order mark"):
        read_frfs(p)
