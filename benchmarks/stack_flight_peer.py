"""Stacks whose ground falls faster than gravity, against PyBullet: the flights the stack's contact model
(pipeline.assemblies.stack_contact) follows for the n-block model.

The bundled records with a vertical, each scaled (horizontals and vertical together) so that its vertical falls to
VERTICAL_G below gravity where a scale of at most MAX_SCALE does it (El Centro Array 6 needs none: its vertical
reaches -1.53 g), in four planes each; four stacks of deep boxes (a statue on its plinth, columns of two, three and
five drums), friction mu on the floor and mu^2 between the boxes in both engines (PyBullet combines the two bodies'
friction as their product). For each scene the lowest box that has fallen at the first fall (none, or the box), and
whether any box falls (the stack's verdict under ``screen``'s default rule, ``stack_verdict`` blank); each
disagreement re-run by PyBullet at half its step and at 0.98 and 1.02 of the record (robust: the engine's verdict
holds in all three), and by rockscreen at 0.98 and 1.02; where the engine overturns a box robustly, rockscreen's
probability and class for that box under the default draws (``screen``'s, the plane a given azimuth drawn about it).
Prints the counts, the agreement and each engine's time per scene.

Run: ``python benchmarks/stack_flight_peer.py [--families statue,two,three,five] [--planes 0,45,90,135]``
(PyBullet is a test extra).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import statistics
import sys
import time
from functools import partial
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))

from rigid_body_peer import NONE_FALLS, bullet_first_fall, perturbed_verdicts  # noqa: E402
from stack_flights import MU, RHO, STACKS, difference, drawn_class, first_fall, flight_records, stack  # noqa: E402

from pipeline.assemblies.n_block_verdicts import judge_n_block  # noqa: E402
from pipeline.records.record import project  # noqa: E402
from pipeline.rocking.codes import STATUS_GROUND_FLIGHT, Verdict  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--families", default=",".join(STACKS))
    ap.add_argument("--planes", default="0,45,90,135", help="azimuths of the planes [deg]")
    args = ap.parse_args()
    records = flight_records(ROOT / "records")
    planes = [float(p) for p in args.planes.split(",")]
    print(f"{len(records)} records: " + ", ".join(f"{r[0]} x{r[5]:.2f}" for r in records))
    for family in args.families.split(","):
        boxes = STACKS[family]
        nb, mu = stack(family)
        agree, any_agree, flights, differ, ours_s, engine_s = 0, 0, 0, [], [], []
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
                any_agree += (ours == NONE_FALLS) == (engine == NONE_FALLS)
                if ours == engine:
                    agree += 1
                    print(f"   {family} {rid} @ {az:g}: the first fall {ours} in both", flush=True)
                    continue
                judge = partial(bullet_first_fall, a, dt, boxes, mu=MU, density=RHO, av_ms2=av)
                robust = perturbed_verdicts(judge) == {engine}
                ours_robust = {first_fall(judge_n_block(nb, s * a, dt, av_ms2=s * av, mu=mu))
                               for s in (0.98, 1.02)} == {ours}
                drawn = drawn_class(family, engine, hz, av, az0, dt, az) if robust and engine != NONE_FALLS else None
                differ.append(difference(f"{rid} @ {az:g}", ours, ours_robust, engine, robust, drawn))
                print("  ", family, differ[-1], flush=True)
        n = len(ours_s)
        print(f"{family}: {agree} of {n} agree on the first fall, {any_agree} of {n} on whether any box falls "
              f"({flights} met a flight); rockscreen "
              f"{1e3 * statistics.median(ours_s):.1f} ms (median; worst {1e3 * max(ours_s):.0f} ms), PyBullet "
              f"{statistics.median(engine_s):.2f} s", flush=True)
        for line in differ:
            print("    ", line)


if __name__ == "__main__":
    main()
