"""Results as netCDF4 files: atomic writes, CF ragged arrays, opening results.

Variable attributes come from :mod:`pipeline.schema`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Hashable

import numpy as np
import xarray as xr

from ..errors import ResultsError
from ..schema import PULSE_SERIES
from .atomic import replace_atomically

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


@dataclass
class PulseSeries:
    """The extracted pulses of a run (``pulses.nc``), held as row descriptions and fetched one record at a
    time: a CF contiguous ragged array with ``velocity`` and ``pulse`` [m s-1] along each record's chosen
    pulse orientation on dimension ``sample``, and ``row_size`` samples per record.

    ``rows`` is ``[(record_id, npts, dt_s), ...]`` in file order; ``fetch(record_id)`` returns that
    record's ``{"velocity": ..., "pulse": ...}`` [m s-1] (from memory or from the scene cache), so
    that writing ``pulses.nc`` holds one record's series at a time, whatever the number of records.
    """

    rows: list[tuple[str, int, float]]
    fetch: Callable[[str], dict]
    attrs: dict = field(default_factory=dict)

    def dataset(self) -> xr.Dataset:
        """The whole CF ragged array in memory (:func:`ragged_dataset`), for API users and tests."""
        rows = [{"id": rid, "dt": dt, **self.fetch(rid)} for rid, _, dt in self.rows]
        ds = ragged_dataset("record_id", "record", rows, PULSE_SERIES)
        ds.attrs.update(self.attrs)
        return ds

    def write(self, path: str | Path) -> Path:
        """Write ``pulses.nc`` atomically, record by record (the same variables, attributes and encoding as
        :func:`write_atomic` of :meth:`dataset`; tested equal)."""
        return replace_atomically(path, self._write)

    def _write(self, tmp: str) -> None:
        import netCDF4

        sizes = np.array([n for _, n, _ in self.rows], dtype="i4")
        size_attrs, id_attrs = _ragged_station_attrs("record")

        def floats(nc, name: str, dtype: str, dim: str, attrs: dict):
            """A float variable with the encoding xarray gives it through _encoding(): zlib 4, NaN fill, and
            along ``sample`` chunks of RAGGED_CHUNK with a small write cache."""
            chunks = _sample_chunks(int(sizes.sum())) if dim == "sample" else None
            v = nc.createVariable(name, dtype, (dim,), zlib=True, complevel=4, shuffle=True,
                                  fill_value=np.dtype(dtype).type(np.nan), chunksizes=chunks)
            if chunks:
                v.set_var_chunk_cache(size=RAGGED_WRITE_CACHE, nelems=61, preemption=1.0)
            v.setncatts(attrs)
            return v

        with netCDF4.Dataset(tmp, "w", format="NETCDF4") as nc:
            nc.createDimension("station", len(self.rows))
            nc.createDimension("sample", int(sizes.sum()))
            v = nc.createVariable("row_size", "i4", ("station",), fill_value=False)
            v.setncatts(size_attrs)
            v[:] = sizes
            floats(nc, "dt", "f8", "station", RAGGED_DT)[:] = np.array([dt for _, _, dt in self.rows], dtype=float)
            v = nc.createVariable("record_id", str, ("station",))
            v.setncatts(id_attrs)
            for k, (rid, _, _) in enumerate(self.rows):
                v[k] = rid
            series = {name: floats(nc, name, "f4", "sample", {**attrs, "coordinates": "time"})
                      for name, attrs in PULSE_SERIES.items()}
            time = floats(nc, "time", "f8", "sample", RAGGED_TIME)
            start = 0
            for rid, n, dt in self.rows:
                values = self.fetch(rid)
                for name, var in series.items():
                    var[start:start + n] = np.asarray(values[name]).astype("f4")
                time[start:start + n] = np.arange(n) * float(dt)
                start += n
            nc.setncatts({**RAGGED_GLOBAL, **self.attrs})


def open_results(path: str | Path, *, variables: tuple[str, ...] | None = None) -> xr.Dataset:
    """Open a results file into memory (the file is closed on return): all of it, or only ``variables``
    (those of them the file has) and their coordinates.

    Raises
    ------
    ResultsError
        If the file is missing or not a netCDF file.
    """
    path = Path(path)
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
