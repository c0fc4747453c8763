"""Imported first by the process pool's forkserver (:data:`.executors.FORKSERVER_PRELOAD`): the signals the run's
own process handles (:data:`.executors.PARENT_SIGNALS`: Ctrl-C and a closed terminal's SIGHUP, which reach the whole
process group) are ignored in the server, and so in the workers it forks, and unblocked (the run's process starts
the server with them ignored and blocked for that instant: :func:`.executors._start_server`; one that arrived then
is discarded here). The run's process cancels the pool and keeps what was done."""

from __future__ import annotations

import signal

from .executors import PARENT_SIGNALS

for _signal in PARENT_SIGNALS:
    signal.signal(_signal, signal.SIG_IGN)
signal.pthread_sigmask(signal.SIG_UNBLOCK, PARENT_SIGNALS)
