"""Exit codes and signals: what each code means, and SIGTERM or SIGHUP treated as Ctrl-C."""

from __future__ import annotations

import argparse
import atexit
import contextlib
import logging
import os
import signal
import sys
import threading
from typing import NoReturn

log = logging.getLogger("pipeline")

EXIT_OK, EXIT_RECORD_FAILURES, EXIT_USAGE, EXIT_OUTPUT = 0, 1, 2, 3
EXIT_LOCKED = 75          # sysexits EX_TEMPFAIL: another run holds the output; try again later
EXIT_INTERRUPTED = 130


#: What each command's exit codes mean, for its --help
EXIT_CODES = {
    "run": "0 ok; 1 some records failed (each reported; --tolerate-failures makes it 0, except when no record was "
           "screened); 2 bad usage, configuration, inventory or no record found; 3 the output cannot be written "
           "(earlier results intact); 75 another run holds the output; 130 interrupted (the work done is kept)",
    "records": "0 ok; 1 some records failed (--tolerate-failures: 0); 2 bad usage, configuration or inventory; "
               "3 the output cannot be written; 75 another run holds the output; 130 interrupted",
    "plain": "0 ok; 2 bad usage, configuration, inventory or input file; 3 the output cannot be written; "
             "130 interrupted",
    "locked": "0 ok; 2 bad usage, configuration, inventory or input file; 3 the output cannot be written; 75 another "
              "run holds the output; 130 interrupted",
}


def _run_exit(records_failed: int, args: argparse.Namespace, *, records_ok: int = 1) -> int:
    """1 when records failed (unless --tolerate-failures), else 0: the same for a run and an up-to-date one. A run
    that screened no record exits 1 whatever the flags: nothing it wrote says an asset is safe."""
    if records_failed and not records_ok:
        log.error("no record was screened (%d failed): every asset is 'not screened'; fix the failures above and run "
                  "again (this exits 1 even with --tolerate-failures)", records_failed)
        return EXIT_RECORD_FAILURES
    return EXIT_RECORD_FAILURES if records_failed and not args.tolerate_failures else EXIT_OK


#: Signals a command treats as Ctrl-C (what systemd, Kubernetes and Slurm send to stop a job, and a closed terminal):
#: the work done is kept, the output's lock released, and the exit code is 130.
INTERRUPT_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


#: A ``KeyboardInterrupt`` swallowed where Python cannot raise it (a finalizer: a weak reference's callback, a
#: ``__del__``) is raised again by sending its signal again after REDELIVER_S [s], at most MAX_REDELIVERIES times in
#: a command (each lands at Python's next check of its signals, almost always outside a finalizer).
REDELIVER_S = 0.01
MAX_REDELIVERIES = 100


def _raise_interrupt(signum, frame) -> None:
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise KeyboardInterrupt(f"signal {signal.Signals(signum).name}")


@contextlib.contextmanager
def _signals_interrupt(*, to_the_end: bool = False, received: list[int] | None = None):
    """While a command runs (in the main thread), :data:`INTERRUPT_SIGNALS` raise ``KeyboardInterrupt`` as Ctrl-C
    does; the previous handlers are restored after, or, with ``to_the_end`` (the console command), those signals and
    Ctrl-C are only noted from then on, for :func:`finish_console` to find. Every signal, Ctrl-C included (unless it
    is ignored, as in a background job), is noted in ``received`` (yielded). One whose ``KeyboardInterrupt`` Python
    swallowed (raised in a finalizer, where it is only reported) is sent again (:data:`REDELIVER_S`), so that the
    command stops as interrupted rather than run on; still swallowed at the end, it is in ``received``, and the
    command is then reported interrupted."""
    received = [] if received is None else received
    if threading.current_thread() is not threading.main_thread():
        yield received
        return

    def interrupt(signum, frame) -> None:
        received.append(signum)
        _raise_interrupt(signum, frame)

    handled = (*INTERRUPT_SIGNALS, *([signal.SIGINT] if signal.getsignal(signal.SIGINT) is signal.default_int_handler
                                     else []))
    previous = {s: signal.signal(s, interrupt) for s in handled}
    previous_hook, timers = sys.unraisablehook, list[threading.Timer]()
    sys.unraisablehook = _redelivering(received, previous_hook, timers)
    try:
        yield received
    finally:
        sys.unraisablehook = previous_hook
        for timer in timers:             # a signal sent again after the command would reach its caller
            timer.cancel()
        if to_the_end:                   # the disposition is the process's: no thread may die of one from here
            for s in (*INTERRUPT_SIGNALS, signal.SIGINT):
                signal.signal(s, lambda signum, frame: received.append(signum))
        else:
            for s, handler in previous.items():
                signal.signal(s, handler)


def _redelivering(received: list[int], previous_hook, timers: list[threading.Timer]):
    """A ``sys.unraisablehook`` that, for a ``KeyboardInterrupt`` of :func:`_signals_interrupt` swallowed in a
    finalizer, sends the last signal noted in ``received`` to this process again after :data:`REDELIVER_S` (at most
    :data:`MAX_REDELIVERIES` times; each timer in ``timers``), instead of printing it; every other report goes to
    ``previous_hook``. A signal sent again that arrives before the hook has returned (a loaded machine) raises its
    KeyboardInterrupt inside the hook, where Python swallows it as well: it is sent once more."""

    def send_again() -> None:
        if len(timers) < MAX_REDELIVERIES:
            timer = threading.Timer(REDELIVER_S, os.kill, (os.getpid(), received[-1]))
            timer.daemon = True
            timers.append(timer)
            timer.start()

    def hook(unraisable) -> None:
        if not (isinstance(unraisable.exc_value, KeyboardInterrupt) and received):
            previous_hook(unraisable)
            return
        try:
            send_again()
        except KeyboardInterrupt:        # the signal just sent again landed here, before the hook returned
            send_again()

    return hook


def finish_console(code: int, received: list[int]) -> NoReturn:
    """End the console command with ``code``, or :data:`EXIT_INTERRUPTED` when one of :data:`INTERRUPT_SIGNALS` or
    Ctrl-C arrived since it returned (``received``, noted by the handlers :func:`_signals_interrupt` left): the exit
    functions run, the output is flushed and the process ends at once. Python's own finalization would put back the
    signals' default actions first, and a signal in that window ended the process with its own status (143 for
    SIGTERM) instead of 130."""
    with contextlib.suppress(Exception):          # Python's own order: threads joined, then the exit functions
        threading._shutdown()                     # type: ignore[attr-defined]
    with contextlib.suppress(Exception):
        atexit._run_exitfuncs()
    _flush()
    if received and code != EXIT_INTERRUPTED:
        print("interrupted as the command ended: what it wrote above is complete", file=sys.stderr)
        _flush()
    os._exit(EXIT_INTERRUPTED if received else code)       # from the check to the end: microseconds


def _flush() -> None:
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
