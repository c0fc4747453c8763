"""Records x blocks orchestration: one task per record, one writer.

A task (:func:`screen_record`) loads one record by path, computes everything
that record needs for all blocks at once, and returns plain arrays; the
caller assembles the tasks' results into one Dataset (:func:`assemble`) and
writes it. Nothing is kept of a record but its results, so memory does not
grow with the number of records.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from .. import __version__, criteria
from ..assemblies.stack_scene import RunMemo
from ..blocks import Inventory
from ..bodies.contract import OnRecord, Placement, Setup
from ..bodies.registry import body_model
from ..closed_forms import PULSE_BETA
from ..config import Config
from ..constants import CM_TO_M
from ..errors import PulseError, TaskFailure
from ..floors.buildings import place_blocks
from ..floors.standing import FloorMotions
from ..pulses import analyze
from ..records.listing import Failure, RecordSource
from ..records.loader import load_record
from ..records.record import Record
from ..risk import RELOCATE_BELOW_SCALE
from ..rocking.block import Block
from ..rocking.orientation import PlaneResult, Planes, plane_grid
from ..scene_progress import SceneProgress
from ..scene_table import SCENE, SceneColumns
from ..schema import (
    COMPONENTS,
    FLOOR_PULSE_VALUES,
    FLOOR_VARS,
    INTEGER_DTYPES,
    PROBABILITY_VARS,
    PULSE_BLOCK_VARS,
    SCHEMA,
    SIMULATION_VARS,
    ResultTable,
    apply_schema,
    floor_key,
    inventory_variable,
    parse_floor_key,
    result_table,
)
from ..stacks import joint_openings, stack_ids, stack_placements, stack_verdicts, stands_on_ids
from ..uncertainty.orientations import (
    OrientationProbability,
    average_normals,
    estimation_normals,
)
from ..uncertainty.sampling import common_normals
from ..uncertainty.scenes import motion
from .engine import as_failure, task_failure

log = logging.getLogger(__name__)


@dataclass
class Context:
    """What every task needs besides its record (picklable)."""

    root: str
    config: Config
    inventory: Inventory
    declared_units: dict
    station_inventory: object = None
    #: building id -> :class:`~pipeline.floors.motion.Building`, for blocks on a floor
    buildings: dict = field(default_factory=dict)
    #: which record and scene the task is on (:mod:`pipeline.scene_progress`)
    progress: SceneProgress = field(default_factory=SceneProgress)

    def load(self, source: RecordSource) -> Record:
        """Read, convert and process one record (:func:`pipeline.records.loader.load_record`)."""
        return load_record(source, root=self.root, config=self.config, declared=self.declared_units,
                           inventory=self.station_inventory)


@dataclass
class RecordResult:
    """Results of one record: per-record scalars and per-component values."""

    record_id: str
    status: str
    values: dict = field(default_factory=dict)
    components: dict = field(default_factory=dict)
    blocks: dict = field(default_factory=dict)
    series: dict = field(default_factory=dict)
    #: the pulse series of each floor blocks stand on, by (building id, floor height [m]): ``velocity``,
    #: ``pulse`` [m s-1], ``dt`` [s] and the floor's record-level pulse values (:data:`FLOOR_PULSE_VALUES`)
    floor_series: dict = field(default_factory=dict)
    #: ids of the blocks the arrays in ``blocks`` are aligned with
    block_ids: tuple = ()
    #: inventory digests of those blocks (what they were computed with)
    block_digests: tuple = ()
    #: a failure caused by the record's content under this configuration (a RockscreenError: format, units,
    #: no horizontal, ...): the same files fail the same way, so it is kept in the scene cache; a crash
    #: or a lost worker is not, and is retried
    deterministic: bool = False

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def to_arrays(self) -> dict[str, np.ndarray]:
        """Plain arrays for the scene cache, each under its schema name (a floor's under
        :func:`~pipeline.schema.floor_key`); read back by :meth:`from_arrays`."""
        arrays = {"record_id": np.array(self.record_id), "block_ids": np.array(self.block_ids, dtype=str),
                  "block_digests": np.array(self.block_digests, dtype=str)}
        for table in (self.values, self.components, self.blocks, self.series):
            arrays.update((name, np.asarray(value)) for name, value in table.items())
        for (building, height_m), table in self.floor_series.items():
            arrays.update((floor_key(building, height_m, name), np.asarray(value)) for name, value in table.items())
        return arrays

    @classmethod
    def from_arrays(cls, z) -> "RecordResult":
        """The result written by :meth:`to_arrays`, each array put in its table by the schema
        (:func:`~pipeline.schema.result_table`).

        Raises
        ------
        ValueError
            When an array is not a variable of the schema (an entry of another layout), or a simulation column
            is missing.
        """
        res = cls(str(z["record_id"]), "ok", block_ids=tuple(z["block_ids"].tolist()),
                  block_digests=tuple(z["block_digests"].tolist()))
        tables = {ResultTable.values: res.values, ResultTable.components: res.components,
                  ResultTable.blocks: res.blocks, ResultTable.series: res.series}
        for key, arr in z.items():
            if key in ENTRY_KEYS:
                continue
            floor = parse_floor_key(key)
            if floor is not None:
                building, height_m, name = floor
                res.floor_series.setdefault((building, height_m), {})[name] = arr.item() if arr.ndim == 0 else arr
                continue
            table = result_table(key)
            value = arr.item() if arr.ndim == 0 else (arr.tolist() if table == ResultTable.components else arr)
            tables[table][key] = value
        missing = set(SIMULATION_VARS) - set(res.blocks)          # pulse columns are absent without a pulse
        if missing:
            raise ValueError(f"block columns {sorted(missing)} missing")
        return res


#: The arrays of a scene-cache entry that are not results: the record, its blocks and the entry's format
ENTRY_KEYS = frozenset({"record_id", "block_ids", "block_digests", "entry_format"})


def _record_values(rec: Record, source: RecordSource) -> tuple[dict, dict]:
    values = {
        "files": ";".join(Path(f).name for f in rec.files),
        "record_label": rec.label,
        "formats": ";".join(rec.formats),
        "notes": "; ".join(rec.notes),
        "processing_history": "\n".join(rec.history),
        "dt": rec.dt_s,
        "npts": rec.npts,
        "duration": rec.dt_s * (rec.npts - 1),
        "n_horizontal": rec.horizontal_ms2.shape[0],
        "has_vertical": int(rec.vertical_ms2 is not None),
        "azimuth_known": int(rec.azimuth_known),
        "processing_level": rec.processing_level,
        "pga": rec.pga_ms2(),
        "pgv": rec.pgv_ms(),
    }
    comps: dict[str, list] = {"component_code": ["", "", ""], "component_azimuth": [np.nan] * 3,
                              "component_pga": [np.nan] * 3, "component_header_pga": [np.nan] * 3}
    series = list(rec.horizontal_ms2) + ([rec.vertical_ms2] if rec.vertical_ms2 is not None else [])
    slots = list(range(rec.horizontal_ms2.shape[0])) + ([2] if rec.vertical_ms2 is not None else [])
    for k, (slot, data) in enumerate(zip(slots, series)):
        code = rec.component_codes[k]
        comps["component_code"][slot] = code
        comps["component_azimuth"][slot] = rec.azimuths_deg[slot] if slot < 2 else np.nan
        comps["component_pga"][slot] = float(np.max(np.abs(data)))
        comps["component_header_pga"][slot] = rec.header_peaks_ms2.get(code, np.nan)
    return values, comps


def _block_directions(rec: Record, inventory: Inventory, strongest_deg: float) -> np.ndarray:
    """Direction each block is checked along: its azimuth, or the strongest pulse axis."""
    az = inventory.azimuth_deg
    if not rec.azimuth_known or rec.single_component:
        return np.full(len(inventory), strongest_deg)
    return np.where(np.isnan(az), strongest_deg, np.round(az) % 180.0)


def _pulse_values(rec: Record, ctx: Context) -> tuple[dict, dict, dict]:
    cfg = ctx.config.pulses
    nb = len(ctx.inventory)
    try:
        pulse = analyze(rec, method=cfg.method, tp_min_s=cfg.tp_min_s, tp_max_s=cfg.tp_max_s)
    except PulseError as exc:
        return {"is_pulse": -1, "pulse_late": -1, "pulse_method": cfg.method,
                "pulse_flags": f"no pulse extracted: {exc}"}, {}, {}
    res, best, lobe = pulse.result, pulse.result.best, pulse.lobe
    flags = list(res.flags)
    if not rec.azimuth_known:
        flags.append("pulse azimuth relative to the first component (absolute azimuth unknown)")
    values = {
        "is_pulse": int(res.is_pulse), "pulse_indicator": best.pulse_indicator,
        "pulse_period": res.tp_s, "pulse_azimuth": pulse.azimuth_deg, "pulse_late": int(best.late),
        "pulse_ap": lobe.ap_ms2, "pulse_tp": lobe.tp_s, "pulse_beta": lobe.beta, "pulse_dv": lobe.dv_ms,
        "pulse_record_ap": pulse.record_ap_ms2, "pulse_candidate": res.chosen + 1,
        "pulse_method": res.method, "pulse_flags": "; ".join(flags),
    }
    directions = _block_directions(rec, ctx.inventory, pulse.azimuth_deg)
    names = (SCENE.block_pulse_ap, SCENE.block_pulse_tp, SCENE.block_pulse_beta, SCENE.block_pulse_dv,
             SCENE.block_record_ap)
    blocks = {n: np.full(nb, np.nan) for n in names}
    blocks[SCENE.block_pulse_azimuth] = directions
    for d in np.unique(directions):
        sel = directions == d
        if d == pulse.azimuth_deg:
            lb, rap = lobe, pulse.record_ap_ms2
        else:
            lb, rap = pulse.along(rec, float(d))
        for n, v in zip(names, (lb.ap_ms2, lb.tp_s, lb.beta, lb.dv_ms, rap)):
            blocks[n][sel] = v
    assert best.velocity_cms is not None and best.pulse_cms is not None     # the chosen candidate has its series
    series = {"velocity": best.velocity_cms * CM_TO_M, "pulse": best.pulse_cms * CM_TO_M}   # dt: the record's value
    return values, blocks, series


def pulses_and_directions(rec: Record, ctx: Context) -> tuple[dict, dict, dict, np.ndarray]:
    """The record's pulse values, per-block pulse values and series (:func:`_pulse_values`), and the
    direction each block is simulated along: the pulse's, or the peak vector's when no pulse was found."""
    values, blocks, series = _pulse_values(rec, ctx)
    directions = blocks.get(SCENE.block_pulse_azimuth)
    if directions is None:
        directions = _block_directions(rec, ctx.inventory, rec.pga_azimuth_deg())
    return values, blocks, series, directions


#: How the rocking plane of a scene was chosen (the ``orientation`` flag).


def simulation_mask(inventory: Inventory, config: Config) -> np.ndarray:
    """Blocks the fidelity tier sends to the simulator for one record (``config.fidelity``).

    ``criterion``: none. ``full`` and ``reference``: all; the planner then integrates nothing
    where the exact at-rest certificate holds (no uplift, no slip at any sample).
    """
    return np.full(len(inventory), config.fidelity.tier != "criterion")


def on_record(rec: Record, cfg: Config, *, scan: bool = True) -> OnRecord:
    """``rec`` as every body model's scene takes it (:class:`~pipeline.bodies.contract.OnRecord`): its planes, the
    orientation grid and, where the run samples, the draws."""
    unc = cfg.uncertainty
    z = common_normals(unc.seed, unc.samples) if scan and cfg.sampling else None
    draws = None if z is None else (z, estimation_normals(unc, unc.samples), average_normals(unc))
    setup = setup_of(cfg)
    base = motion(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, rec.dt_s) if z is not None else None
    planes = Planes(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, g_ms2=cfg.records.g_ms2)
    return OnRecord(rec, base, draws, planes, plane_grid(setup.settings.orientation_step_deg), setup, scan,
                    RunMemo())


def setup_of(cfg: Config) -> Setup:
    """The run's settings as the body models read them."""
    return Setup(cfg.simulation_settings(), cfg.uncertainty, cfg.records.g_ms2, cfg.sampling, RELOCATE_BELOW_SCALE)


def simulate_scenes(rec: Record, directions: np.ndarray, ctx: Context, mask: np.ndarray | None = None, *,
                    scan: bool = True, blocks: Sequence[Block] | None = None) -> SceneColumns:
    """Simulate the blocks in ``mask`` (default all) against one record, each by the body model that claims it
    (:func:`pipeline.bodies.registry.body_model`).

    ``scan=False`` simulates every planar block in ``directions`` only (the pulse axis for a blank azimuth), and
    samples nothing: what ``screen bench`` compares the orientation scan with. ``blocks``: the inventory's
    :meth:`~pipeline.blocks.Inventory.rocking_blocks`, when the caller simulates the same inventory many times
    (``screen fragility``).
    """
    inv = ctx.inventory
    blocks = inv.rocking_blocks(g_ms2=ctx.config.records.g_ms2) if blocks is None else blocks
    out = SceneColumns.empty(len(inv))
    on = on_record(rec, ctx.config, scan=scan)
    placement = Placement.of(rec)
    mask = np.ones(len(inv), dtype=bool) if mask is None else mask
    for j in np.flatnonzero(mask):
        block_id = str(inv.ids[j])
        ctx.progress.scene(block_id)
        t_scene = time.perf_counter()
        shape = inv.shape(int(j))
        got = body_model(shape, placement, on.setup.settings).scene(on, shape, blocks[int(j)], float(directions[j]))
        scene_values(out, int(j), got.result, got.orientation, got.probability)
        ctx.progress.scene_done(block_id=block_id, seconds=time.perf_counter() - t_scene, detail=got.detail)
    return out


def scene_values(out: SceneColumns, j: int, res: PlaneResult, orientation: int,
                 orient: OrientationProbability) -> None:
    """Scene ``j`` of ``out`` from its governing plane's simulated :class:`~pipeline.rocking.scene.Scene` (``res``),
    how its plane was chosen and its probabilities: the one place where the simulator's names become the
    schema's."""
    sc, prob = res.scene, orient.worst
    out.put(j, physics=sc.physics, response=sc.response, overturn_simulated=sc.verdict, theta_max=sc.theta_max,
            n_impacts=sc.n_impacts, time_overturn=sc.t_overturn, friction_demand=sc.friction_demand,
            friction_exceeded=sc.friction_exceeded, sliding_max=sc.sliding_max_m, free_flight=sc.free_flight,
            time_free_flight=sc.t_flight, governing_azimuth=res.azimuth_deg, orientation=orientation,
            planes_simulated=res.planes_simulated, contact_modes=sc.contact_modes, simulation_guard=sc.guard,
            p_overturn=prob.p, p_overturn_low=prob.low, p_overturn_high=prob.high, robustness=prob.robustness,
            samples_drawn=prob.drawn, samples_overturned=prob.overturned, samples_without_verdict=prob.without_verdict,
            sample_simulations=orient.simulations, p_overturn_azimuth=orient.worst_azimuth_deg,
            p_overturn_random_orientation=orient.random, p_overturn_random_orientation_low=orient.random_low,
            p_overturn_random_orientation_high=orient.random_high)


def screen_record(source: RecordSource, ctx: Context, block_ids=None, content_sha256: str | None = None
                  ) -> RecordResult:
    """Screen one record against the blocks ``block_ids`` (all when None).

    Loads the record by path inside the task; a failure comes back as the record's failed row (its ``status``),
    never raised, so one bad record never stops the batch. ``content_sha256`` is the digest the caller already
    took of the files (computed here when None).
    """
    inv = ctx.inventory
    if block_ids is not None:
        index = {b: k for k, b in enumerate(inv.ids)}
        inv = inv.take([index[b] for b in block_ids])
    task_ctx = Context(ctx.root, ctx.config, inv, ctx.declared_units, ctx.station_inventory, ctx.buildings,
                       ctx.progress)
    try:
        content = source.digest() if content_sha256 is None else content_sha256
        rec = ctx.load(source)
        values, comps = _record_values(rec, source)
        values["content_sha256"] = content
        values["screened_utc"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        pulse_values, block_values, series, directions = pulses_and_directions(rec, task_ctx)
        values.update(pulse_values)
        mask = simulation_mask(inv, ctx.config)
        ctx.progress.record(source.record_id, int(np.count_nonzero(mask)))
        motions = FloorMotions(rec, place_blocks(inv, ctx.buildings))
        on_ground = np.isin(np.arange(len(inv)), motions.groups.get((), []))
        block_values.update(simulate_scenes(rec, directions, task_ctx, mask & on_ground).columns())
        floors: dict = {}
        if motions.upper_floors:
            floor_blocks, floors = _floor_values(motions, task_ctx, mask, block_values)
            block_values.update(floor_blocks)
        return RecordResult(source.record_id, "ok", values, comps, block_values, series, floors,
                            block_ids=inv.ids, block_digests=inv.digests())
    except Exception as exc:  # a bug or an unforeseen corruption must not stop the batch either
        return failed_result(source, task_failure(exc, source.record_id))
    finally:
        ctx.progress.finished()


def _floor_values(motions: FloorMotions, ctx: Context, mask: np.ndarray, block_values: dict
                  ) -> tuple[dict, dict]:
    """Pulses and simulation of the blocks on each floor, on that floor's motion, and the floor's peaks; and
    each floor's pulse series with its record-level pulse values (none for a floor without a pulse)."""
    nb = len(ctx.inventory)
    out = {n: np.asarray(block_values.get(n, np.full(nb, np.nan)), dtype=float).copy()
           for n in PULSE_BLOCK_VARS + SIMULATION_VARS + PROBABILITY_VARS}
    out.update({n: np.full(nb, np.nan) for n in FLOOR_VARS})
    floors: dict = {}
    for key, idx in motions.upper_floors.items():
        frec = motions.record(key)
        sub = dataclasses.replace(ctx, inventory=ctx.inventory.take(idx))
        values, blocks, series, directions = pulses_and_directions(frec, sub)
        if series:
            floors[key] = {**series, "dt": frec.dt_s, **{n: float(values[n]) for n in FLOOR_PULSE_VALUES}}
        blocks.update(simulate_scenes(frec, directions, sub, mask[idx]).columns())
        for n, v in blocks.items():
            if n in out:
                out[n][idx] = v
        out[SCENE.floor_pga][idx] = frec.pga_ms2()
        out[SCENE.floor_pgv][idx] = frec.pgv_ms()
    return out, floors


def failed_result(source: RecordSource, failure: TaskFailure) -> RecordResult:
    """A task's failure (its content, a crash, a lost worker) as the record's row in the results."""
    return failure_result(as_failure(source, failure))


def failure_result(f: Failure) -> RecordResult:
    """A record that failed (in the scan or in its task), as its failed row in the results."""
    return RecordResult(f.record_id, f"failed: {f.reason}", {"files": ";".join(Path(p).name for p in f.files)},
                        deterministic=f.deterministic)


def assemble(results: list[RecordResult], inventory: Inventory, config: Config, *,
             attrs: dict | None = None, placements: list | None = None) -> xr.Dataset:
    """Build the results Dataset (dimensions ``record``, ``block``, ``component``): the records' tables stacked
    by the schema, the verdicts (:func:`_verdicts`, the paper's criterion where nothing was simulated) and the
    inventory's per-block variables."""
    results = sorted(results, key=lambda r: r.record_id)
    data_vars = {**_record_variables(results), **_block_variables(results, inventory)}
    for name, (dims, arr) in list(data_vars.items()):
        dtype = INTEGER_DTYPES.get(name) or ("i1" if "flag_values" in SCHEMA.get(name, (0, 0, 0, {}))[3] else None)
        if dtype and arr.dtype.kind == "f":                  # NaN (not evaluated) -> -1
            data_vars[name] = (dims, np.where(np.isnan(arr), -1, arr).astype(dtype))
    geom = inventory.geometry(g_ms2=config.records.g_ms2)
    margin = inventory.base_margins()
    data_vars.update(_verdicts(data_vars, inventory, geom, margin, config))
    data_vars.update(_inventory_variables(inventory, geom, margin, config, placements))
    ds = xr.Dataset(data_vars, coords={
        "record": np.array([r.record_id for r in results], dtype=object),
        "block": np.array(inventory.ids, dtype=object),
        "component": np.array(COMPONENTS, dtype=object),
    })
    ds = apply_schema(ds)
    ds.attrs.update({
        "Conventions": "CF-1.11",
        "title": "rockscreen overturning screening of free-standing rigid blocks",
        "source": f"rockscreen {__version__}",
        **{f"uncertainty_{k}": v for k, v in dataclasses.asdict(config.uncertainty).items()},
        **(attrs or {}),
    })
    return ds


def _record_variables(results: list[RecordResult]) -> dict[str, tuple]:
    """The per-record and per-component variables of the schema, stacked over the records (strings blank and
    numbers NaN where a record has none)."""
    data_vars: dict[str, tuple] = {"status": (("record",), np.array([r.status for r in results], dtype=object))}
    for name in (n for n, (dims, *_) in SCHEMA.items() if dims == ("record",) and n != "status"):
        vals = [r.values.get(name) for r in results]
        if any(v is not None for v in vals):
            sample = next(v for v in vals if v is not None)
            if isinstance(sample, str):
                arr = np.array([v if v is not None else "" for v in vals], dtype=object)
            else:
                arr = np.array([v if v is not None else np.nan for v in vals], dtype=float)
            data_vars[name] = (("record",), arr)
    for name in (n for n, (dims, *_) in SCHEMA.items() if dims == ("record", "component")):
        is_str = SCHEMA[name][1] is None                    # a code, not a quantity
        rows = [r.components.get(name, [""] * 3 if is_str else [np.nan] * 3) for r in results]
        data_vars[name] = (("record", "component"), np.array(rows, dtype=object if is_str else float))
    return data_vars


def _block_variables(results: list[RecordResult], inventory: Inventory) -> dict[str, tuple]:
    """The per-scene variables, (record, block), each record's columns put under the inventory's blocks (blocks no
    longer in the inventory are left out; NaN where a scene has no value)."""
    position = {b: k for k, b in enumerate(inventory.ids)}
    columns = []
    for r in results:
        cols = np.array([position.get(b, -1) for b in r.block_ids], dtype=np.intp)
        columns.append((cols[cols >= 0], np.flatnonzero(cols >= 0)))
    data_vars: dict[str, tuple] = {}
    for name in PULSE_BLOCK_VARS + SIMULATION_VARS + PROBABILITY_VARS + FLOOR_VARS:
        arr = np.full((len(results), len(inventory)), np.nan)
        for i, r in enumerate(results):
            if name in r.blocks:
                to, keep = columns[i]
                arr[i, to] = np.asarray(r.blocks[name], dtype=float)[keep]
        data_vars[name] = (("record", "block"), arr)
    return data_vars


def _verdicts(data_vars: dict, inventory: Inventory, geom, margin: np.ndarray, config: Config) -> dict[str, tuple]:
    """The paper's criterion on every scene's pulse (its variables), and each scene's verdict: the simulation's
    wherever a scene was simulated (-1 for free flight: no verdict), else the criterion's (the criterion tier);
    where it came from; and whether the block slid off its base."""
    scenes = criteria.evaluate(
        data_vars[SCENE.block_pulse_ap][1], data_vars[SCENE.block_pulse_tp][1], data_vars[SCENE.block_pulse_beta][1],
        data_vars[SCENE.block_pulse_dv][1], R_m=geom.R, alpha=geom.alpha, p=geom.p, mu=inventory.mu,
        g_ms2=config.records.g_ms2, form=config.criteria.form)
    out = {name: (("record", "block"), arr) for name, arr in scenes.items()}
    simulated = data_vars[SCENE.response][1] >= 0
    alone = stack_ids(inventory.stacks, len(inventory))[None, :] == ""     # a stack's body: never by the body alone
    criterion = np.where(alone, scenes["overturn_criterion"], -1)
    out["overturn"] = (("record", "block"), np.where(simulated, data_vars[SCENE.overturn_simulated][1],
                                                     criterion).astype("i1"))
    slid = np.nan_to_num(data_vars[SCENE.sliding_max][1], nan=0.0) > margin[None, :]
    out["slides_off_base"] = (("record", "block"), np.where(
        simulated & np.isfinite(margin)[None, :], slid, -1).astype("i1"))
    out["verdict_source"] = (("record", "block"), np.where(
        simulated, 1, np.where(criterion >= 0, 0, -1)).astype("i1"))
    out.update(stack_verdicts(out["overturn"][1], inventory.stacks))
    return out


def _inventory_variables(inventory: Inventory, geom, margin: np.ndarray, config: Config, placements: list | None
                         ) -> dict[str, tuple]:
    """The per-block variables: the inventory as given, its geometry, where each block stands, and the
    criterion's thresholds of each block."""
    g, form, nb = config.records.g_ms2, config.criteria.form, len(inventory)
    return {
        **{inventory_variable(c): (("block",), np.array(v, dtype=object)) for c, v in inventory.extra.items()},
        "block_name": (("block",), np.array(inventory.names, dtype=object)),
        "site": (("block",), np.array(inventory.sites, dtype=object)),
        "height": (("block",), inventory.height_m),
        "width": (("block",), inventory.width_m),
        "shape": (("block",), inventory.kinds().astype("i1")),
        "depth": (("block",), inventory.depths()),
        "half_height": (("block",), geom.h),
        "half_width": (("block",), geom.b),
        "corner_distance": (("block",), geom.R),
        "slenderness": (("block",), geom.alpha),
        "frequency_parameter": (("block",), geom.p),
        "restitution": (("block",), inventory.effective_restitution(geom)),
        "mu": (("block",), inventory.mu),
        "block_sha256": (("block",), np.array(inventory.digests(), dtype=object)),
        "block_azimuth": (("block",), inventory.azimuth_deg),
        "stands_on": (("block",), stands_on_ids(inventory.stacks, nb)),
        "stack_id": (("block",), stack_ids(inventory.stacks, nb)),
        "joint_opening": (("block",), joint_openings(inventory.stacks, nb)),
        **dict(zip(("stack_base_centre", "stack_base_height"),
                   ((("block",), v) for v in stack_placements(inventory.stacks, nb)))),
        "base_margin": (("block",), margin),
        "building": (("block",), np.array([p.building.building_id if p.building is not None else ""
                                           for p in placements] if placements else [""] * nb, dtype=object)),
        "floor_height": (("block",), np.array([p.height_m if p.building is not None else np.nan
                                               for p in placements] if placements else [np.nan] * nb)),
        "uplift_acceleration": (("block",), criteria.uplift_acceleration(geom.alpha, g_ms2=g, form=form)),
        "critical_velocity": (("block",), criteria.critical_velocity(geom.R, geom.alpha, g_ms2=g, form=form)),
        "transition_period": (("block",), criteria.transition_period(geom.p, PULSE_BETA["half-sine"])),
        "rocking_applicable": (("block",), criteria.rocking_applicable(geom.alpha).astype("i1")),
    }
