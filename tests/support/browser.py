"""Headless Chromium for the page tests: the page as a browser lays it out at a window width (the ``layoutProbe``
of the pages' ``layout.js.j2`` writes what it measured into ``<body data-...>``)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

#: A phone (390 px, an iPhone 12-15 in portrait) and a laptop
WIDTHS = (390, 1400)
#: The decision (a page's ranked assets, marked data-decision) starts within this many px of the page's top, at each
#: width: about one screen of a phone (the report's asset table sat 6,077 px down at 390 px when its diagnostics
#: came first)
DECISION_TOP_MAX_PX = {390: 1000, 1400: 700}


def chromium() -> str:
    """The browser's path; skips loudly (fails where ROCKSCREEN_REQUIRE_BROWSER is set, as in CI) without one."""
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    message = ("CHROMIUM IS NOT INSTALLED: the pages were NOT tested in a browser. Install Debian's 'chromium' "
               "package (make test does this when it can) and run again.")
    print(f"\n{'!' * 80}\n{message}\n{'!' * 80}", file=sys.stderr)
    if os.environ.get("ROCKSCREEN_REQUIRE_BROWSER"):
        pytest.fail(message + " (ROCKSCREEN_REQUIRE_BROWSER is set, as in CI)")
    pytest.skip(message)


#: The page in a frame of the width asked for: headless Chromium's window is at least 500 px wide, so a phone's
#: viewport is a frame; the frame's probe (run on its own load) is copied to this page's body for --dump-dom
FRAME = """<!DOCTYPE html><html><body style="margin:0">
<iframe id="f" src="{src}" style="width:{width}px;height:900px;border:0"></iframe>
<script>
document.getElementById("f").addEventListener("load", function () {{
  var data = this.contentDocument.body.dataset;
  Object.keys(data).forEach(function (k) {{ document.body.dataset[k] = data[k]; }});
}});
</script></body></html>"""


def layout_at(page: Path, width: int, tmp: Path) -> dict:
    """The probe's measures of ``page`` in a viewport ``width`` px wide: page-width, window-width,
    tables-overflowing, broken-words (and broken_examples, the first few)."""
    frame = page.parent / f".frame-{width}.html"
    frame.write_text(FRAME.format(src=page.name, width=width))
    common = [chromium(), "--headless=new", "--no-sandbox", "--disable-gpu", f"--user-data-dir={tmp / 'profile'}",
              "--virtual-time-budget=10000", "--window-size=1600,1000", "--hide-scrollbars",
              "--allow-file-access-from-files"]
    try:
        run = subprocess.run([*common, "--dump-dom", frame.as_uri()], capture_output=True, text=True, timeout=120,
                             env=dict(os.environ, HOME=str(tmp)))
    finally:
        frame.unlink()
    assert run.returncode == 0, run.stderr[-2000:]
    got: dict = {k: int(v) for k, v in re.findall(
        r'data-(page-width|window-width|tables-overflowing|broken-words)="(\d+)"', run.stdout)}
    assert len(got) == 4, run.stdout[:500]
    got.update({k: int(v) for k, v in re.findall(r'data-(decision-top|key-column-right)="(\d+)"', run.stdout)})
    examples = re.search(r'data-broken-examples="([^"]*)"', run.stdout)
    got["broken_examples"] = examples.group(1) if examples else ""
    assert got["window-width"] == width, got
    return got


def assert_reads_at(page: Path, tmp: Path) -> None:
    """At a phone's and a laptop's width: the page no wider than the window (tables scroll in their own box), no
    word of a table broken inside, the decision near the top (:data:`DECISION_TOP_MAX_PX`) and the column that
    decides (data-key-column) inside the window."""
    for width in WIDTHS:
        got = layout_at(page, width, tmp)
        assert got["page-width"] <= got["window-width"], (width, got)
        assert got["tables-overflowing"] == 0 and got["broken-words"] == 0, (width, got)
        assert got["decision-top"] <= DECISION_TOP_MAX_PX[width], (width, got)      # every page marks its decision
        assert got.get("key-column-right", 0) <= got["window-width"], (width, got)


#: The project's measure of where a page's decision lands (kept beside the project, in ../shared, not in it)
DECISION_FIRST_TOOL = Path(__file__).resolve().parents[3] / "shared" / "tools" / "decision_first.py"
#: The first screen of a phone and of a laptop [px]
SCREENS = ((390, 844), (1400, 900))


def assert_decision_first(page: Path, assets_csv: Path) -> None:
    """At a phone's and a laptop's first screen, the decision of ``assets_csv``'s first row (its
    ``recommendation``) starts within the screen and ends inside the window, as ../shared/tools/decision_first.py
    measures it; skips loudly without the browser or the tool."""
    chromium()
    if not DECISION_FIRST_TOOL.is_file():
        pytest.skip(f"DECISION-FIRST TOOL NOT FOUND at {DECISION_FIRST_TOOL}: the first screen was NOT measured")
    for width, height in SCREENS:
        run = subprocess.run([sys.executable, str(DECISION_FIRST_TOOL), str(page), str(assets_csv), str(width),
                              str(height)], capture_output=True, text=True, timeout=180)
        assert run.returncode == 0, (width, run.stdout + run.stderr[-1000:])
