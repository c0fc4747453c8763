"""The files beside the records that say what they hold: ``units.toml`` (the units of files whose headers do not
state them) and StationXML (the stations' channels, azimuths and responses)."""

from __future__ import annotations

import sys
from pathlib import Path

import obspy

from ..errors import UnitsError
from .settings import ReaderSettings
from .streams import literal_path
from .units import canonical_units


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
            inv = obspy.read_inventory(literal_path(p))
        except Exception as exc:
            if extra is not None and Path(extra) == p:
                raise UnitsError(f"{p}: not a readable StationXML inventory ({exc})") from exc
            continue
        inventory = inv if inventory is None else inventory + inv
    return inventory
