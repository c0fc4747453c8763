"""Time-series panels drawn directly as SVG: the report's per-record and per-asset traces.

A matplotlib PNG of a three-panel velocity trace costs about 0.25 s (text layout and
rasterizing); the report draws one per pulse-like record and one per asset at risk, and
they dominated a first run's report. These panels are written as SVG text instead: each
trace is reduced to the minimum and maximum of every pixel column (so no peak is lost,
whatever the record's length), axes ticks come from matplotlib's tick locator (no
figure is created), and a panel costs about a millisecond. The browser scales them
without blur.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from html import escape

import numpy as np

#: plot area width [px] and the margins around it
WIDTH, LEFT, RIGHT = 720, 62, 12
PANEL_H, GAP, TOP, BOTTOM = 92, 10, 26, 38


@dataclass
class Panel:
    """One panel: a trace and what is drawn over it."""

    y: np.ndarray
    label: str = ""
    #: horizontal reference lines (value, colour)
    hlines: list = field(default_factory=list)
    #: a vertical marker (time [s], colour, text) or None
    marker: tuple | None = None


def envelope(y: np.ndarray, columns: int) -> tuple[np.ndarray, np.ndarray]:
    """Min-max reduction of ``y`` to at most ``2 * columns`` points (sample index, value).

    Each column of samples becomes its minimum and its maximum at the column's centre, so
    every sample's value lies within the drawn stroke of its column: peaks are kept. NaN
    samples (after an overturn) are dropped.
    """
    y = np.asarray(y, dtype=float)
    idx = np.flatnonzero(np.isfinite(y))
    if idx.size <= 2 * columns:
        return idx.astype(float), y[idx]
    vals = y[idx]
    starts = np.linspace(0, idx.size, columns + 1).astype(int)[:-1]
    lo, hi = np.minimum.reduceat(vals, starts), np.maximum.reduceat(vals, starts)
    centre = idx[np.minimum(starts + np.diff(np.append(starts, idx.size)) // 2, idx.size - 1)].astype(float)
    return np.repeat(centre, 2), np.column_stack([lo, hi]).ravel()


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def panels_svg(panels: list[Panel], dt_s: float, *, title: str, ylabel: str, xlabel: str = "time [s]",
               share_y: bool = True) -> bytes:
    """SVG of stacked time-series panels sharing the time axis.

    Parameters
    ----------
    panels : list of Panel
        Top to bottom.
    dt_s : float
        Sampling interval of every trace [s].
    title, ylabel, xlabel : str
        Texts (escaped).
    share_y : bool
        One y range for all panels (the pulse and its residual on the original's scale).
    """
    from matplotlib.ticker import MaxNLocator  # imported when a figure is drawn, not with the report

    n = max(p.y.size for p in panels)
    t_end = max((n - 1) * dt_s, dt_s)
    height = TOP + len(panels) * PANEL_H + (len(panels) - 1) * GAP + BOTTOM
    plot_w = WIDTH - LEFT - RIGHT

    def y_range(ys) -> tuple[float, float]:
        vals = np.concatenate([np.asarray(v, dtype=float)[np.isfinite(v)] for v in ys] + [np.zeros(1)])
        lo, hi = float(vals.min()), float(vals.max())
        if hi - lo < 1e-12:
            lo, hi = lo - 1.0, hi + 1.0
        pad = 0.05 * (hi - lo)
        return lo - pad, hi + pad

    shared = y_range([p.y for p in panels] + [[h[0] for h in p.hlines] for p in panels]) if share_y else None
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {WIDTH} {height}" width="{WIDTH}" '
           f'height="{height}" font-family="sans-serif" font-size="11">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<text x="{WIDTH / 2:.0f}" y="16" text-anchor="middle" font-size="12">{escape(title)}</text>']
    xticks = [v for v in MaxNLocator(nbins=8).tick_values(0.0, t_end) if 0.0 <= v <= t_end]
    for k, p in enumerate(panels):
        y0 = TOP + k * (PANEL_H + GAP)
        lo, hi = shared if shared is not None else y_range([p.y, [h[0] for h in p.hlines]])

        def sx(t):
            return LEFT + plot_w * np.asarray(t) / t_end

        def sy(v, y0=y0, lo=lo, hi=hi):
            return y0 + PANEL_H * (hi - np.asarray(v)) / (hi - lo)

        out.append(f'<rect x="{LEFT}" y="{y0}" width="{plot_w}" height="{PANEL_H}" fill="none" stroke="#444"/>')
        for v in MaxNLocator(nbins=4).tick_values(lo, hi):
            if lo <= v <= hi:
                yy = float(sy(v))
                out.append(f'<line x1="{LEFT}" x2="{LEFT + plot_w}" y1="{yy:.1f}" y2="{yy:.1f}" stroke="#ddd"/>'
                           f'<text x="{LEFT - 4}" y="{yy + 4:.1f}" text-anchor="end">{_fmt(v)}</text>')
        for v in xticks:
            xx = float(sx(v))
            out.append(f'<line x1="{xx:.1f}" x2="{xx:.1f}" y1="{y0}" y2="{y0 + PANEL_H}" stroke="#eee"/>')
        for value, colour in p.hlines:
            yy = float(sy(value))
            out.append(f'<line x1="{LEFT}" x2="{LEFT + plot_w}" y1="{yy:.1f}" y2="{yy:.1f}" stroke="{colour}" '
                       'stroke-dasharray="5,3"/>')
        xi, yv = envelope(p.y, plot_w)
        pts = " ".join(map("{:.1f},{:.1f}".format, sx(xi * dt_s).tolist(), sy(yv).tolist()))
        out.append(f'<polyline fill="none" stroke="black" stroke-width="0.8" points="{pts}"/>')
        if p.marker is not None:
            t_m, colour, text = p.marker
            xx = float(sx(t_m))
            out.append(f'<line x1="{xx:.1f}" x2="{xx:.1f}" y1="{y0}" y2="{y0 + PANEL_H}" stroke="{colour}" '
                       f'stroke-width="1.5"/><text x="{xx - 4:.1f}" y="{y0 + PANEL_H / 2:.1f}" '
                       f'text-anchor="end" fill="{colour}">{escape(text)}</text>')
        if p.label:
            out.append(f'<text x="{LEFT + 5}" y="{y0 + 14}" fill="#222">{escape(p.label)}</text>')
    y_axis = TOP + len(panels) * PANEL_H + (len(panels) - 1) * GAP
    for v in xticks:
        out.append(f'<text x="{float(LEFT + plot_w * v / t_end):.1f}" y="{y_axis + 14}" '
                   f'text-anchor="middle">{_fmt(v)}</text>')
    out.append(f'<text x="{LEFT + plot_w / 2:.0f}" y="{height - 6}" text-anchor="middle">{escape(xlabel)}</text>')
    out.append(f'<text transform="translate(14 {(TOP + y_axis) / 2:.0f}) rotate(-90)" '
               f'text-anchor="middle">{escape(ylabel)}</text></svg>')
    return "".join(out).encode()
