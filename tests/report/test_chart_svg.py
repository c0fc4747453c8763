"""The report's stability chart, drawn as SVG (pipeline/report/chart_svg.py): every point where the chart's own
labelled ticks put it, none lost under a marker of another series, the legend's counts the scenes', the legend off
the points and inside the chart, and the chart's size bounded whatever the number of scenes."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import numpy as np

from pipeline.report import chart_svg
from pipeline.report.figures import RESPONSE_STYLE, scenes_chart

NS = {"s": "http://www.w3.org/2000/svg"}
#: Widest a character of sans-serif text is taken to be, as a share of the font size (wider than Helvetica's and
#: DejaVu Sans's letters other than m and W): a bound for a legend row's width [-].
CHAR_EM = 0.7


def _parsed(svg: bytes):
    root = ET.fromstring(svg)
    paths = {p.get("stroke"): np.array(re.findall(r"M([-\d.e]+) ([-\d.e]+)h0", p.get("d")), dtype=float)
             for p in root.iter(f"{{{NS['s']}}}path")}
    texts = [(t.get("x"), t.get("y"), t.text or "") for t in root.iter(f"{{{NS['s']}}}text")]
    return root, paths, texts


def _tick_pixels(texts, *, axis: str) -> dict[float, float]:
    """The chart's labelled decades: value -> pixel (x ticks sit under the plot, y ticks left of it)."""
    out = {}
    for x, y, t in texts:
        if x is None or not re.fullmatch(r"[\d.e+-]+", t):
            continue
        if axis == "x" and float(y) > chart_svg.TOP + chart_svg.PLOT_H:
            out[float(t)] = float(x)
        if axis == "y" and float(x) < chart_svg.LEFT:
            out[float(t)] = float(y) - 4.0        # the label's baseline sits 4 px under its grid line
    return out


def _at(ticks: dict[float, float], v: float) -> float:
    """Pixel of ``v`` read off two labelled decades, log-linearly."""
    (v0, p0), (v1, p1) = sorted(ticks.items())[:2]
    return p0 + (p1 - p0) * (math.log10(v) - math.log10(v0)) / (math.log10(v1) - math.log10(v0))


def test_each_point_is_where_the_labelled_ticks_put_it():
    x, y = np.array([0.3, 1.0, 3.16, 7.0]), np.array([0.02, 0.5, 2.0, 9.0])
    code = list(RESPONSE_STYLE)[2]
    _, paths, texts = _parsed(scenes_chart(x, y, np.full(4, code)))
    drawn = paths[RESPONSE_STYLE[code][0]]
    xt, yt = _tick_pixels(texts, axis="x"), _tick_pixels(texts, axis="y")
    assert len(xt) >= 2 and len(yt) >= 2
    want = np.array([[_at(xt, a), _at(yt, b)] for a, b in zip(x, y)])
    assert drawn.shape == (4, 2)
    d = np.sqrt(((drawn[:, None, :] - want[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
    assert d.max() <= chart_svg.SNAP_PX / math.sqrt(2) + 0.2       # within the snap grid's half diagonal


def test_a_marker_is_left_out_only_where_a_later_series_covers_it_whole():
    rng = np.random.default_rng(1)
    n = 3000
    x, y = 10 ** rng.uniform(-1, 1, n), 10 ** rng.uniform(-1, 1, n)
    codes = list(RESPONSE_STYLE)
    resp = rng.choice(codes, n)
    _, paths, texts = _parsed(scenes_chart(x, y, resp))
    xt, yt = _tick_pixels(texts, axis="x"), _tick_pixels(texts, axis="y")
    order = {RESPONSE_STYLE[c][0]: k for k, c in enumerate(codes)}
    cells = {}
    for colour, pts in paths.items():
        for cx, cy in pts.tolist():
            assert (cx, cy) not in cells, "a cell drawn twice"
            cells[(cx, cy)] = order[colour]
    where = np.array(list(cells), dtype=float)
    top = np.array(list(cells.values()))
    for a, b, c in zip(x, y, resp):     # every point: the cell it snaps to shows it or a later series over it
        px, py = _at(xt, a), _at(yt, b)
        near = (np.abs(where[:, 0] - px) <= chart_svg.SNAP_PX / 2 + 0.1) & \
               (np.abs(where[:, 1] - py) <= chart_svg.SNAP_PX / 2 + 0.1)
        assert near.any() and top[near].max() >= codes.index(c)


def test_the_legend_counts_the_scenes_and_stays_off_the_points_inside_the_chart():
    rng = np.random.default_rng(2)
    n = 500
    x, y = 10 ** rng.uniform(-1.3, 1.3, n), 10 ** rng.uniform(-1.3, 1.3, n)     # points fill the whole chart
    resp = rng.choice(list(RESPONSE_STYLE), n)
    x[:7] = np.nan                                                               # no pulse: not a point
    root, paths, texts = _parsed(scenes_chart(x, y, resp))
    ok = np.isfinite(x)
    legend_texts = [t.text for g in root.iter(f"{{{NS['s']}}}g") for t in g.iter(f"{{{NS['s']}}}text")]
    assert legend_texts[:2] == ["overturns by the criterion", "criterion boundary (Eq. 7)"]
    labels = legend_texts[2:]
    want = {f"{label} ({int((ok & (resp == c)).sum())})" for c, (_, label) in RESPONSE_STYLE.items()}
    assert set(labels) == want
    frame = next(r for r in root.iter(f"{{{NS['s']}}}rect") if r.get("stroke") == "#444")     # the axes' frame
    x0, y0 = float(frame.get("x")), float(frame.get("y"))
    x1, y1 = x0 + float(frame.get("width")), y0 + float(frame.get("height"))
    font_px = float(root.get("font-size"))
    for g in root.iter(f"{{{NS['s']}}}g"):                # each legend row: its swatch at its x, its text right of it
        left = float(re.match(r"translate\(([-\d.]+)", g.get("transform")).group(1))
        text = next(g.iter(f"{{{NS['s']}}}text"))
        right = left + float(text.get("x")) + CHAR_EM * font_px * len(text.text)
        assert left >= x1 and right <= float(root.get("width")), text.text
    for pts in paths.values():
        assert (pts[:, 0] >= x0 - 1).all() and (pts[:, 0] <= x1 + 1).all()
        assert (pts[:, 1] >= y0 - 1).all() and (pts[:, 1] <= y1 + 1).all()


def test_the_chart_stays_small_whatever_the_number_of_scenes():
    rng = np.random.default_rng(3)
    n = 1_000_000
    x, y = 10 ** rng.uniform(-1.5, 1.5, n), 10 ** rng.uniform(-1.5, 1.5, n)
    svg = scenes_chart(x, y, rng.choice(list(RESPONSE_STYLE), n))
    cells = (chart_svg.PLOT_W / chart_svg.SNAP_PX + 1) * (chart_svg.PLOT_H / chart_svg.SNAP_PX + 1)
    assert len(svg) < 10_000 + 14 * cells           # a cell at most once, about ten bytes each, and the axes
    ET.fromstring(svg)
