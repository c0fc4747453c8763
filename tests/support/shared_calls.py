"""Warm-up calls that say who made them, for the tests of :mod:`pipeline.bodies.compile_share`: a call appends its
index and the process that made it to a file (the helpers are other processes), then waits ``pause_s``."""

from __future__ import annotations

import os
import time
from pathlib import Path

from pipeline.bodies.compile_share import work_through


def calls(log: Path, n: int, pause_s: float | tuple[float, ...]) -> list:
    """``n`` calls, call ``i`` waiting ``pause_s`` (or ``pause_s[i]``) after it is logged."""
    def call(i):
        def made() -> None:
            with open(log, "a") as f:
                f.write(f"{i} {os.getpid()}\n")
            time.sleep(pause_s if isinstance(pause_s, (int, float)) else pause_s[i])
        return made
    return [call(i) for i in range(n)]


def helper(log: Path, n: int, pause_s: float, claims, who: int) -> None:
    """A helper's target: its share of the same calls."""
    work_through(calls(log, n, pause_s), claims, who)


def made_by(log: Path) -> list[tuple[int, int]]:
    """(index, process) of every call made, in the order written."""
    return [(int(a), int(b)) for a, b in (line.split() for line in log.read_text().splitlines())]
