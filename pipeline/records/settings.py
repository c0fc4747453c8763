"""Settings of the record readers (the ``[records]`` and ``[processing]`` sections of a configuration).

The readers own these dataclasses; :mod:`pipeline.config` maps a TOML file onto them.
:class:`ReaderSettings` is what the loader needs: any object with ``records`` and
``processing`` attributes of these types (:class:`pipeline.config.Config` is one).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

from ..constants import G


def _steps(*steps: dict) -> tuple:
    return tuple(dict(s) for s in steps)


@dataclass(frozen=True)
class RecordsConfig:
    """Reading and grouping records."""

    #: g used to convert records stated in g [m s-2].
    g_ms2: float = G
    #: Components without start times are aligned at their first sample and trimmed to the shorter; a
    #: warning names them when their lengths differ by more than this many samples.
    max_length_mismatch_samples: int = 20
    #: Traces of one station starting within this time belong to one recording [s].
    group_time_tolerance_s: float = 60.0
    #: Units of files that do not state them, by glob (also read from ``units.toml``).
    declared_units: dict = field(default_factory=dict)


@dataclass(frozen=True)
class ProcessingConfig:
    """Ordered processing steps by delivery level (see :mod:`pipeline.records.processing`)."""

    uncorrected: tuple = _steps(
        {"step": "demean"},
        {"step": "detrend", "type": "linear"},
        {"step": "taper", "max_percentage": 0.05, "type": "hann"},
        {"step": "highpass", "freq": 0.05, "corners": 4, "zerophase": True},
        {"step": "integrate", "method": "trapezoid"},
    )
    corrected: tuple = _steps({"step": "integrate", "method": "trapezoid"})



class ReaderSettings(Protocol):
    """What :func:`pipeline.records.loader.load_record` and :func:`~pipeline.records.loader.scan` read."""

    @property
    def records(self) -> RecordsConfig: ...

    @property
    def processing(self) -> ProcessingConfig: ...
