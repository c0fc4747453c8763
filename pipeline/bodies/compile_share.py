"""The warm-up calls of a first run shared with helper processes, each call taken by whichever process is free.

numba compiles a kernel on its first call and caches it on disk, each function on its own, so processes started
together can each compile some of the kernels. A fresh install's warm-up is a list of calls of very unequal cost
(measured in one process on 2 cores: from 5 s, the scanned body's, to 38 s, the 3D contact model's, 132 s in all),
so the calls are not dealt out in advance: each process takes the next call not yet taken, from one counter under a
lock, until none is left. The calling process takes calls too; its helpers are started only once it is compiling (a
warm cache loads every kernel in well under a second, less than a helper takes to start), are spawned (a fresh
interpreter: nothing of the caller's threads or state), and a helper that has taken no call when the list runs out
is ended. The caller then makes every call it did not make itself: each loads the kernel a helper compiled (or
compiles it, where a helper failed), so that the calling process holds every kernel, as without helpers.

A spawned process imports the caller's main module before it runs (Python's multiprocessing does, unless the module
is a package's ``__main__``): a program that does not keep its work under ``if __name__ == "__main__":`` would run
again in the helper. Helpers are therefore started only where that cannot happen (:func:`spawn_safe`); elsewhere the
caller compiles alone, as it would without helpers.
"""

from __future__ import annotations

import logging
import multiprocessing
import re
import sys
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Final

#: How helpers are started: a fresh interpreter (neither fork, which would copy the caller's threads, nor the
#: process pool's forkserver, whose modules are set when the pool starts it).
START_METHOD: Final = "spawn"

log = logging.getLogger(__name__)
#: The guard that keeps a program's work from running when its module is imported.
_MAIN_GUARD = re.compile(r"""^\s*if\s+__name__\s*==\s*['"]__main__['"]\s*:""", re.MULTILINE)


def spawn_safe() -> bool:
    """Whether a spawned process can start without running this program again: its main module is a package's
    ``__main__`` (``python -m``; multiprocessing does not import it again), has no file (``python -c``, an
    interactive session), or guards its work with ``if __name__ == "__main__":`` (as the console scripts pip writes
    do)."""
    main = sys.modules.get("__main__")
    name = getattr(getattr(main, "__spec__", None), "name", None)
    if name is not None and (name == "__main__" or name.endswith(".__main__")):
        return True
    path = getattr(main, "__file__", None)
    if path is None:
        return name is None
    try:
        return bool(_MAIN_GUARD.search(Path(path).read_text(encoding="utf-8", errors="replace")))
    except OSError:
        return False


class SharedCalls:
    """A list of warm-up calls taken one at a time by the calling process and up to ``helpers`` helpers.

    Parameters
    ----------
    calls : sequence of callables
        The warm-up calls, in order.
    helpers : int
        Helper processes to start (:meth:`start_helpers`); 0: the caller makes every call.
    target : callable
        What a helper runs: ``target(*args, claims, who)`` (a module-level function, as spawn requires), which
        makes the same list of calls and makes its share of them with :func:`work_through`.
    args : tuple
        The arguments the helper's ``target`` needs to make that list, passed before the claims.
    """

    def __init__(self, calls: Sequence[Callable[[], None]], *, helpers: int, target: Callable[..., None],
                 args: tuple = ()) -> None:
        self.calls, self.helpers, self.target, self.args = list(calls), max(0, int(helpers)), target, args
        #: the shared claims once helpers start (the next call not taken, its lock, per helper whether it is making
        #: a call, the number of calls); before, the next call is counted here alone
        self.claims: tuple | None = None
        self._next = 0
        self._processes: list = []
        self._guard = threading.Lock()          # the ticker's thread starts the helpers, the caller takes calls
        self._ended = False
        self.made_here: set[int] = set()

    def start_helpers(self) -> int:
        """Start the helpers (once; not after :meth:`finish`, nor in a helper or a process being spawned); how many
        were started. A helper that cannot be started is left out: the caller makes its calls."""
        with self._guard:
            if (self._ended or self._processes or self.helpers == 0 or multiprocessing.parent_process() is not None
                    or not spawn_safe()):
                return 0
            ctx = multiprocessing.get_context(START_METHOD)
            self.claims = (ctx.Value("i", self._next, lock=False), ctx.Lock(), ctx.Array("b", self.helpers,
                                                                                          lock=False), len(self.calls))
            for who in range(self.helpers):
                p = ctx.Process(target=self.target, args=(*self.args, self.claims, who), daemon=True)
                try:
                    p.start()
                except (OSError, RuntimeError) as exc:       # no process to spare, or a main module not guarded
                    log.debug("no helper to compile with: %s", exc)
                    break
                self._processes.append(p)
            return len(self._processes)

    def _take_here(self) -> int:
        """The next call for this process (-1: none left)."""
        with self._guard:
            if self.claims is not None:
                return take(self.claims, -1)
            if self._next >= len(self.calls):
                return -1
            self._next += 1
            return self._next - 1

    def run_here(self) -> None:
        """Make calls in this process until none is left to take, then :meth:`finish`."""
        while (i := self._take_here()) >= 0:
            self.calls[i]()
            self.made_here.add(i)
        self.finish()

    def finish(self) -> None:
        """No call is taken any more; wait for the helpers making one, end the others, then make here every call
        not made here (each loads what a helper compiled). The wait holds no lock the ticker's thread takes
        (:meth:`start_helpers` returns at once after the end), so that the wait is announced as it goes on."""
        with self._guard:
            self._ended = True
            processes, claims = list(self._processes), self.claims
        if claims is not None:
            next_call, lock, busy, n = claims
            with lock:
                next_call.value = n
                making = [bool(busy[k]) for k in range(len(processes))]
            for p, still in zip(processes, making):
                if not still:
                    p.terminate()
                p.join()
        for i, call in enumerate(self.calls):
            if i not in self.made_here:
                call()
                self.made_here.add(i)

    @property
    def processes(self) -> tuple:
        """The helpers started (``multiprocessing`` processes)."""
        return tuple(self._processes)


def take(claims, who: int) -> int:
    """The index of the next call not yet taken (-1 when none is left); ``who`` >= 0, a helper, is marked as making
    it (or as idle when none is left)."""
    next_call, lock, busy, n = claims
    with lock:
        i = next_call.value
        if i >= n:
            if who >= 0:
                busy[who] = 0
            return -1
        next_call.value = i + 1
        if who >= 0:
            busy[who] = 1
        return i


def work_through(calls: Sequence[Callable[[], None]], claims, who: int) -> None:
    """A helper's work: make each call of ``calls`` (the caller's list, made again the same way) that it takes
    (:func:`take`), until none is left."""
    while (i := take(claims, who)) >= 0:
        calls[i]()
