"""The fragility report: ``OUT/fragility.html`` and ``OUT/fragility_assets.csv`` of ``screen fragility``.

``fragility_assets.csv`` has its own name, so ``screen fragility --out`` into the output of ``screen`` leaves
that run's ``assets.csv`` as it was.

Assets are ranked by their annual rate of overturning when a hazard curve was given, else
by the fitted median (the most fragile first). Each asset whose stripes hold an overturning
gets its fragility curve (the fitted lognormal, the stripe fractions and their 90 % Wilson
intervals) and, with a hazard curve, the integrand P(C | im) |d lambda / d im| that shows
which shaking levels drive its rate (at most :data:`MAX_FIGURES`, riskiest first).
"""

from __future__ import annotations

import base64
import io
import math
from pathlib import Path

import numpy as np
import xarray as xr

from ..store import write_csv_atomic, write_text_atomic
from ..uncertainty.fragility import FitStatus, fragility_curve
from ..uncertainty.hazard import HazardSet, integrand_segments
from ..uncertainty.robust import wilson_interval
from .mpl import new_figure

#: Fragility figures drawn, riskiest assets first (every number stays in fragility.nc and assets.csv).
MAX_FIGURES = 40
#: The per-asset table's file name (not ``assets.csv``, which is ``screen``'s).
ASSETS_CSV = "fragility_assets.csv"
#: Columns of fragility_assets.csv: ``im`` names the IM and ``im_units`` the unit of median, median_low and
#: median_high; ``orientation`` the probability fitted for a blank azimuth (random or worst orientation); beta
#: is dimensionless, annual_rate_overturn in 1/yr, p_overturn_50yr a probability.
#: Columns of fragility_assets.csv; ``{im}`` and ``{unit}`` are the fit's IM and the unit of ``--levels``
#: (``median_pga_g``), so that every number's unit is in its column's name.
FRAGILITY_ASSET_COLUMNS = ("rank", "block", "im", "im_component", "orientation", "median_{im}_{unit}",
                 "median_low_{im}_{unit}", "median_high_{im}_{unit}", "beta", "beta_low", "beta_high", "fit_status",
                 "annual_rate_overturn_per_yr", "p_overturn_50yr", "annual_rate_overturn_upper_per_yr",
                 "p_overturn_50yr_upper", "best_im", "best_im_beta", "velocity_ratio_rank",
                 "velocity_ratio_beta", "im_ranking", "recommendation")
#: Assets whose fragility the page's first screen says in words, in the table's order (the table follows).
CARDS = 5


def asset_columns(ds: xr.Dataset) -> tuple[str, ...]:
    """:data:`FRAGILITY_ASSET_COLUMNS` for this fit."""
    unit = ds.attrs.get("im_display_unit", "si")
    return tuple(c.format(im=ds.attrs["im"], unit=unit) for c in FRAGILITY_ASSET_COLUMNS)
STATUS_NAMES = {m.value: m.name for m in FitStatus}
#: How the page writes the units of ``--levels``.
UNIT_WORDS = {"g": "g", "gal": "gal", "cms2": "cm s-2", "ms2": "m s-2", "cms": "cm s-1", "ms": "m s-1", "s": "s",
              "1": "-"}


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def rate_text(x) -> str:
    """An annual rate in one notation down its column: two significant digits in scientific notation ('' for
    NaN)."""
    x = float(x)
    return "" if math.isnan(x) else f"{x:.2e}"


def curve_figure(ds: xr.Dataset, j: int, hazard: HazardSet | None) -> str:
    """The PNG (a data URI) of :func:`curve_figure_of`."""
    return _png(curve_figure_of(ds, j, hazard))


def curve_figure_of(ds: xr.Dataset, j: int, hazard: HazardSet | None):
    """The fitted curve with the stripe fractions and their intervals (and the hazard integrand), in the unit the
    levels were given in (the table's), ticks at the levels; the legend below the axes, covering no stripe."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    shown = float(ds.attrs.get("im_display_factor", 1.0))
    units = UNIT_WORDS.get(ds.attrs.get("im_display_unit", ""), ds.attrs["im_units"])
    levels = ds["im_level"].values / shown
    fig = new_figure(figsize=(9.0 if hazard is not None else 5.0, 4.2))
    fig.subplots_adjust(left=0.09 if hazard is not None else 0.14, right=0.98, top=0.9, bottom=0.34, wspace=0.28)
    axes = fig.subplots(1, 2 if hazard is not None else 1, squeeze=False)[0]
    ax = axes[0]
    n, z = ds["n_records"].values[j], ds["overturned_sum"].values[j]
    frac = ds["fraction_overturned"].values[j]
    lo, hi = wilson_interval(np.round(z), n)
    ok = n > 0
    ax.errorbar(levels[ok], frac[ok], yerr=[frac[ok] - lo[ok], hi[ok] - frac[ok]], fmt="o", color="k", ms=4,
                capsize=2, label="stripes (90 % interval)")
    theta, beta = float(ds["median"].values[j]) / shown, float(ds["beta"].values[j])
    x = np.geomspace(levels[0] / 2, levels[-1] * 2, 200)
    if np.isfinite(theta) and theta > 0 and np.isfinite(beta):
        ax.plot(x, fragility_curve(x, theta, beta), color="tab:red",
                label=f"lognormal: median {theta:.3g} {units}, beta {beta:.2f}")
    ax.set_xscale("log")
    ax.xaxis.set_major_locator(FixedLocator(levels.tolist()))  # the tested levels, labelled plainly
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:.3g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_ylim(-0.03, 1.03)
    ax.set_xlabel(f"{ds.attrs['im']} [{units}]")
    ax.set_ylabel("P(overturn)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.2), borderaxespad=0.0, frameon=False)
    ax.set_title(str(ds["block"].values[j]), fontsize=9)
    if hazard is not None:
        period = float(ds["hazard_period"].values[j]) if "hazard_period" in ds else math.nan
        curve = next((c for c in hazard.curves if c.period_s == period), hazard.curves[0])
        im, dens, _ = integrand_segments(curve, theta * shown, beta)
        axes[1].plot(im / shown, dens * im, color="k")
        axes[1].set_xscale("log")
        axes[1].xaxis.set_minor_formatter(NullFormatter())
        axes[1].xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:.3g}"))
        axes[1].set_xlabel(f"{ds.attrs['im']} [{units}]")
        axes[1].set_ylabel("P(C|im) |d lambda / d ln im| [1/yr]")
        axes[1].set_title("which shaking levels drive the rate", fontsize=9)
        axes[1].grid(alpha=0.3, which="both")
    return fig


def asset_rows(ds: xr.Dataset) -> list[dict]:
    """One row per block, riskiest first."""
    ims = ds["im"].values.tolist()
    unit, factor = ds.attrs.get("im_display_unit", "si"), float(ds.attrs.get("im_display_factor", 1.0))
    rows = []
    for j, block in enumerate(ds["block"].values.tolist()):
        beta_im, rank = ds["beta_im"].values[j], ds["im_rank"].values[j]
        order = np.argsort(rank)
        best = int(order[0])
        vr = ims.index("velocity_ratio")
        rows.append({
            "block": block, "j": j, "im": ds.attrs["im"], "im_units": ds.attrs["im_units"],
            "orientation": ds.attrs.get("orientation", "random"),
            **{k: float(ds[k].values[j]) for k in ("median", "median_low", "median_high", "beta", "beta_low",
                                                    "beta_high")},
            "im_component": ds.attrs.get("im_component", ""),
            **{f"{k}_{ds.attrs['im']}_{unit}": float(ds[k].values[j]) / factor
               for k in ("median", "median_low", "median_high")},
            **{f"{k}_shown": float(ds[k].values[j]) / factor for k in ("median", "median_low", "median_high")},
            "annual_rate_overturn_per_yr": float(ds["annual_rate_overturn"].values[j])
            if "annual_rate_overturn" in ds else math.nan,
            "fit_status": STATUS_NAMES[int(ds["fit_status"].values[j])],
            "annual_rate_overturn": float(ds["annual_rate_overturn"].values[j]) if "annual_rate_overturn" in ds
            else math.nan,
            "p_overturn_50yr": float(ds["p_overturn_50yr"].values[j]) if "p_overturn_50yr" in ds else math.nan,
            "annual_rate_overturn_upper_per_yr": float(ds["annual_rate_overturn_upper"].values[j])
            if "annual_rate_overturn_upper" in ds else math.nan,
            "p_overturn_50yr_upper": float(ds["p_overturn_50yr_upper"].values[j])
            if "p_overturn_50yr_upper" in ds else math.nan,
            "best_im": ims[best] if np.isfinite(beta_im[best]) else "", "best_im_beta": float(beta_im[best]),
            "velocity_ratio_rank": int(rank[vr]), "velocity_ratio_beta": float(beta_im[vr]),
            "im_ranking": ";".join(f"{ims[k]}={beta_im[k]:.3g}" for k in order if np.isfinite(beta_im[k])),
            "at_risk": int(ds["fit_status"].values[j]) != FitStatus.none_overturn,
            "can_rock": bool(int(ds["can_rock"].values[j])) if "can_rock" in ds else True,
            **_unjudged_row(ds, j, factor),
        })
    # by the rate, or where none could be computed (nothing overturned up to the top level) by its upper bound
    rows.sort(key=lambda r: (-np.nan_to_num(r["annual_rate_overturn"] if np.isfinite(r["annual_rate_overturn"])
                                            else r["annual_rate_overturn_upper_per_yr"], nan=-1.0), r["median"]))
    words = UNIT_WORDS.get(unit, ds.attrs.get("im_units", ""))
    for k, r in enumerate(rows, 1):
        r["rank"] = k
        r["recommendation"] = fragility_words(r, im=ds.attrs["im"].upper(), unit=words)
    return rows


def fragility_words(r: dict, *, im: str, unit: str) -> str:
    """What an asset's fragility says, in plain words (the page's first screen and fragility_assets.csv's
    ``recommendation``): its 50-year probability of overturning where a hazard curve was given, else the shaking at
    which half of the records overturn it; an asset that cannot rock, or that no level overturned, said so."""
    if not r["can_rock"]:
        return "cannot overturn: too wide to rock, it slides or stands"
    if r["fit_status"] == "none_overturn":
        return "no level tested overturned it: raise the levels to bound its fragility"
    if math.isfinite(r["p_overturn_50yr"]):
        return (f"P = {r['p_overturn_50yr']:.2g} that it overturns in 50 years at this hazard (median {im} "
                f"{r['median_shown']:.3g} {unit})")
    if not math.isfinite(r["median_shown"]):
        return "its median is not bounded by the levels tested: read its stripes"
    interval = (f" ({r['median_low_shown']:.3g} to {r['median_high_shown']:.3g})"
                if math.isfinite(r["median_low_shown"]) and math.isfinite(r["median_high_shown"]) else "")
    return f"half of the records overturn it at {im} {r['median_shown']:.3g} {unit}{interval}"


def _unjudged_row(ds: xr.Dataset, j: int, factor: float) -> dict:
    """Block ``j``'s records without a verdict (summed over the stripes, and the stripe with most), and its medians
    with them counted as overturning and as standing [display units]."""
    if "n_unjudged" not in ds:
        return {"unjudged": 0.0, "unjudged_most": "", "median_unjudged_overturn_shown": math.nan,
                "median_unjudged_stand_shown": math.nan}
    u = ds["n_unjudged"].values[j]
    k = int(np.argmax(u))
    return {"unjudged": float(u.sum()),
            "unjudged_most": (f"{u[k]:.3g} of {int(ds['n_scaled'].values[j, k])} at "
                              f"{float(ds['im_level'].values[k]) / factor:.4g}"),
            "median_unjudged_overturn_shown": float(ds["median_unjudged_overturn"].values[j]) / factor,
            "median_unjudged_stand_shown": float(ds["median_unjudged_stand"].values[j]) / factor}


def build_fragility_report(ds: xr.Dataset, out_dir: Path, *, hazard: HazardSet | None = None
                           ) -> tuple[Path, Path]:
    """Write ``fragility.html`` and :data:`ASSETS_CSV` into ``out_dir``."""
    from jinja2 import Environment, PackageLoader, select_autoescape

    from .html import _num

    rows = asset_rows(ds)
    drawn = 0
    for r in rows:
        r["figure"] = None
        if r["at_risk"] and drawn < MAX_FIGURES:
            r["figure"] = curve_figure(ds, r["j"], hazard)
            drawn += 1
    env = Environment(loader=PackageLoader("pipeline.report", "templates"),
                      autoescape=select_autoescape(["html", "j2"]))
    env.filters["num"] = _num
    env.filters["rate"] = rate_text
    ims = ds["im"].values.tolist()
    html = env.get_template("fragility.html.j2").render(
        attrs=ds.attrs, assets=rows, cards=rows[:CARDS], hazard=hazard, levels=ds["im_level"].values.tolist(), ims=ims,
        levels_shown=(ds["im_level"].values / float(ds.attrs.get("im_display_factor", 1.0))).tolist(),
        unit_shown=UNIT_WORDS.get(ds.attrs.get("im_display_unit", ""), ds.attrs.get("im_units", "")),
        n_records=ds.sizes["record"], drawn=drawn, unjudged=sum(r["unjudged"] > 0 for r in rows),
        at_risk=sum(r["at_risk"] for r in rows),
        mean_beta={im: float(np.nanmedian(np.where(np.isfinite(ds["beta_im"].values[:, k]),
                                                   ds["beta_im"].values[:, k], np.nan)))
                   if np.isfinite(ds["beta_im"].values[:, k]).any() else math.nan for k, im in enumerate(ims)},
        wins={im: int(np.sum(ds["im_rank"].values[:, k] == 1)) for k, im in enumerate(ims)})
    html_path = write_text_atomic(out_dir / "fragility.html", html)
    columns = asset_columns(ds)
    table = [{c: r[c] for c in columns} for r in rows]
    return html_path, write_csv_atomic(out_dir / ASSETS_CSV, columns, table)
