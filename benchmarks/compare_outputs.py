"""Compare two output directories of rockscreen, file by file: the identity check of a redesign step.

Every netCDF file is compared variable by variable and group by group (dimensions, dtype, values with NaN equal
to NaN, every attribute), the global attributes too except the timestamps (:data:`TIMESTAMP_ATTRS`); every CSV
and XML file byte for byte. HTML pages are listed, not compared (they carry the run's time). The run's own state
(the caches and the lock) is not compared.

Usage::

    python benchmarks/compare_outputs.py BEFORE_DIR AFTER_DIR [--ignore command --ignore fragility]

Exit 0 when everything compared is identical, 1 otherwise (each difference printed).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import sys
from pathlib import Path

import netCDF4
import numpy as np

#: Global attributes and variables that hold the time of the run.
TIMESTAMP_ATTRS = ("screened_utc", "created_utc", "date_created", "history")
#: Folders of the run's own state, not outputs.
STATE_PARTS = (".rockscreen", "staging")
BYTE_SUFFIXES = (".csv", ".xml")


def _equal(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if a.dtype.kind == "f":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a, b))


def _attrs(obj) -> dict:
    return {k: obj.getncattr(k) for k in obj.ncattrs()}


def compare_group(g1, g2, where: str, ignore: tuple = ()) -> list[str]:
    """The differences between two netCDF groups (recursively), the names in ``ignore`` and the timestamps left
    out."""
    out = []
    skip = (*TIMESTAMP_ATTRS, *ignore)
    a1 = {k: v for k, v in _attrs(g1).items() if k not in skip}
    a2 = {k: v for k, v in _attrs(g2).items() if k not in skip}
    for k in sorted(set(a1) | set(a2)):
        if k not in a1 or k not in a2 or not _equal(a1[k], a2[k]):
            out.append(f"{where}: attribute {k}: {a1.get(k)!r} != {a2.get(k)!r}")
    if {k: len(d) for k, d in g1.dimensions.items()} != {k: len(d) for k, d in g2.dimensions.items()}:
        out.append(f"{where}: dimensions differ")
    for name in sorted((set(g1.variables) | set(g2.variables)) - set(skip)):
        if name not in g1.variables or name not in g2.variables:
            out.append(f"{where}: variable {name} only in one")
            continue
        v1, v2 = g1.variables[name], g2.variables[name]
        v1.set_auto_mask(False)
        v2.set_auto_mask(False)
        if v1.dimensions != v2.dimensions or not _equal(v1[...], v2[...]):
            out.append(f"{where}: variable {name}: values or dimensions differ")
        if _attrs(v1).keys() != _attrs(v2).keys() or not all(_equal(_attrs(v1)[k], _attrs(v2)[k])
                                                            for k in _attrs(v1)):
            out.append(f"{where}: variable {name}: attributes differ")
    for name in sorted(set(g1.groups) | set(g2.groups)):
        if name not in g1.groups or name not in g2.groups:
            out.append(f"{where}: group {name} only in one")
        else:
            out += compare_group(g1.groups[name], g2.groups[name], f"{where}/{name}", ignore)
    return out


def compare_dirs(before: Path, after: Path, ignore: tuple = ()) -> tuple[list[str], int]:
    """The differences between two output directories, and the number of files compared."""
    def files(root: Path) -> set[Path]:
        return {p.relative_to(root) for p in root.rglob("*")
                if p.is_file() and not any(part in STATE_PARTS for part in p.relative_to(root).parts)}
    f1, f2 = files(before), files(after)
    out = [f"{p}: only in {before if p in f1 else after}" for p in sorted(f1 ^ f2)]
    n = 0
    for rel in sorted(f1 & f2):
        if rel.suffix == ".nc":
            with netCDF4.Dataset(before / rel) as d1, netCDF4.Dataset(after / rel) as d2:
                out += compare_group(d1, d2, str(rel), ignore)
            n += 1
        elif rel.suffix in BYTE_SUFFIXES or rel.name.endswith(".xml.gz"):
            if (before / rel).read_bytes() != (after / rel).read_bytes():
                out.append(f"{rel}: bytes differ")
            n += 1
    return out, n


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", type=Path)
    ap.add_argument("after", type=Path)
    ap.add_argument("--ignore", action="append", default=[], metavar="NAME",
                    help="an attribute or variable left out (one that holds the run's paths: command, fragility)")
    args = ap.parse_args(argv)
    diffs, n = compare_dirs(args.before, args.after, tuple(args.ignore))
    for d in diffs:
        print(d)
    print(f"{n} files compared: {'identical' if not diffs else f'{len(diffs)} difference(s)'}")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
