"""The event page of ``screen event``: ``OUT/event.html``.

It opens with the inspection list (highest priority first) and a map: the ShakeMap field the assets' fragilities
read, drawn from the grid itself (no map tiles, nothing fetched from the network), the assets coloured by their
inspection level, and the epicentre. Each asset's probability links to its fragility curve with the site's
shaking marked on it (drawn as SVG, at most ``curves`` of them, highest priority first; every number stays in
event.nc and inspection.csv).
"""

from __future__ import annotations

import base64
import math
from html import escape

import numpy as np
import xarray as xr
from scipy.special import ndtr

from ..blocks import Inventory
from ..event.advice import advice_at, is_scenario, natural_rocks
from ..event.assets import Basis, Level
from ..event.shakemap import ShakeMapGrid
from ..records.intensity import display_unit
from ..uncertainty.fragility import FitStatus
from .fragility_html import UNIT_WORDS
from .mpl import new_figure, png_bytes

#: Colour of each inspection level (map markers, table cells)
LEVEL_COLOURS = {Level.high: "#d7301f", Level.medium: "#fc8d59", Level.low: "#fdd49e", Level.none: "#bdbdbd"}
#: Assets whose decision the page's first screen gives, in priority order (the list follows)
CARDS = 5
#: Rows of the inspection list on the page (the whole list is inspection.csv)
PAGE_ROWS = 500
#: Assets named on the map, highest priority first
MAP_LABELS = 8
#: Fragility curve panel, SVG [px]
CURVE_W, CURVE_H, CURVE_PAD = 360, 190, 42


def _unit(ds: xr.Dataset) -> tuple[str, float]:
    """The unit the page shows the shaking in (the IM's display unit, :func:`~pipeline.records.intensity.display_unit`)
    and the factor from SI to it."""
    label, to_si = display_unit(ds.attrs["im"])
    return UNIT_WORDS.get(label, label), 1.0 / to_si


def _plain_log_ticks(axis) -> None:
    """A logarithmic colour bar's ticks at 1, 2 and 5 of each decade, labelled as plain numbers, the rest unlabelled:
    matplotlib labels every minor tick of a range under a decade, and at 1,400 px "3x10^0" ran into "4x10^0"."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def map_png(ds: xr.Dataset, grid: ShakeMapGrid, inv: Inventory, order: list[int]) -> bytes:
    """PNG of :func:`map_figure`."""
    return png_bytes(map_figure(ds, grid, inv, order))


def map_figure(ds: xr.Dataset, grid: ShakeMapGrid, inv: Inventory, order: list[int]):
    """The map: the field most assets read, on a log colour scale, the assets by level, the epicentre. The colour
    bar and the legend sit below the map and the names of the first :data:`MAP_LABELS` assets in a column beside
    it, each joined to its asset by a leader line, so that no label covers another or the assets near the
    epicentre."""
    from matplotlib.colors import LogNorm

    names, counts = np.unique(ds["shakemap_field"].values.astype(str), return_counts=True)
    field = str(names[np.argmax(counts)])
    label, factor = _unit(ds)
    lon, lat = ds["lon"].values, ds["lat"].values
    epi = (float(ds.attrs["epicentre_lon"]), float(ds.attrs["epicentre_lat"]))
    xs = np.append(lon, epi[0] if math.isfinite(epi[0]) else lon[0])
    ys = np.append(lat, epi[1] if math.isfinite(epi[1]) else lat[0])
    pad_x, pad_y = max(np.ptp(xs) * 0.15, 0.1), max(np.ptp(ys) * 0.15, 0.1)
    x0, x1 = max(xs.min() - pad_x, grid.lon[0]), min(xs.max() + pad_x, grid.lon[-1])
    y0, y1 = max(ys.min() - pad_y, grid.lat[0]), min(ys.max() + pad_y, grid.lat[-1])
    ix = (grid.lon >= x0) & (grid.lon <= x1)
    iy = (grid.lat >= y0) & (grid.lat <= y1)
    values = grid.medians[field][np.ix_(iy, ix)] * factor
    fig = new_figure(figsize=(8.0, 6.2), layout="constrained")
    ax = fig.add_subplot()
    positive = values[values > 0]
    norm = LogNorm(vmin=max(positive.min(), positive.max() / 1e3), vmax=positive.max()) if positive.size else None
    mesh = ax.pcolormesh(grid.lon[ix], grid.lat[iy], np.where(values > 0, values, np.nan), shading="nearest",
                         cmap="viridis", norm=norm, rasterized=True)
    bar = fig.colorbar(mesh, ax=ax, label=f"ShakeMap {field} median [{label}]", shrink=0.85, location="bottom",
                       aspect=40)
    _plain_log_ticks(bar.ax.xaxis)
    lv = ds["level"].values.astype(int)
    for level in sorted(Level, key=lambda m: m.value):
        at = lv == level
        if at.any():
            ax.scatter(lon[at], lat[at], s=36 + 12 * level.value, c=LEVEL_COLOURS[level], edgecolors="black",
                       linewidths=0.6, label=f"{level.name} ({int(at.sum())})", zorder=3 + level.value)
    _leader_labels(ax, [(inv.ids[k], float(lon[k]), float(lat[k])) for k in order[:MAP_LABELS]])
    if math.isfinite(epi[0]):
        ax.scatter([epi[0]], [epi[1]], marker="*", s=260, c="white", edgecolors="black", zorder=10,
                   label="epicentre")
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect(1.0 / max(math.cos(math.radians(0.5 * (y0 + y1))), 0.1))
    ax.set_xlabel("longitude [deg]")
    ax.set_ylabel("latitude [deg]")
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=5, fontsize=8,
               title="inspection level", title_fontsize=8, frameon=False)
    ax.set_title(f"{ds.attrs['event_description'] or ds.attrs['event_id']}: ShakeMap v{ds.attrs['shakemap_version']}"
                 f" {field}", fontsize=10)
    return fig


def _leader_labels(ax, named: list[tuple[str, float, float]]) -> None:
    """Each (name, lon, lat) named in a column right of the map (where it has no tick labels), in the order of
    latitude (so that leader lines do not cross one another), joined to its point by a thin line; the layout makes
    room for the column."""
    if not named:
        return
    rows = sorted(named, key=lambda t: -t[2])
    for i, (name, x, y) in enumerate(rows):
        frac = 1.0 - (i + 0.5) / len(rows)
        ax.annotate(name, xy=(x, y), xycoords="data", xytext=(1.03, frac), textcoords="axes fraction",
                    ha="left", va="center", fontsize=8,
                    arrowprops={"arrowstyle": "-", "color": "0.2", "lw": 0.6, "shrinkA": 2, "shrinkB": 3})


def curve_svg(ds: xr.Dataset, k: int) -> str:
    """The asset's fragility curve P(overturn | IM) with the site's median shaking and its +-1 sigma marked."""
    label, factor = _unit(ds)
    theta, beta = float(ds["fragility_median"].values[k]), float(ds["fragility_beta"].values[k])
    m, s = float(ds["shaking_median"].values[k]), float(ds["shaking_log_sd"].values[k])
    centre = theta if math.isfinite(theta) and theta > 0 else m
    lo, hi = min(centre, m) / 8.0, max(centre, m) * 8.0
    x = np.geomspace(lo, hi, 120)
    w, h, pad = CURVE_W, CURVE_H, CURVE_PAD

    def px(v: float) -> float:
        return pad + (w - pad - 10) * math.log(v / lo) / math.log(hi / lo)

    def py(p: float) -> float:
        return h - pad + (pad + 10 - h) * p

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" class="curve">',
             f'<rect x="{pad}" y="10" width="{w - pad - 10}" height="{h - pad - 10}" fill="none" stroke="#999"/>']
    if m > 0 and math.isfinite(s) and s > 0:
        a, b = px(max(m * math.exp(-s), lo)), px(min(m * math.exp(s), hi))
        parts.append(f'<rect x="{a:.1f}" y="10" width="{b - a:.1f}" height="{h - pad - 10}" fill="#9ecae1" '
                     'fill-opacity="0.45"/>')
    if math.isfinite(theta) and theta > 0 and math.isfinite(beta):
        p = ndtr(np.log(x / theta) / beta) if beta > 0 else (x >= theta).astype(float)
        pts = " ".join(f"{px(v):.1f},{py(q):.1f}" for v, q in zip(x, p))
        parts.append(f'<polyline points="{pts}" fill="none" stroke="#d7301f" stroke-width="2"/>')
    if m > 0:
        parts.append(f'<line x1="{px(m):.1f}" x2="{px(m):.1f}" y1="10" y2="{h - pad}" stroke="#08519c" '
                     'stroke-width="2"/>')
    for p in (0.0, 0.5, 1.0):
        parts.append(f'<text x="{pad - 4}" y="{py(p) + 4:.1f}" font-size="10" text-anchor="end">{p:g}</text>')
    for v, anchor in ((lo, "start"), (math.sqrt(lo * hi), "middle"), (hi, "end")):
        parts.append(f'<text x="{px(v):.1f}" y="{h - pad + 14}" font-size="10" text-anchor="{anchor}">'
                     f'{plain(v * factor)}</text>')
    parts.append(f'<text x="{pad + (w - pad) / 2:.0f}" y="{h - 8}" font-size="11" text-anchor="middle">'
                 f'{escape(str(ds["shakemap_field"].values[k]))} [{escape(label)}] (blue: the site, median and '
                 '+-1 sigma)</text>')
    parts.append(f'<text x="12" y="{h / 2:.0f}" font-size="11" transform="rotate(-90 12 {h / 2:.0f})" '
                 'text-anchor="middle">P(overturn)</text></svg>')
    return "".join(parts)


def plain(x: float) -> str:
    """A number without an exponent, three significant digits (a tick label a reader takes in at once)."""
    if x >= 1000:
        return f"{x:,.0f}"
    return f"{x:.3g}" if x >= 1e-3 else f"{x:.2g}"


def number_text(x: float, spec: str, *, factor: float = 1.0) -> str:
    """``x * factor`` in the format ``spec`` for a table cell; never the raw "inf" or "nan": an infinite value
    (a fragility median where no level overturned the asset) reads "none", a missing one "-"."""
    x = float(x)
    if math.isnan(x):
        return "-"
    if math.isinf(x):
        return "none"
    return format(x * factor, spec)


def _p_text(v: dict, k: int) -> str:
    """Asset ``k``'s P for the page (``v``: event.nc's arrays): two decimals, its bounds where it is not given."""
    p, lo, hi = (float(v[n][k]) for n in ("p_overturn_event", "p_overturn_event_low", "p_overturn_event_high"))
    if math.isfinite(p):
        text = f"{p:.2f}" if p >= 0.005 or p == 0 else "<0.01"
        if int(v["basis"][k]) == Basis.unjudged and math.isfinite(hi):
            text += f" (up to {hi:.2f}: records not judged, counted as overturning)"
        return text
    return f"{lo:.2f}-{hi:.2f}" if math.isfinite(lo) and math.isfinite(hi) else "no fit"


def event_page(ds: xr.Dataset, grid: ShakeMapGrid, inv: Inventory, order: list[int], changed: list, *,
               curves: int) -> str:
    """The page's HTML (the module's contents)."""
    from jinja2 import Environment, PackageLoader, select_autoescape

    label, factor = _unit(ds)
    drawn = set(order[:max(curves, 0)])
    v = {name: ds[name].values for name in ds.data_vars}
    natural = natural_rocks(inv.extra.get("object")) or [False] * len(inv.ids)
    scenario = is_scenario(ds.attrs)
    rows = []
    for k in order[:PAGE_ROWS]:
        level = Level(int(v["level"][k]))
        prev = int(v["level_previous"][k])
        rows.append({
            "priority": int(v["priority"][k]), "id": inv.ids[k], "name": inv.names[k], "site": inv.sites[k],
            "level": level.name + (" (it slides at this shaking)" if "sliding_risk" in v and v["sliding_risk"][k]
                                   else ""),
            "colour": LEVEL_COLOURS[level], "p": _p_text(v, k),
            "bounds": f"{float(v['p_overturn_event_low'][k]):.2f}-{float(v['p_overturn_event_high'][k]):.2f}",
            "basis": Basis(int(v["basis"][k])).name.replace("_", " "), "field": str(v["shakemap_field"][k]),
            "shaking": number_text(v["shaking_median"][k], ".3g", factor=factor),
            "sigma": number_text(v["shaking_log_sd"][k], ".2f"),
            "sigma_source": ("grid", "uncertainty.xml", "default")[int(v["log_sd_source"][k])],
            "median": number_text(v["fragility_median"][k], ".3g", factor=factor),
            "beta": number_text(v["fragility_beta"][k], ".2f"),
            "status": FitStatus(int(v["fit_status"][k])).name.replace("_", " "),
            "distance": number_text(v["epicentral_distance"][k], ".1f"),
            "previous": Level(prev).name if prev >= 0 else "", "curve": k in drawn,
            "record": str(v["station_record"][k]), "record_km": number_text(v["station_distance"][k], ".2f"),
            "p_record": f"{float(v['p_overturn_record'][k]):.2f}" if math.isfinite(v["p_overturn_record"][k]) else "",
            "governs": "record" if v["governed_by"][k] else "shakemap",
            "advice": advice_at(v, k, scenario=scenario, natural=natural[k])})
    counts = {lv.name: int(np.sum(ds["level"].values == lv)) for lv in sorted(Level, key=lambda m: -m.value)}
    env = Environment(loader=PackageLoader("pipeline.report", "templates"),
                      autoescape=select_autoescape(["html", "j2"]))
    return env.get_template("event.html.j2").render(
        a=ds.attrs, rows=rows, cards=rows[:CARDS], n_assets=len(order), more=max(len(order) - PAGE_ROWS, 0),
        counts=counts,
        colours={lv.name: c for lv, c in LEVEL_COLOURS.items()}, unit=label, changed=changed,
        map_png="data:image/png;base64," + base64.b64encode(map_png(ds, grid, inv, order)).decode("ascii"),
        curves=[{"id": inv.ids[k], "name": inv.names[k], "p": _p_text(v, k), "svg": curve_svg(ds, k)}
                for k in order[:max(curves, 0)]],
        warnings=[w for w in ds.attrs.get("warnings", "").split("\n") if w],
        with_records=bool(ds.attrs.get("records_directory")))
