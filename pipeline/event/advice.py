"""What to do about each asset after an earthquake, in plain words: its inspection level as an action, with the
probability it rests on (inspection.csv's ``recommendation`` and the first screen of event.html).

The levels are :class:`~.assets.Level`'s, from the probability that the asset overturned in the event (for a
ShakeMap scenario, that it would); where only bounds of that probability are known (:class:`~.assets.Basis`
bounds_only, unjudged), the level reads the upper bound, and the words say that only bounds are known. An asset too
wide to rock cannot overturn; one without a fragility is unknown, never "stands". An asset that slid in its
fragility's stripes at this shaking is also to be checked for sliding, whatever its level.
"""

from __future__ import annotations

import math

from ..rocking.block import NATURAL
from .assets import Basis, Level

#: The action of each level, then what a known probability says (an event that happened; a scenario).
ACTIONS = {
    Level.high: ("inspect first", "it probably overturned", "it would probably overturn"),
    Level.medium: ("inspect", "it may have overturned", "it may overturn"),
    Level.low: ("inspect after the high and medium ones", "it is unlikely to have overturned",
                "it is unlikely to overturn"),
    Level.none: ("no inspection for overturning", "it very probably stands", "it would very probably stand"),
}


#: A natural rock (the inventory's ``object`` natural) is looked at, never restrained: whether it still stands
#: informs the site's hazard.
NATURAL_ACTION = "check whether it still stands (a natural rock: its fall or its standing informs the site's hazard)"


def recommendation(level: Level, basis: Basis, p: float, p_low: float, p_high: float, *, slides: bool,
                   scenario: bool, natural: bool = False) -> str:
    """The asset's action and its reason, e.g. ``inspect first: it probably overturned (P = 0.62)``: ``p`` its
    probability of overturning (NaN where only the bounds ``p_low``, ``p_high`` are known), ``slides`` adds the
    sliding check, ``scenario`` words it for a scenario, ``natural`` for a natural rock."""
    if natural and basis not in (Basis.cannot_rock, Basis.no_fragility) and level != Level.none:
        known = math.isfinite(p) and basis != Basis.unjudged
        chance = _two(p) if known else f"{_two(p_low)} to {_two(p_high)}"
        if scenario:
            return f"no action (a natural rock, never restrained): P = {chance} that it would topple"
        return f"{NATURAL_ACTION}: P = {chance} that it toppled"
    if basis == Basis.cannot_rock:
        text = "no inspection for overturning: too wide to rock, it cannot overturn"
    elif basis == Basis.no_fragility:
        text = "inspect: its fragility is not known, so neither is its chance of overturning"
    else:
        action, happened, would = ACTIONS[level]
        if math.isfinite(p) and basis != Basis.unjudged:
            text = f"{action}: {would if scenario else happened} (P = {_two(p)})"
        else:
            text = f"{action}: only bounds of its chance of overturning are known (P {_two(p_low)} to {_two(p_high)})"
    return text + ("; check it for sliding: it slides at this shaking" if slides else "")


def _two(p: float) -> str:
    """A probability to two decimals ("<0.01" below 0.005 but above 0; "?" where not a number)."""
    if not math.isfinite(p):
        return "?"
    return "<0.01" if 0 < p < 0.005 else f"{p:.2f}"


def advice_at(v, k: int, *, scenario: bool, natural: bool = False) -> str:
    """Asset ``k``'s :func:`recommendation` from an event's arrays ``v`` (event.nc's variables by name: ``level``,
    ``basis``, ``p_overturn_event`` and its bounds, ``sliding_risk``); ``scenario`` for a ShakeMap scenario,
    ``natural`` for a natural rock."""
    return recommendation(Level(int(v["level"][k])), Basis(int(v["basis"][k])), float(v["p_overturn_event"][k]),
                          float(v["p_overturn_event_low"][k]), float(v["p_overturn_event_high"][k]),
                          slides=int(v["sliding_risk"][k]) == 1, scenario=scenario, natural=natural)


def is_scenario(attrs) -> bool:
    """Whether an event's attributes say its ShakeMap is a scenario."""
    return attrs.get("shakemap_event_type", "") == "SCENARIO"


def natural_rocks(objects) -> list[bool]:
    """Per block, whether the inventory's ``object`` column (one string per block, or None) says a natural rock."""
    return [str(o).strip().lower() == NATURAL for o in objects] if objects is not None else []
