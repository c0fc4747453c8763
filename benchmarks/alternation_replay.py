"""What the box alternations of the bundled default cost, replayed in one process: the body's arrays prepared once a
scene (:func:`pipeline.rocking.solids.contact3d.prepare`, as :func:`~pipeline.rocking.solids.alternate.alternate`
does) against every contact run preparing its own.

The default run on the bundled records (``screen`` with its defaults, one process) is made once with the box
family's alternation wrapped to keep its inputs (the ground, the exact model, the azimuth and the start of every
call); then the calls are replayed, the two versions in alternating passes, each pass timed whole. Prints every
pass, the medians and their ratio, and whether every outcome (verdict, peak tilt, slide, lean, steps) of the two
versions is the same. Every call's ground is kept in memory (the draws scale the record, so each call holds its
own: three components of the record's length in doubles; ``--limit`` keeps fewer calls).

Usage::

    python benchmarks/alternation_replay.py [--passes 5] [--limit N]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, NamedTuple

from pipeline.cli.main import main as screen
from pipeline.rocking.solids import alternate as alternation
from pipeline.rocking.solids import box_scene

ROOT = Path(__file__).resolve().parents[1]


class Call(NamedTuple):
    """One call of the alternation, as the box family made it."""

    ax: Any
    ay: Any
    az: Any
    dt_s: float
    model: alternation.ExactModel
    azimuth_deg: float
    start: Any
    g_ms2: float


def capture(limit: int) -> list[Call]:
    """The box alternations of a default run on the bundled records (one process), at most ``limit`` of them."""
    calls: list[Call] = []
    original = box_scene.alternate

    def kept(ax, ay, az, dt_s, model, azimuth_deg, start, *, g_ms2):
        if len(calls) < limit:
            calls.append(Call(ax, ay, az, dt_s, model, azimuth_deg, start, g_ms2))
        return original(ax, ay, az, dt_s, model, azimuth_deg, start, g_ms2=g_ms2)

    box_scene.alternate = kept
    try:
        with tempfile.TemporaryDirectory() as out:
            screen(["--records", str(ROOT / "records"), "--blocks", str(ROOT / "configs" / "blocks.csv"),
                    "--out", out, "--tolerate-failures", "-n", "1"])
    finally:
        box_scene.alternate = original
    return calls


def _fresh_arrays(original):
    """The contact model as it runs without :func:`prepare`'s arrays: each run prepares its own."""
    def run(*args, prepared=None, **kwargs):
        return original(*args, **kwargs)
    return run


#: Calls between two progress lines of a pass (about 1 s of them; a pass of the bundled default's calls takes 10-15 s)
PROGRESS_EVERY = 150


def replay(calls: list[Call], label: str = "") -> tuple[float, list[tuple]]:
    """Every call replayed; the wall time [s] and the outcomes. With ``label``, a progress line every
    :data:`PROGRESS_EVERY` calls (on stderr)."""
    outs = []
    t0 = time.perf_counter()
    for i, c in enumerate(calls, 1):
        outs.append(alternation.alternate(c.ax, c.ay, c.az, c.dt_s, c.model, c.azimuth_deg, c.start, g_ms2=c.g_ms2))
        if label and i % PROGRESS_EVERY == 0:
            print(f"  {label}: {i} of {len(calls)} calls, {time.perf_counter() - t0:.1f} s", file=sys.stderr,
                  flush=True)
    wall = time.perf_counter() - t0
    return wall, [(o.overturned, o.tilt_max_rad, o.slide_max_m, o.lean_at_peak_deg, o.integrated_steps) for o in outs]


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--passes", type=int, default=5, help="timed passes of each version (default 5)")
    ap.add_argument("--limit", type=int, default=10**9, help="keep at most this many calls")
    args = ap.parse_args(argv)
    calls = capture(args.limit)
    print(f"captured {len(calls)} box alternations")
    original = alternation.simulate_contact3d
    replay(calls[:20])                                       # warm-up
    times: dict[str, list[float]] = {"prepared once a scene": [], "prepared every run": []}
    outcomes: dict[str, list[tuple]] = {}
    for k in range(args.passes):
        for name in times:
            alternation.simulate_contact3d = original if name == "prepared once a scene" else _fresh_arrays(original)
            try:
                wall, outcomes[name] = replay(calls, f"pass {k + 1}, {name}")
            finally:
                alternation.simulate_contact3d = original
            times[name].append(wall)
            print(f"pass {k + 1}: {name:22s} {wall:6.2f} s", flush=True)
    once, every = (statistics.median(t) for t in times.values())
    same = outcomes["prepared once a scene"] == outcomes["prepared every run"]
    print(f"median of {args.passes}: prepared once a scene {once:.2f} s, prepared every run {every:.2f} s "
          f"(ratio {every / once:.2f}); every outcome the same: {same}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
