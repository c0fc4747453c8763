"""``--levels auto``: the ladder of IM levels started from the blocks' capacities and extended round by round until
every block that can rock brackets 10 % and 90 % overturning.
"""

from __future__ import annotations

import math

import numpy as np

from .. import criteria
from ..assemblies.stack import interfaces, uplift_ratios
from ..blocks import Inventory
from ..config import Config
from ..errors import UsageError
from ..records.intensity import display_unit
from ..rocking.rules import rocks
from .fragility_stripes import STRIPE_KEYS

#: How a level's unit reads in a sentence (the option's suffix, ``cms``, is not a unit a reader knows)
UNIT_WORDS = {"cms": "cm/s", "ms": "m/s", "cms2": "cm/s2", "ms2": "m/s2"}
#: IMs ``--levels auto`` can start from the blocks' capacities: the uplift acceleration g min(tan alpha, mu) for
#: accelerations, the critical velocity of the reference paper's Eq. (4) for PGV, 1 for the velocity ratio
AUTO_IMS = ("pga", "sa", "ap", "pgv", "velocity_ratio")
#: ``--levels auto``: the ladder's step (each level twice the one below), its rounds of extension at most, and
#: its levels at most
AUTO_STEP, AUTO_ROUNDS, AUTO_MAX_LEVELS = 2.0, 4, 10
#: ... the fractions every block that can rock must reach at the ladder's two ends
AUTO_BRACKET = (0.1, 0.9)


def can_rock_blocks(inventory: Inventory, *, g_ms2: float) -> np.ndarray:
    """Whether each block can rock (:func:`~pipeline.rocking.rules.rocks`): one that cannot never overturns. A body
    of a stack can: its stack's model rocks it whatever its own friction and slenderness (its joints do not slide)."""
    geo = inventory.geometry(g_ms2=g_ms2)
    return np.array([inventory.stack_of(j) is not None or rocks(float(geo.alpha[j]), float(inventory.mu[j]))
                     for j in range(len(inventory))], dtype=bool)


def capacities(inventory: Inventory, im: str, *, g_ms2: float) -> np.ndarray:
    """Each block's capacity in the IM's SI unit, where its stripes start (NaN for a block that cannot rock)."""
    geo = inventory.geometry(g_ms2=g_ms2)
    can = can_rock_blocks(inventory, g_ms2=g_ms2)
    if im in ("pga", "sa", "ap"):
        c = g_ms2 * np.minimum(np.tan(geo.alpha), inventory.mu)             # uplift (Housner 1963)
        for j in range(len(inventory)):                                      # a stack's body: its stack's first
            place = inventory.stack_of(j)                                    # lift-off (stack.uplift_ratios)
            if place is not None:
                c[j] = g_ms2 * min(min(-low, high) for low, high in map(uplift_ratios, interfaces(place.bodies)))
    elif im == "pgv":
        c = criteria.critical_velocity(geo.R, geo.alpha, g_ms2=g_ms2)
    elif im == "velocity_ratio":
        c = np.ones(len(inventory))
    else:
        raise UsageError(f"--levels auto: {im} has no capacity to start from; auto takes {', '.join(AUTO_IMS)}; "
                         "give the levels")
    return np.where(can, np.asarray(c, dtype=float), np.nan)


def auto_ladder(cap: np.ndarray) -> np.ndarray:
    """The first ladder of ``--levels auto``: from the smallest capacity up by :data:`AUTO_STEP` to at least 4 times
    the largest [IM units]."""
    finite = cap[np.isfinite(cap)]
    if finite.size == 0:
        raise UsageError("--levels auto: no block of the inventory can rock (each slides or is too squat); "
                         "nothing can overturn, give the levels to fit anyway")
    n = int(math.ceil(math.log(4.0 * finite.max() / finite.min()) / math.log(AUTO_STEP) - 1e-9)) + 1
    return finite.min() * AUTO_STEP ** np.arange(min(max(n, 3), AUTO_MAX_LEVELS))


def extension(levels: np.ndarray, results: list[dict], cap: np.ndarray, *, outcome: str = "verdict") -> list[float]:
    """The levels to add so that every block that can rock brackets :data:`AUTO_BRACKET`: one step above the top
    where some block's top fraction is below 0.9, one below the bottom where some bottom fraction is above 0.1.
    ``outcome``: the result the fit uses (``verdict``, nominal; or a sampled probability, :data:`ORIENTATIONS`)."""
    if not results:
        return []
    order = np.argsort(levels)
    v = np.stack([r[outcome] for r in results]).astype(float)[:, order, :]          # (records, levels, blocks)
    v = np.where(v >= 0, v, np.nan)                                                  # -1 (no verdict) and NaN out
    with np.errstate(invalid="ignore"):
        frac = np.nanmean(v, axis=0)                                                 # (levels, blocks)
    rock = np.isfinite(cap)
    low, high = AUTO_BRACKET
    add = []
    if np.any(rock & ~(np.nan_to_num(frac[-1], nan=0.0) >= high)):
        add.append(float(levels[order[-1]] * AUTO_STEP))
    if np.any(rock & ~(np.nan_to_num(frac[0], nan=1.0) <= low)):
        add.append(float(levels[order[0]] / AUTO_STEP))
    return add


def merge_rounds(earlier: list[dict], later: list[dict]) -> list[dict]:
    """Per record, the stripes of two rounds of ``--levels auto`` side by side (a record missing from either
    round is left out: it failed there)."""
    by_id = {str(r["record_id"]): r for r in later}
    out = []
    for r in earlier:
        s = by_id.get(str(r["record_id"]))
        if s is None:
            continue
        merged = dict(r)
        for k in STRIPE_KEYS:
            merged[k] = np.concatenate([r[k], s[k]], axis=0)
        out.append(merged)
    return out


def auto_stripes(run, inventory: Inventory, config: Config, im: str, *, say=None, outcome: str = "verdict"
                 ) -> tuple[np.ndarray, list, list, dict]:
    """``--levels auto``: the ladder of :func:`auto_ladder`, extended round by round (:func:`extension`) until
    every block that can rock brackets 0.1 and 0.9, or :data:`AUTO_ROUNDS` rounds, or :data:`AUTO_MAX_LEVELS`
    levels. ``run(levels)`` runs the stripes of new levels; ``say(line)`` announces each round; ``outcome``: the
    result the fit uses (:func:`extension`). Returns the levels
    (increasing), the results (their stripes in that order), the failures and the counts."""
    cap = capacities(inventory, im, g_ms2=config.records.g_ms2)
    levels = auto_ladder(cap)
    shown, factor = display_unit(im)
    words = UNIT_WORDS.get(shown, shown)

    def listed(xs) -> str:
        return ", ".join(f"{x / factor:,.4g}" if x / factor < 1e4 else f"{x / factor:,.0f}" for x in xs)

    if say is not None:
        say(f"levels auto: {listed(levels)} {words}, from the blocks' capacities")
    results, failures, counts = run(levels)
    for k in range(AUTO_ROUNDS):
        add = [x for x in extension(levels, results, cap, outcome=outcome) if levels.size < AUTO_MAX_LEVELS]
        if not add:
            break
        if say is not None:
            say(f"levels auto, round {k + 2}: adding {listed(sorted(add))} {words}, "
                "where some block's stripes do not yet reach 10 % or 90 % overturning")
        more, more_failures, more_counts = run(np.array(sorted(add)))
        results = merge_rounds(results, more)
        failures = list(dict.fromkeys([*failures, *more_failures]))
        counts = dict(counts, wall_time_s=counts["wall_time_s"] + more_counts["wall_time_s"],
                      records_failed=len(failures))
        levels = np.concatenate([levels, np.array(sorted(add))])
    order = np.argsort(levels)
    for r in results:
        for name in STRIPE_KEYS:
            r[name] = np.asarray(r[name])[order]
    return levels[order], results, failures, counts
