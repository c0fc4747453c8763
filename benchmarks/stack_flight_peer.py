"""Stacks whose ground falls faster than gravity, against PyBullet: the flights the stack's contact model
(pipeline.assemblies.stack_contact) follows for the n-block model.

The bundled records with a vertical, each scaled (horizontals and vertical together) so that its vertical falls to
VERTICAL_G below gravity where a scale of at most MAX_SCALE does it (El Centro Array 6 needs none: its vertical
reaches -1.53 g), in four planes each; four stacks of deep boxes (a statue on its plinth, columns of two, three and
five drums), friction mu on the floor and mu^2 between the boxes in both engines (PyBullet combines the two bodies'
friction as their product). For each scene the lowest box that has fallen at the first fall (none, or the box), and
each disagreement re-run by PyBullet at half its step and at 0.98 and 1.02 of the record (robust: the engine's
verdict holds in all three). Prints the counts, the agreement and each engine's time per scene.

Run: ``python benchmarks/stack_flight_peer.py [--families statue,two,three,five] [--planes 0,45,90,135]``
(PyBullet is a test extra).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from functools import partial
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))

from rigid_body_peer import NONE_FALLS, bullet_first_fall, perturbed_verdicts  # noqa: E402

from pipeline.assemblies.n_block import n_block  # noqa: E402
from pipeline.assemblies.n_block_verdicts import judge_n_block  # noqa: E402
from pipeline.assemblies.stack import StackBody  # noqa: E402
from pipeline.config import Config  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.records.loader import iter_records  # noqa: E402
from pipeline.records.record import project  # noqa: E402
from pipeline.rocking.codes import STATUS_GROUND_FLIGHT, Verdict  # noqa: E402

#: each record's vertical scaled down to this below gravity [g], where MAX_SCALE allows
VERTICAL_G = 1.2
MAX_SCALE = 2.2
#: friction of the boxes in PyBullet's sense: mu on the floor, mu^2 between two boxes [-]
MU = 0.8
RHO = 2500.0
#: family -> (width, height) of each box, bottom first [m]
STACKS = {"statue": ((0.70, 1.00), (0.45, 1.70)),
          "two": ((0.60, 1.50), (0.55, 1.20)),
          "three": ((0.62, 1.10), (0.60, 1.10), (0.58, 1.00)),
          "five": ((0.7, 0.8), (0.7, 0.8), (0.7, 0.8), (0.7, 0.8), (0.7, 0.6))}


def flight_records() -> list[tuple[str, np.ndarray, np.ndarray, float, float, float]]:
    """(id, horizontals, vertical, first horizontal's azimuth, dt, scale) of each bundled record whose vertical,
    scaled by at most MAX_SCALE, falls to VERTICAL_G below gravity (none scaled down)."""
    out = []
    for r in iter_records(ROOT / "records", config=Config()):
        if r.vertical_ms2 is None or not r.vertical_ms2.size or r.horizontal_ms2.shape[0] < 2:
            continue
        scale = max(1.0, VERTICAL_G * G / -r.vertical_ms2.min())
        if scale <= MAX_SCALE:
            out.append((r.record_id, r.horizontal_ms2 * scale, r.vertical_ms2 * scale, float(r.azimuths_deg[0]),
                        r.dt_s, scale))
    return out


def first_fall(judged) -> int:
    """The lowest body fallen at the first fall of rockscreen's verdicts, or NONE_FALLS."""
    times = [(t, k) for k, (v, t) in enumerate(zip(judged.verdicts, judged.t_fall_s)) if v == Verdict.overturns]
    return min(times)[1] if times else NONE_FALLS


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--families", default=",".join(STACKS))
    ap.add_argument("--planes", default="0,45,90,135", help="azimuths of the planes [deg]")
    args = ap.parse_args()
    records = flight_records()
    planes = [float(p) for p in args.planes.split(",")]
    print(f"{len(records)} records: " + ", ".join(f"{r[0]} x{r[5]:.2f}" for r in records))
    for family in args.families.split(","):
        boxes = STACKS[family]
        bodies = [StackBody(w, h, RHO * w * h, MU if k == 0 else MU * MU) for k, (w, h) in enumerate(boxes)]
        nb, mu = n_block(bodies), tuple(b.mu for b in bodies)
        agree, flights, differ, ours_s, engine_s = 0, 0, [], [], []
        for rid, hz, av, az0, dt, _scale in records:
            for az in planes:
                a = project(hz, az0, az)
                t0 = time.perf_counter()
                judged = judge_n_block(nb, a, dt, av_ms2=av, mu=mu)
                ours_s.append(time.perf_counter() - t0)
                flights += bool(judged.status & STATUS_GROUND_FLIGHT)
                assert all(v != Verdict.no_verdict for v in judged.verdicts), (rid, az, judged)
                ours = first_fall(judged)
                t0 = time.perf_counter()
                engine = bullet_first_fall(a, dt, boxes, mu=MU, density=RHO, av_ms2=av)
                engine_s.append(time.perf_counter() - t0)
                if ours == engine:
                    agree += 1
                    continue
                judge = partial(bullet_first_fall, a, dt, boxes, mu=MU, density=RHO, av_ms2=av)
                robust = perturbed_verdicts(judge) == {engine}
                differ.append(f"{rid} @ {az:g}: rockscreen {ours}, PyBullet {engine}"
                              f"{' (robust in the engine)' if robust else ' (not robust in the engine)'}")
                print("  ", family, differ[-1], flush=True)
        n = len(ours_s)
        print(f"{family}: {agree} of {n} agree ({flights} met a flight); rockscreen "
              f"{1e3 * statistics.median(ours_s):.1f} ms (median; worst {1e3 * max(ours_s):.0f} ms), PyBullet "
              f"{statistics.median(engine_s):.2f} s", flush=True)
        for line in differ:
            print("    ", line)


if __name__ == "__main__":
    main()
