"""Where a record was recorded: the station's longitude and latitude, from the files themselves where the format
has them.

- SAC: header ``stla``, ``stlo`` (-12345: undefined).
- K-NET and KiK-net: header ``Station Lat.``, ``Station Long.`` (obspy: ``stats.knet.stla``, ``stlo``).
- COSMOS V0-V2: the text header's line ``Coords: lat lon`` (decimal degrees, east positive).
- CSMIP/DMG: the station line, ``37.973N, 122.038W``.
- MiniSEED and other formats without coordinates: the StationXML given with the records (its channel's or
  station's latitude and longitude).
- PEER ``.AT2`` and near-fault ASCII files carry none: such a record has no location.

References
----------
Goldstein, P. & Snoke, A. (2005). SAC Availability for the IRIS Community (the header variables). Kinoshita, S.
(1998). Kyoshin Net (K-NET). Seismological Research Letters 69(4), 309-332. COSMOS (2001). COSMOS Strong-Motion
Data Format, version 1.20. Shakal, A. & Huang, M. (1985). CSMIP Standard Data Format (DMG). Sinnott, R. W. (1984).
Virtues of the haversine. Sky and Telescope 68(2), 159 (:func:`distance_km`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

#: Mean radius of the Earth [km] (great-circle distances)
EARTH_RADIUS_KM = 6371.0
#: SAC's undefined header value
SAC_UNDEFINED = -12345.0
#: COSMOS text header: "Coords: 34.063  -117.785"
_COSMOS_COORDS = re.compile(r"Coords:\s*(-?\d+(?:\.\d+)?)\s+(-?\d+(?:\.\d+)?)")
#: DMG station line: "37.973N, 122.038W"
_DMG_COORDS = re.compile(r"(\d+(?:\.\d+)?)\s*([NS])\s*,\s*(\d+(?:\.\d+)?)\s*([EW])")


@dataclass(frozen=True)
class StationLocation:
    """A record's station: longitude and latitude [deg], and where they were read."""

    lon: float
    lat: float
    source: str


def _valid(lon: float, lat: float) -> bool:
    return math.isfinite(lon) and math.isfinite(lat) and -180.0 <= lon <= 360.0 and -90.0 <= lat <= 90.0 \
        and not (lon == 0.0 and lat == 0.0)


def _from_stats(stats) -> StationLocation | None:
    sac = stats.get("sac")
    if sac is not None:
        lat, lon = float(sac.get("stla", SAC_UNDEFINED)), float(sac.get("stlo", SAC_UNDEFINED))
        if SAC_UNDEFINED not in (lat, lon) and _valid(lon, lat):
            return StationLocation(lon, lat, "SAC header stla, stlo")
    knet = stats.get("knet")
    if knet is not None and "stla" in knet and "stlo" in knet:
        lat, lon = float(knet["stla"]), float(knet["stlo"])
        if _valid(lon, lat):
            return StationLocation(lon, lat, "K-NET header Station Lat., Station Long.")
    cosmos = stats.get("cosmos")
    if cosmos is not None:
        for line in cosmos.get("text_header", []):
            if (m := _COSMOS_COORDS.search(line)) and _valid(float(m.group(2)), float(m.group(1))):
                return StationLocation(float(m.group(2)), float(m.group(1)), "COSMOS header Coords")
    dmg = stats.get("dmg")
    if dmg is not None:
        for line in dmg.get("text_header", []):
            if m := _DMG_COORDS.search(line):
                lat = float(m.group(1)) * (1.0 if m.group(2) == "N" else -1.0)
                lon = float(m.group(3)) * (1.0 if m.group(4) == "E" else -1.0)
                if _valid(lon, lat):
                    return StationLocation(lon, lat, "DMG header station line")
    return None


def station_location(traces, inventory=None) -> StationLocation | None:
    """The station of a recording's traces: from the first trace whose file gives it, else from the StationXML
    ``inventory`` (None: no location)."""
    for tr in traces:
        found = _from_stats(tr.stats)
        if found is not None:
            return found
    if inventory is not None:
        for tr in traces:
            try:
                c = inventory.get_coordinates(tr.id, tr.stats.starttime)
            except Exception:              # obspy raises a bare Exception for a channel it does not hold
                continue
            if _valid(float(c["longitude"]), float(c["latitude"])):
                return StationLocation(float(c["longitude"]), float(c["latitude"]), "StationXML")
    return None


def distance_km(lon: np.ndarray, lat: np.ndarray, lon0: float, lat0: float) -> np.ndarray:
    """Great-circle distance from (lon0, lat0) [km] (haversine, a sphere of :data:`EARTH_RADIUS_KM`)."""
    p1, p2 = np.radians(lat), math.radians(lat0)
    a = np.sin((p2 - p1) / 2) ** 2 + np.cos(p1) * math.cos(p2) * np.sin(np.radians(lon0 - lon) / 2) ** 2
    return 2 * EARTH_RADIUS_KM * np.arcsin(np.sqrt(np.clip(a, 0.0, 1.0)))
