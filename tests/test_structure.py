"""The code's structure, read from the sources: per-scene variables named once, short functions, one typed scene
table, a model registry the planner dispatches through."""

from __future__ import annotations

import ast
import dataclasses
import functools
from pathlib import Path

import pytest

from pipeline import schema
from pipeline.scene_table import SCENE, SceneColumns

PIPELINE = Path(__file__).resolve().parents[1] / "pipeline"
PER_SCENE = set(schema.PULSE_BLOCK_VARS + schema.SIMULATION_VARS + schema.PROBABILITY_VARS + schema.FLOOR_VARS)
#: Strings equal to a per-scene variable's name that name something else, with what they name.
HOMONYMS = {
    ("rocking/planar/kernel.py", "theta_max"): "a field of the rocking kernel's progress record",
    ("rocking/planar/kernel.py", "n_impacts"): "a field of the rocking kernel's progress record",
    ("rocking/scanned/two_sided.py", "n_impacts"): "a field of the two-sided kernel's progress record",
    ("rocking/planar/contact.py", "theta_max"): "a field of the contact model's motion record",
    ("rocking/planar/contact.py", "n_impacts"): "a field of the contact model's motion record",
    ("uncertainty/hazard_files.py", "response"): "a key of the USGS hazard service's JSON",
    ("store/exports.py", "orientation"): "fragility.nc's attribute: the orientation the curves are for",
    ("report/fragility_html.py", "orientation"): "fragility.nc's attribute and fragility_assets.csv's column",
    ("run/fragility_assembly.py", "orientation"): "fragility.nc's attribute: the orientation the curves are for",
    ("run/accuracy.py", "orientation"): "a section of screen bench's table (the orientation scan's rows)",
}
MAX_FUNCTION_LINES = 80


@functools.cache
def _modules() -> tuple[tuple[str, ast.Module], ...]:
    """Every module of the package, parsed once for the file's tests (which only read the trees)."""
    return tuple((path.relative_to(PIPELINE).as_posix(), ast.parse(path.read_text()))
                 for path in sorted(PIPELINE.rglob("*.py")))


def test_per_scene_variables_are_named_as_strings_only_in_the_schema():
    found = []
    for rel, tree in _modules():
        if rel == "schema.py":
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and node.value in PER_SCENE and (rel, node.value) not in HOMONYMS:
                found.append(f"{rel}:{node.lineno}: {node.value!r}")
    assert found == [], "read them as SCENE.<name> or SceneColumns fields"


def test_every_scene_name_read_in_the_package_is_a_per_scene_variable():
    names = {node.attr for _, tree in _modules() for node in ast.walk(tree)
             if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "SCENE"}
    assert names and names <= PER_SCENE, sorted(names - PER_SCENE)
    assert all(getattr(SCENE, n) == n for n in names)
    with pytest.raises(AttributeError, match="not a per-scene variable"):
        _ = SCENE.p_overturned


def test_the_scene_table_has_the_schemas_per_scene_variables_in_order():
    assert tuple(f.name for f in dataclasses.fields(SceneColumns)) == schema.SIMULATION_VARS + schema.PROBABILITY_VARS
    for name in schema.SIMULATION_VARS + schema.PROBABILITY_VARS:
        assert schema.SCHEMA[name][0] == ("record", "block")


def test_no_function_is_over_80_lines():
    long = [f"{rel}:{node.lineno} {node.name} ({node.end_lineno - node.lineno + 1} lines)"
            for rel, tree in _modules() for node in ast.walk(tree)
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
            and node.end_lineno - node.lineno + 1 > MAX_FUNCTION_LINES]
    assert long == []


def test_the_planner_dispatches_through_the_registry_without_a_model_chain():
    """plan() and simulate_scene() compare no Physics member: the registry's certificates choose."""
    tree = ast.parse((PIPELINE / "rocking" / "planner.py").read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and node.name in ("plan", "simulate_scene"):
            uses = {n.value.id for n in ast.walk(node)
                    if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name)}
            assert "Physics" not in uses, node.name
            calls = {n.func.id for n in ast.walk(node) if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)}
            assert "choose" in calls, node.name


#: What the CLI may import below the run layer, and why: each only to parse an option or to print.
CLI_LIBRARY_IMPORTS = {
    "closed_forms": "PULSE_BETA: the pulse shapes --pulse accepts",
    "records.intensity": "IMS, SCALABLE, display_unit: the IMs --im accepts and the unit --levels is printed in",
    "uncertainty.hazard": "Component: the component definitions --im-component accepts",
    "event.assets": "Level: the inspection levels it counts",
    "uncertainty.constraint": "Combine: the rules --combine accepts",
}
#: The application modules the CLI calls (the run layer orchestrates; these read inputs or name outputs; ticker says
#: something at least every 2 s: printing, the CLI's own work).
CLI_APPLICATION_IMPORTS = ("run", "config", "errors", "blocks", "levels", "scene_table", "ticker")


def test_the_cli_parses_and_prints_and_leaves_the_work_to_the_run_layer():
    imported = set()
    for path in (PIPELINE / "cli").glob("*.py"):            # the package's own modules import one another
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level == 2 and node.module:
                imported.add(node.module)
    below = {m for m in imported if m.split(".")[0] not in CLI_APPLICATION_IMPORTS}
    assert below <= set(CLI_LIBRARY_IMPORTS), sorted(below - set(CLI_LIBRARY_IMPORTS))
    assert not {m for m in imported if m.split(".")[0] in ("store", "report", "floors", "pulses")}


def test_the_cli_loads_no_simulator_before_it_has_work():
    """``screen --help``, usage errors and an up-to-date run answer at once: importing the CLI loads neither numba
    nor the simulator (a fresh interpreter)."""
    import subprocess
    import sys

    code = ("import sys, pipeline.cli\n"
            "print(','.join(sorted(m for m in sys.modules\n"
            "                      if m.startswith(('numba', 'pipeline.rocking.planar.kernel')))))")
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip() == ""


def test_no_module_of_the_command_line_is_over_300_lines():
    """The command line is a package of small modules (one per subcommand, the shared options, progress, exits)."""
    long = {p.name: n for p in (PIPELINE / "cli").glob("*.py") if (n := len(p.read_text().splitlines())) > 300}
    assert long == {}, long


def test_the_tests_mirror_the_package():
    """A module's tests are found by its path: every folder of tests/ (but the shared support/ and data/) is a package
    of pipeline/, and every test file sits in one of them or at the top for the top-level modules."""
    tests = Path(__file__).resolve().parent
    folders = [p.relative_to(tests) for p in tests.rglob("*") if p.is_dir() and "__pycache__" not in p.parts
               and p.relative_to(tests).parts[0] not in ("support", "data")]
    assert folders and [f for f in folders if not (PIPELINE / f / "__init__.py").is_file()] == []
    stray = [p.name for p in tests.glob("*.py") if not p.name.startswith("test_") and p.name != "conftest.py"]
    assert stray == [], f"helpers belong in tests/support/: {stray}"


def test_no_code_outside_a_bodys_own_modules_reads_its_type():
    """The 3D bodies are dispatched by their family (``solid3d.FAMILIES``): ``isinstance`` on Box or Cylinder appears
    only in the box's and the cylinder's own modules."""
    bodies = {"Box", "Cylinder"}
    found = []
    for rel, tree in _modules():
        if rel.split("/")[-1].startswith(("box", "cylinder")):
            continue
        for node in ast.walk(tree):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "isinstance"
                    and len(node.args) == 2):
                kinds = node.args[1].elts if isinstance(node.args[1], ast.Tuple) else [node.args[1]]
                if any(isinstance(k, ast.Name) and k.id in bodies for k in kinds):
                    found.append(f"{rel}:{node.lineno}")
    assert found == [], "dispatch through the body's family (rocking/solids/family.py), not its type"


#: The solids' and contact models' code: every function documented and at most this long (lines from its def).
SOLIDS_MAX_FUNCTION_LINES = 60


def test_every_function_of_the_solids_and_contact_code_is_documented_and_short():
    long_or_bare = []
    for rel, tree in _modules():
        if not (rel.startswith("rocking/solids/") or rel.startswith("rocking/planar/contact")):
            continue
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                lines = node.end_lineno - node.lineno + 1
                if lines > SOLIDS_MAX_FUNCTION_LINES or not ast.get_docstring(node):
                    long_or_bare.append(f"{rel}:{node.lineno} {node.name} ({lines} lines)")
    assert long_or_bare == [], "split it, or say what it does"


#: The weights of the Runge-Kutta methods (numerics/rk.py's tableaux), as a step written out would spell them.
RK_WEIGHTS = {35 / 384, 500 / 1113, 125 / 192, 2187 / 6784, 11 / 84, 71 / 57600, 9017 / 3168, 19372 / 6561}


def _stages_written_out(function):
    """The stage numbers a function assigns as a written-out step names its stages (k1, k2o, k3t ...)."""
    numbers = set()
    for node in ast.walk(function):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            name = node.id
            if len(name) in (2, 3) and name[0] == "k" and name[1] in "1234567" and name[2:] in ("", "t", "o"):
                numbers.add(name[1])
    return numbers


def test_one_runge_kutta_step_in_the_tree():
    """Every ODE model steps through numerics/rk.py's rk_step: no other function names three or more stages k1, k2,
    k3 ... written out, and no other module spells a weight of the methods' tableaux (35 / 384 and the like)."""
    found = []
    for rel, tree in _modules():
        if rel == "rocking/numerics/rk.py":
            continue
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and len(_stages_written_out(node)) >= 3:
                found.append(f"{rel}:{node.lineno} {node.name}")
            if (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Div)
                    and all(isinstance(v, ast.Constant) and isinstance(v.value, (int, float))
                            for v in (node.left, node.right))
                    and node.right.value and node.left.value / node.right.value in RK_WEIGHTS):
                found.append(f"{rel}:{node.lineno} {node.left.value} / {node.right.value}")
    assert found == [], "step through pipeline.rocking.numerics.rk.rk_step with the method's tableau"
