"""From a directory of files to the station recordings it holds, reading headers only: the first of the two
passes through a records directory (:mod:`.loader` reads one recording's data at a time, so that records stream
through memory).

Every regular file is offered to the readers by content; the files of one station recording are grouped (SEED id
and start time for obspy's formats, the header's station line for AT2); recordings whose files hold the same bytes
are screened once. A file or group that fails becomes a :class:`Failure` carrying the reason; the other records
are unaffected.
"""

from __future__ import annotations

import hashlib
import os
import re
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import RecordFormatError, UnitsError
from .common import COMMON
from .detect import detect_format, looks_like_a_record
from .settings import ReaderSettings
from .streams import read_stream
from .units import UNITS_TABLE, combined_declarations

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
            st = read_stream(path, fmt=fmt, headonly=True, max_rows=config.records.max_samples)
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
