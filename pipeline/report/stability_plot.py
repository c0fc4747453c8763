"""Drawing of a stability chart (the reference paper's Figs. 2a and 4) with matplotlib."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .mpl import new_figure, save_figure


def plot_stability_chart(chart: xr.Dataset, path: str | Path, *, title: str | None = None):
    """Draw ``chart`` (from :func:`pipeline.run.chart.stability_chart`, optionally merged with
    :func:`pipeline.run.chart.chart_points`) to ``path`` (format from the suffix: .png, .svg, .pdf).

    Left: dimensional, acceleration [g] against period [s]. Right: normalized,
    a_p / a_uplift against the period over the criterion's transition period.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    at = chart.attrs
    g = at["g"]
    T = chart["period"].values
    a_up = float(chart["uplift_acceleration"])
    a_slide = float(chart["sliding_acceleration"])
    t_form = at["transition_period_form"]
    fig = new_figure(figsize=(12, 6.0), layout="constrained")
    ax, axn = fig.subplots(1, 2)

    crit = chart["critical_acceleration"].values
    ax.fill_between(T, np.minimum(crit, a_slide) / g, a_slide / g, where=crit < a_slide,
                    color="tab:red", alpha=0.08, label="unsafe by the criterion")
    ax.plot(T, crit / g, color="tab:red", lw=2.2, label=f"criterion, Eq. 7 ({at['form']} forms)")
    ax.plot(T, chart["critical_acceleration_small_angle"].values / g, color="tab:red", lw=1, ls=":",
            label="Eq. 7 as printed (small angle)")
    ax.plot(T, chart["energy_acceleration"].values / g, color="tab:orange", lw=1, ls="--",
            label="energy hyperbola, Eq. 5")
    ax.axhline(a_up / g, color="tab:green", lw=1.2, label="uplift, Eq. 1")
    ax.axhline(a_slide / g, color="tab:blue", lw=1.2, label=f"sliding line, mu = {at['mu']:g}")
    cf = chart["closed_form_acceleration"].values
    if np.any(np.isfinite(cf)):
        name = "Makris & Roussos eq. 27" if at["pulse"] == "half-sine" else "Housner eq. 9"
        ax.plot(T, cf / g, color="k", lw=1.2, ls="-.", label=f"closed form, {name} (linear)")
    if "critical_acceleration_simulated" in chart:
        ax.plot(T, chart["critical_acceleration_simulated"].values / g, "s-", color="tab:purple", ms=4,
                label="simulated (rigid rocking)")
    ax.axvline(at["transition_period"], color="0.4", lw=0.8, ls=":")
    ax.annotate(f"T = {at['transition_period']:.3f} s", (at["transition_period"], a_up / g),
                xytext=(4, -14), textcoords="offset points", fontsize=8, color="0.3")
    ax.set_xscale("log")
    ax.set_ylim(0, min(3.0 * a_slide, max(float(np.nanmax(crit[T >= T.min()])), a_slide) * 1.1) / g)
    ax.set_xlabel(f"pulse period T = 2 t_p [s] ({at['pulse']})")
    ax.set_ylabel("pulse peak acceleration a_p [g]")

    axn.plot(T / t_form, chart["critical_acceleration_normalized"].values, color="tab:red", lw=2.2,
             label="max(t̄_p / t_p, 1), Eq. 7")
    axn.axhline(1.0, color="tab:green", lw=1.2, label="uplift")
    axn.axhline(a_slide / a_up, color="tab:blue", lw=1.2, label=f"sliding, mu / tan(alpha) = {a_slide / a_up:.2f}")
    axn.set_xscale("log")
    axn.set_ylim(0, min(3.0 * a_slide / a_up, 12.0))
    axn.set_xlabel("t_p / t̄_p (pulse duration over transition duration)")
    axn.set_ylabel("a_p / a_uplift")

    if "record" in chart.dims and chart.sizes["record"]:
        _record_points(chart, ax, axn, g)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.14), ncol=2, frameon=False)
    axn.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, -0.14), ncol=2, frameon=False)
    for a in (ax, axn):
        a.grid(True, which="both", alpha=0.3)
    fig.suptitle(title or at.get("title", "stability chart"), fontsize=10)
    return save_figure(fig, path, dpi=120)


#: Colour and words of a record point by the simulation's verdict (1, 0, -1).
SIMULATED_STYLE = {1: ("tab:red", "overturns (simulation)"), 0: ("tab:green", "stands (simulation)"),
                   -1: ("0.7", "no simulated verdict")}


def _record_points(chart, ax, axn, g: float) -> None:
    """The records' pulses, coloured by the nonlinear simulation's verdict (the truth) when the chart has it;
    a black cross marks each record where the paper's criterion says otherwise. A chart without simulated
    verdicts colours by the criterion and says so in the legend."""
    over = chart["record_overturn_criterion"].values == 1
    sim = (chart["record_overturn_simulated"].values if "record_overturn_simulated" in chart
           else np.full(over.shape, -1))
    simulated = bool(np.any(sim >= 0))
    pulse_like = chart["record_is_pulse"].values == 1
    x_abs, y_abs = chart["record_period"].values, chart["record_ap"].values / g
    x_n, y_n = chart["record_normalized_duration"].values, chart["record_normalized_acceleration"].values
    for sel, marker, label in ((pulse_like, "o", "pulse-like record"), (~pulse_like, "^", "non-pulse record")):
        if simulated:
            groups = [(sim == v, *SIMULATED_STYLE[v]) for v in (1, 0, -1)]
        else:
            groups = [(over, "tab:red", "overturns by the criterion (not simulated)"),
                      (~over, "tab:green", "safe by the criterion (not simulated)")]
        for hit, colour, words in groups:
            m = sel & hit
            if not np.any(m):
                continue
            ax.scatter(x_abs[m], y_abs[m], marker=marker, c=colour, edgecolors="k", linewidths=0.5, s=28, zorder=5,
                       label=f"{label}, {words}")
            axn.scatter(x_n[m], y_n[m], marker=marker, c=colour, edgecolors="k", linewidths=0.5, s=28, zorder=5)
    if simulated:
        wrong = (sim >= 0) & ((sim == 1) != over)
        if np.any(wrong):
            ax.scatter(x_abs[wrong], y_abs[wrong], marker="x", c="k", s=40, zorder=6,
                       label=f"the criterion says otherwise ({int(wrong.sum())})")
            axn.scatter(x_n[wrong], y_n[wrong], marker="x", c="k", s=40, zorder=6)
