"""The up-to-date check (pipeline.run.uptodate): digests of contents, not of times or places."""

from __future__ import annotations

import os

from pipeline.run import uptodate


def test_tree_digest_follows_content_not_times(tmp_path):
    (tmp_path / "a.AT2").write_text("one\n")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b.V2").write_text("two\n")
    first, n = uptodate.tree_sha256(tmp_path)
    assert n == 2
    os.utime(tmp_path / "a.AT2", (1, 1))                       # touched: same bytes
    assert uptodate.tree_sha256(tmp_path)[0] == first
    (tmp_path / "a.AT2").write_text("one!\n")                 # one byte more
    assert uptodate.tree_sha256(tmp_path)[0] != first
    (tmp_path / "a.AT2").write_text("one\n")
    (tmp_path / "sub" / "b.V2").rename(tmp_path / "sub" / "c.V2")   # same bytes, another name
    assert uptodate.tree_sha256(tmp_path)[0] != first


def test_an_output_directory_inside_the_records_is_left_out(tmp_path):
    (tmp_path / "a.AT2").write_text("one\n")
    before = uptodate.tree_sha256(tmp_path)
    out = tmp_path / "results"
    out.mkdir()
    (out / "screening.nc").write_bytes(b"written by the run")
    assert uptodate.tree_sha256(tmp_path, exclude=out) == before
    assert uptodate.tree_sha256(tmp_path) != before


def test_an_unreadable_file_is_part_of_the_key_not_an_error(tmp_path, monkeypatch):
    (tmp_path / "a.AT2").write_text("one\n")
    (tmp_path / "b.AT2").write_text("two\n")
    readable = uptodate.tree_sha256(tmp_path)
    real = uptodate.file_sha256

    def refuse(path):
        if str(path).endswith("b.AT2"):
            raise PermissionError(13, "Permission denied")
        return real(path)

    monkeypatch.setattr(uptodate, "file_sha256", refuse)
    unreadable = uptodate.tree_sha256(tmp_path)
    assert unreadable[1] == 2 and unreadable[0] != readable[0]
    assert uptodate.tree_sha256(tmp_path) == unreadable        # stable while it stays unreadable


def test_manifest_is_refused_when_an_output_changed_or_the_lock_is_held(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    for name in uptodate.OUTPUTS:
        (out / name).write_text(name)
    key = {"records_sha256": "x", "records_files": 1}
    assert uptodate.write_manifest(out, key, counts={"records_failed": 0}, margins={}) is not None
    assert uptodate.up_to_date(out, key)["counts"] == {"records_failed": 0}
    assert uptodate.up_to_date(out, {**key, "records_sha256": "y"}) is None
    (out / ".rockscreen" / "lock").write_text("{}")
    assert uptodate.up_to_date(out, key) is None
    (out / ".rockscreen" / "lock").unlink()
    (out / "assets.csv").write_text("edited")
    assert uptodate.up_to_date(out, key) is None
    (out / "assets.csv").unlink()                              # a missing output: no manifest is written
    assert uptodate.write_manifest(out, key, counts={}, margins={}) is None
    assert uptodate.up_to_date(out, key) is None


def test_code_fingerprint_changes_with_a_library_version(monkeypatch):
    first = uptodate.code_fingerprint()
    assert uptodate.code_fingerprint() == first
    real = uptodate.metadata.version
    monkeypatch.setattr(uptodate.metadata, "version", lambda name: "0.0" if name == "numpy" else real(name))
    assert uptodate.code_fingerprint() != first
