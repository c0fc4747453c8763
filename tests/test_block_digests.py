"""The scene cache's per-block digest covers everything a model reads of a block: every field of BlockShape, the
ones named in blocks.py and any field a new model declares there later."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np

from pipeline import blocks
from pipeline.blocks import Inventory
from pipeline.rocking.block import BlockShape


def _inventory() -> Inventory:
    return Inventory(ids=("A", "B"), names=("", ""), sites=("", ""), notes=("", ""), height_m=np.array([1.0, 1.0]),
                     width_m=np.array([0.2, 0.2]), mu=np.array([0.6, 0.6]), azimuth_deg=np.array([np.nan, np.nan]),
                     restitution=np.array([np.nan, np.nan]), source="<test>")


def test_every_field_of_a_block_today_is_named_in_the_digest():
    assert sorted(f.name for f in dataclasses.fields(BlockShape)) == sorted(blocks.DIGESTED_SHAPE_FIELDS)


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Anchored(BlockShape):
    """A block with a field a new model would declare: an anchor's strength [kN] (0: none)."""

    anchor_kN: float = 0.0


def test_a_field_declared_later_enters_the_digest_where_it_is_set(monkeypatch):
    inv = _inventory()
    plain = inv.digests()
    assert plain[0] != plain[1]                                  # the id enters it
    anchors = {"A": 0.0, "B": 0.0}

    def shape(self, j):
        base = dataclasses.asdict(BlockShape(height_m=float(self.height_m[j]), width_m=float(self.width_m[j]),
                                             mu=float(self.mu[j])))
        return _Anchored(**base, anchor_kN=anchors[self.ids[j]])

    monkeypatch.setattr(Inventory, "shape", shape)
    assert _inventory().digests() == plain                       # at its default: the digest of today
    anchors["B"] = 2.5
    changed = _inventory().digests()                             # (an inventory makes its digests once)
    assert changed[0] == plain[0] and changed[1] != plain[1]     # set: that block's digest changes, alone


def test_what_an_inventory_makes_once_is_kept_and_not_pickled():
    """Shapes, blocks and digests are made once per inventory (a record's task reads every block's), and left out
    of its pickle (the executors send the inventory with every task)."""
    inv = _inventory()
    assert inv.shapes() is inv.shapes() and inv.shape(1) is inv.shapes()[1]
    assert inv.digests() is inv.digests() and inv.rocking_blocks() is inv.rocking_blocks()
    assert inv.rocking_blocks(g_ms2=9.81) is not inv.rocking_blocks()            # one per gravity
    copy = pickle.loads(pickle.dumps(inv))
    assert "_made" in vars(inv) and "_made" not in vars(copy)
    assert copy.digests() == inv.digests() and copy.rocking_blocks() == inv.rocking_blocks()
