"""Checks of drawn matplotlib figures, shared by the tests of every page's figures."""

from __future__ import annotations


def legend_boxes_clear(fig) -> list[str]:
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
