"""The planar two-block model (pipeline.assemblies.two_block_run) against PyBullet on the bundled records: a statue
on its plinth and a column of two drums, each record's first horizontal in the stack's plane scaled to a PGA, no
vertical, friction high enough that no joint slides (the model rocks without sliding: mu 2 in both engines' sense).
PyBullet holds two deep boxes stacked on its floor, the ground's motion as a time-varying gravity (as the project's
other peers, tests/support/rigid_body_peer.py). For each scene the verdict of each: what falls first (the top: its
tilt reaches pi/2; the stack: the lower block's tilt reaches pi/2; PyBullet's by 0.02 rad less), or stands; and each
disagreement re-run by PyBullet at half its step and at 0.98 and 1.02 of the record (robust: the engine's verdict
holds in all three). Prints the counts and the time per scene of each, and of the rocking kernel on the single
block of the stack's outline and of the 3D box model on the box of that outline with a square base (the cost of a
second body).

Run: ``python benchmarks/two_block_peer.py [--pga 0.5] [--records 12]`` (the first records of at most 60 s;
PyBullet is a test extra).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import math
import statistics
import sys
import time
from functools import partial
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))

from rigid_body_peer import bullet_stack_falls, perturbed_verdicts  # noqa: E402

from pipeline.assemblies.stack import StackBody  # noqa: E402
from pipeline.assemblies.two_block import two_block  # noqa: E402
from pipeline.assemblies.two_block_run import FALLS_NONE, FALLS_STACK, FALLS_TOP, simulate_two_block  # noqa: E402
from pipeline.config import Config  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.records.loader import iter_records  # noqa: E402
from pipeline.rocking.simulate import rock  # noqa: E402
from pipeline.rocking.solids.box3d import Box, simulate_box  # noqa: E402

RHO = 2500.0
MU = 2.0
#: name -> ((width, height) of the lower block, (width, height) of the upper) [m]
STACKS = {"statue on plinth": ((0.6, 1.0), (0.3, 1.2)), "two drums": ((0.5, 1.5), (0.5, 1.0))}
#: records longer than this are left out (PyBullet steps at 4 kHz) [s]
MAX_DURATION_S = 60.0
NAMES = {FALLS_NONE: "stands", FALLS_TOP: "top falls", FALLS_STACK: "stack falls"}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pga", type=float, default=0.5, help="each record scaled to this PGA [g]")
    ap.add_argument("--records", type=int, default=12, help="the first N bundled records of at most 60 s")
    args = ap.parse_args()
    records = []
    for r in iter_records(ROOT / "records", config=Config()):
        if len(records) < args.records and r.horizontal_ms2[0].size * r.dt_s <= MAX_DURATION_S:
            records.append(r)
    print(f"{len(records)} bundled records of at most {MAX_DURATION_S:.0f} s, each scaled to PGA {args.pga} g")
    warm = np.zeros(8)                                     # load both kernels before timing them
    simulate_two_block(two_block(StackBody(1, 1, 1, MU), StackBody(1, 1, 1, MU)), warm, 0.01)
    rock(warm, 0.01, p=1.0, alpha=0.3, e=0.9, R_m=1.0)
    simulate_box(warm, warm, None, 0.01, Box(0.5, 0.5, 1.0, mu=MU))
    agree, robust_miss, t_model, t_peer, t_single, t_box = 0, 0, [], [], [], []
    for rec in records:
        a = np.asarray(rec.horizontal_ms2[0], dtype=float)
        a = a * (args.pga * G / np.max(np.abs(a)))
        for name, (lower, upper) in STACKS.items():
            tb = two_block(StackBody(lower[0], lower[1], RHO * lower[0] * lower[1], MU),
                           StackBody(upper[0], upper[1], RHO * upper[0] * upper[1], MU))
            t0 = time.perf_counter()
            ours = simulate_two_block(tb, a, rec.dt_s).falls
            t_model.append(time.perf_counter() - t0)
            width, height = lower[0], lower[1] + upper[1]           # the outline (the wider lower block)
            radius, alpha = math.hypot(width / 2, height / 2), math.atan(width / height)
            t0 = time.perf_counter()
            rock(a, rec.dt_s, p=math.sqrt(0.75 * G / radius), alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2,
                 R_m=radius)
            t_single.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            simulate_box(a, np.zeros_like(a), None, rec.dt_s, Box(width / 2, width / 2, height / 2, mu=MU))
            t_box.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            peer = bullet_stack_falls(a, rec.dt_s, lower, upper, mu=MU, density=RHO)
            t_peer.append(time.perf_counter() - t0)
            note = ""
            if ours == peer:
                agree += 1
            else:
                checks = perturbed_verdicts(partial(bullet_stack_falls, a, rec.dt_s, lower, upper, mu=MU, density=RHO))
                robust = checks == {peer}
                robust_miss += robust
                note = f"  engine {'robust' if robust else 'not robust: ' + str(sorted(NAMES[c] for c in checks))}"
            print(f"{rec.record_id[:40]:40s} {name:17s} rockscreen {NAMES[ours]:11s} PyBullet {NAMES[peer]:11s}{note}",
                  flush=True)
    n = len(t_model)
    print(f"\n{agree} of {n} scenes agree; {robust_miss} disagreements where the engine's verdict is robust")
    print(f"time a scene: rockscreen median {statistics.median(t_model):.4f} s (worst {max(t_model):.4f}); "
          f"PyBullet median {statistics.median(t_peer):.2f} s (worst {max(t_peer):.2f}); the single block of the "
          f"outline median {statistics.median(t_single):.4f} s")
    for what, times in (("the single block of their outline", t_single),
                        ("the 3D box of their outline (a square base)", t_box)):
        ratios = [m / s for m, s in zip(t_model, times)]
        print(f"two blocks / {what}, per scene: median {statistics.median(ratios):.2f}, worst {max(ratios):.2f} "
              f"(its median {statistics.median(times):.4f} s)")


if __name__ == "__main__":
    main()
