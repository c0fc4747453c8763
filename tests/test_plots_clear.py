"""Plots whose legends never cover data: the report's stability chart of every scene and the fragility curves put
their legends outside the axes (checked on the drawn figure: the legend's box and the axes' box do not meet), and
the figure is as wide as it needs to hold both."""

from __future__ import annotations

import numpy as np
import xarray as xr


def _legend_boxes_clear(fig) -> list[str]:
    """The axes whose legend overlaps their plotting area (drawn figure, display coordinates)."""
    fig.canvas.draw()
    bad = []
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is None:
            continue
        lb, ab = legend.get_window_extent(), ax.get_window_extent()
        if lb.x0 < ab.x1 - 1 and lb.x1 > ab.x0 + 1 and lb.y0 < ab.y1 - 1 and lb.y1 > ab.y0 + 1:
            bad.append(ax.get_title() or "axes")
        fig_box = fig.bbox
        assert lb.x1 <= fig_box.x1 + 1 and lb.y0 >= fig_box.y0 - 1, "the legend is cut off the figure"
        label = ax.yaxis.label.get_window_extent()
        assert label.x0 >= fig_box.x0 - 1, "the y label is cut off the figure"
    return bad


def test_the_stability_chart_keeps_its_legend_off_the_points():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from pipeline.report.figures import scenes_chart_figure

    rng = np.random.default_rng(0)
    x, y = 10 ** rng.uniform(-1.2, 1.2, 300), 10 ** rng.uniform(-1.2, 1.2, 300)   # points fill the whole chart
    fig = scenes_chart_figure(x, y, rng.integers(0, 5, 300))
    FigureCanvasAgg(fig)
    assert _legend_boxes_clear(fig) == []


def test_the_fragility_curve_keeps_its_legend_off_the_stripes():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from pipeline.report.fragility_html import curve_figure_of

    levels = np.array([0.11, 0.22, 0.44, 0.88, 1.76]) * 9.80665
    n = np.full(5, 30)
    z = np.array([0, 3, 15, 27, 30])
    ds = xr.Dataset({"n_records": (("block", "im_level"), n[None, :]),
                     "overturned_sum": (("block", "im_level"), z[None, :].astype(float)),
                     "fraction_overturned": (("block", "im_level"), (z / n)[None, :]),
                     "median": (("block",), [0.44 * 9.80665]), "beta": (("block",), [0.5])},
                    coords={"block": ["B"], "im_level": levels})
    ds.attrs.update({"im": "pga", "im_units": "m s-2", "im_display_unit": "g", "im_display_factor": 9.80665})
    fig = curve_figure_of(ds, 0, None)
    FigureCanvasAgg(fig)
    assert _legend_boxes_clear(fig) == []
