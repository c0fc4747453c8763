"""Imported first by the process pool's forkserver (:data:`.executors.FORKSERVER_PRELOAD`): the signals the run's
own process handles (:data:`.executors.PARENT_SIGNALS`: Ctrl-C and a closed terminal's SIGHUP, which reach the whole
process group) are ignored in the server, and so in the workers it forks, and unblocked (the run's process starts
the server with them ignored and blocked for that instant: :func:`.executors._start_server`; one that arrived then
is discarded here). The run's process cancels the pool and keeps what was done. A worker that meets the end of its
run while it starts ends without a traceback (:mod:`.worker_start`, the server's exception hook)."""

from __future__ import annotations

import signal
import sys

from .executors import PARENT_SIGNALS
from .worker_start import worker_start_hook

for _signal in PARENT_SIGNALS:
    signal.signal(_signal, signal.SIG_IGN)
signal.pthread_sigmask(signal.SIG_UNBLOCK, PARENT_SIGNALS)
sys.excepthook = worker_start_hook
