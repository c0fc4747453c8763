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
    #: What ground motions have (:mod:`pipeline.records.plausibility`): a record outside these fails with the
    #: value named, or is screened with a warning when ``implausible = "warn"``. The largest peak acceleration of
    #: a component, in g (the largest recorded are about 3-4 g; a spike of thousands of g is a unit or a data
    #: error).
    max_pga_g: float = 10.0
    #: Sampling intervals accepted [s] (strong-motion records are sampled at 1-10,000 Hz).
    min_dt_s: float = 1e-4
    max_dt_s: float = 1.0
    #: Longest record [s] and most samples per component: beyond these a record is not an earthquake's
    #: strong motion, and its analysis would take memory without bound (about 1.7 kB per sample at the peak).
    max_duration_s: float = 3600.0
    max_samples: int = 1_000_000
    #: ``fail`` (a record outside the limits fails, named) or ``warn`` (it is screened, with a warning and a note).
    implausible: str = "fail"


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
    """What :func:`pipeline.records.loader.load_record` and :func:`~pipeline.records.listing.list_directory` read."""

    @property
    def records(self) -> RecordsConfig: ...

    @property
    def processing(self) -> ProcessingConfig: ...
