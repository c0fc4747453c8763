"""Plain text tables of one ground motion, as laboratories and instruments export them, as an obspy plug-in.

Two layouts, their columns separated by tabs, commas or spaces, optionally gzip-compressed:

* **two columns**: time [s] and acceleration; the sampling interval is the time column's mean step, which must
  be uniform to the precision the times are printed with (a table that is not evenly sampled is refused, the
  line named: resample it);
* **one column**: acceleration; the sampling interval comes from a header line.

Header lines start with ``#`` and may carry ``key=value`` pairs: ``dt_s`` (or ``dt``) the sampling interval [s],
``units`` the acceleration's units (``g``, ``m/s**2``, ``cm/s**2``, ``gal``...), ``n`` the number of samples
(checked), ``component`` what it records (``UP``, ``V`` or ``Z`` for a vertical, or a compass azimuth; without it,
one horizontal component of unknown azimuth, screened in its own plane). Without ``units`` the file's units must
be declared in ``units.toml`` (:mod:`.units`). A line of column names (``time,acc``) is skipped. A table is taken
as recorded, not processed (``processing_level`` uncorrected): the screening's processing for such records removes
the mean and the linear trend (so a DC offset of the table or the instrument goes), tapers the ends and
high-passes (``records.processing.uncorrected``).
"""

from __future__ import annotations

import contextlib
import gzip
import os
import re
import zlib
from array import array
from pathlib import Path

import numpy as np
from obspy import Stream, Trace, UTCDateTime
from obspy.core import AttribDict

from ..errors import RecordFormatError
from ._text import UTF8_BOM, check_interval, check_samples, source_name
from .common import COMMON, common_fields
from .units import canonical_units

#: Data lines a format check reads
PEEK_LINES = 40
#: Bytes a format check decompresses or reads
PEEK_BYTES = 65536
#: At least this many numeric rows make a table
MIN_ROWS = 8
_SEPARATOR = re.compile(r"[,\t; ]+")
_PAIR = re.compile(r"(\w+)\s*=\s*([^\s,;]+)")
_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?$")
#: Header keys of the sampling interval
DT_KEYS = ("dt_s", "dt", "delta")
#: The component a table is without a ``component=`` header: one horizontal (its azimuth unknown)
HORIZONTAL = "H1"
GZIP_MAGIC = b"\x1f\x8b"
#: The format's name among obspy's plug-ins (pyproject.toml's entry point)
TABLE_FORMAT = "TABLE"
#: The most rows a table is read to, unless the run says (its ``[records] max_samples``)
MAX_ROWS = 1_000_000
#: The longest line a table may have [bytes] (a number or two per line: a longer one is not a table)
MAX_LINE_BYTES = 4096
#: Time stamps kept as printed, to judge the time column's precision (:func:`_interval`)
TIME_TEXT_ROWS = 200
#: Bytes read at a time: a block whose lines are all plain rows of the table's width (:data:`_ROWS`) is parsed in
#: one pass, any other line by line; the same rows, values and errors either way (the 246 granite shake-table
#: motions, 1,000-32,000 rows each, read in 6.7 s against 21.4 s line by line, one process)
BLOCK_BYTES = 1 << 16
_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
_SEP = "[,\t; ]"
#: A plain row of one number and of two: what :func:`_fields` and :func:`_is_numeric_row` accept, less the rarer
#: spellings (another whitespace; a blank or ``#`` line), which go line by line
_ROWS = {1: re.compile(rf"{_SEP}*{_NUM}{_SEP}*\r?"), 2: re.compile(rf"{_SEP}*{_NUM}{_SEP}+{_NUM}{_SEP}*\r?")}
_TOKEN = re.compile(_NUM)


def _raw(source, limit: int | None = None) -> bytes:
    """The bytes of a path or file-like ``source`` (decompressed when gzip), at most ``limit`` of them."""
    with _lines(source) as fh:
        return fh.read(limit) if limit else fh.read()


@contextlib.contextmanager
def _lines(source):
    """A binary stream of a path or file-like ``source``, decompressed as read when it is gzip (a file-like source
    is left at the position it had)."""
    if isinstance(source, (str, os.PathLike)):
        with open(source, "rb") as fh:
            magic = fh.read(2)
            fh.seek(0)
            if magic == GZIP_MAGIC:
                with gzip.open(fh) as gz:
                    yield gz
            else:
                yield fh
        return
    pos = source.tell()
    magic = source.read(2)
    source.seek(pos)
    try:
        if magic == GZIP_MAGIC:
            with gzip.open(source) as gz:
                yield gz
        else:
            yield source
    finally:
        source.seek(pos)                       # a format check leaves the caller's file where it was


def _fields(line: str) -> list[str]:
    return [f for f in _SEPARATOR.split(line.strip()) if f]


def _is_numeric_row(fields: list[str]) -> bool:
    return 1 <= len(fields) <= 2 and all(_NUMBER.match(f) for f in fields)


def _is_table(filename) -> bool:
    """True for a text table of one or two numeric columns after optional ``#`` lines (never raises)."""
    try:
        raw = _raw(filename, PEEK_BYTES)
    except Exception:
        return False
    if b"\x00" in raw:
        return False
    lines = raw.removeprefix(UTF8_BOM).decode("latin-1").splitlines()
    rows, width, named = 0, 0, False
    for line in lines[:-1]:                       # the last may be cut by the peek
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        fields = _fields(line)
        if rows == 0 and not named and not _is_numeric_row(fields) and 1 <= len(fields) <= 2:
            named = True                          # one line of column names
            continue
        if not _is_numeric_row(fields) or (width and len(fields) != width):
            return False
        width, rows = len(fields), rows + 1
        if rows >= PEEK_LINES:
            break
    return rows >= MIN_ROWS


def _interval(times: np.ndarray, *, name: str, first_line: int, text: list[str]) -> float:
    """The mean step of a time column, checked uniform to its printed precision."""
    n = times.size
    if n < 2:
        raise RecordFormatError(f"{name}: one sample; expected a time series")
    dt = (times[-1] - times[0]) / (n - 1)
    check_interval(dt, name=name, where="the time column")
    decimals = max((len(t.split(".")[1].split("e")[0].split("E")[0]) if "." in t else 0) for t in text[:TIME_TEXT_ROWS])
    allowed = max(0.5 * 10.0 ** -decimals, 1e-6 * dt) * 1.001
    dev = np.abs(times - (times[0] + dt * np.arange(n)))
    k = int(np.argmax(dev))
    if dev[k] > allowed:
        raise RecordFormatError(f"{name}, line {first_line + k}: time {times[k]:g} s is {dev[k]:.3g} s off an even "
                                f"step of {dt:.6g} s; the table is not evenly sampled: resample it (or give one "
                                "column of samples with '# dt_s=...')")
    return float(dt)


class TableRows:
    """The rows of a table as its lines come, in order: its ``#`` header pairs, the line of column names, the rows'
    values and the first time stamps as printed; a line that is not a row of the table's width is refused, named."""

    def __init__(self, name: str, max_rows: int) -> None:
        self.name, self.max_rows = name, max_rows
        self.head: dict[str, str] = {}
        self.values = array("d")
        self.times: list[str] = []                       # the first time stamps as printed (their precision)
        self.width, self.first_line, self.n_rows, self.named = 0, 0, 0, False

    def block(self, k: int, text: str) -> None:
        """The lines of ``text`` (each ended by a newline), the first of them line ``k``."""
        if not self.first_line:                         # the header, the names and the first row, line by line
            lines = text.split("\n")[:-1]
            for i, line in enumerate(lines):
                self.line(k + i, line, ended=True)
                if self.first_line:
                    k, text = k + i + 1, "".join(f"{rest}\n" for rest in lines[i + 1:])
                    break
            else:
                return
        if text and not self._plain(text):
            for i, line in enumerate(text.split("\n")[:-1]):
                self.line(k + i, line, ended=True)

    def _plain(self, text: str) -> bool:
        """Take the block in one pass where every line is a plain row of the table's width, none too long and the
        row limit not passed; False (nothing taken) otherwise."""
        lines = text.split("\n")[:-1]
        n = len(lines)
        if self.n_rows + n > self.max_rows or max(map(len, lines)) + 1 > MAX_LINE_BYTES:
            return False                                # refused at its line, line by line
        if not all(map(_ROWS[self.width].fullmatch, lines)):
            return False
        tokens = _TOKEN.findall(text)
        if self.width == 2 and len(self.times) < TIME_TEXT_ROWS:
            self.times.extend(tokens[0:2 * (TIME_TEXT_ROWS - len(self.times)):2])
        if "d" in text or "D" in text:
            tokens = [t.replace("D", "E").replace("d", "e") for t in tokens]
        self.values.extend(map(float, tokens))
        self.n_rows += n
        return True

    def too_long(self, k: int) -> None:
        """Refuse line ``k``: longer than :data:`MAX_LINE_BYTES`."""
        raise RecordFormatError(f"{self.name}, line {k}: longer than {MAX_LINE_BYTES:,} bytes; not a table of one or "
                                "two numbers per line")

    def line(self, k: int, line: str, *, ended: bool) -> None:
        """Line ``k`` of the file, its newline removed (``ended``: it had one; the file's last line may not)."""
        name = self.name
        if len(line) + ended > MAX_LINE_BYTES:
            self.too_long(k)
        if line.lstrip().startswith("#"):
            self.head.update({key.lower(): v for key, v in _PAIR.findall(line)})
            return
        if not line.strip():
            return
        fields = _fields(line)
        if not self.first_line and not self.named and not _is_numeric_row(fields):
            self.named = True                                              # the column names
            return
        if not self.first_line:
            self.width, self.first_line = len(fields), k
        if len(fields) != self.width or not _is_numeric_row(fields):
            raise RecordFormatError(f"{name}, line {k}: {line.strip()!r}; expected {self.width} number(s) per line "
                                    f"like line {self.first_line}")
        self.n_rows += 1
        if self.n_rows > self.max_rows:
            raise RecordFormatError(f"{name}: more than {self.max_rows:,} rows; a record that long is refused before "
                                    "it fills memory ([records] max_samples: raise it if the file is a real record)")
        if self.width == 2 and len(self.times) < TIME_TEXT_ROWS:
            self.times.append(fields[0])
        self.values.extend(float(f.replace("D", "E").replace("d", "e")) for f in fields)


def _read_rows(stream, rows: TableRows) -> None:
    """Feed ``rows`` the lines of a binary ``stream`` by blocks of :data:`BLOCK_BYTES`; a line longer than
    :data:`MAX_LINE_BYTES` is refused as soon as that many of its bytes are in, so memory stays bounded."""
    carry, k = b"", 1
    raw = stream.read(max(BLOCK_BYTES, len(UTF8_BOM)))
    data = raw.removeprefix(UTF8_BOM)                              # the mark is not part of line 1
    while raw:
        buf = carry + data
        cut = buf.rfind(b"\n") + 1
        whole, carry = buf[:cut], buf[cut:]
        if whole:
            rows.block(k, whole.decode("latin-1"))
            k += whole.count(b"\n")
        if len(carry) > MAX_LINE_BYTES:                            # a line not ended within the limit
            rows.too_long(k)
        raw = data = stream.read(BLOCK_BYTES)
    if carry:                                                      # the last line, without its newline
        rows.line(k, carry.decode("latin-1"), ended=False)


def read_rows(filename, *, max_rows: int = MAX_ROWS) -> TableRows:
    """The rows of a table file (a path or file-like, gzip or not), read by blocks (:func:`_read_rows`)."""
    name = source_name(filename)
    rows = TableRows(name, max_rows)
    try:
        with _lines(filename) as stream:
            _read_rows(stream, rows)
    except (OSError, EOFError, zlib.error) as exc:
        raise RecordFormatError(f"{name}: cannot be read ({exc})") from exc
    return rows


def _read_table(filename, headonly: bool = False, max_rows: int = MAX_ROWS, **kwargs) -> Stream:
    """Read a one- or two-column table (see the module), as a stream: at most ``max_rows`` data rows (the
    ``[records] max_samples`` of the run) and lines of at most :data:`MAX_LINE_BYTES` are read, so memory stays
    bounded whatever the file (a gzip bomb is refused by the row limit, named)."""
    name = source_name(filename)
    rows = read_rows(filename, max_rows=max_rows)
    head, values, times, width, first_line = rows.head, rows.values, rows.times, rows.width, rows.first_line
    table = np.frombuffer(values, dtype=float).reshape(-1, width) if width else np.zeros((0, 1))
    if width == 2:
        dt = _interval(table[:, 0], name=name, first_line=first_line, text=times)
        acc = table[:, 1].copy()
    else:
        key = next((k for k in DT_KEYS if k in head), None)
        if key is None:
            raise RecordFormatError(f"{name}: one column of samples and no sampling interval; add a header line "
                                    "'# dt_s=0.005 units=g' (your values), or give two columns: time, acceleration")
        try:
            dt = float(head[key])
        except ValueError:
            raise RecordFormatError(f"{name}: header {key}={head[key]!r} is not a number of seconds") from None
        check_interval(dt, name=name, where=f"header {key}")
        acc = table[:, 0].copy() if width else np.zeros(0)
    if "n" in head and head["n"].isdigit() and int(head["n"]) != acc.size:
        raise RecordFormatError(f"{name}: the header says n={head['n']} samples, the table holds {acc.size}; the "
                                "file is truncated or the header is wrong")
    units = canonical_units(head["units"], where=f"{name}: header units=") if "units" in head else None
    stem = Path(name).name.split(".")[0]
    component = head.get("component", HORIZONTAL)
    stats = {"network": "", "station": stem[:16], "location": "", "channel": component.upper(), "delta": dt,
             "starttime": UTCDateTime(0), "npts": acc.size, "table": AttribDict(header=dict(head)),
             COMMON: common_fields(time_known=False, standalone=True, label=stem,
                                   units_unstated="" if units else "a text table without a 'units=' header"),
             "physical_units": units, "processing_level": "uncorrected"}
    if headonly:
        return Stream([Trace(header=stats)])
    return Stream([Trace(data=check_samples(acc, npts=acc.size, name=name), header=stats)])
