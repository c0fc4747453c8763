"""Whether a record is a ground motion at all: its peak, sampling interval, duration and length against what
strong-motion records have (the limits are ``[records]`` settings, :class:`~.settings.RecordsConfig`).

A record outside them is most often a unit or data error: a spike of thousands of g, an interval typed in the
wrong unit, a file of another kind of data. It fails with the value and the limit named and the fix, or, with
``implausible = "warn"``, is screened with a warning and a note in its results. The check runs on the converted
traces before any processing; the sizes of its files and their headers are checked before the samples are read
(:func:`refuse_large_files`, :func:`refuse_implausible_headers`), so that a record of millions of samples is
refused before it takes memory.
"""

from __future__ import annotations

import logging

import numpy as np

from ..errors import RecordFormatError
from .settings import RecordsConfig

log = logging.getLogger(__name__)


class ImplausibleRecordError(RecordFormatError):
    """A record whose peak, interval, duration or length is outside what ground motions have."""


#: The most bytes a record file can plausibly hold per sample of each component: the widest text format read
#: (one value per line, with its time) takes about 30; binary formats take 4 or fewer.
BYTES_PER_SAMPLE_MAX = 80
#: The most components a record file holds (COSMOS and CSMIP/DMG volumes hold three)
COMPONENTS_PER_FILE_MAX = 3


def header_implausibilities(traces, *, records: RecordsConfig) -> list[str]:
    """What is outside the limits of ``records`` in the traces' headers alone (interval, length, duration: read
    before the samples, so that a record of millions of samples is refused before it takes memory)."""
    out = []
    c = records
    for tr in traces:
        where = f"{tr.stats.get('rockscreen_file', '?')} {tr.stats.channel}"
        dt, n = float(tr.stats.delta), int(tr.stats.npts)
        if not c.min_dt_s <= dt <= c.max_dt_s:
            out.append(f"{where}: sampling interval {dt:g} s outside [{c.min_dt_s:g}, {c.max_dt_s:g}] s "
                       "([records] min_dt_s, max_dt_s)")
        if n > c.max_samples:
            out.append(f"{where}: {n} samples, more than {c.max_samples} ([records] max_samples)")
        if dt * (n - 1) > c.max_duration_s:
            out.append(f"{where}: {dt * (n - 1):g} s long, more than {c.max_duration_s:g} s ([records] "
                       "max_duration_s)")
    return out


def implausibilities(traces, *, records: RecordsConfig) -> list[str]:
    """What is outside the limits of ``records`` in the converted traces (values in m s-2): the headers'
    (:func:`header_implausibilities`) and the peak, each with its value, its limit and the setting that holds it;
    empty when the record is plausible."""
    out = header_implausibilities(traces, records=records)
    for tr in traces:
        n = int(tr.stats.npts)
        peak_g = float(np.max(np.abs(tr.data))) / records.g_ms2 if n and len(tr.data) else 0.0
        if peak_g > records.max_pga_g:
            out.append(f"{tr.stats.get('rockscreen_file', '?')} {tr.stats.channel}: peak acceleration "
                       f"{peak_g:.4g} g, more than {records.max_pga_g:g} g ([records] max_pga_g)")
    return out


def file_size_limit(max_samples: int) -> int:
    """The largest file a record of ``max_samples`` samples takes: :data:`BYTES_PER_SAMPLE_MAX` x
    :data:`COMPONENTS_PER_FILE_MAX` x ``max_samples`` [bytes] (as text, or decompressed)."""
    return BYTES_PER_SAMPLE_MAX * COMPONENTS_PER_FILE_MAX * max_samples


def refuse_large_files(sizes, *, records: RecordsConfig) -> None:
    """Refuse a record whose file is larger than :data:`BYTES_PER_SAMPLE_MAX` x :data:`COMPONENTS_PER_FILE_MAX` x
    ``max_samples`` bytes, before anything of it is read; ``sizes``: (path, bytes) of each file. Nothing is
    refused with ``implausible = "warn"`` (the record is then read and screened with a warning).

    Raises
    ------
    ImplausibleRecordError
        Naming the file, its size and the limit, and the fix.
    """
    limit = file_size_limit(records.max_samples)
    found = [f"{p}: {size:,} bytes, more than a file of {COMPONENTS_PER_FILE_MAX} components of "
             f"{records.max_samples:,} samples takes ({limit:,} bytes; [records] max_samples)"
             for p, size in sizes if size > limit]
    if found and records.implausible != "warn":
        raise _refusal(found)


def refuse_implausible_headers(headers, *, records: RecordsConfig) -> None:
    """Refuse a record from its headers alone (:func:`header_implausibilities`), before its samples are read.
    Nothing is refused with ``implausible = "warn"``.

    Raises
    ------
    ImplausibleRecordError
        Naming each value outside its limit, and the fix.
    """
    found = header_implausibilities(headers, records=records)
    if found and records.implausible != "warn":
        raise _refusal(found)


def check_plausible(traces, *, record_id: str, records: RecordsConfig, notes: list[str]) -> None:
    """Refuse a record outside the limits (:func:`implausibilities`), or, with ``implausible = "warn"``, warn and
    note it in ``notes``.

    Raises
    ------
    ImplausibleRecordError
        Naming each value outside its limit, and the fix.
    """
    found = implausibilities(traces, records=records)
    if not found:
        return
    if records.implausible == "warn":
        for f in found:
            log.warning("record %s is screened although %s", record_id, f)
            notes.append(f"implausible, screened as asked ([records] implausible = 'warn'): {f}")
        return
    raise _refusal(found)


def _refusal(found: list[str]) -> ImplausibleRecordError:
    return ImplausibleRecordError(
        "not what ground motions have: " + "; ".join(found) + ". Check the file's units (units.toml) and header; "
        "if the record is right, raise the limit in the configuration, or set [records] implausible = \"warn\" to "
        "screen it with a warning")
