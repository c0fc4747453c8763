"""One file's traces as obspy reads them, with the errors a user can act on (:func:`read_stream`), and a path
as obspy's readers take it (:func:`literal_path`)."""

from __future__ import annotations

import glob
import warnings
from pathlib import Path

import obspy

from ..errors import RecordFormatError, RockscreenError
from .common import annotate
from .compressed import refuse_if_expands_beyond
from .plausibility import file_size_limit
from .table import MAX_ROWS as TABLE_MAX_ROWS
from .table import TABLE_FORMAT


def literal_path(path: Path) -> str:
    """``path`` as obspy's readers take it: obspy expands a path's wildcards (``*``, ``?``, ``[...]``) as a glob,
    so a record named ``rec[1].AT2`` would be read as ``rec1.AT2``; escaped, the pattern matches the file itself."""
    return glob.escape(str(path))


def read_stream(path: Path, *, fmt: str | None = None, headonly: bool = False,
                max_rows: int = TABLE_MAX_ROWS) -> obspy.Stream:
    """The traces of one file (``fmt``: its obspy format, detected by content when None; ``headonly``: headers
    only), each annotated with the fields every reader fills (:mod:`.common`).

    Raises
    ------
    RecordFormatError
        Naming the file and the fix: empty, vanished, truncated, of no format any reader knows, corrupt; a
        compressed file that would expand beyond the largest plausible record.
    """
    try:
        try:
            size = path.stat().st_size
        except FileNotFoundError:
            raise RecordFormatError(f"{path}: the file vanished after the records directory was scanned; "
                                    "re-run when the directory is stable") from None
        if size == 0:
            raise RecordFormatError(f"{path}: the file is empty; expected a strong-motion record")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            if fmt == TABLE_FORMAT:             # read as a stream by its own reader, gzip included
                st = obspy.read(literal_path(path), format=fmt, headonly=headonly, check_compression=False,
                                max_rows=max_rows)
            else:
                refuse_if_expands_beyond(path, file_size_limit(max_rows))
                st = obspy.read(literal_path(path), format=fmt, headonly=headonly)
        for w in caught:
            if "end of file" in str(w.message).lower():
                raise RecordFormatError(f"{path}: truncated ({w.message}); re-download the file")
        for tr in st:
            annotate(tr)
        return st
    except RockscreenError:
        raise
    except TypeError as exc:
        if "Unknown format" in str(exc) or "unknown format" in str(exc).lower():
            raise RecordFormatError(
                f"{path}: unrecognised format (not AT2, COSMOS, CSMIP/DMG, or any format obspy "
                "reads); remove it from the records directory or convert it"
            ) from None
        raise RecordFormatError(f"{path}: cannot be read ({exc})") from exc
    except Exception as exc:
        raise RecordFormatError(f"{path}: corrupt or truncated ({type(exc).__name__}: {exc})") from exc
