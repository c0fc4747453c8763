"""The table reader line by line: the reference the block reader of :mod:`pipeline.records.table` is checked against
(each line through ``TableRows.line`` in order, as the reader took them before it read by blocks)."""

from __future__ import annotations

import gzip

from pipeline.errors import RecordFormatError
from pipeline.records._text import UTF8_BOM
from pipeline.records.table import GZIP_MAGIC, MAX_ROWS, TableRows, read_rows


def _taken(rows: TableRows) -> tuple:
    return ("rows", rows.values.tobytes(), rows.head, rows.width, rows.first_line, rows.times)


def by_lines(data: bytes, name: str, max_rows: int = MAX_ROWS) -> tuple:
    """What a table file's bytes ``data`` (gzip or not) give taken one line at a time: the values, the header pairs,
    the width, the first data line and the first time stamps; or the error's message."""
    if data[:2] == GZIP_MAGIC:
        data = gzip.decompress(data)
    rows = TableRows(name, max_rows)
    lines = data.removeprefix(UTF8_BOM).split(b"\n")
    try:
        for k, line in enumerate(lines, start=1):
            if k == len(lines) and not line:
                break                                   # the file ended with its last line's newline
            rows.line(k, line.decode("latin-1"), ended=k < len(lines))
    except RecordFormatError as exc:
        return ("error", str(exc))
    return _taken(rows)


def by_blocks(path, max_rows: int = MAX_ROWS) -> tuple:
    """The same from the reader (:func:`~pipeline.records.table.read_rows`), or the error's message."""
    try:
        return _taken(read_rows(str(path), max_rows=max_rows))
    except RecordFormatError as exc:
        return ("error", str(exc))
