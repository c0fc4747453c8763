"""The asset-risk report: ``OUT/report.html`` (one self-contained page) and ``OUT/assets.csv``.

Built from the results files alone (``screening.nc``, and next to it
``pulses.nc`` and ``histories.nc`` when present), so ``screen report`` can
regenerate it without the records. Figures are embedded as data URIs (the stability chart a PNG, the
time series SVG, :mod:`pipeline.report.svg`);
the page loads nothing from the network. Tables sort on a click (a few
lines of inline script); the same script marks every figure that rendered
(``data-rendered``) and shows a visible warning for any that did not.

Recommendation rule (per asset; thresholds here). It weighs the probability of overturning under the
declared uncertainty (the largest over the records, when the run sampled) and the simulated margin on the
governing record, and says why in words:

* p >= :data:`P_ANCHOR`, or (without sampling) a simulated margin <= 1: "restrain or anchor" (a margin <= 1
  for an asset that stands under its governing record means the record scaled down overturns it: a window
  of overturning below the nominal amplitude, flagged ``overturns_below_nominal``);
* free flight on the governing record (g + a_v <= 0 before any overturning) and no probability: "no verdict";
* p >= :data:`P_RELOCATE`, a simulated margin <= :data:`RELOCATE_BELOW_SCALE` (<= 1 with p below
  :data:`P_ANCHOR` included), or the paper's criterion says it overturns: "restrain, or relocate";
* the governing scene slides (or the pure-rocking friction demand exceeds mu): "limit sliding";
* otherwise "no action".

Records that are one station recording in other formats or processings
(:func:`pipeline.records.duplicates.same_recordings`) are counted once, as stations, and listed.
"""

from __future__ import annotations

import base64
import hashlib
import logging
import math
from collections import Counter
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import xarray as xr
from markupsafe import Markup, escape

from .. import __version__
from ..constants import M_TO_CM, G
from ..errors import OutputError
from ..margins import P_RELOCATE, RELOCATE_BELOW_SCALE
from ..records.duplicates import RecordingGroup, compared_series, group_compared
from ..rocking.orientation import Orientation
from ..rocking.planner import Physics, Response, guarded_scenes
from ..schema import INVENTORY_PREFIX
from ..store import open_results, ragged_rows, replace_atomically, write_bytes_atomic, write_csv_atomic
from ..uncertainty.robust import Robustness
from . import figures
from .floor_figures import floor_figures

log = logging.getLogger(__name__)

#: A probability of overturning at or above this (under some record) calls for restraint or anchoring [-].
P_ANCHOR = 0.5
# P_RELOCATE (a probability at or above it, the robust-stand bound of the default [uncertainty]) and
# RELOCATE_BELOW_SCALE (a simulated margin at or below it) call for restraint or relocation; they are the margins
# stage's, which keeps a history for every such asset
#: theta(t)/alpha figures drawn, riskiest assets first (all histories stay in histories.nc).
MAX_HISTORY_FIGURES = 60
#: Responses that call for limiting sliding.
SLIDING_RESPONSES = {Response.slide, Response.slide_rock}
RESPONSE_NAMES = {-1: "not simulated", **{m.value: m.name for m in Response}}
PHYSICS_NAMES = {-1: "not simulated", **{m.value: m.name for m in Physics}}
VERDICT = {-1: "n/a", 0: "stands", 1: "overturns"}
ROBUSTNESS_NAMES = {-1: "", **{m.value: m.name for m in Robustness}}

#: Columns of assets.csv; a column named as a screening.nc variable holds that variable (same units: height and
#: width [m], slenderness [rad], frequency_parameter [rad s-1]) for the asset's governing scene, except
#: p_overturn (the worst orientation), its interval, p_overturn_azimuth (the plane it is for [deg]),
#: p_overturn_random_orientation (an unknown orientation) and robustness, which are those of the record with the
#: largest p_overturn (``p_record``). ``stations_*`` count the records of one station recording in several files
#: once (``records_*`` count files). Extra inventory columns follow, as given.
ASSET_COLUMNS = ("rank", "block", "block_name", "site", "height", "width", "mu", "slenderness",
                 "frequency_parameter", "p_overturn", "p_overturn_low", "p_overturn_high", "p_record",
                 "p_overturn_azimuth", "p_overturn_random_orientation", "robustness",
                 "stations_p_half", "records_sensitive", "stations_overturning", "stations_screened",
                 "records_overturning", "records_screened", "governing_record",
                 "governing_azimuth", "verdict_criterion", "verdict_simulation", "theta_max", "response", "physics",
                 "overturn_scale", "overturn_scale_simulated", "overturns_below_nominal", "p_overturn_governing",
                 "overturn_scale_median", "recommendation",
                 "records_overturning_ids", "building", "floor_height_m", "floor_pga_ratio")


def factor_words(x: float) -> str:
    """A factor on a record to the precision that keeps its side of 1 (0.996 is '0.996', never '1.00')."""
    for digits in (2, 3, 4, 6):
        text = f"{x:.{digits}f}"
        if x == 1.0 or (float(text) < 1.0) == (x < 1.0) and float(text) != 1.0:
            return text
    return repr(x)


def _margin_words(sim_scale: float, governing: str) -> str:
    """The simulated margin on the governing record, in words."""
    if not np.isfinite(sim_scale):
        return f"stands under {governing} scaled up to the scan limit" if np.isinf(sim_scale) else "no margin"
    if sim_scale <= 1.0:
        return f"overturns under {governing} x{factor_words(sim_scale)}"
    return f"overturns only with {governing} scaled by {factor_words(sim_scale)}"


def recommendation(*, sim_scale: float, crit_overturns: bool, response: int, overturned: bool = True,
                   p_max: float = math.nan, p_record: str = "", governing: str = "the governing record",
                   stations: tuple[int, int] | None = None, p_words: str = "", slide_m: float = math.nan) -> str:
    """The action for one asset and why, in words (see the module docstring for the rule).

    Parameters
    ----------
    sim_scale : float
        Simulated margin on the governing record: the smallest factor that overturns the asset [-].
    crit_overturns : bool
        The paper's criterion says the governing record overturns it.
    response : int
        Simulated response code of the governing scene.
    overturned : bool
        The governing scene overturns (nominal).
    p_max : float
        The largest probability of overturning over the records (NaN without sampling) [-].
    p_record : str
        The record ``p_max`` is for.
    p_words : str
        ``p_max`` in words, when the caller has more to say (its orientation); default "p = .. under ..".
    slide_m : float
        How far the governing scene slides [m] (NaN: unknown).
    governing : str
        The governing record (the margin's record).
    stations : tuple of int, optional
        (stations whose record overturns the asset, stations screened).
    """
    sampled = np.isfinite(p_max)
    why = [p_words or f"p = {p_max:.2f} under {p_record}"] if sampled else []
    why.append(_margin_words(sim_scale, governing))
    if stations is not None:
        why.append(f"{stations[0]} of {stations[1]} stations overturn it")
    small_margin = np.isfinite(sim_scale) and sim_scale <= RELOCATE_BELOW_SCALE
    if (sampled and p_max >= P_ANCHOR) or (not sampled and np.isfinite(sim_scale) and sim_scale <= 1.0):
        if not sampled and not overturned:
            why.append("it stands under the record itself: overturning is not monotonic in amplitude")
        return "restrain or anchor: " + "; ".join(why)
    if response == Response.free_flight and not sampled:
        return "no verdict: free flight (the ground's g + a_v reached 0 before any overturning)"
    if (sampled and p_max >= P_RELOCATE) or small_margin or crit_overturns:
        if crit_overturns and not small_margin and not (sampled and p_max >= P_RELOCATE):
            why.append("the paper's criterion predicts overturning")
        return "restrain, or relocate: " + "; ".join(why)
    if response in SLIDING_RESPONSES:
        far = f" {slide_m:.2g} m" if np.isfinite(slide_m) else ""
        return f"limit sliding (friction pads or a restraint): it slides{far} under {governing}"
    return "no action: " + "; ".join(why)


def _floor(ds: xr.Dataset, i: int | None, j: int) -> dict:
    """A block's building, floor height [m] and its floor's peak acceleration over the ground's under the governing
    record (empty and NaN on the ground)."""
    building = str(ds["building"].values[j]) if "building" in ds else ""
    ratio = math.nan
    if building and i is not None and "floor_pga" in ds:
        ratio = float(ds["floor_pga"].values[i, j]) / float(ds["pga"].values[i])
    return {"building": building,
            "floor_height_m": float(ds["floor_height"].values[j]) if "floor_height" in ds else math.nan,
            "floor_pga_ratio": ratio}


def _probabilities(ds: xr.Dataset, ok: np.ndarray, j: int, stations: np.ndarray, governing: int | None) -> dict:
    """A block's probabilities of overturning: the largest over the records (with its interval, record and
    robustness class; the governing record when it reaches the largest, so that the two read together), the
    stations with p >= 0.5 and the sensitive scenes. NaN / 0 without sampling."""
    empty = {"p_overturn": np.nan, "p_overturn_low": np.nan, "p_overturn_high": np.nan, "p_record": "",
             "robustness": "", "stations_p_half": 0, "records_sensitive": 0, "p_overturn_azimuth": np.nan,
             "p_overturn_random_orientation": np.nan, "orientation_unknown": False, "p_words": ""}
    if "p_overturn" not in ds:
        return empty
    p = np.where(ok, ds["p_overturn"].values[:, j], np.nan)
    if not np.isfinite(p).any():
        return empty
    i = int(np.nanargmax(p))
    if governing is not None and p[governing] == p[i]:
        i = governing
    robust = ds["robustness"].values[:, j]
    azimuth = float(ds["p_overturn_azimuth"].values[i, j]) if "p_overturn_azimuth" in ds else math.nan
    random = float(ds["p_overturn_random_orientation"].values[i, j]) if "p_overturn_random_orientation" in ds \
        else math.nan
    orientation = int(ds["orientation"].values[i, j])
    unknown = orientation in (Orientation.scanned, Orientation.scanned_relative)
    record = str(ds["record"].values[i])
    words = f"p = {p[i]:.2f} under {record}"
    given = "block_azimuth" in ds and np.isfinite(float(ds["block_azimuth"].values[j]))
    if unknown and np.isfinite(azimuth):
        if orientation == Orientation.scanned_relative:
            # the record's sensors have no known azimuth: a plane is known only relative to its first component
            words += (f" if it faces {azimuth:.0f} deg from the record's first component (its sensors' azimuth is "
                      f"unknown, so {'the given azimuth cannot be used and ' if given else ''}every orientation is "
                      f"scanned; orientation unknown: {random:.2f})")
        else:
            words += f" if it faces {azimuth:.0f} deg (orientation unknown: {random:.2f})"
    return {"p_overturn": float(p[i]), "p_overturn_low": float(ds["p_overturn_low"].values[i, j]),
            "p_overturn_high": float(ds["p_overturn_high"].values[i, j]), "p_record": record,
            "robustness": ROBUSTNESS_NAMES[int(robust[i])],
            "stations_p_half": len(set(stations[ok & (np.nan_to_num(p) >= 0.5)].tolist())),
            "records_sensitive": int(np.sum(ok & (robust == Robustness.sensitive))),
            "p_overturn_azimuth": azimuth, "p_overturn_random_orientation": random, "orientation_unknown": unknown,
            "p_words": words}


def asset_rows(ds: xr.Dataset, *, station_of: dict[str, str] | None = None) -> list[dict]:
    """One row per block, ranked by risk: the largest probability of overturning over the records, then the
    number of stations with p_overturn >= 0.5, then the most stations that overturn it (nominal), the
    smallest simulated margin, the criterion's margin and the largest rotation.

    ``station_of`` maps a record to the record that stands for its station recording (records of one
    recording in several files count once); a record not in it is a station of its own.
    """
    rows = []
    stations = np.array([(station_of or {}).get(r, r) for r in ds["record"].values.tolist()], dtype=object)
    rec_pos = {r: i for i, r in enumerate(ds["record"].values.tolist())}
    ok = ds["status"].values == "ok"
    verdict = ds["overturn"].values if "overturn" in ds else ds["overturn_simulated"].values
    record_ids = ds["record"].values
    extra = [str(n) for n in ds.data_vars if str(n).startswith(INVENTORY_PREFIX)]
    for j, block in enumerate(ds["block"].values.tolist()):
        gov = str(ds["governing_record"].values[j]) if "governing_record" in ds else ""
        i = rec_pos.get(gov)

        def at(name, default=np.nan, i=i, j=j):
            return ds[name].values[i, j] if i is not None else default

        sim_scale = float(ds["overturn_scale_simulated"].values[j])
        crit_scale = float(ds["overturn_scale"].values[j])
        crit = int(at("overturn_criterion", -1))
        sim = int(at("overturn_simulated", -1))
        response = int(at("response", -1))
        slide = float(at("sliding_max"))
        overturning = [str(r) for r in record_ids[ok & (verdict[:, j] == 1)]]
        stations_over = len(set(stations[ok & (verdict[:, j] == 1)].tolist()))
        n_stations = len(set(stations[ok].tolist()))
        probabilities = _probabilities(ds, ok, j, stations, i)
        below = int(ds["overturns_below_nominal"].values[j]) if "overturns_below_nominal" in ds else -1
        rows.append({
            "block": block, "block_name": str(ds["block_name"].values[j]), "site": str(ds["site"].values[j]),
            **_floor(ds, i, j),
            "height": float(ds["height"].values[j]), "width": float(ds["width"].values[j]),
            "corner_distance": float(ds["corner_distance"].values[j]),
            "slenderness": float(ds["slenderness"].values[j]),
            "alpha_deg": math.degrees(float(ds["slenderness"].values[j])),
            "frequency_parameter": float(ds["frequency_parameter"].values[j]), "mu": float(ds["mu"].values[j]),
            "records_overturning": len(overturning), "records_screened": int(ok.sum()),
            "stations_overturning": stations_over, "stations_screened": n_stations,
            "records_overturning_ids": ";".join(overturning),
            "governing_record": gov, "governing_azimuth": float(at("governing_azimuth")),
            "verdict_criterion": VERDICT[crit],
            "verdict_simulation": VERDICT[sim] + (f" (slides {slide:.2g} m)" if response in SLIDING_RESPONSES
                                                  and np.isfinite(slide) and slide > 0 else ""),
            "theta_max": float(at("theta_max")), "response": RESPONSE_NAMES[response],
            "physics": PHYSICS_NAMES[int(at("physics", -1))],
            "overturn_scale": crit_scale, "overturn_scale_simulated": sim_scale, "overturns_below_nominal": below,
            "p_overturn_governing": float(ds["p_overturn_governing"].values[j]) if "p_overturn_governing" in ds
            else np.nan,
            "overturn_scale_median": float(ds["overturn_scale_median"].values[j]) if "overturn_scale_median" in ds
            else np.nan,
            "recommendation": recommendation(sim_scale=sim_scale, crit_overturns=crit == 1, response=response,
                                             overturned=sim == 1, p_max=probabilities["p_overturn"],
                                             p_record=probabilities["p_record"], governing=gov or "the records",
                                             stations=(stations_over, n_stations),
                                             p_words=probabilities["p_words"], slide_m=slide),
            "inventory": {name[len(INVENTORY_PREFIX):]: str(ds[name].values[j]) for name in extra},
            **probabilities,
        })

    def risk(r: dict) -> tuple:
        return (-np.nan_to_num(r["p_overturn"], nan=-1.0), -r["stations_p_half"], -r["stations_overturning"],
                np.nan_to_num(r["overturn_scale_simulated"], nan=np.inf),
                np.nan_to_num(r["overturn_scale"], nan=np.inf), -np.nan_to_num(r["theta_max"], nan=-1.0))

    rows.sort(key=risk)
    for k, r in enumerate(rows, 1):
        r["rank"] = k
    return rows


def write_assets_csv(rows: list[dict], path: Path) -> Path:
    """The per-asset table as CSV (numbers unrounded, inf for 'none up to the scan limit'), then the extra
    inventory columns as given, atomically."""
    extra = list(rows[0]["inventory"]) if rows else []
    table = [{**{c: r[c] for c in ASSET_COLUMNS}, **r["inventory"]} for r in rows]
    return write_csv_atomic(path, ASSET_COLUMNS + tuple(extra), table)


PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


class FigureCache:
    """Figures (PNG or SVG bytes) kept by content: a figure whose data, title and drawing code are unchanged is not
    drawn again (``OUT/.rockscreen/figures``). ``directory=None``: no cache, every figure is drawn.

    Keys hash the figure's kind, the rockscreen version, the arrays' bytes and the title; entries not
    used by the last report are pruned.
    """

    def __init__(self, directory: Path | None):
        self.dir = directory
        self.used: set[str] = set()
        self.drawn = self.reused = 0

    def get(self, kind: str, draw, *arrays, title: str = "") -> bytes:
        """The bytes of ``draw()``, from the cache when the same figure was drawn before."""
        if self.dir is None:
            self.drawn += 1
            return draw()
        h = hashlib.sha256(f"{kind}\n{__version__}\n{title}".encode())
        for a in arrays:
            a = np.ascontiguousarray(a)
            h.update(str((a.dtype.str, a.shape)).encode())
            h.update(a.tobytes())
        path = self.dir / f"{h.hexdigest()[:40]}.fig"
        self.used.add(path.name)
        try:
            png = path.read_bytes()
            if png.startswith((PNG_MAGIC, b"<svg")):
                self.reused += 1
                return png
        except OSError:
            pass
        png = draw()
        self.drawn += 1
        try:
            write_bytes_atomic(path, png)
        except OutputError as exc:   # a full disk for the cache must not stop the report
            log.warning("figure cache %s: %s", self.dir, exc)
        return png

    def prune(self) -> None:
        """Delete the figures this report did not use."""
        if self.dir is None or not self.dir.is_dir():
            return
        for p in self.dir.glob("*.*"):
            if p.name not in self.used:
                p.unlink(missing_ok=True)


def _data_uri(image: bytes) -> str:
    """A data URI of PNG or SVG bytes."""
    mime = "image/png" if image.startswith(PNG_MAGIC) else "image/svg+xml"
    return f"data:{mime};base64," + base64.b64encode(image).decode("ascii")


def _record_rows(ds: xr.Dataset, pulses: xr.Dataset | None, *, all_figures: bool = False,
                 cache: FigureCache | None = None) -> tuple[list[dict], Iterator[tuple[dict, str]]]:
    """One row per record, and the velocity figures of the pulse-like records (of every record with
    ``all_figures``) as a lazy stream of ``(row, data URI)``.

    A figure is read, drawn (or taken from ``cache``) and encoded only when the stream reaches it, so a
    report streamed to its file (:func:`build_report`) holds one record's series and figure at a time,
    whatever the number of records; ``pulses`` must stay open until the stream is consumed.
    """
    cache = cache or FigureCache(None)
    where = {}
    if pulses is not None:
        dts = pulses["dt"].values
        where = {rid: (rows_k, float(dts[k])) for k, (rid, rows_k) in enumerate(ragged_rows(pulses,
                                                                                             "record_id").items())}

    def series(rid: str) -> tuple[np.ndarray, np.ndarray, float]:
        """One record's velocity and pulse, read from the file when its figure is drawn (``pulses`` may be
        opened lazily: the report then holds one record's series at a time)."""
        rows_k, dt = where[rid]
        assert pulses is not None                      # where is empty without pulses
        return (np.asarray(pulses["velocity"][rows_k].values, dtype=float),
                np.asarray(pulses["pulse"][rows_k].values, dtype=float), dt)

    rows = []
    for i, rid in enumerate(ds["record"].values.tolist()):
        def val(name, i=i):
            return ds[name].values[i] if name in ds else np.nan

        is_pulse = int(val("is_pulse")) if np.isfinite(float(val("is_pulse"))) else -1
        label = str(ds["record_label"].values[i]) if "record_label" in ds else ""
        rows.append({"record": rid, "label": "" if label == "nan" else label,
                     "status": str(ds["status"].values[i]), "pga_g": float(val("pga")) / G,
                     "pgv_cms": M_TO_CM * float(val("pgv")), "tp_s": float(val("pulse_period")),
                     "pi": float(val("pulse_indicator")),
                     "pulse": {1: "pulse-like", 0: "non-pulse"}.get(is_pulse, "n/a"),
                     "azimuth_deg": float(val("pulse_azimuth")), "anchor": f"record-{i + 1}",
                     "has_figure": rid in where and (all_figures or is_pulse == 1)})

    def figures_stream() -> Iterator[tuple[dict, str]]:
        for row in rows:
            if row["has_figure"]:
                rid = row["record"]
                v, p, dt = series(rid)
                yield row, _data_uri(cache.get("pulse", lambda v=v, p=p, dt=dt, rid=rid: figures.pulse_figure(
                    v, p, dt, title=rid), v, p, np.array([dt]), title=rid))

    return rows, figures_stream()


def recording_groups(ds: xr.Dataset, pulses: xr.Dataset | None) -> list[RecordingGroup]:
    """The records of ``ds`` that are one station recording in several files (from the velocities in
    ``pulses.nc``; none without it). The record with the most components stands for its group."""
    if pulses is None:
        return []
    ok = dict(zip(ds["record"].values.tolist(), (ds["status"].values == "ok").tolist()))
    dts = pulses["dt"].values
    compared = {rid: compared_series(np.asarray(pulses["velocity"][rows].values, dtype=float), float(dts[k]))
                for k, (rid, rows) in enumerate(ragged_rows(pulses, "record_id").items()) if ok.get(rid)}
    if not compared:
        return []
    counts = [np.nan_to_num(ds[v].values.astype(float)) if v in ds else np.zeros(ds.sizes["record"])
              for v in ("n_horizontal", "has_vertical")]
    n_comp = dict(zip(ds["record"].values.tolist(), (counts[0] + counts[1]).tolist()))
    return group_compared(compared, preference={r: (-int(n_comp.get(r, 0)),) for r in compared})


def _histories(path: Path) -> dict:
    if not path.is_file():
        return {}
    h = open_results(path)
    return {bid: (h["theta_over_alpha"].values[rows].astype(float), float(h["dt"].values[k]),
                  str(h["governing_record"].values[k]))
            for k, (bid, rows) in enumerate(ragged_rows(h, "block_id").items())}


def build_report(results_path: str | Path, out_dir: str | Path | None = None, *,
                 all_figures: bool = False, figure_cache: str | Path | None = None,
                 home: str | Path | None = None) -> tuple[Path, Path]:
    """Write ``report.html`` and ``assets.csv`` next to ``results_path`` (or in ``out_dir``).

    ``home``: the directory the page will be read in, when it is written elsewhere first (a staged output set);
    the fragility page it links to is looked for there (default: ``out_dir``).

    Velocity figures are drawn for the pulse-like records, or for every record with
    ``all_figures``; theta(t) figures for the assets at risk (at most
    :data:`MAX_HISTORY_FIGURES`). With ``figure_cache`` (a directory), a figure whose data and
    title are unchanged since it was last drawn is taken from there (:class:`FigureCache`).

    Raises
    ------
    ResultsError
        If the results file is missing, unreadable, or has no margins (written by a
        rockscreen older than the report).
    """
    from jinja2 import Environment, PackageLoader, select_autoescape

    from ..errors import ResultsError
    results_path = Path(results_path)
    ds = open_results(results_path)
    if "overturn_scale_simulated" not in ds:
        raise ResultsError(f"{results_path}: no margins (overturn_scale_simulated); re-run 'screen' with this "
                           "version to compute them, then 'screen report'")
    out_dir = Path(out_dir) if out_dir is not None else results_path.parent
    out_dir.mkdir(parents=True, exist_ok=True)
    pulses_path = results_path.parent / "pulses.nc"
    # opened lazily (closed below): only the series of the records that get a figure are read
    pulses = xr.open_dataset(pulses_path, engine="netcdf4") if pulses_path.is_file() else None
    cache = FigureCache(Path(figure_cache) if figure_cache is not None else None)
    groups = recording_groups(ds, pulses)
    station_of = {r: grp.kept for grp in groups for r in grp.records}
    assets = asset_rows(ds, station_of=station_of)
    histories = _histories(results_path.parent / "histories.nc")
    drawn = 0
    for r in assets:                       # in risk order: the riskiest assets get the figures
        h = histories.get(r["block"])
        r["figure"] = None
        if h is not None and drawn < MAX_HISTORY_FIGURES:
            title = f"{r['block']} under {h[2]}: theta / alpha"
            r["figure"] = _data_uri(cache.get("theta", lambda h=h, title=title: figures.theta_figure(
                h[0], h[1], title=title), h[0], np.array([h[1]]), title=title))
            drawn += 1
    ok = ds["status"].values == "ok"
    resp = ds["response"].values
    x, y = ds["normalized_duration"].values.ravel(), ds["normalized_acceleration"].values.ravel()
    chart = _data_uri(cache.get("chart", lambda: figures.scenes_chart(x, y, resp.ravel()), x, y, resp.ravel()))
    counts = Counter(r["recommendation"].split(":")[0] for r in assets)
    sampled = "samples_drawn" in ds and bool(np.any(ds["samples_drawn"].values[ok] > 0))
    summary = {
        "records_ok": int(ok.sum()), "records_failed": int((~ok).sum()),
        "stations": len({station_of.get(r, r) for r in ds["record"].values[ok].tolist()}),
        "same_recordings": groups,
        "pulse_like_stations": len({station_of.get(r, r) for r in ds["record"].values[
            ok & (ds["is_pulse"].values == 1)].tolist()}) if "is_pulse" in ds else 0,
        "fragility": _fragility_summary(Path(home) if home is not None else out_dir),
        "failures": [(rid, st) for rid, st in zip(ds["record"].values, ds["status"].values) if st != "ok"],
        "pulse_like": int(np.sum(ds["is_pulse"].values[ok] == 1)) if "is_pulse" in ds else 0,
        "blocks": ds.sizes["block"],
        "overturn_simulation": sum(r["verdict_simulation"] == "overturns" for r in assets),
        "overturn_criterion": sum(r["verdict_criterion"] == "overturns" for r in assets),
        "by_recommendation": counts.most_common(),
        "scenes": int(ok.sum()) * ds.sizes["block"],
        "free_flight": int(np.sum(resp[ok] == Response.free_flight)),
        "free_flight_records": [str(r) for r in ds["record"].values[ok][
            np.any(resp[ok] == Response.free_flight, axis=1)]],
        "guarded": guarded_scenes(ds["simulation_guard"].values, ds["record"].values, ds["block"].values)
        if "simulation_guard" in ds else [],
        "histories": len(histories), "histories_drawn": drawn, "all_figures": all_figures,
        "sampled": sampled,
        "sensitive_scenes": int(np.sum(ds["robustness"].values[ok] == Robustness.sensitive)) if sampled else 0,
        "uncertainty": {k[len("uncertainty_"):]: v for k, v in ds.attrs.items() if k.startswith("uncertainty_")},
    }
    env = Environment(loader=PackageLoader("pipeline.report", "templates"),
                      autoescape=select_autoescape(["html", "j2"]))
    env.filters["num"] = _num
    env.filters["breakable"] = breakable
    records, record_figures = _record_rows(ds, pulses, all_figures=all_figures, cache=cache)
    floors = floor_figures(assets, pulses, pulses_path, lambda *a, **k: _data_uri(cache.get(*a, **k)))
    stream = env.get_template("report.html.j2").stream(
        title=ds.attrs.get("title", "rockscreen"), attrs=ds.attrs, summary=summary, assets=assets,
        records=records, record_figures=record_figures, chart=chart, floor_figures=floors)
    try:        # streamed to the file: the record figures are drawn and written one at a time
        html_path = replace_atomically(out_dir / "report.html",
                                       lambda tmp: stream.dump(tmp, encoding="utf-8"))
    finally:
        if pulses is not None:
            pulses.close()
    cache.prune()
    return html_path, write_assets_csv(assets, out_dir / "assets.csv")


#: Where the report looks for what ``screen fragility`` wrote, relative to its own directory: the same output, or
#: the fragility command's default ``fragility/`` inside it
FRAGILITY_PLACES = (".", "fragility")


def breakable(text) -> Markup:
    """``text`` escaped, with a line-break opportunity after each underscore, so that a long record id wraps
    between its parts rather than inside a name."""
    return Markup(str(escape(str(text))).replace("_", "_<wbr>"))


def _fragility_summary(out_dir: Path) -> dict | None:
    """What ``screen fragility`` wrote into the same output (or its ``fragility/``), for the report's banner and
    link (None when nothing)."""
    for place in FRAGILITY_PLACES:
        path = out_dir / place / "fragility.nc"
        if not (out_dir / place / "fragility.html").is_file() or not path.is_file():
            continue
        try:
            with xr.open_dataset(path, engine="netcdf4") as f:
                return {"hazard": str(f.attrs.get("hazard_curve", "")), "title": str(f.attrs.get("hazard_title", "")),
                        "synthetic": bool(int(f.attrs.get("hazard_synthetic", 0))), "im": str(f.attrs.get("im", "")),
                        "href": "fragility.html" if place == "." else f"{place}/fragility.html"}
        except (OSError, ValueError):
            continue
    return None


def _num(x, digits: int = 3) -> str:
    """A number for a table cell: '' for NaN, 'none up to the limit' for inf."""
    try:
        x = float(x)
    except (TypeError, ValueError):
        return str(x)
    if math.isnan(x):
        return ""
    if math.isinf(x):
        return "> limit"
    return f"{x:.{digits}g}"
