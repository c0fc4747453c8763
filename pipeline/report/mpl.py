"""Matplotlib for files: figures from the object API (no pyplot, no global backend switch), written atomically."""

from __future__ import annotations

from pathlib import Path
from typing import Literal


def new_figure(*, figsize: tuple[float, float], layout: Literal["constrained", "tight"] | None = None):
    """A :class:`matplotlib.figure.Figure` not registered with pyplot (nothing to close, no backend state).

    ``layout`` is matplotlib's layout engine ("constrained", "tight") or None for the fixed
    margins the caller sets with ``subplots_adjust`` (the cheap choice for figures drawn often).
    """
    from matplotlib.figure import Figure

    return Figure(figsize=figsize, layout=layout)


def save_figure(fig, path: str | Path, **savefig_kwargs) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix) atomically.

    Raises
    ------
    OutputError
        If the file cannot be written; an earlier file at ``path`` is left untouched.
    """
    from ..store import replace_atomically

    path = Path(path)
    return replace_atomically(path, lambda tmp: fig.savefig(tmp, format=path.suffix.lstrip(".") or "png",
                                                            **savefig_kwargs))


def png_bytes(fig, *, dpi: int = 90) -> bytes:
    """Render a matplotlib figure to PNG bytes (for embedding in a page)."""
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()
