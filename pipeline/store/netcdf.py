"""Results as netCDF4 files: atomic writes, CF ragged arrays, opening results.

Variable attributes come from :mod:`pipeline.schema`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Hashable, NamedTuple

import numpy as np
import xarray as xr

from ..errors import ResultsError
from ..schema import FLOOR_PULSE_SERIES, FLOOR_PULSE_STATION, PULSE_SERIES
from .atomic import STATE_DIR, replace_atomically

#: Samples per chunk of a ragged array's per-sample variables. Left to itself, netCDF-C makes one chunk of a
#: whole 1-D variable, which the HDF5 chunk cache then holds uncompressed until the file is closed (memory
#: that grows with the records) and which must be decompressed whole to read one record's series.
RAGGED_CHUNK = 2**16
#: Bytes of HDF5 chunk cache per variable while a ragged array is written: a few chunks, so that written
#: chunks are compressed and leave memory as the writing goes on.
RAGGED_WRITE_CACHE = 4 * RAGGED_CHUNK * 8


def _sample_chunks(n_samples: int) -> tuple[int] | None:
    """Chunk shape of a per-sample variable of ``n_samples`` (None: an empty dimension, left contiguous)."""
    return (min(RAGGED_CHUNK, n_samples),) if n_samples > 0 else None


def _encoding(ds: xr.Dataset) -> dict:
    enc: dict[Hashable, dict] = {}
    for name, var in ds.variables.items():
        if var.dtype.kind == "f":
            enc[name] = {"zlib": True, "complevel": 4, "_FillValue": np.nan}
            if var.dims == ("sample",) and (chunks := _sample_chunks(var.size)):
                enc[name]["chunksizes"] = chunks
        elif var.dtype.kind in "OU":
            enc[name] = {"dtype": str}
    return enc


def write_atomic(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` to ``path`` (netCDF4) atomically (:func:`replace_atomically`).

    Raises
    ------
    OutputError
        If the directory is not writable or the disk is full; the previous
        file at ``path``, if any, is left untouched.
    """
    return replace_atomically(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4", encoding=_encoding(ds)))


#: Global attributes of a CF contiguous ragged array of time series.
RAGGED_GLOBAL = {"Conventions": "CF-1.11", "featureType": "timeSeries"}
#: Attributes of the sampling interval and of the time coordinate of a ragged array.
RAGGED_DT = {"units": "s", "long_name": "sampling interval"}
RAGGED_TIME = {"units": "s", "long_name": "time since the first sample of the series", "axis": "T"}


def _ragged_station_attrs(id_long_name: str) -> tuple[dict, dict]:
    """Attributes of ``row_size`` and of the series id variable of a ragged array."""
    return ({"sample_dimension": "sample", "long_name": f"samples per {id_long_name}"},
            {"cf_role": "timeseries_id", "long_name": id_long_name})


def ragged_dataset(id_name: str, id_long_name: str, rows: list[dict], series: dict[str, dict],
                   station: dict[str, dict] | None = None) -> xr.Dataset:
    """Time series of different lengths as a CF contiguous ragged array (featureType timeSeries).

    Parameters
    ----------
    id_name, id_long_name : str
        Name and long name of the series id variable (``cf_role = timeseries_id``).
    rows : list of dict
        One per series: ``"id"``, ``"dt"`` [s] and an array per name in ``series``.
    series : dict
        Name -> attributes of each per-sample variable (stored as float32).
    station : dict, optional
        Name -> attributes of further per-series string variables taken from ``rows``.

    References
    ----------
    CF conventions 1.11, section 9 and appendix H (contiguous ragged array representation).
    """
    first = next(iter(series))
    ids = np.array([r["id"] for r in rows], dtype=str)   # unicode: an empty object array cannot be written
    size_attrs, id_attrs = _ragged_station_attrs(id_long_name)
    data = {"row_size": (("station",), np.array([np.size(r[first]) for r in rows], dtype="i4"), size_attrs),
            "dt": (("station",), np.array([r["dt"] for r in rows], dtype=float), RAGGED_DT),
            id_name: (("station",), ids, id_attrs)}
    for name, attrs in (station or {}).items():
        data[name] = (("station",), np.array([r[name] for r in rows], dtype=str), attrs)
    for name, attrs in series.items():
        values = np.concatenate([np.asarray(r[name]) for r in rows]) if rows else np.zeros(0)
        data[name] = (("sample",), values.astype("f4"), attrs)
    # the time of each sample from the start of its series (record start times are often unknown: AT2 files)
    time = (np.concatenate([np.arange(np.size(r[first])) * float(r["dt"]) for r in rows]) if rows
            else np.zeros(0))
    return xr.Dataset(data, coords={"time": (("sample",), time, RAGGED_TIME)}, attrs=dict(RAGGED_GLOBAL))


def ragged_rows(ds: xr.Dataset, id_name: str) -> dict[str, slice]:
    """Series id -> slice of the ``sample`` dimension, for a :func:`ragged_dataset`."""
    sizes = ds["row_size"].values
    ends = np.cumsum(sizes)
    return {sid: slice(int(e - n), int(e)) for sid, n, e in zip(ds[id_name].values.tolist(), sizes, ends)}


class FloorRow(NamedTuple):
    """One floor's pulse series in ``pulses.nc`` (group ``floors``): the ground record, the building and floor
    height [m], the series' length and interval [s], and the floor motion's pulse values
    (:data:`~pipeline.schema.FLOOR_PULSE_STATION`)."""

    record_id: str
    building: str
    height_m: float
    npts: int
    dt_s: float
    values: dict


#: Name of the group of ``pulses.nc`` that holds the floors' pulses.
FLOOR_GROUP = "floors"


@dataclass
class PulseSeries:
    """The extracted pulses of a run (``pulses.nc``), held as row descriptions and fetched one record at a
    time: a CF contiguous ragged array with ``velocity`` and ``pulse`` [m s-1] along each record's chosen
    pulse orientation on dimension ``sample``, and ``row_size`` samples per record; and, in the group
    ``floors`` (written when blocks stand on floors), the same for the motion of each floor under each record,
    with the floor motion's own pulse values (:data:`~pipeline.schema.FLOOR_PULSE_STATION`).

    ``rows`` is ``[(record_id, npts, dt_s), ...]`` in file order, ``floor_rows`` the :class:`FloorRow` of the
    floors; ``fetch(record_id)`` returns that record's ``{"velocity": ..., "pulse": ...}`` [m s-1] and, under
    ``"floors"``, ``{(building, height_m): {"velocity": ..., "pulse": ...}}`` (from memory or from the scene
    cache), so that writing ``pulses.nc`` holds one record's series at a time, whatever the number of records.
    """

    rows: list[tuple[str, int, float]]
    fetch: Callable[[str], dict]
    attrs: dict = field(default_factory=dict)
    floor_rows: list[FloorRow] = field(default_factory=list)

    def dataset(self) -> xr.Dataset:
        """The ground's CF ragged array in memory (:func:`ragged_dataset`), for API users and tests."""
        rows = [{"id": rid, "dt": dt, **self.fetch(rid)} for rid, _, dt in self.rows]
        ds = ragged_dataset("record_id", "record", rows, PULSE_SERIES)
        ds.attrs.update(self.attrs)
        return ds

    def floor_dataset(self) -> xr.Dataset:
        """The floors' CF ragged array in memory (what ``xr.open_dataset(path, group="floors")`` reads), one
        series per (record, floor), identified by ``series_id`` = ``"<record> <building>@<height> m"``."""
        rows = [{"id": _floor_series_id(fr), "dt": fr.dt_s, "record_id": fr.record_id, "building": fr.building,
                 **self.fetch(fr.record_id)["floors"][fr.building, fr.height_m]} for fr in self.floor_rows]
        text = {n: FLOOR_PULSE_STATION[n] for n in ("record_id", "building")}
        ds = ragged_dataset("series_id", "record and floor", rows, FLOOR_PULSE_SERIES, station=text)
        for name, attrs in FLOOR_PULSE_STATION.items():
            if name not in text:
                ds[name] = (("station",), self._floor_column(name), attrs)
        ds.attrs.update(self.attrs)
        return ds

    def _floor_column(self, name: str) -> np.ndarray:
        if name == "floor_height":
            return np.array([fr.height_m for fr in self.floor_rows], dtype=float)
        dtype = "i1" if name == "is_pulse" else float
        return np.array([fr.values[name] for fr in self.floor_rows], dtype=dtype)

    def write(self, path: str | Path) -> Path:
        """Write ``pulses.nc`` atomically, record by record (the same variables, attributes and encoding as
        :func:`write_atomic` of :meth:`dataset` and, in group ``floors``, of :meth:`floor_dataset`; tested
        equal)."""
        return replace_atomically(path, self._write)

    def _write(self, tmp: str) -> None:
        import netCDF4

        with netCDF4.Dataset(tmp, "w", format="NETCDF4") as nc:
            ground = _RaggedWriter(nc, [(rid, n, dt) for rid, n, dt in self.rows], "record_id", "record",
                                   PULSE_SERIES)
            floors = None
            if self.floor_rows:
                group = nc.createGroup(FLOOR_GROUP)
                floors = _RaggedWriter(group, [(_floor_series_id(fr), fr.npts, fr.dt_s) for fr in self.floor_rows],
                                       "series_id", "record and floor", FLOOR_PULSE_SERIES)
                for name in ("record_id", "building"):
                    v = group.createVariable(name, str, ("station",))
                    v.setncatts(FLOOR_PULSE_STATION[name])
                    for k, fr in enumerate(self.floor_rows):
                        v[k] = getattr(fr, name)
                for name, attrs in FLOOR_PULSE_STATION.items():
                    if name not in ("record_id", "building"):
                        column = self._floor_column(name)
                        if column.dtype.kind == "f":
                            floors.floats(name, "f8", "station", attrs)[:] = column
                        else:
                            v = group.createVariable(name, column.dtype, ("station",), fill_value=False)
                            v.setncatts(attrs)
                            v[:] = column
                group.setncatts({**RAGGED_GLOBAL, **self.attrs})
            by_record: dict[str, list[int]] = {}
            for k, fr in enumerate(self.floor_rows):
                by_record.setdefault(fr.record_id, []).append(k)
            for k, (rid, _, _) in enumerate(self.rows):
                values = self.fetch(rid)
                ground.put(k, values)
                if floors is not None:
                    for m in by_record.get(rid, []):
                        fr = self.floor_rows[m]
                        floors.put(m, values["floors"][fr.building, fr.height_m])
            nc.setncatts({**RAGGED_GLOBAL, **self.attrs})


def _floor_series_id(fr: FloorRow) -> str:
    return f"{fr.record_id} {fr.building}@{fr.height_m:g} m"


class _RaggedWriter:
    """A CF contiguous ragged array written one series at a time into a netCDF4 dataset or group, with the
    variables, attributes and encoding xarray gives :func:`ragged_dataset` through :func:`_encoding`."""

    def __init__(self, nc, rows: list[tuple[str, int, float]], id_name: str, id_long_name: str,
                 series: dict[str, dict]):
        self.nc = nc
        sizes = np.array([n for _, n, _ in rows], dtype="i4")
        self.starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(int) if rows else np.zeros(0, int)
        self.sizes, self.dts = sizes, [dt for _, _, dt in rows]
        size_attrs, id_attrs = _ragged_station_attrs(id_long_name)
        nc.createDimension("station", len(rows))
        nc.createDimension("sample", int(sizes.sum()))
        v = nc.createVariable("row_size", "i4", ("station",), fill_value=False)
        v.setncatts(size_attrs)
        v[:] = sizes
        self.floats("dt", "f8", "station", RAGGED_DT)[:] = np.array(self.dts, dtype=float)
        v = nc.createVariable(id_name, str, ("station",))
        v.setncatts(id_attrs)
        for k, (sid, _, _) in enumerate(rows):
            v[k] = sid
        self.series = {name: self.floats(name, "f4", "sample", {**attrs, "coordinates": "time"})
                       for name, attrs in series.items()}
        self.time = self.floats("time", "f8", "sample", RAGGED_TIME)

    def floats(self, name: str, dtype: str, dim: str, attrs: dict):
        """A float variable with the encoding xarray gives it through _encoding(): zlib 4, NaN fill, and
        along ``sample`` chunks of RAGGED_CHUNK with a small write cache."""
        chunks = _sample_chunks(int(self.sizes.sum())) if dim == "sample" else None
        v = self.nc.createVariable(name, dtype, (dim,), zlib=True, complevel=4, shuffle=True,
                                   fill_value=np.dtype(dtype).type(np.nan), chunksizes=chunks)
        if chunks:
            v.set_var_chunk_cache(size=RAGGED_WRITE_CACHE, nelems=61, preemption=1.0)
        v.setncatts(attrs)
        return v

    def put(self, k: int, values: dict) -> None:
        """Series ``k``'s per-sample values."""
        start, n = int(self.starts[k]), int(self.sizes[k])
        for name, var in self.series.items():
            var[start:start + n] = np.asarray(values[name]).astype("f4")
        self.time[start:start + n] = np.arange(n) * float(self.dts[k])


def open_results(path: str | Path, *, variables: tuple[str, ...] | None = None) -> xr.Dataset:
    """Open a results file into memory (the file is closed on return): all of it, or only ``variables``
    (those of them the file has) and their coordinates.

    Raises
    ------
    ResultsError
        If the file is missing or not a netCDF file.
    """
    path = Path(path)
    if path.is_symlink() and not path.exists() and os.readlink(path).startswith(f"{STATE_DIR}/"):
        raise ResultsError(f"{path}: a link of rockscreen's into {path.parent / STATE_DIR}, which this folder "
                           f"lacks: a copy of the folder's contents left out its hidden {STATE_DIR} (cp -r OUT/* "
                           "does). Copy the folder itself (cp -r OUT DEST, cp -a, tar, rsync -a) or follow the links "
                           "(cp -rL OUT/* DEST)")
    if not path.is_file():
        raise ResultsError(f"{path}: results file not found; run 'screen --records DIR --blocks CSV --out DIR' "
                           "first, which writes DIR/screening.nc")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            if variables is not None:
                ds = ds[[v for v in variables if v in ds.data_vars]]
            return ds.load()
    except (OSError, ValueError) as exc:
        raise ResultsError(f"{path}: not a readable netCDF results file ({exc})") from exc
