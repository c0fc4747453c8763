"""The ``--levels`` option of ``screen fragility``: IM levels, with unit suffixes, in the IM's SI unit.

A suffix on any level applies to every level (0.1,0.2,0.3g is 0.1 g, 0.2 g and 0.3 g); errors name the option,
the value and what it takes.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .constants import G
from .errors import UsageError
from .records.intensity import IMS, SCALABLE, SI_LABEL

#: Unit suffixes ``--levels`` accepts, per SI unit of the IM: suffix -> factor to SI.
LEVEL_UNITS = {"m s-2": {"g": G, "gal": 0.01, "cms2": 0.01, "ms2": 1.0}, "m s-1": {"cms": 0.01, "ms": 1.0}}


def levels_unit(text: str, im: str) -> tuple[str, float]:
    """The unit ``--levels`` is given in: (label, factor to SI). A suffix on any level applies to every level;
    levels with different suffixes are an error.

    Raises
    ------
    UsageError
        For an unknown IM, a suffix the IM's unit does not take, or two different suffixes.
    """
    if im not in SCALABLE:
        raise UsageError(f"--im {im!r}: unknown or not scalable; valid: {', '.join(SCALABLE)}")
    unit = IMS[im][0]
    units = LEVEL_UNITS.get(unit, {})
    found = set()
    for k, raw in enumerate(text.split(","), 1):
        m = re.fullmatch(r"\s*[-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?\s*([A-Za-z][A-Za-z0-9]*)?\s*", raw)
        suffix = (m.group(1) or "").lower() if m else ""         # no number: parse_levels says so
        if suffix:
            if suffix not in units:
                hint = f"one of {', '.join(units)}" if units else "none (give the number alone)"
                raise UsageError(f"--levels: value {k} {raw.strip()!r}: unit {suffix!r} is not one {im} takes "
                                 f"({unit}); suffixes: {hint}")
            found.add(suffix)
    if len(found) > 1:
        raise UsageError(f"--levels {text!r}: several units ({', '.join(sorted(found))}); a unit suffix applies to "
                         "every level, so give one (0.1,0.2,0.3g is 0.1 g, 0.2 g, 0.3 g)")
    if found:
        suffix = found.pop()
        return suffix, units[suffix]
    return SI_LABEL[unit], 1.0


def parse_levels(text: str, im: str) -> np.ndarray:
    """``--levels`` in the IM's SI unit. A unit suffix on any level (g, gal, cms2, ms2 for accelerations; cms,
    ms for velocities) applies to every level (:func:`levels_unit`).

    Raises
    ------
    UsageError
        For an unknown IM or unit, several units, a value that is not a number, not positive or not
        increasing.
    """
    label, factor = levels_unit(text, im)
    unit = IMS[im][0]
    out: list[float] = []
    for k, raw in enumerate(text.split(","), 1):
        s = raw.strip()
        if label != SI_LABEL[unit] or s.lower().endswith(label):
            s = s[:-len(label)] if s.lower().endswith(label) else s
        try:
            v = float(s) * factor
        except ValueError:
            raise UsageError(f"--levels: value {k} {raw.strip()!r} is not a number; give {im} in {unit}"
                             + (" (or with a unit suffix)" if unit in LEVEL_UNITS else "")) from None
        if not (math.isfinite(v) and v > 0):
            raise UsageError(f"--levels: value {k} {raw.strip()!r} must be a positive number")
        if out and v <= out[-1]:
            raise UsageError(f"--levels: value {k} {raw.strip()!r} does not increase; give the levels in "
                             "increasing order")
        out.append(v)
    return np.array(out)
