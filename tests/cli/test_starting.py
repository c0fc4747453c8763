"""A command's start-up is said at once and repeated with its time until its tasks' progress starts
(:func:`pipeline.cli.progress._starting`), so that nothing is silent for 2 s while it loads."""

from __future__ import annotations

import sys
import time

import pytest

from pipeline.cli import progress as cli_progress


def _lines(items, total=None, running=None, label="records screened"):
    print("progress begins", file=sys.stderr)
    yield from items


def test_the_start_up_is_said_at_once_and_repeated_until_the_progress_starts(monkeypatch, capsys):
    monkeypatch.setattr(cli_progress, "PROGRESS_LINE_S", 0.2)
    with cli_progress._starting(False, _lines, "loading") as progress:
        time.sleep(0.5)                                     # the start-up: ticks every 0.15 s
        assert list(progress([1, 2], total=2)) == [1, 2]
        time.sleep(0.5)                                     # the progress has started: no tick
    err = capsys.readouterr().err.splitlines()
    assert err[0] == "starting: loading ..."
    ticks = [line for line in err if line.startswith("  ... starting: ")]
    assert 2 <= len(ticks) and err.index("progress begins") > err.index(ticks[-1])
    assert err[-1] == "progress begins"


@pytest.mark.parametrize("quiet, given", [(True, None), (False, None)])
def test_quiet_or_no_progress(quiet, given, capsys):
    with cli_progress._starting(quiet, given) as progress:
        assert progress is None
    assert (capsys.readouterr().err == "") is quiet
