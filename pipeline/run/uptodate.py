"""Nothing new since the last run: answer from a manifest, without importing the science stack.

A scheduled screening usually finds nothing new. The full re-run path (scan, plan, reuse
every record from the scene cache, write, report) is correct but pays for the imports and
for reading and writing the results. This module decides up front, from content digests
alone, whether the outputs already answer the command:

* the **inputs**: the SHA-256 of every file under ``--records`` (all files, hidden ones
  and side files included, so any change at all counts), of the inventory CSV and of the
  StationXML given with ``--stationxml``;
* the **settings**: the effective configuration's digest (after ``--fidelity``,
  ``--samples``, ``--seed``);
* the **code**: the SHA-256 of every file of the installed ``pipeline`` package and the
  versions of the libraries the results depend on;
* the **outputs**: the SHA-256 of ``screening.nc``, ``pulses.nc``, ``histories.nc``,
  ``report.html`` and ``assets.csv`` as the last run wrote them.

Only when all of these equal the manifest the last complete run wrote
(``OUT/.rockscreen/manifest.json``) is the run skipped, with a line that says so. Any
difference, a missing or damaged manifest, a held lock or ``--force`` takes the full path.
The executor (``-n``, ``--scheduler``) and the output options (``-q``, ``-v``) are not part
of the key: results do not depend on them (tested).
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from importlib import metadata
from pathlib import Path

from ..constants import STATE_DIR

#: The files a complete run writes into the output directory, checked by content.
OUTPUTS = ("screening.nc", "pulses.nc", "histories.nc", "report.html", "assets.csv")
#: Manifest file, inside the output's state directory.
MANIFEST = "manifest.json"
#: Libraries whose versions are part of the key and of the results' provenance (``package_versions``).
LIBRARIES = ("obspy", "numpy", "scipy", "PyWavelets", "xarray", "netCDF4", "numba", "matplotlib", "jinja2")
MANIFEST_FORMAT = 1
_CHUNK = 1 << 20


def file_sha256(path: str | Path) -> str:
    """SHA-256 of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        while chunk := fh.read(_CHUNK):
            h.update(chunk)
    return h.hexdigest()


def tree_sha256(root: str | Path, *, exclude: Path | None = None) -> tuple[str, int]:
    """One SHA-256 over every file under ``root`` (relative path and content, sorted), and the count.

    ``exclude``: a directory under ``root`` left out (an output directory inside the records).
    """
    root = Path(root)
    h = hashlib.sha256()
    n = 0
    ex = str(exclude.resolve()) if exclude is not None else None
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames.sort()
        if ex is not None:
            dirnames[:] = [d for d in dirnames if str((Path(dirpath) / d).resolve()) != ex]
        for name in sorted(filenames):
            p = Path(dirpath) / name
            if not p.is_file():
                continue
            try:
                digest = file_sha256(p)
            except OSError as exc:      # unreadable: the full path reports it; here it is part of the key
                digest = f"unreadable ({exc.errno})"
            h.update(os.fsencode(p.relative_to(root)) + b"\0" + digest.encode() + b"\n")
            n += 1
    return h.hexdigest(), n


def code_fingerprint() -> str:
    """SHA-256 of the ``pipeline`` package's files (sources and templates) and of the library versions."""
    package = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for p in sorted(package.rglob("*")):
        if p.is_file() and "__pycache__" not in p.parts and p.suffix not in (".pyc", ".nbi", ".nbc"):
            h.update(str(p.relative_to(package)).encode() + b"\0" + file_sha256(p).encode() + b"\n")
    for name in LIBRARIES:
        try:
            h.update(f"{name}={metadata.version(name)}\n".encode())
        except metadata.PackageNotFoundError:
            h.update(f"{name}=absent\n".encode())
    return h.hexdigest()


def fingerprint(*, records_dir: Path, blocks_csv: Path, config_sha256: str, stationxml: Path | None,
                out_dir: Path, buildings_csv: Path | None = None) -> dict:
    """Digests of everything the outputs depend on (see the module docstring)."""
    records, n_files = tree_sha256(records_dir, exclude=out_dir)
    return {"format": MANIFEST_FORMAT, "records_dir": str(Path(records_dir).resolve()),
            "records_sha256": records, "records_files": n_files,
            "inventory_sha256": file_sha256(blocks_csv), "config_sha256": config_sha256,
            "stationxml_sha256": file_sha256(stationxml) if stationxml is not None else "",
            "code_sha256": code_fingerprint(),
            **({"buildings_sha256": file_sha256(buildings_csv)} if buildings_csv is not None else {})}


def _manifest_path(out_dir: Path) -> Path:
    return Path(out_dir) / STATE_DIR / MANIFEST


def output_digests(out_dir: Path) -> dict[str, str] | None:
    """SHA-256 of each of :data:`OUTPUTS` in ``out_dir``, or None when one is missing."""
    out = {}
    for name in OUTPUTS:
        p = Path(out_dir) / name
        if not p.is_file():
            return None
        out[name] = file_sha256(p)
    return out


def write_manifest(out_dir: Path, key: dict, *, counts: dict, margins: dict,
                   failures: list[tuple[str, str]] | None = None) -> Path | None:
    """Record a complete run: its input key, its outputs' digests, its closing counts and its failed
    records (id, status), so that a run that skips everything can still name them.

    Called by the run that holds the output lock, after the report. Returns the manifest's path
    (None when an output is missing: no manifest then, and the next run takes the full path).
    """
    from ..store import write_text_atomic

    digests = output_digests(out_dir)
    path = _manifest_path(out_dir)
    if digests is None:
        path.unlink(missing_ok=True)
        return None
    doc = {"key": key, "outputs": digests, "finished_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
           "counts": counts, "margins": margins, "failures": [list(f) for f in failures or []]}
    return write_text_atomic(path, json.dumps(doc, default=str, indent=1))


def check(*, records_dir: Path, blocks_csv: Path, config, stationxml: Path | None, out_dir: Path,
          buildings_csv: Path | None = None, force: bool = False) -> tuple[dict, dict | None]:
    """Whether a run has anything to do: its key (:func:`fingerprint`), and the last run's manifest when nothing
    it depends on changed and its outputs are intact (None: run; always None with ``force``)."""
    key = fingerprint(records_dir=records_dir, blocks_csv=blocks_csv, config_sha256=config.digest(),
                      stationxml=stationxml, out_dir=out_dir, buildings_csv=buildings_csv)
    return key, None if force else up_to_date(out_dir, key)


def up_to_date(out_dir: Path, key: dict) -> dict | None:
    """The last run's manifest when its key equals ``key`` and every output is as it wrote it; else None.

    None also when another run holds the output's lock (the full path then reports it), and when the last run had
    records that failed for a transient cause (a crash, a lost worker): the full path retries them.
    """
    path = _manifest_path(out_dir)
    if (Path(out_dir) / STATE_DIR / "lock").exists():
        return None
    try:
        doc = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(doc, dict) or doc.get("key") != key:
        return None
    if output_digests(out_dir) != doc.get("outputs"):
        return None
    if (doc.get("counts") or {}).get("records_failed_transient"):
        return None
    return doc


def invalidate(out_dir: Path) -> None:
    """Remove the manifest (a run is starting that will change the outputs)."""
    _manifest_path(out_dir).unlink(missing_ok=True)
