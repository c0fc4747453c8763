"""Readers: obspy detects our plug-ins; every bundled file is read or reported with a reason."""

from __future__ import annotations

import numpy as np
import obspy
import pytest

from pipeline.constants import G
from pipeline.errors import RecordFormatError
from pipeline.records import at2
from pipeline.records.listing import find_records
from pipeline.records.loader import load_record
from pipeline.records.side_files import read_declared_units, read_inventory
from pipeline.run.screening import Context, screen_record

FORMATS = {
    "peer-at2/RSN1063_NORTHR_RRS228.AT2": ("PEER_AT2", 1, 1991),
    "peer-at2/NGA_no_1063_RRS228.AT2": ("PEER_AT2", 1, 1991),
    "cosmos/CE23837.V1C": ("COSMOS", 3, 13400),
    "cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c": ("COSMOS", 1, 42000),
    "dmg/CE58667.V2": ("CSMIP_DMG", 3, 7500),
    "dmg/CICLC.v1": ("CSMIP_DMG", 3, 31932),
    "fn-ascii/rinaldi_fn.dat": ("NF_ASCII", 1, 2990),
    "knet/AOM0170806140843.NS": ("KNET", 1, 11500),
    "sac/20190706031952.CJ.T001230.HNE.sac": ("SAC", 1, 15001),
    "mseed/CI.CCC..HNE.mseed": ("MSEED", 1, 39000),
}


@pytest.mark.parametrize("rel", sorted(FORMATS))
def test_obspy_read_detects_format(records_dir, refused_dir, rel):
    fmt, ntr, npts = FORMATS[rel]
    st = obspy.read(str(records_dir / rel if (records_dir / rel).is_file() else refused_dir / rel))
    assert st[0].stats._format == fmt
    assert len(st) == ntr
    assert st[0].stats.npts == npts == len(st[0].data)


def test_at2_old_and_new_headers_give_same_layout(records_dir):
    new = obspy.read(str(records_dir / "peer-at2/RSN1063_NORTHR_RRS228.AT2"))[0]
    old = obspy.read(str(records_dir / "peer-at2/NGA_no_1063_RRS228.AT2"))[0]
    assert new.stats.at2.header_variant == "NGA-West2" and old.stats.at2.header_variant == "NGA-2005"
    assert new.stats.delta == old.stats.delta == 0.01
    # SOURCES.md: PGA 0.874 g (NGA-West2) and 0.825 g (2005 processing) for this record
    assert np.max(np.abs(new.data)) == pytest.approx(0.874, abs=5e-4)
    assert np.max(np.abs(old.data)) == pytest.approx(0.825, abs=5e-4)


def _screened(root, config, blocks_csv) -> tuple[list, set]:
    """Every record under ``root`` screened: the sources with their results, and the files they covered."""
    from pipeline.blocks import read_inventory as read_blocks

    sources, failures = find_records(root, config=config)
    assert failures == []
    ctx = Context(str(root), config, read_blocks(blocks_csv, default_mu=0.6), read_declared_units(root, config),
                  read_inventory(root))
    results = [(s, screen_record(s, ctx)) for s in sources]
    return results, {f for s, _ in results for f in s.files}


@pytest.mark.slow
def test_every_bundled_file_is_screened(records_dir, config, blocks_csv):
    """Every file under records/ (the demo's) ends in a screened record."""
    results, covered = _screened(records_dir, config, blocks_csv)
    for s, res in results:
        assert res.status == "ok", (s.record_id, res.status)
    data_files = {str(p) for p in records_dir.rglob("*") if p.is_file()
                  and p.suffix.lower() not in (".md", ".csv", ".xml", ".toml")}
    assert covered == data_files


def test_a_vertical_channel_alone_is_reported_not_screened(refused_dir, config, blocks_csv):
    """A real COSMOS file of a vertical channel alone (Point MacKenzie 2018, AK.BMR BNZ): read, then refused with
    its reason."""
    results, _ = _screened(refused_dir, config, blocks_csv)
    assert [(s.record_id, "vertical component only" in res.status) for s, res in results] == [
        ("us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc", True)]


# Header-stated peaks: AT2 older header 'PGA=' [g]; K-NET 'Max. Acc.' [gal]; DMG V2 'Peak acceleration'.
HEADER_PEAKS = [
    ("pulse-reference/example1.AT2", "pulse-reference/example2.AT2"),
    ("knet/AOM0170806140843.NS", "knet/AOM0170806140843.EW", "knet/AOM0170806140843.UD"),
    ("knet/test.knet",),
    ("kiknet/AICH040010061330.NS2", "kiknet/AICH040010061330.EW2", "kiknet/AICH040010061330.UD2"),
    ("dmg/CE58667.V2",),
]


@pytest.mark.parametrize("files", HEADER_PEAKS, ids=lambda f: f[0].split("/")[-1])
def test_pga_matches_header_within_half_percent(make_records, config, files):
    root = make_records(*files)
    sources, _ = find_records(root, config=config)
    assert len(sources) == 1
    rec = load_record(sources[0], root=root, config=config)
    series = list(rec.horizontal_ms2) + ([rec.vertical_ms2] if rec.vertical_ms2 is not None else [])
    assert rec.header_peaks_ms2, "the header states a peak"
    for code, data in zip(rec.component_codes, series):
        assert np.max(np.abs(data)) == pytest.approx(rec.header_peaks_ms2[code], rel=5e-3), code


# Independent values: SOURCES.md "PGA (g, computed)" by the data curator.
SOURCES_PGA_G = [
    ("mseed/CI.CCC..HNE.mseed", "mseed/CI.CCC.xml", "HNE", 0.565),   # counts -> StationXML response
    ("mseed/CI.CCC..HNN.mseed", "mseed/CI.CCC.xml", "HNN", 0.470),
    ("sac/20190706031952.CJ.T001230.HNE.sac", None, "HNE", 0.021),  # declared g in units.toml
    ("fn-ascii/rinaldi_fn.dat", None, "FN", 0.890),                 # declared cm/s**2
    ("cosmos/CE23837.V1C", None, "HNN", 0.105),                     # COSMOS V1, g
    ("dmg/CICLC.v1", None, "000", 0.511),                           # DMG V1, g
    ("peer-at2/RSN1086_NORTHR_SYL360.AT2", None, "360", 0.843),
]


@pytest.mark.parametrize("rel,xml,code,pga_g", SOURCES_PGA_G, ids=lambda v: str(v).split("/")[-1])
def test_component_pga_matches_independent_values(make_records, config, rel, xml, code, pga_g):
    root = make_records(rel, *( [xml] if xml else []))
    sources, _ = find_records(root, config=config)
    rec = load_record(sources[0], root=root, config=config, inventory=read_inventory(root))
    idx = rec.component_codes.index(code)
    data = rec.horizontal_ms2[idx] if idx < rec.horizontal_ms2.shape[0] else rec.vertical_ms2
    assert np.max(np.abs(data)) / G == pytest.approx(pga_g, rel=1e-2, abs=6e-4)


def test_at2_truncated_file_names_file_and_counts(tmp_path, records_dir):
    text = (records_dir / "peer-at2/RSN1063_NORTHR_RRS228.AT2").read_text().splitlines()
    bad = tmp_path / "cut.AT2"
    bad.write_text("\n".join(text[:100]) + "\n")
    with pytest.raises(RecordFormatError, match=r"cut\.AT2.*NPTS=1991.*truncated"):
        at2._read_at2(str(bad))


def test_at2_non_numeric_sample_names_line(tmp_path, records_dir):
    text = (records_dir / "peer-at2/RSN1063_NORTHR_RRS228.AT2").read_text().splitlines()
    text[9] = text[9][:10] + "  abc  " + text[9][17:]
    bad = tmp_path / "bad.AT2"
    bad.write_text("\n".join(text) + "\n")
    with pytest.raises(RecordFormatError, match=r"line 10: 'abc' is not a number"):
        at2._read_at2(str(bad))


@pytest.mark.parametrize("lines, expected", [
    (["  1.5D-03  2.0d+01", "-3E2 4"], [1.5e-3, 20.0, -300.0, 4.0]),      # Fortran D exponents, either case
    (["0.1 0.2", "", "   0.3"], [0.1, 0.2, 0.3]),                            # blank lines carry nothing
])
def test_free_format_numbers_parse_as_python_floats(lines, expected):
    from pipeline.records._text import parse_free_floats

    got = parse_free_floats(lines, name="x.AT2", first_line_no=5)
    assert got.tolist() == expected              # exact: the same correctly rounded floats as float()


def test_free_format_bad_token_names_its_line_after_a_d_exponent():
    from pipeline.records._text import parse_free_floats

    with pytest.raises(RecordFormatError, match=r"x\.AT2, line 6: '1\.0x' is not a number"):
        parse_free_floats(["1.0D0 2.0", "1.0x 3.0"], name="x.AT2", first_line_no=5)


@pytest.mark.parametrize("files, label", [
    (("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2"),
     "Northridge-01, 1/17/1994, Rinaldi Receiving Sta"),
    (("pulse-reference/example1.AT2", "pulse-reference/example2.AT2"),
     "IMPERIAL VALLEY 10/15/79 2316, El Centro Array #4"),
    (("fn-ascii/sylmar_fn.dat",), "sylm n Northridge,17 Jan 94,04:31PST; Sylmar, Olive View FF"),
    (("knet/test.knet",), "BO.AKT013 1996-08-10"),
    (("dmg/CICLC.v1",), "CI.CLC 2019-07-06"),
])
def test_a_record_carries_the_station_and_earthquake_its_files_name(make_records, config, files, label):
    """Records are known by their file names ('example', 'test'); the report also shows what the files say."""
    root = make_records(*files)
    assert load_record(find_records(root, config=config)[0][0], root=root, config=config).label == label


@pytest.mark.parametrize("name", ["rec[1].AT2", "rec*.AT2", "rec?.AT2"])
def test_a_record_whose_name_has_wildcards_is_read_as_itself(tmp_path, records_dir, config, name):
    """obspy expands a path's wildcards: a record named with them is read as the file it is, not as the files its
    name matches (here a second record beside it that the pattern would match too)."""
    import shutil

    shutil.copy(records_dir / "peer-at2/RSN1063_NORTHR_RRS228.AT2", tmp_path / name)
    shutil.copy(records_dir / "peer-at2/RSN77_SFERN_PUL164.AT2", tmp_path / "rec1.AT2")
    sources, failures = find_records(tmp_path, config=config)
    assert failures == [] and len(sources) == 2
    source = next(s for s in sources if any(str(f).endswith(name) for f in s.files))
    rec = load_record(source, root=tmp_path, config=config)
    plain = tmp_path / "plain"
    plain.mkdir()
    shutil.copy(records_dir / "peer-at2/RSN1063_NORTHR_RRS228.AT2", plain / "one.AT2")
    direct = load_record(find_records(plain, config=config)[0][0], root=plain, config=config)
    assert rec.horizontal_ms2.shape == direct.horizontal_ms2.shape
    assert np.array_equal(rec.horizontal_ms2, direct.horizontal_ms2)
