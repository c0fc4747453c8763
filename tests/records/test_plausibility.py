"""Records outside what ground motions have fail with the value named (or are screened with a warning when asked),
and every numeric edge of a header is a named error, never a traceback."""

from __future__ import annotations

import logging
import re

import pytest
from obspy import read

from pipeline.config import Config, config_from_dict
from pipeline.errors import ConfigError, RecordFormatError
from pipeline.records.listing import find_records
from pipeline.records.loader import load_record
from pipeline.records.plausibility import ImplausibleRecordError

PACOIMA = "peer-at2/RSN77_SFERN_PUL164.AT2"          # a real AT2 in g: NPTS= 4172, DT= .0100 SEC


def _at2(records_dir, tmp_path, *, header: str | None = None, spike_g: float | None = None,
         extra: int = 0):
    """The Pacoima AT2 with its line 4 replaced (``header``), one sample set to ``spike_g`` or ``extra`` values
    appended; its directory and its one record."""
    lines = (records_dir / PACOIMA).read_text().splitlines()
    if header is not None:
        lines[3] = header
    if spike_g is not None:
        lines[200] = f"  {spike_g:.7E}" + lines[200][15:]
    lines += ["  .1000000E-02"] * extra
    root = tmp_path / "recs"
    root.mkdir()
    (root / "pacoima.AT2").write_text("\n".join(lines) + "\n")
    sources, failures = find_records(root, config=Config())
    return root, sources, failures


@pytest.mark.parametrize("dt", ["nan", "inf", "1e30", "1e-30", "0", "-.01"])
def test_a_header_interval_that_is_not_one_is_a_named_error(records_dir, tmp_path, dt):
    root, sources, failures = _at2(records_dir, tmp_path, header=f"NPTS=   4172, DT=   {dt} SEC,")
    # recognised as an AT2 file, and refused by name when its header is read (at the scan)
    assert not sources and len(failures) == 1
    assert re.search(r"line 4 \(DT\): sampling interval .* is not one", failures[0].reason)
    with pytest.raises(RecordFormatError, match=r"line 4 \(DT\): sampling interval .* is not one"):
        read(str(root / "pacoima.AT2"))


def test_a_spike_of_a_million_g_fails_naming_the_peak_and_the_setting(records_dir, tmp_path):
    root, sources, _ = _at2(records_dir, tmp_path, spike_g=1e6)
    with pytest.raises(ImplausibleRecordError, match=r"peak acceleration 1e\+06 g, more than 10 g \(\[records\] "
                                                     r"max_pga_g\).*units"):
        load_record(sources[0], root=root, config=Config())


def test_implausible_warn_screens_it_with_a_warning_and_a_note(records_dir, tmp_path, caplog):
    root, sources, _ = _at2(records_dir, tmp_path, spike_g=1e6)
    config = config_from_dict({"records": {"implausible": "warn"}})
    with caplog.at_level(logging.WARNING):
        rec = load_record(sources[0], root=root, config=config)
    assert any("is screened although" in r.getMessage() and "max_pga_g" in r.getMessage() for r in caplog.records)
    assert any("implausible, screened as asked" in n for n in rec.notes)


@pytest.mark.parametrize("limits, message", [({"max_samples": 1000}, r"4172 samples, more than 1000"),
                                             ({"max_duration_s": 30.0}, r"41.71 s long, more than 30 s"),
                                             ({"max_dt_s": 0.005}, r"sampling interval 0.01 s outside")])
def test_length_duration_and_interval_limits_are_settings(records_dir, tmp_path, limits, message):
    root, sources, _ = _at2(records_dir, tmp_path)
    assert load_record(sources[0], root=root, config=Config()).npts == 4172      # plausible by default
    with pytest.raises(ImplausibleRecordError, match=message):
        load_record(sources[0], root=root, config=config_from_dict({"records": limits}))


def test_values_beyond_the_headers_npts_are_said_not_dropped_silently(records_dir, tmp_path, caplog):
    root, sources, _ = _at2(records_dir, tmp_path, extra=7)
    with caplog.at_level(logging.WARNING):
        rec = load_record(sources[0], root=root, config=Config())
    assert rec.npts == 4172
    assert any("holds 7 value(s) after the NPTS=4172" in r.getMessage() for r in caplog.records)


def test_zeros_after_the_data_are_padding_and_pass_without_a_word(records_dir, tmp_path, caplog):
    lines = (records_dir / PACOIMA).read_text().splitlines() + ["  0.0000000E+00  0.0000000E+00"]
    root = tmp_path / "recs"
    root.mkdir()
    (root / "pacoima.AT2").write_text("\n".join(lines) + "\n")
    sources, _ = find_records(root, config=Config())
    with caplog.at_level(logging.WARNING):
        assert load_record(sources[0], root=root, config=Config()).npts == 4172
    assert not any("after the NPTS" in r.getMessage() for r in caplog.records)


def test_the_policy_is_checked():
    with pytest.raises(ConfigError, match="implausible"):
        config_from_dict({"records": {"implausible": "ignore"}})


def test_the_bundled_records_are_plausible(records_dir):
    """Every bundled record passes the default limits (their peaks are at most 1.2 g, their intervals 0.0024-0.02
    s, their lengths at most 32,000 samples): none fails as implausible."""
    from pipeline.errors import RockscreenError
    from pipeline.records.side_files import read_declared_units
    from pipeline.records.side_files import read_inventory as read_station_inventory

    config = Config()
    sources, _ = find_records(records_dir, config=config)
    declared, stationxml = read_declared_units(records_dir, config), read_station_inventory(records_dir, None)
    implausible, loaded = [], 0
    for src in sources:
        try:
            load_record(src, root=records_dir, config=config, declared=declared, inventory=stationxml)
            loaded += 1
        except ImplausibleRecordError as exc:
            implausible.append(f"{src.record_id}: {exc}")
        except RockscreenError:
            pass                                   # failing for another reason (the vertical-only file)
    assert loaded >= 35 and implausible == []


def test_a_record_too_long_is_refused_from_its_header_before_its_samples_are_read(records_dir, tmp_path,
                                                                                    monkeypatch):
    """Memory stays bounded: a header announcing more samples than max_samples fails before any sample is
    parsed (a 10-million-sample AT2 once took 816 MB before it was refused; now no more than a normal run)."""
    from pipeline.records import _text, at2

    root, sources, _ = _at2(records_dir, tmp_path)
    config = config_from_dict({"records": {"max_samples": 4000}})

    def no_parsing(*args, **kwargs):
        raise AssertionError("the samples were parsed")

    monkeypatch.setattr(at2, "parse_free_floats", no_parsing)
    monkeypatch.setattr(_text, "parse_free_floats", no_parsing)
    with pytest.raises(ImplausibleRecordError, match=r"4172 samples, more than 4000 \(\[records\] max_samples\)"):
        load_record(sources[0], root=root, config=config)


def test_a_file_larger_than_any_plausible_record_is_refused_before_it_is_read(records_dir, tmp_path, monkeypatch):
    from pipeline.records import loader

    root, sources, _ = _at2(records_dir, tmp_path)
    size = (root / "pacoima.AT2").stat().st_size
    config = config_from_dict({"records": {"max_samples": 100}})           # 80 x 3 x 100 = 24,000 bytes

    def no_reading(*args, **kwargs):
        raise AssertionError("the file was read")

    monkeypatch.setattr(loader, "read_stream", no_reading)
    with pytest.raises(ImplausibleRecordError, match=rf"{size:,} bytes, more than a file of 3 components of 100 "
                                                     r"samples takes \(24,000 bytes; \[records\] max_samples\)"):
        load_record(sources[0], root=root, config=config)
    # with implausible = "warn" it is read and screened, with a warning
    monkeypatch.undo()
    warned = config_from_dict({"records": {"max_samples": 100, "implausible": "warn"}})
    assert load_record(sources[0], root=root, config=warned).notes
