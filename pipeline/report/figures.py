"""Figures of the asset-risk report, returned as SVG bytes for embedding.

* :func:`scenes_chart`: the reference paper's normalized stability chart (SVG, :mod:`.chart_svg`)
  (Fig. 4) with every (record, block) scene as a point, coloured by the
  simulated response: a_p / (g tan alpha) against t_p over the block's
  transition duration. In these coordinates the criterion's boundary is the
  same for every block: the uplift line y = 1 and the energy hyperbola
  x y = 1 (Eqs. 1, 5 and 7).
* :func:`theta_figure`: theta(t) / alpha of an asset's governing scene (SVG, :mod:`.svg`).
* :func:`pulse_figure`: original velocity, extracted pulse and residual (SVG).

References
----------
The reference paper, "Rocking Blocks Stability under Critical Pulses from Near-Fault Earthquakes Using a
Novel Energy Based Approach", Applied Sciences (MDPI), Fig. 4 and Eq. 7.
"""

from __future__ import annotations

import numpy as np

from ..constants import M_TO_CM
from ..rocking.planner import Response
from .chart_svg import Curve, Series, loglog_chart
from .svg import Panel, panels_svg

#: Colour and label of each simulated response code (store.SCHEMA "response"): matplotlib's tab10 colours.
RED = "#d62728"
RESPONSE_STYLE = {Response.overturn: (RED, "overturn"), Response.slide_rock: ("#ff7f0e", "slide + rock"),
                  Response.rock: ("#1f77b4", "rock"), Response.slide: ("#2ca02c", "slide"),
                  Response.rest: ("#999999", "rest"), Response.free_flight: ("#9467bd", "free flight"),
                  -1: ("#d9d9d9", "not simulated")}


def scenes_chart(x: np.ndarray, y: np.ndarray, response: np.ndarray) -> bytes:
    """SVG of the normalized stability chart with one point per scene, coloured by its simulated response; its
    legend outside the axes, so that it covers no point and no line (:func:`.chart_svg.loglog_chart`).

    Parameters
    ----------
    x : ndarray
        t_p over the block's transition duration [-] (``normalized_duration``).
    y : ndarray
        a_p over the uplift acceleration g tan(alpha) [-] (``normalized_acceleration``).
    response : ndarray of int
        Simulated response code per scene.
    """
    x, y, response = (np.asarray(a).ravel() for a in (x, y, response))
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    lo = min(0.05, float(np.min(x[ok])) / 1.5) if ok.any() else 0.05
    hi = max(20.0, float(np.max(x[ok])) * 1.5) if ok.any() else 20.0
    ylim = (min(0.05, float(np.min(y[ok])) / 1.5) if ok.any() else 0.05,
            max(10.0, float(np.max(y[ok])) * 1.5) if ok.any() else 10.0)
    xs = np.geomspace(lo, hi, 400)
    boundary = Curve(xs, np.maximum(1.0, 1.0 / xs), RED, "criterion boundary (Eq. 7)",
                     fill_label="overturns by the criterion")
    series = []
    for code, (colour, label) in RESPONSE_STYLE.items():
        sel = ok & (response == code)
        series.append(Series(x[sel], y[sel], colour, f"{label} ({int(sel.sum())})"))
    return loglog_chart(series, [boundary], xlim=(lo, hi), ylim=ylim,
                        title=f"Every screened scene ({int(ok.sum())} with an extracted pulse)",
                        xlabel="pulse duration / transition duration, t_p / t_bar",
                        ylabel="pulse acceleration / uplift acceleration, a_p / (g tan alpha)",
                        legend_title="simulated response")


def theta_figure(theta_over_alpha: np.ndarray, dt_s: float, *, title: str) -> bytes:
    """SVG of theta(t) / alpha of one scene, with the uplift-scale lines at +-1 and, where the
    history ends early (NaN after overturning), a marker at the overturn."""
    theta = np.asarray(theta_over_alpha, dtype=float)
    finite = np.flatnonzero(np.isfinite(theta))
    marker = None
    if finite.size and finite.size < theta.size:
        marker = (float(finite[-1]) * dt_s, "#c00", "overturns")
    panel = Panel(theta, hlines=[(1.0, "#c00"), (-1.0, "#c00")], marker=marker)
    return panels_svg([panel], dt_s, title=title, ylabel="theta / alpha")


def pulse_figure(velocity_ms: np.ndarray, pulse_ms: np.ndarray, dt_s: float, *, title: str) -> bytes:
    """SVG of the original velocity, extracted pulse and residual [cm/s] (the panels of Shahi &
    Baker's ``make_plot``, on one shared scale)."""
    v, p = M_TO_CM * np.asarray(velocity_ms, dtype=float), M_TO_CM * np.asarray(pulse_ms, dtype=float)
    panels = [Panel(v, "original ground motion"), Panel(p, "extracted pulse"), Panel(v - p, "residual ground motion")]
    return panels_svg(panels, dt_s, title=title, ylabel="velocity [cm/s]")


def floor_figure(ground_ms: np.ndarray, floor_ms: np.ndarray, floor_pulse_ms: np.ndarray, dt_s: float, *,
                 title: str) -> bytes:
    """SVG of a floor's motion beside the ground's [cm/s]: the ground velocity along its pulse orientation,
    the floor's velocity along the floor motion's pulse orientation, and the pulse extracted from the floor
    (one shared scale, so the floor's amplification reads off the panels)."""
    g, f, p = (M_TO_CM * np.asarray(a, dtype=float) for a in (ground_ms, floor_ms, floor_pulse_ms))
    panels = [Panel(g, "ground velocity"), Panel(f, "floor velocity"), Panel(p, "pulse extracted from the floor")]
    return panels_svg(panels, dt_s, title=title, ylabel="velocity [cm/s]")
