"""How long the 3D contact model's steps may be: its verdicts with its steps as shipped, and with every step short
(no long steps, :mod:`pipeline.rocking.solids.long_steps`), against every step a fifth or a tenth as long.

Two sets of scenes, each body from rest:

- the PyBullet peer families of ``contact3d_peer.py`` (statues, cabinets, boxes, cylinders) on the bundled records
  with two horizontals of known azimuth and PGA >= 0.2 g, each record at 1.0 and 1.5 times its amplitude; the
  reference takes every step at 0.1 ms;
- with ``--granite DIR`` (``../shared/experiments/granite-pbr``), the two scanned granite rocks on every
  ``--every``-th shake-table test at 12 yaws; a test-rock's verdict is the worst yaw's (overturned at any); the
  reference takes every step at a tenth of the table's 1.25 ms interval.

Prints, per set and per way of stepping, the verdicts that differ from the reference, the median and 90th
percentile of the relative difference in peak tilt and in the largest slide where both stand and the reference's
exceeds 1e-3 (rad, m), the integrated steps and the time of the contact model's runs (one process); and the verdicts
the long steps turn against every step short. ``--long-step`` tries another long step than the shipped one.

Run: ``python benchmarks/contact3d_steps.py [--granite ../shared/experiments/granite-pbr] [--every 12]
[--long-step 1.3e-3]``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import contextlib
import csv
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_granite import TABLE_MU, motion, rocks_3d  # noqa: E402
from contact3d_peer import FAMILIES, _frame  # noqa: E402

from pipeline.bodies import convex3d  # noqa: E402
from pipeline.config import Config  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.records.loader import iter_records  # noqa: E402
from pipeline.records.record import Record  # noqa: E402
from pipeline.rocking.solids import contact3d, long_steps  # noqa: E402
from pipeline.rocking.solids.contact3d import simulate_contact3d  # noqa: E402
from pipeline.rocking.solids.convex_body import box_body, cylinder_body  # noqa: E402

AMPLITUDES = (1.0, 1.5)
YAWS_DEG = np.arange(0.0, 360.0, 30.0)


@contextlib.contextmanager
def stepping(max_step_s: float, long_step_s: float):
    """The contact model's steps at most ``max_step_s`` [s], taken as one up to ``long_step_s`` [s] (0: never)."""
    kept = contact3d.MAX_STEP_S, long_steps.LONG_STEP_S
    contact3d.MAX_STEP_S, long_steps.LONG_STEP_S = max_step_s, long_step_s
    try:
        yield
    finally:
        contact3d.MAX_STEP_S, long_steps.LONG_STEP_S = kept


def _peer_scenes():
    records = [r for r in iter_records(ROOT / "records", config=Config()) if not r.single_component
               and r.azimuth_known and np.max(np.hypot(*r.horizontal_ms2)) >= 0.2 * G]
    for family, bodies in FAMILIES.items():
        for kind, w, d, h, mu, az in bodies:
            body = cylinder_body(w, h, mu=mu) if kind == "cylinder" else box_body(w, d, h, mu=mu)
            for rec in records:
                bx, by = _frame(rec, az)
                for scale in AMPLITUDES:
                    av = None if rec.vertical_ms2 is None else scale * rec.vertical_ms2
                    yield family, (scale * bx, scale * by, av, rec.dt_s, body, 0.0)


def _granite_scenes(data: Path, every: int):
    rocks = rocks_3d(data, TABLE_MU)
    tests = [t for t in csv.DictReader(open(data / "tests.csv")) if t["has_motion"] == "1"][::every]
    for test in tests:
        ah, dt = motion(data / "motions" / f"{test['test']}.acc.gz")
        rec = Record(record_id=test["test"], dt_s=dt, horizontal_ms2=ah[None, :], azimuths_deg=(0.0,),
                     azimuth_known=False, vertical_ms2=None, files=(), formats=("TABLE",), component_codes=("X",),
                     processing_level="uncorrected")
        for rock, geo in rocks.items():
            fr = convex3d.frame(rec, geo.shape)
            for yaw in YAWS_DEG:
                yield f"{rock} {test['test']}", (fr.ax, fr.ay, fr.av, fr.dt_s, geo.body, float(yaw))


def _run_all(scenes, max_step_s, long_step_s):
    out, seconds, integrated = [], 0.0, 0
    with stepping(max_step_s, long_step_s):
        for key, (ax, ay, av, dt, body, yaw) in scenes:
            t0 = time.perf_counter()
            got = simulate_contact3d(ax, ay, av, dt, body, yaw_deg=yaw)
            seconds += time.perf_counter() - t0
            integrated += got.integrated_steps
            out.append((key, bool(got.overturned), float(got.tilt_max_rad), float(got.slide_max_m)))
    return out, seconds, integrated


def _relative(res, ref, i, least):
    """The relative differences of field ``i`` where both stand and the reference's exceeds ``least``."""
    rel = [abs(a[i] - b[i]) / b[i] for a, b in zip(res, ref) if not a[1] and not b[1] and b[i] > least]
    return f"median {np.median(rel):.3f}, 90th percentile {np.quantile(rel, 0.9):.3f}"


def _worst(runs) -> dict:
    """Each key's verdict over its runs: overturned where any run overturns (the worst of a rock's yaws)."""
    out: dict = {}
    for key, overturned, *_ in runs:
        out[key] = out.get(key, False) or overturned
    return out


def _report(title, runs, group):
    """Each way of stepping against the first (the reference); the last also against the second (every step
    short)."""
    ref, short = runs[0][1][0], runs[1][1][0]
    print(f"\n## {title}: {len(ref)} runs")
    for name, (res, seconds, integrated) in runs:
        line = f"  {name:<34} {seconds:7.1f} s, {integrated:>11,} steps integrated"
        if res is not ref:
            line += (f"; verdicts differing {sum(a[1] != b[1] for a, b in zip(res, ref))}; peak tilt rel. difference "
                     f"{_relative(res, ref, 2, 1e-3)}; largest slide [m] {_relative(res, ref, 3, 1e-3)}")
            if group:
                mine, theirs = _worst(res), _worst(ref)
                line += f"; worst-of-{len(YAWS_DEG)} verdicts differing {sum(mine[k] != theirs[k] for k in mine)} " \
                        f"of {len(mine)}"
        if res is runs[-1][1][0]:
            line += f"; verdicts turned against every step short {sum(a[1] != b[1] for a, b in zip(res, short))}"
        print(line, flush=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--granite", type=Path, help="the granite shake-table data (../shared/experiments/granite-pbr)")
    ap.add_argument("--every", type=int, default=12, help="every k-th granite test")
    ap.add_argument("--long-step", type=float, default=long_steps.LONG_STEP_S,
                    help="the long steps to try [s] (default: as shipped)")
    args = ap.parse_args()
    shipped = contact3d.MAX_STEP_S, args.long_step
    peers = list(_peer_scenes())
    _run_all(peers[:2], *shipped)                                       # compiled before any run is timed
    _report("peer families from rest, at 1.0 and 1.5 times each record", [
        ("every step 0.1 ms (the reference)", _run_all(peers, 1e-4, 0.0)),
        ("every step short (no long steps)", _run_all(peers, shipped[0], 0.0)),
        (f"long steps of {args.long_step * 1e3:g} ms", _run_all(peers, *shipped))], group=False)
    if args.granite:
        rocks = list(_granite_scenes(args.granite, args.every))
        _report(f"granite rocks, every {args.every}th test, {len(YAWS_DEG)} yaws", [
            ("every step 0.125 ms (the reference)", _run_all(rocks, 1.25e-4, 0.0)),
            ("every step short (no long steps)", _run_all(rocks, shipped[0], 0.0)),
            (f"long steps of {args.long_step * 1e3:g} ms", _run_all(rocks, *shipped))], group=True)


if __name__ == "__main__":
    main()
