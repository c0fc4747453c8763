"""Nothing under an output directory is followed out of it: a link planted where rockscreen deletes, writes, locks or
links is refused (exit 3, the path named) and nothing outside the output changes; what rockscreen makes itself (its
links, a copy that followed them, a killed publish's temporaries) is accepted."""

from __future__ import annotations

import os
import shutil

import pytest
from planted_links import ACTIONS, FIVE, PLANTS, fingerprint, published, victim
from small_run import one_record_run

from pipeline.errors import UnsafeOutputError
from pipeline.run.cache import ensure_writable
from pipeline.store import OutputLock, check_output_tree
from pipeline.store.sets import output_names


@pytest.mark.parametrize("action", ACTIONS)
@pytest.mark.parametrize("plant", PLANTS)
def test_a_link_planted_where_rockscreen_acts_is_refused_and_nothing_outside_changes(plant, action, tmp_path):
    out = published(tmp_path / "out")
    v = victim(tmp_path)
    PLANTS[plant](out, v)
    before, outside = fingerprint(v), fingerprint(tmp_path / "victim")
    with pytest.raises(UnsafeOutputError, match=r"\.rockscreen|report\.html") as err:
        ACTIONS[action](out)
    assert isinstance(err.value, OSError)
    assert "changed nothing" in str(err.value)
    assert fingerprint(v) == before == outside


def test_what_rockscreen_makes_is_accepted(tmp_path):
    """Its own links, a killed publish's temporary link, a copy through the links (cp -r, the pointer a real
    directory), the outputs' dangling links of ``cp -r OUT/*``, and a user's own links by other names."""
    out = published(tmp_path / "out")
    os.symlink("sets/x", out / ".rockscreen" / ".screening.current.99.link.tmp")
    (out / "mine").symlink_to(victim(tmp_path))               # a user's link by a name rockscreen never writes
    check_output_tree(out, output_names=output_names(out))
    OutputLock(out).acquire().release()
    copy = tmp_path / "copy"
    shutil.copytree(out, copy, symlinks=False, ignore_dangling_symlinks=True)
    check_output_tree(copy, output_names=output_names(copy))
    bare = tmp_path / "bare"                                   # cp -r OUT/* DEST: links to a state it lacks
    bare.mkdir()
    for name in FIVE:
        os.symlink(os.readlink(out / name), bare / name)
    check_output_tree(bare, output_names=output_names(bare))


def test_a_missing_output_directory_is_fine_and_a_file_in_its_place_is_named(tmp_path):
    check_output_tree(tmp_path / "not yet", output_names=FIVE)
    (tmp_path / "file").write_text("x")
    with pytest.raises(UnsafeOutputError, match="is a file"):
        check_output_tree(tmp_path / "file", output_names=FIVE)


@pytest.mark.slow
def test_screen_force_and_screen_report_refuse_a_planted_link_with_exit_3(make_records, tmp_path, capsys):
    """The findings as reported: ``.rockscreen/cache`` a link to another folder before ``screen --force`` and
    ``.rockscreen/figures`` one before ``screen report``; the lock a link to a file. Each command exits 3 naming the
    path; the other folder and file are as they were."""
    from pipeline.cli import main

    run, out = one_record_run(make_records, tmp_path)
    v = victim(tmp_path)
    before = fingerprint(v)
    for plant, command in (("cache", [*run, "--force"]), ("figures", ["report", str(out / "screening.nc")]),
                           ("lock", [*run, "--force"])):
        PLANTS[plant](out, v)
        assert main(command) == 3
        assert f"{out}/.rockscreen/{plant}" in capsys.readouterr().err
        assert fingerprint(v) == before
        (out / ".rockscreen" / plant).unlink()                      # the operator removes it: runs again
    assert main([*run, "--force"]) == 0


def test_a_users_own_files_in_a_fresh_output_are_refused_not_replaced(tmp_path):
    """A folder rockscreen never wrote into, holding the user's report.html and assets.csv: refused, named, kept.
    The same names beside a screening.nc are a copy of rockscreen's outputs that followed its links: accepted."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.html").write_text("mine")
    (out / "assets.csv").write_text("mine")
    with pytest.raises(UnsafeOutputError, match=r"holds assets\.csv, report\.html, which rockscreen did not write"):
        ensure_writable(out, replaces=FIVE)                     # screen writes both
    assert (out / "report.html").read_text() == "mine" and not (out / ".rockscreen").exists()
    ensure_writable(out, replaces=("fragility.nc", "fragility_assets.csv"))      # a command that writes neither
    shutil.rmtree(out / ".rockscreen")
    (out / "screening.nc").write_bytes(b"copied")
    ensure_writable(out, replaces=FIVE)


def test_a_copy_of_the_folders_contents_without_its_state_says_how_to_copy(tmp_path):
    """``cp -r OUT/* DEST`` leaves DEST's outputs as links into a .rockscreen it lacks: reading them names the cause
    and the copies that work."""
    from pipeline.errors import ResultsError
    from pipeline.store import open_results

    out = published(tmp_path / "out")
    dest = tmp_path / "dest"
    dest.mkdir()
    for name in FIVE:
        os.symlink(os.readlink(out / name), dest / name)
    with pytest.raises(ResultsError, match=r"left out its hidden \.rockscreen.*cp -r OUT DEST.*cp -rL"):
        open_results(dest / "screening.nc")
