"""One station recording's data, read, converted to m s-2, aligned and processed into a
:class:`~pipeline.records.record.Record`: the second of the two passes through a records directory (:mod:`.listing`
groups the files, reading headers only), so that records stream through memory one at a time.

:func:`load_record` refuses a record whose files or headers are implausibly large before any sample is read, reads
its files, converts units (the headers, ``units.toml``, StationXML), orders the horizontals (the second 90 deg
clockwise of the first), aligns the components, applies the processing steps and integrates to velocity.
"""

from __future__ import annotations

import logging
import re
from pathlib import Path

import numpy as np

from ..constants import CM_TO_M
from ..errors import RecordFormatError, RecordGroupingError, RockscreenError, UndeclaredUnitsError, UnitsError
from .common import COMMON
from .coordinates import StationLocation, station_location
from .detect import detect_format
from .listing import RecordSource, find_records
from .orientation import Orientation, orientation_of
from .plausibility import check_plausible, refuse_implausible_headers, refuse_large_files
from .processing import apply_steps, integrate, integration_method
from .record import Record
from .settings import ReaderSettings
from .side_files import read_declared_units
from .streams import read_stream
from .units import advice, declared_units_for, to_ms2

log = logging.getLogger(__name__)


def _header_peak_ms2(tr, g_ms2: float) -> float | None:
    s = tr.stats
    if "at2" in s and s.at2.header_pga_g is not None:
        return abs(s.at2.header_pga_g) * g_ms2
    if "knet" in s and s.knet.get("accmax") is not None:
        return abs(float(s.knet.accmax)) * CM_TO_M  # Max. Acc. (gal)
    if "dmg" in s and s.dmg.header_peak is not None and s.dmg.header_peak_units:
        return abs(s.dmg.header_peak) * (CM_TO_M if "cm" in s.dmg.header_peak_units else g_ms2)
    return None


def _align(traces, *, max_mismatch: int, notes: list[str]) -> None:
    """Trim components in place to a common length (time-aligned where start times exist)."""
    dts = {round(t.stats.delta, 12) for t in traces}
    if max(dts) - min(dts) > 1e-9 * max(dts):
        detail = ", ".join(f"{t.stats.channel}: {t.stats.delta:g} s" for t in traces)
        raise RecordGroupingError(
            f"components have different sampling intervals ({detail}); resample them to one "
            "interval before screening"
        )
    timed = all(t.stats[COMMON].time_known for t in traces)
    lengths = [t.stats.npts for t in traces]
    if timed and len(traces) > 1:
        start = max(t.stats.starttime for t in traces)
        end = min(t.stats.endtime for t in traces)
        if end <= start:
            raise RecordGroupingError("components do not overlap in time")
        for t in traces:
            t.trim(start, end, nearest_sample=True)
        n = min(t.stats.npts for t in traces)
        for t in traces:
            t.data = t.data[:n]
        if len(set(lengths)) > 1 or n != lengths[0]:
            notes.append(f"components trimmed to their common time window: {lengths} -> {n} samples")
        return
    # no start times (PEER AT2 and others): the files of one recording start together; align them at their
    # first sample and keep the common part
    n = min(lengths)
    if max(lengths) != n:
        for t in traces:
            t.data = t.data[:n]
        note = (f"component lengths {lengths} differ and the files give no start time: aligned at their first "
                f"sample and trimmed to the shorter, {n} samples")
        notes.append(note)
        if max(lengths) - n > max_mismatch:
            log.warning("%s: %s (more than records.max_length_mismatch_samples = %d; check that the files "
                        "belong together)", ", ".join(t.stats.get("rockscreen_file", t.stats.channel)
                                                   for t in traces), note, max_mismatch)


#: obspy writes arguments such as ``<Inventory object at 0x7f...>`` into its processing history;
#: the address changes from run to run, so it is dropped to keep results reproducible.
_OBJECT_ADDRESS = re.compile(r" object at 0x[0-9a-fA-F]+>")


def load_record(source: RecordSource, *, root: str | Path, config: ReaderSettings,
                declared: dict[str, str] | None = None, inventory=None) -> Record:
    """Read, convert, align and process one station recording.

    Raises
    ------
    RockscreenError
        (``RecordFormatError``, ``UnitsError``, ``RecordGroupingError``) with the reason.
    """
    root = Path(root)
    declared = read_declared_units(root, config) if declared is None else declared
    notes: list[str] = []
    _refuse_before_reading(source, config)
    traces = _traces_in_ms2(source, root=root, config=config, declared=declared, inventory=inventory)
    check_plausible(traces, record_id=source.record_id, records=config.records, notes=notes)   # before processing
    horizontals, verticals = _components(traces, source, inventory, notes)
    horizontals, az = _horizontal_pair(horizontals, notes)
    azimuth_known = all(o.azimuth_deg is not None for o, _ in horizontals)
    ordered = [tr for _, tr in horizontals] + verticals
    _align(ordered, max_mismatch=config.records.max_length_mismatch_samples, notes=notes)
    history = _processed(ordered, [tr for _, tr in horizontals], config, notes)
    hz = np.vstack([np.asarray(tr.data, dtype=float) for _, tr in horizontals])
    if not np.any(hz):
        raise RecordGroupingError(
            f"every horizontal sample of {[tr.stats.channel for _, tr in horizontals]} is zero after "
            "processing: no horizontal motion to screen (a dead channel or a file of zeros); check the source")
    levels = {tr.stats.get("processing_level", "uncorrected") for tr in ordered}
    level = "corrected" if levels == {"corrected"} else "uncorrected"
    method = integration_method(getattr(config.processing, level))
    dt = float(ordered[0].stats.delta)
    history.append(f"velocity: integrate ({method})")
    peaks = {tr.stats.channel: p for tr in ordered
             if (p := _header_peak_ms2(tr, config.records.g_ms2)) is not None}
    return Record(
        record_id=source.record_id,
        dt_s=dt,
        horizontal_ms2=hz,
        azimuths_deg=tuple(float(a) for a in az),
        azimuth_known=azimuth_known,
        vertical_ms2=np.asarray(verticals[0].data, dtype=float) if verticals else None,
        files=source.files,
        formats=source.formats,
        component_codes=tuple(tr.stats.channel for tr in ordered),
        processing_level=level,
        notes=notes,
        history=history,
        header_peaks_ms2=peaks,
        velocity_ms=integrate(hz, dt, method=method),
        label=next((tr.stats[COMMON].label for tr in ordered if tr.stats[COMMON].label), ""),
    )


def _refuse_before_reading(source: RecordSource, config: ReaderSettings) -> None:
    """The record's file sizes, then its headers, against the plausibility limits, before any sample is read:
    memory stays bounded for a file of millions of samples (:mod:`.plausibility`)."""
    if config.records.implausible == "warn":
        return
    sizes = []
    for f in source.files:
        try:
            sizes.append((f, Path(f).stat().st_size))
        except OSError:
            pass                                  # reported by the read
    refuse_large_files(sizes, records=config.records)
    headers = []
    for f in source.files:
        for tr in read_stream(Path(f), fmt=source.format_of(f) or detect_format(Path(f)), headonly=True,
                              max_rows=config.records.max_samples):
            tr.stats.rockscreen_file = str(f)
            headers.append(tr)
    refuse_implausible_headers(headers, records=config.records)


def _traces_in_ms2(source: RecordSource, *, root: Path, config: ReaderSettings, declared: dict[str, str],
                   inventory) -> list:
    """Every trace of the record's files, converted to m s-2; the files whose units nothing states are reported
    together (one :class:`UnitsError` naming each, with the lines to declare them)."""
    traces = []
    undeclared: list[UndeclaredUnitsError] = []     # every file of the record that needs a declaration, at once
    for f in source.files:
        path = Path(f)
        for tr in read_stream(path, fmt=source.format_of(f) or detect_format(path),
                               max_rows=config.records.max_samples):
            if tr.stats.npts < 2:
                raise RecordFormatError(f"{path}: channel {tr.stats.channel or '?'} holds {tr.stats.npts} "
                                        "sample(s); the file is truncated or has no data. Re-download it")
            try:
                unit_note = to_ms2(tr, path=path, declared=declared_units_for(path, root, declared),
                                   g_ms2=config.records.g_ms2, inventory=inventory)
            except UndeclaredUnitsError as exc:
                if not any(e.path == exc.path for e in undeclared):
                    undeclared.append(exc)
                continue
            tr.stats.rockscreen_history = [f"{path.name} {tr.stats.channel}: {unit_note}"]
            tr.stats.rockscreen_file = str(path)
            traces.append(tr)
    if undeclared:
        names = ", ".join(Path(e.path).name for e in undeclared[1:])
        raise UnitsError(str(undeclared[0]) + (f" (and {names})" if names else "") + advice(root, undeclared))
    return traces


def _components(traces: list, source: RecordSource, inventory, notes: list[str]) -> tuple[list, list]:
    """The traces as (orientation, trace) horizontals and the vertical traces: at most two horizontals and one
    vertical, at least one horizontal; two horizontals whose codes no convention names are an orthogonal pair of
    unknown absolute azimuth."""
    found = [(orientation_of(tr, inventory), tr) for tr in traces]
    unknown = [tr.stats.channel for o, tr in found if o is None]
    if len(unknown) == 2 and all(o is None or o.vertical for o, _ in found):
        # two horizontals with codes no convention names: an orthogonal pair of unknown absolute azimuth
        first, second = sorted((tr for o, tr in found if o is None), key=lambda tr: tr.stats.channel)
        found = [(o, tr) for o, tr in found if o is not None]
        found += [(Orientation(False, None, 0), first), (Orientation(False, None, 1), second)]
        notes.append(f"components {first.stats.channel} and {second.stats.channel}: orientation codes not "
                     "recognised; taken as an orthogonal pair of unknown absolute azimuth "
                     f"({first.stats.channel} first)")
        unknown = []
    if unknown:
        raise RecordGroupingError(
            f"cannot tell the orientation of component(s) {unknown} in {[Path(f).name for f in source.files]}; "
            "expected an azimuth, N/E, 1/2, L/T, FN/FP, H1/H2 or UP/V/Z"
        )
    oriented = [(o, tr) for o, tr in found if o is not None]
    verticals = [tr for o, tr in oriented if o.vertical]
    horizontals = [(o, tr) for o, tr in oriented if not o.vertical]
    if len(verticals) > 1 or len(horizontals) > 2:
        raise RecordGroupingError(
            f"{len(horizontals)} horizontal and {len(verticals)} vertical components grouped "
            "together; one recording has at most two horizontals and one vertical"
        )
    if not horizontals:
        raise RecordGroupingError("vertical component only: no horizontal motion to screen")
    return horizontals, verticals


def _horizontal_pair(horizontals: list, notes: list[str]) -> tuple[list, tuple[float, ...]]:
    """The horizontals in order (the second 90 deg clockwise of the first) and their azimuths [deg]."""
    az: tuple[float, ...]
    if len(horizontals) == 2:
        (o1, t1), (o2, t2) = horizontals
        if o1.azimuth_deg is not None and o2.azimuth_deg is not None:
            diff = (o2.azimuth_deg - o1.azimuth_deg) % 360.0
            if abs(diff - 270.0) < 1.0:
                horizontals = [(o2, t2), (o1, t1)]
            elif abs(diff - 90.0) >= 1.0:
                raise RecordGroupingError(
                    f"horizontal components at {o1.azimuth_deg:g} and {o2.azimuth_deg:g} deg are not "
                    "orthogonal; rotate them to an orthogonal pair first"
                )
            first = float(horizontals[0][0].azimuth_deg or 0.0)
            az = (first, (first + 90.0) % 360.0)
        else:
            if o1.pair_index is None or o2.pair_index is None or o1.pair_index == o2.pair_index:
                raise RecordGroupingError(
                    f"components {t1.stats.channel} and {t2.stats.channel} mix known and unknown "
                    "azimuths; cannot form an orthogonal pair"
                )
            horizontals.sort(key=lambda ot: ot[0].pair_index or 0)
            az = (0.0, 90.0)
            notes.append("absolute azimuth unknown (relative orthogonal pair); block azimuths "
                         "are not used: the simulator scans every rocking plane (worst plane)")
    else:
        o1 = horizontals[0][0]
        az = (o1.azimuth_deg if o1.azimuth_deg is not None else 0.0,)
        notes.append("single horizontal component")
    return horizontals, az


def _processed(ordered: list, horizontals: list, config: ReaderSettings, notes: list[str]) -> list[str]:
    """Process every trace by its delivery level's steps; the history of the record; a horizontal all zero is
    noted, a non-finite sample refused."""
    history = []
    for tr in ordered:
        level = tr.stats.get("processing_level", "uncorrected")
        steps = getattr(config.processing, level)
        apply_steps(tr, steps)
        history += list(tr.stats.rockscreen_history) + [
            f"{Path(tr.stats.rockscreen_file).name} {tr.stats.channel}: {_OBJECT_ADDRESS.sub('>', p)}"
            for p in tr.stats.get("processing", [])]
    for tr in ordered:
        data = np.asarray(tr.data, dtype=float)
        if not np.all(np.isfinite(data)):
            raise RecordFormatError(f"{tr.stats.rockscreen_file}: NaN or infinite samples after processing")
        if not np.any(data) and tr in horizontals:
            notes.append(f"component {tr.stats.channel} is all zero")
    return history


def station_of(source: RecordSource, inventory=None) -> StationLocation | None:
    """Where a record's station is, from its files' headers alone (no samples read, nothing processed) or the
    StationXML ``inventory`` (:func:`~.coordinates.station_location`); None where neither says.

    Raises
    ------
    RecordFormatError
        For a file that cannot be read.
    """
    traces = [tr for f in source.files for tr in read_stream(Path(f), fmt=source.format_of(f), headonly=True)]
    return station_location(traces, inventory)


def iter_records(root: str | Path, *, config: ReaderSettings, inventory=None):
    """Every record under ``root`` that loads, in scan order (failures are skipped).

    For benchmarks and tests that need the bundled records as arrays; the
    screening itself keeps the failures (:func:`pipeline.run.batch.run`).
    """
    root = Path(root)
    sources, _ = find_records(root, config=config)
    declared = read_declared_units(root, config)
    for source in sources:
        try:
            yield load_record(source, root=root, config=config, declared=declared, inventory=inventory)
        except RockscreenError:
            continue
