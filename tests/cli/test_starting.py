"""A stage said before a command's tasks (its start-up: loading the simulator, listing the records) is said at once
and repeated with its time until the tasks' progress starts (:func:`pipeline.cli.progress._ticking`,
:func:`~pipeline.cli.progress._after_stage`), so that nothing is silent for 2 s while it loads."""

from __future__ import annotations

import sys
import time

from pipeline.cli import progress as cli_progress


def _lines(items, total=None, running=None, label="records screened"):
    print("progress begins", file=sys.stderr)
    yield from items


def test_the_start_up_is_said_at_once_and_repeated_until_the_progress_starts(monkeypatch, capsys):
    monkeypatch.setattr(cli_progress, "PROGRESS_LINE_S", 0.2)
    with cli_progress._ticking(False) as say:
        say("starting (loading) ...")
        time.sleep(0.5)                                     # the start-up: ticks every 0.15 s
        progress = cli_progress._after_stage(_lines, say)
        assert list(progress([1, 2], total=2)) == [1, 2]
        time.sleep(0.5)                                     # the progress has started: no tick
    err = capsys.readouterr().err.splitlines()
    assert err[0] == "starting (loading) ..."
    ticks = [line for line in err if line.startswith("  ... starting: ")]
    assert 2 <= len(ticks) and err.index("progress begins") > err.index(ticks[-1])
    assert err[-1] == "progress begins"


def test_a_stage_said_after_the_progress_repeats_again(monkeypatch, capsys):
    """The writing after the tasks is a stage of its own: said, and repeated while it runs."""
    monkeypatch.setattr(cli_progress, "PROGRESS_LINE_S", 0.2)
    with cli_progress._ticking(False) as say:
        list(cli_progress._after_stage(_lines, say)([1], total=1))
        say("writing (the files) ...")
        time.sleep(0.5)
    err = capsys.readouterr().err.splitlines()
    assert err[:2] == ["progress begins", "writing (the files) ..."]
    assert len([line for line in err if line.startswith("  ... writing: ")]) >= 2


def test_quiet_says_nothing(capsys):
    with cli_progress._ticking(True) as say:
        assert say is None and cli_progress._after_stage(None, say) is None
    assert capsys.readouterr().err == ""
