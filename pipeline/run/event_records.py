"""``screen event --records DIR``: the event's own station records, screened directly on the assets near them.

Each record whose files (or StationXML) give its station's coordinates (:mod:`pipeline.records.coordinates`) is
matched to the assets within ``[event] station_radius_km`` of it, the nearest station first. Those assets are
screened on the whole directory by the main job (:func:`pipeline.run.stages.screen`, into ``OUT/records/``: its
own report, cache and re-runs), and each asset's probability of overturning under its nearest station's record
is read back: the physics of the recorded motion, beside the ShakeMap's estimate from a fragility.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from ..blocks import Inventory
from ..config import Config
from ..errors import RockscreenError
from ..records.coordinates import distance_km
from ..records.listing import find_records
from ..records.loader import station_of
from ..records.side_files import read_inventory
from ..scene_table import SCENE
from .stages import ScreenRequest, screen


@dataclass
class NearRecords:
    """Per asset: the nearest located station's record within the radius ("" none), its distance [km] and the
    probability of overturning under it (NaN: none); what was said on the way."""

    record: np.ndarray
    distance_km: np.ndarray
    p: np.ndarray
    notes: list[str] = field(default_factory=list)
    screening: Path | None = None


def _locate(records_dir: Path, config: Config, stationxml: Path | None) -> tuple[list[tuple], list[str]]:
    """(record id, lon, lat, where read) of every record whose headers (or StationXML) say where its station is,
    read from the headers alone; notes on the others."""
    sources, failures = find_records(records_dir, config=config)
    inventory = read_inventory(records_dir, stationxml)
    located, unlocated, notes = [], [], [f"record {f.record_id}: not used ({f.reason})" for f in failures]
    for src in sources:
        try:
            station = station_of(src, inventory)
        except RockscreenError as exc:
            notes.append(f"record {src.record_id}: not used ({exc})")
            continue
        if station is None:
            unlocated.append(src.record_id)
        else:
            located.append((src.record_id, station.lon, station.lat, station.source))
    if unlocated:
        notes.append(f"{len(unlocated)} record(s) say nowhere where their station is (PEER .AT2 and near-fault ASCII "
                     f"files carry no coordinates; MiniSEED needs its StationXML): {', '.join(unlocated[:8])}"
                     f"{' ...' if len(unlocated) > 8 else ''}; they are matched to no asset")
    return located, notes


def near_records(records_dir: Path, inv: Inventory, lon: np.ndarray, lat: np.ndarray, *, config: Config,
                 out_dir: Path, n_workers: int = 1, stationxml: Path | None = None, progress=None,
                 command: tuple = ()) -> NearRecords:
    """The event's records screened on the assets within ``[event] station_radius_km`` of their station (the
    module's steps).

    Raises
    ------
    RockscreenError
        For a records directory the main job refuses (named, with the fix).
    """
    n = len(inv)
    out = NearRecords(np.full(n, "", dtype=object), np.full(n, math.nan), np.full(n, math.nan))
    located, out.notes = _locate(Path(records_dir), config, stationxml)
    radius = config.event.station_radius_km
    for rid, slon, slat, _ in located:
        d = distance_km(lon, lat, slon, slat)
        closer = (d <= radius) & ~(d >= out.distance_km)
        out.record[closer], out.distance_km[closer] = rid, d[closer]
    near = np.flatnonzero(out.record != "")
    out.notes.append(f"{len(located)} located station record(s); {near.size} asset(s) within {radius:g} km of one "
                     "([event] station_radius_km)")
    if near.size == 0:
        return out
    result = screen(ScreenRequest(records_dir=Path(records_dir), blocks_csv=Path(inv.source),
                                  inventory=inv.take(near), config=config, out_dir=Path(out_dir) / "records",
                                  stationxml=stationxml, n_workers=n_workers, command=list(command)),
                    progress=progress)
    out.screening = result.screening_path
    with xr.open_dataset(result.screening_path) as ds:
        records, blocks = list(ds["record"].values), list(ds["block"].values)
        for k in near:
            rid, bid = str(out.record[k]), inv.ids[k]
            if rid not in records or bid not in blocks:
                out.notes.append(f"asset {bid}: record {rid} has no result in {result.screening_path}")
                continue
            i, j = records.index(rid), blocks.index(bid)
            p = float(ds[SCENE.p_overturn].values[i, j])
            if math.isnan(p):                              # --samples 0: the nominal verdict
                verdict = int(ds[SCENE.overturn_simulated].values[i, j])
                p = float(verdict) if verdict >= 0 else math.nan
            out.p[k] = p
    return out
