"""The 3D box against an independent rigid-body engine (PyBullet, tests only) on the bundled records with two
horizontal components and the vertical, per family (square bases of h/w 3, 4.5 and 6; a cabinet twice as deep as
wide): no scene where the engine overturns robustly (its verdict unchanged with its step halved and the record
scaled by 0.98 and by 1.02) while the 3D box stands robustly (unflagged, and standing with the record x0.98 and
x1.02 too), and at least 90 % agreement per family among the scenes where the 3D box has a verdict and the
engine's verdict holds under that check. Slow."""

from __future__ import annotations

import os

import pytest
from rigid_body_peer import STEP_S, bullet_box_overturns

from pipeline.config import Config
from pipeline.records.loader import iter_records
from pipeline.rocking.solids.box3d import FLAG_NONE, Box, simulate_box

#: Every how many of the bundled two-component records the test takes (1: all 22)
EVERY = int(os.environ.get("ROCKSCREEN_PEER_EVERY", "2"))
MU = 0.7
#: (family, width [m], depth [m], height [m])
BOXES = (("square", 0.5, 0.5, 1.5), ("square", 0.4, 0.4, 1.8), ("square", 0.3, 0.3, 1.8),
         ("cabinet", 0.6, 1.2, 2.0))


def _engine(rec, w, d, h, **kw):
    h1, h2 = rec.horizontal_ms2
    return bullet_box_overturns(h1, h2, rec.vertical_ms2, rec.dt_s, width_m=w, depth_m=d, height_m=h, mu=MU,
                                **kw)[0]


def _ours(rec, w, d, h, scale=1.0):
    h1, h2 = rec.horizontal_ms2
    v = None if rec.vertical_ms2 is None else scale * rec.vertical_ms2
    out = simulate_box(scale * h1, scale * h2, v, rec.dt_s, Box(w / 2, d / 2, h / 2, mu=MU))
    return -1 if out.flag != FLAG_NONE else int(out.overturned)


@pytest.mark.slow
def test_the_engine_never_overturns_robustly_what_the_3d_box_says_stands(records_dir):
    rows = []
    two = [rec for rec in iter_records(records_dir, config=Config()) if not rec.single_component]
    for rec in two[::EVERY]:
        for family, w, d, h in BOXES:
            ours = _ours(rec, w, d, h)
            engine = _engine(rec, w, d, h)
            robust, ours_robust = None, None
            if ours != -1 and (ours == 1) != engine:                 # a disagreement: is the engine's robust?
                checks = [_engine(rec, w, d, h, step_s=STEP_S / 2), _engine(rec, w, d, h, scale=0.98),
                          _engine(rec, w, d, h, scale=1.02)]
                robust = all(x == engine for x in checks)
                # ... and ours (the record x0.98 and x1.02, as rockscreen's robust class asks its verdict to hold)
                ours_robust = all(_ours(rec, w, d, h, scale) == ours for scale in (0.98, 1.02))
            rows.append((rec.record_id, family, w, d, h, ours, engine, robust, ours_robust))
    for row in rows:
        print(row)
    missed = [r for r in rows if r[6] and r[5] == 0 and r[7] and r[8]]
    assert not missed, f"the engine overturns robustly where the 3D box stands robustly: {missed}"
    for family in ("square", "cabinet"):
        decided = [r for r in rows if r[1] == family and r[5] != -1 and r[7] is not False]
        agree = [r for r in decided if (r[5] == 1) == r[6]]
        print(f"{family}: {len(rows)} scenes, {len(decided)} decided and robust, agree {len(agree)}")
        assert len(agree) >= 0.9 * len(decided)
