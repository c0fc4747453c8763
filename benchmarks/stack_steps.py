"""What the stacks' slipping joints cost and how their verdicts hold: the verdicts of stacks whose joints slip as
shipped (a stack rocking as one while one joint slips followed by the slide-rock model,
:mod:`pipeline.assemblies.slide_rock`; the contact model's every step 0.25 ms), by the contact model alone (the
slide-rock model off), and with the contact model's long steps (``long_step_s`` of
:func:`pipeline.assemblies.stack_contact.simulate_stack_contact`, off by default), against the contact model alone
with every step a quarter as long (the reference); and what each costs.

The scenes are those of ``stack_slip_peer.py``: the four stacks of deep boxes of tests/support/stack_flights.py (a
statue on its plinth, columns of two, three and five drums), friction mu on the floor and mu^2 between the boxes, on
the bundled records of at most 60 s, each first horizontal scaled to a PGA, at each ``--mu``; rockscreen judges each
stack as ``screen`` does (``stack_flights.screen_verdicts``), the contact model's steps set where the n-block
verdicts call it (:mod:`pipeline.assemblies.n_block_verdicts`). For each way: the scenes whose body
verdicts differ from the reference's, and for each of those whether the shipped steps' verdict holds at 0.98 and
1.02 of the record (robust); the contact model's steps; and per stack, the median time of a scene over the 3D box
model's on the box of the stack's outline with a square base and the floor's friction (the single body a 3D scene of
the stack is measured against), in one process.

Run: ``python benchmarks/stack_steps.py [--mu 0.5,0.6] [--pga 0.5] [--records 21] [--long-step 5e-4,1e-3,1.25e-3]``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import statistics
import sys
import time
from functools import partial
from pathlib import Path
from unittest import mock

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "support"))

from rigid_body_peer import short_records  # noqa: E402
from stack_flights import STACKS, screen_verdicts  # noqa: E402

from pipeline.assemblies import n_block_verdicts, stack_scene  # noqa: E402
from pipeline.assemblies.stack_contact import MAX_STEP_S, simulate_stack_contact  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.rocking.solids.box3d import Box, simulate_box  # noqa: E402

#: The reference's step, as a fraction of the shipped one [-].
REFERENCE_FRACTION = 0.25
#: The record's scales at which a differing scene's verdict is judged again with the shipped steps [-].
SCALES = (0.98, 1.02)


class Stepping:
    """The contact model's steps for a run: the longest step and the long step [s] (0: none); whether the slide-rock
    model follows a stack rocking as one with one joint slipping (``rocking``)."""

    def __init__(self, label: str, step_s: float, long_step_s: float, rocking: bool = True) -> None:
        self.label, self.step_s, self.long_step_s, self.rocking = label, step_s, long_step_s, rocking
        self.steps = 0

    def __call__(self, *args, **kwargs):
        out = simulate_stack_contact(*args, step_s=self.step_s, long_step_s=self.long_step_s, **kwargs)
        self.steps += out.steps
        return out


def _judged(family: str, a, dt_s: float, mu: float, stepping: Stepping) -> tuple[int, ...]:
    with mock.patch.object(n_block_verdicts, "simulate_stack_contact", stepping), mock.patch.object(
            stack_scene, "judge_n_block", partial(n_block_verdicts.judge_n_block, slide_rock=stepping.rocking)):
        return tuple(int(v) for v in screen_verdicts(family, a, dt_s, mu=mu).verdicts)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mu", default="0.5,0.6", help="friction of each box in PyBullet's sense, comma-separated [-]")
    ap.add_argument("--pga", type=float, default=0.5, help="each record scaled to this PGA [g]")
    ap.add_argument("--records", type=int, default=21, help="the first N bundled records of at most 60 s")
    ap.add_argument("--long-step", default="5e-4,1e-3,1.25e-3", help="long steps to try, comma-separated [s]")
    args = ap.parse_args()
    records = short_records(ROOT / "records")[:args.records]
    ways = [Stepping("shipped: the slide-rock model, every contact step short", MAX_STEP_S, 0.0),
            Stepping("the contact model alone, every step short", MAX_STEP_S, 0.0, rocking=False)]
    ways += [Stepping(f"long contact steps of {float(x) * 1e3:g} ms", MAX_STEP_S, float(x))
             for x in args.long_step.split(",") if x]
    reference = Stepping(f"the contact model alone, every step {MAX_STEP_S * REFERENCE_FRACTION * 1e3:g} ms "
                         "(reference)", MAX_STEP_S * REFERENCE_FRACTION, 0.0, rocking=False)
    scenes = [(float(mu), family, rec) for mu in args.mu.split(",") for family in STACKS for rec in records]
    print(f"{len(scenes)} scenes: {len(STACKS)} stacks x {len(args.mu.split(','))} frictions x {len(records)} records "
          f"at {args.pga} g")
    for mu, family in {(mu, family) for mu, family, _ in scenes}:      # compiled and loaded before timing
        rec = records[0]
        for way in (*ways, reference):
            _judged(family, rec.horizontal_ms2[0] * args.pga * G / abs(rec.horizontal_ms2[0]).max(), rec.dt_s, mu,
                    way)
    simulate_box(records[0].horizontal_ms2[0][:8], records[0].horizontal_ms2[0][:8] * 0, None, 0.01,
                 Box(0.5, 0.5, 1.0, mu=0.5))
    verdicts: dict = {}
    seconds: dict = {}
    box_s: dict = {}
    for way in (*ways, reference):
        way.steps = 0
    for mu, family, rec in scenes:
        a = rec.horizontal_ms2[0] * (args.pga * G / abs(rec.horizontal_ms2[0]).max())
        for way in (*ways, reference):
            t0 = time.perf_counter()
            verdicts[way.label, mu, family, rec.record_id] = _judged(family, a, rec.dt_s, mu, way)
            seconds.setdefault((way.label, mu, family), []).append(time.perf_counter() - t0)
        boxes = STACKS[family]
        width, height = max(w for w, _ in boxes), sum(h for _, h in boxes)
        t0 = time.perf_counter()
        simulate_box(a, a * 0.0, None, rec.dt_s, Box(width / 2, width / 2, height / 2, mu=mu))
        box_s.setdefault((mu, family), []).append(time.perf_counter() - t0)
    shipped = ways[0]
    for way in (*ways, reference):
        time_s = sum(sum(v) for k, v in seconds.items() if k[0] == way.label)
        print(f"\n{way.label}: {way.steps:,} contact steps, {time_s:.2f} s for the {len(scenes)} scenes")
        for mu, family in sorted({(mu, family) for mu, family, _ in scenes}):
            ratio = statistics.median(seconds[way.label, mu, family]) / statistics.median(box_s[mu, family])
            print(f"  mu {mu} {family}: a scene {ratio:.2f}x the 3D box of its outline (medians)")
        if way is reference:
            continue
        differ = [(mu, family, rec) for mu, family, rec in scenes
                  if verdicts[way.label, mu, family, rec.record_id] != verdicts[reference.label, mu, family,
                                                                                  rec.record_id]]
        print(f"  verdicts differing from the reference: {len(differ)} of {len(scenes)}")
        for mu, family, rec in differ:
            again = [_judged(family, rec.horizontal_ms2[0] * (f * args.pga * G / abs(rec.horizontal_ms2[0]).max()),
                             rec.dt_s, mu, Stepping("", MAX_STEP_S, 0.0)) for f in SCALES]
            ours, ref = verdicts[way.label, mu, family, rec.record_id], verdicts[reference.label, mu, family,
                                                                                 rec.record_id]
            own = verdicts[shipped.label, mu, family, rec.record_id]
            held = ("holds at " + " and ".join(f"{f:g}" for f in SCALES) if all(v == own for v in again)
                    else "turns at " + " or ".join(f"{f:g}" for f in SCALES))
            print(f"    mu {mu} {family} {rec.record_id}: {ours} against the reference's {ref}; the shipped steps' "
                  f"{own} {held} of the record")

if __name__ == "__main__":
    main()
