"""A worker forked while its run ends: its start fails reading what the run's process sent it, and the forkserver's
exception hook (pipeline.run.worker_start) ends it without a traceback; any other exception is printed."""

from __future__ import annotations

import gc
import multiprocessing
import os
import pickle
import sys
from multiprocessing import context, spawn

import pytest

from pipeline.run.executors import ProcessExecutor
from pipeline.run.worker_start import run_gone_at_start, worker_start_hook


def _start_failure(payload: list[bytes]) -> tuple:
    """The exception (type, value, traceback) of multiprocessing's own worker start (``spawn._main``, as the
    forkserver's child runs it) reading ``payload`` from a pipe whose writer has closed: the run's process gone."""
    r, w = os.pipe()
    with os.fdopen(w, "wb") as writer:
        for part in payload:
            writer.write(part)
    sentinel = os.dup(r)
    try:
        spawn._main(r, sentinel)
    except Exception:
        return sys.exc_info()
    finally:
        os.close(sentinel)                      # the worker's own run would have closed it; it never starts
    raise AssertionError("the worker's start did not fail")


def _printed(exc_info: tuple) -> list:
    seen: list = []
    worker_start_hook(*exc_info, printed=lambda *a: seen.append(a[0]))
    return seen


def _unlinked_lock_state() -> bytes:
    """A pickled lock of the pool's kind whose semaphore the run's process has since released (what a worker being
    forked reads when its run ended meanwhile)."""
    lock = multiprocessing.get_context("spawn").Lock()
    context.set_spawning_popen(object())        # a lock pickles only for a process being started
    try:
        state = pickle.dumps(lock)
    finally:
        context.set_spawning_popen(None)
    del lock
    gc.collect()                                # its finalizer unlinks the semaphore
    return state


def test_a_pipe_closed_before_the_process_object_is_silent():
    exc_info = _start_failure([pickle.dumps({})])          # preparation data, then nothing: EOF
    assert exc_info[0] is EOFError
    assert run_gone_at_start(exc_info[0], exc_info[2])
    assert _printed(exc_info) == []


def test_a_released_semaphore_is_silent():
    exc_info = _start_failure([pickle.dumps({}), _unlinked_lock_state()])
    assert issubclass(exc_info[0], FileNotFoundError)      # as the forkserver's child met it in CI
    assert _printed(exc_info) == []


def test_another_error_at_the_start_is_printed():
    exc_info = _start_failure([b"not a pickle"])
    assert not issubclass(exc_info[0], (OSError, EOFError))
    assert _printed(exc_info) == [exc_info[0]]


@pytest.mark.parametrize("error", [OSError, EOFError, FileNotFoundError])
def test_the_same_error_outside_a_worker_start_is_printed(error):
    try:
        raise error("elsewhere")
    except error:
        exc_info = sys.exc_info()
    assert not run_gone_at_start(exc_info[0], exc_info[2])
    assert _printed(exc_info) == [error]


def _hook(item, shared):
    return sys.excepthook


@pytest.mark.slow
def test_the_pool_s_workers_carry_the_hook():
    """The pool's forkserver installs it (pipeline.run.quiet_server, imported first there), and its workers inherit
    it: the hook a task sees in a worker is this one."""
    with ProcessExecutor(1) as ex:
        hooks = [hook for _, hook in ex.map_unordered(_hook, range(1), None)]
    assert hooks == [worker_start_hook]
