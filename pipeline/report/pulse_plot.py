"""The original velocity, extracted pulse and residual, as the authors' ``make_plot`` draws them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..constants import M_TO_CM
from .mpl import new_figure, save_figure


def plot_pulse(velocity_ms: np.ndarray, pulse_ms: np.ndarray, dt_s: float, *, title: str,
               path: str | Path, tp_s: float | None = None) -> Path:
    """Write a three-panel figure: original velocity, extracted pulse, residual [cm/s].

    Parameters
    ----------
    velocity_ms, pulse_ms : ndarray
        Velocity along the pulse orientation and the extracted pulse [m s-1].
    dt_s : float
        Sampling interval [s].
    title : str
        Figure title (record id).
    path : str or Path
        Output file (.png or .svg).
    tp_s : float, optional
        Pulse period, shown in the title [s].
    """
    fig = pulse_axes(velocity_ms, pulse_ms, dt_s,
                     title=title + (f"  (Tp = {tp_s:.3f} s)" if tp_s and np.isfinite(tp_s) else ""))
    return save_figure(fig, path)


def pulse_axes(velocity_ms: np.ndarray, pulse_ms: np.ndarray, dt_s: float, *, title: str, figsize=(7, 6)):
    """The three-panel figure (original, pulse, residual) [cm/s] on a new matplotlib figure.

    Fixed margins (no layout engine): the panel names sit inside the panels and one shared
    velocity label stands at the left, so nothing overlaps at any size from 4 in tall.
    """
    t = np.arange(velocity_ms.size) * dt_s
    fig = new_figure(figsize=figsize)
    fig.subplots_adjust(left=0.1, right=0.98, top=0.9, bottom=0.11, hspace=0.12)
    axes = fig.subplots(3, 1, sharex=True, sharey=True)
    for ax, y, label in zip(axes, (velocity_ms, pulse_ms, velocity_ms - pulse_ms),
                            ("original ground motion", "extracted pulse", "residual ground motion")):
        ax.plot(t, M_TO_CM * y, lw=0.8, color="k")
        ax.text(0.005, 0.94, label, transform=ax.transAxes, fontsize=8, va="top",
                bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8, "pad": 1})
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    fig.supylabel("velocity [cm/s]", fontsize=9)
    fig.suptitle(title, fontsize=10)
    return fig
