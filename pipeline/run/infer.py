"""Archaeoseismology: bound the dominant pulse from what toppled and what stood.

Given blocks of known sizes and, for each, whether it toppled or stood (and,
optionally, the azimuth it fell towards), find the idealized pulses
(a_p, t_p), and orientations, under which every observation holds:

* by the paper's criterion (closed form, Eqs. 1, 5, 7 and the sliding line
  a_p <= mu g): a block overturns where a_p >= max(v_crit / (beta t_p), g tan alpha);
* by the nonlinear rocking simulation of the idealized pulse at every grid point (a body given by its scan: its
  model, ``[simulation] scanned_model``, in its weakest plane by the footprint, the pulse in either sense; the
  criterion takes its equivalent rectangle).

The pulse acts along an axis at azimuth phi. A block with a rocking plane
(``azimuth_deg`` in the inventory) feels a_p |cos(phi - plane)|; a block free
to rock in any plane (blank azimuth: a column) feels the full a_p and falls
along the pulse axis, so its fall azimuth, if observed, must lie within
``infer.fall_tolerance_deg`` of phi (mod 180). Without any azimuth the
orientation drops out and a single orientation is used.

The grid is log-spaced: t_p over 0.1-10 times the blocks' transition
durations, a_p over 0.5-20 times their uplift accelerations. Observations
that cannot all hold together are reported: the pairs that exclude each
other, and the largest subset that holds at some grid point.

References
----------
The reference paper, "Rocking Blocks Stability under Critical Pulses from Near-Fault Earthquakes Using a
Novel Energy Based Approach", Applied Sciences (MDPI): "the approach could be used in
archaeoseismology to identify the characteristics of the dominant pulse content of past
earthquakes based on their impacts on various historical and heritage structures".
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from .. import criteria
from ..blocks import Inventory
from ..bodies.contract import Placement, PulseOutcome
from ..bodies.registry import body_model
from ..closed_forms import PULSE_BETA
from ..config import Config
from ..errors import InventoryError
from ..rocking.references.excitation import pulse
from ..schema import INFER, apply_schema
from ..stacks import stack_ids
from ..tables import parse_number, read_csv_table

OUTCOMES = ("toppled", "standing", "displaced")
#: The outcomes as a reader is asked for them.
OUTCOME_WORDS = f"{', '.join(OUTCOMES[:-1])} or {OUTCOMES[-1]}"
#: Shapes an inference can assume (half pulses, as in the paper).
INFER_SHAPES = ("half-sine", "step", "linear", "parabolic")


@dataclass(frozen=True)
class Observations:
    """Observed outcomes, aligned with ``inventory``."""

    inventory: Inventory
    toppled: np.ndarray          #: bool per block
    fall_azimuth_deg: np.ndarray  #: fall azimuth mod 180 [deg] (NaN: not observed)
    source: str
    displaced: np.ndarray        #: bool per block: found standing, moved on what it stands on (a body of a stack)


#: Where an idealized pulse acts: one horizontal (the models of blocks judged in 3D on two horizontals take the pulse
#: as the planar model of the same block does).
ONE_DIRECTION = Placement(single_component=True, azimuth_deg=0.0, azimuth_known=True)

def read_observations(path: str | Path, inventory: Inventory) -> Observations:
    """Read ``id,outcome[,fall_azimuth_deg]`` (outcome: toppled | standing | displaced; displaced: a body of a stack
    found standing but moved on what it stands on).

    Raises
    ------
    InventoryError
        Naming the file, line and column, what was found and what is expected.
    """
    path = Path(path)
    header, records = read_csv_table(path, what="observations", expected_header="id,outcome[,fall_azimuth_deg]")
    if "id" not in header or "outcome" not in header or set(header) - {"id", "outcome", "fall_azimuth_deg"}:
        raise InventoryError(f"{path}, line 1: header {header}; expected 'id,outcome' and optionally "
                             "'fall_azimuth_deg'")
    index = {b: k for k, b in enumerate(inventory.ids)}
    picked: list[int] = []
    toppled: list[bool] = []
    fall: list[float] = []
    displaced: list[bool] = []
    stacked = stack_ids(inventory.stacks, len(inventory)) != ""
    seen: dict[str, int] = {}
    for line, where, rec in records:
        bid = rec.get("id", "")
        if bid not in index:
            raise InventoryError(f"{where}, column 'id': {bid!r} is not in the inventory {inventory.source}")
        if bid in seen:
            raise InventoryError(f"{where}, column 'id': {bid!r} observed twice (first on line {seen[bid]})")
        seen[bid] = line
        outcome = rec.get("outcome", "").lower()
        if outcome not in OUTCOMES:
            raise InventoryError(f"{where}, column 'outcome': {rec.get('outcome')!r}; expected {OUTCOME_WORDS}")
        if outcome == "displaced" and not stacked[index[bid]]:
            raise InventoryError(f"{where}, column 'outcome': 'displaced' for {bid!r}, a single block; displaced is "
                                 "judged for the bodies of a stack (its joints' slip is followed, a single block's "
                                 "sliding is not); observe it as standing, or give the body it stands on "
                                 "(stands_on) in the inventory")
        az = rec.get("fall_azimuth_deg", "")
        fall_deg = math.nan
        if az:
            if outcome != "toppled":
                raise InventoryError(f"{where}, column 'fall_azimuth_deg': {az!r}; a fall azimuth is given only "
                                     "for a toppled block")
            fall_deg = parse_number(az, where=where, column="fall_azimuth_deg", rule="an azimuth in [0, 360] deg",
                                    ok=lambda x: 0 <= x <= 360) % 180.0
        picked.append(index[bid])
        toppled.append(outcome == "toppled")
        displaced.append(outcome == "displaced")
        fall.append(fall_deg)
    if not picked:
        raise InventoryError(f"{path}: no observations; add one line per block 'id,toppled', 'id,standing' or "
                             "'id,displaced'")
    return Observations(inventory.take(picked), np.array(toppled), np.array(fall), str(path), np.array(displaced))


def grid(inv: Inventory, *, shape: str, config: Config, oriented: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t_p [s], a_p [m s-2], pulse azimuth [deg]) of the search grid.

    Orientations are searched only when ``oriented`` (a rocking plane or a fall azimuth is known).
    """
    cfg, g = config.infer, config.records.g_ms2
    if cfg.n_durations < 2 or cfg.n_accelerations < 2:
        raise InventoryError("[infer] n_durations and n_accelerations must be at least 2")
    geom = inv.geometry(g_ms2=g)
    a_up = criteria.uplift_acceleration(geom.alpha, g_ms2=g)
    t_bar = criteria.transition_duration(geom.R, geom.alpha, PULSE_BETA[shape], g_ms2=g)
    tp = np.geomspace(0.1 * float(np.min(t_bar)), 10.0 * float(np.max(t_bar)), cfg.n_durations)
    ap = np.geomspace(0.5 * float(np.min(a_up)), 20.0 * float(np.max(a_up)), cfg.n_accelerations)
    return tp, ap, (np.arange(0.0, 180.0, cfg.azimuth_step_deg) if oriented else np.array([0.0]))


def _felt(inv: Inventory, azimuths: np.ndarray) -> np.ndarray:
    """Fraction of the pulse each block feels, (block, azimuth)."""
    plane = inv.azimuth_deg[:, None]
    return np.where(np.isnan(plane), 1.0, np.abs(np.cos(np.radians(azimuths[None, :] - plane))))


def criterion_overturns(inv: Inventory, tp, ap, azimuths, *, shape: str, config: Config) -> np.ndarray:
    """Overturning by the paper's criterion, (block, azimuth, duration, acceleration)."""
    g = config.records.g_ms2
    geom = inv.geometry(g_ms2=g)
    a_crit = criteria.critical_acceleration(tp[None, :], geom.R[:, None], geom.alpha[:, None], PULSE_BETA[shape],
                                            g_ms2=g, form=config.criteria.form)          # (block, tp)
    felt = _felt(inv, azimuths)[:, :, None, None] * ap[None, None, None, :]
    below_sliding = felt <= inv.mu[:, None, None, None] * g                            # the paper's line
    applicable = criteria.rocking_applicable(geom.alpha)[:, None, None, None]
    return (felt >= a_crit[:, None, :, None]) & below_sliding & applicable


def simulated_overturns(inv: Inventory, tp, ap, azimuths, *, shape: str, config: Config,
                        progress=None) -> tuple[np.ndarray, np.ndarray, int]:
    """Overturning by the nonlinear simulation of the idealized pulse, each body's residual offset on what it stands
    on [m] (:attr:`~pipeline.bodies.contract.PulseOutcome.offset_m`: NaN where its model does not say), both
    (block, azimuth, duration, acceleration), and the number of runs (``progress``: the command's progress display,
    told of each block done)."""
    rocking_blocks = inv.rocking_blocks(g_ms2=config.records.g_ms2)
    felt = _felt(inv, azimuths)
    out = np.zeros((len(inv), azimuths.size, tp.size, ap.size), dtype=bool)
    offset = np.full(out.shape, np.nan)
    runs = 0
    settings = config.simulation_settings()
    blocks = range(len(inv))
    for j in (progress(blocks, total=len(inv), label="blocks simulated") if progress is not None else blocks):
        memo: dict[tuple, PulseOutcome] = {}
        body = inv.shape(j)
        overturns = body_model(body, ONE_DIRECTION, settings).pulse(body, rocking_blocks[j], settings=settings,
                                                          g_ms2=config.records.g_ms2)      # once per block
        for k, t in enumerate(tp):
            unit, dt = pulse(shape, amplitude_ms2=1.0, period_s=2.0 * float(t),
                             samples_per_period=config.infer.samples_per_period)
            for m, a in enumerate(ap):
                for q in range(azimuths.size):
                    amp = float(a * felt[j, q])
                    key = (k, round(amp, 12))
                    if key not in memo:
                        memo[key] = overturns(amp * unit, dt)
                        runs += memo[key].runs
                    out[j, q, k, m], offset[j, q, k, m] = memo[key].overturned, memo[key].offset_m
    return out, offset, runs


def _fall_ok(obs: Observations, azimuths: np.ndarray, tolerance_deg: float) -> np.ndarray:
    """(block, azimuth): the pulse axis agrees with the observed fall of blocks free to rock in any plane."""
    fall = obs.fall_azimuth_deg[:, None]
    free = np.isnan(obs.inventory.azimuth_deg)[:, None]
    diff = np.abs((azimuths[None, :] - fall + 90.0) % 180.0 - 90.0)
    return np.where(np.isnan(fall) | ~free, True, diff <= tolerance_deg)


def consistency(overturns: np.ndarray, obs: Observations, azimuths: np.ndarray, config: Config,
                offset_m: np.ndarray | None = None) -> np.ndarray:
    """Per observation: where it holds, (observation, azimuth, duration, acceleration). A displaced body holds where it
    stands with a residual offset ``offset_m`` [m] of at least ``infer.displaced_min_m`` (None: nowhere)."""
    holds = np.where(obs.toppled[:, None, None, None], overturns, ~overturns)
    if obs.displaced.any():
        moved = np.zeros(overturns.shape, dtype=bool) if offset_m is None else \
            np.abs(np.nan_to_num(offset_m, nan=0.0)) >= config.infer.displaced_min_m
        holds = np.where(obs.displaced[:, None, None, None], holds & moved, holds)
    return holds & _fall_ok(obs, azimuths, config.infer.fall_tolerance_deg)[:, :, None, None]


def conflicts(holds: np.ndarray, ids: tuple) -> dict:
    """Whether all observations hold together; if not, the conflicting pairs and a largest consistent subset."""
    n = holds.shape[0]
    flat = holds.reshape(n, -1)
    feasible = flat.all(axis=0)
    if feasible.any():
        return {"consistent": True, "pairs": [], "largest_subset": list(ids), "left_out": []}
    pairs = [(ids[a], ids[b]) for a in range(n) for b in range(a + 1, n) if not (flat[a] & flat[b]).any()]
    alone = [ids[a] for a in range(n) if not flat[a].any()]
    count = flat.sum(axis=0)
    best = int(np.argmax(count))
    keep = [ids[a] for a in range(n) if flat[a, best]]
    return {"consistent": False, "pairs": pairs, "impossible": alone, "largest_subset": keep,
            "left_out": [i for i in ids if i not in keep]}


def infer(obs: Observations, *, shape: str = "half-sine", config: Config, durations_s=None,
          accelerations_ms2=None, progress=None) -> xr.Dataset:
    """The consistency masks on the grid, by the criterion and by simulation (netCDF-ready Dataset).

    Parameters
    ----------
    obs : Observations
        The blocks and what happened to them.
    shape : str
        Assumed pulse shape (:data:`INFER_SHAPES`).
    config : Config
        ``[infer]`` grid settings and the simulation settings.
    durations_s, accelerations_ms2 : array_like, optional
        A fixed grid of t_p [s] and a_p [m s-2] instead of the one fitted to the blocks
        (to compare sites or subsets on the same grid).
    progress : callable, optional
        The command's progress display (the simulation's blocks, one by one).
    """
    from ..errors import ParameterError

    if shape not in INFER_SHAPES:
        raise ParameterError(f"pulse {shape!r}: screen infer assumes one of {list(INFER_SHAPES)}")
    inv = obs.inventory
    oriented = bool(np.any(np.isfinite(inv.azimuth_deg)) or np.any(np.isfinite(obs.fall_azimuth_deg)))
    tp, ap, az = grid(inv, shape=shape, config=config, oriented=oriented)
    if durations_s is not None:
        tp = np.asarray(durations_s, dtype=float)
    if accelerations_ms2 is not None:
        ap = np.asarray(accelerations_ms2, dtype=float)
    crit = consistency(criterion_overturns(inv, tp, ap, az, shape=shape, config=config), obs, az, config)
    stacked = stack_ids(inv.stacks, len(inv)) != ""
    crit[stacked] = True          # the criterion judges a block alone on the ground: a stack's body it leaves free
    t0 = time.perf_counter()
    sim_over, sim_offset, runs = simulated_overturns(inv, tp, ap, az, shape=shape, config=config, progress=progress)
    t_sim = time.perf_counter() - t0
    sim = consistency(sim_over, obs, az, config, sim_offset)
    dims = ("observation", "azimuth", "duration", "acceleration")
    ds = xr.Dataset(
        {"observation_holds_criterion": (dims, crit.astype("i1")),
         "observation_holds_simulation": (dims, sim.astype("i1")),
         "consistent_criterion": (dims[1:], crit.all(axis=0).astype("i1")),
         "consistent_simulation": (dims[1:], sim.all(axis=0).astype("i1")),
         "observations_holding_simulation": (dims[1:], sim.sum(axis=0).astype("i4")),
         "toppled": (("observation",), obs.toppled.astype("i1")),
         "displaced": (("observation",), obs.displaced.astype("i1")),
         "fall_azimuth": (("observation",), obs.fall_azimuth_deg),
         "height": (("observation",), inv.height_m),
         "width": (("observation",), inv.width_m),
         "mu": (("observation",), inv.mu),
         "block_azimuth": (("observation",), inv.azimuth_deg)},
        coords={"observation": np.array(inv.ids, dtype=object), "azimuth": ("azimuth", az),
                "duration": ("duration", tp), "acceleration": ("acceleration", ap)},
        attrs={"Conventions": "CF-1.11", "title": "rockscreen: pulses consistent with observed toppling",
               "pulse": shape, "pulse_beta": PULSE_BETA[shape], "simulation_runs": runs,
               "simulation_time_s": round(t_sim, 3), "observations_file": obs.source,
               "displaced_min_m": config.infer.displaced_min_m,
               "criterion_not_applied": ", ".join(np.asarray(inv.ids, dtype=object)[stacked].tolist())})
    return apply_schema(ds, INFER)


def summarize(ds: xr.Dataset) -> dict:
    """Bounds of the consistent region and the conflicts, by both methods."""
    ids = tuple(ds["observation"].values.tolist())
    out = {}
    for method in ("criterion", "simulation"):
        mask = ds[f"consistent_{method}"].values.astype(bool)
        info = conflicts(ds[f"observation_holds_{method}"].values.astype(bool), ids)
        if mask.any():
            q, k, m = np.nonzero(mask)
            tp, ap = ds["duration"].values[k], ds["acceleration"].values[m]
            info.update(tp_range_s=(float(tp.min()), float(tp.max())), ap_range_ms2=(float(ap.min()), float(ap.max())),
                        pgv_range_ms=(float((ds.attrs["pulse_beta"] * tp * ap).min()),
                                      float((ds.attrs["pulse_beta"] * tp * ap).max())),
                        azimuths_deg=sorted(set(ds["azimuth"].values[q].tolist())), grid_points=int(mask.sum()))
        out[method] = info
    return out


def write_inference(observed_csv: Path, inventory: Inventory, *, shape: str, config: Config, out_dir: Path,
                    history: str, progress=None) -> tuple[xr.Dataset, Path, Path]:
    """``screen infer``: the observations of ``observed_csv`` against the pulses of ``shape`` (:func:`infer`),
    written to ``out_dir/infer.nc`` and drawn in ``out_dir/infer.png``; the dataset and both paths."""
    from ..report.infer_plot import plot_inference
    from ..store import Family, OutputLock, publish_staged, write_atomic

    ds = infer(read_observations(observed_csv, inventory), shape=shape, config=config, progress=progress)
    ds.attrs["history"] = history
    with OutputLock(out_dir, command=history):         # the two files are published as one set
        out, figure = publish_staged(out_dir, lambda stage: [
            write_atomic(ds, stage / "infer.nc"), plot_inference(ds, stage / "infer.png", g_ms2=config.records.g_ms2)],
            family=Family.INFERENCE, command=history)
    return ds, out, figure
