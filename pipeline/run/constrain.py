"""``screen constrain``: the constraint standing fragile rocks put on a site's hazard.

rocks (fragility and draws, :mod:`.constrain_inputs`) + ages (:mod:`pipeline.uncertainty.ages`) + the hazard
model's end branches (:mod:`pipeline.uncertainty.branches`) -> per branch and rock the toppling rate and the
probability of having stood through the age (:mod:`pipeline.uncertainty.constraint`) -> the rocks combined ->
posterior weights -> the site's hazard before and after (:mod:`pipeline.uncertainty.branch_stats`) ->
``constrain.nc``, ``constrain.html``, ``constrain_branches.csv`` and the reweighted curves in the format the
branches came in (:mod:`pipeline.store.hazard_export`).
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import ConstraintError
from ..records.intensity import display_unit
from ..schema import CONSTRAIN, apply_schema
from ..uncertainty.ages import Age, read_ages
from ..uncertainty.branch_stats import common_levels, fractile_curve, level_at_rate, mean_curve, rates_on
from ..uncertainty.branches import LogicTree, read_branches
from ..uncertainty.constraint import (
    CONTRADICTION_LIKELIHOOD,
    Combine,
    combine,
    contradicting,
    posterior_weights,
    survival_error,
    survival_likelihood,
)
from ..uncertainty.hazard import IM_KIND, Component, annual_rates, annual_rates_upper
from .constrain_inputs import Rocks, read_rocks

#: Annual rates at which the hazard's change is reported [1/yr].
TARGET_RATES = (1e-3, 1e-4, 1e-5)
#: Fractiles of the branches reported [-].
FRACTILES = (0.05, 0.5, 0.95)
#: Branches whose draws' rates are held in memory at once (2,000 x 201 fragilities of one rock: 3.2 MB; at most
#: 160 MB at MAX_DRAWS)
BRANCHES_AT_ONCE = 2000
#: The most fragility draws a run takes (each rock's bootstrap is refitted in chunks; beyond this the sampling
#: error of the likelihood is far below the fragility's own spread)
MAX_DRAWS = 10_000
#: How far a rock's Sa period may be from the branches' before it is said [-]
PERIOD_TOLERANCE = 0.1
#: The files ``screen constrain`` writes besides the reweighted curves
OUTPUTS = ("constrain.nc", "constrain.html", "constrain_branches.csv")


@dataclass(frozen=True)
class ConstrainRequest:
    """What ``screen constrain`` is asked (paths as given)."""

    fragility: Path
    ages: Path
    branches: Path
    out_dir: Path
    combine: Combine = Combine.strongest
    draws: int = 200
    seed: int = 20261123
    site: str | None = None
    lonlat: tuple[float, float] | None = None
    period_s: float | None = None
    #: the hazard's component definition where the files do not say (OpenQuake's: rotd50)
    hazard_component: Component | None = None
    #: a stated conversion of the hazard's levels to the fragility's component
    hazard_scale: float | None = None
    #: reweight even where a rock contradicts every branch (:func:`~pipeline.uncertainty.constraint.contradicting`;
    #: each such rock is then a warning, not an error)
    go_on: bool = False
    command: tuple = ()


@dataclass
class ConstrainResult:
    """The dataset, the files written and what was said."""

    dataset: xr.Dataset
    paths: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    seconds: float = 0.0


def constrain(req: ConstrainRequest, *, say=None) -> ConstrainResult:
    """Read the inputs, compute the constraint, write the outputs (published together); ``say`` (the command's stage
    announcer, or None) is told each stage."""
    t0 = time.perf_counter()
    say = say or (lambda _text: None)
    if not 1 <= req.draws <= MAX_DRAWS:
        raise ConstraintError(f"--draws {req.draws}: between 1 and {MAX_DRAWS:,} draws of each rock's fragility")
    say(f"reading the rocks' fragility and drawing it {req.draws} times ({req.fragility})")
    rocks = read_rocks(req.fragility, draws=req.draws, seed=req.seed)
    ages = read_ages(req.ages)
    say(f"reading the hazard's branches ({req.branches})")
    tree = read_branches(req.branches, im=rocks.im, site=req.site, lonlat=req.lonlat, period_s=req.period_s,
                         component=req.hazard_component)
    tree = _matched(tree, rocks, scale=req.hazard_scale)
    rocks, warnings = _with_ages(rocks, ages, req.ages)
    warnings += _period_warnings(tree, rocks)
    say(f"the toppling rates of {len(rocks.ids)} rock(s) x {req.draws} draws on {len(tree.ids)} branches")
    ds = compute(rocks, ages, tree, rule=req.combine, go_on=req.go_on)
    warnings += [w for w in ds.attrs.pop("contradictions", "").split("\n") if w]
    say("writing constrain.nc, constrain.html (its figure) and the reweighted curves")
    ds.attrs.update({"history": f"{time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())} {' '.join(req.command)}",
                     "fragility_source": rocks.source, "ages_file": str(req.ages), "branches_folder": tree.folder,
                     "warnings": "\n".join(warnings)})
    paths = _publish(ds, tree, req)
    return ConstrainResult(ds, paths, warnings, time.perf_counter() - t0)


def _matched(tree: LogicTree, rocks: Rocks, *, scale: float | None) -> LogicTree:
    """The tree's curves on the fragility's component definition (the stated conversion applied), or an error."""
    if tree.im != rocks.im:
        raise ConstraintError(f"{tree.folder}: the branches are {tree.im} curves, the fragility ({rocks.source}) is "
                              f"fitted on {rocks.im}: give the branches' curves of {rocks.im} or fit on {tree.im}")
    comp = tree.component
    if comp == rocks.component:
        if scale is not None:
            raise ConstraintError(f"--hazard-scale {scale:g} given, but the hazard and the fragility are both "
                                  f"{comp.value if comp else 'undefined'}: leave it out")
        return tree
    if scale is None:
        raise ConstraintError(
            f"{tree.folder}: the hazard is {comp.value if comp else 'of an unstated component'}, the fragility "
            f"({rocks.source}) is fitted on {rocks.component.value}: fit the fragility on the hazard's definition "
            f"('screen fragility --im-component {comp.value if comp else 'rotd50'}'), state the hazard's "
            "(--hazard-component) or the conversion (--hazard-scale FACTOR: hazard x FACTOR = fragility's)")
    curves = tuple(dataclasses.replace(c, levels=c.levels * scale, component=rocks.component,
                                       notes=(*c.notes, f"levels x {scale:g}: {comp.value if comp else '?'} to "
                                                        f"{rocks.component.value}")) for c in tree.curves)
    return dataclasses.replace(tree, curves=curves)


def _with_ages(rocks: Rocks, ages: dict[str, Age], ages_path: Path) -> tuple[Rocks, list[str]]:
    """The rocks that have an age; the others refused (an unknown age constrains nothing)."""
    refused = dict(rocks.refused)
    keep = [k for k, r in enumerate(rocks.ids) if r in ages]
    for r in rocks.ids:
        if r not in ages:
            refused[r] = f"no age in {ages_path}: an unknown age constrains nothing"
    warnings = [f"{r}: left out: {why}" for r, why in refused.items()]
    warnings += [f"{r}: an age is given in {ages_path}, but {rocks.source} has no such rock" for r in ages
                 if r not in rocks.ids and r not in refused]
    if not keep:
        raise ConstraintError("no rock can constrain the hazard: " + "; ".join(warnings))
    rocks = dataclasses.replace(rocks, ids=tuple(rocks.ids[k] for k in keep),
                                fragility=tuple(rocks.fragility[k] for k in keep),
                                status=tuple(rocks.status[k] for k in keep),
                                period_s=tuple(rocks.period_s[k] for k in keep), refused=refused)
    return rocks, warnings


def _period_warnings(tree: LogicTree, rocks: Rocks) -> list[str]:
    """For Sa: each rock whose fragility's period is more than :data:`PERIOD_TOLERANCE` away from the branches'
    (the fragility is fitted on Sa at the rock's own period 2 pi / p)."""
    tree_period = tree.curves[0].period_s
    if rocks.im != "sa" or not np.isfinite(tree_period):
        return []
    return [f"{r}: its fragility is on Sa({p:.3g} s), the branches on Sa({tree_period:g} s) (ratio "
            f"{tree_period / p:.2f}): give the branches at its period for a rate of its own"
            for r, p in zip(rocks.ids, rocks.period_s)
            if np.isfinite(p) and abs(np.log(tree_period / p)) > np.log(1.0 + PERIOD_TOLERANCE)]


def compute(rocks: Rocks, ages: dict[str, Age], tree: LogicTree, *, rule: Combine, go_on: bool = False) -> xr.Dataset:
    """The constraint as a dataset (:data:`pipeline.schema.CONSTRAIN`).

    Raises
    ------
    ConstraintError
        Where a rock contradicts every branch (:func:`_contradictions`), unless ``go_on`` (its text is then the
        dataset's attribute ``contradictions``, one line a rock).
    """
    nr, nb = len(rocks.ids), len(tree.ids)
    rate, upper, lik, mc_error = np.empty((nr, nb)), np.empty((nr, nb)), np.empty((nr, nb)), np.empty((nr, nb))
    rate_lo, rate_hi = np.empty((nr, nb)), np.empty((nr, nb))
    for lo in range(0, nb, BRANCHES_AT_ONCE):                                        # memory bounded
        sl = slice(lo, min(lo + BRANCHES_AT_ONCE, nb))
        for i, (rock, frag) in enumerate(zip(rocks.ids, rocks.fragility)):
            # the draws and then the fit, in one call: the branches' weights built once per rock
            rates = annual_rates(tree.curves[sl], np.append(frag.theta_draws, frag.theta),
                                 np.append(frag.beta_draws, frag.beta))            # (branches, draws + 1)
            rate[i, sl] = rates[:, -1]
            rate_lo[i, sl], rate_hi[i, sl] = np.percentile(rates[:, :-1], [5, 95], axis=1)
            lik[i, sl] = survival_likelihood(rates[:, :-1], ages[rock])
            mc_error[i, sl] = survival_error(rates[:, :-1], ages[rock])
            upper[i, sl] = annual_rates_upper(tree.curves[sl], frag.theta, frag.beta, frag.top_level)
    contradictions = _contradictions(lik, rocks, ages, tree)
    if contradictions and not go_on:
        raise ConstraintError("\n".join(contradictions))
    combined, chosen = combine(lik, tree.weights, rule)
    post = posterior_weights(tree.weights, combined)
    per_rock = np.array([_posterior_or_nan(tree.weights, lik[i]) for i in range(nr)])
    grid = common_levels(tree.curves)
    hazard = np.array([rates_on(c, grid) for c in tree.curves])
    notes = [*_grid_notes(tree, grid, rocks.im), *_error_notes(lik, mc_error, post, rocks, tree)]
    data = {"prior_weight": (("branch",), tree.weights), "posterior_weight": (("branch",), post),
            "likelihood": (("branch",), combined), "likelihood_rock": (("rock", "branch"), lik),
            "posterior_weight_rock": (("rock", "branch"), per_rock),
            "toppling_rate": (("rock", "branch"), rate), "toppling_rate_low": (("rock", "branch"), rate_lo),
            "toppling_rate_high": (("rock", "branch"), rate_hi), "toppling_rate_upper": (("rock", "branch"), upper),
            "branch_path": (("branch",), np.array(tree.paths, dtype=object)),
            "branch_name": (("branch",), np.array(tree.labels, dtype=object)),
            "hazard_rate": (("branch", "im_level"), hazard),
            **_rock_variables(rocks, ages), **_summaries(grid, hazard, tree.weights, post)}
    coords = {"rock": np.array(rocks.ids, dtype=object), "branch": np.array(tree.ids, dtype=object),
              "im_level": grid, "fractile": np.array(FRACTILES), "target_rate": np.array(TARGET_RATES)}
    attrs = {"title": "rockscreen: the constraint of standing fragile rocks on a site's hazard",
             "Conventions": "CF-1.11", "im": rocks.im, "im_component": rocks.component.value,
             "im_units": "m s-2" if IM_KIND[rocks.im] == "acceleration" else "m s-1",
             "combine": rule.value, "constraining_rock": rocks.ids[chosen] if chosen >= 0 else "",
             "fragility_draws": int(len(rocks.fragility[0].theta_draws)),
             "branches_layout": tree.layout.value, "site": tree.curves[0].site,
             "refused": "\n".join(f"{r}: {why}" for r, why in rocks.refused.items()),
             "notes": "\n".join((*rocks.notes, *tree.notes, *dict.fromkeys(n for c in tree.curves for n in c.notes),
                                 *notes)),
             "contradictions": "\n".join(contradictions)}
    return apply_schema(xr.Dataset(data, coords=coords, attrs=attrs), CONSTRAIN)


#: Branches whose posterior weight is below this are left out of the Monte Carlo error said [-].
ERROR_WEIGHT_MIN = 0.01


def _grid_notes(tree: LogicTree, grid: np.ndarray, im: str) -> list[str]:
    """What the branches' common levels do to the outputs: where a branch ends before the others (the outputs end
    there too), and each branch that lacks levels the others give (its rate read log-log between its own)."""
    unit, factor = display_unit(im)
    notes = []
    ends = [float(c.levels[-1]) for c in tree.curves]
    if grid[-1] < max(ends) * (1 - 1e-9):
        short = [tree.labels[b] for b, e in enumerate(ends) if e <= grid[-1] * (1 + 1e-9)
                 and not tree.curves[b].ended_at_zero]
        notes.append(f"the mean and fractile curves end at {grid[-1] / factor:.4g} {unit}, where the curve of "
                     f"{', '.join(short[:3])}{' and others' if len(short) > 3 else ''} ends (the longest goes on to "
                     f"{max(ends) / factor:.4g} {unit}); give every branch on the same levels for outputs above it")
    for b, c in enumerate(tree.curves):
        inside = grid[(grid >= c.levels[0]) & (grid <= c.levels[-1])]
        missing = np.setdiff1d(inside, c.levels)
        if missing.size:
            notes.append(f"{tree.labels[b]}: no rate at {missing.size} level(s) the other branches give (from "
                         f"{missing[0] / factor:.4g} {unit}): read log-log between its own levels")
    return notes


def _error_notes(lik: np.ndarray, error: np.ndarray, post: np.ndarray, rocks: Rocks, tree: LogicTree) -> list[str]:
    """The largest Monte Carlo error of a likelihood relative to it, over the rocks and the branches that keep a
    posterior weight of at least :data:`ERROR_WEIGHT_MIN`: what the draws leave uncertain."""
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where((lik > 0) & (post[None, :] >= ERROR_WEIGHT_MIN), error / lik, 0.0)
    if not np.any(relative > 0):
        return []
    i, b = np.unravel_index(int(np.nanargmax(relative)), relative.shape)
    draws = len(rocks.fragility[0].theta_draws)
    return [f"Monte Carlo error of the likelihoods ({draws} fragility draws): at most {100 * relative[i, b]:.1f} % of "
            f"one (rock {rocks.ids[i]}, branch {tree.labels[b]}); it falls as 1 / sqrt(--draws)"]


def _contradictions(lik: np.ndarray, rocks: Rocks, ages: dict[str, Age], tree: LogicTree) -> list[str]:
    """One line per rock that contradicts every branch (``lik``: rocks x branches): its best branch and chance of
    having stood, and what to check."""
    lines = []
    for i in contradicting(lik):
        rock, frag, b = rocks.ids[i], rocks.fragility[i], int(np.nanargmax(lik[i])) if np.any(lik[i] > 0) else 0
        unit, factor = display_unit(rocks.im)
        lines.append(
            f"{rock}: contradicts every branch of the hazard model: under its most favourable branch ({tree.ids[b]}) "
            f"the chance it stood through its age ({ages[rock].mean_yr:,.0f} yr) is {lik[i, b]:.1e}, below "
            f"{CONTRADICTION_LIKELIHOOD:g}, so the posterior would rest on the least impossible branch, not on the "
            f"rock. Check its fragility (median {frag.theta / factor:.3g} {unit} of {rocks.im} "
            f"{rocks.component.value}: the IM, component and units), its age (years) and that it stands at this "
            "site; --go-on reweights anyway")
    return lines


def _posterior_or_nan(prior: np.ndarray, likelihood: np.ndarray) -> np.ndarray:
    try:
        return posterior_weights(prior, likelihood)
    except ConstraintError:
        return np.full(prior.shape, np.nan)


def _rock_variables(rocks: Rocks, ages: dict[str, Age]) -> dict:
    f = rocks.fragility
    return {"age_mean": (("rock",), np.array([ages[r].mean_yr for r in rocks.ids])),
            "age_sd": (("rock",), np.array([ages[r].sd_yr for r in rocks.ids])),
            "fragility_median": (("rock",), np.array([x.theta for x in f])),
            "fragility_beta": (("rock",), np.array([x.beta for x in f])),
            "fragility_median_draws_low": (("rock",), np.array([np.percentile(x.theta_draws, 5) for x in f])),
            "fragility_median_draws_high": (("rock",), np.array([np.percentile(x.theta_draws, 95) for x in f])),
            "fragility_top_level": (("rock",), np.array([x.top_level for x in f])),
            "fit_status": (("rock",), np.array([int(s) for s in rocks.status], dtype="i1"))}


def _summaries(grid: np.ndarray, hazard: np.ndarray, prior: np.ndarray, post: np.ndarray) -> dict:
    """Mean and fractile curves before and after, and their levels at :data:`TARGET_RATES`."""
    out: dict[str, tuple] = {}
    for tag, w in (("prior", prior), ("posterior", post)):
        mean = mean_curve(hazard, w)
        frac = np.array([fractile_curve(hazard, w, q) for q in FRACTILES])
        out[f"mean_rate_{tag}"] = (("im_level",), mean)
        out[f"fractile_rate_{tag}"] = (("fractile", "im_level"), frac)
        out[f"mean_level_{tag}"] = (("target_rate",), np.array([level_at_rate(grid, mean, r) for r in TARGET_RATES]))
        out[f"fractile_level_{tag}"] = (("fractile", "target_rate"),
                                        np.array([[level_at_rate(grid, f, r) for r in TARGET_RATES] for f in frac]))
    before, after = out["mean_level_prior"][1], out["mean_level_posterior"][1]
    spread_before = out["fractile_level_prior"][1][-1] - out["fractile_level_prior"][1][0]
    spread_after = out["fractile_level_posterior"][1][-1] - out["fractile_level_posterior"][1][0]
    with np.errstate(divide="ignore", invalid="ignore"):
        out["mean_level_change"] = (("target_rate",), after / before - 1.0)
        out["range_change"] = (("target_rate",), spread_after / spread_before - 1.0)
    return out


def summary_lines(ds: xr.Dataset) -> list[str]:
    """The change of the site's hazard at each target rate, one line each, as the page's first table gives it."""
    from ..report.constrain_html import summary_lines as lines

    return lines(ds)


def _publish(ds: xr.Dataset, tree: LogicTree, req: ConstrainRequest) -> list[Path]:
    """Write the outputs into a staged set and publish them together."""
    from ..report.constrain_html import constrain_page
    from ..store import Family, OutputLock, publish_staged, write_atomic, write_csv_atomic, write_text_atomic
    from ..store.hazard_export import branch_rows, write_reweighted
    from .cache import ensure_writable

    out_dir = ensure_writable(req.out_dir, replaces=OUTPUTS)

    def write(stage: Path) -> list[Path]:
        columns, rows = branch_rows(ds)
        return [write_atomic(ds, stage / "constrain.nc"),
                write_text_atomic(stage / "constrain.html", constrain_page(ds)),
                write_csv_atomic(stage / "constrain_branches.csv", columns, rows),
                *write_reweighted(ds, tree, stage)]

    with OutputLock(out_dir, command=" ".join(req.command)):
        return publish_staged(out_dir, write, family=Family.CONSTRAINT, command=" ".join(req.command))
