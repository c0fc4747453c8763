"""A constrained logic tree written back in the format its branches came in, and its per-branch table.

* OpenQuake (:class:`~pipeline.uncertainty.branches.TreeFormat.openquake`): ``realizations_posterior.csv``
  (``rlz_id,branch_path,weight`` with the posterior weights), and the posterior mean and fractile curves as
  ``hazard_curve-mean-<IMT>_posterior.csv`` and ``quantile_curve-<q>-<IMT>_posterior.csv`` in OpenQuake's
  layout (a metadata line, ``custom_site_id,lon,lat,depth,poe-<iml>...``, the probabilities of exceedance in the
  branches' investigation time, levels in OpenQuake's units: g, or cm/s for PGV).
* Curves and weights: ``weights_posterior.csv`` (``file,weight``: the branches' files with their posterior
  weights, to put beside them) and the posterior mean and fractile curves as plain CSVs
  (``<im>_<unit>_<component>,annual_rate``), which :func:`pipeline.uncertainty.hazard_files.read_hazard` reads.
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np
import xarray as xr

from .. import __version__
from ..constants import G
from ..uncertainty.branches import LogicTree, TreeFormat
from .atomic import inert, write_csv_atomic, write_text_atomic

#: OpenQuake's units of each IM's levels: (factor to SI, name in a plain CSV header)
OQ_LEVEL_UNITS = {"pga": (G, "g"), "sa": (G, "g"), "pgv": (0.01, "cms")}


def branch_rows(ds: xr.Dataset) -> tuple[tuple[str, ...], list[dict]]:
    """``constrain_branches.csv``: per branch its path, prior weight, likelihood, posterior weight, and each
    rock's toppling rate and likelihood."""
    rocks = [str(r) for r in ds["rock"].values]
    columns = ("branch", "branch_path", "prior_weight", "likelihood", "posterior_weight",
               *(f"toppling_rate_per_yr_{r}" for r in rocks), *(f"likelihood_{r}" for r in rocks))
    rows = []
    for b, bid in enumerate(ds["branch"].values):
        row = {"branch": str(bid), "branch_path": str(ds["branch_path"].values[b]),
               "prior_weight": float(ds["prior_weight"].values[b]), "likelihood": float(ds["likelihood"].values[b]),
               "posterior_weight": float(ds["posterior_weight"].values[b])}
        for i, r in enumerate(rocks):
            row[f"toppling_rate_per_yr_{r}"] = float(ds["toppling_rate"].values[i, b])
            row[f"likelihood_{r}"] = float(ds["likelihood_rock"].values[i, b])
        rows.append(row)
    return columns, rows


def write_reweighted(ds: xr.Dataset, tree: LogicTree, out: Path) -> list[Path]:
    """The posterior weights, mean and fractile curves in the branches' own format, into ``out``."""
    if tree.layout is TreeFormat.openquake:
        return _openquake(ds, tree, out)
    return _plain(ds, tree, out)


def _openquake(ds: xr.Dataset, tree: LogicTree, out: Path) -> list[Path]:
    meta = f"generated_by='rockscreen {__version__} screen constrain'"
    table = io.StringIO()
    rows = csv.writer(table, lineterminator="\n")                # a branch path with a comma or a quote stays whole
    rows.writerow(["rlz_id", "branch_path", "weight"])
    rows.writerows([int(bid[4:]), inert(str(path)), f"{w:.7e}"]
                   for bid, path, w in zip(tree.ids, tree.paths, ds["posterior_weight"].values))
    paths = [write_text_atomic(out / "realizations_posterior.csv",
                               f'#,,"{meta}, kind=\'posterior weights\'"\n{table.getvalue()}')]
    first = tree.curves[0]
    years = first.investigation_time_yr if math.isfinite(first.investigation_time_yr) else 1.0
    factor = OQ_LEVEL_UNITS[ds.attrs["im"]][0]
    levels = ds["im_level"].values / factor
    site = first.site_row or ("", "0.00000", "0.00000", "0.00000")
    curves = [("mean", f"hazard_curve-mean-{tree.imt}_posterior.csv", ds["mean_rate_posterior"].values)]
    curves += [(f"quantile-{q:g}", f"quantile_curve-{q:g}-{tree.imt}_posterior.csv",
                ds["fractile_rate_posterior"].values[k]) for k, q in enumerate(ds["fractile"].values)]
    for kind, name, rates in curves:
        poes = -np.expm1(-np.asarray(rates) * years)
        head = ["custom_site_id", "lon", "lat", "depth", *(f"poe-{x:.7f}" for x in levels)]
        row = [*site, *(f"{p:.6E}" for p in poes)]
        text = ("#," + "," * (len(head) - 2)
                + f'"{meta}, kind=\'{kind} (posterior)\', investigation_time={years:g}, imt=\'{tree.imt}\'"\n'
                + ",".join(head) + "\n" + ",".join(row) + "\n")
        paths.append(write_text_atomic(out / name, text))
    return paths


def _plain(ds: xr.Dataset, tree: LogicTree, out: Path) -> list[Path]:
    rows = [{"file": bid, "weight": float(w)} for bid, w in zip(tree.ids, ds["posterior_weight"].values)]
    paths = [write_csv_atomic(out / "weights_posterior.csv", ("file", "weight"), rows)]
    im = ds.attrs["im"]
    factor, unit = OQ_LEVEL_UNITS[im]
    column = f"{im}_{unit}_{ds.attrs['im_component']}"
    curves = [("hazard_mean_posterior.csv", ds["mean_rate_posterior"].values)]
    curves += [(f"hazard_fractile-{q:g}_posterior.csv", ds["fractile_rate_posterior"].values[k])
               for k, q in enumerate(ds["fractile"].values)]
    for name, rates in curves:
        table = [{column: float(x / factor), "annual_rate": float(r)} for x, r in zip(ds["im_level"].values, rates)]
        paths.append(write_csv_atomic(out / name, (column, "annual_rate"), table))
    return paths
