"""The fragility dataset assembled from the stripes: lognormal fits, their bootstrap intervals, the bounds set by the
records without a verdict, the IM ranking (efficiency and sufficiency) and the warnings said of missing stripes.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..blocks import Inventory
from ..config import Config
from ..errors import UsageError
from ..records.intensity import COMPONENT_IMS, IM_NAMES, IMS, SI_LABEL
from ..scene_table import SCENE
from ..schema import FRAGILITY, apply_schema
from ..uncertainty.fragility import FitStatus, bootstrap_stripes, fit_stripes, im_dispersion, open_interval
from ..uncertainty.hazard import Component, HazardSet
from .fragility_hazard import PERIOD_GAP_WARN, can_rock, hazard_variables


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
        "can_rock": (("block",), can_rock(inventory, config).astype("i1")),
        "sufficiency_p": (("block", "im"), suff), "im_rank": (("block", "im"), rank.astype("i2")),
    }
    if hazard is not None:
        data.update(hazard_variables(hazard, fit, inventory, config, levels, im=im))
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
