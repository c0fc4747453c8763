"""A scatter chart on log-log axes drawn directly as SVG: the report's stability chart of every scene.

A matplotlib PNG of this chart takes 1.1 s (1.9 s as a process's first figure) on the bundled run's 490 points,
most of it the log axes' ticks and text layout; written as SVG text, as the report's time series are (:mod:`.svg`),
it takes a few milliseconds. Its size is bounded whatever the number of scenes: points are snapped to a grid of
:data:`SNAP_PX` pixels (a marker is :data:`MARKER_PX` across: a point moves by at most 1.4 px) and each cell is
drawn once, in the colour of the last series with a point there, whose marker would cover the others' there whole;
a point is a zero-length stroke with round caps (about ten bytes), so the chart stays under 0.75 MB whatever the
number of scenes (0.44 MB for a million spread over the whole chart). The counts in the legend are the scenes',
not the cells'.
"""

from __future__ import annotations

import math
from html import escape
from typing import NamedTuple

import numpy as np

#: The chart's size [px], and the plotting area's margins: the legend sits right of the area, never over a point.
LEFT, TOP, PLOT_W, PLOT_H = 66, 30, 540, 390
WIDTH, HEIGHT = 860, TOP + PLOT_H + 44
LEGEND_X, LEGEND_ROW = LEFT + PLOT_W + 18, 18
FONT_PX = 11
#: Diameter of a point's marker [px] and the grid points are snapped to [px].
MARKER_PX = 7.0
SNAP_PX = 2.0


class Series(NamedTuple):
    """Points of one colour, drawn in the order given (later series over earlier ones)."""

    x: np.ndarray
    y: np.ndarray
    colour: str
    label: str


class Curve(NamedTuple):
    """A line y(x) with, optionally, the area above it up to the chart's top filled."""

    x: np.ndarray
    y: np.ndarray
    colour: str
    label: str
    fill_label: str = ""


def _axis(lo: float, hi: float):
    """log10 of the range and the map from a value to [0, 1] along it."""
    a, b = math.log10(lo), math.log10(hi)
    return a, b, (lambda v: (np.log10(np.asarray(v, dtype=float)) - a) / (b - a))


def _ticks(a: float, b: float) -> tuple[list[float], list[float]]:
    """Decades and the 2-9 multiples between them, within [10^a, 10^b]."""
    major: list[float] = []
    minor: list[float] = []
    for k in range(math.floor(a), math.ceil(b) + 1):
        for m in range(1, 10):
            v = m * 10.0 ** k
            if a - 1e-12 <= math.log10(v) <= b + 1e-12:
                (major if m == 1 else minor).append(v)
    return major, minor


def _visible_cells(points: list[tuple[np.ndarray, np.ndarray]]) -> list[np.ndarray]:
    """For each series of points (pixel coordinates), the cells of :data:`SNAP_PX` where it is drawn on top:
    a cell's marker of a later series covers an earlier one's there whole (same centre, same size), so the earlier
    one is not written. Returns one array of rows (x, y) per series."""
    sizes = [px.size for px, _ in points]
    if sum(sizes) == 0:
        return [np.zeros((0, 2)) for _ in points]
    cx = np.round(np.concatenate([px for px, _ in points]) / SNAP_PX).astype(np.int64)
    cy = np.round(np.concatenate([py for _, py in points]) / SNAP_PX).astype(np.int64)
    which = np.repeat(np.arange(len(points)), sizes)
    key = (cx - cx.min()) * (int(cy.max() - cy.min()) + 1) + (cy - cy.min())
    order = np.lexsort((which, key))
    last = order[np.append(key[order][1:] != key[order][:-1], True)]       # the top series of each cell
    cells, top = np.column_stack([cx[last], cy[last]]) * SNAP_PX, which[last]
    return [cells[top == k] for k in range(len(points))]


def loglog_chart(series: list[Series], curves: list[Curve], *, xlim: tuple[float, float],
                 ylim: tuple[float, float], title: str, xlabel: str, ylabel: str, legend_title: str) -> bytes:
    """SVG of points and curves on log-log axes, the legend right of the plotting area.

    Parameters
    ----------
    series : list of Series
        Points (finite and positive: the caller selects them), one colour each; a series without points is
        left out of the legend.
    curves : list of Curve
        Lines drawn under the points, clipped to the axes.
    xlim, ylim : tuple of float
        The axes' ranges (positive).
    title, xlabel, ylabel, legend_title : str
        Texts (escaped).
    """
    ax_, bx_, fx = _axis(*xlim)
    ay_, by_, fy = _axis(*ylim)

    def sx(v):
        return LEFT + PLOT_W * fx(v)

    def sy(v):
        return TOP + PLOT_H * (1.0 - fy(v))

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {WIDTH} {HEIGHT}" width="{WIDTH}" '
           f'height="{HEIGHT}" font-family="sans-serif" font-size="{FONT_PX}">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<clipPath id="area"><rect x="{LEFT}" y="{TOP}" width="{PLOT_W}" height="{PLOT_H}"/></clipPath>',
           f'<text x="{LEFT + PLOT_W / 2:.0f}" y="18" text-anchor="middle" font-size="12">{escape(title)}</text>']
    out += _grid(ax_, bx_, ay_, by_, sx, sy)
    legend: list[str] = []
    for c in curves:
        pts = " ".join(map("{:.1f},{:.1f}".format, sx(c.x).tolist(), sy(c.y).tolist()))
        if c.fill_label:
            out.append(f'<polygon clip-path="url(#area)" fill="{c.colour}" fill-opacity="0.07" stroke="none" '
                       f'points="{pts} {sx(c.x[-1]):.1f},{TOP} {sx(c.x[0]):.1f},{TOP}"/>')
            legend.append(f'<rect width="20" height="10" y="-8" fill="{c.colour}" fill-opacity="0.15"/>'
                          f'<text x="28">{escape(c.fill_label)}</text>')
        out.append(f'<polyline clip-path="url(#area)" fill="none" stroke="{c.colour}" stroke-width="2" '
                   f'points="{pts}"/>')
        legend.append(f'<line x2="20" y1="-3" y2="-3" stroke="{c.colour}" stroke-width="2"/>'
                      f'<text x="28">{escape(c.label)}</text>')
    for s, cells in zip(series, _visible_cells([(sx(s.x), sy(s.y)) for s in series])):
        if s.x.size == 0:
            continue
        path = "".join(f"M{cx:g} {cy:g}h0" for cx, cy in cells.tolist())
        out.append(f'<path clip-path="url(#area)" d="{path}" stroke="{s.colour}" stroke-width="{MARKER_PX:g}" '
                   'stroke-linecap="round"/>')
        legend.append(f'<circle cx="10" cy="-4" r="{MARKER_PX / 2:g}" fill="{s.colour}" stroke="#000" '
                      f'stroke-width="0.3"/><text x="28">{escape(s.label)}</text>')
    out.append(f'<text x="{LEGEND_X}" y="{TOP + 10}" font-weight="bold">{escape(legend_title)}</text>')
    out += [f'<g transform="translate({LEGEND_X} {TOP + 10 + LEGEND_ROW * (k + 1)})">{item}</g>'
            for k, item in enumerate(legend)]
    out.append(f'<text x="{LEFT + PLOT_W / 2:.0f}" y="{TOP + PLOT_H + 34}" text-anchor="middle">{escape(xlabel)}</text>'
               f'<text transform="translate(16 {TOP + PLOT_H / 2:.0f}) rotate(-90)" text-anchor="middle">'
               f'{escape(ylabel)}</text></svg>')
    return "".join(out).encode()


def _grid(ax_: float, bx_: float, ay_: float, by_: float, sx, sy) -> list[str]:
    """The axes' frame, the decades' grid lines and labels, and the fainter lines of their multiples."""
    out = []
    xmajor, xminor = _ticks(ax_, bx_)
    ymajor, yminor = _ticks(ay_, by_)
    for v in xminor:
        out.append(f'<line x1="{sx(v):.1f}" x2="{sx(v):.1f}" y1="{TOP}" y2="{TOP + PLOT_H}" stroke="#f0f0f0"/>')
    for v in yminor:
        out.append(f'<line x1="{LEFT}" x2="{LEFT + PLOT_W}" y1="{sy(v):.1f}" y2="{sy(v):.1f}" stroke="#f0f0f0"/>')
    for v in xmajor:
        out.append(f'<line x1="{sx(v):.1f}" x2="{sx(v):.1f}" y1="{TOP}" y2="{TOP + PLOT_H}" stroke="#d8d8d8"/>'
                   f'<text x="{sx(v):.1f}" y="{TOP + PLOT_H + 15}" text-anchor="middle">{v:g}</text>')
    for v in ymajor:
        out.append(f'<line x1="{LEFT}" x2="{LEFT + PLOT_W}" y1="{sy(v):.1f}" y2="{sy(v):.1f}" stroke="#d8d8d8"/>'
                   f'<text x="{LEFT - 5}" y="{sy(v) + 4:.1f}" text-anchor="end">{v:g}</text>')
    out.append(f'<rect x="{LEFT}" y="{TOP}" width="{PLOT_W}" height="{PLOT_H}" fill="none" stroke="#444"/>')
    return out
