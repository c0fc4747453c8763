"""Plain text tables of one motion (pipeline.records.table): one column with a '#' header, two columns of time and
acceleration (comma, tab or space), gzip or not; bad tables are refused naming the line and the fix; the bundled
records are never taken for tables; and a table's DC offset is removed by the processing."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import obspy
import pytest

from pipeline.config import Config
from pipeline.errors import RecordFormatError
from pipeline.records.detect import detect_format
from pipeline.records.loader import iter_records
from pipeline.records.table import _is_table

GRANITE = Path(__file__).resolve().parents[3] / "shared" / "experiments" / "granite-pbr" / "motions"
G = 9.80665


def _motion(n=1200, dt=0.01):
    t = np.arange(n) * dt
    return t, 0.25 * np.sin(2 * np.pi * 1.5 * t) * np.exp(-((t - 5.0) / 2.0) ** 2)


def _record_of(tmp_path, header: str, values):
    """The screening's record of a one-column table with ``header`` (read and processed)."""
    root = tmp_path / "recs"
    root.mkdir()
    (root / "table.txt").write_text(header + "\n" + "".join(f"{x:.7f}\n" for x in values))
    return next(iter_records(root, config=Config()))


@pytest.mark.parametrize("sep", [",", "\t", "  "])
def test_two_columns_give_the_interval_from_the_times(tmp_path, sep):
    t, a = _motion()
    path = tmp_path / "run.csv"
    path.write_text("time" + sep + "acc\n" + "".join(f"{ti:.2f}{sep}{ai:.7f}\n" for ti, ai in zip(t, a)))
    assert detect_format(path) == "TABLE"
    tr = obspy.read(str(path), format="TABLE")[0]
    assert tr.stats.delta == pytest.approx(0.01, rel=1e-12) and tr.stats.npts == t.size
    assert np.allclose(tr.data, a, atol=1e-7) and tr.stats.physical_units is None


def test_one_column_takes_the_interval_units_and_component_from_its_header(tmp_path):
    _, a = _motion()
    body = "# rig=A dt_s=0.01 units=cm/s**2 n=1200\n" + "".join(f"{x:.6f}\n" for x in 100 * a)
    plain, packed = tmp_path / "a.txt", tmp_path / "b.acc.gz"
    plain.write_text(body)
    packed.write_bytes(gzip.compress(body.encode()))
    for path in (plain, packed):
        tr = obspy.read(str(path), format="TABLE")[0]
        assert tr.stats.delta == 0.01 and tr.stats.physical_units == "cm/s**2" and tr.stats.channel == "H1"
        assert np.allclose(tr.data, 100 * a, atol=1e-6)
    vertical = tmp_path / "v.txt"
    vertical.write_text("# dt_s=0.01 units=g component=UP\n" + "".join(f"{x:.6f}\n" for x in a))
    assert obspy.read(str(vertical), format="TABLE")[0].stats.channel == "UP"


@pytest.mark.parametrize("text,match", [
    ("".join(f"{x}\n" for x in range(20)), r"no sampling interval; add a header line '# dt_s="),
    ("# dt_s=0.01 n=25\n" + "".join(f"{x}\n" for x in range(20)), r"n=25 samples, the table holds 20"),
    ("".join(f"{0.01 * k + (0.004 if k == 13 else 0):.3f},{k}\n" for k in range(20)), r"line 14: .*not evenly sampled"),
    ("# dt_s=0.01\n" + "".join(f"{x}\n" for x in range(10)) + "1.0 2.0\n" + "".join(f"{x}\n" for x in range(5)),
     r"line 12: .*expected 1 number"),
    ("# dt_s=0.01 units=furlongs\n" + "".join(f"{x}\n" for x in range(20)), r"unknown acceleration unit"),
])
def test_bad_tables_are_refused_naming_the_line_and_the_fix(tmp_path, text, match):
    path = tmp_path / "bad.txt"
    path.write_text(text)
    with pytest.raises((RecordFormatError, ValueError), match=match):
        obspy.read(str(path), format="TABLE")


def test_no_bundled_record_is_taken_for_a_table(records_dir):
    for path in sorted(p for p in records_dir.rglob("*") if p.is_file() and p.name != "units.toml"):
        assert detect_format(path) != "TABLE", path


@pytest.mark.parametrize("text", ["a,b\n1,2\n", "# only a header\n", "x y z\n" + "1 2 3\n" * 20,
                                  "1 2 3\n" * 20, "hello world\n" * 20])
def test_what_is_not_a_table(tmp_path, text):
    path = tmp_path / "x.txt"
    path.write_text(text)
    assert not _is_table(str(path))


def test_a_tables_dc_offset_is_removed_by_the_processing(tmp_path):
    _, a = _motion(n=3000)
    rec = _record_of(tmp_path, "# dt_s=0.01 units=g", a + 0.02)
    h = rec.horizontal_ms2[0]
    assert abs(float(np.mean(h))) < 1e-3 * G                 # the 0.02 g offset is gone
    assert np.max(np.abs(h)) == pytest.approx(0.25 * G, rel=0.05)


@pytest.mark.skipif(not GRANITE.is_dir(), reason="the granite shake-table data (../shared/experiments) is absent")
def test_a_shake_table_motion_reads_as_written():
    path = GRANITE / "Test011.acc.gz"
    tr = obspy.read(str(path))[0]
    expected = np.loadtxt(path)
    assert tr.stats.delta == 0.00125 and tr.stats.physical_units == "g" and tr.stats.npts == expected.size
    assert np.array_equal(tr.data, expected)


def test_a_tables_component_may_give_its_azimuth(tmp_path):
    _, a = _motion(n=2000)
    rec = _record_of(tmp_path, "# dt_s=0.01 units=g component=35", a)
    assert rec.single_component and rec.azimuth_known and rec.azimuths_deg == (35.0,)


def test_a_byte_order_mark_is_not_part_of_the_table(tmp_path):
    """Windows programs write a UTF-8 byte-order mark first: the table reads as the same table without it."""
    t, a = _motion()
    text = "# dt_s=0.01 units=g\n" + "".join(f"{x:.7f}\n" for x in a)
    (tmp_path / "plain.txt").write_bytes(text.encode())
    (tmp_path / "bom.txt").write_bytes(b"\xef\xbb\xbf" + text.encode())
    assert _is_table(tmp_path / "bom.txt")
    plain, bom = (obspy.read(str(tmp_path / n), format="TABLE")[0] for n in ("plain.txt", "bom.txt"))
    assert bom.stats.delta == plain.stats.delta and bom.stats.physical_units == "g"
    np.testing.assert_array_equal(bom.data, plain.data)


def test_a_gzip_bomb_is_refused_by_the_row_limit_in_bounded_memory(tmp_path):
    """A 1 MB gzip table that expands to about 180 MB of rows is refused at the row limit, named; the reader reads
    it as a stream, so its memory is the rows it kept (independent reading: tracemalloc's peak)."""
    import tracemalloc

    path = tmp_path / "bomb.txt.gz"
    with gzip.open(path, "wb", compresslevel=1) as fh:
        fh.write(b"# dt_s=0.01 units=g\n")
        for _ in range(200):
            fh.write(b"0.000000\n" * 100_000)
    assert path.stat().st_size < 2_000_000
    tracemalloc.start()
    with pytest.raises(RecordFormatError, match=r"bomb\.txt\.gz: more than 10,000 rows.*max_samples"):
        obspy.read(str(path), format="TABLE", check_compression=False, max_rows=10_000)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 5_000_000


def test_the_run_reads_a_table_to_its_max_samples(tmp_path):
    """The row limit is the run's [records] max_samples: a 2,000-row table fails alone under max_samples 1,000."""
    import dataclasses

    root = tmp_path / "recs"
    root.mkdir()
    (root / "long.txt").write_text("# dt_s=0.01 units=g\n" + "0.001\n" * 2000)
    cfg = Config()
    cfg = dataclasses.replace(cfg, records=dataclasses.replace(cfg.records, max_samples=1000))
    from pipeline.records.listing import find_records

    sources, failures = find_records(root, config=cfg)
    assert not sources and len(failures) == 1
    assert "long.txt: more than 1,000 rows" in failures[0].reason


def _rows_text(n: int, *, two: bool = True, seed: int = 1) -> list[str]:
    rng = np.random.default_rng(seed)
    return [f"{0.01 * i:.2f},{x:.7f}" if two else f"{x:.7f}" for i, x in enumerate(rng.uniform(-1, 1, n))]


def _edge_cases() -> dict[str, tuple[bytes, str]]:
    """Tables whose lines the block reader must take as the line-by-line reader does: the bytes, and what the file
    gives (``rows``, or the start of the error's message after the file's name)."""
    rows = _rows_text(20_000)
    body = "\n".join(rows) + "\n"
    bad, narrow = list(rows), list(rows)
    bad[17_777], narrow[12_345] = "1.0,abc", "0.5"
    one = "".join(f"{x}\n" for x in _rows_text(9_000, two=False))
    return {
        "names and two columns": (("time,acc\n" + body).encode(), "rows"),
        "CRLF line ends": (("# units=g\n" + body).replace("\n", "\r\n").encode(), "rows"),
        "Fortran D exponents": (("# dt_s=0.01\n" + one.replace("e", "D")).encode(), "rows"),
        "a header line and a blank line among the rows": (("# units=g\n" + "\n".join(rows[:15_000]) + "\n# dt=1\n\n"
                                                           + "\n".join(rows[15_000:]) + "\n").encode(), "rows"),
        "a bad number far down": (("# units=g\n" + "\n".join(bad) + "\n").encode(), ", line 17779: '1.0,abc'"),
        "one number where two were": (("# units=g\n" + "\n".join(narrow) + "\n").encode(), ", line 12347: '0.5'"),
        "no newline at the end": (("# units=g\n" + body.rstrip("\n")).encode(), "rows"),
        "separators after the last column": (("# units=g\n" + body.replace("\n", ",\n")).encode(), "rows"),
        "a byte-order mark": (b"\xef\xbb\xbf" + ("# dt_s=0.01\n" + one).encode(), "rows"),
        "a no-break space after each number": (("# dt_s=0.01\n" + one.replace("\n", "\xa0\n")).encode("latin-1"),
                                               "rows"),
        "a line of 4,095 bytes and its newline": (("# dt_s=0.01\n" + "1\n" * 100 + "2" * 4095 + "\n1\n").encode(),
                                                  "rows"),
        "a line of 4,096 bytes and its newline": (("# dt_s=0.01\n" + "1\n" * 100 + "2" * 4096 + "\n1\n").encode(),
                                                  ", line 102: longer than 4,096 bytes"),
        "a last line of 4,096 bytes": (("# dt_s=0.01\n" + "1\n" * 100 + "2" * 4096).encode(), "rows"),
        "a last line of 4,097 bytes": (("# dt_s=0.01\n" + "1\n" * 100 + "2" * 4097).encode(),
                                       ", line 102: longer than 4,096 bytes"),
        "a line that never ends": (("# dt_s=0.01\n" + "1\n" * 30_000 + "3" * 200_000).encode(),
                                   ", line 30002: longer than 4,096 bytes"),
        "more rows than the limit": (("# dt_s=0.01\n" + "0.1\n" * 70_000).encode(), ": more than 65,000 rows"),
    }


@pytest.mark.parametrize("case", list(_edge_cases()))
@pytest.mark.parametrize("packed", [False, True])
def test_blocks_of_rows_read_as_the_same_lines_one_by_one(tmp_path, case, packed):
    """The reader takes a block of plain rows in one pass and anything else line by line: every table reads as
    its lines taken one by one (the same values to the bit, header, width, first line and time stamps), and a bad
    line is refused with its own line number."""
    from table_lines import by_blocks, by_lines

    data, expected = _edge_cases()[case]
    data = gzip.compress(data) if packed else data
    path = tmp_path / ("t.txt.gz" if packed else "t.txt")
    path.write_bytes(data)
    got = by_blocks(path, max_rows=65_000)
    assert got == by_lines(data, str(path), max_rows=65_000)
    if expected == "rows":
        assert got[0] == "rows" and len(got[1]) > 0
    else:
        assert got[0] == "error" and got[1].startswith(str(path) + expected), got[1]


@pytest.mark.slow                       # 25 s: the 246 motions read line by line
def test_the_granite_motions_read_as_their_lines_one_by_one():
    """Every shake-table motion of the granite tests (246 gzip tables of 1,000-32,000 rows) reads as its lines
    taken one at a time."""
    from table_lines import by_blocks, by_lines

    if not GRANITE.is_dir():
        pytest.skip(f"{GRANITE} not found: the granite shake-table tests are read from ../shared (not shipped)")
    for path in sorted(GRANITE.iterdir()):
        assert by_blocks(path) == by_lines(path.read_bytes(), str(path)), path.name
