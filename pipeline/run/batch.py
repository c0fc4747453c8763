"""A screening run: plan what to compute, run it on an executor, collect the results.

Data flow (one writer)::

    scan -> keys -> plan (cache hits, blocks to compute) -> executor tasks
         -> writer: cache entry per record as it returns -> assemble -> Dataset

With an output directory, every record's result is saved to the scene
cache (:mod:`pipeline.run.cache`) as soon as its task returns, so a run that is
interrupted or killed loses nothing it computed, and the next run into the
same output computes only:

* records that are new, whose files changed, or whose last failure was not caused by their
  content (a crash, a lost worker); a record that failed on its content (format, units, no
  horizontal: a :class:`~pipeline.errors.RockscreenError`) fails again from the cache, with
  the same reason, until its files or the run key change;
* every record, when the configuration, the package version, the declared
  units or the StationXML changed (the run key);
* for unchanged records, only the blocks that are new or whose inventory
  row changed.

Records whose files vanished since the last run keep their last results,
flagged ``source_present = 0``.
"""

from __future__ import annotations

import hashlib
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from ..blocks import Inventory
from ..bodies.registry import stops
from ..config import Config
from ..errors import RockscreenError
from ..floors.buildings import floor_groups, place_blocks
from ..floors.motion import describe
from ..records.listing import Failure, Listing, RecordSource, list_directory, units_toml_lines
from ..records.side_files import read_declared_units
from ..records.units import declared_units_for
from ..risk import scenes_without_verdict
from ..rocking.block import ShapeKind
from ..rocking.orientation import Orientation
from ..rocking.planner import ContactMode, FreeFlight, Physics, Response, guarded_scenes
from ..scene_table import SCENE
from ..schema import FLOOR_PULSE_VALUES
from ..store import FloorRow, PulseSeries
from ..uncertainty.robust import Robustness
from .cache import SceneCache, merge, run_key
from .engine import RecordJobs
from .executors import SerialExecutor
from .screening import Context, RecordResult, assemble, failure_result, screen_record

log = logging.getLogger(__name__)


def _task(item: tuple, ctx: Context) -> RecordResult:
    """One executor task: a record, the ids of the blocks to screen it against (None: all), its digest; a
    failure is the record's failed row."""
    source, block_ids, content = item
    return screen_record(source, ctx, block_ids, content)


class _SharedKeys:
    """One copy of the inventory's block ids and digests for all the results a run holds.

    Every result carries the ids and digests of its blocks (1000 blocks: about 180 KB of strings per
    record, as much as its per-scene values), and results that arrive from a worker or from the scene
    cache bring their own copies. Equal tuples are replaced by the inventory's own, and other strings by
    the inventory's equal ones, so holding many records costs their values only.
    """

    def __init__(self, inventory: Inventory):
        self.ids, self.digests = tuple(inventory.ids), tuple(inventory.digests())
        self.strings = {s: s for s in self.ids + self.digests}

    def __call__(self, res: RecordResult) -> RecordResult:
        res.block_ids = self._share(tuple(res.block_ids), self.ids)
        res.block_digests = self._share(tuple(res.block_digests), self.digests)
        return res

    def _share(self, keys: tuple, whole: tuple) -> tuple:
        if keys == whole:
            return whole
        return tuple(self.strings.get(k, k) for k in keys)


@dataclass
class Plan:
    """What a run computes and what it reuses."""

    keys: _SharedKeys                                  # the inventory's block ids and digests, shared
    tasks: list = field(default_factory=list)          # (RecordSource, block ids or None, content digest)
    cached: dict = field(default_factory=dict)         # record id -> cached RecordResult
    failures: list = field(default_factory=list)       # RecordResult of records that cannot be read
    vanished: list = field(default_factory=list)       # record ids kept from the last run
    dropped: list = field(default_factory=list)        # vanished record ids that could not be kept
    blocks_changed: int = 0                            # blocks new or changed since the last run


#: What the plan reads of the previous results (not their records x blocks arrays).
PLAN_VARIABLES = ("status", "content_sha256", "block_sha256")


def _previous_block_digests(previous: xr.Dataset | None) -> dict:
    if previous is None or "block_sha256" not in previous:
        return {}
    return dict(zip(previous["block"].values.tolist(), previous["block_sha256"].values.tolist()))


def record_content(src: RecordSource, *, root: Path | None = None, declared: dict | None = None) -> str:
    """A record's content digest: its files' names and bytes, and the units ``declared`` (``units.toml`` and the
    configuration) for each of them, so that a declaration recomputes only the records whose files it names."""
    content = src.digest()
    if not declared or root is None:
        return content
    units = ";".join(f"{Path(f).name}={declared_units_for(Path(f), root, declared) or ''}" for f in src.files)
    return hashlib.sha256(f"{content}\n{units}".encode()).hexdigest()


def plan(sources: list[RecordSource], inventory: Inventory, *, cache: SceneCache | None,
         previous: xr.Dataset | None = None, force: bool = False, unreadable: tuple = (),
         root: Path | None = None, declared: dict | None = None) -> Plan:
    """Decide, per record, whether to reuse its cached result, complete it, or screen it.

    Parameters
    ----------
    sources : list of RecordSource
        The records found by the scan.
    inventory : Inventory
        The current inventory.
    cache : SceneCache or None
        The output's scene cache (None: compute everything, keep nothing).
    previous : xarray.Dataset, optional
        The last complete results in the output (for vanished records).
    force : bool
        Recompute everything, ignoring the cache.
    unreadable : tuple of str
        Ids of records present but unreadable at the scan: they fail, they have not vanished.
    root, declared : Path, dict
        The records directory and its declared units (:func:`record_content`).
    """
    keys = _SharedKeys(inventory)
    out = Plan(keys=keys)
    digests = dict(zip(inventory.ids, inventory.digests()))
    old_digests = _previous_block_digests(previous)
    out.blocks_changed = sum(old_digests.get(b) != d for b, d in digests.items()) if old_digests else len(digests)
    seen = set(unreadable)
    for src in sources:
        seen.add(src.record_id)
        try:
            content = record_content(src, root=root, declared=declared)
        except RockscreenError as exc:
            out.failures.append(RecordResult(src.record_id, f"failed: {exc}",
                                             {"files": ";".join(Path(f).name for f in src.files)}))
            continue
        entry = None if (cache is None or force) else cache.load(src.record_id, content)
        if entry is not None:
            entry = keys(entry)
        if entry is not None and not entry.ok:            # the same files failed the same way last time
            out.failures.append(entry)
            continue
        have = {} if entry is None else dict(zip(entry.block_ids, entry.block_digests))
        missing = tuple(b for b in inventory.ids if have.get(b) != digests[b])
        if entry is not None:
            out.cached[src.record_id] = entry
        if missing:
            out.tasks.append((src, missing, content))
    if previous is not None and cache is not None and "content_sha256" in previous:
        ok = previous["status"].values == "ok"
        for rid, content in zip(previous["record"].values[ok], previous["content_sha256"].values[ok]):
            if rid in seen:
                continue
            entry = cache.load(str(rid), str(content))
            if entry is None:
                out.dropped.append(str(rid))
            else:
                out.vanished.append(str(rid))
                out.cached[str(rid)] = keys(entry)
    return out


def _shed_series(res: RecordResult, shed: dict) -> None:
    """Drop a cached result's pulse series (the ground's and its floors') from memory, keeping their length and
    interval and the floors' pulse values."""
    if res.series and "velocity" in res.series:
        shed[res.record_id] = (int(np.size(res.series["velocity"])), float(res.values["dt"]))
        res.series = {}
    for table in res.floor_series.values():
        if "velocity" in table:
            table["npts"] = int(np.size(table.pop("velocity")))
            table.pop("pulse", None)


def _restore_floor_series(res: RecordResult | None, cache: SceneCache | None) -> None:
    """Read back from the scene cache the floor series :func:`_shed_series` dropped from ``res``, before a task
    that screened only some blocks is merged into it (its other floors' series are saved again with it)."""
    shed_floors = tuple(key for key, table in (res.floor_series.items() if res is not None else ())
                        if "velocity" not in table)
    if not shed_floors or cache is None:
        return
    assert res is not None
    got = cache.series(res.record_id, res.values["content_sha256"], shed_floors)
    for key in shed_floors:
        if got is None:                    # the entry vanished: that floor's series are computed again next run
            del res.floor_series[key]
        else:
            res.floor_series[key].pop("npts", None)
            res.floor_series[key].update(got["floors"][key])


def _pulse_series(results: list[RecordResult], shed: dict, cache: SceneCache | None,
                  floors_in_use: frozenset = frozenset()) -> PulseSeries:
    """The run's pulses, fetched per record from memory or, for shed series, from the scene cache: the
    ground's, and those of the floors in ``floors_in_use`` ((building id, height [m]) of the inventory's
    blocks; a floor's series computed for blocks no longer there is left out)."""
    rows: list[tuple[str, int, float]] = []
    in_memory: dict[str, dict] = {}
    content: dict[str, str] = {}
    floors_of: dict[str, list[FloorRow]] = {}
    for r in results:
        if not r.ok:
            continue
        if r.record_id in shed:
            rows.append((r.record_id, *shed[r.record_id]))
            content[r.record_id] = r.values["content_sha256"]
        elif r.series and "velocity" in r.series:
            rows.append((r.record_id, int(np.size(r.series["velocity"])), float(r.values["dt"])))
        else:
            continue
        floors = [FloorRow(r.record_id, b, z, int(table.get("npts", np.size(table.get("velocity")))),
                           float(table["dt"]), {n: table[n] for n in FLOOR_PULSE_VALUES})
                  for (b, z), table in sorted(r.floor_series.items()) if (b, z) in floors_in_use]
        floors_of[r.record_id] = floors
        if r.record_id not in shed:
            in_memory[r.record_id] = {**r.series, "floors": {(f.building, f.height_m): r.floor_series[
                f.building, f.height_m] for f in floors}}

    def fetch(record_id: str) -> dict:
        if record_id in in_memory:
            return in_memory[record_id]
        wanted = floors_of[record_id]
        keys = tuple((f.building, f.height_m) for f in wanted)
        got = cache.series(record_id, content[record_id], keys) if cache is not None else None
        if got is None:       # the cache entry vanished or broke since it was written during this run
            log.warning("record %s: its pulse series could not be read back from the scene cache; written as "
                        "NaN in pulses.nc (run again with --force to recompute them)", record_id)
            return {**_nan_series(shed[record_id][0]),
                    "floors": {(f.building, f.height_m): _nan_series(f.npts) for f in wanted}}
        return got

    return PulseSeries(rows, fetch, floor_rows=[f for floors in floors_of.values() for f in floors])


def _nan_series(n: int) -> dict:
    return {"velocity": np.full(n, np.nan), "pulse": np.full(n, np.nan)}


def _general_reasons(ds: xr.Dataset) -> dict[str, int]:
    """Scenes the general contact model decided, by why pure rocking (or sliding) stopped holding."""
    general = ds[SCENE.physics].values == Physics.general
    flight, modes = ds[SCENE.free_flight].values, ds[SCENE.contact_modes].values
    return {"total": int(np.sum(general)),
            "slide_rock": int(np.sum(general & (modes >= 0) & (modes & ContactMode.slide_rock > 0))),
            "ground_flight": int(np.sum(general & (flight == FreeFlight.ground_flight))),
            "block_liftoff": int(np.sum(general & (flight == FreeFlight.block_liftoff)))}


@dataclass
class BatchOutcome:
    """What the screening stage hands to the next stages.

    Attributes
    ----------
    results : xarray.Dataset
        The screening results (``screening.nc`` before margins).
    pulses : PulseSeries
        The extracted pulses (``pulses.nc``), fetched per record when written (:meth:`PulseSeries.write`)
        or all at once (:meth:`PulseSeries.dataset`).
    counts : dict
        Plain counts and wall time for the closing summary.
    cache : SceneCache or None
        The scene cache (its margin cache is used by the margins stage; pruned after the write).
    sources : dict
        Record id -> :class:`~pipeline.records.listing.RecordSource` of this run.
    context : Context
        The tasks' shared context.
    """

    results: xr.Dataset
    pulses: PulseSeries
    counts: dict
    cache: SceneCache | None
    sources: dict[str, RecordSource]
    context: Context


def run(records_dir: str | Path, inventory: Inventory, config: Config, *, out_dir: str | Path | None = None,
        executor=None, force: bool = False, station_inventory=None, declared_units: dict | None = None,
        stationxml_sha256: str = "", progress=None, listing: Listing | None = None,
        buildings: dict | None = None) -> BatchOutcome:
    """Screen every record under ``records_dir`` against ``inventory``.

    Parameters
    ----------
    records_dir : path
        Directory of records (read by path inside the tasks).
    inventory : Inventory
        The blocks.
    config : Config
        The effective configuration.
    out_dir : path, optional
        Output directory whose scene cache and last results make this run
        incremental. None: compute everything in memory.
    executor : optional
        A :mod:`pipeline.run.executors` executor, already entered (default serial).
    force : bool
        Recompute every record and block.
    progress : callable, optional
        ``progress(iterable, total)`` wrapping the stream of finished tasks.
    listing : Listing, optional
        The directory's scan when the caller has it (:func:`~pipeline.records.listing.list_directory`).
    buildings : dict, optional
        Building id -> :class:`~pipeline.floors.motion.Building`, for blocks on a floor.

    Returns
    -------
    BatchOutcome
    """
    t0 = time.perf_counter()
    records_dir = Path(records_dir)
    found = list_directory(records_dir, config=config) if listing is None else listing
    _say_what_the_scan_found(found)
    declared = read_declared_units(records_dir, config) if declared_units is None else declared_units
    placements = place_blocks(inventory, buildings or {})        # checked before any record is read
    ctx = Context(str(records_dir), config, inventory, declared, station_inventory, dict(buildings or {}))
    # the declared units are in each record's content digest (record_content), not in the run's key: a units.toml
    # line recomputes only the records whose files it names
    key = run_key(config.to_dict(), declared_units={}, station_inventory_sha256=stationxml_sha256,
                  buildings=buildings)
    cache = SceneCache(out_dir, key) if out_dir is not None else None
    the_plan = plan(found.sources, inventory, cache=cache, previous=_previous_plan(out_dir), force=force,
                    unreadable=tuple(f.record_id for f in found.failures), root=Path(records_dir),
                    declared=declared)
    _say_what_the_plan_keeps(the_plan, records_dir)
    executor = executor or SerialExecutor()
    got = _execute(the_plan, ctx, cache, executor, progress, found.failures)
    for f in found.failures:
        log.warning("record %s failed: %s", f.record_id, f.reason)
    everything = _mark_present(got, the_plan)
    ds = assemble(everything, inventory, config, placements=placements)
    _run_attributes(ds, key, buildings, found)
    in_use = frozenset(key for key in floor_groups(placements) if key)
    pulses = _pulse_series(sorted(everything, key=lambda r: r.record_id), got.shed, cache, in_use)
    units_toml = units_toml_lines(records_dir, [f.status for f in got.failed])
    if units_toml:                       # the report opens with these lines: what to paste, where
        ds.attrs["units_toml"] = "\n".join(units_toml)
        ds.attrs["units_toml_path"] = str(Path(records_dir) / "units.toml")
    counts = {**_scene_counts(ds, config), **_record_counts(got, the_plan, found),
              "blocks": len(inventory), "blocks_changed": the_plan.blocks_changed,
              "buildings": ds.attrs.get("buildings", ""),
              "units_toml": units_toml,
              "records_dir": str(records_dir),
              "executor": f"{executor.name} ({executor.n_workers} worker{'s' if executor.n_workers != 1 else ''})",
              "wall_time_s": time.perf_counter() - t0}
    return BatchOutcome(ds, pulses, counts, cache, {s.record_id: s for s in found.sources}, ctx)


@dataclass
class _Collected:
    """The results of a run as its record jobs return them."""

    results: dict[str, RecordResult]                 # record id -> the result (cached or computed)
    shed: dict[str, tuple[int, float]]               # record id -> (length, dt) of series dropped from memory
    failed: list[RecordResult]                       # the failed rows
    records: int = 0                                 # records computed by this run
    scenes: int = 0                                  # scenes computed by this run
    transient: int = 0                               # records failed by a crash or a lost worker (retried next run)


def _execute(the_plan: Plan, ctx: Context, cache: SceneCache | None, executor, progress,
             scan_failures: list[Failure]) -> _Collected:
    """Run the plan's tasks (:class:`~pipeline.run.engine.RecordJobs`) and collect every result into the cached
    ones: each saved to the scene cache as it returns, its pulse series then dropped from memory."""
    got = _Collected(results=dict(the_plan.cached), shed={},
                     failed=[failure_result(f) for f in scan_failures] + the_plan.failures)
    # the pulse series are the part of a result that grows with a record's length: once a result is in the
    # scene cache, its series are dropped from memory and read back one record at a time by the writer
    for res in got.results.values():
        _shed_series(res, got.shed)
    for rec_failure in the_plan.failures:
        if rec_failure.deterministic:
            log.warning("record %s %s (files unchanged since the run that found it)", rec_failure.record_id,
                        rec_failure.status)

    def done(job: tuple, res: RecordResult, _reused: bool) -> None:
        _source, block_ids, content = job
        earlier = None if res.ok or res.deterministic else _earlier_result(cache, res.record_id, content, the_plan)
        if earlier is not None:          # a lost worker never replaces a good result of the same inputs
            log.warning("record %s %s; the result computed earlier for the same files and configuration is kept "
                        "(the next run with --force tries again)", res.record_id, res.status)
            got.results[res.record_id] = earlier
            _shed_series(earlier, got.shed)
            return
        if not res.ok:
            got.transient += not res.deterministic
            log.warning("record %s %s", res.record_id, res.status)
            got.results.pop(res.record_id, None)
            got.shed.pop(res.record_id, None)
            got.failed.append(res)
            if cache is not None and res.deterministic:
                cache.save_failure(res, content)
            return
        _restore_floor_series(got.results.get(res.record_id), cache)
        res = the_plan.keys(merge(got.results.get(res.record_id), res))
        if cache is not None and cache.save(res):
            _shed_series(res, got.shed)
        else:
            got.shed.pop(res.record_id, None)
        got.results[res.record_id] = res
        got.records += 1
        got.scenes += len(block_ids)

    jobs = RecordJobs(executor, progress=progress)
    ctx.progress = jobs.scenes
    jobs.run(_task, the_plan.tasks, ctx, done=done, failed=lambda job, f: done(job, failure_result(f), False))
    return got


def _earlier_result(cache: SceneCache | None, record_id: str, content: str, the_plan: Plan) -> RecordResult | None:
    """The scene cache's good result of a record for the same files and run key, when it covers every block of the
    inventory as it is now (a ``--force`` run overwrites it only as its own results return); else None."""
    entry = cache.load(record_id, content) if cache is not None else None
    if entry is None or not entry.ok:
        return None
    have = dict(zip(entry.block_ids, entry.block_digests))
    if any(have.get(b) != d for b, d in zip(the_plan.keys.ids, the_plan.keys.digests)):
        return None
    return the_plan.keys(entry)


def _mark_present(got: _Collected, the_plan: Plan) -> list[RecordResult]:
    """Every result of the run, each marked with whether its files are still there (``source_present``)."""
    vanished = set(the_plan.vanished)
    for rid, res in got.results.items():
        res.values["source_present"] = 0 if rid in vanished else 1
    for res in got.failed:
        res.values["source_present"] = 1
    return list(got.results.values()) + got.failed


def _run_attributes(ds: xr.Dataset, key: str, buildings: dict | None, found: Listing) -> None:
    """The run's key, its buildings, the files that are not records and the duplicate records, as attributes."""
    ds.attrs["rockscreen_run_key"] = key
    if buildings:
        ds.attrs["buildings"] = "\n".join(describe(b) for _, b in sorted(buildings.items()))
    ds.attrs["files_not_records"] = "\n".join(f"{path}: {reason}" for path, reason in found.not_records)
    ds.attrs["duplicate_records"] = "\n".join(f"{dup} = {kept} ({', '.join(Path(f).name for f in files)})"
                                              for kept, dup, files in found.duplicates)


def _record_counts(got: _Collected, the_plan: Plan, found: Listing) -> dict:
    """The records of the run's summary: ok, failed, screened now, reused, vanished, dropped; the files seen."""
    vanished = len(the_plan.vanished)
    return {"records_ok": len(got.results), "records_failed": len(got.failed), "records_screened": got.records,
            "records_reused": len(got.results) - got.records - vanished, "records_vanished": vanished,
            "records_dropped": len(the_plan.dropped), "scenes_computed": got.scenes,
            "records_failed_transient": got.transient,
            "files_seen": found.files_seen, "not_records": list(found.not_records),
            "duplicates": [(kept, dup) for kept, dup, _ in found.duplicates]}


def _say_what_the_scan_found(found: Listing) -> None:
    """Log the files that are not records, and the records that hold the same bytes as another."""
    for path, reason in found.not_records:
        log.info("not a record: %s: %s", path, reason)
    for kept, dup, files in found.duplicates:
        log.warning("record %s (%s) holds the same bytes as %s: screened once, as %s", dup,
                    ", ".join(Path(f).name for f in files), kept, kept)


def _previous_plan(out_dir: str | Path | None) -> xr.Dataset | None:
    """What the last run of this output directory screened (:data:`PLAN_VARIABLES`), or None (none, or a damaged
    file, which is replaced)."""
    from ..store import open_results

    path = Path(out_dir) / "screening.nc" if out_dir is not None else None
    if path is None or not path.is_file():
        return None
    try:
        return open_results(path, variables=PLAN_VARIABLES)
    except Exception as exc:   # a damaged earlier file must not stop the run; it is replaced
        log.warning("%s/screening.nc: cannot read the previous results (%s); they will be replaced", out_dir, exc)
        return None


def _say_what_the_plan_keeps(the_plan: Plan, records_dir) -> None:
    """Log the records whose files are gone: their results kept, or dropped under another configuration."""
    for rid in the_plan.vanished:
        log.warning("record %s: its files are no longer in %s; its last results are kept (source_present = 0)",
                    rid, records_dir)
    for rid in the_plan.dropped:
        log.warning("record %s: its files are no longer in %s and its results were computed under another "
                    "configuration; it is left out of the new results", rid, records_dir)


def _scene_counts(ds: xr.Dataset, config: Config) -> dict:
    """The scenes of the results by physics, response, orientation and robustness class, the planes and samples
    integrated, the scenes the general contact model decided, the stacks' bodies whose ground flew, those that met
    a guard and those that slid off their base, and the boxes (judged in one plane of their base): the closing
    summary's counts."""
    from ..report.html import planar_boxes

    phys, resp = ds[SCENE.physics].values, ds[SCENE.response].values
    return {
        "scenes_by_physics": {"not simulated": int(np.sum(phys[ds["status"].values == "ok"] == -1)),
                              **{m.name: int(np.sum(phys == m)) for m in Physics}},
        "fidelity": config.fidelity.tier,
        "scenes_by_response": {m.name: int(np.sum(resp == m)) for m in Response},
        "scenes_by_orientation": {m.name: int(np.sum(ds[SCENE.orientation].values == m)) for m in Orientation},
        "planes_integrated": int(np.sum(np.maximum(ds[SCENE.planes_simulated].values, 0))),
        "free_flight_scenes": int(np.sum(resp == Response.free_flight)),
        "scenes_by_robustness": {m.name: int(np.sum(ds[SCENE.robustness].values == m.value)) for m in Robustness},
        "sampled_simulations": int(np.sum(np.maximum(ds[SCENE.sample_simulations].values, 0))),
        "scenes_unjudged": scenes_without_verdict(ds),
        "scenes_unjudged_3d": int(np.sum((ds[SCENE.overturn_simulated].values == -1)
                                         & np.isin(phys, [p for s in stops() if s.contact3d_decides
                                                          for p in s.physics]))),
        "draws_unjudged": int(np.sum(np.maximum(ds[SCENE.samples_without_verdict].values, 0))),
        "draws_total": int(np.sum(np.maximum(ds[SCENE.samples_drawn].values, 0))),
        "scenes_with_unjudged_draws": int(np.sum(ds[SCENE.samples_without_verdict].values > 0)),
        "general_scenes": _general_reasons(ds),
        "stack_flights": int(np.sum((phys == Physics.stack)
                                    & (ds[SCENE.free_flight].values == FreeFlight.ground_flight))),
        "stack_contact": int(np.sum((phys == Physics.stack) & np.isfinite(ds[SCENE.sliding_max].values))),
        "guarded_scenes": [f"{r} x {b}: {names}" for r, b, names in guarded_scenes(
            ds[SCENE.simulation_guard].values, ds["record"].values, ds["block"].values)],
        "slides_off_base": int(np.sum(ds["slides_off_base"].values == 1)),
        "boxes": planar_boxes(ds),
        "boxes_with_depth": int(np.sum((ds["shape"].values == ShapeKind.box) & np.isfinite(ds["depth"].values)))
        if "depth" in ds else 0,
        "box_scenes_3d": int(np.sum(ds[SCENE.orientation].values == Orientation.given_3d)),
        "box_scenes_certified": int(np.sum(ds[SCENE.orientation].values == Orientation.given_certified)),
    }

