"""One run engine for the commands that judge a directory record by record (``screen``, ``screen fragility``).

The commands differ in what a record's task computes and in how its result is cached and assembled. They share
the rest, which lives here: the tasks ordered with the largest records first, run on an executor, with the
workers' scene progress shown beside the progress bar. A task that returns a :class:`~pipeline.errors.TaskFailure`
(``screen fragility``'s) and a worker the executor lost both come back as one value, a
:class:`~pipeline.records.listing.Failure` that names the record and its files. ``screen``'s task returns its
record's failed row instead (the row goes into ``screening.nc``), built from the same value
(:func:`~pipeline.run.screening.failed_result`).

A run goes: scan the directory once (:func:`~pipeline.records.listing.list_directory`), then
:meth:`RecordJobs.run`, the one record-job loop of ``screen``, ``screen fragility`` and the margins stage: each job
looked up in the command's cache, the rest run on the executor under one failure policy (:class:`Guarded`: any
exception a task raises comes back as a :class:`~pipeline.errors.TaskFailure`, and a lost worker as one too), every
result handed to the command's collector as it arrives.
"""

from __future__ import annotations

import logging
import os
import shutil
import tempfile
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import Any

from ..errors import RockscreenError, TaskFailure
from ..records.listing import Failure, RecordSource
from ..scene_progress import SceneProgress, running

log = logging.getLogger(__name__)


def largest_first(tasks: list[tuple]) -> list[tuple]:
    """The tasks (each a tuple whose first item is its :class:`~pipeline.records.listing.RecordSource`) by
    decreasing size of their records' files: the longest records start first, so that no worker is left with a
    long record while the others idle (measured on the bundled records with 2 workers: the nominal run 10.2 s in
    scan order, 7.7-8.1 s largest first)."""
    def size(task: tuple) -> int:
        total = 0
        for f in task[0].files:
            try:
                total += os.path.getsize(f)
            except OSError:                   # vanished since the scan: the task reports it
                pass
        return total
    return sorted(tasks, key=size, reverse=True)


def removing(stream, directory: str):
    """``stream``, removing ``directory`` once it is exhausted or abandoned."""
    try:
        yield from stream
    finally:
        shutil.rmtree(directory, ignore_errors=True)


def task_failure(exc: Exception, record_id: str) -> TaskFailure:
    """The failure a task returns for an exception it caught, the traceback of an unexpected one logged."""
    if not isinstance(exc, RockscreenError):
        log.exception("unexpected error on record %s", record_id)
    return TaskFailure.from_exception(exc)


class Guarded:
    """A record task under the one failure policy: whatever it raises (a bug or an unforeseen corruption as well as
    a :class:`~pipeline.errors.RockscreenError`) comes back as a :class:`~pipeline.errors.TaskFailure`, so one bad
    record never stops the batch (picklable: the executors send it to their workers)."""

    def __init__(self, task: Callable[[tuple, Any], Any]):
        self.task = task

    def __call__(self, item: tuple, ctx) -> Any:
        try:
            return self.task(item, ctx)
        except Exception as exc:  # noqa: BLE001 - the policy: every failure is the record's, reported
            return task_failure(exc, item[0].record_id)


def as_failure(source: RecordSource, failure: TaskFailure) -> Failure:
    """A task's failure (its content, a crash, a lost worker) as the record's :class:`Failure`."""
    return Failure(source.record_id, tuple(source.files), failure.reason, deterministic=failure.deterministic)


class TaskRun:
    """The tasks of one batch of records on an executor.

    Parameters
    ----------
    executor
        A :mod:`pipeline.run.executors` executor, already entered.
    progress : callable, optional
        ``progress(iterable, total, running=...)`` wrapping the stream of finished tasks (the CLI's bar).

    Attributes
    ----------
    scenes : SceneProgress
        Where the workers say which scene they are on: the tasks' context carries it.
    """

    def __init__(self, executor, *, progress: Callable | None = None, label: str | None = None):
        self.executor, self.progress, self.label = executor, progress, label
        self._dir = tempfile.mkdtemp(prefix="rockscreen-scenes-")
        self.scenes = SceneProgress(self._dir)

    def results(self, task: Callable[[tuple, Any], Any], items: list[tuple], ctx) -> Iterator[tuple[tuple, Any]]:
        """``(item, result)`` as the tasks finish, the largest records started first; a
        :class:`~pipeline.errors.TaskFailure` (the task's own or a lost worker's) comes as a :class:`Failure` in
        place of the result."""
        stream = removing(self.executor.map_unordered(task, largest_first(items), ctx), self._dir)
        if self.progress is not None:
            named = {} if self.label is None else {"label": self.label}
            stream = self.progress(stream, len(items), running=lambda: running(self._dir), **named)
        for item, res in stream:
            yield item, (as_failure(item[0], res) if isinstance(res, TaskFailure) else res)


@dataclass
class JobCounts:
    """What one :meth:`RecordJobs.run` did."""

    computed: int = 0             # jobs run on the executor that returned a result
    reused: int = 0               # jobs answered by the command's cache
    failed: int = 0               # jobs that failed (their task, or a lost worker)


class RecordJobs:
    """The record-job loop of every command that works record by record: one batch of jobs, run once.

    Parameters
    ----------
    executor
        A :mod:`pipeline.run.executors` executor, already entered.
    progress : callable, optional
        ``progress(iterable, total, running=..., label=...)`` wrapping the stream of finished tasks (the CLI's
        bar).
    label : str, optional
        What a finished task is, for the progress line (default: the progress's own, "records screened").

    Attributes
    ----------
    scenes : SceneProgress
        Where the workers say which scene they are on: the tasks' context carries it.
    """

    def __init__(self, executor, *, progress: Callable | None = None, label: str | None = None):
        self._tasks = TaskRun(executor, progress=progress, label=label)
        self.scenes = self._tasks.scenes

    def run(self, task: Callable[[tuple, Any], Any], jobs: Iterable[tuple], ctx, *,
            done: Callable[[tuple, Any, bool], None], failed: Callable[[tuple, Failure], None],
            cached: Callable[[tuple], Any] | None = None) -> JobCounts:
        """Run the jobs (each a tuple whose first item is its record's
        :class:`~pipeline.records.listing.RecordSource`), the largest records first.

        ``cached(job)`` answers a job from the command's cache (None: compute it); ``done(job, result, reused)``
        collects each result as it arrives (a cached one with ``reused`` True); ``failed(job, failure)`` each
        :class:`~pipeline.records.listing.Failure` (the task's own, under :class:`Guarded`, or a lost worker's).
        """
        counts = JobCounts()
        todo = []
        for job in jobs:
            hit = cached(job) if cached is not None else None
            if hit is None:
                todo.append(job)
                continue
            done(job, hit, True)
            counts.reused += 1
        for job, res in self._tasks.results(Guarded(task), todo, ctx):
            if isinstance(res, Failure):
                failed(job, res)
                counts.failed += 1
            else:
                done(job, res, False)
                counts.computed += 1
        return counts
