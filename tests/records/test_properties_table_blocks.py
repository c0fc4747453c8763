"""Hypothesis: a text table read by blocks (any block size, so that blocks end anywhere: inside a line, between a
carriage return and its newline, inside the byte-order mark) gives what its lines taken one by one give: the same
values to the bit, header pairs, width, first data line and time stamps, or the same refusal naming the same line."""

from __future__ import annotations

import gzip

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from table_lines import by_blocks, by_lines

import pipeline.records.table as table

_number = st.one_of(st.integers(-10**6, 10**6).map(str),
                    st.floats(-1e6, 1e6, allow_nan=False).map(lambda x: f"{x:.6f}"),
                    st.floats(-1e6, 1e6, allow_nan=False).map(lambda x: f"{x:.5e}"),
                    st.floats(-1e6, 1e6, allow_nan=False).map(lambda x: f"{x:.4E}".replace("E", "D")),
                    st.sampled_from([".5", "5.", "+1", "-0", "1e5", "abc", "1.0.0", "nan", "--", "1_0"]))
_sep = st.sampled_from([",", "\t", " ", ";", ", ", "  ", "\t,", "\xa0"])
_end = st.sampled_from(["", "", "", "\r", ",", " ", "\xa0"])
_lead = st.sampled_from(["", "", "", " ", ",", "\t"])


@st.composite
def _line(draw) -> str:
    kind = draw(st.sampled_from(["row", "row", "row", "row", "row1", "blank", "header", "names", "long"]))
    if kind == "row":
        return draw(_lead) + draw(_number) + draw(_sep) + draw(_number) + draw(_end)
    if kind == "row1":
        return draw(_number) + draw(_end)
    if kind == "blank":
        return draw(st.sampled_from(["", " ", "\t", "\r"]))
    if kind == "header":
        return "# " + draw(st.sampled_from(["dt_s=0.01", "units=g", "n=5", "rig A", "component=UP"]))
    if kind == "names":
        return draw(st.sampled_from(["time,acc", "t acc", "acc"]))
    return "9" * draw(st.integers(4090, 4100))


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(lines=st.lists(_line(), min_size=0, max_size=60), newline_at_end=st.booleans(), bom=st.booleans(),
       packed=st.booleans(), block=st.integers(1, 300), max_rows=st.sampled_from([5, 40, table.MAX_ROWS]))
def test_blocks_read_as_lines(tmp_path_factory, lines, newline_at_end, bom, packed, block, max_rows):
    data = ("\n".join(lines) + ("\n" if newline_at_end and lines else "")).encode("latin-1")
    data = (b"\xef\xbb\xbf" if bom else b"") + data
    data = gzip.compress(data) if packed else data
    path = tmp_path_factory.mktemp("t") / "t.txt"
    path.write_bytes(data)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(table, "BLOCK_BYTES", block)
        got = by_blocks(path, max_rows=max_rows)
    assert got == by_lines(data, str(path), max_rows=max_rows)
