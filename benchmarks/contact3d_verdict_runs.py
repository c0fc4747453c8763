"""The 3D contact model's runs for a verdict only, against the same runs followed to their end: the granite rocks'
draws as ``screen`` runs them (:func:`pipeline.bodies.convex3d.yaw_draws`), each once with the energy barrier
(:func:`pipeline.rocking.solids.contact3d.overturn_barrier`: after the record, the run stops where the body's
energy shows it can never tilt as far as an overturning) and once without.

For every ``--every``-th shake-table test and both rocks: the worst yaw as ``screen`` finds it
(:func:`~pipeline.bodies.convex3d.judge`), then the first ``--draws`` draws of the declared uncertainty there. Prints
the runs, the verdicts and peak tilts that differ between the two ways, the runs the barrier cut short, and each
way's steps integrated and time (one process, the two ways alternating run by run).

Run: ``python benchmarks/contact3d_verdict_runs.py ../shared/experiments/granite-pbr [--every 24] [--draws 40]``.
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_granite import TABLE_MU, motion, rocks_3d  # noqa: E402

from pipeline.bodies import convex3d, scanned3d  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.records.record import Record  # noqa: E402
from pipeline.rocking.solids.contact3d import overturn_barrier  # noqa: E402
from pipeline.uncertainty.sampling import common_normals  # noqa: E402
from pipeline.uncertainty.settings import UncertaintyConfig  # noqa: E402
from pipeline.uncertainty.two_sided import draw_factors  # noqa: E402


def _record(data: Path, test: dict) -> Record:
    ah, dt = motion(data / "motions" / f"{test['test']}.acc.gz")
    return Record(record_id=test["test"], dt_s=dt, horizontal_ms2=ah[None, :], azimuths_deg=(0.0,),
                  azimuth_known=False, vertical_ms2=None, files=(), formats=("TABLE",), component_codes=("X",),
                  processing_level="uncorrected")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("data", type=Path)
    ap.add_argument("--every", type=int, default=24, help="every k-th test")
    ap.add_argument("--draws", type=int, default=40, help="draws per test and rock")
    args = ap.parse_args()
    tests = [t for t in csv.DictReader(open(args.data / "tests.csv")) if t["has_motion"] == "1"][::args.every]
    rocks = rocks_3d(args.data, TABLE_MU)
    unc = UncertaintyConfig()
    z = common_normals(unc.seed, args.draws)
    drawn: dict[tuple[str, int], convex3d.Drawn] = {}
    totals = {"runs": 0, "verdicts differing": 0, "peak tilts differing": 0, "runs cut": 0}
    seconds, integrated = [0.0, 0.0], [0, 0]
    for test in tests:
        rec = _record(args.data, test)
        for rock, geo in rocks.items():
            fr = convex3d.frame(rec, geo.shape)
            yaw = convex3d.judge(fr, geo.body, g_ms2=G).yaw_deg
            for k in range(args.draws):
                f = draw_factors(z[k], unc)
                if (rock, k) not in drawn:
                    body = scanned3d.SCANNED_BODIES.body_of(geo.shape, width=f.width, height=f.height,
                                                            friction=f.friction)
                    drawn[(rock, k)] = convex3d.Drawn(body, overturn_barrier(body))
                body, barrier = drawn[(rock, k)]
                outs = []
                for way, kw in enumerate(({}, {"barrier": barrier})):
                    t0 = time.perf_counter()
                    outs.append(convex3d.run(fr, body, yaw, g_ms2=G, amplitude=f.amplitude, **kw))
                    seconds[way] += time.perf_counter() - t0
                    integrated[way] += outs[-1].integrated_steps
                full, cut = outs
                totals["runs"] += 1
                totals["verdicts differing"] += full.overturned != cut.overturned
                totals["peak tilts differing"] += full.tilt_max_rad != cut.tilt_max_rad
                totals["runs cut"] += cut.steps < full.steps
    print(f"{len(tests)} tests x {len(rocks)} rocks x {args.draws} draws: " +
          ", ".join(f"{k} {v}" for k, v in totals.items()))
    for way, name in enumerate(("followed to the end", "for the verdict (barrier)")):
        print(f"  {name:<28} {integrated[way]:>12,} steps integrated, {seconds[way]:.1f} s")


if __name__ == "__main__":
    main()
