"""PEER NGA ``.AT2`` acceleration files as an obspy waveform plug-in.

Two header variants exist (PEER ``smcat/data.html``):

* NGA-West2: line 4 is ``NPTS=   1991, DT=   .0100 SEC, ...``;
* older NGA (2005): line 4 is ``1991    0.0100    NPTS, DT``.

Lines 1-3 are free text; line 2 ends with the component (``228``, ``UP``,
``N``, ``L``...), line 3 states the units (``IN UNITS OF G``) and, in older
files, ``PGA=   .48431 G``. Samples follow, whitespace separated, the last
line possibly ragged. Values are returned as stored (``stats.physical_units``
says which); :mod:`pipeline.records.units` converts them to m s-2.
"""

from __future__ import annotations

import math
import re

from obspy import Stream, Trace, UTCDateTime
from obspy.core import AttribDict

from ..errors import RecordFormatError
from ._text import check_interval, check_samples, parse_free_floats, peek_lines, read_lines, source_name
from .common import COMMON, common_fields

#: The lines of an AT2 header (the samples start on line 5)
HEADER_LINES = 4

_NEW_HEADER = re.compile(r"NPTS\s*=\s*(\d+)\s*,\s*DT\s*=\s*([-+\d.Ee]+)", re.I)
_OLD_HEADER = re.compile(r"^\s*(\d+)\s+([-+\d.Ee]+)\s+NPTS\s*,\s*DT", re.I)
#: A header whose DT is a word for no number (nan, inf): recognised as AT2, so that the reader refuses it by name.
_NO_NUMBER_DT = re.compile(r"NPTS\s*=\s*(\d+)\s*,\s*DT\s*=\s*([-+]?(?:nan|inf|infinity))\b", re.I)
_PGA = re.compile(r"PGA\s*=\s*([-+\d.Ee]+)\s*G\b", re.I)
_UNITS = {
    "G": "g",
    "CM/SEC/SEC": "cm/s**2",
    "CM/S/S": "cm/s**2",
    "CM/SEC2": "cm/s**2",
    "CM/S2": "cm/s**2",
    "M/S/S": "m/s**2",
    "M/S2": "m/s**2",
}


def _parse_npts_dt(line: str) -> tuple[int, float] | None:
    m = _NEW_HEADER.search(line) or _OLD_HEADER.search(line) or _NO_NUMBER_DT.search(line)
    if not m:
        return None
    try:
        return int(m.group(1)), float(m.group(2))
    except ValueError:                       # not a number (a lone sign): refused by name by the reader
        return int(m.group(1)), math.nan


def _units_of(line3: str) -> str | None:
    m = re.search(r"UNITS\s+OF\s+([A-Z0-9/*]+)", line3.upper())
    if not m:
        return None
    return _UNITS.get(m.group(1).rstrip(",."))


def _is_at2(filename) -> bool:
    """Return True if ``filename`` looks like a PEER acceleration file (never raises)."""
    lines = peek_lines(filename, HEADER_LINES)
    if len(lines) < 4:
        return False
    return "ACCELERATION" in lines[2].upper() and _parse_npts_dt(lines[3]) is not None


def _read_at2(filename, headonly: bool = False, **kwargs) -> Stream:
    """Read a PEER ``.AT2`` file into a one-trace :class:`~obspy.core.stream.Stream`.

    Parameters
    ----------
    filename : str or file-like
        The file.
    headonly : bool
        Read only the header (data left empty).

    Returns
    -------
    obspy.Stream
        One trace, values in the file's units (``stats.physical_units``),
        raw header in ``stats.at2``. The start time is unknown in AT2 files
        and set to 1970-01-01 (``stats.at2.time_known`` is False).

    Raises
    ------
    RecordFormatError
        If the header is malformed or the sample count disagrees with NPTS.
    """
    name = source_name(filename)
    lines = peek_lines(filename, HEADER_LINES) if headonly else read_lines(filename)
    if len(lines) < 4:
        raise RecordFormatError(f"{name}: only {len(lines)} lines; an AT2 file has a 4-line header")
    parsed = _parse_npts_dt(lines[3])
    if parsed is None:
        raise RecordFormatError(
            f"{name}, line 4: {lines[3].strip()!r} is not an AT2 'NPTS=..., DT=...' "
            "or 'npts dt NPTS, DT' header line"
        )
    npts, dt = parsed
    check_interval(dt, name=name, where="line 4 (DT)")
    units = _units_of(lines[2])
    fields = [f.strip() for f in lines[1].split(",")]
    component = fields[-1] if len(fields) > 1 else ""
    pga = _PGA.search(lines[2])
    header = AttribDict(
        title=lines[0].strip(),
        description=lines[1].strip(),
        station_line=", ".join(fields[:-1]) if len(fields) > 1 else lines[1].strip(),
        component=component,
        units_line=lines[2].strip(),
        header_pga_g=float(pga.group(1)) if pga else None,
        time_known=False,
        header_variant="NGA-West2" if _NEW_HEADER.search(lines[3]) else "NGA-2005",
    )
    stats = {
        "network": "",
        "station": re.sub(r"\W+", "", fields[2] if len(fields) > 3 else fields[0])[:16],
        "location": "",
        "channel": component.upper(),
        "delta": dt,
        "starttime": UTCDateTime(0),
        "npts": npts,
        "at2": header,
        COMMON: common_fields(time_known=False, recording=header.station_line.lower(), label=header.station_line),
        "physical_units": units,
        "processing_level": "corrected",
    }
    if headonly:
        return Stream([Trace(header=stats)])
    data = parse_free_floats(lines[4:], name=name, first_line_no=5)
    header.extra_values = max(0, data.size - npts)
    data = check_samples(data, npts=npts, name=name)
    return Stream([Trace(data=data, header=stats)])
