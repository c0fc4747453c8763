"""Exit codes and signals: what each code means, and SIGTERM or SIGHUP treated as Ctrl-C."""

from __future__ import annotations

import argparse
import contextlib
import logging
import signal
import threading

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


def _raise_interrupt(signum, frame) -> None:
    raise KeyboardInterrupt(f"signal {signal.Signals(signum).name}")


@contextlib.contextmanager
def _signals_interrupt():
    """While a command runs (in the main thread), :data:`INTERRUPT_SIGNALS` raise ``KeyboardInterrupt`` as Ctrl-C
    does; the previous handlers are restored after."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, _raise_interrupt) for s in INTERRUPT_SIGNALS}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
