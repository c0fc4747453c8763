"""The rocks of ``screen constrain``: each rock's fragility with its draws, read from a ``screen fragility`` run or
a table of lognormal parameters, and the rocks that cannot constrain anything, each with its reason.

From ``fragility.nc`` the draws are the bootstrap's: the records resampled with replacement and the stripes
fitted again (:func:`pipeline.uncertainty.fragility.fit_stripes`, the same fit as the run's), so that the
fragility's own uncertainty enters the likelihood. A scaled record without a verdict counts as the rock standing, and
the point fit is then the run's ``median_unjudged_stand``. From a table, the median is drawn lognormal and beta normal
(truncated at :data:`BETA_MIN`), each with the standard deviation its 90 % interval implies, or held at the
point where no interval is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr
from scipy.stats import norm

from ..errors import ConstraintError
from ..scene_table import SCENE
from ..tables import read_csv_table
from ..uncertainty.constraint import FragilityDraws
from ..uncertainty.fragility import FitStatus, fit_stripes
from ..uncertainty.hazard import IM_KIND, UNITS, Component

#: The smallest dispersion a table's draws take [-].
BETA_MIN = 0.05
#: Bootstrap draws refitted at once (each holds every record's outcome at every level)
DRAWS_AT_ONCE = 200
#: The z-score of a 90 % interval's ends.
Z90 = float(norm.ppf(0.95))
#: A fragility table's columns (the intervals optional: without them the fragility is taken as exact).
TABLE_HEADER = "rock,im,component,median,unit,beta[,median_low,median_high,beta_low,beta_high]"


@dataclass(frozen=True)
class Rocks:
    """The rocks a constraint uses, their fragilities, and the ones left out with the reason."""

    ids: tuple
    fragility: tuple               # FragilityDraws per rock
    im: str
    component: Component
    #: rock id -> why it cannot constrain the hazard
    refused: dict
    source: str
    notes: tuple = ()
    #: per rock: the fit's status (FitStatus)
    status: tuple = ()
    #: per rock: the period of its Sa fragility [s] (NaN: not known, or an IM other than Sa)
    period_s: tuple = ()


def read_rocks(path: Path, *, draws: int, seed: int) -> Rocks:
    """The rocks of a ``screen fragility`` output folder (its ``fragility.nc``) or of a fragility table (CSV).

    Raises
    ------
    ConstraintError
        For a folder without ``fragility.nc``, a table that is not :data:`TABLE_HEADER`, and values that are not
        a fragility (named with the line).
    """
    path = Path(path)
    nc = path / "fragility.nc" if path.is_dir() else path
    if nc.suffix.lower() != ".nc":
        return _from_table(path, draws=draws, seed=seed)
    if not nc.is_file():
        raise ConstraintError(f"{nc}: no fragility.nc; --fragility is the --out folder of a 'screen fragility' run, or "
                              f"a CSV {TABLE_HEADER}")
    with xr.open_dataset(nc) as ds:
        return _from_run(ds.load(), str(nc), draws=draws, seed=seed)


def _from_run(ds: xr.Dataset, source: str, *, draws: int, seed: int) -> Rocks:
    levels = ds["im_level"].values.astype(float)
    sampled = not str(ds.attrs.get("outcome_measure", "nominal")).startswith("nominal")   # else probabilities
    verdict, prob = ds["outcome"].values, ds[SCENE.p_overturn].values
    factor = ds["scale_factor"].values
    outcome = prob if sampled else np.where(verdict >= 0, verdict.astype(float), np.nan)
    scaled = np.isfinite(factor)
    # a record-level without a verdict counts as the rock standing: no stripe's toppling fraction is raised by it
    unjudged = scaled & ~np.isfinite(outcome)
    outcome = np.where(scaled, np.where(unjudged, 0.0, outcome), np.nan)     # (record, level, block)
    ids = [str(b) for b in ds["block"].values]
    refused, frags, status, notes, periods = {}, [], [], [], []
    unit, shown = _display(ds)
    rng = np.random.Generator(np.random.PCG64(seed))
    for j, rock in enumerate(ids):
        st = FitStatus(int(ds["fit_status"].values[j]))
        reason = _refusal(st, bool(ds["can_rock"].values[j]), levels / shown, unit)
        if reason:
            refused[rock] = reason
            continue
        theta, beta = float(ds["median"].values[j]), float(ds["beta"].values[j])
        if unjudged[:, :, j].any() and "median_unjudged_stand" in ds:
            theta, beta = float(ds["median_unjudged_stand"].values[j]), float(ds["beta_unjudged_stand"].values[j])
            notes.append(f"{rock}: {int(unjudged[:, :, j].sum())} scaled record(s) without a verdict counted as "
                         "standing (no stripe's toppling fraction raised by what was not judged)")
        theta_d, beta_d = _bootstrap(outcome[:, :, j], levels, draws, rng)
        frags.append(FragilityDraws(theta, beta, theta_d, beta_d, float(levels.max())))
        status.append(st)
        periods.append(float(ds["block_period"].values[j]) if "block_period" in ds else math.nan)
    kept = tuple(r for r in ids if r not in refused)
    component = Component(ds.attrs.get("im_component") or Component.rotd100.value)
    return Rocks(kept, tuple(frags), str(ds.attrs["im"]), component, refused, source,
                 (f"fragility draws: {draws} bootstrap resamplings of the records "
                  f"({ds.attrs.get('outcome_measure')})", *notes),
                 tuple(status), tuple(periods))


def _bootstrap(outcome: np.ndarray, levels: np.ndarray, draws: int, rng) -> tuple[np.ndarray, np.ndarray]:
    """Fits of the stripes with the records (rows of ``outcome``) resampled, :data:`DRAWS_AT_ONCE` at a time: the
    medians [SI] (inf: nothing toppled in the draw; 0: everything did) and dispersions of the draws with a fit."""
    thetas, betas = [], []
    n = outcome.shape[0]
    for k in range(0, draws, DRAWS_AT_ONCE):
        pick = rng.integers(0, n, size=(min(DRAWS_AT_ONCE, draws - k), n))
        sample = outcome[pick]                                          # (draws, records, levels)
        fit = fit_stripes(levels, np.nansum(sample, axis=1), np.sum(np.isfinite(sample), axis=1).astype(float))
        keep = (np.isfinite(fit.theta) & np.isfinite(fit.beta)) | np.isin(fit.theta, (0.0, np.inf))
        thetas.append(fit.theta[keep])
        betas.append(np.where(np.isfinite(fit.beta[keep]), fit.beta[keep], 1.0))
    return np.concatenate(thetas), np.concatenate(betas)


def _display(ds: xr.Dataset) -> tuple[str, float]:
    return str(ds.attrs.get("im_display_unit", "")), float(ds.attrs.get("im_display_factor", 1.0))


def _refusal(status: FitStatus, can_rock: bool, levels_shown: np.ndarray, unit: str) -> str:
    """Why a rock's fragility cannot constrain the hazard ("" if it can)."""
    lo, hi = f"{levels_shown.min():.3g} {unit}", f"{levels_shown.max():.3g} {unit}"
    if not can_rock:
        return "it cannot rock (it slides first or is too squat to tip): it has no overturning fragility"
    if status == FitStatus.none_overturn:
        return (f"it toppled at no level tested (up to {hi}): its fragility is unbounded above; re-run 'screen "
                "fragility' with higher --levels (or auto)")
    if status == FitStatus.not_bounded:
        return (f"its stripes ({lo} to {hi}) do not bracket 50 % toppling: the median lies beyond the levels "
                "tested and is unbounded; re-run 'screen fragility' with wider --levels (or auto)")
    if status == FitStatus.all_overturn:
        return f"it toppled at every level tested, down to {lo}: re-run 'screen fragility' with lower --levels"
    return ""


def _from_table(path: Path, *, draws: int, seed: int) -> Rocks:
    header, rows = read_csv_table(path, what="fragility", expected_header=TABLE_HEADER,
                                  required=("rock", "im", "component", "median", "unit", "beta"))
    rng = np.random.Generator(np.random.PCG64(seed))
    ids, frags, ims, comps = [], [], set(), set()
    for _line, where, cells in rows:
        im, comp, unit = cells["im"].lower(), cells["component"].lower(), cells["unit"].lower()
        if im not in IM_KIND:
            raise ConstraintError(f"{where}: im {cells['im']!r}; expected one of {sorted(IM_KIND)}")
        if comp not in {c.value for c in Component}:
            raise ConstraintError(f"{where}: component {cells['component']!r}; expected one of "
                                  f"{[c.value for c in Component]}")
        factor = UNITS[IM_KIND[im]].get(unit)
        if factor is None:
            raise ConstraintError(f"{where}: unit {cells['unit']!r} for {im}; expected one of "
                                  f"{sorted(UNITS[IM_KIND[im]])}")
        values = {k: _number(cells, k, where) for k in ("median", "beta", "median_low", "median_high", "beta_low",
                                                         "beta_high") if k in header and cells.get(k, "") != ""}
        if not (values["median"] > 0 and math.isfinite(values["median"]) and values["beta"] > 0):
            raise ConstraintError(f"{where}: median {cells['median']} and beta {cells['beta']}: a bounded lognormal "
                                  "fragility has a positive finite median and beta; an unbounded one constrains "
                                  "nothing (leave the rock out)")
        theta, beta = values["median"] * factor, values["beta"]
        theta_d, beta_d = _table_draws(theta, beta, values, factor, draws, rng, where)
        frags.append(FragilityDraws(theta, beta, theta_d, beta_d, math.inf))
        ids.append(cells["rock"])
        ims.add(im)
        comps.add(comp)
    if not ids:
        raise ConstraintError(f"{path}: no rows; expected {TABLE_HEADER}")
    if len(ims) > 1 or len(comps) > 1:
        raise ConstraintError(f"{path}: rocks on {sorted(ims)} and components {sorted(comps)}: one IM and one "
                              "component for every rock, the hazard's")
    return Rocks(tuple(ids), tuple(frags), ims.pop(), Component(comps.pop()), {}, str(path),
                 (f"fragility draws: {draws} from each row's 90 % intervals (median lognormal, beta normal)",),
                 tuple(FitStatus.ok for _ in ids), tuple(math.nan for _ in ids))


def _number(cells: dict, key: str, where: str) -> float:
    try:
        return float(cells[key])
    except ValueError:
        raise ConstraintError(f"{where}: {key} = {cells[key]!r} is not a number") from None


def _table_draws(theta: float, beta: float, values: dict, factor: float, draws: int, rng, where: str):
    """Draws of (median [SI], beta) from a table row's 90 % intervals (the point where none is given)."""
    if "median_low" in values and "median_high" in values:
        lo, hi = values["median_low"] * factor, values["median_high"] * factor
        if not 0 < lo <= theta <= hi:
            raise ConstraintError(f"{where}: median interval {values['median_low']}-{values['median_high']} does "
                                  f"not hold the median {values['median']}")
        theta_d = theta * np.exp(rng.normal(0.0, math.log(hi / lo) / (2 * Z90), draws))
    else:
        theta_d = np.full(draws, theta)
    if "beta_low" in values and "beta_high" in values:
        if not 0 < values["beta_low"] <= beta <= values["beta_high"]:
            raise ConstraintError(f"{where}: beta interval {values['beta_low']}-{values['beta_high']} does not hold "
                                  f"beta {beta}")
        beta_d = np.maximum(rng.normal(beta, (values["beta_high"] - values["beta_low"]) / (2 * Z90), draws), BETA_MIN)
    else:
        beta_d = np.full(draws, beta)
    return theta_d, beta_d
