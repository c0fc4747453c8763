"""The stripes of ``screen fragility``: every record scaled to every level and every block judged as ``screen``
judges it (certificate, simulator, orientation scan; p_overturn with [uncertainty] samples), one executor task per
record, cached per record under ``OUT/.rockscreen/fragility`` so that a re-run or a resumed run computes only what is
missing.

For the IM ``sa`` (Sa at the block's own period 2 pi / p) the factor differs per block. A record whose IM is zero or
undefined (no pulse for ``ap``) cannot be scaled: it is left out of every stripe of that block, and the run says so.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import criteria
from ..blocks import Inventory
from ..config import Config
from ..constants import STATE_DIR
from ..floors.buildings import place_blocks
from ..floors.standing import FloorMotions
from ..records.intensity import record_measures, scale_factors
from ..records.listing import Failure, Listing, list_directory
from ..records.side_files import read_declared_units
from ..rocking.scene import Response
from ..scene_table import SCENE
from ..uncertainty.hazard import Component
from .batch import record_content
from .cache import ENTRY_FORMAT, RecordStore, run_key
from .engine import RecordJobs
from .screening import Context, pulses_and_directions, simulate_scenes

#: The per-record results that have one row per level (merged and ordered with the levels)
STRIPE_KEYS = ("verdict", "p", "p_random", "p_unknown", "slides", "factor")
#: The responses that count as sliding in a stripe (:class:`~pipeline.rocking.scene.Response`)
SLIDING_CODES = (int(Response.slide), int(Response.slide_rock))


@dataclass(frozen=True)
class FragilityContext:
    """What every fragility task needs (picklable)."""

    base: Context
    im: str
    levels: tuple
    component: Component = Component.rotd100


def record_ims(rec, blocks: dict, inventory: Inventory, *, g_ms2: float, component: Component = Component.rotd100
               ) -> dict[str, np.ndarray]:
    """Every IM of the unscaled record, per block (shape (n_blocks,)): the record's own
    (:func:`~pipeline.records.intensity.record_measures`, at each block's Sa period) and its pulse's along each
    block (``blocks``: the screening's ``block_pulse_*`` values)."""
    nb = len(inventory)
    geo = inventory.geometry(g_ms2=g_ms2)
    out = record_measures(rec, 2.0 * math.pi / geo.p, component=component.value, g_ms2=g_ms2)
    dv = np.abs(blocks.get(SCENE.block_pulse_dv, np.full(nb, np.nan)))
    v_crit = criteria.critical_velocity(geo.R, geo.alpha, g_ms2=g_ms2)
    return {**out, "ap": np.asarray(blocks.get(SCENE.block_pulse_ap, np.full(nb, np.nan)), dtype=float),
            "tp": np.asarray(blocks.get(SCENE.block_pulse_tp, np.full(nb, np.nan)), dtype=float),
            "velocity_ratio": dv / v_crit}


def judge_record(rec, base: Context, im: str, levels, component: Component = Component.rotd100) -> dict:
    """One loaded record at every level against every block: outcomes, p_overturn, factors and IMs.

    Returns
    -------
    dict
        ``verdict`` (levels, blocks) int8 (1, 0, -1 no verdict or not scalable), ``p`` (levels, blocks: the
        worst orientation), ``p_random`` (levels, blocks: an unknown orientation), ``p_unknown`` (levels,
        blocks: the fraction of the samples without a verdict, NaN not sampled), ``slides`` (levels, blocks
        int8: the nominal scene slides or slide-rocks, -1 not simulated), ``factor`` (levels, blocks) and
        ``im.<name>`` (blocks) for every IM of :data:`IMS`.
    """
    _, blocks, _, directions = pulses_and_directions(rec, base)
    g = base.config.records.g_ms2
    ims = record_ims(rec, blocks, base.inventory, g_ms2=g, component=component)
    levels = np.asarray(levels, dtype=float)
    factors = scale_factors(ims[im], levels, im)
    nb = len(base.inventory)
    verdict = np.full((len(levels), nb), -1, dtype="i1")
    prob = np.full((len(levels), nb), np.nan)
    prob_random = np.full((len(levels), nb), np.nan)
    unknown = np.full((len(levels), nb), np.nan)
    slides = np.full((len(levels), nb), -1, dtype="i1")
    # blocks on floors: each floor's blocks are judged on that floor's motion, scaled by the factor that brings
    # the *ground* record to the level (the filter is linear: the floor of the scaled ground is the scaled
    # floor), so the fragility stays a function of the ground IM the hazard gives
    motions = FloorMotions(rec, place_blocks(base.inventory, base.buildings))
    for key, idx in motions.groups.items():
        sub = dataclasses.replace(base, inventory=base.inventory.take(idx))
        if key:
            _, gblocks, _, gdirections = pulses_and_directions(motions.record(key), sub)
        else:                                      # the ground's blocks: the pulses already extracted above
            gdirections, gblocks = directions[idx], {n: np.asarray(v)[idx] for n, v in blocks.items()}
        part = _judge_levels(motions.record(key), sub, gblocks, gdirections, factors[:, idx])
        verdict[:, idx], prob[:, idx], prob_random[:, idx], unknown[:, idx], slides[:, idx] = part
    return {"record_id": rec.record_id, "verdict": verdict, "p": prob, "p_random": prob_random,
            "p_unknown": unknown, "slides": slides, "factor": factors,
            **{f"im.{k}": v for k, v in ims.items()}}


def _judge_levels(rec, ctx: Context, blocks: dict, directions: np.ndarray, factors: np.ndarray):
    """Verdicts, probabilities, fractions of samples without a verdict and sliding (levels, blocks) of the blocks of
    ``ctx`` on ``rec`` scaled by ``factors``."""
    g = ctx.config.records.g_ms2
    nl, nb = factors.shape
    verdict = np.full((nl, nb), -1, dtype="i1")
    prob = np.full((nl, nb), np.nan)
    prob_random = np.full((nl, nb), np.nan)
    unknown = np.full((nl, nb), np.nan)
    slides = np.full((nl, nb), -1, dtype="i1")
    simulate = ctx.config.fidelity.tier != "criterion"
    geo = ctx.inventory.geometry(g_ms2=g)
    rocking_blocks = ctx.inventory.rocking_blocks(g_ms2=g)  # once: Sa gives every block its own factor
    ap = np.asarray(blocks.get(SCENE.block_pulse_ap, np.full(nb, np.nan)), dtype=float)
    tp = np.asarray(blocks.get(SCENE.block_pulse_tp, np.full(nb, np.nan)), dtype=float)
    for j in range(nl):
        for f in np.unique(factors[j][np.isfinite(factors[j])]):
            sel = factors[j] == f
            if simulate:
                sim = simulate_scenes(rec.scaled(float(f)), directions, ctx, sel, blocks=rocking_blocks)
                verdict[j, sel] = np.nan_to_num(sim.overturn_simulated[sel], nan=-1).astype("i1")
                prob[j, sel] = sim.p_overturn[sel]
                prob_random[j, sel] = sim.p_overturn_random_orientation[sel]
                drawn = sim.samples_drawn[sel]
                with np.errstate(invalid="ignore", divide="ignore"):
                    unknown[j, sel] = np.where(drawn > 0, sim.samples_without_verdict[sel] / drawn, np.nan)
                slides[j, sel] = np.where(np.isfinite(sim.response[sel]),
                                          np.isin(sim.response[sel], SLIDING_CODES), -1).astype("i1")
            else:
                crit = criteria.evaluate(f * ap, tp, blocks.get(SCENE.block_pulse_beta, np.nan),
                                         f * np.asarray(blocks.get(SCENE.block_pulse_dv, np.nan)), R_m=geo.R,
                                         alpha=geo.alpha, p=geo.p, mu=ctx.inventory.mu, g_ms2=g,
                                         form=ctx.config.criteria.form)
                verdict[j, sel] = np.asarray(crit["overturn_criterion"])[sel]
    return verdict, prob, prob_random, unknown, slides


def fragility_task(item: tuple, ctx: FragilityContext) -> dict:
    """Executor task: load one record by path and :func:`judge_record` it (run under the engine's failure policy,
    :class:`~pipeline.run.engine.Guarded`: what it raises comes back as the record's failure)."""
    source, content = item
    try:
        ctx.base.progress.record(source.record_id, len(ctx.levels) * len(ctx.base.inventory))
        out = judge_record(ctx.base.load(source), ctx.base, ctx.im, ctx.levels, ctx.component)
        out.update(record_id=source.record_id, content=content)
        return out
    finally:
        ctx.base.progress.finished()


class FragilityCache(RecordStore):
    """Per-record fragility results under ``OUT/.rockscreen/fragility`` (resumable runs)."""

    what = "fragility cache"

    def __init__(self, out_dir: Path, key: str):
        super().__init__(Path(out_dir) / STATE_DIR / "fragility", key)

    def load(self, record_id: str, content: str) -> dict | None:
        z = self._read(self.path(record_id, content))
        if z is None:
            return None
        out = {k: v for k, v in z.items() if k != "entry_format"}
        out["record_id"], out["content"] = record_id, content
        return out

    def save(self, result: dict) -> None:
        arrays = {k: np.asarray(v) for k, v in result.items() if k not in ("record_id", "content")}
        self._write(self.path(result["record_id"], result["content"]), arrays)


def fragility_key(config: Config, inventory: Inventory, im: str, levels, declared: dict,
                  stationxml_sha256: str = "", component: Component = Component.rotd100,
                  buildings: dict | None = None) -> str:
    """Everything besides a record that its fragility results depend on."""
    # the declared units are in each record's content digest (batch.record_content), not in this key
    payload = json.dumps({"run": run_key(config.to_dict(), declared_units={},
                                         station_inventory_sha256=stationxml_sha256, buildings=buildings), "im": im,
                          "component": component.value,
                          "levels": [float(x) for x in levels], "blocks": list(inventory.digests()),
                          "entry_format": ENTRY_FORMAT}, sort_keys=True)
    return hashlib.sha256(payload.encode()).hexdigest()


def run_stripes(records_dir: Path, inventory: Inventory, config: Config, *, im: str, levels: np.ndarray,
                executor, out_dir: Path | None = None, progress=None, station_inventory=None,
                stationxml_sha256: str = "", component: Component = Component.rotd100,
                buildings: dict | None = None, prune: bool = True, listing: Listing | None = None
                ) -> tuple[list[dict], list[Failure], dict]:
    """Scale every record to every level and judge every block (cached per record under ``out_dir``; ``prune``:
    drop the cache entries this call did not use, which the rounds of ``--levels auto`` keep; ``listing``: the
    directory's listing, made once for all the rounds).

    ``station_inventory`` (an obspy Inventory) converts records in counts, as for ``screen``.

    Returns
    -------
    results : list of dict
        Per record (sorted by id): ``verdict`` and ``p`` (levels, blocks), ``factor``, ``im.<name>``.
    failures : list of Failure
        The records that produced no stripes (:class:`~pipeline.records.listing.Failure`: from the scan, from
        their task, or from a lost worker).
    counts : dict
        ``records_computed``, ``records_reused``, ``wall_time_s``.
    """
    t0 = time.perf_counter()
    found = list_directory(records_dir, config=config) if listing is None else listing
    declared = read_declared_units(records_dir, config)
    jobs = RecordJobs(executor, progress=progress)
    base = Context(str(records_dir), config, inventory, declared, station_inventory, dict(buildings or {}),
                   jobs.scenes)
    ctx = FragilityContext(base, im, tuple(float(x) for x in levels), component)
    cache = FragilityCache(out_dir, fragility_key(config, inventory, im, levels, declared, stationxml_sha256,
                                                  component, buildings)) if out_dir is not None else None
    results: list[dict] = []
    failures = list(found.failures)

    def done(_job: tuple, res: dict, reused: bool) -> None:
        if cache is not None and not reused:
            cache.save(res)
        results.append(res)

    counts = jobs.run(fragility_task, [(src, record_content(src, root=Path(records_dir), declared=declared))
                                       for src in found.sources], ctx, done=done,
                      failed=lambda _job, f: failures.append(f),
                      cached=(lambda job: cache.load(job[0].record_id, job[1])) if cache is not None else None)
    if cache is not None and prune:
        cache.prune()
    results.sort(key=lambda r: str(r["record_id"]))
    return results, failures, {"records_computed": counts.computed, "records_reused": counts.reused,
                               "records_failed": len(failures), "wall_time_s": time.perf_counter() - t0}
