"""Hypothesis: an inventory's two-body stack is read exactly when it can stand at rest, worked by hand here: the upper
body's centre strictly inside the overlap of its base with the lower's top, and the pair's centre of mass strictly
inside the lower's base; otherwise it is a named error with its line."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.blocks import read_inventory
from pipeline.errors import InventoryError

SIZE = st.floats(0.2, 3.0)


@settings(max_examples=150, deadline=None)
@given(w1=SIZE, h1=SIZE, w2=SIZE, h2=SIZE, shift=st.floats(-1.2, 1.2), mass2=st.floats(0.1, 5000.0))
def test_a_stack_is_read_exactly_when_it_stands_at_rest(tmp_path_factory, w1, h1, w2, h2, shift, mass2):
    offset = round(shift * 0.5 * (w1 + w2), 4)
    # By hand: the upper's centre inside the overlap of the two faces (which holds its own base's centre's span
    # intersected with the lower's top), and the pair's centre of mass inside the lower's base.
    left, right = max(-w1 / 2, offset - w2 / 2), min(w1 / 2, offset + w2 / 2)
    mass1 = 1000.0 * w1 * h1 * w1
    x_pair = mass2 * offset / (mass1 + mass2)
    stands = left < offset < right and -w1 / 2 < x_pair < w1 / 2
    if min(abs(offset - left), abs(offset - right), abs(x_pair - w1 / 2), abs(x_pair + w1 / 2)) < 1e-9:
        return                                      # on an edge to rounding: either answer is exact arithmetic's
    path = tmp_path_factory.mktemp("stack") / "blocks.csv"
    path.write_text("id,height_m,width_m,mass_kg,density_kg_m3,stands_on,offset_m\n"
                    f"LO,{h1},{w1},,1000,,\nUP,{h2},{w2},{mass2},,LO,{offset}\n")
    if stands:
        inv = read_inventory(path, default_mu=0.6)
        assert inv.shape(1).stack.bodies[1].offset_m == offset
    else:
        with pytest.raises(InventoryError, match=r"line [23].*cannot stand at rest"):
            read_inventory(path, default_mu=0.6)
