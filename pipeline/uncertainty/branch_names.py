"""The names of an OpenQuake logic tree's end branches, read from the logic-tree files beside its export.

OpenQuake writes a realization's ``branch_path`` as one code per branch set, the source-model tree's codes, ``~``,
then the ground-motion tree's (``B~A``: the second branch of the source-model tree's set, the first of the
ground-motion model's). A code is a branch's position in its set, counted ``A``, ``B``, ... (OpenQuake's
``logictree`` module). With the two trees' NRML files (named by ``job.ini``'s ``source_model_logic_tree_file`` and
``gsim_logic_tree_file``, or under those default names), each realization is named by its branches' ``branchID``
(``high · bssa14``). The names are kept only where every realization's weight is the product of its branches'
``uncertaintyWeight`` (to 1e-6), a check independent of the codes' reading; otherwise, or without the files, the
branches keep OpenQuake's codes and a note says why.

References
----------
Pagani, M., Monelli, D., Weatherill, G. et al. (2014). OpenQuake engine: an open hazard (and risk) software for the
Global Earthquake Model. Seismological Research Letters 85(3), 692-702.
"""

from __future__ import annotations

import configparser
import math
import xml.etree.ElementTree as ET
from pathlib import Path

#: OpenQuake's branch codes, a branch's position in its branch set.
CODES = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789"
#: The trees' default file names, and the job.ini keys that name them.
TREE_FILES = (("source_model_logic_tree_file", "source_model_logic_tree.xml"),
              ("gsim_logic_tree_file", "gsim_logic_tree.xml"))
#: A realization's weight against the product of its branches' weights [-].
WEIGHT_TOL = 1e-6
#: Between a realization's branch names.
JOIN = " · "


def branch_names(folder: Path, paths: tuple, weights) -> tuple[tuple, str]:
    """Each realization's name from the logic-tree files in ``folder`` (its ``paths`` as OpenQuake codes them,
    ``weights`` the realizations' weights as the export gives them), and a note ("" where every name was read);
    the codes themselves where the files are missing or do not give the weights."""
    trees = []
    for key, default in TREE_FILES:
        path = _tree_file(folder, key, default)
        if path is None:
            return paths, f"branch names: no {default} in {folder}: the branches keep OpenQuake's codes"
        try:
            trees.append(_branch_sets(path))
        except (ET.ParseError, ValueError) as exc:
            return paths, f"branch names: {path} could not be read ({exc}): the branches keep OpenQuake's codes"
    names = []
    for path, weight in zip(paths, weights):
        named = _named(str(path), trees)
        if named is None or not math.isclose(named[1], float(weight), rel_tol=0.0, abs_tol=WEIGHT_TOL):
            return paths, (f"branch names: the logic-tree files in {folder} do not give realization {path}'s weight "
                           f"{float(weight):.6g}: the branches keep OpenQuake's codes")
        names.append(named[0])
    return tuple(names), ""


def _tree_file(folder: Path, key: str, default: str) -> Path | None:
    """The tree file ``job.ini`` names under ``key`` (inside ``folder``), else ``default`` where it exists."""
    ini = folder / "job.ini"
    name = default
    if ini.is_file():
        parser = configparser.ConfigParser(interpolation=None)
        try:
            parser.read(ini, encoding="utf-8")
        except configparser.Error:
            parser = configparser.ConfigParser(interpolation=None)
        for section in parser.sections():
            name = parser[section].get(key, name)
    path = folder / Path(name).name                    # no path is followed out of the folder
    return path if path.is_file() else None


def _branch_sets(path: Path) -> list[list[tuple[str, float]]]:
    """The branch sets of an NRML logic tree in document order, each its branches' (branchID, weight)."""
    sets = []
    for element in ET.parse(path).iter():
        if element.tag.rsplit("}", 1)[-1] != "logicTreeBranchSet":
            continue
        branches = []
        for branch in element:
            if branch.tag.rsplit("}", 1)[-1] != "logicTreeBranch":
                continue
            weight = next((c.text for c in branch if c.tag.rsplit("}", 1)[-1] == "uncertaintyWeight"), None)
            branches.append((branch.get("branchID", "?"), float(weight or "nan")))
        sets.append(branches)
    if not sets:
        raise ValueError("no logicTreeBranchSet")
    return sets


def _named(path: str, trees: list) -> tuple[str, float] | None:
    """A realization's name and the product of its branches' weights, or None where its codes do not fit the
    trees (one code per branch set of each tree)."""
    parts = path.split("~")
    if len(parts) != len(trees):
        return None
    names, weight = [], 1.0
    for codes, sets in zip(parts, trees):
        if len(codes) != len(sets):
            return None
        for code, branches in zip(codes, sets):
            k = CODES.find(code)
            if not 0 <= k < len(branches):
                return None
            names.append(branches[k][0])
            weight *= branches[k][1]
    return JOIN.join(names), weight
