"""The chart of ``screen infer``: the pulses consistent with every observation over the stability chart."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .. import criteria
from ..rocking.geometry import geometry
from .mpl import new_figure, save_figure


def plot_inference(ds: xr.Dataset, path: str | Path, *, g_ms2: float = 9.80665) -> Path:
    """Write :func:`inference_figure` to ``path``."""
    return save_figure(inference_figure(ds, g_ms2=g_ms2), path, dpi=100)


def inference_figure(ds: xr.Dataset, *, g_ms2: float = 9.80665):
    """Shade the consistent (t_p, a_p) region (any orientation) and draw each block's boundary.

    Simulation: filled; criterion: hatched outline. Each block's criterion boundary
    (Eq. 7, with the paper's sliding line where it is lower) is drawn solid when the block
    toppled and dashed when it stood; the legend, outside the axes, names them and the two regions.
    """
    from matplotlib.patches import Patch, Rectangle

    tp = ds["duration"].values
    ap_g = ds["acceleration"].values / g_ms2
    fig = new_figure(figsize=(10.5, 6), layout="constrained")
    ax = fig.subplots()
    sim = ds["consistent_simulation"].values.astype(bool).any(axis=0).T        # (acceleration, duration)
    crit = ds["consistent_criterion"].values.astype(bool).any(axis=0).T
    # grid cells (log-spaced edges halfway between the grid points): green where the simulation
    # is consistent, hatched where the criterion is
    edges = lambda x: np.concatenate([[x[0] ** 1.5 / x[1] ** 0.5], np.sqrt(x[1:] * x[:-1]),  # noqa: E731
                                      [x[-1] ** 1.5 / x[-2] ** 0.5]])
    te, ae = edges(tp), edges(ap_g)
    if sim.any():
        ax.pcolormesh(te, ae, np.ma.masked_where(~sim, sim.astype(float)), cmap="Greens", vmin=0, vmax=1.5,
                      alpha=0.6, shading="flat")
    if crit.any():
        for k, m in zip(*np.nonzero(crit)):
            ax.add_patch(Rectangle((te[m], ae[k]), te[m + 1] - te[m], ae[k + 1] - ae[k], fill=False,
                                       hatch="//", edgecolor="k", linewidth=0.0))
    beta = float(ds.attrs["pulse_beta"])
    for k, bid in enumerate(ds["observation"].values.tolist()):
        geo = geometry(float(ds["height"][k]), float(ds["width"][k]), g_ms2=g_ms2)
        curve = criteria.critical_acceleration(tp, geo.R, geo.alpha, beta, g_ms2=g_ms2) / g_ms2
        toppled = bool(ds["toppled"][k])
        seen = "toppled" if toppled else "displaced" if "displaced" in ds and bool(ds["displaced"][k]) else "standing"
        ax.plot(tp, curve, lw=1.2, ls="-" if toppled else "--", label=f"{bid} ({seen}): its criterion boundary")
    handles, _labels = ax.get_legend_handles_labels()
    regions = [Patch(facecolor="tab:green", alpha=0.45, label="consistent with every observation: simulation"),
               Patch(fill=False, hatch="//", edgecolor="k", label="consistent with every observation: criterion")]
    ax.legend(handles=[*regions, *handles], fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0),
              borderaxespad=0.0, title="solid: toppled; dashed: stood", title_fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(tp[0], tp[-1])
    ax.set_ylim(ap_g[0], ap_g[-1])
    ax.set_xlabel("pulse duration t_p [s]")
    ax.set_ylabel("pulse acceleration a_p [g]")
    ax.set_title(f"Pulses ({ds.attrs['pulse']}) consistent with every observation: simulation (green), "
                 "criterion (hatched)", fontsize=9)
    ax.grid(which="both", alpha=0.25)
    return fig
