"""Figures of the asset-risk report, returned as PNG or SVG bytes for embedding.

* :func:`scenes_chart`: the reference paper's normalized stability chart
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

import io

import numpy as np

from ..constants import M_TO_CM
from ..rocking.planner import Response
from .mpl import new_figure
from .svg import Panel, panels_svg

#: Colour and label of each simulated response code (store.SCHEMA "response").
RESPONSE_STYLE = {Response.overturn: ("tab:red", "overturn"), Response.slide_rock: ("tab:orange", "slide + rock"),
                  Response.rock: ("tab:blue", "rock"), Response.slide: ("tab:green", "slide"),
                  Response.rest: ("0.6", "rest"), Response.free_flight: ("tab:purple", "free flight"),
                  -1: ("0.85", "not simulated")}


def png_bytes(fig) -> bytes:
    """Render a matplotlib figure to PNG and close it."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    return buf.getvalue()


def scenes_chart(x: np.ndarray, y: np.ndarray, response: np.ndarray) -> bytes:
    """PNG of :func:`scenes_chart_figure`."""
    return png_bytes(scenes_chart_figure(x, y, response))


def scenes_chart_figure(x: np.ndarray, y: np.ndarray, response: np.ndarray):
    """Normalized stability chart with one point per scene; its legend outside the axes, so that it covers no
    point and no line.

    Parameters
    ----------
    x : ndarray
        t_p over the block's transition duration [-] (``normalized_duration``).
    y : ndarray
        a_p over the uplift acceleration g tan(alpha) [-] (``normalized_acceleration``).
    response : ndarray of int
        Simulated response code per scene.
    """
    fig = new_figure(figsize=(9.5, 5.5), layout="constrained")
    ax = fig.subplots()
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    lo = min(0.05, float(np.min(x[ok])) / 1.5) if ok.any() else 0.05
    hi = max(20.0, float(np.max(x[ok])) * 1.5) if ok.any() else 20.0
    xs = np.geomspace(lo, hi, 400)
    ax.fill_between(xs, np.maximum(1.0, 1.0 / xs), 1e3, color="tab:red", alpha=0.07,
                    label="overturns by the criterion")
    ax.plot(xs, np.maximum(1.0, 1.0 / xs), color="tab:red", lw=2, label="criterion boundary (Eq. 7)")
    for code, (colour, label) in RESPONSE_STYLE.items():
        sel = ok & (response == code)
        if sel.any():
            ax.scatter(x[sel], y[sel], s=14, color=colour, edgecolor="k", linewidth=0.3,
                       label=f"{label} ({int(sel.sum())})", zorder=3)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ymax = max(10.0, float(np.max(y[ok])) * 1.5) if ok.any() else 10.0
    ax.set_xlim(lo, hi)
    ax.set_ylim(min(0.05, float(np.min(y[ok])) / 1.5) if ok.any() else 0.05, ymax)
    ax.set_xlabel("pulse duration / transition duration, t_p / t_bar")
    ax.set_ylabel("pulse acceleration / uplift acceleration, a_p / (g tan alpha)")
    ax.grid(which="both", alpha=0.25)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), title="simulated response",
              title_fontsize=8, borderaxespad=0.0)
    ax.set_title(f"Every screened scene ({int(ok.sum())} with an extracted pulse)", fontsize=10)
    return fig


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
