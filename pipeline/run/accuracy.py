"""``screen bench``: what accuracy costs in time, measured on real records.

Every fidelity tier (:data:`pipeline.config.FIDELITY_TIERS`) runs on the same
scenes: each record is loaded and its pulse extracted once (the common part,
timed apart), then each tier's own work is timed: the paper's criterion for
all scenes, and the simulations the tier asks for. Every tier is compared with
``reference`` (the full simulation at tight tolerances):

* overturning verdicts: misses (the reference overturns, the tier does not)
  and false alarms (the other way round), split by pulse-like and non-pulse
  records;
* max |theta| / alpha: the largest and median difference over the scenes that
  rock in the reference and in which the block stands in both.

Then the simulation's own settings are varied one at a time around the
defaults (integration tolerance, rest threshold, largest step) on the ``full``
tier, against the reference; the orientation scan (its grid step, and the
pulse axis alone as before the scan existed); the approximation that drops a
small vertical (``vertical_fraction``); and the margin scan step on each
block's worst scene, against the finest step (the error columns are then
relative margin differences).

Finally the verdicts under declared uncertainty (``[uncertainty]``): the full tier's time
without and with sampling, and how p_overturn converges with the number of samples (every
scene drawn to exactly N samples, against the largest N; the error columns are then
|p - p_largest|, and ``misses`` counts the scenes whose robustness class differs).

Results: ``OUT/bench.csv``, ``OUT/bench.md`` and ``OUT/bench.png`` (error against
time per scene). The records are held in memory for the whole run; use a
representative sample, not a whole archive.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .. import criteria
from ..blocks import Inventory
from ..bodies.contract import Placement
from ..bodies.registry import body_model
from ..config import FIDELITY_TIERS, Config
from ..errors import RockscreenError, UsageError
from ..floors.motion import Building
from ..floors.standing import floor_record
from ..records.listing import Failure, find_records
from ..records.record import Record
from ..records.side_files import read_declared_units
from ..records.side_files import read_inventory as read_station_inventory
from ..rocking.planner import Physics
from ..scene_progress import SceneProgress
from ..scene_table import SCENE, SceneColumns
from ..store import Family, OutputLock, publish_staged, write_csv_atomic, write_text_atomic
from .bench_solids import solid_rows
from .screening import Context, pulses_and_directions, simulate_scenes, simulation_mask

COLUMNS = ("section", "setting", "value", "time_s", "time_per_scene_us", "scenes_simulated",
           SCENE.planes_simulated, "scenes", "misses", "false_alarms", "misses_pulse", "false_alarms_pulse",
           "misses_non_pulse", "false_alarms_non_pulse", "theta_error_max", "theta_error_median")


@dataclasses.dataclass
class _Scene:
    """Per-record data shared by the tiers."""

    record: Record
    blocks: dict
    directions: np.ndarray
    is_pulse: int


def _load(records_dir: Path, inventory: Inventory, config: Config) -> tuple[list[_Scene], float, list[Failure]]:
    """Every record of ``records_dir`` loaded, with its pulses along the blocks' directions; the time that took
    [s]; and the records that could not be (from the scan, or named with the reason they failed to load)."""
    sources, failures = find_records(records_dir, config=config)
    failures = list(failures)
    ctx = Context(str(records_dir), config, inventory, read_declared_units(records_dir, config),
                  read_station_inventory(records_dir))
    out, t_common = [], 0.0
    for src in sources:
        try:
            t0 = time.perf_counter()
            rec = ctx.load(src)
            values, blocks, _, directions = pulses_and_directions(rec, ctx)
            t_common += time.perf_counter() - t0
        except RockscreenError as exc:
            failures.append(Failure(src.record_id, tuple(str(f) for f in src.files), str(exc), deterministic=True))
            continue
        out.append(_Scene(record=rec, blocks=blocks, directions=directions, is_pulse=int(values.get("is_pulse", -1))))
    if not out:
        raise UsageError(f"{records_dir}: no record could be screened ("
                         + "; ".join(f"{f.record_id}: {f.reason}" for f in failures[:5]) + "); nothing to benchmark")
    return out, t_common, failures


def _criterion(scenes: list[_Scene], inventory: Inventory, config: Config) -> tuple[np.ndarray, float]:
    """The criterion's verdict for every scene (records x blocks) and its time."""
    nb = len(inventory)
    arrays = {n: np.vstack([s.blocks.get(n, np.full(nb, np.nan)) for s in scenes])
              for n in (SCENE.block_pulse_ap, SCENE.block_pulse_tp, SCENE.block_pulse_beta, SCENE.block_pulse_dv)}
    geom = inventory.geometry(g_ms2=config.records.g_ms2)
    t0 = time.perf_counter()
    out = criteria.evaluate(arrays[SCENE.block_pulse_ap], arrays[SCENE.block_pulse_tp],
                            arrays[SCENE.block_pulse_beta], arrays[SCENE.block_pulse_dv], R_m=geom.R,
                            alpha=geom.alpha, p=geom.p, mu=inventory.mu, g_ms2=config.records.g_ms2,
                            form=config.criteria.form)
    return out["overturn_criterion"], time.perf_counter() - t0


class _SceneTimes(SceneProgress):
    """A progress reporter that keeps each scene's wall-clock time (the bench's worst-scene rows)."""

    def __init__(self) -> None:
        super().__init__()
        self.times: list[tuple[float, str]] = []

    def scene_done(self, *, block_id: str, seconds: float, detail) -> None:
        self.times.append((seconds, f"{self._state.get('record', '?')} x {block_id}"))


def _simulate(scenes: list[_Scene], inventory: Inventory, config: Config, *, scan: bool = True,
              times: _SceneTimes | None = None) -> tuple[SceneColumns, float]:
    """Simulate what the tier of ``config`` asks for: every scene's simulated values (records x blocks; the verdict
    -1 and the counts 0 where not simulated), and the time (each scene's in ``times``, when given)."""
    ctx = Context("", config, inventory, {}, progress=times if times is not None else SceneProgress())
    tables = []
    t = 0.0
    for s in scenes:
        ctx.progress.record(s.record.record_id, len(inventory))
        t0 = time.perf_counter()
        tables.append(simulate_scenes(s.record, s.directions, ctx, simulation_mask(inventory, config), scan=scan))
        t += time.perf_counter() - t0
    grid = SceneColumns.stack(tables)
    grid.overturn_simulated = np.where(np.isnan(grid.overturn_simulated), -1, grid.overturn_simulated).astype(int)
    grid.planes_simulated = np.nan_to_num(grid.planes_simulated)
    grid.free_flight = np.nan_to_num(grid.free_flight)
    grid.friction_exceeded = np.nan_to_num(grid.friction_exceeded)
    grid.sample_simulations = np.nan_to_num(grid.sample_simulations)
    return grid, t


def _agreement(tier_verdict: np.ndarray, tier_theta: np.ndarray, ref: SceneColumns, is_pulse: np.ndarray) -> dict:
    """Misses and false alarms against the reference (split by pulse class), theta_max error."""
    judged = ref.overturn_simulated >= 0
    ref_yes = judged & (ref.overturn_simulated == 1)
    yes = tier_verdict == 1
    miss, alarm = ref_yes & ~yes, judged & ~ref_yes & yes
    pulse = np.broadcast_to(is_pulse[:, None] == 1, miss.shape)
    # theta error over the scenes that rock (reference theta > 0) and stand in both
    both = np.isfinite(tier_theta) & (np.nan_to_num(ref.theta_max) > 0) & ~yes & judged & ~ref_yes
    err = np.abs(tier_theta[both] - ref.theta_max[both])
    return {"misses": int(miss.sum()), "false_alarms": int(alarm.sum()),
            "misses_pulse": int((miss & pulse).sum()), "false_alarms_pulse": int((alarm & pulse).sum()),
            "misses_non_pulse": int((miss & ~pulse).sum()), "false_alarms_non_pulse": int((alarm & ~pulse).sum()),
            "theta_error_max": float(err.max()) if err.size else np.nan,
            "theta_error_median": float(np.median(err)) if err.size else np.nan}


class Bench(NamedTuple):
    """What ``screen bench`` measured: the rows of its table (:data:`COLUMNS`) and the records it could not use
    (each with its reason; the bench measured the others)."""

    rows: list[dict]
    failures: list[Failure]


def run_bench(records_dir: str | Path, inventory: Inventory, config: Config, *, out_dir: str | Path,
              settings_sweep: bool = True, progress=None) -> Bench:
    """Run every tier (and the settings sweep) and write bench.csv, bench.md and bench.png.

    ``progress``, when given, is called with a line before each measurement (each takes seconds to minutes).

    Returns
    -------
    Bench
        The rows of the table and the records that failed.
    """
    records_dir, out_dir = Path(records_dir), Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    rows: list[dict] = []
    total = SECTIONS_TIERS + (SECTIONS_SWEEP + len(CONVERGENCE_SAMPLES) if settings_sweep else 0)
    done = {"sections": 0}

    def say(what: str) -> None:
        """Announce the next measurement (its number among the bench's sections and the time so far: the sections
        differ in cost too much for an estimate of the time left to be honest), and write the rows measured so
        far (an interrupted bench keeps its finished sections)."""
        if rows:
            _write(rows, out_dir)
        done["sections"] += 1
        if progress is None:
            return
        progress(f"bench: section {done['sections']} of {total}: {what} ({time.perf_counter() - t_start:.0f} s "
                 "so far)")

    sampled = config if config.with_tier("full").sampling else Config().with_tier(config.fidelity.tier)
    config = config.with_uncertainty(samples=0)           # the tiers and settings compare nominal verdicts
    say("reading the records and extracting their pulses")
    scenes, t_common, failures = _load(records_dir, inventory, config)
    is_pulse = np.array([s.is_pulse for s in scenes])
    n_scenes = len(scenes) * len(inventory)
    say(f"the criterion on {n_scenes} scenes")
    crit, t_crit = _criterion(scenes, inventory, config)
    say("the reference tier")
    ref, t_ref = _simulate(scenes, inventory, config.with_tier("reference"))
    rows.append({"section": "common", "setting": "load records and extract pulses", "value": "",
                 "time_s": t_common, "time_per_scene_us": 1e6 * t_common / n_scenes, "scenes": n_scenes})
    for tier in FIDELITY_TIERS:
        say(f"tier {tier}")
        cfg = config.with_tier(tier)
        sim, t_sim = (ref, t_ref) if tier == "reference" else _simulate(scenes, inventory, cfg)
        simulated = sim.overturn_simulated >= 0
        verdict = np.where(simulated, sim.overturn_simulated, crit)
        t = t_crit + t_sim
        rows.append({"section": "tier", "setting": "fidelity", "value": tier, "time_s": t,
                     "time_per_scene_us": 1e6 * t / n_scenes, "scenes_simulated": int((sim.physics >= 0).sum()),
                     SCENE.planes_simulated: int(sim.planes_simulated.sum()),
                     "scenes": n_scenes, **_agreement(verdict, sim.theta_max, ref, is_pulse)})
    try:
        say("the slowest scenes, on the records and on the tie mu = tan(alpha)")
        rows += _worst_scene_rows(scenes, inventory, config)
        rows += solid_rows(scenes, inventory, config)
        if settings_sweep:
            _settings_sweep(scenes, inventory, config, ref, is_pulse, n_scenes, say, rows)
            rows += _uncertainty_rows(scenes, inventory, sampled, n_scenes, say)
    finally:                     # every finished section is written, also when interrupted
        _write(rows, out_dir)
    return Bench(rows, failures)


#: The bench's sections (each announced): the records, the criterion, the reference, the tiers and the slowest
#: scenes; and with the settings sweep its 16 settings, 7 orientation variants, the contact model, floors, margin
#: steps and the nominal and sampled runs, plus one per convergence sample size
SECTIONS_TIERS = 4 + len(FIDELITY_TIERS)
SECTIONS_SWEEP = 16 + 7 + 3 + 2


def _worst_scene_rows(scenes, inventory: Inventory, config: Config) -> list[dict]:
    """The slowest scenes of the full tier (nominal), on the records as they are and on a boundary set: every
    block with its friction set to tan(alpha) exactly (the tie of :mod:`pipeline.rocking.rules`, rule 1), so that
    a slow pathological scene shows as a number."""
    geom = inventory.geometry(g_ms2=config.records.g_ms2)
    sets = (("records x inventory", inventory),
            ("boundary set: records x inventory with mu = tan(alpha)",
             dataclasses.replace(inventory, mu=np.tan(geom.alpha))))
    rows = []
    for label, inv in sets:
        times = _SceneTimes()
        _simulate(scenes, inv, config.with_tier("full"), times=times)
        ordered = sorted(times.times, reverse=True)
        seconds = np.array([t for t, _ in ordered])
        for rank, (t, which) in enumerate(ordered[:3], 1):
            rows.append({"section": "worst scenes", "setting": f"{label}: slowest #{rank} ({which})",
                         "value": f"{t / max(float(np.median(seconds)), 1e-9):.0f}x the median", "time_s": t,
                         "time_per_scene_us": 1e6 * t, "scenes": len(seconds)})
        rows.append({"section": "worst scenes", "setting": f"{label}: median scene", "value": "",
                     "time_s": float(np.median(seconds)), "time_per_scene_us": 1e6 * float(np.median(seconds)),
                     "scenes": len(seconds)})
    return rows


def _settings_sweep(scenes, inventory, config, ref, is_pulse, n_scenes, say, rows: list[dict]) -> None:
    """The simulation settings, orientation variants, contact model, floors and margin steps, appended to ``rows``
    as each is measured."""
    sweeps = {"rtol": (1e-4, 1e-5, 1e-6, 1e-7, 1e-9), "rest_ratio": (1e-3, 1e-4, 1e-5, 1e-6, 1e-8),
              "max_step_p": (0.2, 0.1, 0.05, 0.02), "closed_form_chatter": (True, False)}
    full = config.with_tier("full")
    for name, values in sweeps.items():
        for v in values:
            say(f"simulation setting {name} = {v:g}")
            cfg = dataclasses.replace(full, simulation=dataclasses.replace(full.simulation, **{name: v}))
            sim, t = _simulate(scenes, inventory, cfg)
            default = getattr(config.simulation, name) == v
            rows.append({"section": "simulation", "setting": name + (" (default)" if default else ""), "value": v,
                         "time_s": t, "time_per_scene_us": 1e6 * t / n_scenes,
                         "scenes_simulated": int((sim.overturn_simulated >= 0).sum()), "scenes": n_scenes,
                         **_agreement(sim.overturn_simulated, sim.theta_max, ref, is_pulse)})
    # the orientation scan: coarser grids, no refinement, and the pulse axis alone (no scan)
    variants: list[tuple[str, float | str, dict[str, float], bool]] = [
        ("orientation_step_deg", v, {"orientation_step_deg": v}, True) for v in (5.0, 10.0, 15.0, 30.0)]
    variants += [("orientation_refine_deg", 0.0, {"orientation_refine_deg": 0.0}, True),
                 ("pulse axis only (no scan)", "", {}, False),
                 ("vertical_fraction (approximation)", 0.05, {"vertical_fraction": 0.05}, True)]
    for label, value, change, scanned in variants:
        say(f"{label} {value}")
        cfg = dataclasses.replace(full, simulation=dataclasses.replace(full.simulation, **change))
        sim, t = _simulate(scenes, inventory, cfg, scan=scanned)
        default = bool(change) and all(getattr(config.simulation, k) == x for k, x in change.items())
        section = "vertical" if label.startswith("vertical") else "orientation"
        rows.append({"section": section, "setting": label + (" (default)" if default else ""), "value": value,
                     "time_s": t, "time_per_scene_us": 1e6 * t / n_scenes,
                     "scenes_simulated": int((sim.overturn_simulated >= 0).sum()),
                     SCENE.planes_simulated: int(sim.planes_simulated.sum()), "scenes": n_scenes,
                     **_agreement(sim.overturn_simulated, sim.theta_max, ref, is_pulse)})
    say("the general contact model against pure rocking and flags")
    rows += _contact_rows(scenes, inventory, full, n_scenes)
    say("the floor filter of a building")
    rows += _floor_rows(scenes)
    say("margin scan steps")
    rows += _margin_sweep(scenes, inventory, full, ref)


#: The building the floor-filter row measures: a 6-storey museum (T1 0.6 s, 5 % damping, alpha 3, 21 m).
BENCH_BUILDING = Building("bench-museum", 0.6, 0.05, 3.0, 21.0, 6)


def _floor_rows(scenes) -> list[dict]:
    """What a floor costs: the floor motion (both horizontals and their velocities) of the top floor of
    :data:`BENCH_BUILDING` under every record, computed once per record and floor and shared by its blocks."""
    t0 = time.perf_counter()
    for s in scenes:
        floor_record(s.record, BENCH_BUILDING, BENCH_BUILDING.height_m * 5 / 6)
    t = time.perf_counter() - t0
    return [{"section": "floors", "setting": "floor motion of one floor per record (6-storey museum, top floor)",
             "value": len(scenes), "time_s": t, "time_per_scene_us": 1e6 * t / max(len(scenes), 1),
             "scenes": len(scenes)}]


def _contact_rows(scenes, inventory, config, n_scenes) -> list[dict]:
    """What the general contact model costs and changes: the whole simulation with it and without it (pure
    rocking with flags, free flight without a verdict), the scenes that need it, and their cost per scene."""
    off = dataclasses.replace(config, simulation=dataclasses.replace(config.simulation, contact_model=False))
    rows = []
    runs = {}
    for label, cfg in (("contact_model = false: pure rocking with flags, free flight without a verdict", off),
                       ("contact_model = true (default): the general model where pure rocking stops holding",
                        config)):
        sim, t = _simulate(scenes, inventory, cfg)
        runs[cfg.simulation.contact_model] = (sim, t)
        general = int(np.sum(sim.physics == Physics.general))
        rows.append({"section": "contact model", "setting": label, "value": int(cfg.simulation.contact_model),
                     "time_s": t, "time_per_scene_us": 1e6 * t / n_scenes, "scenes": n_scenes,
                     "scenes_simulated": general, SCENE.planes_simulated: int(sim.planes_simulated.sum())})
    (on, t_on), (flagged, t_off) = runs[True], runs[False]
    general = on.physics == Physics.general
    before, after = flagged.overturn_simulated[general], on.overturn_simulated[general]
    for what, sel in (("verdicts given where free flight had none", before == -1),
                      ("verdicts changed from overturn to stand", (before == 1) & (after == 0)),
                      ("verdicts changed from stand to overturn", (before == 0) & (after == 1))):
        rows.append({"section": "contact model", "setting": what, "value": int(np.sum(sel)),
                     "scenes": int(np.sum(general))})
    per_scene = (t_on - t_off) / max(int(np.sum(general)), 1)
    rows.append({"section": "contact model", "setting": "extra time per scene that needs the general model",
                 "value": "", "time_s": per_scene, "time_per_scene_us": 1e6 * per_scene,
                 "scenes": int(np.sum(general))})
    return rows


#: Largest numbers of samples compared in the convergence rows (the last is the yardstick).
CONVERGENCE_SAMPLES = (10, 20, 40, 80)


#: Bands on the nominal max theta/alpha measured as a sampling shortcut: scenes below one would go unsampled.
SAMPLE_BANDS = (0.0, 0.05, 0.1, 0.2, 0.5)


def _uncertainty_rows(scenes, inventory, config, n_scenes, say) -> list[dict]:
    """The probabilistic run's cost against the nominal one, and p_overturn against the number of samples.

    Rows ``uncertainty`` / ``nominal`` and ``samples (the configuration)``: time of the full tier
    without and with sampling (time includes the nominal simulation). Rows ``convergence``: every
    scene drawn to exactly N samples (no early stop: one batch of N), compared with the largest N;
    the error columns hold max / median |p - p_largest| and ``misses`` the scenes whose robustness
    class differs from the largest N's.
    """
    full = config.with_tier("full")
    say("nominal verdicts (samples = 0)")
    _, t_nominal = _simulate(scenes, inventory, full.with_uncertainty(samples=0))
    say(f"sampled verdicts (samples = {full.uncertainty.samples})")
    prob, t_prob = _simulate(scenes, inventory, full)
    u = full.uncertainty
    rows = [{"section": "uncertainty", "setting": "nominal (samples = 0)", "value": 0, "time_s": t_nominal,
             "time_per_scene_us": 1e6 * t_nominal / n_scenes, "scenes": n_scenes},
            {"section": "uncertainty", "setting": f"samples (batch {u.batch}, sequential stop)", "value": u.samples,
             "time_s": t_prob, "time_per_scene_us": 1e6 * t_prob / n_scenes, "scenes": n_scenes,
             "scenes_simulated": int(np.isfinite(prob.p_overturn).sum())}]
    rows += _band_rows(prob, u.robust_below, n_scenes)
    runs = {}
    for n in CONVERGENCE_SAMPLES:
        say(f"convergence: {n} samples per scene")
        cfg = dataclasses.replace(full, uncertainty=dataclasses.replace(u, samples=n, batch=n))
        runs[n] = _simulate(scenes, inventory, cfg)
    best = runs[CONVERGENCE_SAMPLES[-1]][0]
    for n in CONVERGENCE_SAMPLES:
        sim, t = runs[n]
        ok = np.isfinite(sim.p_overturn) & np.isfinite(best.p_overturn)
        d = np.abs(sim.p_overturn[ok] - best.p_overturn[ok])
        rows.append({"section": "convergence", "setting": "samples per scene (no early stop)", "value": n,
                     "time_s": t, "time_per_scene_us": 1e6 * t / n_scenes, "scenes": n_scenes,
                     "scenes_simulated": int(ok.sum()), "misses": int((sim.robustness != best.robustness)[ok]
                                                                     .sum()),
                     "theta_error_max": float(d.max()) if d.size else np.nan,
                     "theta_error_median": float(np.median(d)) if d.size else np.nan})
    return rows


def _band_rows(prob: SceneColumns, robust_below: float, n_scenes: int) -> list[dict]:
    """What a band on the nominal max theta/alpha would leave out, measured against sampling every scene.

    A scene would go unsampled when its nominal scene stands with no flag (no free flight, friction not
    exceeded) and its max theta/alpha is below the band. ``misses``: those scenes whose sampled
    p_overturn is at least ``robust_below``; ``planes_simulated``: the sampled planes they cost;
    ``theta_error_max`` (as in the convergence rows, a probability here): the largest p among them.
    """
    theta = np.nan_to_num(prob.theta_max, nan=0.0)
    flagged = (prob.overturn_simulated == 1) | (prob.free_flight != 0) | (prob.friction_exceeded == 1)
    p = np.nan_to_num(prob.p_overturn, nan=0.0)
    cost = np.maximum(prob.sample_simulations, 0)
    rows = []
    for band in SAMPLE_BANDS:
        below = ~flagged & ((theta <= 0.0) if band == 0.0 else (theta < band))
        rows.append({"section": "sample band", "setting": "nominal max theta/alpha below which a standing, unflagged "
                     "scene is not sampled (0: never lifted)", "value": band, "time_s": np.nan,
                     "time_per_scene_us": np.nan, "scenes": n_scenes, "scenes_simulated": int((~below).sum()),
                     SCENE.planes_simulated: int(cost[below].sum()),
                     "misses": int((below & (p >= robust_below)).sum()),
                     "theta_error_max": float(p[below].max()) if below.any() else np.nan})
    return rows


def _margin_sweep(scenes, inventory, config, ref) -> list[dict]:
    """Margin scans on each block's worst simulated scene (in its governing plane), for several steps, against
    the finest."""
    rocking_blocks = inventory.rocking_blocks(g_ms2=config.records.g_ms2)
    theta = np.nan_to_num(ref.theta_max, nan=-1.0)
    worst = np.argmax(np.where(ref.overturn_simulated == 1, np.inf, theta), axis=0)
    steps = (0.04, 0.02, 0.01, 0.005)
    margins, times = {}, {}
    for step in steps:
        settings = dataclasses.replace(config.simulation, margin_step=step)
        t0 = time.perf_counter()
        out = []
        for j, i in enumerate(worst):
            rec = scenes[i].record
            plane = ref.governing_azimuth[i, j]
            plane = float(scenes[i].directions[j] if np.isnan(plane) else plane)
            shape = inventory.shape(j)
            model = body_model(shape, Placement.of(rec), settings)        # the model its scenes were judged by
            out.append(model.scale(rec, shape, rocking_blocks[j], plane, settings=settings,
                                   g_ms2=config.records.g_ms2))
        times[step], margins[step] = time.perf_counter() - t0, np.array(out)
    finest = margins[min(steps)]
    rows = []
    for step in steps:
        ok = np.isfinite(finest) & np.isfinite(margins[step])
        rel = np.abs(margins[step][ok] / finest[ok] - 1.0)
        rows.append({"section": "margin", "setting": "margin_step" + (
            " (default)" if step == config.simulation.margin_step else ""), "value": step,
            "time_s": times[step], "time_per_scene_us": 1e6 * times[step] / len(worst),
            "scenes_simulated": len(worst), "scenes": len(worst),
            "theta_error_max": float(rel.max()) if rel.size else np.nan,
            "theta_error_median": float(np.median(rel)) if rel.size else np.nan})
    return rows


def _write(rows: list[dict], out_dir: Path) -> None:
    """Publish bench.csv, bench.md and bench.png as one set (:func:`pipeline.store.publish_staged`)."""
    def write(stage: Path) -> list[Path]:
        return [write_csv_atomic(stage / "bench.csv", COLUMNS, rows),
                write_text_atomic(stage / "bench.md", markdown(rows)), _plot(rows, stage / "bench.png")]

    with OutputLock(out_dir, command="screen bench"):
        publish_staged(out_dir, write, family=Family.BENCH, command="screen bench")


def markdown(rows: list[dict]) -> str:
    """The table as Markdown (the margin rows' error columns are relative margin differences)."""
    head = ("| section | setting | value | time [s] | per scene [us] | simulated | planes | "
            "misses (pulse / non-pulse) | false alarms (pulse / non-pulse) | theta/alpha error max / median |")
    lines = [head, "|" + "---|" * 10]
    fmt = lambda x, d=3: "" if x in ("", None) or (isinstance(x, float) and np.isnan(x)) else (  # noqa: E731
        f"{x:.{d}g}" if isinstance(x, float) else str(x))
    for r in rows:
        mp = (f"{r['misses']} ({r['misses_pulse']} / {r['misses_non_pulse']})" if "misses_pulse" in r
              else str(r.get("misses", "")))
        fa = (f"{r['false_alarms']} ({r['false_alarms_pulse']} / {r['false_alarms_non_pulse']})"
              if "false_alarms_pulse" in r else str(r.get("false_alarms", "")))
        err = (f"{fmt(r.get('theta_error_max', ''))} / {fmt(r.get('theta_error_median', ''))}"
               if "theta_error_max" in r else "")
        lines.append(f"| {r['section']} | {r['setting']} | {fmt(r['value'])} | {fmt(r.get('time_s'))} | "
                     f"{fmt(r.get('time_per_scene_us'))} | {r.get('scenes_simulated', '')} | "
                     f"{r.get(SCENE.planes_simulated, '')} | {mp} | {fa} | {err} |")
    return "\n".join(lines) + "\n"


def _plot(rows: list[dict], path: Path) -> Path:
    from ..report.mpl import new_figure, save_figure

    fig = new_figure(figsize=(13, 5.2), layout="constrained")
    ax, ax2 = fig.subplots(1, 2)
    tiers = [r for r in rows if r["section"] == "tier"]
    for r, marker in zip(tiers, ("o", "s", "D", "^", "v")):
        wrong = max(r["misses"] + r["false_alarms"], 0.5)
        ax.scatter(r["time_per_scene_us"], wrong, s=40, marker=marker,
                   label=f"{r['value']}: {r['misses']} missed, {r['false_alarms']} false alarms")
    if tiers:                                   # named in a legend beside the panel: no label over another
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(0.0, -0.18), borderaxespad=0.0, frameon=False)
    markers = {"rtol": "o", "rest_ratio": "s", "max_step_p": "^"}
    for name, marker in markers.items():
        sweep = [r for r in rows if r["section"] == "simulation" and r["setting"].split()[0] == name]
        sweep = [r for r in sweep if np.isfinite(r.get("theta_error_median", np.nan))]
        if not sweep:
            continue
        x = [r["time_per_scene_us"] for r in sweep]
        y = [max(r["theta_error_median"], 1e-16) for r in sweep]        # 0 drawn at 1e-16 on the log axis
        ax2.plot(x, y, marker=marker, lw=0.8, label=name)
        for r, xi, yi in zip(sweep, x, y):
            ax2.annotate(f"{r['value']:g}", (xi, yi), fontsize=7, xytext=(3, 3), textcoords="offset points")
    if ax2.lines:
        ax2.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0,
                   title="setting (values beside the points)", title_fontsize=8)
    else:
        ax2.text(0.5, 0.5, "settings not swept (--tiers-only)", transform=ax2.transAxes, ha="center")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time per scene [us]")
    ax.set_ylabel("wrong verdicts vs reference (0 drawn at 0.5)")
    ax.set_title("fidelity tiers", fontsize=10)
    if ax2.lines:
        ax2.set_xscale("log")
        ax2.set_yscale("log")
    ax2.set_xlabel("time per scene [us]")
    ax2.set_ylabel("median theta_max/alpha error vs reference")
    ax2.set_title("simulation settings (full tier)", fontsize=10)
    for a in (ax, ax2):
        a.grid(which="both", alpha=0.3)
    return save_figure(fig, path, dpi=100)
