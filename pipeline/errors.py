"""Exception hierarchy.

Every error raised on bad input is a :class:`RockscreenError` and also the
builtin class a Python user would expect (``ValueError`` for bad values,
``OSError`` for file-system trouble), so ``except ValueError`` keeps working.
Messages say what was found, what was expected, and how to fix it.
"""

from __future__ import annotations


class RockscreenError(Exception):
    """Base class of every error raised by rockscreen."""


class UsageError(RockscreenError, ValueError):
    """A command or function was called with arguments that cannot work together or are out of range."""


class RecordsNotFoundError(RockscreenError, FileNotFoundError):
    """The records directory does not exist."""


class DependencyError(RockscreenError, ImportError):
    """An optional dependency a feature needs is not installed."""


class SchedulerError(RockscreenError, ConnectionError):
    """No Dask scheduler answers at the given address."""


class NoRecordsError(RockscreenError, ValueError):
    """The records directory holds no strong-motion record."""


class RecordFormatError(RockscreenError, ValueError):
    """A record file is corrupt, truncated, empty or not in a known format."""


class UnitsError(RockscreenError, ValueError):
    """The physical units of a record cannot be determined or converted."""


class UndeclaredUnitsError(UnitsError):
    """Nothing states a file's units (no header, no response, no declaration): it needs a ``units.toml`` entry.

    Attributes
    ----------
    path : str
        The file.
    suggested : str
        The unit the file's peak reads as most plausibly (see :func:`pipeline.records.units.plausible_units`).
    readings : str
        What the peak reads as in each plausible unit, for the user to check.
    """

    def __init__(self, message: str, *, path: str, suggested: str, readings: str):
        super().__init__(message)
        self.path, self.suggested, self.readings = path, suggested, readings


class RecordGroupingError(RockscreenError, ValueError):
    """Components of one station recording do not fit together."""


class InventoryError(RockscreenError, ValueError):
    """The block inventory CSV is invalid (names file, line and column)."""


class HazardError(RockscreenError, ValueError):
    """The hazard-curve CSV is invalid (names file, line and value)."""


class ConstraintError(RockscreenError, ValueError):
    """Inputs of a hazard constraint by fragile rocks that cannot be used (an age, a branch, a weight, a rock)."""


class ConfigError(RockscreenError, ValueError):
    """The TOML configuration is invalid (names the key and the valid values)."""


class ParameterError(RockscreenError, ValueError):
    """An impossible analysis parameter (names the parameter and its valid range)."""


class BlockParameterError(ParameterError):
    """Impossible block or friction parameters (names the parameter and range)."""


class MeshError(RockscreenError, ValueError):
    """A scanned shape cannot be used: unreadable, not closed, or not standing on its base."""


class PulseError(RockscreenError, ValueError):
    """Pulse extraction cannot run on this record (too short, all zero, ...)."""


class ResultsError(RockscreenError, ValueError):
    """A results file given as input is missing or not a rockscreen netCDF file."""


class TaskFailure(RockscreenError, RuntimeError):
    """A task of a batch that could not produce its result: returned in place of the result, never raised, so
    one bad record never stops the batch. Every task (screening, margins, fragility) and every executor
    (a worker lost) reports failure with this one value.

    Attributes
    ----------
    reason : str
        What went wrong, for the record's status and the log.
    deterministic : bool
        The record's content causes it (format, units, ...): the same files fail the same way again, so the
        failure may be cached. A crash or a lost worker is not, and is retried.
    """

    def __init__(self, reason: str, *, deterministic: bool = False):
        super().__init__(reason)
        self.reason, self.deterministic = reason, deterministic

    @classmethod
    def from_exception(cls, exc: BaseException) -> "TaskFailure":
        """The failure for an exception caught in a task: deterministic for a RockscreenError (the content),
        not for anything else (a bug or an unforeseen corruption, named by its type)."""
        if isinstance(exc, RockscreenError):
            return cls(str(exc), deterministic=True)
        return cls(f"unexpected {type(exc).__name__}: {exc}")

    def __reduce__(self):                     # picklable across processes with its keyword argument
        return (_task_failure, (self.reason, self.deterministic))


def _task_failure(reason: str, deterministic: bool) -> TaskFailure:
    return TaskFailure(reason, deterministic=deterministic)


class InterruptedAfterPublishing(RockscreenError, KeyboardInterrupt):
    """Ctrl-C (or SIGTERM, SIGHUP) that arrived while a command swapped in its new output set: the set was swapped
    whole, and the command stops there."""


def raised_by_interrupt(exc: BaseException) -> bool:
    """Whether ``exc`` is a ``KeyboardInterrupt`` or was raised from or while handling one (its causes and contexts):
    a Ctrl-C that lands while a C extension initialises becomes that extension's error, raised from the interrupt
    (scipy's HiGHS wrapper: ``ImportError: initialization failed``)."""
    seen: set[int] = set()
    link: BaseException | None = exc
    while link is not None and id(link) not in seen:
        if isinstance(link, KeyboardInterrupt):
            return True
        seen.add(id(link))
        link = link.__cause__ or link.__context__
    return False


class OutputError(RockscreenError, OSError):
    """Results cannot be written (unwritable directory, disk full, ...)."""


class UnsafeOutputError(OutputError):
    """Something under the output directory is not what rockscreen makes there (a planted link, a file where its
    state directory goes): refused before anything is changed."""


class OutputLockedError(OutputError):
    """Another run holds the lock on the output directory."""
