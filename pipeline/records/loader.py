"""From a directory of files to :class:`~pipeline.records.record.Record` objects.

Two passes, so that records stream through memory one at a time:

1. :func:`scan` reads only headers and groups the files of one station
   recording (SEED id and start time for obspy formats; header station line
   for AT2), returning light :class:`RecordSource` objects;
2. :func:`load_record` reads one source's data, converts units, aligns the
   components, applies the processing steps and integrates to velocity.

A file or group that fails becomes a :class:`Failure` carrying the reason;
the other records are unaffected.
"""

from __future__ import annotations

import glob
import hashlib
import logging
import os
import re
import sys
import warnings
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import obspy

from ..constants import CM_TO_M
from ..errors import RecordFormatError, RecordGroupingError, RockscreenError, UndeclaredUnitsError, UnitsError
from .common import COMMON, annotate
from .compressed import refuse_if_expands_beyond
from .coordinates import StationLocation, station_location
from .detect import detect_format, looks_like_a_record
from .orientation import Orientation, orientation_of
from .plausibility import (
    check_plausible,
    file_size_limit,
    refuse_implausible_headers,
    refuse_large_files,
)
from .processing import apply_steps, integrate, integration_method
from .record import Record
from .settings import ReaderSettings
from .table import MAX_ROWS as TABLE_MAX_ROWS
from .table import TABLE_FORMAT
from .units import UNITS_TABLE, advice, canonical_units, combined_declarations, declared_units_for, to_ms2

log = logging.getLogger(__name__)

#: Files in a records directory that are metadata, not records.
SIDE_FILES = {"units.toml"}
SIDE_SUFFIXES = {".xml"}


@dataclass(frozen=True)
class RecordSource:
    """The files of one station recording, before their data are read."""

    record_id: str
    files: tuple[str, ...]
    formats: tuple[str, ...]
    #: obspy format of each file, aligned with ``files`` (detected by content at the scan)
    file_formats: tuple[str, ...] = ()
    #: SHA-256 of each file's bytes, aligned with ``files`` (taken at the scan, so a run reads them once)
    file_sha256: tuple[str, ...] = ()

    def format_of(self, path: str) -> str | None:
        """The detected format of one of the files, or None (detect again)."""
        return dict(zip(self.files, self.file_formats)).get(path)

    def digest(self) -> str:
        """SHA-256 over the names and content of the files (for re-run detection), from the byte digests
        taken at the scan when there are any; a file that vanished since is an error."""
        try:
            for f in self.files:
                os.stat(f)
            return files_sha256(self.files, byte_digests=dict(zip(self.files, self.file_sha256)))
        except OSError as exc:
            raise RecordFormatError(f"{exc.filename}: the file vanished or became unreadable after the records "
                                    f"directory was scanned ({exc.strerror}); re-run when the directory "
                                    "is stable") from None


def files_sha256(paths, *, byte_digests: dict[str, str] | None = None) -> str:
    """SHA-256 over the names and the bytes' SHA-256 of ``paths``, in sorted order ("" for none).

    ``byte_digests`` gives the bytes' digests already taken (path -> hex); the other files are read.

    Raises
    ------
    OSError
        If a file cannot be read.
    """
    paths = sorted(str(p) for p in paths)
    if not paths:
        return ""
    known = byte_digests or {}
    h = hashlib.sha256()
    for f in paths:
        h.update(os.fsencode(Path(f).name))
        h.update((known.get(f) or _bytes_sha256(f)).encode())
    return h.hexdigest()


@dataclass(frozen=True)
class Failure:
    """A record (or an unreadable file) that could not be screened: the one failure value of a run, from the scan
    or from a record's task (:mod:`pipeline.run.engine`). ``deterministic``: the files cause it (format, units,
    ...), so the same files fail the same way again; a crash or a lost worker is not, and is retried."""

    record_id: str
    files: tuple[str, ...]
    reason: str
    deterministic: bool = False


def read_declared_units(root: Path, config: ReaderSettings) -> dict[str, str]:
    """Merge ``units.toml`` in ``root`` (table ``[files]``) with the configuration's declarations."""
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib

    declared = {}
    for pattern, unit in config.records.declared_units.items():
        declared[pattern] = canonical_units(unit, where=f"config records.declared_units[{pattern!r}]")
    path = root / "units.toml"
    if path.exists():
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise UnitsError(f"{path}: not valid TOML ({exc})") from exc
        stray = [k for k in data if k != "files"]
        if stray:
            raise UnitsError(f"{path}: {', '.join(repr(k) for k in stray)} outside the [files] table, where it "
                             "would be ignored; put every declaration on a line after the line [files], e.g.\n"
                             "[files]\n\"sac/*.sac\" = \"g\"")
        for pattern, unit in data.get("files", {}).items():
            declared[pattern] = canonical_units(str(unit), where=f"{path} [files] {pattern!r}")
    return declared


def stationxml_paths(root: Path, extra: str | Path | None = None) -> list[Path]:
    """The StationXML files a run uses: every ``*.xml`` under ``root``, then ``extra``."""
    paths = sorted(p for p in Path(root).rglob("*.xml") if p.is_file())
    if extra is not None:
        paths.append(Path(extra))
    return paths


def read_inventory(root: Path, extra: str | Path | None = None):
    """Read every StationXML file in ``root`` (and ``extra``) into one inventory, or None."""
    paths = stationxml_paths(root, extra)
    inventory = None
    for p in paths:
        try:
            inv = obspy.read_inventory(_literal(p))
        except Exception as exc:
            if extra is not None and Path(extra) == p:
                raise UnitsError(f"{p}: not a readable StationXML inventory ({exc})") from exc
            continue
        inventory = inv if inventory is None else inventory + inv
    return inventory


def units_toml_lines(root: str | Path, messages: list[str]) -> list[str]:
    """The ``units.toml`` lines a run's failure ``messages`` ask for, merged into globs that match exactly the
    files needing them among the records directory's files (:func:`~.units.combined_declarations`)."""
    if not any(UNITS_TABLE in m for m in messages):
        return []
    root = Path(root)
    return combined_declarations(messages, [p.relative_to(root).as_posix() for p in _record_files(root)])


def _utf8_name(path: Path) -> bool:
    """Whether ``path``'s name is text (the file system gave valid UTF-8, not bytes Python could only escape)."""
    try:
        path.name.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _record_files(root: Path) -> list[Path]:
    """Every regular file under ``root`` that may hold a record: all but hidden files, ``units.toml``
    and StationXML (``*.xml``, read as the inventory), whatever their extension."""
    files = []
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = sorted(d for d in dirnames if not d.startswith("."))
        for name in sorted(filenames):
            p = Path(dirpath) / name
            if name.startswith(".") or name in SIDE_FILES or p.suffix.lower() in SIDE_SUFFIXES or not p.is_file():
                continue
            files.append(p)
    return files


def _literal(path: Path) -> str:
    """``path`` as obspy's readers take it: obspy expands a path's wildcards (``*``, ``?``, ``[...]``) as a glob,
    so a record named ``rec[1].AT2`` would be read as ``rec1.AT2``; escaped, the pattern matches the file itself."""
    return glob.escape(str(path))


def _read(path: Path, *, fmt: str | None = None, headonly: bool = False,
          max_rows: int = TABLE_MAX_ROWS) -> obspy.Stream:
    try:
        try:
            size = path.stat().st_size
        except FileNotFoundError:
            raise RecordFormatError(f"{path}: the file vanished after the records directory was scanned; "
                                    "re-run when the directory is stable") from None
        if size == 0:
            raise RecordFormatError(f"{path}: the file is empty; expected a strong-motion record")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            if fmt == TABLE_FORMAT:             # read as a stream by its own reader, gzip included
                st = obspy.read(_literal(path), format=fmt, headonly=headonly, check_compression=False,
                                max_rows=max_rows)
            else:
                refuse_if_expands_beyond(path, file_size_limit(max_rows))
                st = obspy.read(_literal(path), format=fmt, headonly=headonly)
        for w in caught:
            if "end of file" in str(w.message).lower():
                raise RecordFormatError(f"{path}: truncated ({w.message}); re-download the file")
        for tr in st:
            annotate(tr)
        return st
    except RockscreenError:
        raise
    except TypeError as exc:
        if "Unknown format" in str(exc) or "unknown format" in str(exc).lower():
            raise RecordFormatError(
                f"{path}: unrecognised format (not AT2, COSMOS, CSMIP/DMG, or any format obspy "
                "reads); remove it from the records directory or convert it"
            ) from None
        raise RecordFormatError(f"{path}: cannot be read ({exc})") from exc
    except Exception as exc:
        raise RecordFormatError(f"{path}: corrupt or truncated ({type(exc).__name__}: {exc})") from exc


def _group_key(tr, path: Path) -> tuple:
    info = tr.stats[COMMON]
    if info.recording:
        return ("HEADER", str(path.parent), info.recording)
    cha = tr.stats.channel
    knet_like = re.fullmatch(r"(NS|EW|UD)([12]?)", cha)
    seed_like = not knet_like and len(cha) == 3 and cha[:2].isalpha()
    if info.standalone or not (seed_like or knet_like):
        return ("FILE", str(path))
    band = cha[:2] if seed_like or knet_like is None else knet_like.group(2)
    return ("SEED", tr.stats.network, tr.stats.station, tr.stats.location, band)


def _common_stem(files: list[str]) -> str:
    stems = [Path(f).stem for f in files]
    prefix = os.path.commonprefix(stems).rstrip("-_. ")
    return prefix if len(prefix) >= 3 else stems[0]


@dataclass
class Listing:
    """What a records directory holds.

    Attributes
    ----------
    sources : list of RecordSource
        One per station recording, sorted by id.
    failures : list of Failure
        Files that look like records (by content or by name) but cannot be read.
    not_records : list of (path, reason)
        Files no reader recognises and whose name does not say they are records.
    files_seen : int
        Regular files offered to the readers.
    duplicates : list of (kept id, duplicate id, files)
        Recordings whose files hold the same bytes as an earlier one's under other names: screened
        once, under the first id.
    """

    sources: list[RecordSource]
    failures: list[Failure]
    not_records: list[tuple[str, str]]
    files_seen: int
    duplicates: list[tuple[str, str, tuple[str, ...]]] = field(default_factory=list)


def find_records(root: str | Path, *, config: ReaderSettings) -> tuple[list[RecordSource], list[Failure]]:
    """Group the files under ``root`` into station recordings, reading headers only
    (:func:`list_directory` without the files that are not records)."""
    found = list_directory(root, config=config)
    return found.sources, found.failures


def list_directory(root: str | Path, *, config: ReaderSettings) -> Listing:
    """Offer every regular file under ``root`` to the readers by content, and group the records.

    A file no reader recognises is a failed record when its name says it is a record
    (:data:`pipeline.records.detect.RECORD_SUFFIXES`), and is listed in ``not_records`` otherwise.
    """
    root = Path(root)
    if not root.is_dir():
        raise RecordFormatError(f"{root}: records directory not found")
    groups: dict[tuple, list[tuple]] = defaultdict(list)
    failures = []
    not_records = []
    files = _record_files(root)
    for path in files:
        if not _utf8_name(path):
            shown = os.fsencode(path).decode("utf-8", "backslashreplace")
            failures.append(Failure(os.fsencode(path.stem).decode("utf-8", "backslashreplace"), (shown,),
                                    f"{shown}: the file name is not UTF-8 (its bytes shown as \\x..); results name "
                                    "their records in UTF-8: rename it (e.g. 'convmv -f latin1 -t utf8 --notest')",
                                    deterministic=True))
            continue
        empty = path.stat().st_size == 0
        fmt = None if empty else detect_format(path)
        if fmt is None and not looks_like_a_record(path):
            if empty:
                not_records.append((str(path), "empty file"))
            else:
                not_records.append((str(path), "no reader recognises its content (not AT2, COSMOS, CSMIP/DMG, "
                                               "K-NET, SAC, MiniSEED or any other format obspy reads)"))
            continue
        try:
            st = _read(path, fmt=fmt, headonly=True, max_rows=config.records.max_samples)
        except (RecordFormatError, UnitsError) as exc:        # this file alone fails: the others are screened
            failures.append(Failure(path.stem, (str(path),), str(exc)))
            continue
        for tr in st:
            groups[_group_key(tr, path)].append((tr.stats.starttime, str(path), tr.stats._format))
    sources = []
    tol = config.records.group_time_tolerance_s
    for key, members in groups.items():
        members.sort()
        clusters: list[list[tuple]] = []
        for m in members:
            if key[0] == "SEED" and clusters and abs(m[0] - clusters[-1][0][0]) <= tol:
                clusters[-1].append(m)
            elif key[0] != "SEED" and clusters:
                clusters[-1].append(m)
            else:
                clusters.append([m])
        for c in clusters:
            by_file = {f: fmt for _, f, fmt in c}
            group_files = sorted(by_file)
            formats = tuple(sorted(set(by_file.values())))
            sources.append(RecordSource(_common_stem(group_files), tuple(group_files), formats,
                                        tuple(by_file[f] for f in group_files)))
    seen: dict[str, int] = defaultdict(int)
    unique = []
    for s in sorted(sources, key=lambda s: (s.record_id, s.files)):
        seen[s.record_id] += 1
        rid = s.record_id if seen[s.record_id] == 1 else f"{s.record_id}#{seen[s.record_id]}"
        unique.append(RecordSource(rid, s.files, s.formats, s.file_formats))
    kept, duplicates = [], []
    first_with: dict[tuple, str] = {}
    for s in unique:
        try:
            hashes = tuple(_bytes_sha256(f) for f in s.files)
        except OSError:                         # vanished since: the plan reports it with the reason
            kept.append(s)
            continue
        content = tuple(sorted(hashes))
        if content in first_with:
            duplicates.append((first_with[content], s.record_id, s.files))
            continue
        first_with[content] = s.record_id
        kept.append(RecordSource(s.record_id, s.files, s.formats, s.file_formats, hashes))
    return Listing(kept, failures, not_records, len(files), duplicates)


def _bytes_sha256(path: str) -> str:
    """SHA-256 of a file's bytes (not its name): equal for the same file under two names."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


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
        for tr in _read(Path(f), fmt=source.format_of(f) or detect_format(Path(f)), headonly=True,
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
        for tr in _read(path, fmt=source.format_of(f) or detect_format(path), max_rows=config.records.max_samples):
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
    traces = [tr for f in source.files for tr in _read(Path(f), fmt=source.format_of(f), headonly=True)]
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
