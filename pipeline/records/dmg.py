"""CSMIP/DMG V1 (uncorrected) and V2 (corrected) files as an obspy plug-in.

Each channel starts with a free-text header naming the channel
(``Chan  1:  90 Deg``, ``Chan  2:  Up``, ``Chan  1:  H1``) and the start time
(``Start time:  7/06/19, 03:16: 8.0 UTC``), then integer and real headers in
Fortran fixed-width fields, then the acceleration block:

* V1: ``31932 Accelerogram points at 100 pts/sec in units of g. Format: (8f9.6)``
* V2: ``7500 points of accel data equally spaced at .010 sec, in cm/sec2. (8f10.6)``
  (followed by velocity and displacement blocks, not read).

A channel ends with a line starting ``/&``. Fields can touch
(``5.0000000-999.00000``), so samples are read by column, never split on
blanks. Values are returned as stored, units in ``stats.physical_units``.

References
----------
California Strong Motion Instrumentation Program, "CSMIP processed data
format" (DMG/CSMIP V1, V2 tape formats), California Geological Survey.
"""

from __future__ import annotations

import math
import re
from typing import NamedTuple

from obspy import Stream, Trace, UTCDateTime
from obspy.core import AttribDict

from ..errors import RecordFormatError
from ._text import check_interval, check_samples, parse_fixed_floats, peek_lines, read_lines, source_name
from .common import COMMON, codes_label, common_fields

_V1_DATA = re.compile(
    r"^\s*(\d+)\s+Accelerogram points at\s+([\d.]+)\s*pts/sec in units of\s+([^.\s]+)\.?"
    r".*\((\d+)f(\d+)\.\d+\)", re.I)
_V2_DATA = re.compile(
    r"^\s*(\d+)\s+points of accel data equally spaced at\s+([\d.]+)\s*sec,\s*in\s+([^.\s]+)\.?"
    r".*\((\d+)f(\d+)\.\d+\)", re.I)
_CHAN = re.compile(r"^Chan\s+(\d+):\s*(.+?)\s*$", re.I)
_START = re.compile(r"Start time:\s*(\d+)/(\d+)/(\d+),\s*(\d+):\s*(\d+):\s*([\d.]+)\s*UTC", re.I)
_STATION = re.compile(r"Station (?:Id\.|No\.)\s*(\S+)", re.I)
_SCNL = re.compile(r"^(\d*)\.?([A-Z0-9]{1,2})\.([A-Z0-9]+)\.(--|[A-Z0-9]{2})\.([A-Z]{2})\b")
_PEAK = re.compile(r"Peak acceleration\s*=\s*([-\d.]+)\s*(\S+)", re.I)
_UNITS = {"g": "g", "cm/sec2": "cm/s**2", "cm/sec/sec": "cm/s**2", "cm/s2": "cm/s**2",
          "gal": "cm/s**2", "m/sec2": "m/s**2"}
_FIRST = ("uncorrected accelerogram", "corrected accelerogram")


def _is_dmg(filename) -> bool:
    """Return True if ``filename`` starts like a CSMIP/DMG V1 or V2 file (never raises)."""
    lines = peek_lines(filename, 30)
    if not lines or "(Format v" in lines[0]:
        return False
    return lines[0].strip().lower().startswith(_FIRST) and any(_CHAN.match(line) for line in lines)


def _orientation(text: str) -> tuple[float | None, bool, str]:
    """Return (azimuth [deg] or None, vertical, channel code) from ``'90 Deg'``, ``'Up'``, ``'H1'``."""
    word = text.split()[0] if text.split() else ""
    m = re.match(r"^(\d+(?:\.\d+)?)\s*Deg", text, re.I)
    if m:
        az = float(m.group(1)) % 360.0
        return az, False, f"{az:03.0f}"
    if word.upper() in ("UP", "DOWN", "DWN", "V", "VERT", "Z"):
        return None, True, "UP"
    return None, False, word.upper()


def _read_dmg(filename, headonly: bool = False, **kwargs) -> Stream:
    """Read the acceleration channels of a CSMIP/DMG V1 or V2 file.

    Returns
    -------
    obspy.Stream
        One trace per channel, values as stored, units in
        ``stats.physical_units``, header text in ``stats.dmg``.

    Raises
    ------
    RecordFormatError
        No channel, malformed data line, truncated data.
    """
    name = source_name(filename)
    lines = read_lines(filename)
    starts = [0] + [k + 1 for k, line in enumerate(lines) if line.startswith("/&")]
    traces = []
    for s in starts:
        if s >= len(lines) or not lines[s].strip():
            continue
        k = _data_line(lines, s, name)
        fmt = _data_format(lines[k])
        check_interval(fmt.dt_s, name=name, where=f"line {k + 1} (the data line's sampling)")
        stats = _channel_stats(lines[s:k], fmt)
        if headonly:
            traces.append(Trace(header=stats))
            continue
        n_lines = -(-fmt.npts // fmt.per_line)
        data = parse_fixed_floats(lines[k + 1:k + 1 + n_lines], width=fmt.width, count=fmt.npts,
                                  name=name, first_line_no=k + 2)
        traces.append(Trace(data=check_samples(data, npts=fmt.npts, name=name), header=stats))
    if not traces:
        raise RecordFormatError(f"{name}: no CSMIP/DMG channel found")
    return Stream(traces)


class _DataFormat(NamedTuple):
    """What a channel's acceleration data line says of its data."""

    npts: int
    dt_s: float
    unit_word: str
    per_line: int
    width: int
    level: str


def _data_line(lines: list[str], s: int, name: str) -> int:
    """The index of the acceleration data line of the channel whose header starts at line ``s``."""
    k = s
    while k < len(lines) and not (_V1_DATA.match(lines[k]) or _V2_DATA.match(lines[k])):
        if lines[k].startswith("/&"):
            break
        k += 1
    if k >= len(lines) or lines[k].startswith("/&"):
        raise RecordFormatError(
            f"{name}, line {s + 1}: channel header without an acceleration data line "
            "('... Accelerogram points at ...' or '... points of accel data ...'); "
            "the file is truncated or not CSMIP/DMG"
        )
    return k


def _data_format(line: str) -> _DataFormat:
    """The data line of a V1 (uncorrected: a sampling rate) or V2 (corrected: an interval) channel."""
    m1 = _V1_DATA.match(line)
    if m1:
        rate = float(m1.group(2))                   # samples per second: 0 is no interval (refused by name)
        return _DataFormat(int(m1.group(1)), 1.0 / rate if rate > 0 else math.nan, m1.group(3), int(m1.group(4)),
                           int(m1.group(5)), "uncorrected")
    m2 = _V2_DATA.match(line)
    assert m2 is not None                   # _data_line stops only at a line one of the two matches
    return _DataFormat(int(m2.group(1)), float(m2.group(2)), m2.group(3), int(m2.group(4)), int(m2.group(5)),
                       "corrected")


def _channel_stats(text: list[str], fmt: _DataFormat) -> dict:
    """A channel's obspy stats from its header text: orientation, start time, station codes and the header's
    peak (the text kept in ``stats.dmg``)."""
    chan = next((m for t in text if (m := _CHAN.match(t.strip()))), None)
    azimuth, vertical, code = _orientation(chan.group(2) if chan else "")
    st = next((m for t in text if (m := _START.search(t))), None)
    start = None
    if st:
        mo, da, yr, hh, mi, sec = st.groups()
        yr = int(yr) + (2000 if int(yr) < 70 else 1900) if int(yr) < 100 else int(yr)
        start = UTCDateTime(yr, int(mo), int(da), int(hh), int(mi)) + float(sec)
    sta = next((m.group(1) for t in text if (m := _STATION.search(t))), "")
    scnl = next((m for t in text if (m := _SCNL.match(t.strip()))), None)
    peak = next((m for t in text if (m := _PEAK.search(t))), None)
    header = AttribDict(
        text_header=[t.rstrip() for t in text],
        channel_number=int(chan.group(1)) if chan else None,
        azimuth_deg=azimuth,
        vertical=vertical,
        time_known=start is not None,
        header_peak=float(peak.group(1)) if peak else None,
        header_peak_units=peak.group(2) if peak else None,
    )
    return {
        "network": scnl.group(2) if scnl else "",
        "station": scnl.group(3) if scnl else sta,
        "location": "",
        "channel": code,
        "delta": fmt.dt_s,
        "starttime": start or UTCDateTime(0),
        "npts": fmt.npts,
        "dmg": header,
        COMMON: common_fields(time_known=start is not None,
                              label=codes_label(scnl.group(2) if scnl else "", scnl.group(3) if scnl else sta,
                                                start)),
        "physical_units": _UNITS.get(fmt.unit_word.lower()),
        "processing_level": fmt.level,
    }
