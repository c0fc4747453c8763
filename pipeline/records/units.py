"""Conversion of every trace to acceleration in m s-2, never by guessing.

Where the units come from, in order:

1. the file itself: our plug-ins put the stated units in ``stats.physical_units``
   (AT2 ``IN UNITS OF G``, COSMOS ``units=cm/sec2``, DMG ``in units of g``);
2. K-NET/KiK-net: obspy's ``stats.calib`` (the file's ``Scale Factor`` in gal
   per count, times 0.01), applied to the raw counts;
3. counts with a StationXML response (a ``*.xml`` file in the records
   directory, or ``--stationxml``): the instrument sensitivity is removed for
   accelerometers (flat response), the full response for other sensors;
4. a declaration in ``units.toml`` in the records directory (or the
   configuration's ``records.declared_units``) for formats that do not say,
   such as SAC files (whose ``idep`` header producers often set to ``IACC``,
   nominally nm s-2, for data written in g) and near-fault ASCII files.

Anything else is a :class:`~pipeline.errors.UnitsError` for that file.
"""

from __future__ import annotations

import fnmatch
import os
import re
from pathlib import Path

import numpy as np

from ..constants import CM_TO_M
from ..errors import UndeclaredUnitsError, UnitsError
from .common import COMMON

#: Factors to m s-2 for units that do not depend on the configured g.
FACTORS_TO_MS2 = {"m/s**2": 1.0, "cm/s**2": CM_TO_M, "gal": CM_TO_M, "mm/s**2": 1e-3}
#: Units measured in multiples of g.
G_MULTIPLES = {"g": 1.0, "mg": 1e-3}
#: Spellings accepted in declarations, mapped to the canonical names above.
ALIASES = {"m/s^2": "m/s**2", "m/s2": "m/s**2", "m s-2": "m/s**2", "cm/s^2": "cm/s**2",
           "cm/s2": "cm/s**2", "cm s-2": "cm/s**2", "gal": "gal", "g": "g", "mg": "mg",
           "mm/s^2": "mm/s**2", "mm s-2": "mm/s**2"}
#: Units tried, in this order, when a file's units must be declared: the first in which its peak is a plausible
#: ground acceleration is suggested (strong-motion files in g and in cm s-2 are the common cases).
SUGGESTION_ORDER = ("g", "cm/s**2", "m/s**2")
#: Peak ground accelerations a record can plausibly have [g]: from a weak distant record to the largest recorded.
PLAUSIBLE_PGA_G = (1e-4, 5.0)
#: The table of ``units.toml`` that holds the declarations.
UNITS_TABLE = "[files]"


def canonical_units(text: str, *, where: str) -> str:
    """Return the canonical spelling of a declared unit, or raise with the valid list."""
    key = text.strip()
    key = ALIASES.get(key.lower(), ALIASES.get(key, key))
    if key in FACTORS_TO_MS2 or key in G_MULTIPLES:
        return key
    valid = sorted(set(FACTORS_TO_MS2) | set(G_MULTIPLES))
    raise UnitsError(f"{where}: unknown acceleration unit {text!r}; use one of {valid}")


def factor_to_ms2(units: str, *, g_ms2: float) -> float:
    """Return the factor that converts ``units`` to m s-2.

    Parameters
    ----------
    units : str
        Canonical unit name (see :data:`FACTORS_TO_MS2`, :data:`G_MULTIPLES`).
    g_ms2 : float
        The value of g used for units of g [m s-2].
    """
    if units in G_MULTIPLES:
        return G_MULTIPLES[units] * g_ms2
    return FACTORS_TO_MS2[units]


def declared_units_for(path: Path, root: Path, declarations: dict[str, str]) -> str | None:
    """Return the unit declared for ``path`` by a glob in ``declarations`` (relative or basename)."""
    try:
        rel = path.relative_to(root).as_posix()
    except ValueError:
        rel = path.name
    for pattern, unit in declarations.items():
        if matches(pattern, rel):
            return unit
    return None


def advice(root: Path, errors: list[UndeclaredUnitsError]) -> str:
    """The lines to paste into ``root/units.toml`` for files whose units must be declared (one record's files:
    a glob is checked against the files of their folders).

    Parameters
    ----------
    root : Path
        The records directory.
    errors : list of UndeclaredUnitsError
        One per file that needs a declaration.
    """
    def rel(p: str) -> str:
        try:
            return Path(p).resolve().relative_to(Path(root).resolve()).as_posix()
        except ValueError:
            return Path(p).name

    failing = {rel(e.path): e.suggested for e in errors if e.suggested}
    unknown = [e for e in errors if not e.suggested]
    text = ""
    if failing:
        folders = {Path(root) / f.rpartition("/")[0] for f in failing}
        every_file = [rel(str(p)) for d in folders if d.is_dir() for p in d.iterdir() if p.is_file()]
        readings = {rel(e.path): e.readings for e in errors if e.suggested}
        lines = suggest_declarations(failing, every_file)
        text += (f"\n  paste these lines into {Path(root) / 'units.toml'} (the {UNITS_TABLE} line once; the unit is "
                 "the one that makes the peak a plausible ground acceleration, so check it):\n"
                 + UNITS_TABLE + "\n" + "\n".join(lines)
                 + "".join(f"\n# {r}: peak reads as {readings[r]}" for r in sorted(readings)))
    for e in unknown:
        text += (f"\n  {rel(e.path)}: no unit makes its peak a plausible ground acceleration (raw counts?): give "
                 "the StationXML response instead")
    return text


def combined_declarations(messages: list[str], every_file: list[str]) -> list[str]:
    """The ``units.toml`` lines for every file that the failure ``messages`` of a run ask to declare, merged
    into as few globs as match exactly those files (``[]`` when none asks).

    Parameters
    ----------
    messages : list of str
        The failed records' statuses (the lines :func:`advice` wrote into them).
    every_file : list of str
        Relative paths of the files of the records directory.
    """
    asked = [d for text in messages for d in parse_declarations(text)]
    if not asked:
        return []
    failing = {rel: unit for pattern, unit in asked for rel in every_file if matches(pattern, rel)}
    return suggest_declarations(failing, every_file)


def to_ms2(trace, *, path: Path, declared: str | None, g_ms2: float, inventory=None) -> str:
    """Convert ``trace`` in place to m s-2 and return a note saying how.

    Raises
    ------
    UnitsError
        If the units cannot be determined or the response is missing.
    """
    stats = trace.stats
    fmt = getattr(stats, "_format", "?")
    info = stats[COMMON]
    stated = stats.get("physical_units")
    if stated == "counts":
        stated = None
    if stated is not None:
        if declared is not None and declared != stated:
            raise UnitsError(
                f"{path}: the file states units {stated!r} but units.toml declares {declared!r}; "
                "remove the declaration for this file"
            )
        factor = factor_to_ms2(stated, g_ms2=g_ms2)
        trace.data = np.asarray(trace.data, dtype=float) * factor
        return f"units: {stated} (stated in file) x {factor:g} -> m/s**2"
    if declared is not None:
        factor = factor_to_ms2(declared, g_ms2=g_ms2)
        trace.data = np.asarray(trace.data, dtype=float) * factor
        return f"units: {declared} (declared in units.toml) x {factor:g} -> m/s**2"
    if info.calib_to_ms2:
        if not stats.calib or stats.calib == 1.0:
            raise UnitsError(f"{path}: K-NET file without a Scale Factor; cannot convert counts")
        trace.data = np.asarray(trace.data, dtype=float) * stats.calib
        return f"units: counts x calib {stats.calib:.6e} (Scale Factor, gal->m/s**2) -> m/s**2"
    if inventory is not None and describes(inventory, trace):
        return _remove_response(trace, path=path, inventory=inventory)
    if info.units_unstated:
        why = info.units_unstated
    else:
        why = (f"the units of this {fmt} file cannot be determined (raw counts with no StationXML response, or "
               "units not stated); put the StationXML file in the records directory or pass --stationxml, or")
    readings = plausible_units(trace.data, g_ms2=g_ms2)
    suggested = readings[0][0] if readings else ""
    reading_text = "; ".join(f"{pga_g:.3g} g if in {unit}" for unit, pga_g in readings)
    raise UndeclaredUnitsError(f"{path}: {why} declare them in units.toml", path=str(path), suggested=suggested,
                               readings=reading_text)


def plausible_units(data, *, g_ms2: float) -> list[tuple[str, float]]:
    """The units in which a file's peak is a plausible ground acceleration, most likely first.

    Parameters
    ----------
    data : array_like
        The file's samples as stored (the mean is removed first: raw files carry offsets).
    g_ms2 : float
        The value of g [m s-2].

    Returns
    -------
    list of (str, float)
        ``(unit, peak ground acceleration [g])`` for each unit of :data:`SUGGESTION_ORDER` that puts the peak
        within :data:`PLAUSIBLE_PGA_G`; empty when none does (counts, for example).
    """
    x = np.asarray(data, dtype=float)
    x = x[np.isfinite(x)]
    if x.size == 0:
        return []
    peak = float(np.max(np.abs(x - x.mean())))
    out = []
    for unit in SUGGESTION_ORDER:
        pga_g = peak * factor_to_ms2(unit, g_ms2=g_ms2) / g_ms2
        if PLAUSIBLE_PGA_G[0] <= pga_g <= PLAUSIBLE_PGA_G[1]:
            out.append((unit, pga_g))
    return out


def common_glob(names: list[str]) -> str:
    """One glob for several file names: their common prefix, ``*`` (or ``?`` for one differing character),
    their common suffix. A single name is returned as it is."""
    names = sorted(set(names))
    if len(names) == 1:
        return names[0]
    prefix = os.path.commonprefix(names)
    suffix = os.path.commonprefix([n[len(prefix):][::-1] for n in names])[::-1]
    middles = {n[len(prefix):len(n) - len(suffix)] for n in names}
    return prefix + ("?" if all(len(m) == 1 for m in middles) else "*") + suffix


def declaration_line(pattern: str, unit: str) -> str:
    """One ``units.toml`` line under :data:`UNITS_TABLE`."""
    return f'"{pattern}" = "{unit}"'


_DECLARATION = re.compile(r'^"(?P<pattern>[^"]+)" = "(?P<unit>[^"]+)"')


def parse_declarations(text: str) -> list[tuple[str, str]]:
    """The ``(pattern, unit)`` declarations suggested in an error message (the lines after :data:`UNITS_TABLE`)."""
    out, inside = [], False
    for line in text.splitlines():
        stripped = line.strip()
        if stripped == UNITS_TABLE:
            inside = True
        elif inside and (m := _DECLARATION.match(stripped)):
            out.append((m["pattern"], m["unit"]))
    return out


def matches(pattern: str, rel: str) -> bool:
    """True when a ``units.toml`` pattern applies to the file at ``rel`` (relative path, or its name)."""
    return fnmatch.fnmatch(rel, pattern) or fnmatch.fnmatch(rel.rsplit("/", 1)[-1], pattern)


def suggest_declarations(failing: dict[str, str], every_file: list[str]) -> list[str]:
    """``units.toml`` patterns for files that need a declaration, as few as possible.

    Parameters
    ----------
    failing : dict
        Relative path -> suggested unit, of the files that need one.
    every_file : list of str
        Relative paths of the files a glob could match: a glob is used only when it matches exactly the
        failing files of its folder and unit (a declaration on a file that states its own units is an error),
        else the files are listed one by one.

    Returns
    -------
    list of str
        ``"pattern" = "unit"`` lines.
    """
    groups: dict[tuple[str, str, str], list[str]] = {}
    for rel, unit in sorted(failing.items()):
        folder, _, name = rel.rpartition("/")
        groups.setdefault((folder, unit, Path(name).suffix), []).append(rel)
    lines = []
    for (folder, unit, _), rels in groups.items():
        names = [r.rpartition("/")[2] for r in rels]
        pattern = (folder + "/" if folder else "") + common_glob(names)
        covered = {r for r in every_file if matches(pattern, r)}
        if covered == set(rels):
            lines.append(declaration_line(pattern, unit))
        else:
            lines += [declaration_line(r, unit) for r in rels]
    return lines


def describes(inventory, trace) -> bool:
    """True when the StationXML ``inventory`` has the trace's channel (a StationXML applies to nothing else)."""
    s = trace.stats
    try:
        found = inventory.select(network=s.network or None, station=s.station or None,
                                 location=s.location if s.location else None, channel=s.channel or None)
    except Exception:   # a malformed id: the inventory cannot be about this trace
        return False
    return bool(s.network and s.station and s.channel) and len(found.get_contents()["channels"]) > 0


def _remove_response(trace, *, path: Path, inventory) -> str:
    try:
        response = inventory.get_response(trace.id, trace.stats.starttime)
    except Exception as exc:
        raise UnitsError(
            f"{path}: counts, and the StationXML has no response for {trace.id} at "
            f"{trace.stats.starttime}; add that channel to the inventory ({exc})"
        ) from exc
    input_units = (response.instrument_sensitivity.input_units or "").upper()
    trace.data = np.asarray(trace.data, dtype=float)
    if input_units in ("M/S**2", "M/S2", "M/S/S"):
        sensitivity = response.instrument_sensitivity.value
        trace.remove_sensitivity(inventory)
        return f"units: counts / sensitivity {sensitivity:.6g} counts per m/s**2 (StationXML) -> m/s**2"
    trace.remove_response(inventory, output="ACC", pre_filt=None, water_level=60)
    return f"units: counts, full response removed to ACC (StationXML, input units {input_units})"
