"""The README's and the docs' Markdown tables are whole: outside code blocks, every line of a table is a row that
starts and ends with a pipe and has the header's number of cells, so that no row is cut in two by a line break
(which ends the table where a reader sees it)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def cells(row: str) -> int:
    """The cells of a table row, pipes inside backticks or escaped not counted."""
    text = re.sub(r"`[^`]*`", "", row.strip()).replace("\\|", "")
    return text.count("|") - 1


def table_defects(text: str) -> list[str]:
    """Each table row that is not whole: its line number and why."""
    defects, header, fenced = [], None, False
    lines = text.splitlines()
    for k, line in enumerate(lines, start=1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            continue
        stripped = line.strip()
        if header is None:
            nxt = lines[k].strip() if k < len(lines) else ""
            if stripped.startswith("|") and re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", nxt):
                header = cells(stripped)
            continue
        if not stripped:
            header = None
            continue
        if not (stripped.startswith("|") and stripped.endswith("|")):
            defects.append(f"line {k}: a table's row does not start and end with '|' (a line break inside a row?)")
        elif cells(stripped) != header:
            defects.append(f"line {k}: {cells(stripped)} cells against the header's {header}")
    return defects


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_table_row_is_whole(page):
    assert table_defects(page.read_text()) == []


def test_a_row_cut_by_a_line_break_is_found():
    page = "| a | b |\n|---|---|\n| 1 | two words\n. and more |\n\nafter\n"
    cut = "a table's row does not start and end with '|' (a line break inside a row?)"
    assert table_defects(page) == [f"line 3: {cut}", f"line 4: {cut}"]
    assert table_defects("| a | b |\n|---|---|\n| 1 | 2 |\n| 3 |\n") == ["line 4: 1 cells against the header's 2"]
    assert table_defects("| a | b |\n|---|---|\n| `x | y` | 2 |\n") == []
