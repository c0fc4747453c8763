"""Stacks whose joints slip, against PyBullet: the level slip model, the slide-rock model and the stack's contact
model (pipeline.assemblies.flat_slip, slide_rock, stack_contact) where a joint needs more friction than it has, on
grounds without a vertical (no flight).

The bundled records of at most 60 s, each first horizontal scaled to a PGA, in the stacks' plane; the four stacks of
deep boxes of tests/support/stack_flights.py (a statue on its plinth, columns of two, three and five drums), friction
mu on the floor and mu^2 between the boxes in both engines (PyBullet combines the two bodies' friction as their
product), so that at mu 0.6 a joint slips where the ground's acceleration passes 0.36 g; rockscreen judges each stack
as ``screen`` does (tests/support/stack_flights.screen_verdicts: the rest certificate, the two-block model for two
bodies, the n-block model, and where a joint slips the level slip model, the slide-rock model or the stack's contact
model). For each scene
the lowest box that has fallen at the first fall (none, or the box), whether any box falls (the stack's verdict under
``screen``'s default rule), which boxes have fallen by the end (each body's verdict; PyBullet's run followed to its
end, :func:`rigid_body_peer.bullet_stack_fallen`), rockscreen's largest slip at a joint; each disagreement on the
first fall re-run by PyBullet at half its step and at 0.98 and 1.02 of the record (robust: the engine's verdict holds
in all three) and by rockscreen at 0.98 and 1.02; where the engine overturns a box robustly and rockscreen has every
box stand, rockscreen's probability and class for that box under the default draws. Prints the counts, the agreement
and each engine's time per scene (PyBullet's to the first fall), and rockscreen's time over the 3D box model's on the
box of the stack's outline with a square base and the floor's friction (the single body a 3D scene of the stack is
measured against; ``--cost-only``: that alone, without PyBullet; ``--profile``: where rockscreen's time goes, by
cProfile around its runs alone).

Run: ``python benchmarks/stack_slip_peer.py [--mu 0.6] [--pga 0.5] [--records 21] [--families statue,two,three,five]
[--cost-only] [--profile]`` (PyBullet is a test extra).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import cProfile
import pstats
import statistics
import sys
import time
from functools import partial
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))

from rigid_body_peer import NONE_FALLS, bullet_first_fall, bullet_stack_fallen, perturbed_verdicts, short_records  # noqa: E402
from stack_flights import RHO, STACKS, difference, drawn_class, first_fall, screen_verdicts  # noqa: E402

from pipeline.constants import G  # noqa: E402
from pipeline.rocking.codes import Verdict  # noqa: E402
from pipeline.rocking.solids.box3d import Box, simulate_box  # noqa: E402

#: a joint has slipped where rockscreen's largest slip there passes this [m]
SLIPPED_M = 1e-3


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mu", type=float, default=0.6, help="friction of each box in PyBullet's sense [-]")
    ap.add_argument("--pga", type=float, default=0.5, help="each record scaled to this PGA [g]")
    ap.add_argument("--records", type=int, default=21, help="the first N bundled records of at most 60 s")
    ap.add_argument("--families", default=",".join(STACKS))
    ap.add_argument("--cost-only", action="store_true", help="time rockscreen and the 3D box only (no PyBullet)")
    ap.add_argument("--profile", action="store_true", help="profile rockscreen's runs of each family")
    args = ap.parse_args()
    records = short_records(ROOT / "records")[:args.records]
    for family in args.families.split(","):
        boxes = STACKS[family]
        agree, any_agree, bodies_agree, slipped, differ, ours_s, engine_s = 0, 0, 0, 0, [], [], []
        width, height = max(w for w, _ in boxes), sum(h for _, h in boxes)
        outline, box_s = Box(width / 2, width / 2, height / 2, mu=args.mu), []
        for rec in records[:2]:     # compiled, and loaded: the models a slipping scene calls (the level slip's too)
            screen_verdicts(family, rec.horizontal_ms2[0] * args.pga * G / abs(rec.horizontal_ms2[0]).max(),
                            rec.dt_s, mu=args.mu)
        simulate_box(records[0].horizontal_ms2[0][:8], records[0].horizontal_ms2[0][:8] * 0, None, 0.01, outline)
        profile = cProfile.Profile() if args.profile else None
        for rec in records:
            scale = args.pga * G / abs(rec.horizontal_ms2[0]).max()
            a = rec.horizontal_ms2[0] * scale
            t0 = time.perf_counter()
            if profile:
                profile.enable()
            judged = screen_verdicts(family, a, rec.dt_s, mu=args.mu)
            if profile:
                profile.disable()
            ours_s.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            simulate_box(a, a * 0.0, None, rec.dt_s, outline)
            box_s.append(time.perf_counter() - t0)
            assert all(v != Verdict.no_verdict for v in judged.verdicts), (rec.record_id, judged)
            if args.cost_only:
                continue
            slipped += bool(judged.slide_m) and max(judged.slide_m) > SLIPPED_M
            ours = first_fall(judged)
            judge = partial(bullet_first_fall, a, rec.dt_s, boxes, mu=args.mu, density=RHO)
            t0 = time.perf_counter()
            engine = judge()
            engine_s.append(time.perf_counter() - t0)
            any_agree += (ours == NONE_FALLS) == (engine == NONE_FALLS)
            ours_fallen = tuple(v == Verdict.overturns for v in judged.verdicts)
            engine_fallen = bullet_stack_fallen(a, rec.dt_s, boxes, mu=args.mu, density=RHO)
            bodies_agree += ours_fallen == engine_fallen
            print(f"   {family} {rec.record_id}: fallen by the end, rockscreen {_fallen(ours_fallen)}, PyBullet "
                  f"{_fallen(engine_fallen)}{'' if ours_fallen == engine_fallen else ' (differ)'}", flush=True)
            if ours == engine:
                agree += 1
                continue
            robust = perturbed_verdicts(judge) == {engine}
            ours_robust = {first_fall(screen_verdicts(family, s * a, rec.dt_s, mu=args.mu))
                           for s in (0.98, 1.02)} == {ours}
            drawn = (drawn_class(family, engine, a[None, :], None, 0.0, rec.dt_s, 0.0, args.mu)
                     if robust and engine != NONE_FALLS and ours == NONE_FALLS else None)
            differ.append(difference(rec.record_id, ours, ours_robust, engine, robust, drawn))
            print("  ", family, differ[-1], flush=True)
        n = len(ours_s)
        ratios = [o / b for o, b in zip(ours_s, box_s)]
        print(f"{family}: a scene, rockscreen / the 3D box of its outline: median {statistics.median(ratios):.2f}, "
              f"worst {max(ratios):.1f} (rockscreen median {1e3 * statistics.median(ours_s):.1f} ms, the box "
              f"{1e3 * statistics.median(box_s):.1f} ms)", flush=True)
        if profile:
            pstats.Stats(profile).sort_stats("tottime").print_stats(6)
        if args.cost_only:
            continue
        print(f"{family} at mu {args.mu:g}, {args.pga:g} g: {agree} of {n} agree on the first fall, {any_agree} of {n} "
              f"on whether any box falls, {bodies_agree} of {n} on every box's verdict; a joint slipped more than "
              f"{1e3 * SLIPPED_M:g} mm in {slipped} (rockscreen); rockscreen {1e3 * statistics.median(ours_s):.1f} ms "
              f"a scene (median; worst {1e3 * max(ours_s):.0f} ms), PyBullet {statistics.median(engine_s):.2f} s",
              flush=True)
        for line in differ:
            print("    ", line)


def _fallen(fallen: tuple) -> str:
    """The boxes fallen, bottom first (0 the bottom), or 'none'."""
    return ", ".join(str(k) for k, f in enumerate(fallen) if f) or "none"


if __name__ == "__main__":
    main()
