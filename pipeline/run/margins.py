"""Per asset: the governing record, the margin to overturning, the rocking history.

For every block the *governing record* is the one whose scene is worst:
overturned by the simulation first, then by the paper's criterion, then the
largest max |theta| / alpha, then the largest velocity ratio of the paper's criterion. On that record:

* ``overturn_scale`` is the criterion's margin: the smallest factor on the
  record that reaches the criterion's boundary (closed form, the scene's
  ``criterion_scale``);
* ``overturn_scale_simulated`` is the simulator's margin: the smallest factor
  of an upward scan on the whole record (horizontal and vertical), in the
  governing scene's rocking plane, under which the block overturns. The scan
  starts from the factor that first lifts the block and grows by
  ``simulation.margin_step`` (1 %) per step; the factor 1 is always tried.
  Never by bisection: overturning is not monotonic in amplitude, so a
  bisection can step over a window of overturning. What holds: a scene that
  overturns has a margin <= 1. A scene that stands can also have a margin
  below 1, when a smaller factor overturns it (a window of overturning below
  the nominal amplitude); such blocks are flagged ``overturns_below_nominal``.
  A window narrower than one step can be missed. ``inf`` means nothing
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
rules out bisection.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from ..floors.buildings import place_blocks
from ..floors.standing import FloorMotions
from ..records.loader import Failure, RecordSource
from ..risk import P_RELOCATE, RELOCATE_BELOW_SCALE, p_with_unknown
from ..rocking.block import Block
from ..rocking.planner import rocks, simulate_scene
from ..rocking.solids.solid3d import Solid, drawn, judge_solid, lift_factor, solid_of
from ..scene_table import SCENE
from ..schema import HISTORY_SERIES, apply_schema
from ..uncertainty.sampling import common_normals, sample_block
from .engine import RecordJobs
from .scale_scan import scale_scan
from .screening import Context

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


def overturn_scale_simulated(ah_ms2: np.ndarray, av_ms2, dt_s: float, *, block: Block, settings,
                             overturns_at_one: bool | None = None) -> tuple[float, int]:
    """Smallest factor on the record under which the block overturns (upward scan).

    Parameters
    ----------
    ah_ms2, av_ms2 : ndarray
        Horizontal acceleration along the block's direction and vertical (or None) [m s-2].
    dt_s : float
        Sampling interval [s].
    block : Block
        The block.
    settings : SimulationConfig
        ``margin_step`` and ``margin_max_factor``, and the integration settings.
    overturns_at_one : bool, optional
        The simulated verdict of the unscaled record, when already known.

    Returns
    -------
    scale : float
        The first factor of the scan that overturns (below 1 for a standing scene when a
        smaller factor overturns it); ``inf`` when none up to ``margin_max_factor``; NaN for
        blocks the rocking model does not apply to (sliding or squat blocks never overturn in
        it), and when a scaled record reaches free flight before any overturning.
    runs : int
        Scenes simulated.
    """
    if not rocks(block.alpha, block.mu):
        return math.nan, 0
    tan_a = math.tan(block.alpha)
    lift = np.abs(ah_ms2) - (av_ms2 * tan_a if av_ms2 is not None else 0.0)
    if not np.any(lift > 0):
        return math.inf, 0
    f = float(np.min(block.g_ms2 * tan_a / lift[lift > 0]))      # the factor that first lifts the block

    def verdict_at(factor: float) -> int:
        av = None if av_ms2 is None else factor * av_ms2
        return simulate_scene(factor * ah_ms2, av, dt_s, block=block, settings=settings).verdict

    return scale_scan(f, verdict_at, settings=settings, overturns_at_one=overturns_at_one)


def solid_scale_simulated(rec, solid: Solid, *, settings, g_ms2: float,
                          overturns_at_one: bool | None = None) -> tuple[float, int]:
    """:func:`overturn_scale_simulated` of a solid on a record's two horizontals and vertical, by its 3D model
    (:mod:`pipeline.rocking.solids.solid3d`), from the factor at which it first lifts
    (:func:`~pipeline.rocking.solids.solid3d.lift_factor`)."""
    h = rec.horizontal_ms2
    f = lift_factor(h[0], h[1], rec.vertical_ms2, solid, g_ms2=g_ms2)
    if not math.isfinite(f):
        return math.inf, 0

    def verdict_at(factor: float) -> int:
        return judge_solid(h[0], h[1], rec.vertical_ms2, rec.dt_s, solid, settings=settings, g_ms2=g_ms2,
                     amplitude=factor).scene.verdict

    return scale_scan(f, verdict_at, settings=settings, overturns_at_one=overturns_at_one)


def theta_history(ah_ms2, av_ms2, dt_s: float, *, block: Block, settings) -> np.ndarray | None:
    """theta(t) / alpha at every sample of the scene, or None where nothing rocks."""
    sc = simulate_scene(ah_ms2, av_ms2, dt_s, block=block, settings=settings, history=True)
    return sc.theta_over_alpha


def sampled_margins(ah_ms2: np.ndarray, av_ms2, dt_s: float, *, j: int, inv, settings, unc,
                    g_ms2: float, sampling: bool) -> tuple[np.ndarray, int]:
    """The simulated margin of the first ``unc.margin_samples`` samples of block ``j`` (common random
    numbers), as factors on the *nominal* record: the sampled block's scan on the record scaled by the
    sample's amplitude factor, times that factor (none where the run does not sample: ``sampling``,
    :attr:`pipeline.config.Config.sampling`). Returns the margins and the scenes simulated."""
    n = unc.margin_samples if sampling else 0       # --samples 0: nominal results only
    if n <= 0:
        return np.zeros(0), 0
    sb = sample_block(common_normals(unc.seed, n), dataclasses.replace(inv.shape(j), azimuth_deg=math.nan),
                      settings=unc, g_ms2=g_ms2)
    out, runs = np.full(n, np.nan), 0
    for k in range(n):
        eps = float(sb.amplitude[k])
        av = None if av_ms2 is None else eps * av_ms2
        scale, r = overturn_scale_simulated(eps * ah_ms2, av, dt_s, block=sb.block(k), settings=settings)
        out[k], runs = scale * eps, runs + r
    return out, runs


def margin_task(item: tuple, ctx: Context) -> dict:
    """One record and the blocks it governs: their margins and, for those at risk, theta(t)/alpha.

    ``item`` is ``(source, [(block_id, direction_deg, overturned, want_history), ...])``.
    Returns ``{block_id: (scale, runs, history or None, dt_s, sampled margins)}``; run under the engine's
    failure policy (:class:`~pipeline.run.engine.Guarded`): a record that cannot be loaded again comes back as
    its failure.
    """
    from .scanned import scanned_margins

    source, blocks = item
    cfg = ctx.config
    rec = ctx.load(source)
    inv = ctx.inventory
    rocking_blocks = inv.rocking_blocks(g_ms2=cfg.records.g_ms2)
    settings = cfg.simulation_settings()
    index = {b: k for k, b in enumerate(inv.ids)}
    motions = FloorMotions(rec, place_blocks(inv, ctx.buildings))   # a block on a floor: that floor's motion
    out = {}
    for block_id, direction, overturned, want_history in blocks:
        on = motions.of_block(index[block_id])
        if inv.scanned()[index[block_id]]:                              # two-sided, in its governing plane
            out[block_id] = scanned_margins(on, inv.shape(index[block_id]), float(direction), cfg, settings,
                                            overturned=overturned, want_history=want_history)
            continue
        solid = None if on.single_component else solid_of(inv.shape(index[block_id]), record_azimuth_deg=float(
            on.azimuths_deg[0]), known_azimuth=bool(on.azimuth_known))
        if solid is not None:                                           # the 3D model, as its scene was judged
            out[block_id] = _solid_margins(on, inv.shape(index[block_id]), solid, cfg, settings,
                                           overturned=overturned, want_history=want_history)
            continue
        ah = on.along(float(direction))
        block = rocking_blocks[index[block_id]]
        scale, runs = overturn_scale_simulated(ah, on.vertical_ms2, on.dt_s, block=block, settings=settings,
                                               overturns_at_one=overturned)
        history = theta_history(ah, on.vertical_ms2, on.dt_s, block=block, settings=settings) \
            if want_history or scale <= RELOCATE_BELOW_SCALE else None
        sampled, more = sampled_margins(ah, on.vertical_ms2, on.dt_s, j=index[block_id], inv=inv,
                                        settings=settings, unc=cfg.uncertainty, g_ms2=cfg.records.g_ms2,
                                        sampling=cfg.sampling)
        out[block_id] = (scale, runs + more, history, on.dt_s, sampled)
    return out


def solid_history(rec, solid: Solid, *, settings, g_ms2: float) -> np.ndarray | None:
    """A solid's history on two horizontals (:func:`~pipeline.rocking.solids.solid3d.judge_solid`), shape (2, n):
    theta(t)/alpha and the compass azimuth it leans toward [deg] (NaN at rest and after overturning; a box judged in
    the plane of its width leans along it), or None where nothing lifts."""
    h = rec.horizontal_ms2
    got = judge_solid(h[0], h[1], rec.vertical_ms2, rec.dt_s, solid, settings=settings, g_ms2=g_ms2, history=True)
    theta, lean = got.scene.theta_over_alpha, got.lean_history_deg
    if theta is None or lean is None or not got.scene.theta_max > 0:
        return None
    return np.vstack([theta, (float(rec.azimuths_deg[0]) - lean) % 360.0])


def _solid_margins(rec, shape, solid: Solid, cfg, settings, *, overturned: bool, want_history: bool) -> tuple:
    """A solid's margin task on two horizontals, by its 3D model (a box's planar scene where its other axis is
    certified): its scale scan, its history when at risk (:func:`solid_history`), and the sampled margins (each
    draw's own scan, as factors on the nominal record)."""
    g = cfg.records.g_ms2
    scale, runs = solid_scale_simulated(rec, solid, settings=settings, g_ms2=g, overturns_at_one=overturned)
    history = None
    if want_history or scale <= RELOCATE_BELOW_SCALE:
        history = solid_history(rec, solid, settings=settings, g_ms2=g)
    n = cfg.uncertainty.margin_samples if cfg.sampling else 0
    sampled = np.full(max(n, 0), np.nan)
    if n > 0:
        sb = sample_block(common_normals(cfg.uncertainty.seed, n), shape, settings=cfg.uncertainty, g_ms2=g)
        for k in range(n):
            az = None if np.isnan(sb.azimuth_deg[k]) else float(sb.azimuth_deg[k])
            body = drawn(solid, R_m=float(sb.R_m[k]), alpha=float(sb.alpha[k]), mu=float(sb.mu[k]),
                         restitution=float(sb.e[k]), azimuth_deg=az, record_azimuth_deg=float(rec.azimuths_deg[0]))
            eps = float(sb.amplitude[k])
            scaled = dataclasses.replace(rec, horizontal_ms2=eps * rec.horizontal_ms2,
                                         vertical_ms2=None if rec.vertical_ms2 is None else eps * rec.vertical_ms2)
            s_k, r = solid_scale_simulated(scaled, body, settings=settings, g_ms2=g)
            sampled[k], runs = s_k * eps, runs + r
    return scale, runs, history, rec.dt_s, sampled


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
    ds.attrs["margin_settings"] = (f"upward scan of the factor on the governing record, in the governing "
                                   f"scene's rocking plane, x(1 + "
                                   f"{ctx.config.simulation.margin_step:g}) per step, up to "
                                   f"{ctx.config.simulation.margin_max_factor:g}; no bisection")
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
