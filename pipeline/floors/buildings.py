"""Buildings as the user gives them, and where each block stands in one.

``buildings.csv``: ``id,period_s,damping,stiffness_ratio,height_m[,n_stories]`` (fundamental period [s], modal
damping ratio, lateral-stiffness ratio alpha of the shear-flexural model, height [m], storeys). The inventory
places a block with its ``building`` column and its height above the building's base, ``floor_height_m``, or
its ``floor`` number (0 the ground floor) times the storey height height_m / n_stories. A block with no
building stands on the ground, as before.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import NamedTuple, Protocol

import numpy as np

from ..errors import InventoryError
from ..tables import parse_number, read_csv_table
from .motion import Building

#: Columns of buildings.csv.
REQUIRED = ("id", "period_s", "damping", "stiffness_ratio", "height_m")
OPTIONAL = ("n_stories",)


def read_buildings(path: str | Path) -> dict[str, Building]:
    """Read and check ``buildings.csv``; every bad cell is reported at once.

    Raises
    ------
    InventoryError
        Naming the file, and for each problem the line and column, what was found and what is expected.
    """
    path = Path(path)
    errors: list[str] = []
    _, records = read_csv_table(path, what="buildings", expected_header=",".join(REQUIRED) + "[,n_stories]",
                                problems=errors, required=REQUIRED)
    rules = {"period_s": ("a fundamental period in seconds, > 0 (about 0.1 s per storey)", lambda x: x > 0),
             "damping": ("a damping ratio in [0, 1), e.g. 0.05", lambda x: 0 <= x < 1),
             "stiffness_ratio": ("a lateral-stiffness ratio alpha >= 0 (0-2 walls, 1.5-6 dual systems, 5-20 "
                                 "frames)", lambda x: x >= 0),
             "height_m": ("a height in metres, > 0", lambda x: x > 0),
             "n_stories": ("a whole number of storeys >= 1", lambda x: x >= 1 and float(x).is_integer())}
    out: dict[str, Building] = {}
    for _line, where, rec in records:
        bid = rec.get("id", "")
        if not bid:
            errors.append(f"{where}, column 'id': empty; every building needs an id")
            continue
        if bid in out:
            errors.append(f"{where}, column 'id': duplicate id {bid!r}")
            continue
        values = {}
        for col, (rule, ok) in rules.items():
            raw = rec.get(col, "")
            if col == "n_stories" and not raw:
                values[col] = 0.0
                continue
            try:
                values[col] = parse_number(raw, where=where, column=col, rule=rule, ok=ok)
            except InventoryError as exc:
                errors.append(str(exc))
                values[col] = math.nan
        stories = values["n_stories"]
        out[bid] = Building(bid, values["period_s"], values["damping"], values["stiffness_ratio"],
                            values["height_m"], 0 if math.isnan(stories) else int(stories))
    if errors:
        raise InventoryError(f"{path}: {len(errors)} problem(s):\n  " + "\n  ".join(errors))
    if not out:
        raise InventoryError(f"{path}: no buildings; add at least one row under the header")
    return out


class Placement(NamedTuple):
    """Where a block stands: its building (None: on the ground) and its height above the building's base [m]."""

    building: Building | None
    height_m: float


class Placed(Protocol):
    """What placing blocks reads of an inventory (:class:`pipeline.blocks.Inventory` is one)."""

    @property
    def ids(self) -> tuple: ...

    @property
    def source(self) -> str: ...

    @property
    def extra(self) -> dict: ...

    def buildings(self) -> tuple: ...

    def floor_heights(self) -> np.ndarray: ...


def place_blocks(inventory: Placed, buildings: dict[str, Building]) -> list[Placement]:
    """Each block's building and floor height (the module's rules).

    Raises
    ------
    InventoryError
        For a block naming a building that is not in ``buildings``, with neither ``floor_height_m`` nor a
        ``floor`` number (or a ``floor`` number and no ``n_stories``), or a floor above the roof; all at once.
    """
    errors: list[str] = []
    floors: tuple = inventory.extra.get("floor", ("",) * len(inventory.ids))
    out = []
    for j, bid in enumerate(inventory.ids):
        name = inventory.buildings()[j]
        if not name:
            out.append(Placement(None, 0.0))
            continue
        b = buildings.get(name)
        if b is None:
            known = ", ".join(sorted(buildings)) or "none (give --buildings FILE)"
            errors.append(f"block {bid}: building {name!r} is not in the buildings file; buildings: {known}")
            out.append(Placement(None, 0.0))
            continue
        z = float(inventory.floor_heights()[j])
        if math.isnan(z):
            level: int | None
            try:
                level = int(str(floors[j]).strip())
            except ValueError:
                level = None
            if level is None or b.n_stories < 1:
                errors.append(f"block {bid}: in building {name!r} but no floor_height_m"
                              + ("" if level is None else f", and floor {level} needs the building's n_stories")
                              + "; give floor_height_m (metres above the building's base) or a floor number with "
                                "n_stories in the buildings file")
                out.append(Placement(None, 0.0))
                continue
            z = level * b.height_m / b.n_stories
        if not (0.0 <= z <= b.height_m * (1 + 1e-9)):
            errors.append(f"block {bid}: floor at {z:g} m is outside building {name!r} (0-{b.height_m:g} m)")
            out.append(Placement(None, 0.0))
            continue
        out.append(Placement(b, z))
    if errors:
        raise InventoryError(f"{inventory.source}: {len(errors)} problem(s) placing blocks in buildings:\n  "
                             + "\n  ".join(errors))
    return out


def floor_groups(placements: list[Placement]) -> dict[tuple, np.ndarray]:
    """Block indices per floor: key (building id, height [m]), or ``()`` for the blocks on the ground (including
    those on a building's ground floor, z = 0, whose motion is the ground's)."""
    groups: dict[tuple, list[int]] = {}
    for j, p in enumerate(placements):
        key = () if p.building is None or p.height_m == 0.0 else (p.building.building_id, float(p.height_m))
        groups.setdefault(key, []).append(j)
    return {k: np.array(v, dtype=int) for k, v in groups.items()}
