"""A box rolling from corner to corner: a ground moving in a circle, by the box's exact model, the contact model and
PyBullet.

Three seconds of a circular ground motion (a_x = a sin(2 pi f t), a_y = a cos(2 pi f t)), then nine still, under a
box of 0.6 x 0.6 x 2.1 m and one of 0.6 x 1.2 x 2.1 m with friction 2 (no corner slips): each scene by the box's
exact model (:func:`pipeline.rocking.solids.box3d.simulate_box`, Housner's restitution as the contact model's plastic
contacts give), by the contact model alone (:func:`pipeline.rocking.solids.contact3d.simulate_contact3d`), and by
PyBullet (``tests/support/rigid_body_peer.py``, both senses of the circle) and MuJoCo
(``contact3d_second_engine.py``: both senses, its step and half of it) where they are installed. Prints each
model's verdict and peak tilt [rad], the exact model's flag (0: it followed the whole record itself) and its
impacts, and the contact model's twist.

The ground's demand turns with it, so a box that lifts leans in a direction that turns too: it rolls from corner to
corner, which the exact model follows by turning the box on a landing corner alone where the old pivot then rises.

``--records`` then runs the bundled records' two-component scenes of the four boxes of
``tests/rocking/solids/test_box_peer.py`` at friction 2 and compares, on the scenes the exact model follows to the
end itself, its verdicts and peaks with the contact model's alone.

    python benchmarks/box_circular.py [--records]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import math
import sys
from pathlib import Path

import numpy as np

from pipeline.config import Config
from pipeline.constants import G
from pipeline.records.loader import iter_records
from pipeline.rocking.solids.box3d import FLAG_NONE, Box, simulate_box
from pipeline.rocking.solids.contact3d import simulate_contact3d

DT_S = 0.01
#: (half width, half depth, half height) [m]
BOXES = ((0.3, 0.3, 1.05), (0.3, 0.6, 1.05))
#: (amplitude [g], frequency [Hz])
GROUNDS = ((0.3, 1.0), (0.4, 1.0), (0.4, 2.0), (0.5, 2.0), (0.6, 2.0))
MU = 2.0
#: The boxes of the PyBullet comparison on real records (full width, depth, height [m])
RECORD_BOXES = ((0.5, 0.5, 1.5), (0.4, 0.4, 1.8), (0.3, 0.3, 1.8), (0.6, 1.2, 2.0))


def circle(amplitude_g: float, frequency_hz: float, sense: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Three seconds of the circular ground, then nine still [m s-2]."""
    t = np.arange(0.0, 12.0, DT_S)
    on = amplitude_g * G * (t < 3.0)
    return on * np.sin(2.0 * math.pi * frequency_hz * t), sense * on * np.cos(2.0 * math.pi * frequency_hz * t)


def _peer():
    """PyBullet's box judge, or None where it is not installed."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "support"))
    try:
        from rigid_body_peer import bullet_box_overturns, pybullet
        pybullet()
    except Exception:  # noqa: BLE001 - an optional peer: its absence is said below
        return None
    return bullet_box_overturns


def _second():
    """MuJoCo's box verdict (``benchmarks/contact3d_second_engine.py``), or None where it is not installed."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    try:
        import mujoco  # noqa: F401
        from contact3d_second_engine import mujoco_overturns
    except Exception:  # noqa: BLE001 - an optional peer: its absence is said below
        return None
    return mujoco_overturns


def main() -> None:
    peer, second = _peer(), _second()
    if peer is None:
        print("PyBullet is not installed: its column is left out (pip install pybullet)")
    if second is None:
        print("MuJoCo is not installed: its column is left out (pip install mujoco)")
    for b, d, h in BOXES:
        box = Box(b, d, h, mu=MU, restitution_ratio=1.0)
        for amplitude_g, frequency_hz in GROUNDS:
            ax, ay = circle(amplitude_g, frequency_hz)
            exact = simulate_box(ax, ay, None, DT_S, box)
            alone = simulate_contact3d(ax, ay, None, DT_S, box.convex())
            line = (f"{2 * b:.1f} x {2 * d:.1f} x {2 * h:.1f} m, {amplitude_g:.1f} g {frequency_hz:.0f} Hz: "
                    f"exact {exact.overturned!s:5} {exact.theta_max_rad:6.3f} (flag {exact.flag}, "
                    f"{exact.impacts} impacts)  contact {alone.overturned!s:5} {alone.tilt_max_rad:6.3f} "
                    f"(twist {math.degrees(alone.twist_max_rad):5.1f} deg)")
            if peer is not None:
                both = [peer(*circle(amplitude_g, frequency_hz, sense), None, DT_S, width_m=2 * b, depth_m=2 * d,
                             height_m=2 * h, mu=MU) for sense in (1.0, -1.0)]
                line += "  PyBullet " + ", ".join(f"{v!s:5} {tilt:6.3f}" for v, tilt in both)
            if second is not None:
                over = [second("box", 2 * b, 2 * d, 2 * h, MU, *circle(amplitude_g, frequency_hz, sense), None, DT_S,
                               **step) for sense in (1.0, -1.0) for step in ({}, {"step_s": 5e-5})]
                line += "  MuJoCo overturns (each sense, its step and half) " + "/".join(str(int(v)) for v in over)
            print(line, flush=True)


def on_records() -> None:
    """The bundled records: the exact model's own scenes against the contact model alone."""
    followed, agree, apart = 0, 0, []
    for rec in iter_records(Path(__file__).resolve().parents[1] / "records", config=Config()):
        if rec.single_component:
            continue
        h1, h2 = rec.horizontal_ms2
        for w, d, h in RECORD_BOXES:
            box = Box(w / 2, d / 2, h / 2, mu=MU, restitution_ratio=1.0)
            exact = simulate_box(h1, h2, rec.vertical_ms2, rec.dt_s, box)
            if exact.flag != FLAG_NONE or exact.held != FLAG_NONE:
                continue
            alone = simulate_contact3d(h1, h2, rec.vertical_ms2, rec.dt_s, box.convex())
            alpha = math.atan2(w, h)
            followed, agree = followed + 1, agree + (exact.overturned == alone.overturned)
            peaks = (exact.theta_max_rad / alpha, alone.tilt_max_rad / alpha)
            if not exact.overturned and max(peaks) > 0.05 and max(peaks) > 1.5 * max(min(peaks), 1e-9):
                apart.append(f"{rec.record_id} {w} x {d} x {h} m: exact {peaks[0]:.3f}, contact {peaks[1]:.3f} alpha")
    print(f"records: {followed} scenes the exact model follows to the end; verdicts as the contact model's alone in "
          f"{agree}; standing peaks above 0.05 alpha that differ by more than 1.5x: {len(apart)}")
    for line in apart:
        print("  " + line)


if __name__ == "__main__":
    main()
    if "--records" in sys.argv[1:]:
        on_records()
