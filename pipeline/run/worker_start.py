"""The exception hook of the process pool's forkserver and the workers it forks (installed by :mod:`.quiet_server`).

A worker the server forks reads its process object from the run's process before it runs anything
(``multiprocessing.spawn._main``). Where the run ended meanwhile (an interrupt while the pool started that worker,
before the pool knew its pid and could end it), the semaphores and pipe that object names are gone, and the read fails
with an ``OSError`` or ``EOFError``, which the server's child printed as a traceback under the run's "interrupted"
line. :func:`worker_start_hook` ends such a worker without a word; every other exception is printed as Python prints
it. A run still there finds its pool broken and starts a new one (:meth:`.executors.ProcessExecutor.map_unordered`,
with a warning where tasks were in flight)."""

from __future__ import annotations

import os
import sys
from types import TracebackType

#: Where a worker forked by the server reads its process object from the run's process: (the file's path ends so, the
#: function's name).
WORKER_START = (os.path.join("multiprocessing", "spawn.py"), "_main")
#: Where a worker's own run starts (its exceptions are the process's to report, not the start's).
WORKER_RUN = (os.path.join("multiprocessing", "process.py"), "_bootstrap")


def _passes(tb: TracebackType | None, where: tuple[str, str]) -> bool:
    """The traceback ``tb`` has a frame of the function ``where`` names (its file's path's end, its name)."""
    while tb is not None:
        code = tb.tb_frame.f_code
        if code.co_name == where[1] and code.co_filename.endswith(where[0]):
            return True
        tb = tb.tb_next
    return False


def run_gone_at_start(exc_type: type[BaseException], tb: TracebackType | None) -> bool:
    """An ``OSError`` or ``EOFError`` raised while a forked worker read its process object from the run's process
    (in :data:`WORKER_START`, not yet in :data:`WORKER_RUN`): what the read meets where the run has ended."""
    return (issubclass(exc_type, (OSError, EOFError)) and _passes(tb, WORKER_START)
            and not _passes(tb, WORKER_RUN))


def worker_start_hook(exc_type: type[BaseException], exc: BaseException, tb: TracebackType | None,
                      printed=sys.__excepthook__) -> None:
    """``sys.excepthook`` of the server and the workers it forks: silent for :func:`run_gone_at_start`, else
    ``printed`` (Python's own hook)."""
    if not run_gone_at_start(exc_type, tb):
        printed(exc_type, exc, tb)
