"""Plots whose legends never cover data: the fragility curves put their legends outside the axes (checked on the
drawn figure: the legend's box and the axes' box do not meet), and the figure is as wide as it needs to hold both
(the report's stability chart, drawn as SVG: tests/report/test_chart_svg.py)."""

from __future__ import annotations

import numpy as np
import xarray as xr
from figure_checks import legend_boxes_clear


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
    assert legend_boxes_clear(fig) == []
