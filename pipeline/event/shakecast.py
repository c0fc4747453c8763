"""Blocks as USGS ShakeCast facilities: an inventory with its overturning fragilities in ShakeCast's facility XML,
so that a ShakeCast system alerts on rockscreen's physics; and the reader of that XML.

The format (``FacilityTable/FacilityRow``): EXTERNAL_FACILITY_ID, FACILITY_TYPE, COMPONENT_CLASS, COMPONENT,
FACILITY_NAME, DESCRIPTION, SHORT_NAME, FEATURE (GEOM_TYPE, GEOM "lon,lat,depth"), FACILITY_MODEL and FRAGILITY,
whose damage levels (GREEN, YELLOW, ORANGE, RED, GREY) each hold METRIC (PGA, PGV, PSA03, PSA10, PSA30, MMI),
ALPHA (the median, in ShakeMap's unit of the metric: %g for PGA and PSA, cm/s for PGV) and BETA (the lognormal
dispersion).

rockscreen writes only the damage levels it defines physically:

- **RED: overturning**, the block's fitted fragility (``screen fragility``; floors included), on its IM.
- **YELLOW: motion starts** (uplift, or slip where friction is lower), on PGA, for a block on the ground: a rigid
  block on a rigid base moves when |a_h| exceeds g min(tan alpha, mu) (Housner 1963), a threshold with the
  dispersion of the declared uncertainty on the size and the friction. Blocks in a building have no such ground
  PGA and get no YELLOW.

No GREEN, ORANGE or GREY: rockscreen defines no damage state there.

References
----------
Lin, K.-W. & Wald, D. J. (2008). ShakeCast Manual. U.S. Geological Survey Open-File Report 2008-1158.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape

from ..constants import G
from ..errors import RockscreenError

#: ShakeCast's damage levels, in its order
DAMAGE_LEVELS = ("GREEN", "YELLOW", "ORANGE", "RED", "GREY")
#: ShakeCast metrics and the factor from SI to ShakeMap's unit (%g for accelerations, cm/s for velocity)
METRIC_FACTORS = {"PGA": 100.0 / G, "PSA03": 100.0 / G, "PSA10": 100.0 / G, "PSA30": 100.0 / G, "PGV": 100.0}
#: The fields of a facility row, in the format's order
ROW_FIELDS = ("EXTERNAL_FACILITY_ID", "FACILITY_TYPE", "COMPONENT_CLASS", "COMPONENT", "FACILITY_NAME",
              "DESCRIPTION", "SHORT_NAME")
#: ShakeCast takes the log of BETA; a dispersion below this is written as this [-]
BETA_FLOOR = 0.01


class ShakeCastError(RockscreenError, ValueError):
    """A facility XML that does not follow the format (the message names the file, the facility and the field)."""


@dataclass(frozen=True)
class DamageLevel:
    """One damage level of a facility: its metric, median in ShakeMap units, dispersion and meaning."""

    name: str
    metric: str
    alpha: float
    beta: float


@dataclass(frozen=True)
class Facility:
    """A block as a ShakeCast facility."""

    facility_id: str
    name: str
    description: str
    lon: float
    lat: float
    levels: tuple[DamageLevel, ...]
    facility_type: str = "STATUE"
    model: str = "ROCKING_BLOCK"


def facility_xml(facilities: list[Facility]) -> str:
    """The facilities as a ShakeCast facility XML document (UTF-8 text, tab-indented as ShakeCast's examples)."""
    out = ['<?xml version="1.0" encoding="UTF-8" standalone="yes"?>', "<FacilityTable>"]
    for f in facilities:
        values = {"EXTERNAL_FACILITY_ID": f.facility_id, "FACILITY_TYPE": f.facility_type,
                  "COMPONENT_CLASS": "SYSTEM", "COMPONENT": "SYSTEM", "FACILITY_NAME": f.name or f.facility_id,
                  "DESCRIPTION": f.description, "SHORT_NAME": f.facility_id[:10]}
        out.append("\t<FacilityRow>")
        out += [f"\t\t<{key}>{escape(values[key])}</{key}>" for key in ROW_FIELDS]
        out += ["\t\t<FEATURE>", "\t\t\t<GEOM_TYPE>POINT</GEOM_TYPE>",
                f"\t\t\t<GEOM>{f.lon:.6f},{f.lat:.6f},0</GEOM>", "\t\t</FEATURE>",
                f"\t\t<FACILITY_MODEL>{escape(f.model)}</FACILITY_MODEL>", "\t\t<FRAGILITY>"]
        for level in sorted(f.levels, key=lambda lv: DAMAGE_LEVELS.index(lv.name)):
            out += [f"\t\t\t<{level.name}>", f"\t\t\t\t<METRIC>{level.metric}</METRIC>",
                    f"\t\t\t\t<ALPHA>{level.alpha:.6g}</ALPHA>",
                    f"\t\t\t\t<BETA>{max(level.beta, BETA_FLOOR):.6g}</BETA>", f"\t\t\t</{level.name}>"]
        out += ["\t\t</FRAGILITY>", "\t</FacilityRow>"]
    out.append("</FacilityTable>")
    return "\n".join(out) + "\n"


def overturning_level(metric: str, median_si: float, beta: float) -> DamageLevel | None:
    """RED: the overturning fragility in ShakeMap units (None where the median is not a finite positive value)."""
    if not (math.isfinite(median_si) and median_si > 0 and math.isfinite(beta)):
        return None
    return DamageLevel("RED", metric, median_si * METRIC_FACTORS[metric], beta)


def onset_level(*, alpha_rad: float, mu: float, size_cov: float, friction_cov: float,
                g_ms2: float = G) -> DamageLevel:
    """YELLOW: motion starts at PGA = g min(tan alpha, mu), with the dispersion of the declared spread of the
    governing one (tan alpha = width / height, each with ``size_cov``; mu with ``friction_cov``)."""
    tan_a = math.tan(alpha_rad)
    if mu < tan_a:
        threshold, beta = mu, math.sqrt(math.log1p(friction_cov ** 2))
    else:
        threshold, beta = tan_a, math.sqrt(2.0 * math.log1p(size_cov ** 2))
    return DamageLevel("YELLOW", "PGA", threshold * g_ms2 * METRIC_FACTORS["PGA"], beta)


def read_facilities(path: str | Path) -> list[Facility]:
    """Read a ShakeCast facility XML (the format in the module's docstring).

    Raises
    ------
    ShakeCastError
        For a missing field, a metric ShakeCast does not know, or an ALPHA or BETA that is not a positive number.
    """
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as exc:
        raise ShakeCastError(f"{path}: cannot read it as XML ({exc})") from exc
    if root.tag != "FacilityTable":
        raise ShakeCastError(f"{path}: the root element is {root.tag}, expected FacilityTable")
    out = []
    for k, row in enumerate(root.findall("FacilityRow"), start=1):
        fid = row.findtext("EXTERNAL_FACILITY_ID")
        where = f"{path}: facility {fid or k}"
        if not fid:
            raise ShakeCastError(f"{where}: no EXTERNAL_FACILITY_ID")
        geom = (row.findtext("FEATURE/GEOM") or "").split(";")[0].split(",")
        try:
            lon, lat = float(geom[0]), float(geom[1])
        except (ValueError, IndexError):
            raise ShakeCastError(f"{where}: FEATURE/GEOM {row.findtext('FEATURE/GEOM')!r} is not 'lon,lat,depth'"
                                 ) from None
        levels = []
        for el in row.find("FRAGILITY") or []:
            if el.tag not in DAMAGE_LEVELS:
                raise ShakeCastError(f"{where}: damage level {el.tag}; expected one of {DAMAGE_LEVELS}")
            metric = el.findtext("METRIC") or ""
            if metric not in (*METRIC_FACTORS, "MMI"):
                raise ShakeCastError(f"{where}: {el.tag} METRIC {metric!r}; expected one of "
                                     f"{[*METRIC_FACTORS, 'MMI']}")
            try:
                alpha, beta = float(el.findtext("ALPHA") or ""), float(el.findtext("BETA") or "")
            except ValueError:
                raise ShakeCastError(f"{where}: {el.tag} ALPHA or BETA is not a number") from None
            if not (alpha > 0 and beta > 0):
                raise ShakeCastError(f"{where}: {el.tag} ALPHA {alpha} and BETA {beta} must be positive")
            levels.append(DamageLevel(el.tag, metric, alpha, beta))
        out.append(Facility(fid, row.findtext("FACILITY_NAME") or "", row.findtext("DESCRIPTION") or "", lon, lat,
                            tuple(levels), row.findtext("FACILITY_TYPE") or "", row.findtext("FACILITY_MODEL") or ""))
    return out
