"""A second rigid-body engine, MuJoCo, on the scenes where the 3D contact model and PyBullet disagree
(``benchmarks/contact3d_peer.py``): which contact treatment is at fault. Each scene is run four times, as the peer
benchmark re-runs PyBullet: MuJoCo's step, the step halved, and the record x0.98 and x1.02 (robust: the verdict
holds in all four).

The body is a MuJoCo free body (a box, or a cylinder primitive) on a plane, both with friction mu (elliptic cones,
condim 3, stiff soft contacts); the ground's motion enters as MuJoCo's gravity set at each step to
(-a_x, -a_y, -(g + a_z)), the record linear between samples: the same moving-ground frame as the contact model.
Overturned: the axis within 0.01 rad of horizontal. MuJoCo is a test extra, never in the verdict path.

Run: ``python benchmarks/contact3d_second_engine.py [family:body:record ...]`` (default: the disagreements listed
in docs/validation.md; ``pip install mujoco``).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from contact3d_peer import FAMILIES, _frame  # noqa: E402
from rigid_body_peer import ground_at  # noqa: E402

from pipeline.config import Config  # noqa: E402
from pipeline.constants import G  # noqa: E402
from pipeline.records.loader import iter_records  # noqa: E402
from pipeline.rocking.solids.contact3d import simulate_contact3d  # noqa: E402
from pipeline.rocking.solids.convex_body import box_body, cylinder_body  # noqa: E402

#: family, index of the body in the family, record id: the peer benchmark's disagreements
DISAGREEMENTS = [("statues", 1, "RSN181_IMPVALL.H_H-E06"), ("cabinets", 0, "RSN181_IMPVALL.H_H-E06"),
                 ("cylinders", 0, "CICLC"), ("cylinders", 0, "RSN1176_KOCAELI_YPT"),
                 ("cylinders", 1, "RSN181_IMPVALL.H_H-E06")]
STEP_S = 1e-4
TAIL_S = 5.0
LYING_SLACK_RAD = 1e-2


def mujoco_body(kind, w, d, h, mu, *, step_s=STEP_S):
    """MuJoCo's model and data of the body (a box w x d x h, or a cylinder w across and h high) standing on a plane,
    both with friction mu (elliptic cones, condim 3, stiff soft contacts), stepped at ``step_s``."""
    import mujoco

    size = f"{w / 2} {h / 2}" if kind == "cylinder" else f"{w / 2} {d / 2} {h / 2}"
    xml = f"""<mujoco><option timestep="{step_s}" cone="elliptic" integrator="implicitfast"/>
      <default><geom condim="3" solref="{max(5 * step_s, 5e-4)} 1" solimp="0.99 0.999 0.0001"/></default>
      <worldbody><geom type="plane" size="100 100 0.1" friction="{mu} 0 0"/>
      <body pos="0 0 {h / 2}"><freejoint/><geom type="{kind}" size="{size}" friction="{mu} 0 0"/></body>
      </worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def mujoco_overturns(kind, w, d, h, mu, ax, ay, az, dt, *, step_s=STEP_S, scale=1.0) -> bool:
    """Whether MuJoCo's body overturns under the record (body frame: x along the width) times ``scale``."""
    import mujoco

    model, data = mujoco_body(kind, w, d, h, mu, step_s=step_s)
    n = len(ax)
    while data.time < (n - 1) * dt + TAIL_S:
        g = [scale * a for a in ground_at((ax, ay, az), data.time, dt)]
        model.opt.gravity[:] = (-g[0], -g[1], -(G + g[2]))
        mujoco.mj_step(model, data)
        if math.acos(max(-1.0, min(1.0, data.xmat[1][8]))) >= 0.5 * math.pi - LYING_SLACK_RAD:
            return True
    return False


def require_mujoco(*, otherwise: str = "") -> None:
    """Stop with the fix where MuJoCo (a test extra) is not installed; ``otherwise`` the way to run without it."""
    try:
        import mujoco  # noqa: F401
    except ImportError:
        sys.exit("MuJoCo is not installed (a test extra): pip install mujoco" + (f", or {otherwise}" if otherwise
                                                                                  else ""))


def main() -> None:
    require_mujoco()
    import mujoco
    cases = ([(a, int(b), c) for a, b, c in (x.split(":") for x in sys.argv[1:])] if sys.argv[1:]
             else DISAGREEMENTS)
    records = {r.record_id: r for r in iter_records(ROOT / "records", config=Config())
               if not r.single_component and r.azimuth_known}
    print(f"MuJoCo {mujoco.__version__}; each scene: step {STEP_S} s, halved, record x0.98, x1.02")
    for family, index, record_id in cases:
        kind, w, d, h, mu, az = FAMILIES[family][index]
        rec = records[record_id]
        bx, by = _frame(rec, az)
        runs = [mujoco_overturns(kind, w, d, h, mu, bx, by, rec.vertical_ms2, rec.dt_s, step_s=s, scale=k)
                for s, k in ((STEP_S, 1.0), (STEP_S / 2, 1.0), (STEP_S, 0.98), (STEP_S, 1.02))]
        body = cylinder_body(w, h, mu=mu) if kind == "cylinder" else box_body(w, d, h, mu=mu)
        ours = simulate_contact3d(bx, by, rec.vertical_ms2, rec.dt_s, body).overturned
        verdict = "overturns" if runs[0] else "stands"
        print(f"{family} {w}x{d}x{h} mu {mu} x {record_id}: MuJoCo {verdict} "
              f"({'robust' if len(set(runs)) == 1 else 'not robust'}: {runs}); contact model "
              f"{'overturns' if ours else 'stands'}", flush=True)


if __name__ == "__main__":
    main()
