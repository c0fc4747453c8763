"""One ticker for every "say something at least every N seconds" of the commands: the progress lines, the
progress bar's refresh, a stage's name repeated while it runs, the simulator's compilation announced.

A :class:`Ticker` runs a daemon thread that looks at the silence every :data:`POLL_FRACTION` of its period and
speaks once the silence is within one look of the period, so that no silence exceeds it; whatever else the command
prints marks the silence's start with :meth:`Ticker.said`. (``tools/ticking.py`` does the same for ``make``, with the
standard library alone, outside the package.)
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

#: How often a ticker looks at the silence, as a fraction of its shortest period [-]
POLL_FRACTION = 0.25
#: ... and at least this often where no period is positive [s]
MIN_POLL_S = 0.01


class Ticker:
    """Call ``speak(seconds since the start)`` whenever ``every_s`` seconds pass without output, the first time
    after ``first_after_s`` (default ``every_s``); a context manager that starts and stops its thread.

    Parameters
    ----------
    speak : callable
        Called from the ticker's thread with the seconds since the ticker started [s]; what it prints counts as
        output.
    every_s : float
        The longest silence between two outputs [s].
    first_after_s : float, optional
        The silence before the first output [s].
    """

    def __init__(self, speak: Callable[[float], None], *, every_s: float, first_after_s: float | None = None):
        self._speak = speak
        self._every = float(every_s)
        self._first = self._every if first_after_s is None else float(first_after_s)
        periods = [x for x in (self._every, self._first) if x > 0.0]
        self._poll = min(periods) * POLL_FRACTION if periods else MIN_POLL_S
        self._t0 = self._last = time.monotonic()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._lock = threading.Lock()
        #: whether the ticker has spoken
        self.spoke = False

    def said(self) -> None:
        """Mark now as the last output (the silence starts again)."""
        with self._lock:
            self._last = time.monotonic()

    def _run(self) -> None:
        while True:                      # a look at once (a first_after_s of 0 speaks at the start), then every poll
            now = time.monotonic()
            with self._lock:
                due = now - self._last >= (self._every if self.spoke else self._first) - self._poll
            if due:
                self._speak(now - self._t0)
                with self._lock:
                    self._last, self.spoke = time.monotonic(), True
            if self._stop.wait(self._poll):
                return

    def __enter__(self) -> Ticker:
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._thread.join()
