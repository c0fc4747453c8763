"""Grouping into station recordings, orientation, trimming, and units."""

from __future__ import annotations

import numpy as np
import pytest

from pipeline.config import config_from_dict
from pipeline.errors import RecordGroupingError, UnitsError
from pipeline.records.listing import find_records
from pipeline.records.loader import load_record
from pipeline.records.orientation import orientation_from_code
from pipeline.records.units import FACTORS_TO_MS2, canonical_units, factor_to_ms2


@pytest.mark.parametrize("code,vertical,azimuth,pair", [
    ("228", False, 228.0, None), ("360", False, 0.0, None), ("HNE", False, 90.0, None),
    ("HNN", False, 0.0, None), ("HNZ", True, None, None), ("NS2", False, 0.0, None),
    ("EW", False, 90.0, None), ("UD2", True, None, None), ("UP", True, None, None),
    ("V", True, None, None), ("L", False, None, 0), ("T", False, None, 1), ("FN", False, None, 0),
    ("FP", False, None, 1), ("HN1", False, None, 0), ("HN2", False, None, 1), ("H2", False, None, 1),
    # PEER NGA-West2 / NGA-East / NGA-Sub suffixes and header components, COSMOS, K-NET/KiK-net, SEED
    ("LN", False, None, 0), ("TR", False, None, 1), ("LONG", False, None, 0), ("TRAN", False, None, 1),
    ("R", False, None, 0), ("X", False, None, 0), ("Y", False, None, 1), ("H1", False, None, 0),
    ("N", False, 0.0, None), ("E", False, 90.0, None), ("S", False, 180.0, None), ("W", False, 270.0, None),
    ("NS", False, 0.0, None), ("NS1", False, 0.0, None), ("EW1", False, 90.0, None), ("UD1", True, None, None),
    ("DWN", True, None, None), ("DN", True, None, None), ("Z", True, None, None), ("VER", True, None, None),
    ("HHN", False, 0.0, None), ("BHE", False, 90.0, None), ("HLZ", True, None, None), ("000", False, 0.0, None),
    ("090", False, 90.0, None), ("NWH360", False, 0.0, None), ("E06140", False, 140.0, None),
    ("TCU052-E", False, 90.0, None), ("TCU052-V", True, None, None), ("BAM-L", False, None, 0),
    ("KJM_000", False, 0.0, None),
])
def test_orientation_codes(code, vertical, azimuth, pair):
    o = orientation_from_code(code)
    assert (o.vertical, o.azimuth_deg, o.pair_index) == (vertical, azimuth, pair)


def test_unknown_orientation_code_is_none():
    assert orientation_from_code("XYZW") is None


@pytest.mark.parametrize("files,n_files,codes,azimuths,known", [
    (("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2",
      "peer-at2/RSN1063_NORTHR_RRS-UP.AT2"), 3, ("228", "318", "UP"), (228.0, 318.0), True),
    # second horizontal must be 90 deg clockwise of the first: 270 then 0
    (("peer-at2/RSN292_ITALY_A-STU000.AT2", "peer-at2/RSN292_ITALY_A-STU270.AT2"), 2,
     ("270", "0"), (270.0, 0.0), True),
    (("peer-at2/RSN4040_BAM_BAM-L.AT2", "peer-at2/RSN4040_BAM_BAM-T.AT2",
      "peer-at2/RSN4040_BAM_BAM-V.AT2"), 3, ("L", "T", "V"), (0.0, 90.0), False),
    (("kiknet/AICH040010061330.NS2", "kiknet/AICH040010061330.EW2",
      "kiknet/AICH040010061330.UD2"), 3, ("NS2", "EW2", "UD2"), (0.0, 90.0), True),
    (("pulse-reference/example1.AT2", "pulse-reference/example2.AT2"), 2, ("140", "230"),
     (140.0, 230.0), True),
    (("dmg/CE58667.V2",), 1, ("H1", "H2", "UP"), (0.0, 90.0), False),
])
def test_grouping_and_orientation(make_records, config, files, n_files, codes, azimuths, known):
    root = make_records(*files)
    sources, failures = find_records(root, config=config)
    assert failures == [] and len(sources) == 1 and len(sources[0].files) == n_files
    rec = load_record(sources[0], root=root, config=config)
    assert rec.component_codes == codes
    assert rec.azimuths_deg == azimuths
    assert rec.azimuth_known is known


def _at2_copy(src, dst, *, component: str, npts: int | None = None) -> None:
    """A bundled AT2 file with another header component, optionally cut to ``npts`` samples."""
    lines = src.read_text().splitlines()
    fields = lines[1].split(",")
    lines[1] = ",".join(fields[:-1] + [f" {component}"])
    if npts is not None:
        values = " ".join(lines[4:]).split()[:npts]
        lines[3] = lines[3].replace(lines[3].split(",")[0], f"NPTS= {npts:6d}")
        lines = lines[:4] + [" ".join(values[k:k + 5]) for k in range(0, len(values), 5)]
    dst.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("first, second, known, pair_note", [
    ("LN", "TR", False, False),            # PEER longitudinal / transverse
    ("QX7", "QY9", False, True),           # codes no convention names: an orthogonal pair, flagged
])
def test_peer_suffix_pairs_and_unequal_lengths_are_screened(tmp_path, records_dir, config, first, second, known,
                                                            pair_note):
    src = records_dir / "peer-at2"
    _at2_copy(src / "RSN1063_NORTHR_RRS228.AT2", tmp_path / f"RSN1063_NORTHR_RRS-{first}.AT2", component=first)
    _at2_copy(src / "RSN1063_NORTHR_RRS318.AT2", tmp_path / f"RSN1063_NORTHR_RRS-{second}.AT2",
              component=second, npts=1600)       # 1991 and 1600 samples, no start times in the files
    sources, failures = find_records(tmp_path, config=config)
    assert failures == [] and len(sources) == 1
    rec = load_record(sources[0], root=tmp_path, config=config)
    assert rec.npts == 1600 and rec.horizontal_ms2.shape == (2, 1600)
    assert rec.azimuth_known is known and rec.azimuths_deg == (0.0, 90.0)
    assert any("aligned at their first sample" in n for n in rec.notes)
    assert any("not recognised" in n for n in rec.notes) is pair_note
    # the samples are those of the files, from the first one on
    full = load_record(find_records(records_dir / "peer-at2", config=config)[0][
        [s.record_id for s in find_records(records_dir / "peer-at2", config=config)[0]].index("RSN1063_NORTHR_RRS")],
        root=records_dir, config=config)
    assert rec.horizontal_ms2[0][:100] == pytest.approx(full.horizontal_ms2[0][:100], rel=1e-6, abs=1e-9)


def test_single_component_record_is_flagged(make_records, config):
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2")
    rec = load_record(find_records(root, config=config)[0][0], root=root, config=config)
    assert rec.single_component and "single horizontal component" in rec.notes


def test_lengths_within_20_samples_are_trimmed_with_note(make_records, config):
    root = make_records("peer-at2/RSN181_IMPVALL.H_H-E06140.AT2", "peer-at2/RSN181_IMPVALL.H_H-E06230.AT2",
                        "peer-at2/RSN181_IMPVALL.H_H-E06-UP.AT2")
    rec = load_record(find_records(root, config=config)[0][0], root=root, config=config)
    assert rec.npts == 7815  # 7817 / 7818 / 7815 in SOURCES.md
    assert any("7815" in n for n in rec.notes)


def _write_at2(path, comp, npts, dt, rng):
    vals = rng.normal(0, 0.01, npts)
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD", f"Test quake, 1/1/2000, Test Station, {comp}",
             "ACCELERATION TIME SERIES IN UNITS OF G", f"NPTS= {npts}, DT= {dt:.4f} SEC,"]
    lines += ["".join(f"{v:15.7E}" for v in vals[i:i + 5]) for i in range(0, npts, 5)]
    path.write_text("\n".join(lines) + "\n")


def test_length_mismatch_over_the_threshold_is_screened_with_a_warning(tmp_path, config, caplog):
    rng = np.random.default_rng(1)
    _write_at2(tmp_path / "TEST000.AT2", "0", 1000, 0.01, rng)
    _write_at2(tmp_path / "TEST090.AT2", "90", 1030, 0.01, rng)
    assert load_record(find_records(tmp_path, config=config)[0][0], root=tmp_path, config=config).npts == 1000
    assert "TEST000.AT2" in caplog.text and "max_length_mismatch_samples = 20" in caplog.text
    caplog.clear()
    relaxed = config_from_dict({"records": {"max_length_mismatch_samples": 40}})
    assert load_record(find_records(tmp_path, config=relaxed)[0][0], root=tmp_path, config=relaxed).npts == 1000
    assert "max_length_mismatch_samples" not in caplog.text


def test_different_sampling_intervals_are_an_error(tmp_path, config):
    rng = np.random.default_rng(2)
    _write_at2(tmp_path / "TEST000.AT2", "0", 1000, 0.01, rng)
    _write_at2(tmp_path / "TEST090.AT2", "90", 1000, 0.005, rng)
    with pytest.raises(RecordGroupingError, match="different sampling intervals"):
        load_record(find_records(tmp_path, config=config)[0][0], root=tmp_path, config=config)


def test_non_orthogonal_pair_is_an_error(tmp_path, config):
    rng = np.random.default_rng(3)
    _write_at2(tmp_path / "TEST000.AT2", "0", 500, 0.01, rng)
    _write_at2(tmp_path / "TEST045.AT2", "45", 500, 0.01, rng)
    with pytest.raises(RecordGroupingError, match="not orthogonal"):
        load_record(find_records(tmp_path, config=config)[0][0], root=tmp_path, config=config)


@pytest.mark.parametrize("unit,factor", [("g", 9.80665), ("mg", 9.80665e-3), ("cm/s**2", 0.01),
                                         ("gal", 0.01), ("m/s**2", 1.0), ("mm/s**2", 1e-3)])
def test_unit_factors(unit, factor):
    # 1 mg = 0.98 cm/s^2 (gmprocess's table got this wrong by a factor of 100)
    assert factor_to_ms2(unit, g_ms2=9.80665) == pytest.approx(factor, rel=1e-15)


def test_unknown_declared_unit_lists_valid_ones():
    with pytest.raises(UnitsError, match=r"unknown acceleration unit 'furlongs'.*cm/s\*\*2"):
        canonical_units("furlongs", where="units.toml")
    assert set(FACTORS_TO_MS2) <= {"m/s**2", "cm/s**2", "gal", "mm/s**2"}


def test_sac_without_declaration_is_an_error_naming_the_fix(make_records, config):
    root = make_records("sac/20190706031952.CJ.T001230.HNE.sac", units_toml=False)
    with pytest.raises(UnitsError, match=r"idep=IACC.*units\.toml"):
        load_record(find_records(root, config=config)[0][0], root=root, config=config)


def test_counts_without_response_is_an_error(make_records, config):
    root = make_records("mseed/CI.CCC..HNE.mseed", units_toml=False)
    with pytest.raises(UnitsError, match="StationXML"):
        load_record(find_records(root, config=config)[0][0], root=root, config=config)


def test_declaration_conflicting_with_file_is_an_error(make_records, config):
    root = make_records("peer-at2/RSN77_SFERN_PUL164.AT2", units_toml=False)
    (root / "units.toml").write_text('[files]\n"peer-at2/*.AT2" = "cm/s**2"\n')
    with pytest.raises(UnitsError, match="states units 'g' but units.toml declares"):
        load_record(find_records(root, config=config)[0][0], root=root, config=config)


def test_history_records_conversion_and_steps(make_records, config):
    root = make_records("knet/AOM0170806140843.NS", "knet/AOM0170806140843.EW")
    rec = load_record(find_records(root, config=config)[0][0], root=root, config=config)
    text = "\n".join(rec.history)
    assert "calib" in text and "detrend" in text and "filter" in text and "integrate" in text
