"""A body given by its scan judged in 3D through the body model (``[simulation] scanned_model = "contact3d"``,
pipeline.bodies.scanned3d): the record's frame and the body's yaw against a box by its corners pushed along its
width (two horizontals, one of known azimuth), the worst yaw of an unknown orientation against every yaw run by hand,
a pulse along the body's weakest direction, and (slow) a whole screening whose every scene has a verdict."""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest
import trimesh

from pipeline.bodies.contract import OnRecord, Setup
from pipeline.bodies.convex3d import frame, judge
from pipeline.bodies.scanned3d import SCANNED_3D, YAW_STEP_DEG, body_of
from pipeline.constants import G
from pipeline.records.record import Record
from pipeline.rocking.block import BlockShape, ShapeKind
from pipeline.rocking.settings import ScannedModel, SimulationConfig
from pipeline.rocking.solids.contact3d import simulate_contact3d
from pipeline.rocking.solids.convex_body import box_body
from pipeline.shapes.scan import read_scan
from pipeline.uncertainty.settings import UncertaintyConfig

DT = 0.005
T = np.arange(0.0, 4.0, DT)
A0_DEG = 20.0           # the record's first horizontal, compass
PUSH_DEG = 75.0         # the pulse's compass direction


@pytest.fixture(scope="module")
def box_scan(tmp_path_factory):
    """A 0.4 x 0.6 x 1.6 m box (width along its settled x) given as a mesh."""
    pts = np.array([[x, y, z] for x in (-0.2, 0.2) for y in (-0.3, 0.3) for z in (0.0, 1.6)])
    path = tmp_path_factory.mktemp("box3d") / "box.obj"
    trimesh.convex.convex_hull(pts).export(path)
    return read_scan(path)


def _shape(scan, azimuth_deg):
    return BlockShape(height_m=1.6, width_m=0.4, mu=0.6, azimuth_deg=azimuth_deg, kind=ShapeKind.scanned, scan=scan)


def _record(pulse_ms2, *, single=False):
    c, s = math.cos(math.radians(PUSH_DEG - A0_DEG)), math.sin(math.radians(PUSH_DEG - A0_DEG))
    if single:                                   # one horizontal, along the pulse
        return Record(record_id="one", dt_s=DT, horizontal_ms2=pulse_ms2[None, :], azimuths_deg=(PUSH_DEG,),
                      azimuth_known=True, vertical_ms2=None, files=(), formats=("TEST",), component_codes=("X",),
                      processing_level="corrected")
    return Record(record_id="two", dt_s=DT, horizontal_ms2=np.vstack([c * pulse_ms2, s * pulse_ms2]),
                  azimuths_deg=(A0_DEG, A0_DEG + 90.0), azimuth_known=True, vertical_ms2=None, files=(),
                  formats=("TEST",), component_codes=("X", "Y"), processing_level="corrected")


def _pulse(amp_g, period_s):
    return np.where(T < period_s, amp_g * G * np.sin(2 * np.pi * T / period_s), 0.0)


def _on(rec):
    setup = Setup(SimulationConfig(scanned_model=ScannedModel.contact3d), UncertaintyConfig(), G, False, 0.0)
    return OnRecord(rec, None, None, None, np.zeros(1), setup)      # nominal only: no planes, no draws


@pytest.mark.parametrize("single", [False, True])
@pytest.mark.parametrize("amp_g, period_s", [(0.4, 0.6), (0.55, 0.5)])
def test_a_box_mesh_pushed_along_its_given_azimuth_moves_as_the_box_along_its_width(box_scan, single, amp_g,
                                                                                    period_s):
    """The mesh's width axis at compass 75 deg and a pulse along compass 75 (two horizontals at 20 and 110 deg, or
    one at 75): the box by its corners under the pulse along its width, nothing across. The same verdict, tilt and
    slide (to 1e-4: other principal axes), leaning along the pulse's line."""
    ah = _pulse(amp_g, period_s)
    got = SCANNED_3D.scene(_on(_record(ah, single=single)), _shape(box_scan, PUSH_DEG), None, 0.0)
    box = simulate_contact3d(ah, np.zeros_like(ah), None, DT, box_body(0.4, 0.6, 1.6, mu=0.6))
    tipping = math.atan2(0.2, 0.8)
    assert got.result.scene.overturned == box.overturned
    assert got.result.scene.theta_max * tipping == pytest.approx(box.tilt_max_rad, rel=1e-4)
    assert got.result.scene.sliding_max_m == pytest.approx(box.slide_max_m, rel=1e-4, abs=1e-9)
    assert min(abs(got.result.azimuth_deg - PUSH_DEG) % 180.0, 180.0 - abs(got.result.azimuth_deg - PUSH_DEG) % 180.0
               ) == pytest.approx(0.0, abs=0.5)


def test_an_unknown_orientation_takes_the_first_yaw_that_overturns(box_scan):
    """A blank azimuth: the yaws of the grid in turn, each the box by its corners turned by hand in the record's
    frame (x along its first horizontal); the first that overturns it governs, after as many runs."""
    ah = _pulse(0.55, 0.5)
    rec = _record(ah)
    fr = frame(rec, _shape(box_scan, math.nan))
    turn = math.radians(PUSH_DEG - A0_DEG)             # the pulse, clockwise of x: y counter-clockwise
    by_hand = [simulate_contact3d(math.cos(turn) * ah, -math.sin(turn) * ah, None, DT,
                                  box_body(0.4, 0.6, 1.6, mu=0.6), yaw_deg=float(yaw)).overturned
               for yaw in np.arange(0.0, 360.0, YAW_STEP_DEG)]
    assert any(by_hand) and not all(by_hand)
    got = judge(fr, body_of(_shape(box_scan, math.nan)), g_ms2=G)
    assert got.scene.overturned and got.runs == by_hand.index(True) + 1
    assert got.yaw_deg == YAW_STEP_DEG * by_hand.index(True)


def test_a_pulse_is_judged_along_the_weakest_direction_either_way(box_scan):
    """The box tips most easily across its 0.4 m width: a pulse the box by its corners survives along its width
    either way is survived, one that overturns it either way overturns the mesh."""
    judge_pulse = SCANNED_3D.pulse(_shape(box_scan, math.nan), None, settings=SimulationConfig(), g_ms2=G)
    for amp_g, period_s in ((0.3, 0.6), (0.6, 0.5)):
        ah = _pulse(amp_g, period_s)
        either = any(simulate_contact3d(s * ah, np.zeros_like(ah), None, DT, box_body(0.4, 0.6, 1.6, mu=0.6)
                                        ).overturned for s in (1.0, -1.0))
        got = judge_pulse(ah, DT)
        assert (got.overturned, got.runs) == (either, 2) and math.isnan(got.offset_m)   # a single body: no offset


@pytest.mark.slow
def test_a_screening_in_3d_gives_every_scanned_scene_a_verdict(kocaeli, scans_dir, tmp_path):
    """``scanned_model = "contact3d"`` through ``screen`` with sampling and margins: every scene of the three
    scanned bodies is the contact model's, with a verdict and a probability."""
    from pipeline.cli import main
    from pipeline.rocking.scene import Physics
    from pipeline.store import open_results

    for name in ("box-0.3x3.0x1.5.obj", "leaning-statue.obj"):
        shutil.copy(scans_dir / name, tmp_path / name)
    (tmp_path / "blocks.csv").write_text("id,height_m,width_m,mu,azimuth_deg,mesh,mass_kg\n"
                                         "BOX-MESH,,,1.0,30,box-0.3x3.0x1.5.obj,\n"
                                         "STAT,,,0.6,,leaning-statue.obj,350\n")
    (tmp_path / "c3.toml").write_text('[simulation]\nscanned_model = "contact3d"\n')
    assert main(["--records", str(kocaeli), "--blocks", str(tmp_path / "blocks.csv"), "--out", str(tmp_path / "out"),
                 "-q", "--samples", "12", "--config", str(tmp_path / "c3.toml")]) == 0
    ds = open_results(tmp_path / "out" / "screening.nc")
    assert (ds["physics"].values == int(Physics.contact3d)).all()
    assert np.isin(ds["overturn_simulated"].values, (0, 1)).all()
    p = ds["p_overturn"].values
    assert np.isfinite(p).all() and ((p >= 0) & (p <= 1)).all()
