"""Component orientation from channel codes and headers.

Horizontal azimuths are in degrees clockwise from north. A pair whose
absolute azimuth is unknown but that is orthogonal (``1/2``, ``L/T``,
``FN/FP``, ``H1/H2``) gets the nominal azimuths 0 and 90 and is flagged.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

#: Component codes of the public strong-motion sets (PEER NGA-West2, NGA-East and NGA-Sub file suffixes and
#: header components, COSMOS, K-NET/KiK-net, SEED): vertical ones.
VERTICAL_CODES = {"UP", "V", "Z", "UD", "DWN", "DN", "DOWN", "VER", "VERT", "VERTICAL", "HNZ", "HHZ", "HLZ"}
#: Absolute horizontal azimuths [deg clockwise from north] named by letters.
AZIMUTH_CODES = {"N": 0.0, "NS": 0.0, "NORTH": 0.0, "S": 180.0, "SN": 180.0, "SOUTH": 180.0,
                 "E": 90.0, "EW": 90.0, "EAST": 90.0, "W": 270.0, "WE": 270.0, "WEST": 270.0}
#: Orthogonal pairs of unknown absolute azimuth: first -> 0, second -> 90 (nominal). L/T and LN/TR
#: (longitudinal / transverse), R/T (radial / transverse), FN/FP (fault normal / parallel), H1/H2, 1/2, X/Y.
RELATIVE_PAIRS = {"1": 0, "2": 1, "L": 0, "T": 1, "LN": 0, "TR": 1, "LON": 0, "LONG": 0, "TRA": 1, "TRAN": 1,
                  "TRANS": 1, "R": 0, "RAD": 0, "FN": 0, "FP": 1, "H1": 0, "H2": 1, "X": 0, "Y": 1}


@dataclass(frozen=True)
class Orientation:
    """Orientation of one component.

    Attributes
    ----------
    vertical : bool
        True for the vertical component.
    azimuth_deg : float or None
        Absolute azimuth [deg clockwise from north], None when unknown.
    pair_index : int or None
        0 or 1 within an orthogonal pair of unknown absolute azimuth.
    """

    vertical: bool
    azimuth_deg: float | None = None
    pair_index: int | None = None


def orientation_from_code(code: str) -> Orientation | None:
    """Return the orientation that a component code implies, or None if it says nothing.

    Examples: ``"228"`` -> 228 deg, ``"HNE"`` -> 90 deg, ``"NS2"`` -> 0 deg,
    ``"UP"`` -> vertical, ``"L"`` -> first of a relative pair.
    """
    c = code.strip().upper()
    if re.fullmatch(r"\d+(\.\d+)?", c):
        return Orientation(False, float(c) % 360.0)
    c = re.sub(r"[12]$", "", c) if re.fullmatch(r"(NS|EW|UD)[12]", c) else c     # KiK-net NS1/NS2 ...
    if re.search(r"[-_. ]", c):                 # "TCU052-E", "BAM-L", "KJM_000": the part after the station
        return orientation_from_code(re.split(r"[-_. ]+", c.strip("-_. "))[-1])
    if c in VERTICAL_CODES:
        return Orientation(True)
    if c in AZIMUTH_CODES:
        return Orientation(False, AZIMUTH_CODES[c])
    if c in RELATIVE_PAIRS:
        return Orientation(False, None, RELATIVE_PAIRS[c])
    m = re.fullmatch(r"[A-Z][A-Z0-9]*(\d{3})", c)   # station, then a 3-digit azimuth: "NWH360", "E06140"
    if m and len(c) >= 5:
        return Orientation(False, float(m.group(1)) % 360.0)
    if len(c) == 3 and c[:2].isalpha():  # SEED band + instrument + orientation
        last = c[2]
        if last == "Z":
            return Orientation(True)
        if last in ("N", "E"):
            return Orientation(False, 0.0 if last == "N" else 90.0)
        if last in ("1", "2"):
            return Orientation(False, None, RELATIVE_PAIRS[last])
        return None
    return None


def orientation_of(trace, inventory=None) -> Orientation | None:
    """Orientation of an obspy trace: header fields first, then the channel code."""
    stats = trace.stats
    for fmt in ("cosmos", "dmg"):
        if fmt in stats:
            hdr = stats[fmt]
            if hdr.get("vertical"):
                return Orientation(True)
            if hdr.get("azimuth_deg") is not None:
                return Orientation(False, float(hdr.azimuth_deg) % 360.0)
    if "sac" in stats and stats.sac.get("cmpinc") is not None and stats.sac.get("cmpaz") is not None:
        inc = float(stats.sac.cmpinc)
        if abs(inc) < 1e-3 or abs(inc - 180.0) < 1e-3:
            return Orientation(True)
        if abs(inc - 90.0) < 1e-3:
            return Orientation(False, float(stats.sac.cmpaz) % 360.0)
    if inventory is not None:
        try:
            meta = inventory.get_orientation(trace.id, stats.starttime)
            if abs(abs(meta["dip"]) - 90.0) < 1e-3:
                return Orientation(True)
            if abs(meta["dip"]) < 1e-3:
                return Orientation(False, float(meta["azimuth"]) % 360.0)
        except Exception:  # channel not in the inventory: fall back to the code
            pass
    return orientation_from_code(stats.channel)
