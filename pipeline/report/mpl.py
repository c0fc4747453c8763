"""Matplotlib for files: the non-interactive backend, and figures written atomically."""

from __future__ import annotations

from pathlib import Path


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, path: str | Path, **savefig_kwargs) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix) atomically, then close it.

    Raises
    ------
    OutputError
        If the file cannot be written; an earlier file at ``path`` is left untouched.
    """
    from ..store import replace_atomically

    path = Path(path)
    try:
        return replace_atomically(path, lambda tmp: fig.savefig(tmp, format=path.suffix.lstrip(".") or "png",
                                                                **savefig_kwargs))
    finally:
        pyplot().close(fig)
