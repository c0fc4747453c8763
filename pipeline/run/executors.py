"""Executors behind one interface: serial, local processes, Dask distributed.

Every executor maps a task function over items and yields ``(item, result)``
pairs as they complete, in any order, to a single consumer (the writer).
Tasks are coarse (one record with its blocks) and load their data by path,
so a task's arguments are a path list and the shared context. The shared
context (configuration, inventory) is sent once per worker where the
backend allows it (Dask ``scatter``).

A worker that dies does not lose its task: the process executor restarts
its pool and re-runs each task that was in flight alone (so a task that
kills its worker is told apart from its neighbours); Dask reschedules it by
itself. A task that kills its worker every time fails alone, as a failed
record.

References
----------
Dask best practices (coarse tasks, load data inside tasks) and
``distributed.as_completed``: https://docs.dask.org/en/stable/best-practices.html
"""

from __future__ import annotations

import ctypes
import functools
import gc
import logging
import multiprocessing
import os
import signal
import threading
import time
from collections import deque
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Callable, Iterable, Iterator

from ..errors import DependencyError, SchedulerError, TaskFailure, UsageError

log = logging.getLogger(__name__)

#: Ctrl-C and a closed terminal's SIGHUP reach the whole process group: the run's own process handles them (it
#: cancels the pool and keeps what was done); the pool's forkserver and workers ignore them.
PARENT_SIGNALS = (signal.SIGINT, signal.SIGHUP)

#: How many times a task may kill its worker, running alone, before it is given up.
MAX_TASK_ATTEMPTS = 3

#: Modules the process pool's forkserver imports before it forks a worker: the record task's whole stack (numpy,
#: scipy, obspy, numba, xarray and the pipeline). Each worker imported them itself before; forked from the server,
#: the workers share those pages with it and with each other (the memory a process tree holds, its summed PSS, is
#: measured in docs/validation.md). The first module ignores, in the server, the signals the run's process handles.
#: The server starts once a run knows it uses the pool (:func:`start_workers_early`), or with the first pool of a
#: process, and keeps what it imported. Besides the pipeline's own imports, the two a record's processing imports when
#: it first detrends and filters (obspy's Trace.detrend and Trace.filter import scipy.signal and obspy.signal, which
#: imports its PPSD: 0.75-1.0 s and 0.8-0.9 s measured after the pipeline's imports), once in the server instead of
#: in each worker.
FORKSERVER_PRELOAD = ("pipeline.run.quiet_server", "pipeline.run.batch", "scipy.signal", "obspy.signal")

#: The environment of the process workers, each variable unless the user set it, as Dask's Nanny sets its workers'
#: (``distributed.nanny.pre-spawn-environ``; the numba pool's size and the mmap threshold are this one's own): one
#: thread per BLAS, OpenMP or numba pool (N workers with a pool of threads each oversubscribe the cores: -n 2 ran 2.6x
#: slower than serial without it); glibc's malloc trimming the top of a worker's heap whenever more than 64 KiB is
#: free there, so that more of what a worker frees after a record goes back to the system (docs/validation.md
#: measures the process tree's memory with and without it); and, since setting a trim threshold turns off glibc's
#: adjustment of its mmap threshold, that threshold fixed at glibc's largest adjusted value, 32 MiB: at its
#: 128 KiB start every array of a long record's length is mapped and unmapped again at each use, and each of its
#: pages faulted in afresh (on the bundled default run the workers took 2.1-2.2 s of system time each, with 1.2
#: million page faults, against 0.5-0.6 s and 0.2 million with it; docs/validation.md).
WORKER_ENVIRONMENT = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
                      "NUMBA_NUM_THREADS": "1", "MALLOC_TRIM_THRESHOLD_": "65536",
                      "MALLOC_MMAP_THRESHOLD_": str(32 * 2**20)}

#: Dask settings of the LocalCluster (``--scheduler local``): its periodic housekeeping made rarer. With one worker
#: per core, every cycle a worker's other threads or its nanny spend is taken from a record task: at Dask's defaults
#: the record tasks of a 10-record run spent 44.0 s of wall time for 39.2 s of their own thread's CPU (the worker's
#: statistical profiler samples every 10 ms, the event loop ticks every 20 ms, the nanny reads the worker's memory
#: every 100 ms); with these, 40.3 s for 39.4 s, as in the process pool (40.1 s for 39.0 s). What they give up:
#: the dashboard's profile and its refresh, the nanny's memory limit checked every 2 s instead of 0.1 s, and the
#: scheduler's work stealing every 1 s instead of 0.1 s (a task is a whole record). A remote cluster keeps its own
#: configuration (docs/user-guide.md says how to set the same there). Its nannies give their workers the process
#: workers' environment besides (:func:`worker_environment`).
LOCAL_CLUSTER_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.worker.memory.monitor-interval": "2s",
    "distributed.scheduler.work-stealing-interval": "1s",
}


def worker_environment() -> dict[str, str]:
    """The environment a worker runs with: :data:`WORKER_ENVIRONMENT` (which holds the variables Dask's nanny sets, at
    Dask's values), each variable the user set at the user's value."""
    return {name: os.environ.get(name, value) for name, value in WORKER_ENVIRONMENT.items()}


class TaskLost(TaskFailure):
    """A task whose worker died on every attempt (never deterministic: a later run retries it)."""

    def __reduce__(self):
        return (TaskLost, (self.reason,))


class SerialExecutor:
    """Run tasks one after another in this process (the default; easiest to debug)."""

    name = "serial"
    n_workers = 1

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return None

    def map_unordered(self, fn: Callable, items: Iterable, shared) -> Iterator[tuple]:
        for item in items:
            yield item, fn(item, shared)

    def release(self) -> None:
        """Nothing to end: the tasks ran in this process."""


class ProcessExecutor:
    """A local process pool with a bounded number of tasks in flight.

    Parameters
    ----------
    n_workers : int
        Worker processes (``-n N``).
    """

    name = "processes"

    def __init__(self, n_workers: int):
        self.n_workers = checked_workers(n_workers)
        self._pool: ProcessPoolExecutor | None = None
        self._entered = False

    def _new_pool(self) -> ProcessPoolExecutor:
        # forkserver: workers never inherit the parent's threads (progress bar, Dask client); the server imports the
        # tasks' modules once (FORKSERVER_PRELOAD), and the workers forked from it share those pages
        return ProcessPoolExecutor(max_workers=self.n_workers, mp_context=_forkserver_context(),
                                   initializer=_worker_init, initargs=(os.getpid(),))

    def __enter__(self):
        # the forkserver reads the environment when it starts; the workers it forks inherit it
        os.environ.update(worker_environment())
        self._entered = True
        return self

    def __exit__(self, exc_type, *exc):
        if self._pool is not None:
            if exc_type is not None:
                # an interrupt or an error: the tasks in flight are given up, so their workers end now (SIGTERM,
                # whose default the workers keep), also one the pool is still starting, which would otherwise
                # print a traceback when the queues it was forked for are gone
                for process in list(getattr(self._pool, "_processes", {}).values()):
                    process.terminate()
            self._pool.shutdown(wait=exc_type is None, cancel_futures=True)
        self._pool = None
        self._entered = False

    def release(self) -> None:
        """End the workers now, their memory returned to the system (a later map starts a new pool): a run's last
        tasks done, the main process assembles and writes without idle workers beside it."""
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None

    def map_unordered(self, fn: Callable, items: Iterable, shared) -> Iterator[tuple]:
        if not self._entered:
            raise RuntimeError("ProcessExecutor.map_unordered outside its 'with' block")
        pending = deque(items)
        if not pending:
            return
        if self._pool is None:          # started at the first work: a run with nothing to compute starts none
            self._pool = self._new_pool()
        pool: ProcessPoolExecutor = self._pool
        suspects: deque = deque()       # tasks in flight when a worker died: each is re-run alone
        deaths: dict[int, int] = {}
        in_flight: dict = {}
        alone = False
        limit = 2 * self.n_workers
        while pending or suspects or in_flight:
            if not in_flight and suspects:
                item = suspects.popleft()
                try:
                    in_flight[pool.submit(trimmed, fn, item, shared)] = item
                    alone = True
                except BrokenProcessPool:       # lost with no task in flight: a new pool, the task not yet run
                    suspects.appendleft(item)
                    pool.shutdown(wait=False, cancel_futures=True)
                    self._pool = pool = self._new_pool()
                    continue
            try:
                while not alone and pending and len(in_flight) < limit:
                    item = pending.popleft()
                    in_flight[pool.submit(trimmed, fn, item, shared)] = item
            except BrokenProcessPool:
                # a worker died after the last wait: this task never ran; the ones in flight report the loss (none
                # in flight: an idle worker died, and a new pool takes the work)
                pending.appendleft(item)
                if not in_flight:
                    pool.shutdown(wait=False, cancel_futures=True)
                    self._pool = pool = self._new_pool()
                    continue
            done, _ = wait(in_flight, return_when=FIRST_COMPLETED)
            broken = False
            for fut in done:
                item = in_flight.pop(fut)
                try:
                    result = fut.result()
                except BrokenProcessPool:
                    in_flight[fut] = item
                    broken = True
                    continue
                yield item, result
            if broken:
                # the pool is lost with every task in flight: start a new one; a task that was
                # running alone killed its worker itself, the others are re-run alone to find out
                lost = list(in_flight.values())
                in_flight.clear()
                pool.shutdown(wait=False, cancel_futures=True)
                self._pool = pool = self._new_pool()
                log.warning("a worker process died; restarting the pool and retrying %d task(s)", len(lost))
                if alone:
                    (item,) = lost
                    n = deaths[id(item)] = deaths.get(id(item), 0) + 1
                    if n >= MAX_TASK_ATTEMPTS:
                        yield item, TaskLost(f"the worker process died {n} times running this task alone")
                    else:
                        suspects.append(item)
                else:
                    suspects.extend(lost)
            if not in_flight:
                alone = False


#: The environment variable that sets the default number of worker processes (``-n``).
WORKERS_ENV = "ROCKSCREEN_NUM_PROCESSES"


def default_workers() -> int:
    """The default ``-n``: ``$ROCKSCREEN_NUM_PROCESSES``, else the cores this process may run on.

    Raises
    ------
    UsageError
        For a value of the variable that is not a positive integer.
    """
    value = os.environ.get(WORKERS_ENV, "").strip()
    if value:
        try:
            n = int(value)
        except ValueError:
            raise UsageError(f"{WORKERS_ENV}={value!r}: expected a positive integer (the default of -n)") from None
        if n < 1:
            raise UsageError(f"{WORKERS_ENV}={value!r}: expected a positive integer (the default of -n)")
        return n
    return available_cores()


def available_cores() -> int:
    """The cores this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def workers(n: int | None) -> int:
    """The number of worker processes of a run: ``-n`` when given, else :func:`default_workers`, checked."""
    return checked_workers(default_workers() if n is None else n)


def checked_workers(n: int) -> int:
    """``-n``: a number of worker processes, at least 1.

    Raises
    ------
    UsageError
        Naming the value.
    """
    if n < 1:
        raise UsageError(f"-n {n}: the number of worker processes must be >= 1")
    return n


#: How often a worker checks that the run that started it is still there [s]: a worker whose run was killed (SIGKILL,
#: the OOM killer) ends within this time, and with the last worker the pool's forkserver and resource tracker,
#: which live as long as a worker holds their pipes.
PARENT_POLL_S = 1.0
#: A worker's exit status when its run is gone.
EXIT_ORPHANED = 70


def _forkserver_context():
    """The forkserver's multiprocessing context, its server started (:func:`_start_server`) to import
    :data:`FORKSERVER_PRELOAD`."""
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(list(FORKSERVER_PRELOAD))
    _start_server()
    return context


def _start_server() -> None:
    """Start the forkserver (and multiprocessing's resource tracker) unless it runs, :data:`PARENT_SIGNALS` ignored
    in it from its first instruction: ignored here for the instant of the start (an ignored signal stays ignored
    across exec, and Python keeps it so), and blocked meanwhile, so that one that arrives then reaches this process's
    own handler after it. Where this is not the main thread (which alone may set handlers), the server is started as
    it is, and ignores them from its first import (:mod:`.quiet_server`)."""
    from multiprocessing import forkserver

    if threading.current_thread() is not threading.main_thread():
        forkserver.ensure_running()
        return
    held = signal.pthread_sigmask(signal.SIG_BLOCK, PARENT_SIGNALS)
    handlers = {sig: signal.signal(sig, signal.SIG_IGN) for sig in PARENT_SIGNALS}
    try:
        forkserver.ensure_running()
    finally:
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, held)


def start_workers_early(*, n_workers: int, scheduler: str | None) -> bool:
    """Start the process pool's forkserver now, where the run will use the pool (:func:`uses_processes`), and return
    at once: the server imports the tasks' modules
    (:data:`FORKSERVER_PRELOAD`, over a second) while this process reads the inventory and loads the simulator,
    instead of after, when the first task starts the pool. The environment the workers run with
    (:func:`worker_environment`) is set first, as :meth:`ProcessExecutor.__enter__` sets it; the pool then forks its
    workers from this server. True where it was started (or already running)."""
    if not uses_processes(n_workers=n_workers, scheduler=scheduler):
        return False
    os.environ.update(worker_environment())
    _forkserver_context()
    return True


def _worker_init(parent_pid: int) -> None:
    """Each worker of the process pool: ignore Ctrl-C and a closed terminal's SIGHUP, which reach the whole process
    group (the parent handles them, cancels the pool and keeps what was done; SIGTERM keeps its default, which the
    pool uses to end its workers when one of them dies), end when the run that started it is gone, and leave the
    objects it was forked with (the forkserver's imports) out of its garbage collections: a collection writes to
    every object it visits, so each worker's first full collection copied about 40 MB of the pages it shares with
    the server (``gc.freeze``; measured in docs/validation.md)."""
    gc.freeze()
    for sig in PARENT_SIGNALS:
        signal.signal(sig, signal.SIG_IGN)
    threading.Thread(target=_end_with, args=(parent_pid,), name="rockscreen-parent-watch", daemon=True).start()


def _end_with(parent_pid: int) -> None:
    """End this worker at once when the process ``parent_pid`` has ended (its parent is the pool's forkserver,
    which outlives the run, so the kernel's parent-death signal cannot serve)."""
    while True:
        time.sleep(PARENT_POLL_S)
        if not process_alive(parent_pid):
            os._exit(EXIT_ORPHANED)


def trimmed(fn: Callable, item, shared):
    """``fn(item, shared)`` in a pool worker, then every free page of the worker's heap handed back to the system
    (:func:`trim_heap`), so that what a record's task freed is not held while the worker waits or starts the next.
    """
    try:
        return fn(item, shared)
    finally:
        trim_heap()


def trim_heap() -> bool:
    """Hand every free page of this process's malloc heaps back to the system (glibc's ``malloc_trim(0)``: the free
    pages inside the heap too, where the trim threshold of :data:`WORKER_ENVIRONMENT` releases its top only);
    0.5-7 ms after a record of the scale benchmark. Returns whether anything was released; False where the C library
    has no ``malloc_trim`` (not glibc).
    """
    trim = _malloc_trim()
    return bool(trim(0)) if trim is not None else False


@functools.lru_cache(maxsize=1)
def _malloc_trim():
    """glibc's ``malloc_trim``, or None where the C library has none."""
    try:
        trim = ctypes.CDLL(None).malloc_trim         # the C library the interpreter runs on
    except (OSError, AttributeError):
        return None
    trim.argtypes, trim.restype = [ctypes.c_size_t], ctypes.c_int
    return trim


def process_alive(pid: int) -> bool:
    """Whether process ``pid`` runs (a zombie, ended but not yet reaped by its parent, does not)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            state = fh.read().rsplit(b")", 1)[1].split()[0]
        return state != b"Z"
    except FileNotFoundError:
        return False
    except (OSError, IndexError):           # no /proc (not Linux): ask the kernel
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        except PermissionError:
            return True
        return True


class DaskExecutor:
    """Dask distributed: a remote scheduler (``tcp://HOST:PORT``) or a LocalCluster (``local``).

    Parameters
    ----------
    scheduler : str
        ``"local"`` for a LocalCluster on this machine, else a scheduler address.
    n_workers : int
        Workers of the LocalCluster (ignored for a remote scheduler).
    """

    name = "dask"

    def __init__(self, scheduler: str, n_workers: int = 2):
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise DependencyError("--scheduler needs Dask: pip install 'rockscreen[dask]'") from None
        self.scheduler = scheduler
        self.n_workers = n_workers
        self.client: Any = None
        self.cluster: Any = None

    def __enter__(self):
        import dask
        from distributed import Client, LocalCluster

        # distributed sets its own loggers to INFO on import; follow the application's verbosity instead
        logging.getLogger("distributed").setLevel(max(logging.getLogger().getEffectiveLevel(), logging.INFO))
        if self.scheduler == "local":
            with dask.config.set({**LOCAL_CLUSTER_CONFIG, "distributed.nanny.pre-spawn-environ": worker_environment()}):
                # the nannies hand both to their workers
                self.cluster = LocalCluster(n_workers=self.n_workers, threads_per_worker=1, processes=True,
                                            host="127.0.0.1", dashboard_address=":0")
            self.client = Client(self.cluster)
            log.info("Dask LocalCluster at %s, dashboard %s", self.cluster.scheduler_address,
                     self.client.dashboard_link)
        else:
            try:
                self.client = Client(self.scheduler, timeout="20s")
            except OSError as exc:
                raise SchedulerError(f"--scheduler {self.scheduler}: no Dask scheduler answers there ({exc}); "
                                      "start one with 'dask scheduler' or use --scheduler local") from exc
        self.n_workers = max(1, len(self.client.scheduler_info().get("workers", {})))
        return self

    def __exit__(self, *exc):
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        self.client = self.cluster = None

    def release(self) -> None:
        """Nothing ended: a cluster's workers are its own (a LocalCluster's end with the executor)."""

    def map_unordered(self, fn: Callable, items: Iterable, shared) -> Iterator[tuple]:
        from distributed import as_completed

        items = list(items)
        if not items:
            return
        # hash=False: a fresh key per map, so a second map never races with the release of the first
        shared_future = self.client.scatter(shared, broadcast=True, hash=False)
        # the items' order is the caller's (largest record first): Dask's priority keeps it, as the pools' queues do
        futures = {self.client.submit(fn, item, shared_future, pure=False, priority=len(items) - k): k
                   for k, item in enumerate(items)}
        try:
            for fut in as_completed(futures):
                item = items[futures[fut]]
                try:
                    yield item, fut.result()
                except Exception as exc:            # KilledWorker after repeated worker deaths, ...
                    yield item, TaskLost(f"Dask could not run this task: {type(exc).__name__}: {exc}")
                fut.release()
        finally:
            self.client.cancel(list(futures))


def uses_processes(*, n_workers: int, scheduler: str | None) -> bool:
    """Whether :func:`make_executor` gives a :class:`ProcessExecutor` for these options."""
    return scheduler == "processes" or (scheduler in (None, "serial") and n_workers > 1)


def make_executor(*, n_workers: int = 1, scheduler: str | None = None):
    """The executor for the command-line options ``-n`` and ``--scheduler``.

    ``scheduler`` is None/"serial", "processes", "local" (Dask LocalCluster)
    or a Dask scheduler address; with None, ``n_workers > 1`` means processes.
    """
    if uses_processes(n_workers=n_workers, scheduler=scheduler):
        return ProcessExecutor(n_workers)
    if scheduler in (None, "serial"):
        return SerialExecutor()
    return DaskExecutor(scheduler, n_workers=n_workers)
