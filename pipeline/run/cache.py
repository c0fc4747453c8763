"""The scene cache: one file per screened record, so re-runs redo only what changed.

Each record that screens successfully is saved, as soon as its task
returns, to ``OUT/.rockscreen/cache/<key>.npz``, where the key hashes the
record's id and content (its files' names and bytes) with the *run key* (the
effective configuration, the package version, the declared units and the
StationXML inventory). An entry holds the record's own values and its
results for a set of blocks, each tagged with the block's inventory digest
(:meth:`pipeline.blocks.Inventory.digests`).

A later run into the same output looks each record up by its key and
computes only the blocks that are missing or whose inventory row changed.
A run that is killed or interrupted keeps every entry it wrote, so the
next run picks up where it stopped. Entries are plain ``.npz`` files read
with ``allow_pickle=False``: nothing in the output directory can execute
code on load.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import tempfile
import zipfile
from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import OutputError
from ..schema import FLOOR_PULSE_SERIES, PULSE_SERIES, floor_key
from ..store import STATE_DIR, check_output_tree, output_names, replace_atomically
from .screening import RecordResult

log = logging.getLogger(__name__)

#: Bump when the entry layout changes: older entries are then ignored.
ENTRY_FORMAT = 9


def run_key(config_dict: dict, *, declared_units: dict, station_inventory_sha256: str = "",
            buildings: dict | None = None) -> str:
    """SHA-256 over everything, besides a record and a block, that changes results.

    Parameters
    ----------
    config_dict : dict
        The effective configuration (:meth:`pipeline.config.Config.to_dict`).
    declared_units : dict
        File pattern -> declared units (``units.toml`` and the configuration).
    station_inventory_sha256 : str
        Digest of the StationXML files used for records in counts.
    buildings : dict, optional
        The buildings blocks stand in (``--buildings``); none leaves the key as it was without them.
    """
    content = {"config": config_dict, "version": __version__, "entry_format": ENTRY_FORMAT,
               "declared_units": declared_units, "stationxml": station_inventory_sha256}
    if buildings:
        content["buildings"] = {k: list(v) for k, v in sorted(buildings.items())}
    payload = json.dumps(content, sort_keys=True, default=str)
    return hashlib.sha256(payload.encode()).hexdigest()


def record_key(record_id: str, content_sha256: str, run: str) -> str:
    """Cache key of one record (its id and content) under one run key.

    The id is part of the key: two copies of the same files in two
    directories are two records and must not share an entry.
    """
    return hashlib.sha256(f"{record_id}\n{content_sha256}\n{run}".encode()).hexdigest()[:40]


def scene_cache_dir(out_dir: str | Path) -> Path:
    """Where the scene cache of an output directory lives."""
    return Path(out_dir) / STATE_DIR / "cache"


class _NpzStore:
    """A directory of ``.npz`` entries written atomically, with pruning of unused entries."""

    what = "cache"

    def __init__(self, directory: Path):
        self.dir = directory
        self.used: set[str] = set()
        self.write_errors = 0

    def _read(self, path: Path, keys: tuple[str, ...] | None = None) -> dict | None:
        """The entry's arrays (only ``keys``, those of them it has, when given: an npz member is read when
        asked for), or None when it is missing, unreadable or of another format."""
        self.used.add(path.name)
        if not path.is_file():
            return None
        try:
            with np.load(path, allow_pickle=False) as z:
                if int(z["entry_format"]) != ENTRY_FORMAT:
                    return None
                return {k: z[k] for k in (z.files if keys is None else [k for k in keys if k in z.files])}
        except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:
            log.warning("%s: unreadable %s entry (%s); it is computed again", path, self.what, exc)
            return None

    def _write(self, path: Path, arrays: dict) -> bool:
        """Write atomically; True when written. A failure is logged once, never raised (the run goes on
        in memory)."""
        self.used.add(path.name)

        def write(tmp: str) -> None:
            with open(tmp, "wb") as fh:
                np.savez(fh, entry_format=np.array(ENTRY_FORMAT), **arrays)

        try:
            replace_atomically(path, write)
        except OutputError as exc:
            self.write_errors += 1
            if self.write_errors == 1:
                cause = exc.__cause__
                log.warning("%s: cannot save the %s (%s); results are kept in memory until the final write",
                            self.dir, self.what, getattr(cause, "strerror", None) or cause or exc)
            return False
        return True

    def prune(self) -> int:
        """Delete entries not used by this run (other configurations, changed records); returns the count."""
        if not self.dir.is_dir():
            return 0
        n = 0
        for p in self.dir.iterdir():
            if p.name not in self.used:
                try:
                    p.unlink()
                    n += 1
                except OSError:
                    pass
        return n


class RecordStore(_NpzStore):
    """One ``.npz`` entry per record, keyed by the record's id and content under a run key."""

    def __init__(self, directory: Path, run: str):
        super().__init__(directory)
        self.run = run

    def path(self, record_id: str, content_sha256: str) -> Path:
        return self.dir / f"{record_key(record_id, content_sha256, self.run)}.npz"


class SceneCache(RecordStore):
    """Per-record result files under ``OUT/.rockscreen/cache``.

    Parameters
    ----------
    out_dir : path
        The run's output directory.
    run : str
        The run key (:func:`run_key`).
    """

    what = "scene cache"

    def __init__(self, out_dir: str | Path, run: str):
        super().__init__(scene_cache_dir(out_dir), run)

    def load(self, record_id: str, content_sha256: str) -> RecordResult | None:
        """The cached result of a record, or None (missing, unreadable, or not of the schema's layout)."""
        z = self._read(self.path(record_id, content_sha256))
        if z is None:
            return None
        if "failed_status" in z:
            return RecordResult(record_id, str(z["failed_status"]), {"files": str(z["files"])}, deterministic=True)
        try:
            return RecordResult.from_arrays(z)
        except (KeyError, ValueError) as exc:
            log.warning("%s: %s entry for record %s is not of this version's layout (%s); screening it again",
                        self.dir, self.what, record_id, exc)
            return None

    def save(self, result: RecordResult) -> bool:
        """Write one record's result atomically; True when written (a failure is logged, never raised)."""
        return self._write(self.path(result.record_id, result.values["content_sha256"]), result.to_arrays())

    def series(self, record_id: str, content_sha256: str, floors: tuple = ()) -> dict | None:
        """The pulse series of a saved record (``velocity``, ``pulse`` [m s-1]) and, under ``"floors"``, those
        of the ``floors`` asked for (``(building, height_m)`` -> ``{"velocity", "pulse"}``); None when the
        entry or any of them is missing."""
        names = tuple(PULSE_SERIES)
        keys = {(b, z, n): floor_key(b, z, n) for b, z in floors for n in FLOOR_PULSE_SERIES}
        got = self._read(self.path(record_id, content_sha256), (*names, *keys.values()))
        if got is None or len(got) < len(names) + len(keys):
            return None
        return {**{n: got[n] for n in names},
                "floors": {(b, z): {n: got[keys[b, z, n]] for n in FLOOR_PULSE_SERIES} for b, z in floors}}

    def save_failure(self, result: RecordResult, content_sha256: str) -> None:
        """Keep a deterministic failure (:attr:`RecordResult.deterministic`) of these files under this run key:
        the next run reports it again without reading the record."""
        self._write(self.path(result.record_id, content_sha256),
                    {"failed_status": np.array(result.status), "files": np.array(result.values.get("files", ""))})

    def margins(self) -> "MarginCache":
        """The margin cache of the same output and run key."""
        return MarginCache(self.dir.parent / "margins", self.run)


class MarginCache(_NpzStore):
    """Margin scans (``pipeline.run.margins``) per (governing record, block), under ``OUT/.rockscreen/margins``.

    The key hashes the record's cache key (id, content, run key) with the block's inventory
    digest: everything a margin and its history depend on.
    """

    what = "margin cache"

    def __init__(self, directory: Path, run: str):
        super().__init__(directory)
        self.run = run

    def path(self, record_id: str, content_sha256: str, block_sha256: str) -> Path:
        key = hashlib.sha256(f"{record_key(record_id, content_sha256, self.run)}\n{block_sha256}".encode())
        return self.dir / f"{key.hexdigest()[:40]}.npz"

    def get(self, record_id: str, content_sha256: str, block_sha256: str):
        """(scale, runs, history or None, dt, sampled margins) or None."""
        z = self._read(self.path(record_id, content_sha256, block_sha256))
        if z is None:
            return None
        history = z["history"] if z["history"].size else None
        return float(z["scale"]), int(z["runs"]), history, float(z["dt"]), np.asarray(z["sampled"], dtype=float)

    def put(self, record_id: str, content_sha256: str, block_sha256: str, value: tuple) -> None:
        scale, runs, history, dt, sampled = value
        self._write(self.path(record_id, content_sha256, block_sha256),
                    {"scale": np.array(scale), "runs": np.array(runs), "dt": np.array(dt),
                     "history": np.zeros(0) if history is None else np.asarray(history),
                     "sampled": np.asarray(sampled, dtype=float)})


def merge(old, new):
    """A record's cached result completed by a task that screened only some blocks.

    The new task's record values replace the old ones (they are the same
    computation on the same content); block columns are the union, the new
    ones winning.
    """
    if old is None:
        return new
    fresh = set(new.block_ids)
    keep_old = [k for k, b in enumerate(old.block_ids) if b not in fresh]
    ids = list(new.block_ids) + [old.block_ids[k] for k in keep_old]
    digests = list(new.block_digests) + [old.block_digests[k] for k in keep_old]
    blocks = {name: np.concatenate([np.asarray(new.blocks[name], dtype=float),
                                    np.asarray(old.blocks[name], dtype=float)[keep_old]])
              for name in new.blocks}
    new.block_ids, new.block_digests, new.blocks = tuple(ids), tuple(digests), blocks
    new.floor_series = {**old.floor_series, **new.floor_series}
    return new


def ensure_writable(out_dir: str | Path, *, replaces=()) -> Path:
    """Create the output directory and check that files can be created in it, after :func:`check_output_tree`
    (``replaces``: the names the command writes, which must not be a user's own files in a fresh folder).

    Raises
    ------
    OutputError
        Naming the directory and the reason, before any record is screened.
    """
    out = Path(out_dir)
    check_output_tree(out, output_names=output_names(out), replaces=replaces)  # planted links; a user's files
    try:
        (out / STATE_DIR).mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".probe.", dir=out)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputError(f"{out}: the output directory is not writable ({exc.strerror or exc}); "
                          "choose another --out or fix its permissions. Nothing was screened.") from exc
    return out


def writable_target(out_dir: str | Path) -> None:
    """A quick check, before any work and without creating anything, that ``out_dir`` (or its nearest existing
    parent, where it will be created) can be written (:func:`ensure_writable` checks again by writing).

    Raises
    ------
    OutputError
        Naming the directory that cannot be written, and the fix.
    """
    here = Path(out_dir).absolute()
    while not here.exists() and here != here.parent:
        here = here.parent
    if not here.is_dir() or not os.access(here, os.W_OK | os.X_OK):
        raise OutputError(f"{out_dir}: the output directory is not writable ({here} is "
                          f"{'not a directory' if not here.is_dir() else 'read-only'}); choose another --out or "
                          "fix its permissions. Nothing was screened.")
