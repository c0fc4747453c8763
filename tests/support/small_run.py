"""The smallest screening run of the tests that need a real output folder: one bundled record, one block,
``--samples 0`` (a few seconds)."""

from __future__ import annotations

from pathlib import Path


def one_record_run(make_records, tmp_path: Path) -> tuple[list[str], Path]:
    """The arguments of ``screen`` for one record and one block into ``tmp_path/out``, run once; and that folder."""
    from pipeline.cli import main

    recs = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2")
    blocks = tmp_path / "b.csv"
    blocks.write_text("id,height_m,width_m,mu\nTOMB,1.1,0.2,0.65\n")
    out = tmp_path / "out"
    run = ["--records", str(recs), "--blocks", str(blocks), "--out", str(out), "--samples", "0", "-q"]
    assert main(run) == 0
    return run, out
