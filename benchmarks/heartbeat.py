"""Every benchmark says it is still running: a line ``  ... NAME: 12 s`` on stderr whenever 2 s pass with nothing
printed, from its first import to its end (its imports, numba's caches loading and its long runs included).

A benchmark imports this module before anything else (``import heartbeat``). Run as a script (``python
benchmarks/NAME.py``: this folder is then on ``sys.path`` and the script is ``__main__``), the heartbeat starts at
that import and stops at the interpreter's exit. Imported otherwise (a test loading a benchmark's functions), it
starts nothing. What the benchmark prints through ``sys.stdout`` or ``sys.stderr`` restarts the silence; a child
process's output does not, so a line may come while a child prints. The lines come from a thread: a compiled call
that holds the interpreter (numba's code does) delays them until it returns, so a benchmark whose single compiled
call lasts longer than the silence prints a line before it (as ``bench_cubic_events.py`` does).
"""

from __future__ import annotations

import atexit
import sys
from pathlib import Path

from pipeline.ticker import Ticker

#: The longest silence [s]
EVERY_S = 2.0


class _Heard:
    """A text stream that tells the ticker whenever something is written to it, and remembers whether the last
    text written ended its line (so that a heartbeat never lands in the middle of one)."""

    def __init__(self, stream, ticker: Ticker) -> None:
        self._stream = stream
        self._ticker = ticker
        self.line_open = False

    def write(self, text: str) -> int:
        n = self._stream.write(text)
        if text:
            self.line_open = not text.endswith("\n")
            self._ticker.said()
        return n

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


def start(name: str) -> None:
    """Start the heartbeat of the benchmark ``name`` (its lines on the original stderr)."""
    err = sys.stderr
    streams: list[_Heard] = []

    def speak(seconds: float) -> None:
        opened = any(s.line_open for s in streams)
        err.write(("\n" if opened else "") + f"  ... {name}: {seconds:.0f} s\n")
        err.flush()
        for s in streams:
            s.line_open = False

    ticker = Ticker(speak, every_s=EVERY_S)
    streams.extend((_Heard(sys.stdout, ticker), _Heard(err, ticker)))
    sys.stdout, sys.stderr = streams            # type: ignore[assignment]
    ticker.__enter__()
    atexit.register(ticker.__exit__, None, None, None)


def _run_as_a_benchmark() -> str | None:
    """The name of the benchmark run as a script from this folder, else None."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if path is None or Path(path).resolve().parent != Path(__file__).resolve().parent:
        return None
    return Path(path).stem


if (_name := _run_as_a_benchmark()) is not None:
    start(_name)
