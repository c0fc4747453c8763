"""The hand-back to the exact models (pipeline.rocking.solids.alternate: a box on an edge, a cylinder on its rim)
against the contact model alone, on every draw and margin run of the bundled default that the contact model decides.

Runs ``screen`` on the bundled records in one process. Each scene the hand-back decides is run again by the contact
model alone from the same start, at its step and at half its step, its long steps halved with it (the contact
model's own resolution: how often its verdict turns with the step); a cylinder also on a rim of FINE_RIM_POINTS
points at half the step (the contact model's cylinder is a polygon of 32, the exact model's a circle). Prints, for
the boxes and for the cylinders, the runs, the verdicts that agree pairwise, and the time of each side.

    python benchmarks/contact3d_handback.py [--records records] [--blocks configs/blocks.csv]

About 2.5 minutes on 2 cores (one process).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import math
import tempfile
import time
from collections import defaultdict
from typing import Any

import pipeline.rocking.solids.contact3d as contact3d
from pipeline import cli
from pipeline.rocking.solids import box_scene, cylinder_scene, long_steps
from pipeline.rocking.solids.alternate import ExactModel
from pipeline.rocking.solids.convex_body import ConvexBody, cylinder_body

#: The families whose scenes are handed back, by the module that calls the alternation.
FAMILIES: dict[str, Any] = {"box": box_scene, "cylinder": cylinder_scene}
#: The points on each rim of the finer cylinder the cylinders' verdicts are also compared with.
FINE_RIM_POINTS = 128


def finer(body: ConvexBody) -> ConvexBody:
    """The contact model's cylinder of ``body`` (points on its two rims) with FINE_RIM_POINTS points a rim."""
    radius, half_height = math.hypot(*body.vertices[0, :2]), float(abs(body.vertices[0, 2]))
    return cylinder_body(2.0 * radius, 2.0 * half_height, mu=body.mu, rim_points=FINE_RIM_POINTS)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", default="records")
    ap.add_argument("--blocks", default="configs/blocks.csv")
    args = ap.parse_args()
    rows: dict[str, list[tuple[bool, bool, bool, bool, float, float, bool, bool]]] = defaultdict(list)
    plain = contact3d.simulate_contact3d
    original = {name: module.alternate for name, module in FAMILIES.items()}

    def alone(ax, ay, az, dt_s, body: ConvexBody, azimuth_deg, start, g_ms2, step_s):
        """The contact model alone with its steps scaled to ``step_s`` [s], its long steps with them."""
        kept = contact3d.MAX_STEP_S, long_steps.LONG_STEP_S
        contact3d.MAX_STEP_S, long_steps.LONG_STEP_S = step_s, kept[1] * step_s / kept[0]
        try:
            return plain(ax, ay, az, dt_s, body, yaw_deg=azimuth_deg, g_ms2=g_ms2, start=start)
        finally:
            contact3d.MAX_STEP_S, long_steps.LONG_STEP_S = kept

    def both(name: str):
        def run(ax, ay, az, dt_s, model: ExactModel, azimuth_deg, start, *, g_ms2):
            t0 = time.perf_counter()
            handed = original[name](ax, ay, az, dt_s, model, azimuth_deg, start, g_ms2=g_ms2)
            t1 = time.perf_counter()
            step = contact3d.MAX_STEP_S
            at_h = alone(ax, ay, az, dt_s, model.body, azimuth_deg, start, g_ms2, step)
            t2 = time.perf_counter()
            at_half = alone(ax, ay, az, dt_s, model.body, azimuth_deg, start, g_ms2, step / 2.0)
            fine = at_half if name == "box" else alone(ax, ay, az, dt_s, finer(model.body), azimuth_deg, start,
                                                       g_ms2, step / 2.0)
            rows[name].append((handed.overturned, at_h.overturned, at_half.overturned, fine.overturned, t1 - t0,
                               t2 - t1, bool(handed.flags & contact3d.FLAG_TAIL_CAP),
                               bool(at_h.flags & contact3d.FLAG_TAIL_CAP)))
            return handed
        return run

    for name, module in FAMILIES.items():
        module.alternate = both(name)
    try:
        with tempfile.TemporaryDirectory() as out:
            try:
                cli.main(["--records", args.records, "--blocks", args.blocks, "--out", out, "--tolerate-failures",
                          "-n", "1", "--quiet"])
            except SystemExit:
                pass
    finally:
        for name, module in FAMILIES.items():
            module.alternate = original[name]
    for name, family_rows in rows.items():
        _report(name, family_rows)


def _report(name: str, rows: list[tuple[bool, bool, bool, bool, float, float, bool, bool]]) -> None:
    """Print one family's agreement and time."""
    n = len(rows)

    def agree(i: int, j: int) -> int:
        return sum(r[i] == r[j] for r in rows)

    t_hand, t_alone = sum(r[4] for r in rows), sum(r[5] for r in rows)
    print(f"{name} runs decided with the hand-back: {n}")
    print(f"  verdicts agree: hand-back and the contact model alone {agree(0, 1)} ({agree(0, 1) / n:.1%}); "
          f"the contact model alone at its step and at half of it {agree(1, 2)} ({agree(1, 2) / n:.1%}); "
          f"hand-back and the contact model at half its step {agree(0, 2)} ({agree(0, 2) / n:.1%})")
    if name != "box":
        print(f"  against {FINE_RIM_POINTS} points a rim at half the step: the hand-back {agree(0, 3)} "
              f"({agree(0, 3) / n:.1%}), the contact model alone {agree(1, 3)} ({agree(1, 3) / n:.1%})")
    print(f"  time: hand-back {t_hand:.2f} s, contact model alone {t_alone:.2f} s (ratio {t_alone / t_hand:.2f}); "
          f"runs at the tail's cap: hand-back {sum(r[6] for r in rows)}, contact model alone {sum(r[7] for r in rows)}")


if __name__ == "__main__":
    main()
