"""Chosen bundled record files copied into a folder of their own, for tests that need a few real records."""

from __future__ import annotations

import shutil
from pathlib import Path


def copy_bundled(records_dir: Path, root: Path, *names: str, folder: str = "peer-at2") -> Path:
    """Copy the bundled files ``names`` (in ``records_dir / folder``) and the units file into ``root``."""
    for name in names:
        shutil.copy(records_dir / folder / name, root / name)
    shutil.copy(records_dir / "units.toml", root / "units.toml")
    return root


def read_bundled(records_dir: Path, root: Path, *names: str) -> list:
    """The records read from the bundled files ``names`` copied into ``root`` (:func:`copy_bundled`)."""
    from pipeline.config import Config
    from pipeline.records.loader import iter_records

    return list(iter_records(copy_bundled(records_dir, root, *names), config=Config()))
