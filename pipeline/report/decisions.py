"""The decision first, in plain words: what the report's first screen tells the person who acts.

Each asset's decision is its recommendation's action (the words before the colon: "restrain or anchor", "limit
sliding", "no action", ...; :mod:`pipeline.risk` decides it) with one sentence of why, in words and whole numbers
rather than the analyst's figures, which follow in the asset table. The tally counts the assets per decision.
"""

from __future__ import annotations

import math
from collections import Counter

from ..scene_table import SCENE

#: The assets the first screen names one by one: every asset whose decision calls for something, at most this many
#: (the rest are in the tally and the table).
FIRST_SCREEN_ASSETS = 8
#: Decisions that call for nothing.
NO_ACTION = "no action"


def action_of(recommendation: str) -> str:
    """The decision's words: the recommendation's action, before its reasons."""
    return recommendation.split(":")[0].strip()


def _stations(r: dict) -> str:
    over, screened = int(r["stations_overturning"]), int(r["stations_screened"])
    if over == 0:
        return f"none of the {screened} stations' records overturns it"
    return f"{over} of the {screened} stations' records overturn it"


def reason_of(r: dict) -> str:
    """One sentence of why, from the asset's row (:func:`pipeline.risk.asset_rows`)."""
    action = action_of(r["recommendation"])
    margin = float(r.get("overturn_scale_simulated", math.nan))
    p = float(r.get(SCENE.p_overturn, math.nan))
    chance = f"; its highest chance of overturning over the records is {round(100 * p)} %" if math.isfinite(p) else ""
    p_record, governing = str(r.get("p_record", "") or ""), str(r.get("governing_record", "") or "")
    if chance and p_record and governing and p_record != governing:       # each record the worst by its own measure
        chance += (f", under {p_record}: the record with the highest chance is not the one that overturns it at the "
                   f"smallest factor, {governing}")
    if action.startswith(("restrain", "monitor")):
        # the margin is said where it matters: a weaker record overturns it, or no record does as recorded
        said = math.isfinite(margin) and (margin < 1.0 or int(r["stations_overturning"]) == 0)
        scaled = f"; {r['governing_record']} overturns it at {margin:.2f} times its shaking" if said else ""
        return f"{_stations(r)}{scaled}{chance}."
    if action == NO_ACTION:
        return f"{_stations(r)}{chance}."
    rest = r["recommendation"].split(":", 1)
    return (rest[1].split(";")[0].strip() + ".") if len(rest) > 1 else ""


def first_screen(assets: list[dict]) -> list[dict]:
    """The assets named on the first screen, riskiest first: those whose decision calls for something (at most
    :data:`FIRST_SCREEN_ASSETS`), else the riskiest few; each with its block, name, decision and reason."""
    acting = [r for r in assets if action_of(r["recommendation"]) != NO_ACTION]
    chosen = (acting or assets)[:FIRST_SCREEN_ASSETS]
    return [{"block": r["block"], "name": r["block_name"], "decision": action_of(r["recommendation"]),
             "reason": reason_of(r)} for r in chosen]


def tally(assets: list[dict]) -> list[tuple[str, int]]:
    """How many assets get each decision, the most common first."""
    return Counter(action_of(r["recommendation"]) for r in assets).most_common()
