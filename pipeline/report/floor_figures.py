"""The report's figures of floor motion: for each asset on an upper floor of a building, its floor's velocity
under the governing record beside the ground's, from ``pulses.nc`` (the ground's series, and the group
``floors``). One figure per (record, building, floor height): the assets on one floor share it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ..store import FLOOR_GROUP, ragged_rows
from . import figures


def _series(ds: xr.Dataset, id_name: str) -> dict[str, tuple[slice, float]]:
    """Series id -> (its samples, its interval [s])."""
    dts = ds["dt"].values
    return {sid: (rows, float(dts[k])) for k, (sid, rows) in enumerate(ragged_rows(ds, id_name).items())}


def floor_figures(assets: list[dict], ground: xr.Dataset | None, pulses_path: Path, draw) -> list[dict]:
    """Set ``floor_anchor`` on each asset row on an upper floor whose floor motion under its governing record is
    in ``pulses_path`` ("" otherwise), and return the figures, one per (record, building, floor height):
    ``{"anchor", "record", "building", "floor_height_m", "blocks", "uri"}``.

    ``ground`` is the file's ground group, already open (the report's); ``draw(kind, make, *arrays, title)``
    turns a drawing into a data URI (the report's figure cache).
    """
    for r in assets:
        r["floor_anchor"] = ""
    on_floors = [r for r in assets if r.get("building") and r.get("floor_height_m", 0) > 0]
    if not on_floors or ground is None:
        return []
    try:
        floors = xr.open_dataset(pulses_path, engine="netcdf4", group=FLOOR_GROUP)
    except OSError:                       # a run without blocks on floors, or an older file
        return []
    out: dict[tuple, dict] = {}
    with floors:
        where_floor = {(str(rid), str(b), float(z)): sid for rid, b, z, sid in zip(
            floors["record_id"].values, floors["building"].values, floors["floor_height"].values,
            floors["series_id"].values)}
        floor_rows, ground_rows = _series(floors, "series_id"), _series(ground, "record_id")
        for r in on_floors:
            key = (r["governing_record"], r["building"], float(r["floor_height_m"]))
            sid = where_floor.get(key)
            if sid is None or key[0] not in ground_rows:
                continue
            if key not in out:
                rows, dt = floor_rows[sid]
                g = np.asarray(ground["velocity"][ground_rows[key[0]][0]].values, dtype=float)
                f = np.asarray(floors["velocity"][rows].values, dtype=float)
                p = np.asarray(floors["pulse"][rows].values, dtype=float)
                title = f"{key[1]}, floor at {key[2]:g} m, under {key[0]}"
                out[key] = {"anchor": f"floor-{len(out) + 1}", "record": key[0], "building": key[1],
                            "floor_height_m": key[2], "blocks": [],
                            "uri": draw("floor", lambda g=g, f=f, p=p, dt=dt, title=title: figures.floor_figure(
                                g, f, p, dt, title=title), g, f, p, np.array([dt]), title=title)}
            out[key]["blocks"].append(r["block"])
            r["floor_anchor"] = out[key]["anchor"]
    return list(out.values())
