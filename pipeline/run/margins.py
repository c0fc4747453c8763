"""Per asset: the governing record, the margin to overturning, the rocking history.

For every block the *governing record* is the one whose scene is worst:
overturned by the simulation first, then by the paper's criterion, then the
largest max |theta| / alpha, then the largest velocity ratio of the paper's criterion. On that record:

* ``overturn_scale`` is the criterion's margin: the smallest factor on the
  record that reaches the criterion's boundary (closed form, the scene's
  ``criterion_scale``);
* ``overturn_scale_simulated`` is the simulator's margin: the first factor
  of an upward scan on the whole record (horizontal and vertical), in the
  governing scene's rocking plane, under which the block overturns
  (:mod:`pipeline.bodies.factor_sweep`). The scan starts from the factor that
  first lifts the block and grows by ``simulation.margin_step`` (1 %) per step
  up to ``margin_fine_to`` (x1.5), then by steps doubling up to
  ``margin_coarse_step`` (10 %), an overturning there bisected back to 1 %
  against the last factor that stood; the factor 1 is always tried.
  Overturning is not monotonic in amplitude, so no range the scan has not
  stepped over is bisected. What holds: the margin overturns and the factor
  1 % below it stands; a scene that overturns has a margin <= 1. A scene that
  stands can also have a margin below 1, when a smaller factor overturns it (a
  window of overturning below the nominal amplitude); such blocks are flagged
  ``overturns_below_nominal``. A window narrower than the step (1 % up to x1.5,
  up to 10 % above) can be missed. ``inf`` means nothing
  overturns up to ``simulation.margin_max_factor``; NaN that the rocking
  model does not apply, or that the scaled record reaches free flight
  (g + a_v <= 0) before any overturning;
* ``p_overturn_governing``: the fraction of the samples that overturn at factor 1 on the
  governing record (its scene's ``p_overturn``);
* ``overturn_scale_median`` (with ``uncertainty.margin_samples`` > 0; off by default): the
  median, over that many samples of the block and the record's amplitude (common random
  numbers), of the simulated margin on the governing record, as a factor on the nominal record;
  each sample costs a whole margin scan (off too with ``samples = 0``);
* theta(t) / alpha of the governing scene for the assets at risk, for the report.

References
----------
Purvance, Anooshehpoor & Brune (2008) scale records to find overturning
thresholds; Zhang & Makris (2001) show the non-monotonic overturning that
rules out bisecting a range not scanned.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from ..bodies.contract import Placement
from ..bodies.registry import body_model
from ..floors.buildings import place_blocks
from ..floors.standing import FloorMotions
from ..records.listing import Failure, RecordSource
from ..risk import P_RELOCATE, p_with_unknown
from ..scene_table import SCENE
from ..schema import HISTORY_SERIES, apply_schema
from .engine import RecordJobs
from .screening import Context, setup_of

log = logging.getLogger(__name__)


def governing_records(ds: xr.Dataset) -> np.ndarray:
    """Index of the governing record of every block (-1 where no record was screened)."""
    ok = ds["status"].values == "ok"
    out = np.full(ds.sizes["block"], -1)
    if not ok.any():
        return out
    sim = ds[SCENE.overturn_simulated].values == 1
    crit = ds["overturn_criterion"].values == 1
    theta = np.nan_to_num(ds[SCENE.theta_max].values, nan=-1.0, posinf=1e300)
    energy = np.nan_to_num(ds["velocity_ratio"].values, nan=-1.0, posinf=1e300)
    rows = np.flatnonzero(ok)
    for j in range(ds.sizes["block"]):
        # lexsort: last key is primary; the last element of the order is the worst scene
        order = np.lexsort((energy[rows, j], theta[rows, j], crit[rows, j], sim[rows, j]))
        out[j] = rows[order[-1]]
    return out




def at_risk(ds: xr.Dataset, rec_index: np.ndarray) -> np.ndarray:
    """Blocks whose governing scene overturns by the simulation or by the criterion, or has no verdict (unknown is
    never safe), or whose largest probability of overturning, the samples without a verdict counted as overturning,
    reaches :data:`P_RELOCATE` (every asset the report marks at risk gets a history; one whose margin is small is
    added by the margin task, which finds it)."""
    cols = np.arange(ds.sizes["block"])
    has = rec_index >= 0
    r = np.where(has, rec_index, 0)
    verdict = ds[SCENE.overturn_simulated].values[r, cols]
    simulated = ds[SCENE.physics].values[r, cols] >= 0 if SCENE.physics in ds else np.zeros(len(cols), dtype=bool)
    sim = (verdict == 1) | ((verdict == -1) & simulated)                                   # simulated, no verdict
    crit = ds["overturn_criterion"].values[r, cols] == 1
    likely = np.zeros(ds.sizes["block"], dtype=bool)
    if SCENE.p_overturn in ds:
        ok = (ds["status"].values == "ok")[:, None] if "status" in ds else True
        p = np.fmax(ds[SCENE.p_overturn].values, p_with_unknown(ds))   # the unknown counted as overturning
        likely = np.any(np.where(ok, np.nan_to_num(p, nan=0.0), 0.0) >= P_RELOCATE, axis=0)
    return has & (sim | crit | likely)


def margin_task(item: tuple, ctx: Context) -> dict:
    """One record and the blocks it governs: their margins and, for those at risk, theta(t)/alpha.

    ``item`` is ``(source, [(block_id, direction_deg, overturned, want_history), ...])``.
    Returns ``{block_id: (scale, runs, history or None, dt_s, sampled margins)}``; run under the engine's
    failure policy (:class:`~pipeline.run.engine.Guarded`): a record that cannot be loaded again comes back as
    its failure.
    """
    source, blocks = item
    cfg = ctx.config
    rec = ctx.load(source)
    inv = ctx.inventory
    rocking_blocks = inv.rocking_blocks(g_ms2=cfg.records.g_ms2)
    setup = setup_of(cfg)
    index = {b: k for k, b in enumerate(inv.ids)}
    motions = FloorMotions(rec, place_blocks(inv, ctx.buildings))   # a block on a floor: that floor's motion
    out = {}
    for block_id, direction, overturned, want_history in blocks:
        j = index[block_id]
        on = motions.of_block(j)
        shape = inv.shape(j)
        model = body_model(shape, Placement.of(on), setup.settings)     # the model its scene was judged by
        out[block_id] = tuple(model.margins(on, shape, rocking_blocks[j], float(direction), setup=setup,
                                            overturned=overturned, want_history=want_history))
    return out


#: The most blocks one margin task scans on its record: the blocks a record governs are split into tasks of at most
#: this many, so that a large inventory under few records uses every worker, shows its progress, and keeps in the
#: margin cache each task as it finishes (each task loads its record again: a few tenths of a second).
MARGIN_TASK_BLOCKS = 32


def add_margins(ds: xr.Dataset, sources: dict[str, RecordSource], ctx: Context, executor, *,
                cache=None, progress=None) -> tuple:
    """Governing record, both margins and the at-risk histories of every block.

    With a :class:`pipeline.run.cache.MarginCache`, scans already done for the same record
    content, block and run key are reused, and new ones are saved as they return. The records' margin tasks run
    as the screening's do (:class:`~pipeline.run.engine.RecordJobs`), with their own progress line.

    Returns
    -------
    ds : xarray.Dataset
        ``ds`` with per-block ``governing_record``, ``overturn_scale``,
        ``overturn_scale_simulated`` and ``margin_simulations``.
    histories : xarray.Dataset
        theta(t)/alpha of the governing scene of every block at risk (CF ragged array).
    summary : dict
        ``simulations`` (scaled scenes behind the margins), ``computed`` and ``reused``
        (margins scanned now or taken from the cache) and ``unavailable`` (record ids whose
        files could not be loaded again).
    """
    rec_index = governing_records(ds)
    got = _Margins.empty(ds)
    items, reused = _margin_items(ds, rec_index, got, ctx, cache)
    unavailable = [rid for rid in items if rid not in sources]
    tasks = [(sources[rid], blocks[k:k + MARGIN_TASK_BLOCKS]) for rid, blocks in items.items() if rid in sources
             for k in range(0, len(blocks), MARGIN_TASK_BLOCKS)]
    position = {b: k for k, b in enumerate(got.block_ids)}

    def done(job: tuple, result: dict, _reused: bool) -> None:
        rid = job[0].record_id
        for block_id, value in result.items():
            got.keep(position[block_id], rid, value)
            if cache is not None:
                cache.put(rid, got.content[rid], got.digest[block_id], value)

    def failed(job: tuple, failure: Failure) -> None:
        log.warning("record %s: no margins (%s)", failure.record_id, failure.reason)
        unavailable.append(failure.record_id)

    RecordJobs(executor, progress=progress, label="margin tasks done").run(margin_task, tasks, ctx, done=done,
                                                                            failed=failed)
    # screen's last tasks: its workers end here, so that none holds memory while the datasets are built (a later map
    # on the executor would start new ones)
    executor.release()
    computed = sum(len(blocks) for _, blocks in tasks)
    return apply_schema(_with_margins(ds, rec_index, got, ctx)), history_dataset(got.histories), {
        "simulations": int(got.runs[got.runs > 0].sum()), "reused": reused, "computed": computed,
        "unavailable": sorted(set(unavailable))}


@dataclass
class _Margins:
    """The margins of every block as they are found (NaN / -1: none)."""

    block_ids: list
    content: dict          # record id -> content digest
    digest: dict           # block id -> inventory digest
    sim_scale: np.ndarray
    median_scale: np.ndarray
    runs: np.ndarray
    histories: dict = field(default_factory=dict)

    @classmethod
    def empty(cls, ds: xr.Dataset) -> _Margins:
        nb = ds.sizes["block"]
        record_ids, block_ids = ds["record"].values, ds["block"].values.tolist()
        content = dict(zip(record_ids.tolist(), ds["content_sha256"].values.tolist())) \
            if "content_sha256" in ds else {}
        return cls(block_ids, content, dict(zip(block_ids, ds["block_sha256"].values.tolist())),
                   np.full(nb, np.nan), np.full(nb, np.nan), np.full(nb, -1, dtype="i4"))

    def keep(self, j: int, rid: str, value: tuple) -> None:
        """Block ``j``'s margin scan on record ``rid``: (scale, runs, history or None, dt, sampled margins)."""
        scale, n, history, dt, sampled = value
        self.sim_scale[j], self.runs[j] = scale, n
        finite = np.asarray(sampled)[~np.isnan(sampled)]
        self.median_scale[j] = float(np.median(finite)) if finite.size else np.nan
        if history is not None:
            self.histories[self.block_ids[j]] = (history, dt, rid)


def _margin_items(ds: xr.Dataset, rec_index: np.ndarray, got: _Margins, ctx: Context, cache
                  ) -> tuple[dict[str, list], int]:
    """The blocks to scan, by governing record: ``{record id: [(block id, direction, overturned, at risk)]}``; the
    blocks the margin cache answers are kept at once (their number returned too)."""
    risky = at_risk(ds, rec_index)
    record_ids = ds["record"].values
    items: dict[str, list] = {}
    reused = 0
    simulate = ctx.config.fidelity.tier != "criterion"      # the criterion tier simulates nothing
    for j in np.flatnonzero((rec_index >= 0) & simulate).tolist():
        rid = str(record_ids[rec_index[j]])
        direction = float(ds[SCENE.governing_azimuth].values[rec_index[j], j])
        if not np.isfinite(direction):
            continue
        hit = cache.get(rid, got.content[rid], got.digest[got.block_ids[j]]) if cache is not None else None
        if hit is not None:
            got.keep(j, rid, hit)
            reused += 1
            continue
        overturned = bool(ds[SCENE.overturn_simulated].values[rec_index[j], j] == 1)
        items.setdefault(rid, []).append((got.block_ids[j], direction, overturned, bool(risky[j])))
    return items, reused


def _with_margins(ds: xr.Dataset, rec_index: np.ndarray, got: _Margins, ctx: Context) -> xr.Dataset:
    """``ds`` with the per-block margin variables (the records x blocks arrays shared, not copied)."""
    nb = ds.sizes["block"]
    cols = np.arange(nb)
    r = np.where(rec_index >= 0, rec_index, 0)
    record_ids = ds["record"].values
    ds = ds.copy(deep=False)            # new per-block variables only: the records x blocks arrays are shared
    ds["governing_record"] = (("block",), np.array([record_ids[i] if i >= 0 else "" for i in rec_index],
                                                   dtype=object))
    ds["overturn_scale"] = (("block",), np.where(rec_index >= 0, ds["criterion_scale"].values[r, cols], np.nan))
    ds["overturn_scale_simulated"] = (("block",), got.sim_scale)
    ds["margin_simulations"] = (("block",), got.runs)
    ds["overturn_scale_median"] = (("block",), got.median_scale)
    p_gov = ds[SCENE.p_overturn].values[r, cols] if SCENE.p_overturn in ds else np.full(nb, np.nan)
    ds["p_overturn_governing"] = (("block",), np.where(rec_index >= 0, p_gov, np.nan))
    standing = np.where(rec_index >= 0, ds[SCENE.overturn_simulated].values[r, cols] == 0, False)
    below = np.where(np.isfinite(got.sim_scale), standing & (got.sim_scale < 1.0), False)
    ds["overturns_below_nominal"] = (("block",), np.where(np.isnan(got.sim_scale), -1, below).astype("i1"))
    sim = ctx.config.simulation
    ds.attrs["margin_settings"] = (f"upward scan of the factor on the governing record, in the governing scene's "
                                   f"rocking plane, x(1 + {sim.margin_step:g}) per step up to {sim.margin_fine_to:g}, "
                                   f"then steps doubling up to x(1 + {sim.margin_coarse_step:g}), up to "
                                   f"{sim.margin_max_factor:g}; an overturning above {sim.margin_fine_to:g} bisected "
                                   f"back to x(1 + {sim.margin_step:g}) against the last factor that stood")
    return ds


def _series(history: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """theta/alpha and the lean's compass azimuth of a history: a planar scene's (one row) leans in its plane, its
    azimuth not kept (NaN); a solid's has both rows (:func:`solid_history`)."""
    h = np.asarray(history, dtype=float)
    return (h[0], h[1]) if h.ndim == 2 else (h, np.full(h.shape, np.nan))


def history_dataset(histories: dict) -> xr.Dataset:
    """theta(t)/alpha per block, and the compass azimuth a solid leans toward, as a CF contiguous ragged array
    (featureType timeSeries)."""
    from ..store import ragged_dataset

    rows = [{"id": b, "theta_over_alpha": _series(histories[b][0])[0], "lean_azimuth": _series(histories[b][0])[1],
             "dt": histories[b][1], "governing_record": histories[b][2]} for b in sorted(histories)]
    return ragged_dataset("block_id", "block", rows, HISTORY_SERIES,
                          station={"governing_record": {"long_name": "governing record of the block"}})
