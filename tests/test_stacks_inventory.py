"""Stacks in the inventory (pipeline.stacks): each bad stack a named error with its line, the masses the motion
reads, and a stack's body recomputed when any body of its stack changes."""

from __future__ import annotations

import math

import pytest

from pipeline.blocks import read_inventory
from pipeline.errors import InventoryError

HEADER = "id,height_m,width_m,mu,azimuth_deg,shape,depth_m,mass_kg,density_kg_m3,stands_on,offset_m\n"
PLINTH = "PL,1.0,0.8,0.6,,,,,,,\n"
STATUE = "ST,1.6,0.5,0.6,,,,,,PL,\n"


def _read(tmp_path, rows: str):
    path = tmp_path / "blocks.csv"
    path.write_text(HEADER + rows)
    return read_inventory(path, default_mu=0.6)


def test_a_statue_on_its_plinth_is_one_stack_bottom_first(tmp_path):
    inv = _read(tmp_path, PLINTH + STATUE + "SOLO,1.0,0.3,0.6,,,,,,,\n")
    plinth, statue, solo = (inv.shape(k) for k in range(3))
    assert solo.stack is None
    assert plinth.stack is not None and statue.stack is not None
    assert plinth.stack.ids == statue.stack.ids == ("PL", "ST")
    assert (plinth.stack.position, statue.stack.position) == (0, 1)
    assert [b.height_m for b in statue.stack.bodies] == [1.0, 1.6]


def test_masses_follow_the_volumes_of_one_density_unless_given(tmp_path):
    """Blank mass and density: one density, a square plan where no depth is given (0.8 x 1.0 x 0.8 against
    0.5 x 1.6 x 0.5); a given mass, or a density given on one body, wins."""
    bodies = _read(tmp_path, PLINTH + STATUE).shape(0).stack.bodies
    assert bodies[0].mass_kg / bodies[1].mass_kg == pytest.approx(0.64 / 0.4)
    given = _read(tmp_path, "PL,1.0,0.8,0.6,,,0.4,,2400,,\n" "ST,1.6,0.5,0.6,,,,300,,PL,\n").shape(0).stack.bodies
    assert (given[0].mass_kg, given[1].mass_kg) == (pytest.approx(2400 * 0.8 * 1.0 * 0.4), 300.0)


def test_the_offset_places_the_upper_body(tmp_path):
    from pipeline.stacks import joint_openings, stack_placements

    inv = _read(tmp_path, PLINTH + "ST,1.6,0.5,0.6,,,,,,PL,0.1\n" + "SOLO,1.0,0.3,0.6,,,,,,,\n")
    assert inv.shape(1).stack.bodies[1].offset_m == 0.1
    centres, bases = stack_placements(inv.stacks, len(inv))        # the statue 0.1 m aside on the 1.0 m plinth
    assert list(centres[:2]) == [0.0, 0.1] and list(bases[:2]) == [0.0, 1.0]
    assert math.isnan(centres[2]) and math.isnan(bases[2])
    # the statue 0.1 m off centre, fully on the plinth: its joint opens at the nearer end of its own base, 0.25 / 0.8
    openings = joint_openings(inv.stacks, len(inv))
    assert openings[1] == pytest.approx(0.25 / 0.8, rel=1e-12) and math.isnan(openings[2])


def _rules(tmp_path, rows: str):
    path = tmp_path / "rules.csv"
    path.write_text(HEADER.rstrip("\n") + ",stack_verdict\n" + rows)
    return read_inventory(path, default_mu=0.6)


def test_a_stack_is_failed_by_its_own_rule(tmp_path):
    """The rule given on any body is the stack's (blank: any body falls); each body's verdicts under each record
    give the stack's: any body, the top body, the bottom body (a body falling first, then no verdict)."""
    import numpy as np

    from pipeline.stacks import StackRule, stack_verdicts

    assert _read(tmp_path, PLINTH + STATUE).stacks[0].rule == StackRule.any
    # records: the statue falls alone; both fall; nothing falls; the statue has no verdict, the plinth stands
    overturn = np.array([[0, 1], [1, 1], [0, 0], [0, -1]])
    expected = {"any": [1, 1, 0, -1], "top": [1, 1, 0, -1], "collapse": [0, 1, 0, 0]}
    for rule, fails in expected.items():
        inv = _rules(tmp_path, f"PL,1.0,0.8,0.6,,,,,,,,{rule}\n" + STATUE.rstrip("\n") + ",\n")
        assert inv.stacks[1].rule == StackRule[rule]
        got = stack_verdicts(overturn, inv.stacks)
        assert got["stack_fails"][1].T.tolist() == [fails, fails], rule
        assert list(got["stack_rule"][1]) == [rule, rule]


@pytest.mark.parametrize("rows, found", [
    ("PL,1.0,0.8,0.6,,,,,,,,all\n" + STATUE.rstrip("\n") + ",\n",
     r"line 2, column 'stack_verdict': 'all' is not a rule"),
    ("PL,1.0,0.8,0.6,,,,,,,,top\n" + STATUE.rstrip("\n") + ",collapse\n",
     r"is given the rules \['collapse', 'top'\]; a stack has one"),
    ("SOLO,1.0,0.3,0.6,,,,,,,,top\n", r"line 2, column 'stack_verdict': 'top' on a row in no stack"),
])
def test_a_bad_stack_rule_is_a_named_error(tmp_path, rows, found):
    with pytest.raises(InventoryError, match=found):
        _rules(tmp_path, rows)


@pytest.mark.parametrize("rows, found", [
    (PLINTH + "ST,1.6,0.5,0.6,,,,,,PLX,\n", r"line 3, column 'stands_on': 'PLX' is not the id of a row"),
    (PLINTH + "ST,1.6,0.5,0.6,,,,,,ST,\n", "line 3, column 'stands_on': the row stands on itself"),
    ("A,1,0.3,0.5,,,,,,B,\nB,1,0.3,0.5,,,,,,A,\n", "line 2, column 'stands_on': .* in a loop"),
    (PLINTH + STATUE + "ST2,1.0,0.3,0.6,,,,,,PL,\n", "'PL' already carries 'ST'"),
    (PLINTH + STATUE + "".join(f"D{k},0.5,0.3,0.6,,,,,,{'ST' if k == 0 else f'D{k - 1}'},\n" for k in range(4)),
     "has 6 bodies; the assembly model takes stacks of at most 5"),
    (PLINTH + "ST,1.6,0.5,0.6,,cylinder,,,,PL,\n", "line 3: a body of the stack .* is a cylinder or a scan"),
    ("PL,1.0,0.8,0.6,30,,,,,,\nST,1.6,0.5,0.6,,,,,,PL,\n", "line 3, column 'azimuth_deg': nan differs from the bottom"),
    (PLINTH + "ST,1.6,0.5,0.6,,,,,,PL,0.45\n", "cannot stand at rest"),
    (PLINTH + "ST,1.6,0.5,0.6,,,,,,,0.1\n", "line 3, column 'offset_m': '0.1' on a row that stands on no body"),
    (PLINTH + "ST,1.6,0.5,0.6,,,,,,PL,x\n", "line 3, column 'offset_m'"),
])
def test_a_bad_stack_is_a_named_error_with_its_line(tmp_path, rows, found):
    with pytest.raises(InventoryError, match=found):
        _read(tmp_path, rows)


def test_the_bodies_of_a_stack_stand_on_one_floor(tmp_path):
    path = tmp_path / "blocks.csv"
    path.write_text("id,height_m,width_m,building,floor,stands_on\nPL,1.0,0.8,MUSEUM,2,\nST,1.6,0.5,MUSEUM,3,PL\n")
    with pytest.raises(InventoryError, match="line 3, column 'floor': '3' differs from the bottom body 'PL'"):
        read_inventory(path, default_mu=0.6)


def test_a_body_is_recomputed_when_its_stack_changes(tmp_path):
    """The statue's digest (what the scene cache keys on) changes with its plinth's width, its own row unchanged."""
    before = _read(tmp_path, PLINTH + STATUE).digests()
    after = _read(tmp_path, "PL,1.0,0.7,0.6,,,,,,,\n" + STATUE).digests()
    assert before[1] != after[1] and before[0] != after[0]
    same = _read(tmp_path, PLINTH + STATUE).digests()
    assert same == before


def test_a_sub_inventory_keeps_each_bodys_stack(tmp_path):
    """A task screening some blocks (Inventory.take) judges a body with its whole stack, even without the others."""
    inv = _read(tmp_path, PLINTH + STATUE + "SOLO,1.0,0.3,0.6,,,,,,,\n")
    sub = inv.take([1, 2])
    assert sub.shape(0).stack == inv.shape(1).stack and sub.shape(1).stack is None
    assert math.isclose(sub.shape(0).stack.bodies[0].width_m, 0.8)


def test_a_restitution_given_to_a_stacks_body_is_named_as_not_used(tmp_path, caplog):
    path = tmp_path / "blocks.csv"
    path.write_text("id,height_m,width_m,restitution,stands_on\nPL,1.0,0.8,,\nST,1.6,0.5,0.8,PL\n")
    read_inventory(path, default_mu=0.6)
    assert "restitution given for ST, bodies of a stack: not used" in caplog.text
