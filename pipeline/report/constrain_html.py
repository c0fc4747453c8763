"""``constrain.html``: the site's hazard before and after the rocks, the branches' weights, the rocks used and the
rocks left out, and the limits of the method, drawn from ``constrain.nc``."""

from __future__ import annotations

import base64
import io
import math

import numpy as np
import xarray as xr

from ..records.intensity import display_unit
from ..uncertainty.fragility import FitStatus
from .mpl import new_figure

#: Branches drawn in the figure, the heaviest after the constraint first (every curve is in constrain.nc)
MAX_CURVES = 200


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def hazard_figure(ds: xr.Dataset) -> str:
    """The branches' hazard curves coloured by their posterior weight, the prior and posterior means and 5-95 %
    fractiles, and the target rates; a PNG as a data URL."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    unit, factor = display_unit(ds.attrs["im"])
    x = ds["im_level"].values / factor
    post = ds["posterior_weight"].values
    fig = new_figure(figsize=(7.5, 5.0), layout="constrained")
    ax = fig.add_subplot()
    cmap, norm = colormaps["viridis"], Normalize(vmin=0.0, vmax=max(float(post.max()), 1e-9))
    for b in np.argsort(post)[-MAX_CURVES:]:                 # the heaviest drawn last, on top
        ax.plot(x, ds["hazard_rate"].values[b], color=cmap(norm(post[b])), lw=1.2, alpha=0.9)
    ax.plot(x, ds["mean_rate_prior"].values, "k--", lw=2, label="mean, prior weights")
    ax.plot(x, ds["mean_rate_posterior"].values, color="#c0392b", lw=2.4, label="mean, posterior weights")
    f = ds["fractile_rate_posterior"].values
    ax.fill_between(x, f[0], f[-1], color="#c0392b", alpha=0.12, label="5-95 %, posterior")
    fp = ds["fractile_rate_prior"].values
    ax.plot(x, fp[0], "k:", lw=1), ax.plot(x, fp[-1], "k:", lw=1, label="5 % and 95 %, prior")
    for r in ds["target_rate"].values:
        ax.axhline(r, color="#888", lw=0.6)
    ax.set(xscale="log", yscale="log", xlabel=f"{ds.attrs['im'].upper()} ({ds.attrs['im_component']}) [{unit}]",
           ylabel="annual rate of exceedance [1/yr]", ylim=(min(1e-6, float(np.nanmin(ds["target_rate"].values)) / 3),
                                                            None))
    ax.legend(fontsize=8, loc="lower left")
    fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, label="posterior weight of the branch")
    return _png(fig)


def level_text(x: float, factor: float) -> str:
    """A level [SI] in the display unit (``factor`` to SI), or "not reached" where the curve does not reach the
    rate."""
    return "not reached" if not math.isfinite(x) else f"{x / factor:.3g}"


def percent_text(x: float) -> str:
    """A relative change as a signed percentage ("0 %" where it rounds to 0; "not computed" where it is not a
    number: a curve that does not reach the rate)."""
    if not math.isfinite(x):
        return "not computed"
    return "0 %" if round(100 * x) == 0 else f"{100 * x:+.0f} %"


def change_rows(ds: xr.Dataset) -> list[dict]:
    """The change of the site's hazard at each target rate, as text in the IM's display unit: the page's first
    table and the lines ``screen constrain`` prints (:func:`summary_lines`)."""
    _, factor = display_unit(ds.attrs["im"])
    rows = []
    for k, r in enumerate(ds["target_rate"].values):
        fp, fq = ds["fractile_level_prior"].values[:, k], ds["fractile_level_posterior"].values[:, k]
        rows.append({"rate": f"{r:.0e}", "prior": level_text(ds["mean_level_prior"].values[k], factor),
                     "posterior": level_text(ds["mean_level_posterior"].values[k], factor),
                     "change": percent_text(ds["mean_level_change"].values[k]),
                     "prior_low": level_text(fp[0], factor), "prior_high": level_text(fp[-1], factor),
                     "posterior_low": level_text(fq[0], factor), "posterior_high": level_text(fq[-1], factor),
                     "width_change": percent_text(ds["range_change"].values[k])})
    return rows


#: The annual rate the headline reads the change at [1/yr] (the middle target rate).
HEADLINE_RATE = 1e-4
#: Branches the headline names as losing weight, at most.
HEADLINE_BRANCHES = 2


def headline(ds: xr.Dataset) -> dict:
    """The page's first words: what the rocks do to the site's mean hazard at :data:`HEADLINE_RATE` (``change``),
    and the branches that lose the most weight with their prior and posterior weights (``losers``)."""
    unit, factor = display_unit(ds.attrs["im"])
    k = int(np.argmin(np.abs(np.log(ds["target_rate"].values / HEADLINE_RATE))))
    rate = f"{ds['target_rate'].values[k]:.0e}"
    before, after = ds["mean_level_prior"].values[k], ds["mean_level_posterior"].values[k]
    change = ds["mean_level_change"].values[k]
    im = f"{ds.attrs['im'].upper()} ({ds.attrs['im_component']})"
    if not (math.isfinite(before) and math.isfinite(after)):
        text = f"The site's mean {im} hazard curve does not reach {rate} per year: its change there is not computed."
    elif round(100 * change) == 0:
        text = (f"The rocks leave the site's mean {im} at {rate} per year unchanged: "
                f"{level_text(before, factor)} {unit}.")
    else:
        verb = "lower" if change < 0 else "raise"
        text = (f"The rocks {verb} the site's mean {im} at {rate} per year by {abs(100 * change):.0f} %, from "
                f"{level_text(before, factor)} to {level_text(after, factor)} {unit}.")
    names = _branch_names(ds)
    moved = ds["posterior_weight"].values - ds["prior_weight"].values
    losers = [{"name": str(names[b]), "prior": f"{ds['prior_weight'].values[b]:.2f}",
               "posterior": f"{ds['posterior_weight'].values[b]:.2f}"}
              for b in np.argsort(moved)[:HEADLINE_BRANCHES] if moved[b] < -0.005]
    return {"text": text, "losers": losers}


def _branch_names(ds: xr.Dataset) -> np.ndarray:
    """Each branch's readable name (``branch_name``; its path in a dataset written before names were read)."""
    return ds["branch_name"].values if "branch_name" in ds else ds["branch_path"].values


def summary_lines(ds: xr.Dataset) -> list[str]:
    """One line per target rate: the mean and the 5-95 % range before and after."""
    unit = display_unit(ds.attrs["im"])[0]
    return [f"at {r['rate']}/yr: mean {ds.attrs['im']} {r['prior']} -> {r['posterior']} {unit} ({r['change']}); "
            f"5-95 % {r['prior_low']}-{r['prior_high']} -> {r['posterior_low']}-{r['posterior_high']} {unit} "
            f"(width {r['width_change']})" for r in change_rows(ds)]


def _rock_rows(ds: xr.Dataset, factor: float) -> list[dict]:
    rows = []
    for i, rock in enumerate(ds["rock"].values):
        rows.append({"rock": str(rock), "median": f"{ds['fragility_median'].values[i] / factor:.3g}",
                     "draws": f"{ds['fragility_median_draws_low'].values[i] / factor:.3g} to "
                              f"{ds['fragility_median_draws_high'].values[i] / factor:.3g}",
                     "beta": f"{ds['fragility_beta'].values[i]:.2f}",
                     "status": FitStatus(int(ds["fit_status"].values[i])).name.replace("_", " "),
                     "age": f"{ds['age_mean'].values[i]:,.0f} &plusmn; {ds['age_sd'].values[i]:,.0f}",
                     "rates": f"{np.nanmin(ds['toppling_rate'].values[i]):.2e} to "
                              f"{np.nanmax(ds['toppling_rate'].values[i]):.2e}",
                     "likelihoods": f"{np.min(ds['likelihood_rock'].values[i]):.3f} to "
                                    f"{np.max(ds['likelihood_rock'].values[i]):.3f}"})
    return rows


def _branch_rows(ds: xr.Dataset) -> list[dict]:
    order = np.argsort(-ds["posterior_weight"].values)[:MAX_CURVES]
    names = _branch_names(ds)
    return [{"branch": str(ds["branch"].values[b]), "name": str(names[b]), "path": str(ds["branch_path"].values[b]),
             "prior": f"{ds['prior_weight'].values[b]:.3f}", "likelihood": f"{ds['likelihood'].values[b]:.3g}",
             "posterior": f"{ds['posterior_weight'].values[b]:.3f}"} for b in order]


def constrain_page(ds: xr.Dataset) -> str:
    """The page's HTML."""
    from jinja2 import Environment, PackageLoader, select_autoescape

    unit, factor = display_unit(ds.attrs["im"])
    env = Environment(loader=PackageLoader("pipeline.report", "templates"),
                      autoescape=select_autoescape(["html", "j2"]))
    refused = [line.split(": ", 1) for line in ds.attrs.get("refused", "").splitlines() if line]
    return env.get_template("constrain.html.j2").render(
        attrs=ds.attrs, unit=unit, changes=change_rows(ds), headline=headline(ds), rocks=_rock_rows(ds, factor),
        branches=_branch_rows(ds), refused=refused, figure=hazard_figure(ds), drawn=min(MAX_CURVES, ds.sizes["branch"]),
        n_branches=ds.sizes["branch"],
        notes=[n for n in ds.attrs.get("notes", "").splitlines() if n],
        warnings=[w for w in ds.attrs.get("warnings", "").splitlines() if w])
