"""Near-fault ASCII files with ``%`` header lines as an obspy plug-in.

This is the layout of the SAC steel project near-fault set (``rinaldi_fn.dat``):
line 1 ``%<code> <component> <description>``, line 2 ``%<npts> <dt> ...``,
then samples, six per line, the last line zero-padded beyond NPTS.
The files do not state their units, so ``stats.physical_units`` is None and
the units must be declared (``units.toml`` in the records directory);
see :mod:`pipeline.records.units`.
"""

from __future__ import annotations

import re
from pathlib import Path

from obspy import Stream, Trace, UTCDateTime
from obspy.core import AttribDict

from ..errors import RecordFormatError
from ._text import check_interval, check_samples, parse_free_floats, peek_lines, read_lines, source_name
from .common import COMMON, common_fields

#: The lines of a near-fault ASCII header (the samples start on line 3)
HEADER_LINES = 2

_LINE2 = re.compile(r"^%\s*(\d+)\s+([-+\d.Ee]+)")


def _is_nfascii(filename) -> bool:
    """Return True for a two-``%``-line near-fault ASCII file (never raises)."""
    lines = peek_lines(filename, 3)
    return (len(lines) >= 3 and lines[0].startswith("%") and bool(_LINE2.match(lines[1]))
            and not lines[2].lstrip().startswith("%"))


def _read_nfascii(filename, headonly: bool = False, **kwargs) -> Stream:
    """Read a ``%``-header near-fault ASCII file (one component, units unstated)."""
    name = source_name(filename)
    lines = peek_lines(filename, HEADER_LINES) if headonly else read_lines(filename)
    m = _LINE2.match(lines[1]) if len(lines) > 1 else None
    if not m:
        raise RecordFormatError(f"{name}, line 2: expected '%<npts> <dt>'")
    npts, dt = int(m.group(1)), float(m.group(2))
    check_interval(dt, name=name, where="line 2 (dt)")
    tokens = lines[0][1:].split()
    stem = Path(name).stem.lower()
    component = "FN" if stem.endswith("_fn") or (len(tokens) > 1 and tokens[1].lower() == "fn") else (
        "FP" if stem.endswith("_fp") else tokens[1].upper() if len(tokens) > 1 else "")
    header = AttribDict(description=lines[0][1:].strip(), time_known=False, component=component)
    stats = {"network": "", "station": tokens[0][:16] if tokens else "", "location": "",
             "channel": component, "delta": dt, "starttime": UTCDateTime(0), "npts": npts,
             "nfascii": header,
             COMMON: common_fields(time_known=False, standalone=True, label=" ".join(header.description.split())),
             "physical_units": None, "processing_level": "corrected"}
    if headonly:
        return Stream([Trace(header=stats)])
    data = parse_free_floats(lines[2:], name=name, first_line_no=3)
    header.padding_values = max(0, data.size - npts)
    return Stream([Trace(data=check_samples(data, npts=npts, name=name), header=stats)])
