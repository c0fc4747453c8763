"""Ctrl-C and the signals a command treats as it (:mod:`pipeline.cli.exits`): an interrupt Python swallows in a
finalizer (where it can only report it) still stops the command, raised again by the signal sent once more."""

from __future__ import annotations

import argparse
import signal
import time
import weakref

import pytest

from pipeline.cli.exits import EXIT_INTERRUPTED, MAX_REDELIVERIES, _signals_interrupt
from pipeline.cli.main import _run


@pytest.fixture
def ctrl_c_raises():
    """Ctrl-C as a terminal's foreground command meets it (a test runner may have it ignored)."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


class _Anything:
    pass


def _swallowed(signum: int) -> None:
    """``signum`` raised inside a finalizer: its handler's KeyboardInterrupt is reported as unraisable, not raised."""
    thing = _Anything()
    weakref.finalize(thing, signal.raise_signal, signum)
    del thing


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_an_interrupt_swallowed_in_a_finalizer_is_raised_again(ctrl_c_raises, signum):
    with pytest.raises(KeyboardInterrupt):
        with _signals_interrupt() as received:
            _swallowed(signum)
            deadline = time.monotonic() + 5.0
            while time.monotonic() < deadline:
                time.sleep(0.01)
    assert received[0] == signum and len(received) >= 2          # noted, then sent again and raised


def test_an_ignored_ctrl_c_stays_ignored():
    """A background job starts with Ctrl-C ignored: the command keeps it so, noting nothing."""
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with _signals_interrupt() as received:
            signal.raise_signal(signal.SIGINT)
            time.sleep(0.05)
        assert received == []
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)


def test_handlers_and_the_hook_are_restored_and_nothing_is_sent_after(ctrl_c_raises):
    """A command that ends before its swallowed interrupt is sent again: the sending is cancelled (the caller's
    Ctrl-C would raise in the sleep below), and the command is told (``received``)."""
    import sys

    hook, term = sys.unraisablehook, signal.getsignal(signal.SIGTERM)
    with _signals_interrupt() as received:
        _swallowed(signal.SIGINT)
    assert received == [signal.SIGINT]
    assert sys.unraisablehook is hook and signal.getsignal(signal.SIGTERM) is term
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    time.sleep(0.2)


def test_the_signal_is_sent_again_a_bounded_number_of_times(ctrl_c_raises):
    """Each interrupt swallowed again is sent again, up to the cap; then the command is told at its end
    (``received``) and runs on."""
    with _signals_interrupt() as received:
        with pytest.MonkeyPatch.context() as mp:
            import pipeline.cli.exits as exits

            mp.setattr(exits, "REDELIVER_S", 0.001)

            def always_swallowed(signum, frame):     # every delivery lands in a finalizer
                received.append(signum)
                _swallowed_raise()

            signal.signal(signal.SIGINT, always_swallowed)
            _swallowed(signal.SIGINT)
            time.sleep(1.0)
            signal.signal(signal.SIGINT, signal.default_int_handler)
    assert 2 <= len(received) <= MAX_REDELIVERIES + 1


def _swallowed_raise() -> None:
    thing = _Anything()
    weakref.finalize(thing, _raise)
    del thing


def _raise() -> None:
    raise KeyboardInterrupt


def test_a_resent_interrupt_landing_inside_the_hook_is_sent_once_more(ctrl_c_raises, monkeypatch):
    """On a loaded machine the signal sent again may arrive before the hook that sent it has returned: its
    KeyboardInterrupt is then raised inside the hook, where Python swallows it too. The first sending is made to
    land there (the signal sent at once, while the hook runs); the command must still be interrupted."""
    import os
    import threading

    from pipeline.cli import exits

    real_timer, first = threading.Timer, []

    class _LandsInTheHook(real_timer):
        def start(self) -> None:
            if not first:
                first.append(True)
                os.kill(os.getpid(), self.args[1])        # handled before the hook returns
                return
            super().start()

    monkeypatch.setattr(exits.threading, "Timer", _LandsInTheHook)
    with pytest.raises(KeyboardInterrupt):
        with _signals_interrupt():
            _swallowed(signal.SIGINT)
            deadline = time.monotonic() + 5.0
            while time.monotonic() < deadline:
                time.sleep(0.01)
    assert first


def _importing_when_interrupted(args, argv) -> int:
    """A command interrupted while a C extension initialises: Ctrl-C arrives, and the extension's import turns the
    interrupt into its own error, raised from it (scipy's HiGHS wrapper: ``ImportError: initialization failed``)."""
    try:
        signal.raise_signal(signal.SIGINT)
        time.sleep(5.0)
    except KeyboardInterrupt as exc:
        raise ImportError("initialization failed") from exc
    return 0


def test_an_interrupt_turned_into_an_import_error_stops_the_command_as_interrupted(ctrl_c_raises, capsys):
    received: list[int] = []
    code = _run(_importing_when_interrupted, argparse.Namespace(), [], console=False, received=received)
    assert code == EXIT_INTERRUPTED and received == [signal.SIGINT]
    assert "interrupted" in capsys.readouterr().err


def test_an_import_error_without_an_interrupt_is_raised(ctrl_c_raises):
    """The same error where no signal arrived (an interrupt raised by the command's own code, or none) is not
    taken for an interrupt: it propagates."""
    def failing(args, argv) -> int:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise ImportError("initialization failed") from exc

    with pytest.raises(ImportError, match="initialization failed"):
        _run(failing, argparse.Namespace(), [], console=False, received=[])
