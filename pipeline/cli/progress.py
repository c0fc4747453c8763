"""What a command prints while it works: a progress bar or lines, a stage's name (by the one ticker)."""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time

from ..ticker import POLL_FRACTION, Ticker
from .options import _say

#: Longest silence of a command while it works [s]: a progress line, a stage's name or the bar's refresh comes at
#: least this often (stderr not a terminal: scheduled runs, logs; or the stages of screen bench), by a
#: :class:`~pipeline.ticker.Ticker`
PROGRESS_LINE_S = 2.0


def _tick_s() -> float:
    """The tickers' period [s]: :data:`PROGRESS_LINE_S` less one look of the ticker, which leaves that quarter for
    the ticker's thread to be woken late (a busy machine, a long hold of the interpreter's lock: the bundled default's
    longest silences in a terminal were 1.69-1.91 s with a 2 s period)."""
    return PROGRESS_LINE_S * (1.0 - POLL_FRACTION)


def _progress(quiet: bool):
    """How finished tasks are shown: nothing with ``-q``; a tqdm bar on a terminal of known width; otherwise a
    progress line at every tenth of the work, and whenever :data:`PROGRESS_LINE_S` seconds pass without one."""
    if quiet:
        return None
    if sys.stderr.isatty() and _terminal_columns() > 0:
        return _progress_bar
    return _progress_lines


def _terminal_columns() -> int:
    """The width of the terminal on stderr; 0 where it has none (a pseudo-terminal whose size was never set, as
    some job runners open, in which a tqdm bar draws nothing)."""
    try:
        return os.get_terminal_size(sys.stderr.fileno()).columns
    except (OSError, ValueError):
        return 0


def _progress_bar(items, total=None, running=None, label: str = "records screened"):
    """Yield ``items`` under a tqdm bar whose postfix names the records running long and their scenes (``label``:
    what a finished item is; its first word is the bar's name)."""
    from tqdm import tqdm

    bar = tqdm(items, total=total, desc=label.split()[0], unit="rec", file=sys.stderr, leave=False)

    def refresh(_elapsed_s: float) -> None:
        bar.set_postfix_str("; ".join(running()) if running is not None else "", refresh=True)

    try:
        with Ticker(refresh, every_s=_tick_s()):
            yield from bar
    finally:
        bar.close()


def _progress_lines(items, total=None, running=None, label: str = "records screened"):
    """Yield ``items``, printing progress lines (from a watcher thread while a task takes long); ``running()``
    names the records that have run long and the scene each is on; ``label``: what a finished item is."""
    t0 = time.monotonic()
    state = {"done": 0}
    lock = threading.Lock()

    def line(_elapsed_s: float = 0.0) -> None:
        with lock:
            busy = running() if running is not None else []
            print(f"progress: {state['done']}/{total} {label}, {time.monotonic() - t0:.0f} s"
                  + (f"; running long: {'; '.join(busy)}" if busy else ""), file=sys.stderr, flush=True)
            ticker.said()

    ticker = Ticker(line, every_s=_tick_s())
    if not total:
        yield from items
        return
    step = max(1, total // 10)
    line()                                       # at once: the run has started and how much it has to do
    with ticker:
        for k, item in enumerate(items, 1):
            yield item
            state["done"] = k
            if k % step == 0 or k == total:
                line()


@contextlib.contextmanager
def _ticking(quiet: bool, first: str = ""):
    """A stage announcer (None with ``-q``): ``announce(text)`` says a stage's name at once and, while it runs,
    repeats it with the time spent on it every :func:`_tick_s`, so that nothing is silent for longer;
    ``announce(None)`` ends the stage silently (its tasks' progress speaks from then on: :func:`_after_stage`).
    ``first``: the stage announced on entry (the command's start-up, said before its slow imports)."""
    if quiet:
        yield None
        return
    stage, started = {"text": ""}, {"t": time.monotonic()}

    def announce(text: str | None) -> None:
        stage["text"], started["t"] = text or "", time.monotonic()
        ticker.said()
        if text:
            _say(text)

    def tick(_elapsed_s: float) -> None:
        if stage["text"]:
            _say(f"  ... {stage['text'].split(' (')[0]}: {time.monotonic() - started['t']:.0f} s")

    ticker = Ticker(tick, every_s=_tick_s())
    with ticker:
        if first:
            announce(first)
        yield announce


def _after_stage(progress, announce):
    """``progress`` (as :func:`_progress` gives it) that ends the stage ``announce`` (:func:`_ticking`) repeats when
    it starts: a stage said before the tasks (the start-up: loading the simulator, listing the records; a round of
    levels) stops repeating once their progress speaks. None where either is None (``-q``)."""
    if progress is None or announce is None:
        return progress

    def started(*args, **kwargs):
        announce(None)
        yield from progress(*args, **kwargs)

    return started
