"""The asset-risk report: ``OUT/report.html`` (one self-contained page) and ``OUT/assets.csv``.

Built from the results files alone (``screening.nc``, and next to it
``pulses.nc`` and ``histories.nc`` when present), so ``screen report`` can
regenerate it without the records. Figures are embedded as data URIs (the stability chart a PNG, the
time series SVG, :mod:`pipeline.report.svg`);
the page loads nothing from the network. Tables sort on a click (a few
lines of inline script); the same script marks every figure that rendered
(``data-rendered``) and shows a visible warning for any that did not.

The assets, their ranking and their recommendations come from :mod:`pipeline.risk`.

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
from ..config import CRITERION_MEASURED_MISSES, sampling_of, tier_of
from ..constants import M_TO_CM, G
from ..errors import OutputError
from ..records.duplicates import RecordingGroup, compared_series, group_compared
from ..risk import asset_rows, assets_csv_table, scenes_without_verdict
from ..rocking.block import ShapeKind
from ..rocking.orientation import Orientation
from ..rocking.planner import Response, guarded_scenes
from ..scene_table import SCENE
from ..store import open_results, ragged_rows, replace_atomically, write_bytes_atomic, write_csv_atomic
from ..uncertainty.robust import Robustness
from . import figures
from .decisions import first_screen, tally
from .floor_figures import floor_figures

log = logging.getLogger(__name__)

#: theta(t)/alpha figures drawn, riskiest assets first (all histories stay in histories.nc).
MAX_HISTORY_FIGURES = 60
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
    assets = asset_rows(ds, station_of=station_of, criterion_only=tier_of(ds.attrs) == "criterion")
    histories = _histories(results_path.parent / "histories.nc")
    drawn = _theta_figures(assets, histories, cache)
    resp = ds[SCENE.response].values
    x, y = ds["normalized_duration"].values.ravel(), ds["normalized_acceleration"].values.ravel()
    chart = _data_uri(cache.get("chart", lambda: figures.scenes_chart(x, y, resp.ravel()), x, y, resp.ravel()))
    summary = _summary(ds, assets, groups, station_of, fragility=_fragility_summary(
        Path(home) if home is not None else out_dir), histories=len(histories), drawn=drawn, all_figures=all_figures)
    env = Environment(loader=PackageLoader("pipeline.report", "templates"),
                      autoescape=select_autoescape(["html", "j2"]))
    env.filters["num"] = _num
    env.filters["breakable"] = breakable
    records, record_figures = _record_rows(ds, pulses, all_figures=all_figures, cache=cache)
    floors = floor_figures(assets, pulses, pulses_path, lambda *a, **k: _data_uri(cache.get(*a, **k)))
    stream = env.get_template("report.html.j2").stream(
        title=ds.attrs.get("title", "rockscreen"), attrs=ds.attrs, summary=summary, assets=assets,
        decisions=first_screen(assets), decision_tally=tally(assets), more_assets=len(assets),
        records=records, record_figures=record_figures, chart=chart, floor_figures=floors)
    try:        # streamed to the file: the record figures are drawn and written one at a time
        html_path = replace_atomically(out_dir / "report.html",
                                       lambda tmp: stream.dump(tmp, encoding="utf-8"))
    finally:
        if pulses is not None:
            pulses.close()
    cache.prune()
    return html_path, write_csv_atomic(out_dir / "assets.csv", *assets_csv_table(assets))


def _theta_figures(assets: list[dict], histories: dict, cache: FigureCache) -> int:
    """theta(t)/alpha figures of the assets at risk, in risk order (the riskiest get them, at most
    :data:`MAX_HISTORY_FIGURES`), as each row's ``figure``; the number drawn."""
    drawn = 0
    for r in assets:
        h = histories.get(r["block"])
        r["figure"] = None
        if h is not None and drawn < MAX_HISTORY_FIGURES:
            title = f"{r['block']} under {h[2]}: theta / alpha"
            r["figure"] = _data_uri(cache.get("theta", lambda h=h, title=title: figures.theta_figure(
                h[0], h[1], title=title), h[0], np.array([h[1]]), title=title))
            drawn += 1
    return drawn


def _summary(ds: xr.Dataset, assets: list[dict], groups, station_of: dict, *, fragility, histories: int,
             drawn: int, all_figures: bool) -> dict:
    """The numbers the page's summary states: records, stations, verdicts, recommendations, free flights, guards,
    figures and the sampling."""
    ok = ds["status"].values == "ok"
    resp = ds[SCENE.response].values
    counts = Counter(r["recommendation"].split(":")[0] for r in assets)
    sampled = sampling_of(ds.attrs)
    criterion_only = tier_of(ds.attrs) == "criterion"
    return {
        "records_ok": int(ok.sum()), "records_failed": int((~ok).sum()),
        "stations": len({station_of.get(r, r) for r in ds["record"].values[ok].tolist()}),
        "same_recordings": groups,
        "pulse_like_stations": len({station_of.get(r, r) for r in ds["record"].values[
            ok & (ds["is_pulse"].values == 1)].tolist()}) if "is_pulse" in ds else 0,
        "fragility": fragility,
        "failures": [(rid, st) for rid, st in zip(ds["record"].values, ds["status"].values) if st != "ok"],
        "units_toml": str(ds.attrs.get("units_toml", "")), "units_toml_path": str(ds.attrs.get("units_toml_path", "")),
        "pulse_like": int(np.sum(ds["is_pulse"].values[ok] == 1)) if "is_pulse" in ds else 0,
        "blocks": ds.sizes["block"],
        "boxes": planar_boxes(ds),
        "box_scenes_3d": int(np.sum(ds[SCENE.orientation].values[ok] == Orientation.given_3d)),
        "box_scenes_certified": int(np.sum(ds[SCENE.orientation].values[ok] == Orientation.given_certified)),
        "overturn_simulation": sum(r["verdict_simulation"] == "overturns" for r in assets),
        "overturn_criterion": sum(r["verdict_criterion"] == "overturns" for r in assets),
        "by_recommendation": counts.most_common(),
        "scenes": int(ok.sum()) * ds.sizes["block"],
        "free_flight_scenes": int(np.sum(resp[ok] == Response.free_flight)),
        "unjudged_assets": sum(1 for r in assets if r["stations_without_verdict"] or r["draws_without_verdict"]),
        "unjudged_scenes": scenes_without_verdict(ds),
        "unjudged_samples": sum(r["draws_without_verdict"] for r in assets),
        "draws": sum(r["draws"] for r in assets),
        "criterion_only": criterion_only, "criterion_misses": CRITERION_MEASURED_MISSES,
        "free_flight_records": [str(r) for r in ds["record"].values[ok][
            np.any(resp[ok] == Response.free_flight, axis=1)]],
        "guarded": guarded_scenes(ds[SCENE.simulation_guard].values, ds["record"].values, ds["block"].values)
        if SCENE.simulation_guard in ds else [],
        "histories": histories, "histories_drawn": drawn, "all_figures": all_figures,
        "sampled": sampled,
        "sensitive_scenes": int(np.sum(ds[SCENE.robustness].values[ok] == Robustness.sensitive)) if sampled else 0,
        "uncertainty": {k[len("uncertainty_"):]: v for k, v in ds.attrs.items() if k.startswith("uncertainty_")},
    }


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
    """A number for a table cell: '' for NaN, '> limit' for inf (a margin scan that reached its limit)."""
    try:
        x = float(x)
    except (TypeError, ValueError):
        return str(x)
    if math.isnan(x):
        return ""
    if math.isinf(x):
        return "> limit"
    return f"{x:.{digits}g}"


def planar_boxes(ds) -> int:
    """The boxes whose other base axis is never checked: without a depth or an azimuth (judged in the plane of their
    width; a box with both is simulated in 3D on two horizontals of known azimuth)."""
    if "shape" not in ds:
        return int(ds.sizes["block"])
    box = ds["shape"].values == ShapeKind.box
    in_3d = np.isfinite(ds["depth"].values) & np.isfinite(ds["block_azimuth"].values)
    return int(np.sum(box & ~in_3d))
