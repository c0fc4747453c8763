"""Files written atomically: a temporary file in the same directory, fsync, rename.

A reader, or a run killed at any instant, sees the old file or the new one, never a partial one.
"""

from __future__ import annotations

import csv
import math
import os
import shutil
import tempfile
from pathlib import Path
from typing import Callable

import numpy as np

from ..constants import STATE_DIR
from ..errors import OutputError

#: How netCDF4 begins the message of a failed file operation (a full disk among them), raised as RuntimeError
NETCDF_ERROR = "NetCDF:"


def replace_atomically(path: str | Path, write: Callable[[str], None]) -> Path:
    """Create or replace ``path`` through ``write(temporary_path)``: temporary file, fsync, rename.

    The temporary ``.<name>.*.tmp`` lies in the same directory, so the rename is atomic:
    a reader, or a run killed at any instant, sees the old file or the new one.

    Raises
    ------
    OutputError
        If the directory is not writable or the disk is full; the previous
        file at ``path``, if any, is left untouched.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
        os.close(fd)
        os.chmod(tmp, default_file_mode())
    except OSError as exc:
        raise OutputError(f"{path.parent}: cannot write results here ({exc.strerror or exc}); "
                          "choose another --out directory or fix its permissions") from exc
    try:
        write(tmp)
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        _remove_quietly(tmp)
        raise OutputError(f"{path}: writing failed ({exc.strerror or exc}); the previous results, if "
                          "any, are intact. Free disk space or choose another --out") from exc
    except RuntimeError as exc:
        if not str(exc).startswith(NETCDF_ERROR):
            _remove_quietly(tmp)
            raise
        free = shutil.disk_usage(path.parent).free          # netCDF4 reports a failed write (a full disk) so
        _remove_quietly(tmp)
        raise OutputError(f"{path}: writing failed ({exc}; {free:,} bytes free on that disk); the previous "
                          "results, if any, are intact. Free disk space or choose another --out") from exc
    except BaseException:
        _remove_quietly(tmp)
        raise
    return path


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write UTF-8 text atomically (:func:`replace_atomically`)."""
    def write(tmp: str) -> None:
        Path(tmp).write_text(text, encoding="utf-8")

    return replace_atomically(path, write)


def write_bytes_atomic(path: str | Path, data: bytes) -> Path:
    """Write bytes atomically (:func:`replace_atomically`)."""
    def write(tmp: str) -> None:
        Path(tmp).write_bytes(data)

    return replace_atomically(path, write)


#: The first characters with which a spreadsheet reads a cell as a formula (CSV injection; OWASP).
FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def inert(value):
    """A CSV cell a spreadsheet reads as meant: a number that is not finite (NaN, +-inf) is a blank cell, which
    spreadsheets and pandas read as missing (never the text "nan" or "inf"; the table's other columns say why it
    is missing); text that starts like a formula (:data:`FORMULA_START`) gets a leading apostrophe, as OWASP
    advises; numbers, also negative ones written as text, are kept as they are."""
    if isinstance(value, (float, np.floating)) and not math.isfinite(value):
        return ""
    if not isinstance(value, str) or not value.startswith(FORMULA_START):
        return value
    try:
        float(value)
        return value
    except ValueError:
        return "'" + value


def write_csv_atomic(path: str | Path, columns, rows: list[dict]) -> Path:
    """Write a CSV table (header ``columns``; missing keys and numbers that are not finite blank) atomically
    (:func:`replace_atomically`); text that a spreadsheet would execute as a formula is written inert
    (:func:`inert`)."""
    def write(tmp: str) -> None:
        with open(tmp, "w", newline="", encoding="utf-8") as fh:
            w = csv.DictWriter(fh, fieldnames=list(columns), restval="", extrasaction="ignore")
            w.writeheader()
            w.writerows({k: inert(v) for k, v in row.items()} for row in rows)

    return replace_atomically(path, write)


def remove_stale_temporaries(out_dir: str | Path) -> int:
    """Delete temporaries a killed run left in ``out_dir`` (call only while holding its lock)."""
    out = Path(out_dir)
    n = 0
    for pattern in (".*.tmp", f"{STATE_DIR}/.*.tmp", f"{STATE_DIR}/*/.*.tmp"):
        for p in out.glob(pattern):
            _remove_quietly(p)
            n += 1
    return n


def default_file_mode() -> int:
    """The mode an ordinary new file gets under the process umask (mkstemp alone gives 0600)."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def _remove_quietly(path) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass
