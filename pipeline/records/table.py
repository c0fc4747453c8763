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


def _header(lines: list[str]) -> dict[str, str]:
    """The ``key=value`` pairs of the ``#`` lines (lower-case keys)."""
    pairs: dict[str, str] = {}
    for line in lines:
        if line.lstrip().startswith("#"):
            pairs.update({k.lower(): v for k, v in _PAIR.findall(line)})
    return pairs


def _interval(times: np.ndarray, *, name: str, first_line: int, text: list[str]) -> float:
    """The mean step of a time column, checked uniform to its printed precision."""
    n = times.size
    if n < 2:
        raise RecordFormatError(f"{name}: one sample; expected a time series")
    dt = (times[-1] - times[0]) / (n - 1)
    check_interval(dt, name=name, where="the time column")
    decimals = max((len(t.split(".")[1].split("e")[0].split("E")[0]) if "." in t else 0) for t in text[:200])
    allowed = max(0.5 * 10.0 ** -decimals, 1e-6 * dt) * 1.001
    dev = np.abs(times - (times[0] + dt * np.arange(n)))
    k = int(np.argmax(dev))
    if dev[k] > allowed:
        raise RecordFormatError(f"{name}, line {first_line + k}: time {times[k]:g} s is {dev[k]:.3g} s off an even "
                                f"step of {dt:.6g} s; the table is not evenly sampled: resample it (or give one "
                                "column of samples with '# dt_s=...')")
    return float(dt)


def _read_table(filename, headonly: bool = False, max_rows: int = MAX_ROWS, **kwargs) -> Stream:
    """Read a one- or two-column table (see the module), as a stream: at most ``max_rows`` data rows (the
    ``[records] max_samples`` of the run) and lines of at most :data:`MAX_LINE_BYTES` are read, so memory stays
    bounded whatever the file (a gzip bomb is refused by the row limit, named)."""
    name = source_name(filename)
    head: dict[str, str] = {}
    values = array("d")
    times: list[str] = []                              # the first time stamps as printed (their precision)
    width, first_line, n_rows, named = 0, 0, 0, False
    try:
        with _lines(filename) as stream:
            for k, raw in enumerate(iter(lambda: stream.readline(MAX_LINE_BYTES + 1), b""), start=1):
                if len(raw) > MAX_LINE_BYTES:
                    raise RecordFormatError(f"{name}, line {k}: longer than {MAX_LINE_BYTES:,} bytes; not a table "
                                            "of one or two numbers per line")
                line = (raw.removeprefix(UTF8_BOM) if k == 1 else raw).decode("latin-1")
                if line.lstrip().startswith("#"):
                    head.update({key.lower(): v for key, v in _PAIR.findall(line)})
                    continue
                if not line.strip():
                    continue
                fields = _fields(line)
                if not first_line and not named and not _is_numeric_row(fields):
                    named = True                                           # the column names
                    continue
                if not first_line:
                    width, first_line = len(fields), k
                if len(fields) != width or not _is_numeric_row(fields):
                    raise RecordFormatError(f"{name}, line {k}: {line.strip()!r}; expected {width} number(s) per "
                                            f"line like line {first_line}")
                n_rows += 1
                if n_rows > max_rows:
                    raise RecordFormatError(f"{name}: more than {max_rows:,} rows; a record that long is refused "
                                            "before it fills memory ([records] max_samples: raise it if the file "
                                            "is a real record)")
                if width == 2 and len(times) < TIME_TEXT_ROWS:
                    times.append(fields[0])
                values.extend(float(f.replace("D", "E").replace("d", "e")) for f in fields)
    except (OSError, EOFError, zlib.error) as exc:
        raise RecordFormatError(f"{name}: cannot be read ({exc})") from exc
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
