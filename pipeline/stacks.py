"""Assemblies in the block inventory: bodies that stand on other bodies (a statue on its plinth, a drum on a drum).

A row whose ``stands_on`` names another row's id stands on that body instead of on the ground (or its floor);
``offset_m`` places its base's centre from the centre of the body's top, in the rocking plane [m] (blank: 0). The
rows so linked form a stack, bottom first, judged together (:mod:`pipeline.bodies.assembly`): each row keeps its own
verdict. Each body's mass is its ``mass_kg``, else its ``density_kg_m3`` (blank: the same for every body of the
stack) times its volume, width x height x depth (``depth_m``; blank: its width, a square plan): only the bodies'
ratios of mass enter the motion.

The stack's model is planar (:mod:`pipeline.assemblies.two_block` for two bodies, :mod:`pipeline.assemblies.n_block`
for more): every body a box in the one rocking plane, so
the bodies of a stack share their ``azimuth_deg``, ``building`` and ``floor_height_m``; a stack holds at most
:data:`MAX_BODIES` bodies, each carrying at most one; and a stack that cannot stand at rest (the centre of mass of the
part above an interface outside its support) is an error (:func:`pipeline.assemblies.stack.interfaces`).
"""

from __future__ import annotations

import enum
import logging
import math

import numpy as np

from .assemblies.n_block import MAX_BODIES as N_BLOCK_MAX
from .assemblies.stack import StackBody, StackPlace, interfaces, opening_ratio, placements
from .errors import BlockParameterError
from .rocking.block import ShapeKind
from .tables import parse_number

log = logging.getLogger(__name__)

#: The most bodies a stack may hold (the planar n-block model's, :mod:`pipeline.assemblies.n_block`)
MAX_BODIES = N_BLOCK_MAX
#: The inventory's columns for stacks
COLUMNS = ("stands_on", "offset_m", "stack_verdict")


class StackRule(enum.IntEnum):
    """What fails a stack as a whole (inventory column ``stack_verdict``, on any of its rows; blank: ``any``)."""

    #: any body falls
    any = 0
    #: the top body falls
    top = 1
    #: the bottom body falls, so that nothing stands
    collapse = 2


#: Each rule in words, as the report says it
RULE_WORDS = {StackRule.any: "a body falls", StackRule.top: "the top body falls",
              StackRule.collapse: "the whole stack falls"}


def read_stack_cells(rec: dict, where: str, rows: dict[str, list], errors: list[str]) -> None:
    """Append a row's ``stands_on`` (stripped; blank: ""), ``stack_verdict`` (blank: "") and ``offset_m`` (blank: 0)
    to ``rows``, a bad rule's or offset's problem to ``errors``."""
    rows["stands_on"].append(rec.get("stands_on", "").strip())
    rule = rec.get("stack_verdict", "").strip()
    rows["stack_verdict"].append(rule)
    if rule and rule not in StackRule.__members__:
        errors.append(f"{where}, column 'stack_verdict': {rule!r} is not a rule; use "
                      f"{', '.join(StackRule.__members__)} (what fails the stack: a body falls, the top body falls, "
                      "the whole stack falls; blank: any)")
    cell = rec.get("offset_m", "")
    if not cell:
        rows["offset_m"].append(0.0)
        return
    try:
        rows["offset_m"].append(parse_number(cell, where=where, column="offset_m", rule="a distance in metres "
                                             "(blank: 0, the body centred on the one below)", ok=math.isfinite))
    except ValueError as exc:
        errors.append(str(exc))
        rows["offset_m"].append(0.0)
    if not rows["stands_on"][-1] and rows["offset_m"][-1] != 0.0:
        errors.append(f"{where}, column 'offset_m': {cell!r} on a row that stands on no body; an offset places a "
                      "body on the one it stands on (fill stands_on, or leave offset_m blank)")


def build_stacks(rows: dict[str, list], lines: list[str], errors: list[str]) -> tuple:
    """Each row's :class:`~pipeline.assemblies.stack.StackPlace` (None for a row in no stack), every problem added
    to ``errors`` with its line (``lines[k]``: row k's ``"<path>, line <n>"``).

    ``rows`` holds the inventory's columns, one entry per row (``id``, ``stands_on``, ``offset_m``, sizes, ``mu``,
    ``azimuth_deg``, ``shape``, ``scan``, ``depth_m``, ``density_kg_m3``, ``mass_kg``, ``building``,
    ``floor_height_m``).
    """
    ids = rows["id"]
    index = {b: k for k, b in enumerate(ids)}
    below = rows["stands_on"]
    above: dict[int, int] = {}
    for k, name in enumerate(below):
        if not name:
            continue
        if name not in index:
            errors.append(f"{lines[k]}, column 'stands_on': {name!r} is not the id of a row; name the body this one "
                          "stands on (blank: the ground)")
        elif index[name] == k:
            errors.append(f"{lines[k]}, column 'stands_on': the row stands on itself; name the body below it")
        elif index[name] in above:
            errors.append(f"{lines[k]}, column 'stands_on': {name!r} already carries {ids[above[index[name]]]!r}; "
                          "a body carries at most one body (a stack, bottom first)")
        else:
            above[index[name]] = k
    if errors:
        return ()
    places: list[StackPlace | None] = [None] * len(ids)
    placed: set[int] = set()
    for bottom in (k for k in range(len(ids)) if not below[k] and k in above):
        chain = [bottom]
        while chain[-1] in above:               # each body carries at most one: the chain ends
            chain.append(above[chain[-1]])
        placed.update(chain)
        place = _stack(chain, rows, lines, errors)
        for j, k in enumerate(chain):
            places[k] = None if place is None else place._replace(position=j)
    for k in range(len(ids)):
        if rows["stack_verdict"][k] and k not in placed:
            errors.append(f"{lines[k]}, column 'stack_verdict': {rows['stack_verdict'][k]!r} on a row in no stack; the "
                          "rule judges a stack as a whole (fill stands_on, or leave stack_verdict blank)")
        if below[k] and k not in placed:
            errors.append(f"{lines[k]}, column 'stands_on': the bodies it stands on stand on each other in a loop; "
                          "the bottom body of a stack stands on the ground (blank stands_on)")
    return tuple(places) if any(p is not None for p in places) else ()


def _stack(chain: list[int], rows: dict[str, list], lines: list[str], errors: list[str]) -> StackPlace | None:
    """The stack of the rows ``chain`` (bottom first), or None with its problems added to ``errors``."""
    ids = tuple(rows["id"][k] for k in chain)
    where = lines[chain[0]]
    before = len(errors)
    if len(chain) > MAX_BODIES:
        errors.append(f"{where}: the stack {' < '.join(reversed(ids))} has {len(chain)} bodies; the assembly model "
                      f"takes stacks of at most {MAX_BODIES} bodies in a plane; screen the bodies above the "
                      f"{MAX_BODIES}th as their own stack, or join two bodies into one block")
    for k in chain:
        if rows["shape"][k] != int(ShapeKind.box) or rows["scan"][k] is not None:
            errors.append(f"{lines[k]}: a body of the stack {ids} is a cylinder or a scan; the assembly model takes "
                          "boxes in a plane (height_m, width_m in the rocking plane): leave shape and mesh blank")
        for column, same in (("azimuth_deg", _same_number), ("building", str.__eq__),
                             ("floor_height_m", _same_number), ("floor", str.__eq__)):
            if column not in rows:
                continue
            if not same(rows[column][k], rows[column][chain[0]]):
                errors.append(f"{lines[k]}, column {column!r}: {rows[column][k]!r} differs from the bottom body "
                              f"{ids[0]!r}'s {rows[column][chain[0]]!r}; a stack's bodies share their rocking plane "
                              "and what they stand on: give every body of the stack the same value")
    rules = {rows["stack_verdict"][k] for k in chain} - {""}
    if len(rules) > 1:
        errors.append(f"{where}, column 'stack_verdict': the stack {' < '.join(reversed(ids))} is given the rules "
                      f"{sorted(rules)}; a stack has one: give it on one body, or the same on every body")
    if len(errors) > before:
        return None
    given = [ids[j] for j, k in enumerate(chain) if math.isfinite(rows["restitution"][k])]
    if given:
        log.warning("%s: restitution given for %s, bodies of a stack: not used (a stack's impacts lose what its impact "
                    "law loses: Housner's for a body rocking alone); leave it blank", where, ", ".join(given))
    bodies = tuple(StackBody(width_m=float(rows["width_m"][k]), height_m=float(rows["height_m"][k]),
                             mass_kg=_mass(rows, k, chain), mu=float(rows["mu"][k]),
                             offset_m=float(rows["offset_m"][k])) for k in chain)
    try:
        interfaces(bodies, label=f"{where} (stack {' < '.join(reversed(ids))})")
    except BlockParameterError as exc:
        errors.append(str(exc))
        return None
    return StackPlace(bodies, 0, ids, int(StackRule[rules.pop()]) if rules else int(StackRule.any))


def _same_number(a: float, b: float) -> bool:
    """Equal, or both blank (NaN)."""
    return (math.isnan(a) and math.isnan(b)) or a == b


def _mass(rows: dict[str, list], k: int, chain: list[int]) -> float:
    """Body ``k``'s mass [kg]: its ``mass_kg``, else its density times its volume (depth blank: its width); a blank
    density is the first density given in the stack ``chain`` (none given: 1, every body the same)."""
    if math.isfinite(rows["mass_kg"][k]):
        return float(rows["mass_kg"][k])
    given = [rows["density_kg_m3"][j] for j in chain if math.isfinite(rows["density_kg_m3"][j])]
    density = rows["density_kg_m3"][k] if math.isfinite(rows["density_kg_m3"][k]) else (given[0] if given else 1.0)
    depth = rows["depth_m"][k] if math.isfinite(rows["depth_m"][k]) else rows["width_m"][k]
    return float(density * rows["width_m"][k] * rows["height_m"][k] * depth)


def stack_ids(places: tuple, n: int) -> np.ndarray:
    """Each of the ``n`` rows' stack as the id of its bottom body ("" for a row in no stack; ``places`` empty: no
    row is)."""
    return np.array(["" if not places or places[k] is None else places[k].ids[0] for k in range(n)], dtype=object)


def stands_on_ids(places: tuple, n: int) -> np.ndarray:
    """The id of the body each of the ``n`` rows stands on ("" on the ground or its floor)."""
    return np.array(["" if not places or places[k] is None or places[k].position == 0
                     else places[k].ids[places[k].position - 1] for k in range(n)], dtype=object)


def _per_row(places: tuple, n: int, value) -> np.ndarray:
    """``value(place)`` for each of the ``n`` rows in a stack (its :class:`~.assemblies.stack.StackPlace`), NaN for a
    row in no stack."""
    out = np.full(n, np.nan)
    for k in range(n):
        place = places[k] if places else None
        if place is not None:
            out[k] = value(place)
    return out


def stack_placements(places: tuple, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Each of the ``n`` rows' base centre and base height in its stack at rest (:func:`~.assemblies.stack.placements`;
    NaN for a row in no stack) [m]."""
    return (_per_row(places, n, lambda p: placements(p.bodies)[0][p.position]),
            _per_row(places, n, lambda p: placements(p.bodies)[1][p.position]))


def joint_openings(places: tuple, n: int) -> np.ndarray:
    """The ground's |a_h| / (g + a_v) at which the joint under each of the ``n`` rows starts to open at rest, the
    bodies above with it (:func:`~.assemblies.stack.opening_ratio`; NaN for a row in no stack) [-]."""
    return _per_row(places, n, lambda p: opening_ratio(interfaces(p.bodies, label=p.ids[0])[p.position]))


def stack_verdicts(overturn: np.ndarray, places: tuple) -> dict[str, tuple]:
    """Each stack's verdicts under each record, on every row of its bodies, from the bodies' ``overturn`` (records x
    rows: 1 overturns, 0 stands, -1 no verdict): ``stack_overturn``, any body falls (1 where one does; -1 where none
    does and one has no verdict), and ``stack_collapse``, the bottom body falls, so that nothing stands. -1 for a row
    in no stack; and ``stack_fails``, the verdict of the stack's own rule (:class:`StackRule`: any body, the top body,
    the bottom body), with the rule on each row (``stack_rule``, "" for a row in no stack)."""
    n_records, n = overturn.shape
    anybody = np.full((n_records, n), -1, dtype="i1")
    collapse = np.full((n_records, n), -1, dtype="i1")
    fails = np.full((n_records, n), -1, dtype="i1")
    rule_names = np.full(n, "", dtype=object)
    ids = stack_ids(places, n)
    for bottom in {b for b in ids if b}:
        rows = np.flatnonzero(ids == bottom)
        v = overturn[:, rows]
        anybody[:, rows] = np.where((v == 1).any(axis=1), 1, np.where((v < 0).any(axis=1), -1, 0))[:, None]
        positions = [places[k].position for k in rows]
        collapse[:, rows] = overturn[:, rows[positions.index(0)]][:, None]
        rule = StackRule(places[rows[0]].rule)
        top = overturn[:, rows[positions.index(max(positions))]]
        fails[:, rows] = {StackRule.any: anybody[:, rows[0]], StackRule.top: top,
                          StackRule.collapse: collapse[:, rows[0]]}[rule][:, None]
        rule_names[rows] = rule.name
    return {"stack_overturn": (("record", "block"), anybody), "stack_collapse": (("record", "block"), collapse),
            "stack_fails": (("record", "block"), fails), "stack_rule": (("block",), rule_names)}
