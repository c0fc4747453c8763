"""Two scanned granite rocks against their shake-table tests: rockscreen's verdicts and probabilities, scored.

For every test of DATA_DIR (the layout of ``../shared/experiments/granite-pbr``: ``tests.csv``, ``motions/``,
``geometry/``) with a table motion: the motion read by rockscreen's table reader and processed by its uncorrected
chain (mean and trend removed, 5 % taper, 0.05 Hz high-pass); each rock from its scan (:mod:`pipeline.shapes.scan`:
SP1 from ``SP1.obj``, SP2 from ``final_sp2_1.obj``, the closed mesh of the same shape; settled on a flat base).
Every parameter is declared, none fitted to a test; restitution: the impact rule's own ratio; friction: not
modelled (the rocks do not slide in either model). The baselines: always "stands"; a logistic curve in ln PGA and
ln(PGV/PGA) (``tests.csv``) scored by leave-one-motion-out cross-validation (each motion's tests predicted by a
curve fitted without them).

``--model rolling`` (the default) judges each rock as ``screen`` judges a body given by its mesh with a blank
azimuth on a record of one horizontal, with its default model (:func:`pipeline.bodies.scanned.scanned_scene`; the rock
rolls on its convex hull, :mod:`pipeline.shapes.hull`, :mod:`pipeline.rocking.scanned.rolling`: no footprint tolerance;
the landing on the base loses what the impact rule says, the rolling over the scan's facets nothing): every
vertical plane of the body on the ``--orientation-step`` grid (5 degrees, rockscreen's default) facing the table's
axis. ``overturn_nominal`` is the worst orientation's verdict, ``p_overturn`` the worst orientation's probability
under rockscreen's amplitude, size and restitution spreads (the largest over the
:data:`~pipeline.uncertainty.two_sided.CANDIDATES` planes nearest to overturning at the nominal; ``--samples``
draws at most), ``p_random_orientation`` the probability under an orientation drawn at random among the planes,
and ``overturning_planes_deg`` the planes that overturn it (a false alarm's ``why`` says in how many); the summary
adds the verdicts if the orientation were known, estimated by leave-one-motion-out (the baseline's protocol, one
parameter).

``--model contact3d`` judges each rock as ``screen`` judges a body given by its mesh with a blank azimuth with
``scanned_model = "contact3d"`` (:mod:`pipeline.bodies.convex3d`): in 3D on its hull (the 3D contact model
:mod:`pipeline.rocking.solids.contact3d`: sliding, twisting, rocking on an edge or a corner, rolling over the hull's
facets, lift-off), the table's shaking axis at the yaws of a ``--yaw-step`` grid in the rock's settled frame (the
pose on the table is not recorded) until one overturns the rock, as ``screen`` stops, friction ``--mu`` (not
recorded either: :data:`TABLE_MU`, declared before any run), plastic contacts. ``overturn_nominal`` is the worst
yaw's verdict (overturned first, then the largest tilt); ``p_overturn`` (``--p-from draws``, the default)
``screen``'s: the worst yaw's under the declared uncertainty's draws, stopped by the sequential rule. With
``--every-yaw`` every yaw is run (``yaws_run`` says how many were), for the yaws' columns: the share that overturn
it (``p_random_orientation``, the probability under a yaw at random on the grid; ``screen`` draws it instead,
``--random-draws``), which overturn it, each one's final tilt, and the orientation chosen leave-one-motion-out;
``--p-from yaws`` runs every yaw and takes that share as ``p_overturn`` too. A rock overturns when it lies on a side
or comes to rest after the record on another face of its hull, tilted beyond its smallest static tipping angle.

``--model two_sided`` rocks each rock on one pivot per side (:mod:`pipeline.shapes.plane`,
:mod:`pipeline.rocking.scanned.two_sided`): the footprint's extreme points within ``--footprint-mm`` (default
rockscreen's 2 mm) of the base, or (``--pivots tipping``) where each side's static tipping angle puts them. The
orientation on
the table is not recorded: four poses are taken, the scans' x axis along the shaking (the published simulation's
pose) and their y axis, each in both senses. ``overturn_nominal`` is the worst pose's verdict; ``p_overturn`` the
probability under a pose drawn at random among the four (``--samples`` draws per pose).

Writes ``OUT_DIR/predictions.csv`` (``test``, ``rock``, ``overturn_nominal``, ``p_overturn``, ``observed``, the
per-pose verdicts, ``p_logistic_lomo``, and ``why`` for each wrong verdict: below uplift at every pose, lifted but
never overturned, or overturned by some draws only; a false alarm), ``OUT_DIR/summary.csv`` (accuracy, F1, Brier
score, log-loss per rock and predictor), ``OUT_DIR/reliability.png`` and ``OUT_DIR/boundary.png``. The data stays
where it is (GPL-3 material: the project ships no copy).

Run: ``python benchmarks/bench_granite.py ../shared/experiments/granite-pbr --out results/granite``.
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import csv
import dataclasses
import math
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import NamedTuple

import numpy as np
import obspy

from pipeline.bodies import convex3d, scanned3d
from pipeline.bodies.contract import Setup
from pipeline.bodies.scanned import scanned_scene
from pipeline.config import Config
from pipeline.constants import G
from pipeline.records.processing import apply_steps
from pipeline.records.record import Record
from pipeline.records.settings import ProcessingConfig
from pipeline.rocking.block import BlockShape, ShapeKind
from pipeline.rocking.orientation import plane_grid
from pipeline.rocking.scanned.two_sided import rock_two_sided_compiled, two_sided_block
from pipeline.rocking.settings import ScannedModel, SimulationConfig
from pipeline.rocking.simulate import step_control
from pipeline.rocking.solids.contact3d import FLAG_TAIL_CAP, Contact3DOutcome, pose
from pipeline.rocking.solids.convex_body import ConvexBody, base_threshold
from pipeline.shapes.hull import hull_chain
from pipeline.shapes.plane import PivotRule, PlaneBody, equivalent_rectangle, plane_body
from pipeline.shapes.scan import FOOTPRINT_TOL_M, read_scan
from pipeline.store import write_csv_atomic
from pipeline.ticker import Ticker
from pipeline.uncertainty.sampling import common_normals
from pipeline.uncertainty.scenes import motion as scene_motion
from pipeline.uncertainty.settings import UncertaintyConfig
from pipeline.uncertainty.two_sided import plane_draws

SCANS = {"SP1": "SP1.obj", "SP2": "final_sp2_1.obj"}
#: (label, azimuth of the shaking axis in the scan's settled frame [deg], sense of the table's +x along it)
POSES = (("x", 0.0, 1.0), ("-x", 0.0, -1.0), ("y", 90.0, 1.0), ("-y", 90.0, -1.0))
#: Probabilities are clipped to [P_CLIP, 1 - P_CLIP] in the log-loss only (a p of 0 or 1 that is wrong scores inf)
P_CLIP = 0.01
#: Friction of granite on the shake table (not recorded): declared before any run of the 3D model, a value in the
#: range published for granite on steel and concrete [-]
TABLE_MU = 0.8
#: Bins of the reliability plot
BINS = np.array([0.0, 0.05, 0.2, 0.4, 0.6, 0.8, 0.95, 1.0])


def bodies(data: Path, rule: PivotRule, tol_m: float) -> dict[tuple[str, str], PlaneBody]:
    """Each rock's :class:`PlaneBody` in each pose (a pose of sense -1 is its plane reversed)."""
    out = {}
    for rock, scan in SCANS.items():
        shape = read_scan(data / "geometry" / scan)
        for label, az, sense in POSES:
            pb = plane_body(shape, az, rule=rule, footprint_tol_m=tol_m)
            out[(rock, label)] = pb if sense > 0 else pb.reversed()
    return out


def motion(path: Path) -> tuple[np.ndarray, float]:
    """A table motion [m s-2] and its interval [s], processed as rockscreen processes uncorrected records."""
    tr = obspy.read(str(path), format="TABLE")[0]
    tr.data = tr.data.astype(float) * (G if tr.stats.physical_units == "g" else 1.0)
    apply_steps(tr, ProcessingConfig().uncorrected)
    return np.asarray(tr.data, dtype=float), float(tr.stats.delta)


def _one_test(job) -> list[dict]:
    """Every rock and pose of one test: the nominal verdict and the draws."""
    data, test, geo, samples, _step = job
    ah, dt = motion(data / "motions" / f"{test['test']}.acc.gz")
    control = step_control(SimulationConfig())
    z = common_normals(UncertaintyConfig().seed, samples)
    rows = []
    for rock in SCANS:
        row = {"test": test["test"], "rock": rock, "motion_id": test["motion_id"],
               "pga_g": float(test["scaled_pga_g"]), "pgv_pga_s": float(test["pgv_pga_s"]),
               "observed": int(test[f"{rock.lower()}_overturned"])}
        ps, undecided = [], 0
        for label, _az, _sense in POSES:
            pb = geo[(rock, label)]
            out = rock_two_sided_compiled(ah, np.zeros(0), dt, two_sided_block(pb.two_sided()), control, np.zeros(0))
            row[f"nominal_{label}"] = int(out.overturned)
            draws = plane_draws(ah, dt, pb, z, settings=UncertaintyConfig())
            undecided += int(draws.undecided.sum())
            ps.append(draws.p)
        row["overturn_nominal"] = max(row[f"nominal_{lab}"] for lab, _a, _s in POSES)
        row["p_overturn"] = float(np.nanmean(ps))
        row["undecided_draws"] = undecided
        row["table_pga_g"] = float(np.max(np.abs(ah)) / G)
        row["uplift_pga_g"] = min(min(pb.b_plus_m, pb.b_minus_m) / pb.com_height_m
                                  for (r, _lab), pb in geo.items() if r == rock)
        row["why"] = why(row)
        rows.append(row)
    return rows


class Rock(NamedTuple):
    """A rock as ``screen`` takes a body given by its mesh with a blank azimuth (no friction: neither model slides;
    the impact rule's own restitution), and its smallest uplift acceleration over the grid's planes [g]."""

    shape: BlockShape
    uplift_g: float


def scans(data: Path, step_deg: float) -> dict[str, Rock]:
    """Each rock of the data (:class:`Rock`), its uplift over the planes of a ``step_deg`` grid."""
    out = {}
    for rock, scan in SCANS.items():
        shape = read_scan(data / "geometry" / scan)
        height, width = equivalent_rectangle(shape)
        uplift = min(hull_chain(shape, float(az)).base_tan_alpha() for az in np.arange(0.0, 360.0, step_deg))
        out[rock] = Rock(BlockShape(height_m=height, width_m=width, mu=math.inf, kind=ShapeKind.scanned, scan=shape),
                         uplift)
    return out


def _one_test_rolling(job) -> list[dict]:
    """Every rock of one test as ``screen`` judges a body given by its scan, with a blank azimuth, on a record of one
    horizontal (:func:`pipeline.bodies.scanned.scanned_scene` with the rolling model): every plane of the body facing
    the shaking (the worst orientation's verdict), its probability (the draws in the :data:`CANDIDATES` planes
    nearest to overturning, the largest) and an orientation's at random."""
    data, test, geo, samples, step_deg = job
    ah, dt = motion(data / "motions" / f"{test['test']}.acc.gz")
    rec = Record(record_id=test["test"], dt_s=dt, horizontal_ms2=ah[None, :], azimuths_deg=(0.0,),
                 azimuth_known=False, vertical_ms2=None, files=(), formats=("TABLE",), component_codes=("X",),
                 processing_level="uncorrected")
    cfg = Config(simulation=SimulationConfig(orientation_step_deg=step_deg, scanned_model=ScannedModel.rolling),
                 uncertainty=dataclasses.replace(UncertaintyConfig(), samples=samples))
    z = common_normals(cfg.uncertainty.seed, samples)
    rows = []
    for rock, (shape, uplift_g) in geo.items():
        row = {"test": test["test"], "rock": rock, "motion_id": test["motion_id"],
               "pga_g": float(test["scaled_pga_g"]), "pgv_pga_s": float(test["pgv_pga_s"]),
               "observed": int(test[f"{rock.lower()}_overturned"])}
        got = scanned_scene(rec, scene_motion(rec.horizontal_ms2, 0.0, None, dt), z, shape, direction_deg=0.0,
                            grid_deg=plane_grid(step_deg),
                            setup=Setup(cfg.simulation, cfg.uncertainty, cfg.records.g_ms2, True, math.inf))
        nominal = got.search.scenes
        row["overturn_nominal"] = int(got.result.scene.overturned)
        # the worst orientation without a verdict (a pivot that would slip or lift): unknown, never standing
        row["verdict_unknown"] = int(got.result.scene.verdict < 0)
        row["orientations_overturning"] = float(np.mean([sc.overturned for _pl, sc in nominal]))
        row["planes"] = len(nominal)
        row["overturning_planes_deg"] = ";".join(f"{pl.body_deg:g}" for pl, sc in nominal if sc.overturned)
        row["p_overturn"] = got.probability.worst.p
        row["p_random_orientation"] = got.probability.random
        row["draws"] = got.probability.worst.drawn
        row["undecided_draws"] = got.probability.worst.without_verdict + sum(int(sc.verdict < 0) for _pl, sc in nominal)
        row["table_pga_g"] = float(np.max(np.abs(ah)) / G)
        row["uplift_pga_g"] = uplift_g
        row["why"] = why(row)
        rows.append(row)
    return rows


class Rock3D(NamedTuple):
    """A rock as ``screen`` takes a body given by its mesh with a blank azimuth, judged in 3D (``scanned_model =
    "contact3d"``, friction ``mu``), the contact model's body of it, and the table acceleration below which it
    cannot move [g]."""

    shape: BlockShape
    body: ConvexBody
    uplift_g: float


def rocks_3d(data: Path, mu: float) -> dict[str, Rock3D]:
    """Each rock as the 3D contact model's body (:class:`Rock3D`)."""
    out = {}
    for rock, scan in SCANS.items():
        mesh = read_scan(data / "geometry" / scan)
        height, width = equivalent_rectangle(mesh)
        shape = BlockShape(height_m=height, width_m=width, mu=mu, kind=ShapeKind.scanned, scan=mesh)
        body = scanned3d.body_of(shape)
        out[rock] = Rock3D(shape, body, float(base_threshold(pose(body.vertices, body.rest).standing, mu)))
    return out


#: Each worker's drawn bodies of each rock, draw k's under :func:`~pipeline.uncertainty.sampling.common_normals`
#: (the same draws for every test, as ``screen`` draws the same for every record): a stretched hull's tipping angle
#: is a search, done once per draw and rock in a worker rather than once per test
_DRAWN: dict[str, dict[int, ConvexBody]] = {}


def _one_test_3d(job) -> list[dict]:
    """Every rock of one test as ``screen`` judges a body given by its scan with a blank azimuth in 3D
    (:mod:`pipeline.bodies.convex3d`): the table's axis at the yaws of the grid until one overturns the rock
    (:func:`~pipeline.bodies.convex3d.judge`), the worst yaw's verdict (overturned first, then the largest tilt) and
    ``screen``'s probability: the worst yaw's under the declared uncertainty's draws (amplitude, the scan's sizes
    about G, friction), stopped by the sequential rule. With ``every_yaw`` (or ``--p-from yaws``: p the share of the
    yaws that overturn it) every yaw is run, for the yaws' columns; ``p_random_orientation`` is then that share, or
    with ``--random-draws`` ``screen``'s: the draws cycling over the grid (as many runs again)."""
    data, test, geo, samples, (yaw_step, p_from, random_draws, every_yaw) = job
    ah, dt = motion(data / "motions" / f"{test['test']}.acc.gz")
    rec = Record(record_id=test["test"], dt_s=dt, horizontal_ms2=ah[None, :], azimuths_deg=(0.0,),
                 azimuth_known=False, vertical_ms2=None, files=(), formats=("TABLE",), component_codes=("X",),
                 processing_level="uncorrected")
    unc = dataclasses.replace(UncertaintyConfig(), samples=samples)
    z = common_normals(unc.seed, samples)
    rows = []
    for rock, (shape, body, uplift_g) in geo.items():
        fr = convex3d.frame(rec, shape)._replace(yaws_deg=np.arange(0.0, 360.0, yaw_step))
        row = {"test": test["test"], "rock": rock, "motion_id": test["motion_id"],
               "pga_g": float(test["scaled_pga_g"]), "pgv_pga_s": float(test["pgv_pga_s"]),
               "observed": int(test[f"{rock.lower()}_overturned"]), "verdict_unknown": 0, "planes": len(fr.yaws_deg),
               "table_pga_g": float(np.max(np.abs(ah)) / G), "uplift_pga_g": uplift_g, "undecided_draws": 0}
        if every_yaw or p_from == "yaws":
            worst_yaw, worst_out = _every_yaw(fr, body, row)
        else:
            judged = convex3d.judge(fr, body, g_ms2=G)
            worst_yaw, worst_out = judged.yaw_deg, judged.outcome
            row.update(overturn_nominal=int(worst_out.overturned), yaws_run=judged.runs,
                       p_overturn=float(worst_out.overturned), p_random_orientation=math.nan, draws=0,
                       **_run_columns([worst_out]))         # (judge keeps the worst run's outcome only)
        if p_from == "draws":
            drawn = _DRAWN.setdefault(rock, {})
            family = scanned3d.SCANNED_BODIES
            at_worst = convex3d.yaw_draws(fr, shape, z, np.array([worst_yaw]), drawn, family=family, settings=unc,
                                          g_ms2=G)
            row.update(p_overturn=at_worst.p, draws=at_worst.drawn, undecided_draws=at_worst.without_verdict)
            if random_draws:                    # screen's p_random_orientation: the draws cycling over the yaws
                at_random = convex3d.yaw_draws(fr, shape, z, fr.yaws_deg, drawn, family=family, settings=unc,
                                               g_ms2=G)
                row.update(p_random_orientation=at_random.p, draws=at_worst.drawn + at_random.drawn,
                           undecided_draws=at_worst.without_verdict + at_random.without_verdict)
        row["why"] = why(row)
        rows.append(row)
    return rows


def _every_yaw(fr: convex3d.Frame, body: ConvexBody, row: dict) -> tuple[float, Contact3DOutcome]:
    """Every yaw of the grid run, the yaws' columns into ``row``; the worst yaw (overturned first, then the largest
    tilt, the first of equals: :func:`~pipeline.bodies.convex3d.judge`'s) and its outcome."""
    outs = [convex3d.run(fr, body, float(y), g_ms2=G) for y in fr.yaws_deg]
    over = [o.overturned for o in outs]
    worst = max(range(len(outs)), key=lambda k: (outs[k].overturned, outs[k].tilt_max_rad, -k))
    row.update(overturn_nominal=int(any(over)), yaws_run=len(outs), orientations_overturning=float(np.mean(over)),
               overturning_planes_deg=";".join(f"{y:g}" for y, o in zip(fr.yaws_deg, over) if o),
               p_overturn=float(np.mean(over)), p_random_orientation=float(np.mean(over)), draws=0,
               tilt_end_deg=";".join(f"{math.degrees(o.tilt_end_rad):.0f}" for o in outs), **_run_columns(outs))
    return float(fr.yaws_deg[worst]), outs[worst]


def _run_columns(outs: list[Contact3DOutcome]) -> dict:
    """The runs' columns: how many had a step at the sweeps' cap, ran to the tail's cap, or toppled onto a face
    short of lying on a side; the largest slide [m] and twist [deg]."""
    return {"capped_runs": sum(o.capped_steps > 0 for o in outs),
            "tail_capped_runs": sum(bool(o.flags & FLAG_TAIL_CAP) for o in outs),
            "toppled_on_a_face": sum(o.overturned and o.tilt_end_rad < 1.5 for o in outs),
            "slide_max_m": max(o.slide_max_m for o in outs),
            "twist_max_deg": math.degrees(max(o.twist_max_rad for o in outs))}


def why(row: dict) -> str:
    """What a wrong verdict of the worst pose is, measured: a missed overturning the table could not even lift at any
    pose (its peak below the smallest g tan alpha: the pivots or the base's rolling are not the rock's); one it lifted
    but no pose and no draw overturned; one only some draws overturned (a sensitive scene); a false alarm (with the
    rolling model: in how many of the planes, and which: the orientation that decides it)."""
    if row["overturn_nominal"] == row["observed"]:
        return ""
    if row["observed"] == 0:
        planes = [a for a in row.get("overturning_planes_deg", "").split(";") if a]
        if not planes:
            return "false alarm"
        share = round(row["orientations_overturning"] * row["planes"])
        return f"false alarm: overturns in {share} of {row['planes']} orientations ({', '.join(planes)} deg)"
    if row["table_pga_g"] <= row["uplift_pga_g"]:
        return "missed: below uplift at every pose"
    return ("missed: some draws overturn" if row["p_overturn"] > 0
            else "missed: lifts, no orientation or draw overturns")


def orientation_lomo(rows: list[dict]) -> np.ndarray:
    """The verdicts of one rock if its orientation on the table were known, that orientation estimated by
    leave-one-motion-out: for each motion, the plane whose verdicts agree best with the other motions' tests (the
    first of equals), its verdict on the motion's own tests. The protocol of the logistic baseline, one parameter."""
    planes = sorted({float(a) for r in rows for a in r["overturning_planes_deg"].split(";") if a})
    verdicts = np.array([[f"{a:g}" in r["overturning_planes_deg"].split(";") for a in planes] for r in rows], int)
    if not planes:
        return np.zeros(len(rows), int)
    obs = np.array([r["observed"] for r in rows])
    motions = np.array([r["motion_id"] for r in rows])
    out = np.zeros(len(rows), int)
    for m in np.unique(motions):
        held = motions == m
        agree = (verdicts[~held] == obs[~held, None]).mean(axis=0)
        out[held] = verdicts[held, int(np.argmax(agree))]
    return out


def logistic_lomo(rows: list[dict]) -> np.ndarray:
    """Leave-one-motion-out predictions of a logistic curve in ln PGA and ln(PGV/PGA) (:func:`_fit`)."""
    x = np.column_stack([np.ones(len(rows)), np.log([r["pga_g"] for r in rows]),
                         np.log([r["pgv_pga_s"] for r in rows])])
    y = np.array([r["observed"] for r in rows], dtype=float)
    motions = np.array([r["motion_id"] for r in rows])
    p = np.empty(len(rows))
    for m in np.unique(motions):
        held = motions == m
        w = _fit(x[~held], y[~held])
        p[held] = 1.0 / (1.0 + np.exp(-x[held] @ w))
    return p


def _fit(x: np.ndarray, y: np.ndarray, *, ridge: float = 1e-6, iterations: int = 50) -> np.ndarray:
    """Logistic regression by Newton's method (iteratively reweighted least squares) with a tiny ridge, so that
    a separable training set still has a finite fit."""
    w = np.zeros(x.shape[1])
    for _ in range(iterations):
        p = 1.0 / (1.0 + np.exp(-x @ w))
        grad = x.T @ (p - y) + ridge * w
        hess = (x * (p * (1 - p))[:, None]).T @ x + ridge * np.eye(x.shape[1])
        step = np.linalg.solve(hess, grad)
        w -= step
        if np.max(np.abs(step)) < 1e-10:
            break
    return w


def scores(pred: np.ndarray, p: np.ndarray, obs: np.ndarray) -> dict[str, float]:
    """Accuracy and F1 of the verdicts; Brier score and log-loss of the probabilities."""
    tp, fp = int(np.sum((pred == 1) & (obs == 1))), int(np.sum((pred == 1) & (obs == 0)))
    fn = int(np.sum((pred == 0) & (obs == 1)))
    pc = np.clip(p, P_CLIP, 1 - P_CLIP)
    return {"accuracy": float(np.mean(pred == obs)), "f1": 2 * tp / (2 * tp + fp + fn) if tp + fp + fn else 1.0,
            "brier": float(np.mean((p - obs) ** 2)),
            "log_loss": float(-np.mean(obs * np.log(pc) + (1 - obs) * np.log(1 - pc))),
            "false_alarms": fp, "missed": fn}


def summary(rows: list[dict]) -> list[dict]:
    """The scores per rock of every predictor."""
    out = []
    for rock in SCANS:
        sel = [r for r in rows if r["rock"] == rock]
        obs = np.array([r["observed"] for r in sel])
        preds = {"always_stands": (np.zeros(len(sel), int), np.zeros(len(sel))),
                 "logistic_lomo": (np.array([r["p_logistic_lomo"] >= 0.5 for r in sel], int),
                                   np.array([r["p_logistic_lomo"] for r in sel])),
                 ("rockscreen 3D contact model (worst yaw, "
                  + ("its p)" if any(r["draws"] for r in sel) else "p over yaws)") if "yaws_run" in sel[0]
                  else "rockscreen (worst orientation, its p)" if "orientations_overturning" in sel[0]
                  else "rockscreen (worst pose; p over poses)"): (np.array([r["overturn_nominal"] for r in sel]),
                                                           np.array([r["p_overturn"] for r in sel]))}
        p_own = np.array([r["p_overturn"] for r in sel])
        if "verdict_unknown" in sel[0]:
            unknown = np.array([r["verdict_unknown"] for r in sel])
            preds["rockscreen, no verdict counted as overturning (the report's reading)"] = (
                np.array([r["overturn_nominal"] for r in sel]) | unknown, p_own)
        preds["rockscreen, p >= 0.5 (the report's threshold)"] = ((p_own >= 0.5).astype(int), p_own)
        p_random = np.array([r.get("p_random_orientation", math.nan) for r in sel])
        if np.all(np.isfinite(p_random)):             # (screen's first overturning yaw alone: no random one)
            preds["rockscreen (worst orientation, p of a random one)"] = (
                np.array([r["overturn_nominal"] for r in sel]), p_random)
        if "overturning_planes_deg" in sel[0]:
            v = orientation_lomo(sel)
            preds["rockscreen, orientation chosen leave-one-motion-out"] = (v, v.astype(float))
        for label, _a, _s in POSES:
            if f"nominal_{label}" in sel[0]:
                v = np.array([r[f"nominal_{label}"] for r in sel])
                preds[f"rockscreen pose {label}"] = (v, v.astype(float))
        for name, (v, p) in preds.items():
            out.append({"rock": rock, "predictor": name, "tests": len(sel), "overturned": int(obs.sum()),
                        **scores(v, p, obs)})
    return out


def plots(rows: list[dict], out: Path) -> None:
    """The reliability plot and the (PGA, PGV/PGA) boundary, observed against predicted."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), constrained_layout=True)
    for ax, rock in zip(axes, SCANS):
        sel = [r for r in rows if r["rock"] == rock]
        obs = np.array([r["observed"] for r in sel])
        for key, label, marker in (("p_overturn", "rockscreen", "o"), ("p_logistic_lomo", "logistic (LOMO)", "s")):
            p = np.array([r[key] for r in sel])
            idx = np.clip(np.digitize(p, BINS[1:-1]), 0, len(BINS) - 2)
            xs, ys, ns = [], [], []
            for b in range(len(BINS) - 1):
                if np.any(idx == b):
                    xs.append(p[idx == b].mean())
                    ys.append(obs[idx == b].mean())
                    ns.append(int(np.sum(idx == b)))
            ax.plot(xs, ys, marker=marker, label=label)
            for x, y, n in zip(xs, ys, ns):
                ax.annotate(str(n), (x, y), textcoords="offset points", xytext=(4, -10), fontsize=7)
        ax.plot([0, 1], [0, 1], color="0.6", lw=0.8, ls=":", label="perfect")
        ax.set(title=f"{rock}: reliability (tests per bin beside each point)", xlabel="predicted p of overturning",
               ylabel="observed frequency", xlim=(-0.02, 1.02), ylim=(-0.02, 1.02))
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=3, fontsize=8)   # below: never on a point
    fig.savefig(out / "reliability.png", dpi=120)
    plt.close(fig)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), constrained_layout=True, sharey=True)
    for ax, rock in zip(axes, SCANS):
        sel = [r for r in rows if r["rock"] == rock]
        for obs_v, pred_v, color, marker, label in (
                (1, 1, "tab:red", "o", "overturned, predicted"), (1, 0, "tab:red", "x", "overturned, missed"),
                (0, 0, "tab:blue", "o", "stood, predicted"), (0, 1, "tab:blue", "x", "stood, false alarm")):
            pts = [(r["pga_g"], r["pgv_pga_s"]) for r in sel if r["observed"] == obs_v
                   and r["overturn_nominal"] == pred_v]
            if pts:
                a = np.array(pts)
                if marker == "x":
                    ax.scatter(a[:, 0], a[:, 1], c=color, marker=marker, s=18, label=f"{label} ({len(pts)})")
                else:                           # stood: open circles, overturned: filled
                    ax.scatter(a[:, 0], a[:, 1], edgecolors=color, facecolors="none" if obs_v == 0 else color,
                               marker=marker, s=18, label=f"{label} ({len(pts)})")
        ax.set(xscale="log", yscale="log", title=f"{rock}: observed against rockscreen's worst pose",
               xlabel="PGA as tests.csv gives it [g]", ylabel="PGV/PGA as tests.csv gives it [s]")
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2, fontsize=8)
    fig.savefig(out / "boundary.png", dpi=120)
    plt.close(fig)


def _write(path: Path, rows: list[dict]) -> None:
    """The table as rockscreen writes every CSV (:func:`~pipeline.store.write_csv_atomic`: NaN a blank cell)."""
    write_csv_atomic(path, list(rows[0]), rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("data", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--limit", type=int, default=0, help="the first N tests only (0: all)")
    ap.add_argument("--pivots", choices=[r.name for r in PivotRule], default=PivotRule.footprint.name)
    ap.add_argument("--footprint-mm", type=float, default=FOOTPRINT_TOL_M * 1e3,
                    help="the footprint's tolerance above the base [mm] (default %(default)s)")
    ap.add_argument("--samples", type=int, default=UncertaintyConfig().samples, help="draws per pose")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--mu", type=float, default=TABLE_MU, help="contact3d: friction on the table (default %(default)s)")
    ap.add_argument("--yaw-step", type=float, default=30.0,
                    help="contact3d: the grid of the rock's yaw on the table [deg] (default %(default)s)")
    ap.add_argument("--p-from", choices=("draws", "yaws"), default="draws",
                    help="contact3d: p_overturn from screen's draws at the worst yaw (default) or the yaws' share")
    ap.add_argument("--random-draws", action="store_true",
                    help="contact3d, --p-from draws: p_random_orientation from screen's draws over the yaws too")
    ap.add_argument("--every-yaw", action="store_true",
                    help="contact3d: run every yaw (the yaws' columns and scores), not screen's stop at the first "
                         "that overturns the rock")
    ap.add_argument("--model", choices=("rolling", "two_sided", "contact3d"), default="rolling",
                    help="rolling (screen's default): the body rolls on its convex hull, every plane of the "
                         "--orientation-step grid, as screen judges a mesh with a blank azimuth; two_sided: one "
                         "pivot per side at the footprint (four poses)")
    ap.add_argument("--orientation-step", type=float, default=5.0,
                    help="the rolling model's grid of planes [deg] (default %(default)s, rockscreen's scan)")
    args = ap.parse_args()
    tests = [r for r in csv.DictReader((args.data / "tests.csv").open()) if r["has_motion"] == "1"]
    tests = tests[:args.limit] if args.limit else tests
    step = args.orientation_step
    if args.model == "contact3d":
        geo: dict = rocks_3d(args.data, args.mu)
        task, step = _one_test_3d, (args.yaw_step, args.p_from, args.random_draws, args.every_yaw)
        for rock, (_shape, body, uplift_g) in geo.items():
            print(f"{rock}: {len(body.vertices)} hull vertices in 3D, mu {args.mu:g}, moves from {uplift_g:.3f} g, "
                  f"smallest static tipping angle {math.degrees(body.tipping_rad):.1f} deg; "
                  f"yaws every {args.yaw_step:g} deg")
    elif args.model == "rolling":
        geo = scans(args.data, args.orientation_step)
        task = _one_test_rolling
        for rock, (shape, uplift_g) in geo.items():
            alpha = [math.degrees(math.atan(hull_chain(shape.scan, az).base_tan_alpha()))
                     for az in np.arange(0.0, 360.0, args.orientation_step)]
            print(f"{rock}: rolling on its hull in {len(alpha)} planes; base alpha {min(alpha):.1f}-{max(alpha):.1f}"
                  f" deg (uplift from {uplift_g:.3f} g)")
    else:
        geo = bodies(args.data, PivotRule[args.pivots], args.footprint_mm / 1e3)
        task = _one_test
        for (rock, label), pb in geo.items():
            tip = [math.degrees(math.atan2(b, pb.com_height_m)) for b in (pb.b_plus_m, pb.b_minus_m)]
            print(f"{rock} {label:>2}: alpha {tip[0]:.1f} / {tip[1]:.1f} deg, z_G {1e3 * pb.com_height_m:.1f} mm")
    args.out.mkdir(parents=True, exist_ok=True)
    rows: list[dict] = []
    t0 = time.perf_counter()
    done = [0]                                          # tests finished, read by the ticker's thread
    with ProcessPoolExecutor(max_workers=args.jobs) as pool, \
            Ticker(lambda s: print(f"{done[0]}/{len(tests)} tests, {s:.0f} s", flush=True), every_s=2.0):
        jobs = [(args.data, t, geo, args.samples, step) for t in tests]
        for got in pool.map(task, jobs):
            rows.extend(got)
            done[0] += 1
    for row, p in zip(rows, logistic_lomo(rows)):
        row["p_logistic_lomo"] = float(p)
    _write(args.out / "predictions.csv", rows)
    table = summary(rows)
    _write(args.out / "summary.csv", table)
    plots(rows, args.out)
    for rock in SCANS:
        kinds: dict[str, int] = {}
        for r in rows:
            if r["rock"] == rock and r["why"]:
                kind = r["why"].split(":")[0] if r["why"].startswith("false alarm") else r["why"]
                kinds[kind] = kinds.get(kind, 0) + 1
        print(f"{rock} wrong verdicts (worst pose): " + ", ".join(f"{k} {v}" for k, v in sorted(kinds.items())))
    for r in table:
        print(f"{r['rock']} {r['predictor']:<40} accuracy {r['accuracy']:.3f}  F1 {r['f1']:.3f}  Brier "
              f"{r['brier']:.3f}  log-loss {r['log_loss']:.3f}  false alarms {r['false_alarms']}  missed {r['missed']}")
    print(f"undecided draws: {sum(r['undecided_draws'] for r in rows)}; wrote {args.out}; "
          f"{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
