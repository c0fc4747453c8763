"""A ShakeMap grid (``grid.xml``, ShakeMap 3.5 and 4) read into SI medians and log standard deviations, and the
shaking at a site by bilinear interpolation of ln IM.

The grid's values are medians (exp of the mean of ln IM); its STD fields are standard deviations of the natural
log, so they do not depend on the unit. Unit strings are read, never assumed: ShakeMap 3.5 writes ``pctg`` (percent
of g) and ``cms`` (cm/s), ShakeMap 4 ``%g`` and ``cm/s``; a log field says ``ln(pctg)`` or ``ln(g)``.

References
----------
Worden, C. B., Thompson, E. M., Hearne, M. & Wald, D. J. (2020). ShakeMap Manual Online: technical manual, user's
guide, and software guide. U.S. Geological Survey (the grid.xml format, the medians, the uncertainty fields).
"""

from __future__ import annotations

import dataclasses
import gzip
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..constants import G
from ..errors import RockscreenError
from .assets import convolved

#: The grid's namespace
NAMESPACE = "{http://earthquake.usgs.gov/eqcenter/shakemap}"
#: Unit string -> factor to SI, for the median fields (accelerations to m s-2, velocities to m s-1)
MEDIAN_UNITS = {"pctg": 0.01 * G, "%g": 0.01 * G, "g": G, "cms": 0.01, "cm/s": 0.01, "ms": 1.0, "m/s": 1.0}
#: Unit strings of a log standard deviation (the same number in any unit of the IM)
LOG_UNITS = ("ln(pctg)", "ln(%g)", "ln(g)", "ln(cms)", "ln(cm/s)", "ln(m/s)", "ln(ms)")
#: ShakeMap's IM fields rockscreen reads, and the STD field of each
IM_FIELDS = {"PGA": "STDPGA", "PGV": "STDPGV", "PSA03": "STDPSA03", "PSA10": "STDPSA10", "PSA30": "STDPSA30"}
#: The period of each PSA field [s]
PSA_PERIODS = {"PSA03": 0.3, "PSA10": 1.0, "PSA30": 3.0}
#: A median below this fraction of its unit is taken as this, so that its log is finite [-]
FLOOR = 1e-6


class ShakeMapError(RockscreenError, ValueError):
    """A ShakeMap file that cannot be read as a grid (the message names the file and what is wrong)."""


@dataclass(frozen=True)
class ShakeMapGrid:
    """A ShakeMap grid: its event, the nodes and each field.

    Attributes
    ----------
    event_id, version : str
        The event id and ShakeMap version (``shakemap_version``).
    event : dict
        The ``event`` element's attributes (magnitude, depth, lat, lon, event_timestamp, event_description).
    attrs : dict
        The root element's attributes (map_status, shakemap_event_type, process_timestamp, ...).
    lon, lat : ndarray
        The nodes' longitudes (increasing) and latitudes (increasing) [deg].
    medians : dict
        IM name (``PGA``, ``PGV``, ``PSA03``, ...) -> median at the nodes, shape (nlat, nlon), SI [m s-2, m s-1].
    log_sd : dict
        IM name -> standard deviation of ln IM at the nodes, shape (nlat, nlon) [-], where the grid has it.
    units : dict
        Field name -> the unit string the file gives.
    """

    event_id: str
    version: str
    event: dict
    attrs: dict
    lon: np.ndarray
    lat: np.ndarray
    medians: dict
    log_sd: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)
    #: IM name -> where its log standard deviation came from: "grid" (an STD field of grid.xml) or "uncertainty"
    #: (the uncertainty.xml given)
    log_sd_source: dict = field(default_factory=dict)

    def contains(self, lon: float, lat: float) -> bool:
        """True when (lon, lat) lies within the grid's nodes."""
        return bool(self.lon[0] <= lon <= self.lon[-1] and self.lat[0] <= lat <= self.lat[-1])


def read_grid(path: str | Path, *, uncertainty: str | Path | None = None) -> ShakeMapGrid:
    """Read a ShakeMap ``grid.xml`` (and, optionally, its ``uncertainty.xml``, whose STD fields are taken where the
    grid has none).

    Raises
    ------
    ShakeMapError
        For a file that is not a ShakeMap grid, a unit it does not know, or data that do not fill a grid.
    """
    grid = _read(Path(path))
    grid = dataclasses.replace(grid, log_sd_source={im: "grid" for im in grid.log_sd})
    if uncertainty is not None:
        extra = _read(Path(uncertainty))
        if extra.lon.shape != grid.lon.shape or extra.lat.shape != grid.lat.shape \
                or not (np.allclose(extra.lon, grid.lon) and np.allclose(extra.lat, grid.lat)):
            raise ShakeMapError(f"{uncertainty}: its nodes are not those of {path}; give the uncertainty.xml of the "
                                "same ShakeMap run")
        log_sd = {**extra.log_sd, **grid.log_sd}
        grid = ShakeMapGrid(grid.event_id, grid.version, grid.event, grid.attrs, grid.lon, grid.lat, grid.medians,
                            log_sd, {**extra.units, **grid.units},
                            {**{im: "uncertainty" for im in extra.log_sd}, **grid.log_sd_source})
    return grid


#: The largest grid.xml read, decompressed [bytes]. Real ShakeMap grids are a few MB to tens of MB (the two of the
#: project's tests: 2.9 and 3.2 MB); a larger file, such as a decompression bomb, is refused with the limit named,
#: and a gzip file is never decompressed past it.
MAX_GRID_BYTES = 256 * 2**20


def _grid_text(path: Path) -> str:
    """The text of a grid.xml, plain or gzip (read as it is), at most :data:`MAX_GRID_BYTES` of it."""
    gz = path.suffix.lower() == ".gz"                     # a grid.xml compressed as it is (gzip)
    try:
        with (gzip.open(path, "rb") if gz else open(path, "rb")) as fh:
            data = fh.read(MAX_GRID_BYTES + 1)
    except (OSError, EOFError, gzip.BadGzipFile) as exc:
        raise ShakeMapError(f"{path}: cannot read it ({getattr(exc, 'strerror', None) or exc})") from exc
    if len(data) > MAX_GRID_BYTES:
        raise ShakeMapError(f"{path}: more than {MAX_GRID_BYTES // 2**20} MiB{' once decompressed' if gz else ''}, "
                            "where ShakeMap grids are a few MB to tens of MB; refused (not a ShakeMap grid.xml, or a "
                            "decompression bomb). Give the event's grid.xml as USGS publishes it")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ShakeMapError(f"{path}: not UTF-8 text at byte {exc.start}; give the event's grid.xml") from exc


def _read(path: Path) -> ShakeMapGrid:
    text = _grid_text(path)
    head, sep, rest = text.partition("<grid_data>")
    if not sep or "shakemap_grid" not in head:
        raise ShakeMapError(f"{path}: not a ShakeMap grid.xml (no shakemap_grid element with grid_data); give the "
                            "grid.xml of a ShakeMap event")
    if "<!DOCTYPE" in head or "<!ENTITY" in head:
        raise ShakeMapError(f"{path}: declares a DTD or XML entities, which ShakeMap grids never do; refused (entity "
                            "expansion or external entities could exhaust memory or read local files). Give the "
                            "event's grid.xml as USGS publishes it")
    data, _, _ = rest.partition("</grid_data>")
    try:
        root = ET.fromstring(head + "</shakemap_grid>")
    except ET.ParseError as exc:
        raise ShakeMapError(f"{path}: its header is not well-formed XML ({exc}); give the event's grid.xml as USGS "
                            "publishes it") from exc
    fields = sorted(((int(f.get("index", "0")), f.get("name", ""), f.get("units", ""))
                     for f in root.iter(f"{NAMESPACE}grid_field")), key=lambda x: x[0])
    names = [name.upper() for _, name, _ in fields]
    if names[:2] != ["LON", "LAT"]:
        raise ShakeMapError(f"{path}: the first two grid fields are {names[:2]}, expected LON and LAT")
    values = np.array(data.split(), dtype=float)
    if values.size == 0 or values.size % len(fields):
        raise ShakeMapError(f"{path}: grid_data holds {values.size} numbers, not a whole number of rows of "
                            f"{len(fields)} fields")
    table = values.reshape(-1, len(fields))
    lon, lat = np.unique(np.round(table[:, 0], 6)), np.unique(np.round(table[:, 1], 6))
    if lon.size * lat.size != table.shape[0]:
        raise ShakeMapError(f"{path}: {table.shape[0]} rows do not fill a grid of {lon.size} longitudes x "
                            f"{lat.size} latitudes")
    ilon = np.searchsorted(lon, np.round(table[:, 0], 6))
    ilat = np.searchsorted(lat, np.round(table[:, 1], 6))
    medians, log_sd, units = {}, {}, {}
    for k, (_, name, unit) in enumerate(fields[2:], start=2):
        key, unit_l = name.upper(), unit.strip()
        node = np.full((lat.size, lon.size), np.nan)
        node[ilat, ilon] = table[:, k]
        units[key] = unit_l
        if key in IM_FIELDS:
            if unit_l.lower() not in MEDIAN_UNITS:
                raise ShakeMapError(f"{path}: field {name} has unit {unit!r}; expected one of {sorted(MEDIAN_UNITS)}")
            medians[key] = node * MEDIAN_UNITS[unit_l.lower()]
        elif key in IM_FIELDS.values():
            if unit_l.lower() not in LOG_UNITS:
                raise ShakeMapError(f"{path}: field {name} has unit {unit!r}; a standard deviation of ln IM is "
                                    f"expected ({', '.join(LOG_UNITS)})")
            log_sd[next(im for im, sd in IM_FIELDS.items() if sd == key)] = node
    return ShakeMapGrid(str(root.get("event_id", "")), str(root.get("shakemap_version", "")),
                        dict(next(root.iter(f"{NAMESPACE}event"), ET.Element("event")).attrib), dict(root.attrib),
                        lon, lat, medians, log_sd, units)


@dataclass(frozen=True)
class SiteShaking:
    """The shaking at a site: its median [SI] and the standard deviation of ln IM (NaN: the grid has none)."""

    median: float
    log_sd: float


def bilinear(values: np.ndarray, lon_axis: np.ndarray, lat_axis: np.ndarray, lon, lat) -> np.ndarray:
    """Bilinear interpolation of ``values`` (shape (nlat, nlon)) at the points (``lon``, ``lat``), which lie within
    the axes (a one-node axis takes its node)."""
    lon, lat = np.asarray(lon, dtype=float), np.asarray(lat, dtype=float)

    def cell(axis: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if axis.size == 1:
            return np.zeros(x.shape, dtype=int), np.zeros(x.shape)
        i = np.clip(np.searchsorted(axis, x) - 1, 0, axis.size - 2)
        return i, (x - axis[i]) / (axis[i + 1] - axis[i])

    i, u = cell(lon_axis, lon)
    j, v = cell(lat_axis, lat)
    i1 = np.minimum(i + 1, lon_axis.size - 1)
    j1 = np.minimum(j + 1, lat_axis.size - 1)
    return ((1 - u) * (1 - v) * values[j, i] + u * (1 - v) * values[j, i1]
            + (1 - u) * v * values[j1, i] + u * v * values[j1, i1])


@dataclass(frozen=True)
class SitesShaking:
    """The shaking at many sites: medians [SI] and standard deviations of ln IM (NaN where the grid has none)."""

    median: np.ndarray
    log_sd: np.ndarray


def sites_shaking(grid: ShakeMapGrid, im: str, lon, lat, *, names=None) -> SitesShaking:
    """The median of ``im`` at each site by bilinear interpolation of ln IM between the four surrounding nodes (a
    median below :data:`FLOOR` of its unit counts as that), and its log standard deviation likewise (linear).

    Raises
    ------
    ShakeMapError
        For sites outside the grid (named from ``names``, with their coordinates) or an IM the grid does not have.
    """
    if im not in grid.medians:
        raise ShakeMapError(f"ShakeMap {grid.event_id}: no {im} field; it has {sorted(grid.medians)}")
    lon, lat = np.atleast_1d(np.asarray(lon, dtype=float)), np.atleast_1d(np.asarray(lat, dtype=float))
    outside = ~((grid.lon[0] <= lon) & (lon <= grid.lon[-1]) & (grid.lat[0] <= lat) & (lat <= grid.lat[-1]))
    if outside.any():
        labels = list(names) if names is not None else [f"site {k}" for k in range(lon.size)]
        bad = [f"{labels[k]} (lon {lon[k]}, lat {lat[k]})" for k in np.flatnonzero(outside)]
        raise ShakeMapError(f"{len(bad)} site(s) outside ShakeMap {grid.event_id}'s grid (lon {grid.lon[0]:.4f} to "
                            f"{grid.lon[-1]:.4f}, lat {grid.lat[0]:.4f} to {grid.lat[-1]:.4f}): "
                            f"{', '.join(bad[:10])}{' ...' if len(bad) > 10 else ''}; check the assets' coordinates")
    unit = MEDIAN_UNITS[grid.units[im].lower()]
    ln = np.log(np.maximum(grid.medians[im], FLOOR * unit))
    median = np.exp(bilinear(ln, grid.lon, grid.lat, lon, lat))
    sd = grid.log_sd.get(im)
    log_sd = bilinear(sd, grid.lon, grid.lat, lon, lat) if sd is not None else np.full(lon.shape, math.nan)
    return SitesShaking(median, log_sd)


def site_shaking(grid: ShakeMapGrid, im: str, lon: float, lat: float, *, site: str = "") -> SiteShaking:
    """The shaking at one site (:func:`sites_shaking`).

    Raises
    ------
    ShakeMapError
        For a site outside the grid (named by ``site``) or an IM the grid does not have.
    """
    out = sites_shaking(grid, im, [lon], [lat], names=[site or "the site"])
    return SiteShaking(float(out.median[0]), float(out.log_sd[0]))


def p_overturn_event(median: float, log_sd: float, theta: float, beta: float, *, k_sigma: float = 0.0) -> float:
    """P(overturn | the event) at a site: Phi(ln(m e^(k sigma) / theta) / sqrt(beta^2 + sigma^2)) for a lognormal
    fragility (median ``theta``, dispersion ``beta``) and a lognormal IM at the site (median ``median``, log
    standard deviation ``log_sd``, NaN taken as 0); ``k_sigma`` > 0 takes the shaking at its median times
    exp(k sigma), as regulators ask for. sigma = 0 is the fragility at the median shaking. NaN for a fragility
    that is not one (theta <= 0 or NaN, beta < 0 or NaN)."""
    if not (theta > 0 and math.isfinite(beta) and beta >= 0):
        return math.nan
    return float(convolved(np.array([median]), np.array([log_sd]), np.array([theta]), np.array([beta]),
                           k_sigma=k_sigma)[0])


def field_for(im: str, period_s: float = math.nan) -> str:
    """The ShakeMap field of a fragility's IM: PGA and PGV; for Sa, the PSA period nearest (in log period) to
    ``period_s``."""
    if im == "pga":
        return "PGA"
    if im == "pgv":
        return "PGV"
    if im == "sa" and math.isfinite(period_s) and period_s > 0:
        return min(PSA_PERIODS, key=lambda f: abs(math.log(PSA_PERIODS[f] / period_s)))
    raise ShakeMapError(f"a fragility on {im} cannot be read from a ShakeMap (it gives PGA, PGV and PSA at 0.3, 1 "
                        "and 3 s); fit the fragility on pga, pgv or sa")
