"""Small user tables (inventories, buildings, observations): a CSV's header and rows, and numbers read from its
cells, with errors that name the file, line and column and say what was expected."""

from __future__ import annotations

import csv
import difflib
import logging
import math
import re
from pathlib import Path

from .errors import InventoryError

log = logging.getLogger(__name__)

#: The delimiters a table may use, tried on its header line (European spreadsheets export ';')
DELIMITERS = (",", ";", "\t")
#: A number written with a decimal comma (read where the table's delimiter is not a comma)
DECIMAL_COMMA = re.compile(r"^[+-]?\d*,\d+([eE][+-]?\d+)?$")


def close_match(name: str, names) -> str | None:
    """The known column ``name`` most likely meant (a misspelling, another case), or None."""
    lowered = {n.lower(): n for n in names}
    if name.lower() in lowered:
        return lowered[name.lower()]
    got = difflib.get_close_matches(name.lower(), list(lowered), n=1, cutoff=0.75)
    if not got:                               # a name without its unit suffix: 'azimuth' for 'azimuth_deg'
        got = [n for n in lowered if n.split("_")[0] == name.lower()][:1]
    return lowered[got[0]] if got else None


def _delimiter(line: str) -> str:
    """The delimiter of a header line: the most frequent of :data:`DELIMITERS` (a comma on ties)."""
    counts = {d: line.count(d) for d in DELIMITERS}
    best = max(DELIMITERS, key=lambda d: (counts[d], d == ","))
    return best if counts[best] else ","


def parse_number(value: str, *, where: str, column: str, rule: str, ok) -> float:
    """A finite number from a CSV cell, or an :class:`InventoryError` naming ``where`` and ``column``."""
    try:
        x = float(value)
    except ValueError:
        raise InventoryError(f"{where}, column {column!r}: {value!r} is not a number; expected {rule}") from None
    if not math.isfinite(x) or not ok(x):
        raise InventoryError(f"{where}, column {column!r}: {value!r} is out of range; expected {rule}")
    return x


def read_csv_table(path: Path, *, what: str, expected_header: str, problems: list[str] | None = None,
                   required: tuple[str, ...] = ()):
    """Header and rows of a small CSV table, for the readers of user tables.

    Returns
    -------
    header : list of str
        Stripped column names of line 1.
    records : iterator of (line, where, dict)
        Per non-blank row: its line number, ``"<path>, line <n>"`` for messages, and
        column -> stripped cell.

    Raises
    ------
    InventoryError
        File missing, not UTF-8, empty, a header without the ``required`` columns or with a column
        twice, or (while iterating) a row whose field count differs from the header's. With
        ``problems``, such rows are reported there and skipped instead.
    """
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise InventoryError(f"{path}: {what} file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InventoryError(f"{path}: cannot be read as UTF-8 text ({exc})") from exc
    lines = text.splitlines()
    delimiter = _delimiter(lines[0]) if lines else ","
    decimal_comma = delimiter != ","
    if delimiter != ",":
        log.info("%s: columns separated by %r; numbers with a decimal comma are read as decimals", path, delimiter)
    reader = csv.reader(lines, delimiter=delimiter)
    try:
        header = [c.strip() for c in next(reader)]
    except StopIteration:
        raise InventoryError(f"{path}: empty file; expected a header line {expected_header!r}") from None
    missing = [c for c in required if c not in header]
    if missing:
        hints = [f"{close!r} to {c!r}" for c in missing
                 if (close := close_match(c, [h for h in header if h not in required])) is not None]
        raise InventoryError(f"{path}, line 1: missing required column(s) {missing}; expected {expected_header!r} "
                             f"(columns separated by {delimiter!r}: found {header})"
                             + (f"; rename {', '.join(hints)}" if hints else ""))
    dupes = {c for c in header if header.count(c) > 1}
    if required and dupes:
        raise InventoryError(f"{path}, line 1: column(s) {sorted(dupes)} appear more than once")

    def records():
        for row in reader:
            if not any(cell.strip() for cell in row):
                continue
            where = f"{path}, line {reader.line_num}"
            if len(row) != len(header):
                message = f"{where}: {len(row)} fields, expected {len(header)} as in the header"
                if problems is None:
                    raise InventoryError(message)
                problems.append(message)
                continue
            cells = {c: row[i].strip() for i, c in enumerate(header)}
            if decimal_comma:
                cells = {c: v.replace(",", ".") if DECIMAL_COMMA.match(v) else v for c, v in cells.items()}
            yield reader.line_num, where, cells

    return header, records()
