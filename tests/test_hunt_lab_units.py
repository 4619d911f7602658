"""Frequency units of measured FRF families (stop 31 hunt).

Before: ``read_frfs`` dropped the unit a column name states
(``frequency_Hz``, ``omega_rad_s``), so records from a file in Hz and one
in rad/s were combined silently; one record of the paper's macroslip
family given in Hz (the same sweep, 50-300 rad/s as 7.96-47.7 Hz) was left
out of step 1 without a word (4 pairs compared instead of 5) and the
verdict came out as if all were there; a ``stuck_frequency`` in Hz for
records in rad/s (31.8 for 200) ended in ``"undecided"`` with no reason
(``undecided_reason`` None, the explanation "Verdict: undecided").

The family is the paper's SDOF scene by the describing function (plain
NumPy, :mod:`tests.test_criterion`): stuck resonance 200 rad/s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_criterion import RATIOS, SCENES, describing_function_frf

from hbmfric.criterion import FRFRecord, choose_contact_model, read_frfs, write_frfs

OMEGA = np.linspace(50.0, 300.0, 251)


@pytest.fixture(scope="module")
def family():
    p = SCENES["paper"]
    c = 2.0 * p["zeta"] * math.sqrt(p["k"] * p["m"])
    recs = []
    for force in (1.0, 1000.0):
        for ratio in RATIOS:
            fn = force / ratio

            def load(d, fn=fn):
                return np.minimum(p["kt"] * d, p["mu"] * fn)

            a = describing_function_frf(p["m"], c, p["k"], load, force, OMEGA)
            recs.append(FRFRecord(force, fn, OMEGA, a))
    return recs


def _in_hz(r):
    return FRFRecord(r.force, r.normal_load, r.omega / (2 * math.pi), r.amplitude)


def _write(path, records, column, scale=1.0):
    lines = [f"force,normal_load,{column},amplitude"]
    for r in records:
        lines += [
            f"{r.force:.17g},{r.normal_load:.17g},{w * scale:.17g},{a:.17g}"
            for w, a in zip(r.omega, r.amplitude, strict=True)
        ]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_files_in_hz_and_rad_s_are_not_combined(tmp_path, family):
    assert choose_contact_model(family).verdict == "macroslip without roughness"
    a = read_frfs(_write(tmp_path / "a.csv", family[:5], "omega_rad_s"))
    b = read_frfs(
        _write(tmp_path / "b.csv", family[5:], "frequency_Hz", 1 / (2 * math.pi))
    )
    assert {r.omega_unit for r in a} == {"rad/s"}
    assert {r.omega_unit for r in b} == {"Hz"}
    with pytest.raises(ValueError, match="different frequency units"):
        choose_contact_model(a + b)
    # the same files converted to one unit decide as the family does
    b_rad = [
        FRFRecord(r.force, r.normal_load, 2 * math.pi * r.omega, r.amplitude) for r in b
    ]
    res = choose_contact_model(a + b_rad)
    assert res.verdict == "macroslip without roughness"


@pytest.mark.parametrize("index", [0, 4, 9])
def test_one_record_in_hz_among_rad_s_is_refused(family, index):
    mix = [_in_hz(r) if i == index else r for i, r in enumerate(family)]
    with pytest.raises(ValueError, match="2π times the band"):
        choose_contact_model(mix)


def test_stuck_frequency_in_hz_for_records_in_rad_s(family):
    with pytest.raises(ValueError, match="stuck_frequency"):
        choose_contact_model(family, stuck_frequency=200.0 / (2 * math.pi))
    # below the band and not 2π off: undecided, and it says why
    res = choose_contact_model(family, stuck_frequency=20.0)
    assert res.verdict == "undecided"
    assert res.indicators["undecided_reason"] == "data"
    assert "below the band" in res.explanation


def test_round_trip_keeps_the_unit(tmp_path, family):
    recs = [
        FRFRecord(r.force, r.normal_load, r.omega, r.amplitude, omega_unit="hz")
        for r in family[:2]
    ]
    assert recs[0].omega_unit == "Hz"
    back = read_frfs(write_frfs(tmp_path / "w.csv", recs))
    assert [r.omega_unit for r in back] == ["Hz", "Hz"]
    with pytest.raises(ValueError, match="omega_unit"):
        FRFRecord(1.0, 1.0, OMEGA, family[0].amplitude, omega_unit="rpm")
