"""Options that leave the 3D scenes an exact model stops without a verdict (``[simulation] contact3d = false``).

The tests of the store, the command line, the batch and the report screen the sample inventory, whose 3D boxes
(a cabinet, a transformer) would otherwise run every factor of their margin scans through the 3D contact model
(about 5 s a record of 40 s here); the hand-off itself is tested in ``tests/rocking/solids``."""

from __future__ import annotations

from pathlib import Path

#: ``--config`` with the hand-off off.
NO_HANDOFF = ("--config", str(Path(__file__).resolve().parents[1] / "data" / "no-contact3d.toml"))
