"""Hazard curves as the tools export them: OpenQuake CSV, the USGS NSHM web service's JSON, and a plain CSV.

Every reader returns a :class:`~.hazard.HazardCurve` in SI units and annual rates, with the IM, its
horizontal component definition, Sa's period and the site it is for, and what was done to the
numbers (``notes``):

* **OpenQuake** ``hazard_curve-*.csv`` (``oq export hcurves``): a metadata line
  (``kind``, ``investigation_time``, ``imt``), then ``[custom_site_id,]lon,lat,depth,poe-<iml>...``, one
  row per site. Values are probabilities of exceedance in ``investigation_time`` T years, converted to
  annual rates by the Poisson relation lambda = -ln(1 - poe) / T. The site is chosen by
  ``custom_site_id`` or as the nearest to a given lon/lat; a file of several sites with none chosen is an
  error that lists them. PGA and SA are in g, PGV in cm/s. The models behind such curves predict a
  median-direction component: the curve is taken as RotD50 unless another is stated.
* **USGS NSHM** service JSON: ``response.hazardCurves[]`` with ``imt.value`` (``PGA``, ``SA1P0``, ``PGV``) and
  ``data[{"component": "Total", "values": {"xs", "ys"}}]``, ys already annual rates; the legacy
  ``response[].metadata.xvalues`` / ``data[].yvalues`` layout too. Components: RotD50, or RotD100 where the
  request asked for ``maxdir``.
* **Plain CSV**: ``<im>_<unit>[_<component>],annual_rate`` (``pga_g_rotd50,annual_rate``; Sa as
  ``sa(1.0)_g``), comment lines starting with ``#``.

Exact zeros and flat stretches are data: a rate of 0 ends the curve (nothing exceeds the levels from
there); equal rates make a flat segment, which adds nothing to the integral; a probability of exceedance
of 1 (an infinite rate, a saturated low level) is dropped. Each is said in ``notes``.

References
----------
Pagani, M. et al. (2014). OpenQuake engine: an open hazard (and risk) software for the Global Earthquake
Model. Seismol. Res. Lett. 85(3), 692-702 (the hazard-curve export). Boore, D. M. (2010). Orientation-
independent, nongeometric-mean measures of seismic intensity from two horizontal components of motion.
BSSA 100(4), 1830-1835 (RotD50, RotD100).
"""

from __future__ import annotations

import csv
import json
import math
import re
from pathlib import Path

import numpy as np

from ..constants import G
from ..errors import HazardError
from .hazard import IM_KIND, UNITS, Component, HazardCurve

#: OpenQuake's and the USGS service's IMT names -> (rockscreen IM, unit factor to SI).
IMT_UNITS = {"PGA": ("pga", G), "PGV": ("pgv", 0.01), "SA": ("sa", G)}
#: Earth radius for the nearest site [km].
EARTH_RADIUS_KM = 6371.0
#: How many choices an ambiguity error lists.
SHOWN = 12


def read_hazard(path: str | Path, *, im: str, site: str | None = None, lonlat: tuple[float, float] | None = None,
                period_s: float | None = None, component: Component | None = None) -> HazardCurve:
    """Read a hazard curve for ``im`` from an OpenQuake CSV, a USGS JSON or a plain CSV (the module's formats).

    Parameters
    ----------
    path : path
        The file.
    im : str
        The IM wanted (``pga``, ``pgv``, ``sa``, ...).
    site : str, optional
        OpenQuake ``custom_site_id`` of the site wanted.
    lonlat : (float, float), optional
        Longitude and latitude [deg] of the site wanted: the nearest site of the file is taken.
    period_s : float, optional
        Sa's period [s], where the file holds several.
    component : Component, optional
        The horizontal component definition of the curve, stated by the user (overrides the format's).

    Raises
    ------
    HazardError
        For an unreadable file, an unknown layout, an IM the file does not hold, several sites or IMs
        and no choice among them (the error lists them), values that are not numbers, levels that do not
        increase or rates that increase.
    """
    path = Path(path)
    if im not in IM_KIND:
        raise HazardError(f"{path}: a hazard curve for IM {im!r} is not supported; supported: {sorted(IM_KIND)}")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as exc:
        raise HazardError(f"{path}: cannot read the hazard curve ({exc.strerror or exc})") from exc
    stripped = text.lstrip()
    if stripped.startswith(("{", "[")):
        curve = _usgs(path, text, im=im, period_s=period_s)
    elif _is_openquake(text):
        curve = _openquake(path, text, im=im, site=site, lonlat=lonlat, period_s=period_s)
    else:
        curve = _plain(path, text, im=im)
    if component is not None:
        curve = curve.with_component(component, stated=True)
    return curve


def _is_openquake(text: str) -> bool:
    first = next((ln for ln in text.splitlines() if ln.strip()), "")
    return first.startswith("#,") and "imt=" in first or any(
        c.strip().startswith("poe-") for c in first.split(","))


def _imt(name: str, path: Path) -> tuple[str, float, float]:
    """(IM, factor to SI, period [s] or NaN) of an OpenQuake (``SA(0.5)``) or USGS (``SA0P5``) IMT name."""
    m = re.fullmatch(r"SA\(([\d.]+)\)|SA(\d+)P(\d+)|(PGA|PGV)", name.strip().upper())
    if not m:
        raise HazardError(f"{path}: IMT {name!r} is not one rockscreen can use; it reads PGA, PGV and SA(T)")
    if m.group(4):
        im, factor = IMT_UNITS[m.group(4)]
        return im, factor, math.nan
    period = float(m.group(1)) if m.group(1) else float(f"{m.group(2)}.{m.group(3)}")
    return "sa", G, period


def _finish(path: Path, im: str, levels, rates, *, notes: list[str], **kw) -> HazardCurve:
    """Check the curve's order, drop saturated levels, end it at a zero rate."""
    levels, rates = np.asarray(levels, dtype=float), np.asarray(rates, dtype=float)
    if np.any(~np.isfinite(levels)) or np.any(levels <= 0):
        raise HazardError(f"{path}: IM levels must be positive numbers; found {levels[~(levels > 0)][:3].tolist()}")
    if np.any(np.diff(levels) <= 0):
        k = int(np.flatnonzero(np.diff(levels) <= 0)[0]) + 1
        raise HazardError(f"{path}: IM level {levels[k]:g} (point {k + 1}) does not increase; the levels must "
                          "increase")
    if np.any(np.isnan(rates)) or np.any(rates < 0):
        raise HazardError(f"{path}: rates of exceedance must be numbers >= 0; found "
                          f"{rates[np.isnan(rates) | (rates < 0)][:3].tolist()}")
    finite = np.isfinite(rates)
    if not finite.all():
        notes.append(f"{int(np.sum(~finite))} level(s) with a probability of exceedance of 1 (saturated) dropped")
        levels, rates = levels[finite], rates[finite]
    if np.any(np.diff(rates) > 0):
        k = int(np.flatnonzero(np.diff(rates) > 0)[0]) + 1
        raise HazardError(f"{path}: the rate at level {levels[k]:g} ({rates[k]:.4g}) exceeds the one below it "
                          f"({rates[k - 1]:.4g}); rates of exceedance cannot increase with the level")
    zero = np.flatnonzero(rates == 0)
    if zero.size:
        unit = "g" if IM_KIND[im] == "acceleration" else "cms"                          # the pages' units
        factor = UNITS[IM_KIND[im]][unit]
        notes.append(f"the rate reaches 0 at {levels[zero[0]] / factor:.4g} {unit}: the curve ends there "
                     f"({levels.size - zero[0]} level(s) of rate 0)")
        levels, rates = levels[:zero[0]], rates[:zero[0]]
        kw["ended_at_zero"] = True
    flat = int(np.sum(np.diff(rates) == 0))
    if flat:
        notes.append(f"{flat} flat segment(s) (equal rates) add nothing to the integral")
    if levels.size < 2:
        raise HazardError(f"{path}: {levels.size} usable point(s) with a positive rate; a hazard curve needs at "
                          "least 2")
    return HazardCurve(im, levels, rates, str(path), notes=tuple(notes), **kw)


def _plain(path: Path, text: str, *, im: str) -> HazardCurve:
    lines = [(k, ln) for k, ln in enumerate(text.splitlines(), 1) if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise HazardError(f"{path}: empty hazard curve; expected a header '{im}_<unit>,annual_rate' and rows")
    head_no, head = lines[0]
    cols = [c.strip().lower() for c in next(csv.reader([head]))]
    units = UNITS[IM_KIND[im]]
    pattern = rf"{re.escape(im)}(?:\(([\d.]+)\))?_({'|'.join(units)})(?:_({'|'.join(c.value for c in Component)}))?"
    m = re.fullmatch(pattern, cols[0]) if cols else None
    expected = (f"'{im}_<unit>[_<component>],annual_rate' with <unit> one of {sorted(units)} and <component> one "
                f"of {[c.value for c in Component]}" + (" (Sa as sa(1.0)_g)" if im == "sa" else ""))
    if len(cols) < 2 or cols[1] != "annual_rate" or not m:
        raise HazardError(f"{path}, line {head_no}: header {head.strip()!r}; expected {expected}")
    factor = units[m.group(2)]
    levels: list[float] = []
    rates: list[float] = []
    for no, line in lines[1:]:
        row = next(csv.reader([line]))
        if len(row) < 2:
            raise HazardError(f"{path}, line {no}: {line.strip()!r}; expected two values: level,annual_rate")
        values = []
        for name, value in zip(cols[:2], row[:2]):
            try:
                values.append(float(value))
            except ValueError:
                raise HazardError(f"{path}, line {no}: {name} = {value.strip()!r} is not a number") from None
        level, rate = values
        if not (math.isfinite(level) and level > 0):
            raise HazardError(f"{path}, line {no}: {cols[0]} = {row[0].strip()!r}; expected a positive number")
        if not (math.isfinite(rate) and rate >= 0):
            raise HazardError(f"{path}, line {no}: annual_rate = {row[1].strip()!r}; expected a number >= 0")
        if levels and level * factor <= levels[-1]:
            raise HazardError(f"{path}, line {no}: {cols[0]} = {row[0].strip()} does not increase; the levels "
                              "must increase down the file")
        if rates and rate > rates[-1]:
            raise HazardError(f"{path}, line {no}: annual_rate = {row[1].strip()} increases; rates of exceedance "
                              "cannot increase with the level (equal rates are a flat stretch, 0 ends the curve)")
        levels.append(level * factor)
        rates.append(rate)
    comments = [ln.strip().lstrip("#").strip() for ln in text.splitlines()[:head_no - 1]
                if ln.lstrip().startswith("#")]
    title = " ".join(c for c in comments if c)
    component = Component(m.group(3)) if m.group(3) else None
    return _finish(path, im, levels, rates, notes=[], title=title, synthetic="synthetic" in title.lower(),
                   units=m.group(2), component=component, component_stated=component is not None,
                   period_s=float(m.group(1)) if m.group(1) else math.nan, source_format="csv")


def _openquake_metadata(line: str) -> dict[str, str]:
    fields = next(csv.reader([line]))
    meta = fields[-1] if fields else ""
    return {k: (v1 if v1 else v2).strip() for k, v1, v2 in re.findall(r"(\w+)=(?:'([^']*)'|([^,]*))", meta)}


def _openquake(path: Path, text: str, *, im: str, site, lonlat, period_s) -> HazardCurve:
    lines = [ln for ln in text.splitlines() if ln.strip()]
    meta = _openquake_metadata(lines[0]) if lines[0].startswith("#") else {}
    body = lines[1:] if lines[0].startswith("#") else lines
    if not body:
        raise HazardError(f"{path}: an OpenQuake hazard-curve file with no header or rows")
    header = [c.strip() for c in next(csv.reader([body[0]]))]
    poe_cols = [k for k, c in enumerate(header) if c.startswith("poe-")]
    if not poe_cols or "lon" not in header or "lat" not in header:
        raise HazardError(f"{path}: header {body[0]!r}; expected OpenQuake's '[custom_site_id,]lon,lat,depth,"
                          "poe-<level>,...'")
    imt_name = meta.get("imt") or _imt_from_name(path)
    file_im, factor, file_period = _imt(imt_name, path)
    if file_im != im:
        raise HazardError(f"{path}: holds IMT {imt_name}, not {im}; run with --im {file_im} or give the "
                          f"{im.upper()} curve")
    if im == "sa" and period_s is not None and not math.isclose(period_s, file_period, rel_tol=1e-6):
        raise HazardError(f"{path}: holds SA({file_period:g}), not SA({period_s:g})")
    try:
        T = float(meta["investigation_time"])
    except (KeyError, ValueError):
        raise HazardError(f"{path}: no investigation_time in the metadata line {lines[0]!r}; OpenQuake writes it "
                          "there (the probabilities are for that many years)") from None
    rows = [next(csv.reader([ln])) for ln in body[1:]]
    sid = header.index("custom_site_id") if "custom_site_id" in header else None
    lon_k, lat_k = header.index("lon"), header.index("lat")
    choice, label = _choose_site(path, rows, sid, lon_k, lat_k, site=site, lonlat=lonlat)
    row = rows[choice]
    levels = [float(header[k][4:]) * factor for k in poe_cols]
    try:
        poes = np.array([float(row[k]) for k in poe_cols])
    except (ValueError, IndexError):
        raise HazardError(f"{path}: site {label}: a probability that is not a number in {row!r}") from None
    if np.any((poes < 0) | (poes > 1)):
        raise HazardError(f"{path}: site {label}: probabilities of exceedance must lie in [0, 1]")
    with np.errstate(divide="ignore"):
        rates = -np.log1p(-poes) / T                                       # Poisson: lambda = -ln(1 - poe) / T
    notes = [f"OpenQuake {meta.get('kind', '')} curve, site {label}, probabilities in {T:g} years converted to "
             "annual rates by -ln(1 - poe) / T"]
    title = f"OpenQuake {meta.get('kind', 'hazard')} curve, {imt_name}, site {label}"
    return _finish(path, im, levels, rates, notes=notes, title=title, units="g" if im != "pgv" else "cms",
                   component=Component.rotd50, component_stated=False, period_s=file_period, site=label,
                   source_format="openquake", investigation_time_yr=T,
                   site_row=(row[sid].strip() if sid is not None else "", row[lon_k].strip(), row[lat_k].strip(),
                             row[header.index("depth")].strip() if "depth" in header else "0.00000"))


def _imt_from_name(path: Path) -> str:
    m = re.search(r"(SA\([\d.]+\)|PGA|PGV)", path.name)
    if not m:
        raise HazardError(f"{path}: neither the metadata line nor the file name names the IMT")
    return m.group(1)


def _choose_site(path: Path, rows: list, sid, lon_k, lat_k, *, site, lonlat) -> tuple[int, str]:
    def name(k):
        return rows[k][sid] if sid is not None else f"lon {rows[k][lon_k]}, lat {rows[k][lat_k]}"

    if site is not None:
        if sid is None:
            raise HazardError(f"{path}: --hazard-site {site!r} given, but the file has no custom_site_id column; "
                              "choose by --hazard-lonlat")
        hits = [k for k, r in enumerate(rows) if r[sid].strip() == site]
        if not hits:
            raise HazardError(f"{path}: no site {site!r}; sites: "
                              + ", ".join(name(k) for k in range(min(len(rows), SHOWN))))
        return hits[0], name(hits[0])
    if lonlat is not None:
        lon = np.radians([float(r[lon_k]) for r in rows])
        lat = np.radians([float(r[lat_k]) for r in rows])
        lo, la = math.radians(lonlat[0]), math.radians(lonlat[1])
        d = 2 * EARTH_RADIUS_KM * np.arcsin(np.sqrt(np.sin((lat - la) / 2) ** 2
                                                    + np.cos(lat) * math.cos(la) * np.sin((lon - lo) / 2) ** 2))
        k = int(np.argmin(d))
        return k, f"{name(k)} ({d[k]:.2f} km from the given point)"
    if len(rows) == 1:
        return 0, name(0)
    shown = ", ".join(name(k) for k in range(min(len(rows), SHOWN))) + (", ..." if len(rows) > SHOWN else "")
    raise HazardError(f"{path}: {len(rows)} sites and none chosen; choose one with --hazard-site ID "
                      f"(custom_site_id) or --hazard-lonlat LON,LAT. Sites: {shown}")


def _usgs(path: Path, text: str, *, im: str, period_s) -> HazardCurve:
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise HazardError(f"{path}: not valid JSON ({exc}); expected the USGS hazard service's response") from None
    resp = doc.get("response") if isinstance(doc, dict) else None
    curves: list[tuple[str, list, list]] = []                   # (imt name, xs, ys)
    if isinstance(resp, dict) and "hazardCurves" in resp:
        for hc in resp["hazardCurves"]:
            imt = hc.get("imt", {})
            name = str(imt.get("value", "")) if isinstance(imt, dict) else str(imt)
            total = [d for d in hc.get("data", []) if str(d.get("component", "")).lower() == "total"]
            if total:
                curves.append((name, total[0]["values"]["xs"], total[0]["values"]["ys"]))
    elif isinstance(resp, list):
        for r in resp:
            md = r.get("metadata", {})
            imt = md.get("imt", {})
            name = str(imt.get("value", "")) if isinstance(imt, dict) else str(imt)
            total = [d for d in r.get("data", []) if str(d.get("component", "")).lower() == "total"]
            if total:
                curves.append((name, md["xvalues"], total[0]["yvalues"]))
    if not curves:
        raise HazardError(f"{path}: no 'Total' hazard curve found; expected the USGS service's "
                          "response.hazardCurves[].data[{component: 'Total', values: {xs, ys}}]")
    wanted = []
    for name, xs, ys in curves:
        file_im, factor, period = _imt(name, path)
        if file_im == im and (period_s is None or math.isnan(period) or math.isclose(period, period_s, rel_tol=1e-6)):
            wanted.append((name, factor, period, xs, ys))
    names = [c[0] for c in curves]
    if not wanted:
        raise HazardError(f"{path}: no {im.upper()} curve; the file holds {', '.join(names)}")
    if len(wanted) > 1:
        raise HazardError(f"{path}: {len(wanted)} {im.upper()} curves ({', '.join(w[0] for w in wanted)}); choose "
                          "one with --hazard-period SECONDS")
    name, factor, period, xs, ys = wanted[0]
    request = doc.get("request", {}) if isinstance(doc, dict) else {}
    maxdir = bool(request.get("maxdir", False)) if isinstance(request, dict) else False
    component = Component.rotd100 if maxdir else Component.rotd50
    levels = np.asarray(xs, dtype=float) * factor
    return _finish(path, im, levels, np.asarray(ys, dtype=float), notes=[f"USGS {name} curve (Total)"],
                   title=f"USGS hazard curve, {name}" + (", maximum direction" if maxdir else ""),
                   units="g" if im != "pgv" else "cms", component=component, component_stated=True,
                   period_s=period, source_format="usgs")
