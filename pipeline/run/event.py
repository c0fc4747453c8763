"""``screen event``: after an earthquake, every asset's probability of overturning from the event's ShakeMap and the
fragilities ``screen fragility`` fitted, ranked into an inspection list.

grid.xml (+ uncertainty.xml) -> the shaking at each asset's site (bilinear in ln IM, the ShakeMap field of the
fragility's IM) -> P(overturn | event) (:mod:`pipeline.event.assets`) -> event.nc, inspection.csv, event.html and
shakecast-facilities.xml, published together. A newer ShakeMap version of the same event replaces the results and
lists the assets whose level changed; an older one never overwrites a newer.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from ..blocks import Inventory
from ..config import Config
from ..errors import OutputError, RockscreenError
from ..event.advice import advice_at, is_scenario, natural_rocks
from ..event.assets import Basis, Fragilities, Level, event_risk, levels
from ..event.shakecast import Facility, facility_xml, onset_level, overturning_level
from ..event.shakemap import PSA_PERIODS, ShakeMapGrid, field_for, read_grid, sites_shaking
from ..records.coordinates import distance_km
from ..records.intensity import display_unit
from ..rocking.geometry import ALPHA_MAX_ROCKING
from ..schema import EVENT, apply_schema
from ..store import (
    Family,
    OutputLock,
    publish_staged,
    write_atomic,
    write_csv_atomic,
    write_text_atomic,
)
from ..tables import read_csv_table
from ..uncertainty.fragility import FitStatus

#: The files ``screen event`` writes, published together
OUTPUTS = ("event.nc", "inspection.csv", "event.html", "shakecast-facilities.xml")
#: The IMs of a fragility that a ShakeMap gives (as fields PGA, PGV, PSA..)
SHAKEMAP_IMS = ("pga", "pgv", "sa")
#: Columns of inspection.csv; ``{unit}`` is the unit of the shaking and the fragility median
INSPECTION_COLUMNS = ("priority", "block", "name", "site", "lon", "lat", "level", "recommendation", "sliding_risk",
                      "p_overturn_event",
                      "p_overturn_event_low", "p_overturn_event_high", "basis", "shakemap_field",
                      "shaking_median_{unit}", "shaking_log_sd", "log_sd_source", "fragility_median_{unit}",
                      "fragility_beta", "fit_status", "epicentral_distance_km", "station_record",
                      "station_distance_km", "p_overturn_record", "governed_by", "level_previous", "level_changed")
LOG_SD_SOURCES = ("grid", "uncertainty", "default")
#: The variables of fragility.nc an event reads
FRAGILITY_READ = ("median", "beta", "median_low", "median_high", "fit_status", "beta_im", "median_unjudged_overturn",
                  "beta_unjudged_overturn", "n_unjudged", "n_sliding")


class EventError(RockscreenError, ValueError):
    """Inputs of ``screen event`` that do not fit together (the message says which and the fix)."""


@dataclass(frozen=True)
class EventRequest:
    """What ``screen event`` is asked (paths as given)."""

    shakemap: Path
    inventory: Inventory
    fragility_dir: Path
    out_dir: Path
    config: Config
    uncertainty: Path | None = None
    sites: Path | None = None
    k_sigma: float = 0.0
    #: factor from the ShakeMap's component to the fragility's (None: they must be the same)
    shakemap_scale: float | None = None
    #: the event's station records (None: none), their StationXML, and the workers that screen them
    records: Path | None = None
    stationxml: Path | None = None
    n_workers: int = 1
    command: tuple = ()


@dataclass
class EventResult:
    """What the run did: its outputs, warnings, the assets whose level changed, its timings."""

    paths: list[Path]
    dataset: xr.Dataset
    warnings: list[str] = field(default_factory=list)
    changed: list[tuple[str, str, str]] = field(default_factory=list)
    replaced_version: str = ""
    seconds: float = 0.0


def open_fragility(directory: Path) -> xr.Dataset:
    """The fits of the ``fragility.nc`` of a ``screen fragility`` output directory (:data:`FRAGILITY_READ`, with
    its coordinates and attributes; loaded, the file closed).

    Raises
    ------
    EventError
        When there is none.
    """
    path = Path(directory) / "fragility.nc"
    if not path.is_file():
        raise EventError(f"{path}: no fragility.nc; --fragility is the --out directory of a 'screen fragility' run "
                         "on the same inventory (run it first)")
    with xr.open_dataset(path) as ds:
        # the fits, not the stripes (scale factors and outcomes per record, level and block: most of the file)
        return ds[[n for n in FRAGILITY_READ if n in ds]].assign_coords(im_level=ds["im_level"]).load()


def coordinates(inv: Inventory, sites: Path | None) -> tuple[np.ndarray, np.ndarray]:
    """Each asset's (lon, lat) [deg]: the inventory's ``lon`` and ``lat`` columns, else the sites table's row of its
    ``site``.

    Raises
    ------
    EventError
        For an asset without coordinates or with values that are not degrees (named, with the fix).
    """
    table: dict[str, tuple[str, str]] = {}
    if sites is not None:
        _, rows = read_csv_table(Path(sites), what="sites", expected_header="site,lon,lat",
                                 required=("site", "lon", "lat"))
        table = {row["site"]: (row["lon"], row["lat"]) for _, _, row in rows}
    lons, lats = inv.extra.get("lon", ("",) * len(inv)), inv.extra.get("lat", ("",) * len(inv))
    out_lon, out_lat, errors = [], [], []
    for k, bid in enumerate(inv.ids):
        lon_s, lat_s = lons[k].strip(), lats[k].strip()
        if not (lon_s and lat_s) and inv.sites[k] in table:
            lon_s, lat_s = table[inv.sites[k]]
        try:
            lon, lat = float(lon_s), float(lat_s)
        except ValueError:
            errors.append(f"{bid}: lon {lon_s!r}, lat {lat_s!r}")
            lon = lat = math.nan
        if not (-180.0 <= lon <= 360.0 and -90.0 <= lat <= 90.0):
            if math.isfinite(lon):
                errors.append(f"{bid}: lon {lon}, lat {lat} are not degrees of longitude and latitude")
        out_lon.append(lon if lon <= 180.0 else lon - 360.0)
        out_lat.append(lat)
    if errors:
        raise EventError(f"{inv.source}: {len(errors)} asset(s) without a location: {'; '.join(errors[:10])}"
                         f"{' ...' if len(errors) > 10 else ''}. Give lon and lat columns (decimal degrees) in the "
                         "inventory, or --sites with columns site,lon,lat for the assets' site")
    return np.array(out_lon), np.array(out_lat)


def _check_component(frag: xr.Dataset, req: EventRequest) -> str:
    """The component definitions of the ShakeMap and the fit must match, or a conversion is stated."""
    fit = str(frag.attrs.get("im_component", "") or "rotd100")
    shakemap = req.config.event.shakemap_component
    if fit == shakemap:
        return f"ShakeMap and fragility on {fit}"
    if req.shakemap_scale is None:
        raise EventError(f"the fragility is fitted on {frag.attrs['im']} as {fit} ('screen fragility "
                         f"--im-component'), the ShakeMap gives {shakemap} ([event] shakemap_component). Re-fit "
                         f"with --im-component {shakemap}, or state the conversion with --shakemap-scale F (ShakeMap "
                         f"values x F give {fit}; e.g. the ratio of {fit} to {shakemap} of Boore & Kishida 2017)")
    return f"ShakeMap {shakemap} x {req.shakemap_scale:g} taken as the fragility's {fit} (--shakemap-scale)"


def _fragilities(frag: xr.Dataset, inv: Inventory, g_ms2: float) -> tuple[Fragilities, np.ndarray]:
    """The assets' fragilities in inventory order, and their Sa periods [s]."""
    known = set(frag["block"].values.tolist())
    missing = [b for b in inv.ids if b not in known]
    if missing:
        raise EventError(f"{len(missing)} asset(s) of the inventory are not in the fragility run: "
                         f"{', '.join(missing[:10])}; run 'screen fragility' on this inventory")
    sel = frag.sel(block=list(inv.ids))
    geom = inv.geometry(g_ms2=g_ms2)
    levels = frag["im_level"].values.astype(float)

    def col(name: str) -> np.ndarray:
        return sel[name].values.astype(float) if name in sel else np.full(len(inv), math.nan)

    unjudged = (sel["n_unjudged"].values > 0).any(axis=1) if "n_unjudged" in sel else np.zeros(len(inv), bool)
    slid = sel["n_sliding"].values > 0 if "n_sliding" in sel else np.zeros((len(inv), levels.size), bool)
    slides_from = np.where(slid.any(axis=1), np.min(np.where(slid, levels, np.inf), axis=1), np.inf)
    frags = Fragilities(col("median"), col("beta"), col("median_low"), col("median_high"),
                        sel["fit_status"].values.astype(int), float(levels.min()), float(levels.max()),
                        np.asarray(geom.alpha) < ALPHA_MAX_ROCKING,
                        median_unjudged=np.where(unjudged, col("median_unjudged_overturn"), np.nan),
                        beta_unjudged=col("beta_unjudged_overturn"), slides_from=slides_from)
    return frags, 2.0 * math.pi / np.asarray(geom.p, dtype=float)


def unjudged_warnings(frag: xr.Dataset, inv: Inventory, risk) -> list[str]:
    """One line per asset whose fragility stripes hold records without a verdict: how many, and P with them counted
    as overturning (its upper bound, which ranks it)."""
    if "n_unjudged" not in frag:
        return []
    counts = frag["n_unjudged"].sel(block=list(inv.ids)).values.sum(axis=1)
    return [f"{inv.ids[k]}: {counts[k]:.3g} scaled record-levels of its fragility run have no verdict (a model "
            f"stopped where the base slides, twists or lifts off); P up to {float(risk.p_high[k]):.2f} counts them "
            "as overturning, and ranks it" for k in np.flatnonzero(counts > 0)]


def most_efficient(frag: xr.Dataset, inv: Inventory) -> tuple[np.ndarray, np.ndarray]:
    """Per asset, the ShakeMap IM (pga, pgv, sa) whose fit of the same outcomes has the smallest dispersion
    (fragility.nc ``beta_im``), and that dispersion ("" and NaN where none has a finite fit)."""
    names = np.full(len(inv), "", dtype=object)
    betas = np.full(len(inv), math.nan)
    if "beta_im" not in frag:
        return names, betas
    ims = [str(x) for x in frag["im"].values]
    cols = [ims.index(x) for x in SHAKEMAP_IMS if x in ims]
    table = frag["beta_im"].sel(block=list(inv.ids)).values[:, cols]
    finite = np.where(np.isfinite(table), table, np.inf)
    pick = np.argmin(finite, axis=1)
    ok = np.isfinite(finite[np.arange(len(inv)), pick])
    names[ok] = np.array([ims[cols[c]] for c in pick])[ok]
    betas[ok] = finite[np.arange(len(inv)), pick][ok]
    return names, betas


def _shaking(grid: ShakeMapGrid, im: str, periods: np.ndarray, lon: np.ndarray, lat: np.ndarray,
             inv: Inventory, req: EventRequest) -> tuple[dict, list[str]]:
    """Per asset: the field read, its median [SI] and log-sd, and where the log-sd came from."""
    fields = np.array([field_for(im, float(T)) for T in periods], dtype=object)
    median, log_sd = np.full(len(inv), math.nan), np.full(len(inv), math.nan)
    source = np.zeros(len(inv), dtype=np.int8)
    warnings = []
    for name in dict.fromkeys(fields.tolist()):
        if name not in grid.medians:
            raise EventError(f"ShakeMap {grid.event_id} has no {name} field (it has {sorted(grid.medians)}); the "
                             f"fragility is on {im}")
        at = fields == name
        out = sites_shaking(grid, name, lon[at], lat[at], names=[inv.ids[k] for k in np.flatnonzero(at)])
        median[at], log_sd[at] = out.median, out.log_sd
        if name in grid.log_sd:
            source[at] = LOG_SD_SOURCES.index(grid.log_sd_source.get(name, "grid"))
        else:
            source[at] = LOG_SD_SOURCES.index("default")
            log_sd[at] = req.config.event.default_log_sd
            warnings.append(f"ShakeMap {grid.event_id} gives no STD{name} (neither in {req.shakemap.name} nor in an "
                            f"uncertainty.xml): the log standard deviation of {name} is taken as "
                            f"{req.config.event.default_log_sd} ([event] default_log_sd) for {int(at.sum())} "
                            "asset(s)")
    if req.shakemap_scale is not None:
        median = median * req.shakemap_scale
    period = np.array([PSA_PERIODS.get(f, math.nan) for f in fields])
    return {"field": fields, "median": median, "log_sd": log_sd, "source": source, "period": period}, warnings


def _version(value: str) -> tuple:
    """A ShakeMap version, comparable (numbers as numbers)."""
    try:
        return (0, float(value))
    except ValueError:
        return (1, value)


def previous_levels(out_dir: Path, grid: ShakeMapGrid) -> tuple[dict, str]:
    """The levels of the event's previous run into ``out_dir`` (block -> level) and its version ("" for none).

    Raises
    ------
    EventError
        When ``out_dir`` holds another event, or a newer version of this one.
    """
    path = out_dir / "event.nc"
    if not path.is_file():
        return {}, ""
    with xr.open_dataset(path) as old:
        old_id, old_version = str(old.attrs.get("event_id", "")), str(old.attrs.get("shakemap_version", ""))
        old_time = str(old.attrs.get("process_timestamp", ""))
        levels = dict(zip(old["block"].values.tolist(), old["level"].values.astype(int).tolist()))
    if old_id != grid.event_id:
        raise EventError(f"{out_dir} holds the results of event {old_id}; event {grid.event_id} would replace them. "
                         "Give each event its own --out directory")
    new_time = str(grid.attrs.get("process_timestamp", ""))
    if (_version(grid.version), new_time) < (_version(old_version), old_time):
        raise EventError(f"{out_dir} holds ShakeMap version {old_version} of event {old_id} (processed {old_time}); "
                         f"version {grid.version} (processed {new_time}) is older and never overwrites it. Give "
                         "another --out to keep both")
    return levels, old_version


def screen_event(req: EventRequest, *, progress=None) -> EventResult:
    """Run ``screen event`` (the module's steps) and publish its outputs together.

    Raises
    ------
    EventError, ShakeMapError, OutputError
        For inputs that do not fit together, a ShakeMap that cannot be read, an output that cannot be written.
    """
    t0 = time.perf_counter()
    grid = read_grid(req.shakemap, uncertainty=req.uncertainty)
    frag = open_fragility(req.fragility_dir)
    im = str(frag.attrs.get("im", ""))
    if im not in SHAKEMAP_IMS:
        raise EventError(f"{req.fragility_dir}/fragility.nc is fitted on {im}; a ShakeMap gives PGA, PGV and PSA: "
                         "re-run 'screen fragility --im pga' (or pgv, sa)")
    out_dir = Path(req.out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{out_dir}: cannot create the output directory ({exc.strerror or exc})") from exc
    with OutputLock(out_dir, command=" ".join(req.command)):
        return _run(req, grid, frag, im, out_dir, t0, progress)


def _run(req: EventRequest, grid: ShakeMapGrid, frag: xr.Dataset, im: str, out_dir: Path, t0: float, progress
         ) -> EventResult:
    cfg = req.config
    old_levels, old_version = previous_levels(out_dir, grid)
    component_note = _check_component(frag, req)
    inv = req.inventory
    lon, lat = coordinates(inv, req.sites)
    frags, periods = _fragilities(frag, inv, cfg.records.g_ms2)
    shaking, warnings = _shaking(grid, im, periods, lon, lat, inv, req)
    best, best_beta = most_efficient(frag, inv)
    better = [bid for bid, b in zip(inv.ids, best) if b and b != im]
    if better:
        warnings.append(f"for {len(better)} asset(s) ({', '.join(better[:5])}{' ...' if len(better) > 5 else ''}) "
                        f"the fragility stage found another ShakeMap IM more efficient than {im} (a smaller beta; "
                        "event.nc: most_efficient_im): re-fit with 'screen fragility --im' of that IM for sharper "
                        "probabilities")
    thresholds = (cfg.event.level_low, cfg.event.level_medium, cfg.event.level_high)
    risk = event_risk(shaking["median"], shaking["log_sd"], frags, k_sigma=req.k_sigma)
    warnings += unjudged_warnings(frag, inv, risk)
    near = None
    if req.records is not None:
        from .event_records import near_records

        near = near_records(req.records, inv, lon, lat, config=cfg, out_dir=out_dir, n_workers=req.n_workers,
                            stationxml=req.stationxml, progress=progress, command=req.command)
        warnings += near.notes
    rank, record_governs = governing(risk.p_rank, near)
    level = levels(rank, thresholds, at_least_low=risk.sliding)
    order = sorted(range(len(inv)), key=lambda k: (-np.nan_to_num(rank[k], nan=2.0), inv.ids[k]))
    priority = np.empty(len(inv), dtype=np.int32)
    priority[order] = np.arange(1, len(inv) + 1)
    previous = np.array([old_levels.get(b, -1) for b in inv.ids], dtype=np.int8)
    epi_lon, epi_lat = float(grid.event.get("lon", "nan")), float(grid.event.get("lat", "nan"))
    ds = xr.Dataset({
        "p_overturn_event": (("block",), risk.p), "p_overturn_event_low": (("block",), risk.p_low),
        "p_overturn_event_high": (("block",), risk.p_high), "basis": (("block",), risk.basis),
        "level": (("block",), level), "level_previous": (("block",), previous),
        "sliding_risk": (("block",), risk.sliding.astype(np.int8)),
        "priority": (("block",), priority), "shaking_median": (("block",), shaking["median"]),
        "shaking_log_sd": (("block",), shaking["log_sd"]), "log_sd_source": (("block",), shaking["source"]),
        "shakemap_field": (("block",), shaking["field"].astype(str)),
        "shakemap_period": (("block",), shaking["period"]), "block_period": (("block",), periods),
        "fragility_median": (("block",), frags.median), "fragility_beta": (("block",), frags.beta),
        "fit_status": (("block",), frags.status.astype(np.int8)), "lon": (("block",), lon),
        "lat": (("block",), lat), "epicentral_distance": (("block",), distance_km(lon, lat, epi_lon, epi_lat)),
        "most_efficient_im": (("block",), best.astype(str)), "most_efficient_beta": (("block",), best_beta),
        "station_record": (("block",), (near.record if near else np.full(len(inv), "", dtype=object)).astype(str)),
        "station_distance": (("block",), near.distance_km if near else np.full(len(inv), math.nan)),
        "p_overturn_record": (("block",), near.p if near else np.full(len(inv), math.nan)),
        "governed_by": (("block",), record_governs.astype(np.int8)),
    }, coords={"block": np.array(inv.ids, dtype=object)})
    ds.attrs.update({
        "title": "rockscreen event screening: P(overturn | event) per asset", "Conventions": "CF-1.11",
        "event_id": grid.event_id, "shakemap_version": grid.version,
        "process_timestamp": str(grid.attrs.get("process_timestamp", "")),
        "map_status": str(grid.attrs.get("map_status", "")),
        "shakemap_event_type": str(grid.attrs.get("shakemap_event_type", "")),
        "magnitude": str(grid.event.get("magnitude", "")), "epicentre_lon": epi_lon, "epicentre_lat": epi_lat,
        "event_description": str(grid.event.get("event_description", "")),
        "event_timestamp": str(grid.event.get("event_timestamp", "")),
        "im": im, "im_units": str(frag["median"].attrs.get("units", "")), "component": component_note,
        "k_sigma": req.k_sigma, "default_log_sd": cfg.event.default_log_sd, "level_low": thresholds[0],
        "level_medium": thresholds[1], "level_high": thresholds[2], "shakemap": str(req.shakemap),
        "uncertainty_file": str(req.uncertainty or ""), "fragility": str(Path(req.fragility_dir) / "fragility.nc"),
        "previous_version": old_version, "command": " ".join(req.command),
        "records_directory": str(req.records or ""),
        "station_radius_km": cfg.event.station_radius_km if req.records is not None else math.nan,
        "warnings": "\n".join(warnings)})
    ds = apply_schema(ds, EVENT)
    changed = [(inv.ids[k], Level(int(previous[k])).name, Level(int(level[k])).name)
               for k in order if previous[k] >= 0 and previous[k] != level[k]]
    paths = _publish(ds, grid, inv, req, order, changed)
    return EventResult(paths, ds, warnings, changed, old_version, time.perf_counter() - t0)


def governing(p_shakemap: np.ndarray, near) -> tuple[np.ndarray, np.ndarray]:
    """The probability that ranks each asset, and whether its station's record governs: the larger of the
    ShakeMap's (or its upper bound where it is not given) and the record's, so that the list is never less
    cautious than either."""
    if near is None:
        return p_shakemap, np.zeros(p_shakemap.shape, dtype=bool)
    record = np.isfinite(near.p) & ~(near.p <= np.nan_to_num(p_shakemap, nan=-1.0))
    return np.where(record, near.p, p_shakemap), record


def inspection_rows(ds: xr.Dataset, inv: Inventory, order: list[int]) -> tuple[tuple[str, ...], list[dict]]:
    """inspection.csv's columns and rows, highest priority first."""
    label, to_si = display_unit(ds.attrs["im"])         # g for accelerations, cms for velocities
    factor = 1.0 / to_si
    columns = tuple(c.format(unit=label) for c in INSPECTION_COLUMNS)
    arrays = {name: ds[name].values for name in ds.data_vars}
    natural = natural_rocks(inv.extra.get("object")) or [False] * len(inv.ids)
    scenario = is_scenario(ds.attrs)
    rows = []
    for k in order:
        v = {name: a[k] for name, a in arrays.items()}
        prev = int(v["level_previous"])
        rows.append(dict(zip(columns, (
            int(v["priority"]), inv.ids[k], inv.names[k], inv.sites[k], f"{v['lon']:.5f}", f"{v['lat']:.5f}",
            Level(int(v["level"])).name, advice_at(arrays, k, scenario=scenario, natural=natural[k]),
            "yes" if int(v["sliding_risk"]) == 1 else "",
            _value(v["p_overturn_event"]), _value(v["p_overturn_event_low"]),
            _value(v["p_overturn_event_high"]), Basis(int(v["basis"])).name, str(v["shakemap_field"]),
            _value(v["shaking_median"] * factor), _value(v["shaking_log_sd"]),
            LOG_SD_SOURCES[int(v["log_sd_source"])], _value(v["fragility_median"] * factor),
            _value(v["fragility_beta"]), FitStatus(int(v["fit_status"])).name, _value(v["epicentral_distance"]),
            str(v["station_record"]), _value(v["station_distance"]), _value(v["p_overturn_record"]),
            "record" if v["governed_by"] else "shakemap",
            Level(prev).name if prev >= 0 else "", "yes" if 0 <= prev != int(v["level"]) else ""))))
    return columns, rows


def _value(x) -> float | str:
    """A number for inspection.csv, unrounded; blank where it is not finite (no value, or none bounded)."""
    return float(x) if np.isfinite(x) else ""


def facilities(ds: xr.Dataset, inv: Inventory, cfg: Config) -> list[Facility]:
    """The assets as ShakeCast facilities (:mod:`pipeline.event.shakecast`): RED overturning on the fragility's
    ShakeMap field; YELLOW motion starts, on PGA, for assets on the ground."""
    geom = inv.geometry(g_ms2=cfg.records.g_ms2)
    u = cfg.uncertainty
    on_ground = [not b for b in (inv.building or ("",) * len(inv))]
    field_, median, beta = (ds[n].values for n in ("shakemap_field", "fragility_median", "fragility_beta"))
    lon, lat = ds["lon"].values, ds["lat"].values
    out = []
    for k, bid in enumerate(inv.ids):
        levels = []
        red = overturning_level(str(field_[k]), float(median[k]), float(beta[k]))
        if red is not None:
            levels.append(red)
        if on_ground[k] and float(geom.alpha[k]) < ALPHA_MAX_ROCKING:
            levels.append(onset_level(alpha_rad=float(geom.alpha[k]), mu=float(inv.mu[k]), size_cov=u.size_cov,
                                      friction_cov=u.friction_cov, g_ms2=cfg.records.g_ms2))
        out.append(Facility(bid, inv.names[k], "rockscreen: RED overturning (fragility), YELLOW motion starts "
                            "(uplift or slip, g min(tan alpha, mu))", float(lon[k]), float(lat[k]), tuple(levels)))
    return out


def _publish(ds: xr.Dataset, grid: ShakeMapGrid, inv: Inventory, req: EventRequest, order: list[int],
             changed: list) -> list[Path]:
    """Stage the four outputs and publish them together."""
    from ..report.event_html import event_page

    out_dir = Path(req.out_dir)

    def write(stage: Path) -> list[Path]:
        columns, rows = inspection_rows(ds, inv, order)
        return [write_atomic(ds, stage / "event.nc"), write_csv_atomic(stage / "inspection.csv", columns, rows),
                write_text_atomic(stage / "event.html", event_page(ds, grid, inv, order, changed,
                                                                   curves=req.config.event.page_curves)),
                write_text_atomic(stage / "shakecast-facilities.xml", facility_xml(facilities(ds, inv, req.config)))]

    return publish_staged(out_dir, write, family=Family.EVENT, command=" ".join(req.command))
