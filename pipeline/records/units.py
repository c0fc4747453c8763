"""Conversion of every trace to acceleration in m s-2, never by guessing.

Where the units come from, in order:

1. the file itself: our plug-ins put the stated units in ``stats.physical_units``
   (AT2 ``IN UNITS OF G``, COSMOS ``units=cm/sec2``, DMG ``in units of g``);
2. K-NET/KiK-net: obspy's ``stats.calib`` (the file's ``Scale Factor`` in gal
   per count, times 0.01), applied to the raw counts;
3. counts with a StationXML response (a ``*.xml`` file in the records
   directory, or ``--inventory``): the instrument sensitivity is removed for
   accelerometers (flat response), the full response for other sensors;
4. a declaration in ``units.toml`` in the records directory (or the
   configuration's ``records.declared_units``) for formats that do not say,
   such as SAC files (whose ``idep`` header producers often set to ``IACC``,
   nominally nm s-2, for data written in g) and near-fault ASCII files.

Anything else is a :class:`~pipeline.errors.UnitsError` for that file.
"""

from __future__ import annotations

import fnmatch
from pathlib import Path

import numpy as np

from ..constants import CM_TO_M
from ..errors import UnitsError

#: Factors to m s-2 for units that do not depend on the configured g.
FACTORS_TO_MS2 = {"m/s**2": 1.0, "cm/s**2": CM_TO_M, "gal": CM_TO_M, "mm/s**2": 1e-3}
#: Units measured in multiples of g.
G_MULTIPLES = {"g": 1.0, "mg": 1e-3}
#: Spellings accepted in declarations, mapped to the canonical names above.
ALIASES = {"m/s^2": "m/s**2", "m/s2": "m/s**2", "m s-2": "m/s**2", "cm/s^2": "cm/s**2",
           "cm/s2": "cm/s**2", "cm s-2": "cm/s**2", "gal": "gal", "g": "g", "mg": "mg",
           "mm/s^2": "mm/s**2", "mm s-2": "mm/s**2"}
SAC_IDEP = {5: "IUNKN (unknown)", 6: "IDISP (nm)", 7: "IVEL (nm/s)", 8: "IACC (nm/s**2)", 50: "IVOLTS"}


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
        if fnmatch.fnmatch(rel, pattern) or fnmatch.fnmatch(path.name, pattern):
            return unit
    return None


def to_ms2(trace, *, path: Path, declared: str | None, g_ms2: float, inventory=None) -> str:
    """Convert ``trace`` in place to m s-2 and return a note saying how.

    Raises
    ------
    UnitsError
        If the units cannot be determined or the response is missing.
    """
    stats = trace.stats
    fmt = getattr(stats, "_format", "?")
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
    if fmt == "KNET":
        if not stats.calib or stats.calib == 1.0:
            raise UnitsError(f"{path}: K-NET file without a Scale Factor; cannot convert counts")
        trace.data = np.asarray(trace.data, dtype=float) * stats.calib
        return f"units: counts x calib {stats.calib:.6e} (Scale Factor, gal->m/s**2) -> m/s**2"
    if inventory is not None and describes(inventory, trace):
        return _remove_response(trace, path=path, inventory=inventory)
    if fmt == "SAC":
        idep = int(stats.sac.get("idep", 5)) if "sac" in stats else 5
        raise UnitsError(
            f"{path}: SAC header idep={SAC_IDEP.get(idep, idep)} does not reliably give the "
            "units (producers write IACC for data in g or cm/s**2). Declare them in units.toml "
            f"in the records directory, e.g.  \"{path.name}\" = \"g\""
        )
    raise UnitsError(
        f"{path}: the units of this {fmt} file cannot be determined (raw counts with no "
        "StationXML response, or units not stated). Put the StationXML file in the records "
        "directory or pass --inventory; or declare the units in units.toml, e.g. "
        f"\"{path.name}\" = \"cm/s**2\""
    )


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
