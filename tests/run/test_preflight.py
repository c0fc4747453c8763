"""An empty records folder and an output that cannot be written are said at once, before the simulator is
compiled or loaded (the inputs stage checks both again in full)."""

from __future__ import annotations

import pytest


@pytest.fixture
def no_warmup(monkeypatch):
    """The simulator's warm-up, made to fail the test if it is reached."""
    from pipeline.run import stages

    def refuse(*args, **kwargs):
        raise AssertionError("the simulator was warmed up before the inputs were checked")

    monkeypatch.setattr(stages, "compile_simulator", refuse)


def test_an_empty_records_folder_is_said_before_the_warm_up(tmp_path, no_warmup, capsys):
    from pipeline.cli import main

    (tmp_path / "recs").mkdir()
    (tmp_path / "b.csv").write_text("id,height_m,width_m\nA,1.0,0.2\n")
    assert main(["--records", str(tmp_path / "recs"), "--blocks", str(tmp_path / "b.csv"), "--out",
                 str(tmp_path / "out")]) == 2
    assert "the records directory is empty" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_an_output_that_cannot_be_written_is_said_before_the_warm_up(records_dir, tmp_path, no_warmup, capsys):
    from pipeline.cli import main

    (tmp_path / "b.csv").write_text("id,height_m,width_m\nA,1.0,0.2\n")
    (tmp_path / "a-file").write_text("")
    assert main(["--records", str(records_dir / "fn-ascii"), "--blocks", str(tmp_path / "b.csv"), "--out",
                 str(tmp_path / "a-file" / "out")]) == 3
    err = capsys.readouterr().err
    assert "output directory is not writable" in err and "a-file is not a directory" in err
