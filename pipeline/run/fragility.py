"""``screen fragility``: multiple-stripe analysis, lognormal fragility fits, IM ranking, hazard integral.

Data flow (one task per record, on the same executors as ``screen``)::

    scan -> per record: load, pulse, IMs, then for each level the record scaled (all components
    by one factor) so that its IM equals the level, every block judged as ``screen`` judges it
    (certificate, simulator, orientation scan; p_overturn with [uncertainty] samples)
    -> fragility cache entry per record (a re-run or a resumed run computes only what is missing)
    -> stripes -> fits, bootstrap, IM efficiency and sufficiency -> hazard -> fragility.nc, report

For the IM ``sa`` (Sa at the block's own period 2 pi / p) the factor differs per block.
A record whose IM is zero or undefined (no pulse for ``ap``) cannot be scaled: it is left out
of every stripe of that block, and the run says so.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import logging
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from .. import criteria
from ..blocks import Inventory
from ..config import Config
from ..constants import STATE_DIR
from ..errors import UsageError
from ..floors.buildings import place_blocks
from ..floors.standing import FloorMotions
from ..records.intensity import (
    COMPONENT_IMS,
    IM_NAMES,
    IMS,
    SI_LABEL,
    display_unit,
    record_measures,
    scale_factors,
)
from ..records.loader import Failure, Listing, list_directory, read_declared_units
from ..rocking.rules import rocks
from ..rocking.scene import Response
from ..scene_table import SCENE
from ..schema import FRAGILITY, apply_schema
from ..uncertainty.fragility import FitStatus, bootstrap_stripes, fit_stripes, im_dispersion, open_interval
from ..uncertainty.hazard import Component, HazardSet, annual_rate, annual_rate_upper, probability_in
from .batch import record_content
from .cache import ENTRY_FORMAT, RecordStore, run_key
from .engine import RecordJobs
from .screening import Context, pulses_and_directions, simulate_scenes

log = logging.getLogger(__name__)

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
        The records that produced no stripes (:class:`~pipeline.records.loader.Failure`: from the scan, from
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


#: The per-record results that have one row per level (merged and ordered with the levels)
STRIPE_KEYS = ("verdict", "p", "p_random", "p_unknown", "slides", "factor")
#: The responses that count as sliding in a stripe (:class:`~pipeline.rocking.scene.Response`)
SLIDING_CODES = (int(Response.slide), int(Response.slide_rock))

#: How a level's unit reads in a sentence (the option's suffix, ``cms``, is not a unit a reader knows)
UNIT_WORDS = {"cms": "cm/s", "ms": "m/s", "cms2": "cm/s2", "ms2": "m/s2"}
#: IMs ``--levels auto`` can start from the blocks' capacities: the uplift acceleration g min(tan alpha, mu) for
#: accelerations, the critical velocity of the reference paper's Eq. (4) for PGV, 1 for the velocity ratio
AUTO_IMS = ("pga", "sa", "ap", "pgv", "velocity_ratio")
#: ``--levels auto``: the ladder's step (each level twice the one below), its rounds of extension at most, and
#: its levels at most
AUTO_STEP, AUTO_ROUNDS, AUTO_MAX_LEVELS = 2.0, 4, 10
#: ... the fractions every block that can rock must reach at the ladder's two ends
AUTO_BRACKET = (0.1, 0.9)


def capacities(inventory: Inventory, im: str, *, g_ms2: float) -> np.ndarray:
    """Each block's capacity in the IM's SI unit, where its stripes start (NaN for a block that cannot rock)."""
    geo = inventory.geometry(g_ms2=g_ms2)
    can = np.array([rocks(float(a), float(m)) for a, m in zip(geo.alpha, inventory.mu)])
    if im in ("pga", "sa", "ap"):
        c = g_ms2 * np.minimum(np.tan(geo.alpha), inventory.mu)             # uplift (Housner 1963)
    elif im == "pgv":
        c = criteria.critical_velocity(geo.R, geo.alpha, g_ms2=g_ms2)
    elif im == "velocity_ratio":
        c = np.ones(len(inventory))
    else:
        raise UsageError(f"--levels auto: {im} has no capacity to start from; auto takes {', '.join(AUTO_IMS)}; "
                         "give the levels")
    return np.where(can, np.asarray(c, dtype=float), np.nan)


def auto_ladder(cap: np.ndarray) -> np.ndarray:
    """The first ladder of ``--levels auto``: from the smallest capacity up by :data:`AUTO_STEP` to at least 4 times
    the largest [IM units]."""
    finite = cap[np.isfinite(cap)]
    if finite.size == 0:
        raise UsageError("--levels auto: no block of the inventory can rock (each slides or is too squat); "
                         "nothing can overturn, give the levels to fit anyway")
    n = int(math.ceil(math.log(4.0 * finite.max() / finite.min()) / math.log(AUTO_STEP) - 1e-9)) + 1
    return finite.min() * AUTO_STEP ** np.arange(min(max(n, 3), AUTO_MAX_LEVELS))


def extension(levels: np.ndarray, results: list[dict], cap: np.ndarray, *, outcome: str = "verdict") -> list[float]:
    """The levels to add so that every block that can rock brackets :data:`AUTO_BRACKET`: one step above the top
    where some block's top fraction is below 0.9, one below the bottom where some bottom fraction is above 0.1.
    ``outcome``: the result the fit uses (``verdict``, nominal; or a sampled probability, :data:`ORIENTATIONS`)."""
    if not results:
        return []
    order = np.argsort(levels)
    v = np.stack([r[outcome] for r in results]).astype(float)[:, order, :]          # (records, levels, blocks)
    v = np.where(v >= 0, v, np.nan)                                                  # -1 (no verdict) and NaN out
    with np.errstate(invalid="ignore"):
        frac = np.nanmean(v, axis=0)                                                 # (levels, blocks)
    rock = np.isfinite(cap)
    low, high = AUTO_BRACKET
    add = []
    if np.any(rock & ~(np.nan_to_num(frac[-1], nan=0.0) >= high)):
        add.append(float(levels[order[-1]] * AUTO_STEP))
    if np.any(rock & ~(np.nan_to_num(frac[0], nan=1.0) <= low)):
        add.append(float(levels[order[0]] / AUTO_STEP))
    return add


def merge_rounds(earlier: list[dict], later: list[dict]) -> list[dict]:
    """Per record, the stripes of two rounds of ``--levels auto`` side by side (a record missing from either
    round is left out: it failed there)."""
    by_id = {str(r["record_id"]): r for r in later}
    out = []
    for r in earlier:
        s = by_id.get(str(r["record_id"]))
        if s is None:
            continue
        merged = dict(r)
        for k in STRIPE_KEYS:
            merged[k] = np.concatenate([r[k], s[k]], axis=0)
        out.append(merged)
    return out


def auto_stripes(run, inventory: Inventory, config: Config, im: str, *, say=None, outcome: str = "verdict"
                 ) -> tuple[np.ndarray, list, list, dict]:
    """``--levels auto``: the ladder of :func:`auto_ladder`, extended round by round (:func:`extension`) until
    every block that can rock brackets 0.1 and 0.9, or :data:`AUTO_ROUNDS` rounds, or :data:`AUTO_MAX_LEVELS`
    levels. ``run(levels)`` runs the stripes of new levels; ``say(line)`` announces each round; ``outcome``: the
    result the fit uses (:func:`extension`). Returns the levels
    (increasing), the results (their stripes in that order), the failures and the counts."""
    cap = capacities(inventory, im, g_ms2=config.records.g_ms2)
    levels = auto_ladder(cap)
    shown, factor = display_unit(im)
    words = UNIT_WORDS.get(shown, shown)

    def listed(xs) -> str:
        return ", ".join(f"{x / factor:,.4g}" if x / factor < 1e4 else f"{x / factor:,.0f}" for x in xs)

    if say is not None:
        say(f"levels auto: {listed(levels)} {words}, from the blocks' capacities")
    results, failures, counts = run(levels)
    for k in range(AUTO_ROUNDS):
        add = [x for x in extension(levels, results, cap, outcome=outcome) if levels.size < AUTO_MAX_LEVELS]
        if not add:
            break
        if say is not None:
            say(f"levels auto, round {k + 2}: adding {listed(sorted(add))} {words}, "
                "where some block's stripes do not yet reach 10 % or 90 % overturning")
        more, more_failures, more_counts = run(np.array(sorted(add)))
        results = merge_rounds(results, more)
        failures = list(dict.fromkeys([*failures, *more_failures]))
        counts = dict(counts, wall_time_s=counts["wall_time_s"] + more_counts["wall_time_s"],
                      records_failed=len(failures))
        levels = np.concatenate([levels, np.array(sorted(add))])
    order = np.argsort(levels)
    for r in results:
        for name in STRIPE_KEYS:
            r[name] = np.asarray(r[name])[order]
    return levels[order], results, failures, counts


def hazard_and_component(paths: list, *, im: str, site: str | None, lonlat: tuple[float, float] | None,
                         stated: str | None, im_component: str | None, scale: float | None
                         ) -> tuple[HazardSet | None, Component]:
    """The hazard curves of ``paths`` (``--hazard``), bound to the fit, and the component definition the fit uses:
    the one asked for (``im_component``), else the first curve's (read from the file, or ``stated`` for it), else
    RotD100.

    Raises
    ------
    RockscreenError
        For a hazard file that cannot be read as a curve of ``im`` (named, with the fix).
    """
    from ..uncertainty.hazard import hazard_set
    from ..uncertainty.hazard_files import read_hazard

    declared = Component(stated) if stated else None
    curves = [read_hazard(path, im=im, site=site, lonlat=lonlat, component=declared) for path in paths]
    fit = Component(im_component) if im_component else (
        curves[0].component if curves and curves[0].component is not None else Component.rotd100)
    hazard = hazard_set(curves, im=im, fit_component=fit, scale=scale) if curves else None
    return hazard, fit


def fits_probabilities(config: Config) -> bool:
    """True when the stripes' outcomes are sampled probabilities (else nominal verdicts): :attr:`Config.sampling`."""
    return config.sampling


#: ``--orientation``: the probability a sampled stripe is fitted on, for a block of blank azimuth.
ORIENTATIONS = {"random": ("p_random", "p_overturn_random_orientation (a block of unknown orientation)"),
                "worst": ("p", "p_overturn (the orientation found worst on the scan's grid)")}


def assemble_fragility(results: list[dict], inventory: Inventory, config: Config, *, im: str, levels: np.ndarray,
                       hazard: HazardSet | None = None, bootstrap: int = 200,
                       orientation: str = "random", component: Component = Component.rotd100,
                       level_unit: tuple[str, float] | None = None, progress=None) -> xr.Dataset:
    """Stripes, fits, bootstrap intervals, IM ranking and (with a hazard curve) the annual rates (``progress``:
    the command's progress display, told of each block's bootstrap).

    ``orientation`` (:data:`ORIENTATIONS`): with sampling, each scaled scene's outcome is its probability for a
    block of unknown orientation (the default: the risk of such a block) or in its worst orientation; a block
    with a given azimuth has one probability, the same in both.
    """
    if orientation not in ORIENTATIONS:
        raise UsageError(f"--orientation {orientation!r}: expected one of {sorted(ORIENTATIONS)}")
    key, measure = ORIENTATIONS[orientation]
    levels = np.asarray(levels, dtype=float)
    nb, nl = len(inventory), len(levels)
    sampled = fits_probabilities(config)
    verdict = np.stack([r["verdict"] for r in results]) if results else np.full((0, nl, nb), -1)
    prob = np.stack([r[key] for r in results]) if results else np.full((0, nl, nb), np.nan)
    factor = np.stack([r["factor"] for r in results]) if results else np.full((0, nl, nb), np.nan)
    # the outcome of a scene: p_overturn when sampled, else the nominal verdict (NaN: no verdict)
    outcome = prob if sampled else np.where(verdict >= 0, verdict.astype(float), np.nan)
    outcome = np.where(np.isfinite(factor), outcome, np.nan)
    n = np.sum(np.isfinite(outcome), axis=0)                                  # (levels, blocks)
    z = np.nansum(outcome, axis=0)
    frac = np.where(n > 0, z / np.maximum(n, 1), np.nan)
    fit = fit_stripes(levels, z.T, n.T)
    unjudged = _unjudged(results, outcome, factor, sampled=sampled, shape=(nl, nb))
    scaled = np.sum(np.isfinite(factor), axis=0)                              # every record scaled, judged or not
    # the fits bounded by the records without a verdict: counted as overturning, then as standing
    fit_over = fit_stripes(levels, (z + unjudged.overturn_add).T, scaled.T)
    fit_stand = fit_stripes(levels, (z + unjudged.stand_add).T, scaled.T)
    th_ci, be_ci = np.full((nb, 2), np.nan), np.full((nb, 2), np.nan)
    blocks = range(nb)
    label = f"blocks fitted ({bootstrap} bootstrap draws each)"
    for j in (progress(blocks, total=nb, label=label) if progress is not None and bootstrap else blocks):
        th_ci[j], be_ci[j] = bootstrap_stripes(levels, outcome[:, :, j], draws=bootstrap,
                                               seed=config.uncertainty.seed + j)
        if fit.status[j] == FitStatus.not_bounded:     # the median lies beyond the levels: its interval is open
            th_ci[j] = open_interval(frac[:, j], th_ci[j])
    names = list(IMS)
    median_im, beta_im, suff, rank = _im_ranking(results, outcome, factor, names)
    data = {
        "fraction_overturned": (("block", "im_level"), frac.T),
        "n_records": (("block", "im_level"), n.T.astype("i4")),
        "n_scaled": (("block", "im_level"), scaled.T.astype("i4")),
        "n_unjudged": (("block", "im_level"), unjudged.count.T),
        "n_sliding": (("block", "im_level"), unjudged.sliding.T.astype("i4")),
        "median_unjudged_overturn": (("block",), fit_over.theta), "beta_unjudged_overturn": (("block",), fit_over.beta),
        "median_unjudged_stand": (("block",), fit_stand.theta), "beta_unjudged_stand": (("block",), fit_stand.beta),
        "overturned_sum": (("block", "im_level"), z.T),
        "median": (("block",), fit.theta), "beta": (("block",), fit.beta), "fit_status": (("block",), fit.status),
        "median_low": (("block",), th_ci[:, 0]), "median_high": (("block",), th_ci[:, 1]),
        "beta_low": (("block",), be_ci[:, 0]), "beta_high": (("block",), be_ci[:, 1]),
        "scale_factor": (("record", "im_level", "block"), factor),
        "outcome": (("record", "im_level", "block"), verdict.astype("i1")),
        SCENE.p_overturn: (("record", "im_level", "block"), prob),
        "beta_im": (("block", "im"), beta_im), "median_im": (("block", "im"), median_im),
        "block_period": (("block",), 2.0 * math.pi / inventory.geometry(g_ms2=config.records.g_ms2).p),
        "can_rock": (("block",), _can_rock(inventory, config).astype("i1")),
        "sufficiency_p": (("block", "im"), suff), "im_rank": (("block", "im"), rank.astype("i2")),
    }
    if hazard is not None:
        data.update(_hazard_variables(hazard, fit, inventory, config, levels, im=im))
    ds = xr.Dataset(data, coords={
        "block": np.array(inventory.ids, dtype=object), "im_level": levels,
        "record": np.array([str(r["record_id"]) for r in results], dtype=object),
        "im": np.array(names, dtype=object)})
    ds.attrs.update({"im": im, "im_units": IMS[im][0], "im_long_name": IM_NAMES[im],
                     "im_component": component.value if im in COMPONENT_IMS else "",
                     "im_display_unit": (level_unit or (SI_LABEL[IMS[im][0]], 1.0))[0],
                     "im_display_factor": (level_unit or (SI_LABEL[IMS[im][0]], 1.0))[1],
                     "hazard_notes": "\n".join(n for c in (hazard.curves if hazard else ()) for n in c.notes),
                     "im_units_by_im": json.dumps({k: v[0] for k, v in IMS.items()}),
                     "outcome_measure": measure if sampled else "nominal verdict",
                     "orientation": orientation,
                     "bootstrap_draws": bootstrap, "Conventions": "CF-1.11",
                     "title": "rockscreen fragility: multiple-stripe analysis"})
    return apply_schema(ds, FRAGILITY)


@dataclass(frozen=True)
class Unjudged:
    """Per stripe (levels, blocks): what the records without a verdict add to the overturned sum when counted as
    overturning or as standing, their count (a sampled scene counts by the fraction of its samples without a
    verdict), and the records whose nominal scene slid."""

    overturn_add: np.ndarray
    stand_add: np.ndarray
    count: np.ndarray
    sliding: np.ndarray


def _unjudged(results: list[dict], outcome: np.ndarray, factor: np.ndarray, *, sampled: bool,
              shape: tuple[int, int]) -> Unjudged:
    """The records without a verdict of every stripe (:class:`Unjudged`). A scene without any verdict adds 1 when
    counted as overturning and 0 as standing; a sampled scene with a verdict, p over its judged samples, is
    k / n + u / n or k / n when its u samples without a verdict are counted as overturning or standing (its
    outcome, p, already sits in the judged sum: the differences are added)."""
    if not results:
        zero = np.zeros(shape)
        return Unjudged(zero, zero, zero, zero)
    scaled = np.isfinite(factor)
    none = scaled & ~np.isfinite(outcome)
    over, stand, count = none.astype(float), np.zeros(outcome.shape), none.astype(float)
    if sampled:
        fu = np.stack([np.asarray(r["p_unknown"], dtype=float) for r in results])
        fu = np.where(scaled & np.isfinite(outcome) & np.isfinite(fu), fu, 0.0)
        p = np.nan_to_num(outcome)
        over = over + (p * (1.0 - fu) + fu) - p
        stand = stand + p * (1.0 - fu) - p
        count = count + fu
    slid = np.stack([np.asarray(r["slides"], dtype=int) for r in results]) == 1
    return Unjudged(over.sum(axis=0), stand.sum(axis=0), count.sum(axis=0), (slid & scaled).sum(axis=0))


def _im_ranking(results: list[dict], outcome: np.ndarray, factor: np.ndarray, names: list[str]) -> tuple:
    """IM efficiency and sufficiency: the same outcomes against every IM of the scaled records; per block and IM,
    the median, the dispersion, the sufficiency p-value and the rank by dispersion (-1: no fit, nothing
    overturns)."""
    nb, nl = outcome.shape[2], outcome.shape[1]
    beta_im = np.full((nb, len(names)), np.nan)
    median_im = np.full((nb, len(names)), np.nan)
    suff = np.full((nb, len(names)), np.nan)
    for j in range(nb):
        y = outcome[:, :, j].ravel()
        f = factor[:, :, j]
        tp = np.repeat(np.array([r["im.tp"][j] for r in results]), nl) if results else np.zeros(0)
        for k, name in enumerate(names):
            base = np.array([r[f"im.{name}"][j] for r in results]) if results else np.zeros(0)
            x = (base[:, None] * f ** IMS[name][1]).ravel() if results else np.zeros(0)
            cov = None if name == "tp" else np.log(np.where(tp > 0, tp, np.nan))
            median_im[j, k], beta_im[j, k], suff[j, k] = im_dispersion(x, y, cov)
    rank = np.argsort(np.argsort(np.where(np.isnan(beta_im), np.inf, beta_im), axis=1, kind="stable"),
                      axis=1) + 1
    rank = np.where(np.isnan(beta_im), -1, rank)           # no fit (nothing overturns): not ranked
    return median_im, beta_im, suff, rank


def _hazard_variables(hazard: HazardSet, fit, inventory: Inventory, config: Config, levels: np.ndarray, *,
                      im: str) -> dict:
    """The annual rates of overturning and the 50-year probabilities (and their upper bounds) from the hazard
    curve of each block's IM (Sa at its own period, with the period taken and its ratio)."""
    periods = 2.0 * math.pi / inventory.geometry(g_ms2=config.records.g_ms2).p
    chosen = [hazard.for_block(float(T) if im == "sa" else math.nan) for T in periods]
    rate, upper = _rates(chosen, fit, inventory, config, levels)
    data = {"annual_rate_overturn": (("block",), rate),
            "p_overturn_50yr": (("block",), np.array([probability_in(r, 50.0) for r in rate])),
            "annual_rate_overturn_upper": (("block",), upper),
            "p_overturn_50yr_upper": (("block",), np.array([probability_in(r, 50.0) for r in upper]))}
    if im == "sa":
        data["hazard_period"] = (("block",), np.array([c.period_s for c, _ in chosen]))
        data["hazard_period_ratio"] = (("block",), np.array([r for _, r in chosen]))
    return data


def _can_rock(inventory: Inventory, config: Config) -> np.ndarray:
    """Whether each block can rock (:func:`~pipeline.rocking.rules.rocks`): one that cannot never overturns."""
    geom = inventory.geometry(g_ms2=config.records.g_ms2)
    return np.array([rocks(float(geom.alpha[j]), float(inventory.mu[j])) for j in range(len(inventory))], dtype=bool)


def _rates(chosen: list, fit, inventory: Inventory, config: Config, levels: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """Each block's annual rate of overturning, and its upper bound for levels never tested (overturning certain
    above the top level). A block that can rock but overturned at no level has no rate (NaN: raise the levels),
    only the bound, the hazard's rate of exceeding the top level; one that cannot rock (it slides) has 0."""
    top = float(np.max(levels))
    rate, upper = np.full(len(chosen), np.nan), np.full(len(chosen), np.nan)
    can_rock = _can_rock(inventory, config)
    for j, (curve, _) in enumerate(chosen):
        theta, beta = float(fit.theta[j]), float(fit.beta[j])
        if fit.status[j] == FitStatus.none_overturn and not can_rock[j]:
            rate[j] = upper[j] = 0.0
            continue
        rate[j] = math.nan if fit.status[j] == FitStatus.none_overturn else annual_rate(curve, theta, beta)
        upper[j] = annual_rate_upper(curve, theta, beta, top)
    return rate, upper


def stripe_warnings(ds: xr.Dataset) -> list[str]:
    """Why records or stripes are missing: records that could not be scaled, stripes with no verdict."""
    out = []
    f = ds["scale_factor"].values
    why = " (no pulse was extracted)" if ds.attrs["im"] in ("ap", "velocity_ratio") else ""
    for i, rid in enumerate(ds["record"].values.tolist()):
        bad = ~np.isfinite(f[i, 0, :])
        if bad.any():
            out.append(f"record {rid}: its {ds.attrs['im']} is zero or undefined for {int(bad.sum())} block(s) "
                       f"(e.g. {ds['block'].values[np.flatnonzero(bad)[0]]}): it cannot be scaled to a level and is "
                       f"left out of their stripes{why}")
    n = ds["n_records"].values
    for j, block in enumerate(ds["block"].values.tolist()):
        empty = np.flatnonzero(n[j] == 0)
        if empty.size:
            lv = ", ".join(f"{x:g}" for x in ds["im_level"].values[empty])
            out.append(f"block {block}: no record has a verdict at level(s) {lv} {ds.attrs['im_units']} (every "
                       "record unscalable there, in free flight, or with a base that would slide, twist or lift off "
                       "where the model stops); those stripes are empty")
    if "n_unjudged" in ds:
        out += unjudged_words(ds)
    if "hazard_period_ratio" in ds:
        for j, block in enumerate(ds["block"].values.tolist()):
            ratio = float(ds["hazard_period_ratio"].values[j])
            if abs(math.log(ratio)) > math.log(PERIOD_GAP_WARN):
                out.append(f"block {block}: its Sa period is {float(ds['block_period'].values[j]):.3g} s; the "
                           f"nearest hazard curve is for {float(ds['hazard_period'].values[j]):.3g} s (ratio "
                           f"{ratio:.2f}); give a curve nearer its period for a closer rate")
    return out


def unjudged_words(ds: xr.Dataset) -> list[str]:
    """Per block whose stripes hold records without a verdict: how many, at which levels, and the median counted
    both ways (the fit bounds), in words."""
    out = []
    unit = ds.attrs.get("im_display_unit", ds.attrs.get("im_units", ""))
    factor = float(ds.attrs.get("im_display_factor", 1.0))
    for j, block in enumerate(ds["block"].values.tolist()):
        u = ds["n_unjudged"].values[j]
        if not np.any(u > 0):
            continue
        worst = int(np.argmax(u))
        lo, hi = (_median_words(float(ds[v].values[j]) / factor, unit)
                  for v in ("median_unjudged_overturn", "median_unjudged_stand"))
        out.append(f"block {block}: {u.sum():.3g} record-levels without a verdict (up to {u[worst]:.3g} of "
                   f"{int(ds['n_scaled'].values[j, worst])} records at "
                   f"{float(ds['im_level'].values[worst]) / factor:.4g} "
                   f"{unit}); counted as overturning the median is {lo}, as standing {hi}: "
                   "the fit is bounded by them, and screen event takes P's upper bound from the first")
    return out


def _median_words(x: float, unit: str) -> str:
    """A fitted median in words: 'none (no level overturns)' for inf, 'below every level' for 0."""
    if math.isinf(x):
        return "none (no level overturns)"
    if x == 0.0:
        return "below every level"
    return "not fitted" if math.isnan(x) else f"{x:.4g} {unit}"


#: A block integrated against an Sa curve whose period differs from its own by more than this factor is warned of.
PERIOD_GAP_WARN = 1.25


@dataclass(frozen=True)
class FragilityRequest:
    """Everything ``screen fragility`` was asked for."""

    records_dir: Path
    blocks_csv: Path
    inventory: Inventory
    config: Config
    im: str
    #: the IM levels [SI]; None: ``--levels auto`` (:func:`auto_stripes`)
    levels: np.ndarray | None
    out_dir: Path
    hazard: HazardSet | None = None
    #: the horizontal component definition of PGA, PGV and Sa the fit uses
    component: Component = Component.rotd100
    #: the unit ``--levels`` was given in (label, factor to SI): the outputs' medians are in it
    level_unit: tuple[str, float] | None = None
    #: the buildings blocks stand in (``--buildings``), by id
    buildings: dict = dataclasses.field(default_factory=dict)
    n_workers: int = 1
    scheduler: str | None = None
    bootstrap: int = 200
    command: tuple = ()
    #: StationXML for records in counts (``--stationxml``; else ``*.xml`` in the records directory)
    stationxml: Path | None = None
    #: the probability fitted for a block of blank azimuth (:data:`ORIENTATIONS`)
    orientation: str = "random"


def _say_why_all_is_new(out_dir: Path, request: FragilityRequest) -> None:
    """Warn when the last fragility run into ``out_dir`` fitted the same IM under another component definition:
    the records are scaled to the levels under the new one, so no scaled scene of the last run can be reused."""
    path = out_dir / "fragility.nc"
    if not path.is_file():
        return
    try:
        with xr.open_dataset(path, engine="netcdf4") as last:
            im, component = str(last.attrs.get("im", "")), str(last.attrs.get("im_component", ""))
    except (OSError, ValueError):
        return
    if im == request.im and component and request.im in COMPONENT_IMS and component != request.component.value:
        log.warning("the last run fitted %s as %s, this one as %s (the hazard's definition, or --im-component): "
                    "the records are scaled to the levels under %s, so every scaled scene is simulated again (to "
                    "reuse the last run's, fit on %s: --im-component %s, with --hazard-scale converting the hazard)",
                    im, component, request.component.value, request.component.value, component, component)


def fragility(request: FragilityRequest, *, progress=None, say=None) -> dict:
    """Run the stripes (resumable), fit, integrate the hazard, write fragility.nc, fragility.html and
    fragility_assets.csv.

    Returns
    -------
    dict
        Counts, paths and warnings for the closing summary.
    """
    from ..records.loader import files_sha256, read_inventory, stationxml_paths
    from ..report.fragility_html import build_fragility_report
    from ..store import Family, OutputLock, publish_staged, write_atomic
    from ..store.exports import left_out, write_exports
    from ..store.sets import PLAIN_BEFORE_SETS
    from .cache import ensure_writable
    from .executors import make_executor

    out_dir = ensure_writable(request.out_dir, replaces=PLAIN_BEFORE_SETS[Family.FRAGILITY])
    station = read_inventory(request.records_dir, request.stationxml)
    levels = request.levels
    _say_why_all_is_new(out_dir, request)
    found = list_directory(request.records_dir, config=request.config)      # once, for every round of auto
    with OutputLock(out_dir, command=" ".join(request.command)):
        with make_executor(n_workers=request.n_workers, scheduler=request.scheduler) as executor:
            def run(lv: np.ndarray, prune: bool = True):
                return run_stripes(request.records_dir, request.inventory, request.config, im=request.im, levels=lv,
                                   executor=executor, out_dir=out_dir, progress=progress, station_inventory=station,
                                   stationxml_sha256=files_sha256(stationxml_paths(request.records_dir,
                                                                                   request.stationxml)),
                                   component=request.component, buildings=request.buildings, prune=prune,
                                   listing=found)

            if levels is None:                         # --levels auto
                levels, results, failures, counts = auto_stripes(
                    lambda lv: run(lv, prune=False), request.inventory, request.config, request.im, say=say,
                    outcome=ORIENTATIONS[request.orientation][0] if fits_probabilities(request.config) else "verdict")
            else:
                results, failures, counts = run(levels)
        if not results:
            raise UsageError(f"{request.records_dir}: no record could be scaled and judged; failures: "
                             + "; ".join(f"{f.record_id}: {f.reason}" for f in failures[:5]))
        ds = assemble_fragility(results, request.inventory, request.config, im=request.im, levels=levels,
                                hazard=request.hazard, bootstrap=request.bootstrap,
                                orientation=request.orientation, component=request.component,
                                level_unit=request.level_unit, progress=progress)
        if say is not None:
            say("writing fragility.nc, fragility.html (its figures) and the exports ...")
        ds.attrs.update({"history": f"{time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())} "
                                    f"{' '.join(request.command)}",
                         "rockscreen_config": json.dumps(request.config.to_dict(), sort_keys=True),
                         "inventory_file": str(request.blocks_csv),
                         "records_failed": "\n".join(f"{f.record_id}: {f.reason}" for f in failures),
                         "hazard_curve": request.hazard.path if request.hazard is not None else "",
                         "hazard_title": request.hazard.title if request.hazard is not None else "",
                         "hazard_synthetic": int(request.hazard.synthetic) if request.hazard is not None else 0})
        nc, html, csv_path, *exports = publish_staged(       # the set is published whole, or not at all
            out_dir, lambda stage: [write_atomic(ds, stage / "fragility.nc"),
                                    *build_fragility_report(ds, stage, hazard=request.hazard),
                                    *write_exports(ds, stage)],
            family=Family.FRAGILITY, command=" ".join(request.command))
    return {**counts, "scenes": int(ds.sizes["record"] * ds.sizes["im_level"] * ds.sizes["block"]),
            "failures": failures, "paths": (nc, html, csv_path, *exports),
            "warnings": stripe_warnings(ds) + [f"exports leave out {x}" for x in (left_out(ds) if exports else [])]}
