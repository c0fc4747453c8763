"""Asset risk: one row per asset from the screening results, ranked, with the action it calls for and why
(``assets.csv``, and the table of the report).

Recommendation rule (per asset; thresholds here). It weighs the probability of overturning under the
declared uncertainty (the largest over the records, when the run sampled) and the simulated margin on the
governing record, and says why in words. A scene or a sample without a verdict is unknown, never safe: the
rule also weighs ``p_overturn_with_unknown``, the largest over the records of the fraction of samples that
overturn or have no verdict (the unknown counted as overturning).

* p >= :data:`P_ANCHOR`, or (without sampling) a simulated margin <= 1: "restrain or anchor" (a margin <= 1
  for an asset that stands under its governing record means the record scaled down overturns it: a window
  of overturning below the nominal amplitude, flagged ``overturns_below_nominal``);
* p >= :data:`P_RELOCATE`, a simulated margin <= :data:`RELOCATE_BELOW_SCALE` (<= 1 with p below
  :data:`P_ANCHOR` included), or the paper's criterion says it overturns: "restrain" ("restrain, or move it to a
  lower floor" on an upper floor of a building, where that lowers its motion);
* stations whose records have no verdict (the ground fell faster than gravity, a model stopped where the base
  would slide, twist or lift off, or a cap), or samples without a verdict that could lift p to
  :data:`P_RELOCATE`: "at risk until judged", with how many and why, never "no action" nor "limit sliding";
* the governing scene slides (or the pure-rocking friction demand exceeds mu): "limit sliding";
* no record screened at all (every record failed): "not screened", with the failures' count, never "no action";
* the paper's criterion alone (fidelity ``criterion``, no simulation): "check by simulation", never "no action":
  the criterion misses most overturnings;
* otherwise "no action".

A natural object (the inventory's ``object`` column ``natural``: a precariously balanced rock, a rock of a hazard
study) is never told to be anchored nor to limit its sliding: at risk it is "monitor", and otherwise a rock that
stands "informs the site's hazard" (``screen constrain``).

Every recommendation that counts the stations overturning the asset also counts those without a verdict. An
asset with any station or sample without a verdict is never ``robust_stand`` and its simulated verdict never
reads "stands" alone.

References
----------
The reference paper, "Rocking Blocks Stability under Critical Pulses from Near-Fault Earthquakes Using a Novel
Energy Based Approach", Applied Sciences (MDPI) (the criterion the rule weighs beside the simulation).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .rocking.block import NATURAL
from .rocking.orientation import Orientation
from .rocking.planner import FreeFlight, Physics, Response
from .scene_table import SCENE
from .schema import INVENTORY_PREFIX
from .stacks import RULE_WORDS, StackRule
from .uncertainty.robust import Robustness

#: A probability of overturning at or above this (under some record) calls for restraint or anchoring [-].
P_ANCHOR = 0.5
#: What a natural object (the inventory's ``object`` natural) is told: it is never anchored. At risk, it is watched
#: (its state recorded, a fall noticed); standing under every record, its age bounds the site's hazard.
NATURAL_AT_RISK = "monitor (a natural rock)"
#: The remedy besides a restraint where the asset stands on an upper floor of a building: a lower floor moves less
#: (on the ground, relocating it changes nothing).
UPPER_FLOOR_REMEDY = "restrain, or move it to a lower floor"
NATURAL_STANDS = "no action: a rock that stands informs the site's hazard (screen constrain)"
#: An asset is at risk ('restrain' in the report; the margins stage keeps a history for it) when its
#: largest probability of overturning over the records reaches this [-] (the robust-stand bound of the default
#: [uncertainty]) ...
P_RELOCATE = 0.1
#: ... or its simulated margin on its governing record is at most this [-]
RELOCATE_BELOW_SCALE = 1.5
#: Responses that call for limiting sliding.
SLIDING_RESPONSES = {Response.slide, Response.slide_rock}
RESPONSE_NAMES = {-1: "not simulated", **{m.value: m.name for m in Response}}
PHYSICS_NAMES = {-1: "not simulated", **{m.value: m.name for m in Physics}}
VERDICT = {-1: "n/a", 0: "stands", 1: "overturns"}
ROBUSTNESS_NAMES = {-1: "", **{m.value: m.name for m in Robustness}}
#: The robustness an asset reads where some station or sample has no verdict and its judged ones would stand.
ROBUSTNESS_UNKNOWN = "unknown"

#: Columns of assets.csv (their headers: :data:`ASSETS_CSV_HEADERS` adds the unit to a name); a column named as a
#: screening.nc variable holds that variable (same units: height and width [m], slenderness [rad],
#: frequency_parameter [rad s-1], azimuths [deg]) for the asset's governing scene, except
#: p_overturn (the worst orientation), its interval, p_overturn_azimuth (the plane it is for [deg]),
#: p_overturn_random_orientation (an unknown orientation) and robustness, which are those of the record with the
#: largest p_overturn (``p_record``). ``p_overturn_with_unknown``: the largest over the records of (samples that
#: overturn + samples without a verdict) / samples drawn; ``draws_without_verdict`` and ``draws``: the samples
#: without a verdict and the samples drawn, summed over the records. ``stations_*`` count the records of one station
#: recording in several files once (``records_*`` count files). Extra inventory columns follow, as given.
ASSETS_CSV_COLUMNS = ("rank", "block", "block_name", "site", "height", "width", "mu", "slenderness",
                 "frequency_parameter", SCENE.p_overturn, SCENE.p_overturn_low, SCENE.p_overturn_high, "p_record",
                 "p_overturn_with_unknown", "draws_without_verdict", "draws",
                 SCENE.p_overturn_azimuth, SCENE.p_overturn_random_orientation, SCENE.robustness,
                 "stations_p_half", "records_sensitive", "stations_overturning", "stations_screened",
                 "stations_without_verdict",
                 "records_overturning", "records_screened", "governing_record",
                 SCENE.governing_azimuth, "verdict_criterion", "verdict_simulation", SCENE.theta_max, SCENE.response,
                 SCENE.physics,
                 "overturn_scale", "overturn_scale_simulated", "overturns_below_nominal", "p_overturn_governing",
                 "overturn_scale_median", "recommendation",
                 "records_overturning_ids", "building", "floor_height_m", "floor_pga_ratio", "stands_on", "stack_id",
                 "joint_opening_g", "stack_opens_first", "stack_rule", "stack_records_failing")


#: The paper's criterion's words for a body of a stack: it judges a block alone on the ground, not a stack's body
STACK_CRITERION = "not applicable (a body of a stack)"


def _col(ds: xr.Dataset, name: str) -> np.ndarray:
    """The array of ``ds``'s variable ``name``, read from its variable: ``ds[name]`` builds a DataArray each time
    (about 50 us, 150 times the look-up), and an asset's row reads some 40 (the rows of 1,000 blocks on 10 records:
    0.23-0.26 s, against 1.8-1.9 s through ``ds[name]``, the same rows)."""
    return ds.variables[name].values


def factor_words(x: float) -> str:
    """A factor on a record to the precision that keeps its side of 1 (0.996 is '0.996', never '1.00')."""
    for digits in (2, 3, 4, 6):
        text = f"{x:.{digits}f}"
        if x == 1.0 or (float(text) < 1.0) == (x < 1.0) and float(text) != 1.0:
            return text
    return repr(x)


def _margin_words(sim_scale: float, governing: str) -> str:
    """The simulated margin on the governing record, in words."""
    if not np.isfinite(sim_scale):
        return (f"no overturning found under {governing} scaled up to the scan limit" if np.isinf(sim_scale)
                else "no margin")
    if sim_scale <= 1.0:
        return f"overturns under {governing} scaled by {factor_words(sim_scale)}"
    return f"overturns only with {governing} scaled by {factor_words(sim_scale)}"


def recommendation(*, sim_scale: float, crit_overturns: bool, response: int, overturned: bool = True,
                   p_max: float = math.nan, p_record: str = "", governing: str = "the governing record",
                   stations: tuple[int, int] | None = None, p_words: str = "", slide_m: float = math.nan,
                   undecided: int = 0, undecided_why: str = "", failed: int = 0,
                   unknown_draws: tuple[int, int] = (0, 0), p_with_unknown: float = math.nan,
                   criterion_only: bool = False, natural: bool = False, upper_floor: bool = False) -> str:
    """The action for one asset and why, in words (see the module docstring for the rule).

    Parameters
    ----------
    sim_scale : float
        Simulated margin on the governing record: the first factor of the upward scan that overturns the asset [-].
    crit_overturns : bool
        The paper's criterion says the governing record overturns it.
    response : int
        Simulated response code of the governing scene.
    overturned : bool
        The governing scene overturns (nominal).
    p_max : float
        The largest probability of overturning over the records (NaN without sampling) [-].
    p_record : str
        The record ``p_max`` is for.
    p_words : str
        ``p_max`` in words, when the caller has more to say (its orientation); default "p = .. under ..".
    slide_m : float
        How far the governing scene slides [m] (NaN: unknown).
    governing : str
        The governing record (the margin's record).
    stations : tuple of int, optional
        (stations whose record overturns the asset, stations screened).
    undecided : int
        Stations whose records all leave the asset without a verdict (the model stopped).
    undecided_why : str
        Why, in words (:func:`undecided_causes`).
    failed : int
        Records that could not be screened (said where none was).
    unknown_draws : tuple of int
        (samples without a verdict, samples drawn), summed over the records.
    p_with_unknown : float
        The largest over the records of the fraction of samples that overturn or have no verdict [-].
    criterion_only : bool
        The run judged by the paper's criterion alone (fidelity ``criterion``).
    natural, upper_floor : bool
        A natural object (the inventory's ``object``), and an asset on an upper floor (their words: the module's).
    """
    if stations is not None and stations[1] == 0:
        return ("not screened: no record was screened" + (f" ({failed} failed; the report lists each failure and "
                                                          "its fix)" if failed else ""))
    sampled = np.isfinite(p_max)
    why = [p_words or f"p = {p_max:.2f} under {p_record}"] if sampled else []
    if not criterion_only:
        why.append(_margin_words(sim_scale, governing))
    if stations is not None:
        why.append(f"{stations[0]} of {stations[1]} stations overturn it" + (" by the paper's criterion"
                                                                              if criterion_only else ""))
    why += _unknown_words(stations, undecided, undecided_why, unknown_draws, p_with_unknown)
    small_margin = np.isfinite(sim_scale) and sim_scale <= RELOCATE_BELOW_SCALE
    if (sampled and p_max >= P_ANCHOR) or (not sampled and np.isfinite(sim_scale) and sim_scale <= 1.0):
        if not sampled and not overturned:
            why.append("it stands under the record itself: overturning is not monotonic in amplitude")
        return _at_risk(natural, "restrain or anchor") + ": " + "; ".join(why)
    if (sampled and p_max >= P_RELOCATE) or small_margin or crit_overturns:
        if crit_overturns and not small_margin and not (sampled and p_max >= P_RELOCATE):
            why.append("the paper's criterion predicts overturning")
        return _at_risk(natural, UPPER_FLOOR_REMEDY if upper_floor else "restrain") + ": " + "; ".join(why)
    unknown_matters = undecided > 0 or (response == Response.free_flight and not sampled) or (
        np.isfinite(p_with_unknown) and p_with_unknown >= P_RELOCATE)
    if unknown_matters:
        return ("at risk until judged: treat it as at risk until the records without a verdict are judged (a "
                "model of the base's sliding, twisting or lift-off, or a check by another tool); " + "; ".join(why))
    if criterion_only:
        return ("check by simulation: the paper's criterion alone finds no overturning, and it is not conservative "
                "(it misses most overturnings the simulation finds); run the default fidelity; " + "; ".join(why))
    if response in SLIDING_RESPONSES and not natural:
        far = f" {slide_m:.2g} m" if np.isfinite(slide_m) and slide_m > 0 else ""
        return f"limit sliding (friction pads or a restraint): it slides{far} under {governing}"
    if natural:
        return NATURAL_STANDS + "; " + "; ".join(why)
    return "no action: " + "; ".join(why)


def _unknown_words(stations: tuple[int, int] | None, undecided: int, undecided_why: str,
                   unknown_draws: tuple[int, int], p_with_unknown: float) -> list[str]:
    """What was not judged, in words: the stations without a verdict and why, the samples without one and what
    they could make of p."""
    out = []
    if undecided and stations is not None:
        out.append(f"overturning not judged on {undecided} of {stations[1]} stations "
                   f"({undecided_why or 'the model stopped'})")
    if unknown_draws[0]:
        words = f"{unknown_draws[0]} of {unknown_draws[1]} samples have no verdict"
        if np.isfinite(p_with_unknown):
            words += f" (counted as overturning, p reaches {p_with_unknown:.2f})"
        out.append(words)
    return out


def undecided_causes(ds: xr.Dataset, rows: np.ndarray, j: int) -> str:
    """Why the scenes ``rows`` (a mask over records) of block ``j`` have no verdict, in words: the ground falling
    faster than gravity, where a body model stops (its :class:`~pipeline.bodies.contract.Stops` in the registry), or
    a simulator's cap."""
    from .bodies.registry import stops

    flight = np.asarray(_col(ds, SCENE.free_flight)[rows, j] == FreeFlight.ground_flight if SCENE.free_flight in ds
                        else np.zeros(int(np.sum(rows)), bool), dtype=bool)
    physics = _col(ds, SCENE.physics)[rows, j]
    causes = ["the ground fell faster than gravity"] if np.any(flight) else []
    explained = flight.copy()
    left_out = _left_out(ds, rows, j)
    for stop in stops():
        theirs = np.isin(physics, stop.physics) & ~flight & (left_out if stop.flagged_only else True)
        if np.any(theirs) and stop.words not in causes:
            causes.append(stop.words)
        explained |= theirs
    if np.any(~explained):
        causes.append("the simulation stopped at a cap")
    return "; ".join(causes)


def _station_counts(stations: np.ndarray, ok: np.ndarray, verdict: np.ndarray) -> tuple[int, int, int]:
    """Stations whose record overturns the block, stations whose records all left it without a verdict, and stations
    screened (``verdict`` over the records: 1, 0, -1)."""
    decided = set(stations[ok & (verdict >= 0)].tolist())
    return (len(set(stations[ok & (verdict == 1)].tolist())),
            len(set(stations[ok & (verdict < 0)].tolist()) - decided), len(set(stations[ok].tolist())))


def _left_out(ds: xr.Dataset, rows: np.ndarray, j: int) -> np.ndarray:
    """Whether each scene ``rows`` of block ``j`` was flagged for an effect its model leaves out (friction exceeded
    at a pivot, or the block's own lift-off)."""
    n = int(np.sum(rows))
    exceeded = _col(ds, SCENE.friction_exceeded)[rows, j] == 1 if SCENE.friction_exceeded in ds else np.zeros(n, bool)
    lift = (_col(ds, SCENE.free_flight)[rows, j] == FreeFlight.block_liftoff if SCENE.free_flight in ds
            else np.zeros(n, bool))
    return np.asarray(exceeded | lift, dtype=bool)


def p_with_unknown(ds: xr.Dataset) -> np.ndarray:
    """Per scene (records, blocks): (samples that overturn + samples without a verdict) / samples drawn, the
    unknown counted as overturning (NaN: not sampled, or a results file without the counts)."""
    if SCENE.samples_without_verdict not in ds:
        return np.full(ds[SCENE.overturn_simulated].shape, np.nan)
    drawn = _col(ds, SCENE.samples_drawn).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(drawn > 0, (_col(ds, SCENE.samples_overturned)
                                    + _col(ds, SCENE.samples_without_verdict)) / drawn, np.nan)


def scenes_without_verdict(ds: xr.Dataset) -> int:
    """The screened scenes (records of status ok) the simulation left without a verdict; 0 where it ran nothing
    (fidelity ``criterion``: no scene was simulated, so none stopped)."""
    ok = _col(ds, "status") == "ok"
    simulated = _col(ds, SCENE.physics)[ok] >= 0 if SCENE.physics in ds else np.zeros((0,), dtype=bool)
    return int(np.sum((_col(ds, SCENE.overturn_simulated)[ok] < 0) & simulated))


def _unknown_samples(ds: xr.Dataset, ok: np.ndarray, j: int, bound: np.ndarray) -> tuple[int, int, float]:
    """Block ``j``'s samples without a verdict and samples drawn, summed over the records ``ok``, and the largest
    over those records of :func:`p_with_unknown` (``bound``; NaN: not sampled)."""
    if SCENE.samples_without_verdict not in ds:
        return 0, 0, math.nan
    drawn, unknown = (np.maximum(np.where(ok, _col(ds, v)[:, j], 0), 0)
                      for v in (SCENE.samples_drawn, SCENE.samples_without_verdict))
    frac = np.where(ok, bound[:, j], np.nan)
    return int(unknown.sum()), int(drawn.sum()), float(np.nanmax(frac)) if np.isfinite(frac).any() else math.nan


def _verdict_words(sim: int, response: int, slide_m: float, undecided: int, n_stations: int,
                   unknown_samples: int) -> str:
    """The simulation's verdict under the governing record, in words; never "stands" alone where a station or a
    sample has no verdict."""
    words = VERDICT[sim] + (f" (slides {slide_m:.2g} m)" if response in SLIDING_RESPONSES and np.isfinite(slide_m)
                            and slide_m > 0 else "")
    if sim == 1:
        return words
    if sim < 0:
        words = "not judged"
    gaps = ([f"not judged on {undecided} of {n_stations} stations"] if undecided else []) + (
        [f"{unknown_samples} samples without a verdict"] if unknown_samples else [])
    return f"unknown: {words} under the governing record; " + "; ".join(gaps) if gaps else words


def _at_risk(natural: bool, remedy: str) -> str:
    """The action for an object at risk: ``remedy``, or a natural rock's (:data:`NATURAL_AT_RISK`)."""
    return NATURAL_AT_RISK if natural else remedy


def _natural(ds: xr.Dataset, j: int) -> bool:
    """The inventory says block ``j`` is a natural object (its ``object`` column: :data:`NATURAL`)."""
    name = INVENTORY_PREFIX + "object"
    return name in ds and str(_col(ds, name)[j]).strip().lower() == NATURAL


def _upper_floor(ds: xr.Dataset, j: int) -> bool:
    """Block ``j`` stands above the ground floor of a building."""
    return ("building" in ds and bool(str(_col(ds, "building")[j])) and "floor_height" in ds
            and float(_col(ds, "floor_height")[j]) > 0.0)


def _floor(ds: xr.Dataset, i: int | None, j: int) -> dict:
    """A block's building, floor height [m] and its floor's peak acceleration over the ground's under the governing
    record (empty and NaN on the ground)."""
    building = str(_col(ds, "building")[j]) if "building" in ds else ""
    ratio = math.nan
    if building and i is not None and SCENE.floor_pga in ds:
        ratio = float(_col(ds, SCENE.floor_pga)[i, j]) / float(_col(ds, "pga")[i])
    return {"building": building,
            "floor_height_m": float(_col(ds, "floor_height")[j]) if "floor_height" in ds else math.nan,
            "floor_pga_ratio": ratio}


def _stack(ds: xr.Dataset, j: int, i: int | None = None) -> dict:
    """The body block ``j`` stands on and its stack's bottom body ("" for a block that stands alone), and what the
    stack does under the record ``i`` in words (``stack_outcome``: "" without one)."""
    out = {name: str(_col(ds, name)[j]) if name in ds else "" for name in ("stands_on", "stack_id")}
    words = ""
    if out["stack_id"] and i is not None and "stack_overturn" in ds:
        anybody, collapse = int(_col(ds, "stack_overturn")[i, j]), int(_col(ds, "stack_collapse")[i, j])
        words = ("the whole stack falls" if collapse == 1 else "a body falls off, the bottom body stands"
                 if anybody == 1 and collapse == 0 else "every body stands" if anybody == 0
                 else "not every body has a verdict")
    slips = int(np.sum(_col(ds, SCENE.friction_exceeded)[:, j] == 1)) if out["stack_id"] else 0
    rule = str(_col(ds, "stack_rule")[j]) if out["stack_id"] and "stack_rule" in ds else ""
    failing = int(np.sum(_col(ds, "stack_fails")[:, j] == 1)) if rule else 0
    return {**out, "stack_outcome": words, "stack_slips": slips, **_stack_statics(ds, j, out["stack_id"]),
            "stack_rule": rule, "stack_rule_words": RULE_WORDS[StackRule[rule]] if rule else "",
            "stack_records_failing": failing}


def _stack_statics(ds: xr.Dataset, j: int, stack_id: str) -> dict:
    """Block ``j``'s stack at rest: where the joint under the block starts to open (``joint_opening_g``: the ground's
    horizontal acceleration in g without vertical shaking; NaN: not a stack's body), the body whose joint opens first
    (``stack_opens_first``: "" for none) and the report's drawing (``stack_drawing``, :func:`_drawing`; None)."""
    if not stack_id or "joint_opening" not in ds or "stack_base_height" not in ds:
        return {"joint_opening_g": math.nan, "stack_opens_first": "", "stack_drawing": None}
    opening = _col(ds, "joint_opening")
    rows = np.flatnonzero(_col(ds, "stack_id") == stack_id)
    first = rows[int(np.argmin(opening[rows]))]
    return {"joint_opening_g": float(opening[j]), "stack_opens_first": str(_col(ds, "block")[first]),
            "stack_drawing": _drawing(ds, stack_id)}


def _drawing(ds: xr.Dataset, stack_id: str) -> dict:
    """The stack at rest in its rocking plane as the report draws it (an SVG's coordinates: x to the right, y down,
    in metres; the bodies placed by ``stack_base_centre`` and ``stack_base_height``): ``bodies``, bottom first, each
    one's ``id``, ``x``, ``y`` (its top left corner), ``width`` and ``height``; ``view_box`` around them and the
    ground; ``font`` a label's size."""
    rows = np.flatnonzero(_col(ds, "stack_id") == stack_id)
    rows = rows[np.argsort(_col(ds, "stack_base_height")[rows])]          # bottom first
    bodies: list[dict] = []
    for k in rows:
        width, height = 2.0 * float(_col(ds, "half_width")[k]), 2.0 * float(_col(ds, "half_height")[k])
        base = float(_col(ds, "stack_base_height")[k])
        bodies.append({"id": str(_col(ds, "block")[k]), "x": float(_col(ds, "stack_base_centre")[k]) - 0.5 * width,
                       "y": -(base + height), "width": width, "height": height})
    z = -min(b["y"] for b in bodies)
    left = min(b["x"] for b in bodies)
    right = max(b["x"] + b["width"] for b in bodies)
    font = 0.06 * max(z, right - left)
    labels = 0.65 * font * max(len(b["id"]) for b in bodies)     # each body's id to its right
    return {"bodies": tuple(bodies), "font": font,
            "view_box": f"{left - font:.4g} {-z - font:.4g} {right - left + 2.5 * font + labels:.4g} "
                        f"{z + 2 * font:.4g}"}


def _probabilities(ds: xr.Dataset, ok: np.ndarray, j: int, stations: np.ndarray, governing: int | None) -> dict:
    """A block's probabilities of overturning: the largest over the records (with its interval, record and
    robustness class; the governing record when it reaches the largest, so that the two read together), the
    stations with p >= 0.5 and the sensitive scenes. NaN / 0 without sampling."""
    empty = {SCENE.p_overturn: np.nan, SCENE.p_overturn_low: np.nan, SCENE.p_overturn_high: np.nan, "p_record": "",
             SCENE.robustness: "", "stations_p_half": 0, "records_sensitive": 0, SCENE.p_overturn_azimuth: np.nan,
             SCENE.p_overturn_random_orientation: np.nan, "orientation_unknown": False, "p_words": ""}
    if SCENE.p_overturn not in ds:
        return empty
    p = np.where(ok, _col(ds, SCENE.p_overturn)[:, j], np.nan)
    if not np.isfinite(p).any():
        drawn = np.where(ok, _col(ds, SCENE.samples_drawn)[:, j], 0) if SCENE.samples_drawn in ds else np.zeros(1)
        if np.any(drawn > 0):          # sampled, but no sample had a verdict: p unknown, its interval [0, 1]
            bounds = (np.where(ok & (drawn > 0), _col(ds, v)[:, j], np.nan)
                      for v in (SCENE.p_overturn_low, SCENE.p_overturn_high))
            low, high = (float(np.nanmax(b)) for b in bounds)
            return {**empty, SCENE.p_overturn_low: low, SCENE.p_overturn_high: high,
                    SCENE.robustness: ROBUSTNESS_UNKNOWN, "p_words": "p unknown (no sample had a verdict)"}
        return empty
    i = int(np.nanargmax(p))
    if governing is not None and p[governing] == p[i]:
        i = governing
    robust = _col(ds, SCENE.robustness)[:, j]
    azimuth = float(_col(ds, SCENE.p_overturn_azimuth)[i, j]) if SCENE.p_overturn_azimuth in ds else math.nan
    random = float(_col(ds, SCENE.p_overturn_random_orientation)[i, j]) if SCENE.p_overturn_random_orientation in ds \
        else math.nan
    orientation = int(_col(ds, SCENE.orientation)[i, j])
    unknown = orientation in (Orientation.scanned, Orientation.scanned_relative)
    record = str(_col(ds, "record")[i])
    words = f"p = {p[i]:.2f} under {record}"
    given = "block_azimuth" in ds and np.isfinite(float(_col(ds, "block_azimuth")[j]))
    if unknown and np.isfinite(azimuth):
        if orientation == Orientation.scanned_relative:
            # the record's sensors have no known azimuth: a plane is known only relative to its first component
            words += (f" if it faces {azimuth:.0f} deg from the record's first component (its sensors' azimuth is "
                      f"unknown, so {'the given azimuth cannot be used and ' if given else ''}every orientation is "
                      f"scanned; orientation unknown: {random:.2f})")
        else:
            words += f" if it faces {azimuth:.0f} deg (orientation unknown: {random:.2f})"
    return {SCENE.p_overturn: float(p[i]), SCENE.p_overturn_low: float(_col(ds, SCENE.p_overturn_low)[i, j]),
            SCENE.p_overturn_high: float(_col(ds, SCENE.p_overturn_high)[i, j]), "p_record": record,
            SCENE.robustness: ROBUSTNESS_NAMES[int(robust[i])],
            "stations_p_half": len(set(stations[ok & (np.nan_to_num(p) >= 0.5)].tolist())),
            "records_sensitive": int(np.sum(ok & (robust == Robustness.sensitive))),
            SCENE.p_overturn_azimuth: azimuth, SCENE.p_overturn_random_orientation: random,
            "orientation_unknown": unknown,
            "p_words": words}


def _risk_key(r: dict) -> tuple:
    """An asset row's place in the ranking (:func:`asset_rows`), smallest first (NaN: not sampled, last)."""
    return (-np.nan_to_num(np.fmax(r[SCENE.p_overturn], r["p_overturn_with_unknown"]), nan=-1.0),
            -r["stations_p_half"], -(r["stations_overturning"] + r["stations_without_verdict"]),
            np.nan_to_num(r["overturn_scale_simulated"], nan=np.inf),
            np.nan_to_num(r["overturn_scale"], nan=np.inf), -np.nan_to_num(r[SCENE.theta_max], nan=-1.0))


def asset_rows(ds: xr.Dataset, *, station_of: dict[str, str] | None = None, criterion_only: bool = False
               ) -> list[dict]:
    """One row per block, ranked by risk: the largest probability of overturning over the records (with the
    samples without a verdict counted as overturning where that is larger), then the number of stations with
    p_overturn >= 0.5, then the most stations that overturn it (nominal) or have no verdict, the smallest simulated
    margin, the criterion's margin and the largest rotation.

    ``station_of`` maps a record to the record that stands for its station recording (records of one
    recording in several files count once); a record not in it is a station of its own. ``criterion_only``: the
    run judged by the paper's criterion alone (fidelity ``criterion``): no asset is cleared.
    """
    rows = []
    stations = np.array([(station_of or {}).get(r, r) for r in _col(ds, "record").tolist()], dtype=object)
    rec_pos = {r: i for i, r in enumerate(_col(ds, "record").tolist())}
    ok = _col(ds, "status") == "ok"
    verdict = _col(ds, "overturn") if "overturn" in ds else _col(ds, SCENE.overturn_simulated)
    record_ids = _col(ds, "record")
    extra = [str(n) for n in ds.data_vars if str(n).startswith(INVENTORY_PREFIX)]
    bound = p_with_unknown(ds)
    for j, block in enumerate(_col(ds, "block").tolist()):
        gov = str(_col(ds, "governing_record")[j]) if "governing_record" in ds else ""
        i = rec_pos.get(gov)

        def at(name, default=np.nan, i=i, j=j):
            return _col(ds, name)[i, j] if i is not None else default

        sim_scale = float(_col(ds, "overturn_scale_simulated")[j])
        crit_scale = float(_col(ds, "overturn_scale")[j])
        crit = int(at("overturn_criterion", -1))
        sim = int(at(SCENE.overturn_simulated, -1))
        response = int(at(SCENE.response, -1))
        slide = float(at(SCENE.sliding_max))
        overturning = [str(r) for r in record_ids[ok & (verdict[:, j] == 1)]]
        stations_over, undecided, n_stations = _station_counts(stations, ok, verdict[:, j])
        probabilities = _probabilities(ds, ok, j, stations, i)
        unknown = _unknown_samples(ds, ok, j, bound)
        if (undecided or unknown[0]) and probabilities[SCENE.robustness] == Robustness.robust_stand.name:
            probabilities[SCENE.robustness] = ROBUSTNESS_UNKNOWN
        below = int(_col(ds, "overturns_below_nominal")[j]) if "overturns_below_nominal" in ds else -1
        rows.append({
            "block": block, "block_name": str(_col(ds, "block_name")[j]), "site": str(_col(ds, "site")[j]),
            **_floor(ds, i, j), **_stack(ds, j, i),
            "height": float(_col(ds, "height")[j]), "width": float(_col(ds, "width")[j]),
            "corner_distance": float(_col(ds, "corner_distance")[j]),
            "slenderness": float(_col(ds, "slenderness")[j]),
            "alpha_deg": math.degrees(float(_col(ds, "slenderness")[j])),
            "frequency_parameter": float(_col(ds, "frequency_parameter")[j]), "mu": float(_col(ds, "mu")[j]),
            "records_overturning": len(overturning), "records_screened": int(ok.sum()),
            "stations_overturning": stations_over, "stations_screened": n_stations,
            "stations_without_verdict": undecided,
            "records_overturning_ids": ";".join(overturning),
            "governing_record": gov, SCENE.governing_azimuth: float(at(SCENE.governing_azimuth)),
            "verdict_criterion": VERDICT[crit] if not _stack(ds, j)["stack_id"] else STACK_CRITERION,
            "verdict_simulation": _verdict_words(sim, response, slide, undecided, n_stations, unknown[0]),
            SCENE.theta_max: float(at(SCENE.theta_max)), SCENE.response: RESPONSE_NAMES[response],
            SCENE.physics: PHYSICS_NAMES[int(at(SCENE.physics, -1))],
            "overturn_scale": crit_scale, "overturn_scale_simulated": sim_scale, "overturns_below_nominal": below,
            "p_overturn_governing": float(_col(ds, "p_overturn_governing")[j]) if "p_overturn_governing" in ds
            else np.nan,
            "overturn_scale_median": float(_col(ds, "overturn_scale_median")[j]) if "overturn_scale_median" in ds
            else np.nan,
            "recommendation": recommendation(sim_scale=sim_scale, crit_overturns=crit == 1, response=response,
                                             overturned=sim == 1, p_max=probabilities[SCENE.p_overturn],
                                             p_record=probabilities["p_record"], governing=gov or "the records",
                                             stations=(stations_over, n_stations),
                                             p_words=probabilities["p_words"], slide_m=slide,
                                             undecided=undecided, failed=int((~ok).sum()),
                                             undecided_why=undecided_causes(ds, ok & (verdict[:, j] < 0), j),
                                             unknown_draws=unknown[:2], p_with_unknown=unknown[2],
                                             criterion_only=criterion_only, natural=_natural(ds, j),
                                             upper_floor=_upper_floor(ds, j)),
            "draws_without_verdict": unknown[0], "draws": unknown[1], "p_overturn_with_unknown": unknown[2],
            "inventory": {name[len(INVENTORY_PREFIX):]: str(_col(ds, name)[j]) for name in extra},
            **probabilities,
        })

    rows.sort(key=_risk_key)
    for k, r in enumerate(rows, 1):
        r["rank"] = k
    return rows


#: assets.csv's header of a column whose number has a unit: the unit in the name, as the console and the report
#: print it (the others are dimensionless, counts, names or words)
ASSETS_CSV_HEADERS = {"height": "height_m", "width": "width_m", "slenderness": "slenderness_rad",
                      "frequency_parameter": "frequency_parameter_rad_s",
                      SCENE.p_overturn_azimuth: "p_overturn_azimuth_deg", SCENE.governing_azimuth:
                      "governing_azimuth_deg", SCENE.theta_max: "theta_max_over_alpha"}


def assets_csv_table(rows: list[dict]) -> tuple[tuple[str, ...], list[dict]]:
    """The columns and rows of ``assets.csv``: the per-asset table (numbers unrounded, inf for 'none up to the
    scan limit'; a header with a unit has it in its name, :data:`ASSETS_CSV_HEADERS`), then the extra inventory
    columns as given."""
    extra = list(rows[0]["inventory"]) if rows else []
    header = tuple(ASSETS_CSV_HEADERS.get(c, c) for c in ASSETS_CSV_COLUMNS)
    return header + tuple(extra), [{**{ASSETS_CSV_HEADERS.get(c, c): r[c] for c in ASSETS_CSV_COLUMNS},
                                    **r["inventory"]} for r in rows]
