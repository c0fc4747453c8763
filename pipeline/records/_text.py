"""Helpers shared by the text-format readers (AT2, COSMOS, DMG, NF-ASCII).

obspy hands a plug-in either a path or an open binary file; these helpers
accept both, never move the caller's file position in ``peek_lines`` and
never raise from a format check.
"""

from __future__ import annotations

import logging
import math
import os
from pathlib import Path

import numpy as np

from ..errors import RecordFormatError

log = logging.getLogger(__name__)

#: Bytes read by a format check: enough for every header we detect on.
PEEK_BYTES = 4096
#: The UTF-8 byte-order mark some Windows programs write first; not part of the text.
UTF8_BOM = b"\xef\xbb\xbf"

def source_name(source) -> str:
    """Return a printable name for a path or file-like ``source``."""
    if isinstance(source, (str, os.PathLike)):
        return str(source)
    return getattr(source, "name", "<file-like object>")


def peek_lines(source, n_lines: int) -> list[str]:
    """Return the first ``n_lines`` text lines of ``source`` without raising.

    An unreadable or binary source gives an empty list.
    """
    try:
        if isinstance(source, (str, os.PathLike)):
            with open(source, "rb") as fh:
                raw = fh.read(PEEK_BYTES)
        else:
            pos = source.tell()
            raw = source.read(PEEK_BYTES)
            source.seek(pos)
    except Exception:  # a format check must never raise
        return []
    if isinstance(raw, str):
        raw = raw.encode("latin-1", "replace")
    if b"\x00" in raw:
        return []
    return raw.removeprefix(UTF8_BOM).decode("latin-1").splitlines()[:n_lines]


def read_lines(source) -> list[str]:
    """Read the whole text of ``source`` as lines (latin-1, never fails on bytes).

    Raises
    ------
    RecordFormatError
        If the file cannot be read or is empty.
    """
    name = source_name(source)
    try:
        if isinstance(source, (str, os.PathLike)):
            raw = Path(source).read_bytes()
        else:
            raw = source.read()
    except OSError as exc:
        raise RecordFormatError(f"{name}: cannot be read ({exc})") from exc
    if isinstance(raw, str):
        raw = raw.encode("latin-1", "replace")
    if not raw.strip():
        raise RecordFormatError(f"{name}: the file is empty; expected a strong-motion record")
    if b"\x00" in raw:
        raise RecordFormatError(f"{name}: binary content in a text format; the file is corrupt")
    return raw.removeprefix(UTF8_BOM).decode("latin-1").splitlines()


def parse_free_floats(lines: list[str], *, name: str, first_line_no: int) -> np.ndarray:
    """Parse whitespace-separated numbers; name the first bad line on failure.

    Parameters
    ----------
    lines : list of str
        Data lines.
    name : str
        File name for messages.
    first_line_no : int
        1-based line number of ``lines[0]`` in the file, for messages.
    """
    text = " ".join(lines)
    if "D" in text or "d" in text:                       # Fortran double-precision exponents
        text = text.replace("D", "E").replace("d", "e")
    tokens = text.split()
    try:                                                 # one C-level pass; the loop below only names a bad line
        return np.fromiter(map(float, tokens), dtype=float, count=len(tokens))
    except ValueError as exc:
        error = exc
    for k, line in enumerate(lines):
        for token in line.split():
            try:
                float(token.replace("D", "E").replace("d", "e"))
            except ValueError:
                raise RecordFormatError(
                    f"{name}, line {first_line_no + k}: {token!r} is not a number; "
                    "expected numeric samples. The file is corrupt or not in this format."
                ) from None
    raise RecordFormatError(f"{name}: {error}; expected numeric samples") from error


def parse_fixed_floats(
    lines: list[str], *, width: int, count: int, name: str, first_line_no: int
) -> np.ndarray:
    """Parse Fortran fixed-width real fields (values may touch: ``5.0-999.0``).

    Parameters
    ----------
    lines : list of str
        Data lines, each holding ``len(line) // width`` fields.
    width : int
        Field width [characters].
    count : int
        Number of values expected; reading stops there.
    name : str
        File name for messages.
    first_line_no : int
        1-based line number of ``lines[0]``.

    Raises
    ------
    RecordFormatError
        If a field is not a number or fewer than ``count`` values are present.
    """
    out = np.empty(count, dtype=float)
    k = 0
    for i, line in enumerate(lines):
        line = line.rstrip("\r\n")
        for start in range(0, len(line), width):
            if k == count:
                break
            field = line[start:start + width].strip()
            if not field:
                continue
            try:
                out[k] = float(field.replace("D", "E"))
            except ValueError:
                raise RecordFormatError(
                    f"{name}, line {first_line_no + i}: field {field!r} is not a number "
                    f"(fixed width {width}); the file is corrupt or truncated."
                ) from None
            k += 1
        if k == count:
            break
    if k < count:
        raise RecordFormatError(
            f"{name}: header announces {count} values but only {k} were found; "
            "the file is truncated. Re-download it."
        )
    return out


#: Sampling intervals a reader accepts at all [s]: outside these the header holds no sampling interval (the limits
#: of what ground motions have, narrower, are settings: :mod:`pipeline.records.plausibility`).
READABLE_DT_S = (1e-9, 1e4)


def check_interval(dt_s: float, *, name: str, where: str) -> float:
    """A header's sampling interval [s], refused (naming the value) when it is not a finite number within
    :data:`READABLE_DT_S`.

    Raises
    ------
    RecordFormatError
        Naming the file, the header line and the value.
    """
    lo, hi = READABLE_DT_S
    if not (math.isfinite(dt_s) and lo <= dt_s <= hi):
        raise RecordFormatError(f"{name}, {where}: sampling interval {dt_s!r} s is not one (expected a finite number "
                                f"of seconds in [{lo:g}, {hi:g}]; strong-motion records are typically sampled every "
                                "0.001-0.02 s); fix the header or re-download the file")
    return dt_s


def check_samples(data: np.ndarray, *, npts: int, name: str) -> np.ndarray:
    """Check the sample count against the header and reject non-finite data."""
    if data.size < npts:
        raise RecordFormatError(
            f"{name}: header says NPTS={npts} but only {data.size} values were read; "
            "the file is truncated. Re-download it."
        )
    if data.size > npts and np.any(data[npts:] != 0):         # zeros after the data are padding (rinaldi_fn.dat)
        log.warning("%s: holds %d value(s) after the NPTS=%d its header states, not all zero; the first %d are read "
                    "(check the header's NPTS if the record is longer)", name, data.size - npts, npts, npts)
    data = data[:npts]
    if npts == 0:
        raise RecordFormatError(f"{name}: header says NPTS=0; the record holds no samples")
    if not np.all(np.isfinite(data)):
        bad = int(np.count_nonzero(~np.isfinite(data)))
        raise RecordFormatError(f"{name}: {bad} of {npts} samples are NaN or infinite")
    return data
