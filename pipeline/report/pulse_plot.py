"""The original velocity, extracted pulse and residual, as the authors' ``make_plot`` draws them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .mpl import pyplot, save_figure


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
    fig = pulse_axes(pyplot(), velocity_ms, pulse_ms, dt_s,
                     title=title + (f"  (Tp = {tp_s:.3f} s)" if tp_s and np.isfinite(tp_s) else ""))
    return save_figure(fig, path)


def pulse_axes(plt, velocity_ms: np.ndarray, pulse_ms: np.ndarray, dt_s: float, *, title: str,
               figsize=(7, 6)):
    """The three-panel figure (original, pulse, residual) [cm/s] on a new matplotlib figure."""
    t = np.arange(velocity_ms.size) * dt_s
    fig, axes = plt.subplots(3, 1, figsize=figsize, sharex=True, sharey=True)
    for ax, y, label in zip(axes, (velocity_ms, pulse_ms, velocity_ms - pulse_ms),
                            ("Original ground motion", "Extracted pulse", "Residual ground motion")):
        ax.plot(t, 100 * y, lw=0.8, color="k")
        ax.set_ylabel("velocity [cm/s]")
        ax.set_title(label, fontsize=9)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig
