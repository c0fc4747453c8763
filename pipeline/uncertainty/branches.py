"""A hazard model's logic tree as exported: one hazard curve per end branch (realization) and its weight.

Two layouts of a folder are read:

* **OpenQuake** (``oq export hcurves`` and ``oq export realizations`` of a calculation with
  ``individual_rlzs = true``): ``realizations_<calc>.csv`` (``rlz_id,branch_path,weight``) and one
  ``hazard_curve-rlz-<NNN>-<IMT>_<calc>.csv`` per realization; each curve is read by
  :func:`~.hazard_files.read_hazard` (probabilities in the investigation time converted to annual rates).
* **Curves and weights**: ``weights.csv`` (``file,weight``) naming each branch's curve file in the folder, in
  any format :func:`~.hazard_files.read_hazard` reads.

The weights must sum to 1 (to 1e-3: OpenQuake writes them to 8 digits); they are then normalised. Every branch
must be for the same IM, component definition and site.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

import numpy as np

from ..errors import ConstraintError
from ..tables import read_csv_table
from .branch_names import branch_names
from .hazard import Component
from .hazard_files import read_hazard

#: How far the weights of a logic tree's end branches may sum from 1 before the tree is refused [-].
WEIGHT_SUM_TOL = 1e-3
#: OpenQuake's realization curve files: hazard_curve-rlz-<NNN>-<IMT>[_<calc id>].csv
OQ_RLZ = re.compile(r"hazard_curve-rlz-(\d+)-(.+?)(?:_(\d+))?\.csv$")
#: A folder of curves: the weights file
WEIGHTS_FILE = "weights.csv"
#: rockscreen IM -> OpenQuake's IMT name
OQ_IMT = {"pga": "PGA", "pgv": "PGV", "sa": "SA"}


class TreeFormat(Enum):
    """The layout a logic tree came in (and is written back in)."""

    openquake = "openquake"
    weights = "weights"


@dataclass(frozen=True)
class LogicTree:
    """The end branches of a hazard model: their curves, names and prior weights."""

    #: a short id per branch (``rlz-000``, or the curve file's name)
    ids: tuple
    #: what each branch is (OpenQuake's ``branch_path``, or the file's name)
    paths: tuple
    curves: tuple
    #: prior weights, summing to 1 [-]
    weights: np.ndarray
    folder: str
    layout: TreeFormat
    notes: tuple = ()
    #: OpenQuake's IMT name of the curves (``PGA``, ``SA(1.0)``) and the calculation id ("" if none)
    imt: str = ""
    calc_id: str = ""
    #: a readable name per branch (OpenQuake: its branches' IDs in the logic-tree files, :mod:`.branch_names`; else
    #: as ``paths``)
    names: tuple = ()

    @property
    def labels(self) -> tuple:
        """Each branch's readable name (:attr:`names`, else its path)."""
        return self.names or self.paths

    @property
    def im(self) -> str:
        return self.curves[0].im

    @property
    def component(self) -> Component | None:
        return self.curves[0].component


def read_branches(folder: Path, *, im: str, site: str | None = None, lonlat: tuple[float, float] | None = None,
                  period_s: float | None = None, component: Component | None = None) -> LogicTree:
    """Read a logic tree's end branches from ``folder`` (OpenQuake's export, or curves and ``weights.csv``).

    Raises
    ------
    ConstraintError
        For a folder with neither layout, a realization without its curve file, weights that are not positive
        numbers or do not sum to 1, and branches of different IMs, components or sites.
    HazardError
        For a curve file that cannot be read (named).
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ConstraintError(f"{folder}: not a folder; --hazard-branches is a folder of OpenQuake's exported "
                              f"realization curves and realizations_<calc>.csv, or of curves and {WEIGHTS_FILE}")
    tables = sorted(folder.glob("realizations_*.csv")) + sorted(folder.glob("realizations.csv"))
    if tables:
        tree = _openquake(folder, tables, im=im, site=site, lonlat=lonlat, period_s=period_s, component=component)
    elif (folder / WEIGHTS_FILE).is_file():
        tree = _weights(folder, im=im, site=site, lonlat=lonlat, period_s=period_s, component=component)
    else:
        raise ConstraintError(f"{folder}: no realizations_<calc>.csv (OpenQuake: oq export realizations <calc> -e csv) "
                              f"and no {WEIGHTS_FILE} (file,weight: one row per branch's curve file)")
    _check_alike(tree)
    return tree


def _openquake(folder: Path, tables: list[Path], *, im: str, period_s, **kw) -> LogicTree:
    if len(tables) > 1:
        raise ConstraintError(f"{folder}: {len(tables)} realizations tables ({', '.join(t.name for t in tables)}): "
                              "one calculation per folder")
    table = tables[0]
    calc = re.fullmatch(r"realizations_?(\d*)\.csv", table.name)
    calc_id = calc.group(1) if calc else ""
    rows = _realizations(table)
    files = _rlz_files(folder, im=im, period_s=period_s, calc_id=calc_id)
    rlzs, paths, curves, weights = [], [], [], []
    for _line, where, cells in rows:
        try:
            rlz, weight = int(cells["rlz_id"]), float(cells["weight"])
        except ValueError:
            raise ConstraintError(f"{where}: rlz_id {cells['rlz_id']!r}, weight {cells['weight']!r}: expected an "
                                  "integer and a number") from None
        if rlz not in files:
            raise ConstraintError(f"{where}: realization {rlz} has no {OQ_IMT.get(im, im)} curve file "
                                  f"hazard_curve-rlz-{rlz:03d}-...csv in {folder}; export every realization "
                                  "(individual_rlzs = true, oq export hcurves <calc> -e csv)")
        rlzs.append(rlz)
        paths.append(cells["branch_path"])
        curves.append(read_hazard(files[rlz][1], im=im, period_s=period_s, **kw))
        weights.append(weight)
    if not rlzs:
        raise ConstraintError(f"{table}: no realizations listed")
    extra = sorted(set(files) - set(rlzs))
    if extra:
        raise ConstraintError(f"{folder}: curve files of realizations {extra} not in {table.name}: a folder holds "
                              "one calculation's export")
    w, notes = _normalised(np.array(weights), where=str(table))
    names, note = branch_names(folder, tuple(paths), weights)
    return LogicTree(tuple(f"rlz-{r:03d}" for r in rlzs), tuple(paths), tuple(curves), w, str(folder),
                     TreeFormat.openquake, (*notes, *([note] if note else [])), imt=files[rlzs[0]][0],
                     calc_id=calc_id, names=names)


def _realizations(table: Path):
    """The rows of OpenQuake's realizations table (``rlz_id,branch_path,weight``), after its metadata line."""
    try:
        lines = table.read_text(encoding="utf-8-sig").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise ConstraintError(f"{table}: cannot be read ({exc})") from None
    numbered = [(k, ln) for k, ln in enumerate(lines, start=1) if ln.strip() and not ln.startswith("#")]
    if not numbered:
        raise ConstraintError(f"{table}: no header; expected rlz_id,branch_path,weight")
    head_no, head = numbered[0]
    header = [c.strip() for c in next(csv.reader([head]))]
    if any(c not in header for c in ("rlz_id", "branch_path", "weight")):
        raise ConstraintError(f"{table}, line {head_no}: header {header}; expected rlz_id,branch_path,weight")
    for k, line in numbered[1:]:
        row = next(csv.reader([line]))
        if len(row) != len(header):
            raise ConstraintError(f"{table}, line {k}: {len(row)} fields, expected {len(header)}")
        yield k, f"{table}, line {k}", {c: row[i].strip() for i, c in enumerate(header)}


def _rlz_files(folder: Path, *, im: str, period_s, calc_id: str) -> dict[int, tuple[str, Path]]:
    """Realization -> (IMT name, file) for the IM (and Sa period) wanted."""
    out: dict[int, tuple[str, Path]] = {}
    seen = set()
    for path in sorted(folder.iterdir()):
        m = OQ_RLZ.fullmatch(path.name)
        if not m or (calc_id and m.group(3) and m.group(3) != calc_id):
            continue
        imt = m.group(2)
        seen.add(imt)
        if not _imt_is(imt, im, period_s):
            continue
        rlz = int(m.group(1))
        if rlz in out:
            raise ConstraintError(f"{folder}: two {imt} curves for realization {rlz}: {out[rlz][1].name}, {path.name}"
                                  + ("; give --hazard-period" if im == "sa" else ""))
        out[rlz] = (imt, path)
    if not out:
        raise ConstraintError(f"{folder}: no realization curve of {OQ_IMT.get(im, im)}"
                              + (f" at {period_s:g} s" if period_s else "")
                              + f"; the folder holds {', '.join(sorted(seen)) or 'none'}")
    return out


def _imt_is(imt: str, im: str, period_s) -> bool:
    if im != "sa":
        return imt.upper() == OQ_IMT.get(im, "")
    m = re.fullmatch(r"SA\(([\d.]+)\)", imt.upper())
    if m is None:
        return False
    return period_s is None or math.isclose(float(m.group(1)), period_s, rel_tol=1e-6)


def _weights(folder: Path, **kw) -> LogicTree:
    table = folder / WEIGHTS_FILE
    _, rows = read_csv_table(table, what="weights", expected_header="file,weight", required=("file", "weight"))
    ids, curves, weights = [], [], []
    for _line, where, cells in rows:
        name = cells["file"]
        path = (folder / name)
        if Path(name).is_absolute() or ".." in Path(name).parts or not path.is_file():
            raise ConstraintError(f"{where}: file {name!r}: expected the name of a curve file in {folder}")
        try:
            weight = float(cells["weight"])
        except ValueError:
            raise ConstraintError(f"{where}: weight {cells['weight']!r} is not a number") from None
        ids.append(name)
        curves.append(read_hazard(path, **kw))
        weights.append(weight)
    if not ids:
        raise ConstraintError(f"{table}: no branches listed")
    w, notes = _normalised(np.array(weights), where=str(table))
    return LogicTree(tuple(ids), tuple(ids), tuple(curves), w, str(folder), TreeFormat.weights, tuple(notes))


def _normalised(weights: np.ndarray, *, where: str) -> tuple[np.ndarray, list[str]]:
    if np.any(~np.isfinite(weights)) or np.any(weights <= 0):
        bad = weights[~(weights > 0)][:3].tolist()
        raise ConstraintError(f"{where}: weights {bad}: every branch's weight must be a positive number (leave a "
                              "branch of weight 0 out)")
    total = float(weights.sum())
    if abs(total - 1.0) > WEIGHT_SUM_TOL:
        raise ConstraintError(f"{where}: the weights sum to {total:.6g}; the end branches of a logic tree sum to 1 "
                              "(give every end branch, with its product of branch weights)")
    notes = [f"the prior weights summed to {total:.9g}; normalised to 1"] if total != 1.0 else []
    return weights / total, notes


def _check_alike(tree: LogicTree) -> None:
    first = tree.curves[0]
    for bid, c in zip(tree.ids, tree.curves):
        for what, a, b in (("IM", c.im, first.im), ("component", c.component, first.component),
                           ("site", c.site, first.site)):
            if a != b:
                raise ConstraintError(f"{tree.folder}: branch {bid} is for {what} {a}, branch {tree.ids[0]} for {b}; "
                                      "every branch of one logic tree must be for the same IM, component and site")
