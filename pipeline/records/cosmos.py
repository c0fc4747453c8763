"""COSMOS strong-motion data format (v01.20) V1/V2 files as an obspy plug-in.

Each channel is: text header lines (their count is stated in line 1),
an integer header (``N Integer-header values follow on M lines, Format= (10I8)``),
a real header (``... Format= (6F13.6)`` or ``(5F15.6)``), comment lines
starting with ``|``, then the data line
``13400 acceleration pts, approx 67 secs, units=g. (02)Format=(8f9.6)``
and the fixed-width samples, closed by ``End-of-data for ...``.
Files may hold several channels in sequence (V1C).

Header words used (1-based, as in the COSMOS v01.20 tables): Int(40) year,
Int(41) day of year, Int(44) hour, Int(45) minute; Real(30) second,
Real(62) sampling interval [ms]. Channel orientation is read from text
line 9 (``Sta Chan  1: 360 deg``), else from the ``<SCNL>`` comment's
channel code. Values are returned as stored; ``stats.physical_units`` names
their units.

References
----------
COSMOS Strong Motion Data Format, version 1.20 (Consortium of Organizations
for Strong-Motion Observation Systems, 2001).
"""

from __future__ import annotations

import re

from obspy import Stream, Trace, UTCDateTime
from obspy.core import AttribDict

from ..errors import RecordFormatError
from ._text import check_interval, check_samples, parse_fixed_floats, peek_lines, read_lines, source_name
from .common import COMMON, codes_label, common_fields

_FIRST_LINE = re.compile(r"\(Format v(\d+\.\d+) with (\d+) text lines\)", re.I)
_BLOCK_HEAD = re.compile(
    r"^\s*(\d+)\s+(Integer|Real)-header values follow on\s+(\d+)\s+lines?,\s*Format\s*=\s*"
    r"\((\d+)([IF])(\d+)(?:\.\d+)?\)",
    re.I,
)
_COMMENTS = re.compile(r"^\s*(\d+)\s+Comment line\(s\) follow", re.I)
_DATA_HEAD = re.compile(
    r"^\s*(\d+)\s+(acceleration|velocity|displacement)\s+pts.*units\s*=\s*([^,(. ]+).*"
    r"Format\s*=\s*\((\d+)[EeFf](\d+)\.\d+\)",
    re.I,
)
_SCNL = re.compile(r"<SCNL>\s*(\S+)")
_ORIENT = re.compile(r"Sta Chan\s+\S+:\s*(\d+)\s*deg|Sta Chan\s+\S+:\s*(Up|Down)", re.I)
_UNITS = {"g": "g", "cm/sec2": "cm/s**2", "cm/s2": "cm/s**2", "cm/sec/sec": "cm/s**2",
          "gal": "cm/s**2", "m/sec2": "m/s**2", "m/s2": "m/s**2", "counts": "counts"}
MISSING = -999


def _is_cosmos(filename) -> bool:
    """Return True if ``filename`` starts like a COSMOS v01.xx file (never raises)."""
    lines = peek_lines(filename, 1)
    return bool(lines) and _FIRST_LINE.search(lines[0]) is not None


def _read_block(lines, i, name):
    """Parse one integer or real header block starting at line index ``i``."""
    m = _BLOCK_HEAD.match(lines[i]) if i < len(lines) else None
    if not m:
        raise RecordFormatError(
            f"{name}, line {i + 1}: expected an 'Integer-/Real-header values follow' line, "
            f"found {lines[i].strip()[:60]!r}" if i < len(lines) else f"{name}: file ends inside a header"
        )
    count, n_lines, width = int(m.group(1)), int(m.group(3)), int(m.group(6))
    values = parse_fixed_floats(lines[i + 1:i + 1 + n_lines], width=width, count=count,
                                name=name, first_line_no=i + 2)
    return values, i + 1 + n_lines


def _start_time(ints, reals) -> UTCDateTime | None:
    year, jday, hour, minute = (int(ints[k - 1]) for k in (40, 41, 44, 45))
    second = float(reals[30 - 1])
    if MISSING in (year, jday, hour, minute) or second == MISSING:
        return None
    return UTCDateTime(year=year, julday=jday, hour=hour, minute=minute) + second


def _read_cosmos(filename, headonly: bool = False, **kwargs) -> Stream:
    """Read every channel of a COSMOS V1/V2 file.

    Returns
    -------
    obspy.Stream
        One trace per channel, values as stored, units in
        ``stats.physical_units``, headers in ``stats.cosmos``.

    Raises
    ------
    RecordFormatError
        Malformed header, missing data line, truncated data.
    """
    name = source_name(filename)
    lines = read_lines(filename)
    traces = []
    i = 0
    while i < len(lines):
        if not lines[i].strip():
            i += 1
            continue
        trace, i = _channel(lines, i, name, headonly)
        if trace is not None:
            traces.append(trace)
        if i < len(lines) and lines[i].lower().startswith("end-of-data"):
            i += 1
    if not traces:
        raise RecordFormatError(f"{name}: no COSMOS acceleration channel found")
    return Stream(traces)


def _channel(lines: list[str], i: int, name: str, headonly: bool) -> tuple[Trace | None, int]:
    """The channel whose header starts at line ``i`` (None for a velocity or displacement channel: derived
    products, only acceleration is read), and the line after its data."""
    first = _FIRST_LINE.search(lines[i])
    if not first:
        raise RecordFormatError(
            f"{name}, line {i + 1}: expected a COSMOS channel header "
            f"'(Format v01.20 with 13 text lines)', found {lines[i].strip()[:60]!r}"
        )
    text = lines[i:i + int(first.group(2))]
    ints, j = _read_block(lines, i + len(text), name)
    reals, j = _read_block(lines, j, name)
    comments = []
    mc = _COMMENTS.match(lines[j]) if j < len(lines) else None
    if mc:
        comments = lines[j + 1:j + 1 + int(mc.group(1))]
        j += 1 + int(mc.group(1))
    md = _DATA_HEAD.match(lines[j]) if j < len(lines) else None
    if not md:
        raise RecordFormatError(
            f"{name}, line {j + 1}: expected the data line '<n> acceleration pts, ... "
            "units=..., Format=(...)'; the file is truncated or not COSMOS v01.20"
        )
    npts, kind = int(md.group(1)), md.group(2).lower()
    per_line, width = int(md.group(4)), int(md.group(5))
    n_data_lines = -(-npts // per_line)
    dt_ms = float(reals[62 - 1])
    check_interval(dt_ms / 1000.0, name=name, where="Real(62), the sampling interval in ms")
    stats = _channel_stats(text, ints, reals, comments, kind=kind, units=_UNITS.get(md.group(3).strip().lower()),
                           npts=npts, dt_ms=dt_ms)
    body = lines[j + 1:j + 1 + n_data_lines]
    trace = None
    if kind != "acceleration":
        pass  # velocity/displacement channels are derived products; acceleration is read
    elif headonly:
        trace = Trace(header=stats)
    else:
        data = parse_fixed_floats(body, width=width, count=npts, name=name, first_line_no=j + 2)
        trace = Trace(data=check_samples(data, npts=npts, name=name), header=stats)
    return trace, j + 1 + n_data_lines


def _channel_stats(text: list[str], ints, reals, comments: list[str], *, kind: str, units, npts: int,
                   dt_ms: float) -> dict:
    """A channel's obspy stats from its text header, integer and real headers and comments: the SCNL codes, the
    orientation, the start time, the units and the delivery level (headers kept in ``stats.cosmos``)."""
    scnl = next((m.group(1) for c in comments if (m := _SCNL.search(c))), None)
    sta, cha, net, loc = (scnl.split(".") + ["", "", "", ""])[:4] if scnl else ("", "", "", "")
    orient = next((m for t in text if (m := _ORIENT.search(t))), None)
    azimuth = None
    vertical = False
    if orient:
        if orient.group(1) is not None:
            azimuth = float(orient.group(1)) % 360.0
        else:
            vertical = True
    code = re.search(r"Code:\s*(\S+)", text[4]) if len(text) > 4 else None
    start = _start_time(ints, reals)
    header = AttribDict(
        text_header=[t.rstrip() for t in text],
        comments=[c.rstrip() for c in comments],
        kind=kind,
        azimuth_deg=azimuth,
        vertical=vertical,
        time_known=start is not None,
        header_peak=float(reals[64 - 1]) if reals[64 - 1] != MISSING else None,
    )
    return {
        "network": net if net not in ("--",) else "",
        "station": sta or (code.group(1).split("-")[-1] if code else ""),
        "location": "" if loc in ("--", "") else loc,
        "channel": cha or ("UP" if vertical else f"{azimuth:03.0f}" if azimuth is not None else ""),
        "delta": dt_ms / 1000.0,
        "starttime": start or UTCDateTime(0),
        "npts": npts,
        "cosmos": header,
        COMMON: common_fields(time_known=start is not None,
                              label=codes_label(net if net not in ("--",) else "",
                                                sta or (code.group(1).split("-")[-1] if code else ""), start)),
        "physical_units": units,
        "processing_level": "uncorrected" if text[0].lower().startswith(("uncorrected", "raw")) else "corrected",
    }
