"""dptbd.output_folder: every refusal (whole message), all-or-nothing folders, a user's folder
never replaced, files never overwritten without --force."""

import json
import os
import pathlib

import numpy as np
import pytest

from dptbd.output_folder import (check_new_files, check_output_file, check_output_folder,
                                 check_still_new, json_text, jsonable, staged_folder,
                                 write_new_text, written_by)
from helpers.refusals import whole

MARK = dict(marker="summary.json", tool="dptbd run")


def earlier_run(folder, tool="dptbd run"):
    folder.mkdir()
    (folder / "summary.json").write_text(json.dumps({"tool": tool}))
    (folder / "table.md").write_text("old")
    return folder


def leftovers(folder):
    return sorted(p.name for p in folder.iterdir())


def test_written_by_reads_the_marker_tool(tmp_path):
    assert written_by(earlier_run(tmp_path / "r"), "summary.json", "dptbd run")
    assert not written_by(tmp_path / "r", "summary.json", "dptbd compare")
    assert not written_by(tmp_path / "r", "result.json", "dptbd run")
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / "summary.json").write_text("[1, 2]")     # JSON, but not an object
    assert not written_by(tmp_path / "bad", "summary.json", "dptbd run")
    (tmp_path / "bad" / "summary.json").write_text("{not json")
    assert not written_by(tmp_path / "bad", "summary.json", "dptbd run")


def test_a_new_folder_and_an_empty_one_pass(tmp_path):
    assert check_output_folder(tmp_path / "new", False, **MARK) == tmp_path / "new"
    (tmp_path / "empty").mkdir()
    assert check_output_folder(tmp_path / "empty", True, **MARK) == tmp_path / "empty"


def test_refuses_a_missing_parent(tmp_path):
    out = tmp_path / "no" / "r"
    with pytest.raises(FileNotFoundError, match=whole(
            f"--out {out}: the folder {tmp_path / 'no'} does not exist")):
        check_output_folder(out, False, **MARK)


def test_refuses_the_current_folder_and_its_parents(tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    for out in (work, tmp_path):
        with pytest.raises(ValueError, match=whole(
                f"--out {out} is the current folder or one of its parents; give a new folder")):
            check_output_folder(out, True, **MARK)


def test_refuses_an_existing_folder_without_force(tmp_path):
    out = earlier_run(tmp_path / "r")
    with pytest.raises(FileExistsError, match=whole(
            f"--out {out} exists; pass --force to replace it, or choose another folder")):
        check_output_folder(out, False, **MARK)


def test_force_refuses_a_file_and_a_link(tmp_path):
    (tmp_path / "f").write_text("mine")
    earlier_run(tmp_path / "r")
    (tmp_path / "link").symlink_to(tmp_path / "r")
    for name in ("f", "link"):
        out = tmp_path / name
        with pytest.raises(FileExistsError, match=whole(
                f"--out {out} exists and is not a folder; --force replaces only the folder of "
                f"an earlier dptbd run")):
            check_output_folder(out, True, **MARK)


def test_force_refuses_a_folder_another_job_or_the_user_wrote(tmp_path):
    other = earlier_run(tmp_path / "other", tool="dptbd compare")
    with pytest.raises(FileExistsError, match=whole(
            f"--out {other} is not the folder of an earlier dptbd run (no summary.json from "
            f"it); --force will not replace it")):
        check_output_folder(other, True, **MARK)
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    with pytest.raises(FileExistsError, match=whole(
            f"--dir {mine} is not the folder of an earlier dptbd detectors run (no result.json "
            f"from it); --force will not replace it")):
        check_output_folder(mine, True, marker="result.json", tool="dptbd detectors",
                            option="--dir")


def test_staged_folder_appears_only_when_complete(tmp_path):
    out = tmp_path / "r"
    with staged_folder(out, False, **MARK) as tmp:
        assert tmp.parent == tmp_path and tmp.name.startswith(".r.partial-")
        (tmp / "summary.json").write_text(json.dumps({"tool": "dptbd run"}))
        assert not out.exists()
    assert leftovers(tmp_path) == ["r"] and leftovers(out) == ["summary.json"]
    umask = os.umask(0)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o777 & ~umask      # not mkdtemp's private 0700


def test_an_exception_inside_leaves_nothing_and_the_old_folder_as_it_was(tmp_path):
    out = tmp_path / "r"
    with pytest.raises(RuntimeError, match="^disk full$"):
        with staged_folder(out, False, **MARK) as tmp:
            (tmp / "table.md").write_text("half")
            raise RuntimeError("disk full")
    assert leftovers(tmp_path) == []
    earlier_run(out)
    with pytest.raises(KeyboardInterrupt):
        with staged_folder(out, True, **MARK) as tmp:
            (tmp / "table.md").write_text("new")
            raise KeyboardInterrupt
    assert leftovers(tmp_path) == ["r"] and (out / "table.md").read_text() == "old"


def test_force_replaces_an_earlier_run_as_a_whole(tmp_path):
    out = earlier_run(tmp_path / "r")
    with staged_folder(out, True, **MARK) as tmp:
        (tmp / "summary.json").write_text(json.dumps({"tool": "dptbd run", "new": True}))
    assert leftovers(out) == ["summary.json"] and json.loads((out / "summary.json").read_text())["new"]
    assert leftovers(tmp_path) == ["r"]


def test_a_user_folder_that_appears_meanwhile_is_never_replaced(tmp_path):
    out = tmp_path / "r"
    with pytest.raises(FileExistsError, match=whole(
            f"--out {out} is not the folder of an earlier dptbd run (no summary.json from it); "
            f"--force will not replace it")):
        with staged_folder(out, True, **MARK) as tmp:
            (tmp / "summary.json").write_text(json.dumps({"tool": "dptbd run"}))
            out.mkdir()
            (out / "notes.txt").write_text("keep")
    assert leftovers(tmp_path) == ["r"] and leftovers(out) == ["notes.txt"]


def test_staged_folder_refuses_before_the_block_runs(tmp_path):
    out = earlier_run(tmp_path / "r")
    entered = []
    with pytest.raises(FileExistsError, match=whole(
            f"--out {out} exists; pass --force to replace it, or choose another folder")):
        with staged_folder(out, False, **MARK):
            entered.append(True)
    assert entered == [] and leftovers(tmp_path) == ["r"]


@pytest.mark.parametrize("name, force, exception, message", [
    ("t.txt", False, ValueError, "--markdown {path} must end in .md"),
    ("folder.md", True, FileExistsError, "--markdown {path} is a folder"),
    ("no/t.md", False, FileNotFoundError, "--markdown {path}: the folder {parent} does not exist"),
    ("old.md", False, FileExistsError, "--markdown {path} exists; pass --force to overwrite it"),
])
def test_check_output_file_refusals(tmp_path, name, force, exception, message):
    (tmp_path / "folder.md").mkdir()
    (tmp_path / "old.md").write_text("mine")
    path = tmp_path / name
    with pytest.raises(exception, match=whole(message.format(path=path, parent=path.parent))):
        check_output_file(path, "--markdown", force, ".md")


def test_check_output_file_passes(tmp_path):
    check_output_file(None, "--markdown", False, ".md")
    check_output_file(tmp_path / "new.MD", "--markdown", False, ".md")
    (tmp_path / "old.md").write_text("mine")
    check_output_file(tmp_path / "old.md", "--markdown", True, ".md")


def test_write_new_text_never_replaces_without_force(tmp_path):
    path = tmp_path / "t.md"
    write_new_text(path, "one", False)
    with pytest.raises(FileExistsError):
        write_new_text(path, "two", False)
    assert path.read_text() == "one"
    write_new_text(path, "three", True)
    assert path.read_text() == "three"


def test_check_new_files_names_every_existing_one(tmp_path):
    v, j, h = tmp_path / "top.v", tmp_path / "top.json", tmp_path / "top.h"
    check_new_files([v, j, h], False)
    v.write_text("mine")
    with pytest.raises(FileExistsError, match=whole(f"{v} exists; pass --force to overwrite")):
        check_new_files([v, j, h], False)
    j.write_text("mine")
    h.symlink_to(tmp_path / "nowhere")
    with pytest.raises(FileExistsError, match=whole(
            f"{v}, {j} and {h} exist; pass --force to overwrite")):
        check_new_files([v, j, h], False)
    check_new_files([v, j, h], True)
    assert v.read_text() == "mine"


def test_check_still_new_refuses_a_file_that_appeared(tmp_path):
    path = tmp_path / "f.png"
    check_still_new(path, "--figure", False)
    path.write_bytes(b"mine")
    with pytest.raises(FileExistsError, match=whole(
            f"--figure {path} appeared during the run; not overwritten")):
        check_still_new(path, "--figure", False)
    check_still_new(path, "--figure", True)


def strict(text):
    """``json.loads`` refusing NaN and +-Infinity, as ``jq`` and other languages' parsers do."""
    def refuse(name):
        raise ValueError(f"{name} is not JSON")
    return json.loads(text, parse_constant=refuse)


def test_json_text_writes_every_non_finite_number_as_null():
    value = {"nan": float("nan"), "inf": np.float64("inf"), "rows": (1.5, -np.inf, np.int64(7)),
             "array": np.array([0.25, np.nan]), ("a", 1): np.bool_(True), 3: pathlib.Path("x/y")}
    assert strict(json_text(value)) == {"nan": None, "inf": None, "rows": [1.5, None, 7],
                                        "array": [0.25, None], "('a', 1)": True, "3": "x/y"}
    assert jsonable([np.float32(0.5), {"k": [float("-inf")]}]) == [0.5, {"k": [None]}]


def test_json_text_keeps_finite_output_as_json_dumps_writes_it():
    value = {"tool": "t", "pd": 0.1 + 0.2, "n": 3, "ok": False, "none": None, "keys": {8.0: 1}}
    for options in ({}, {"indent": 1}, {"indent": 2, "sort_keys": True}):
        assert json_text(value, **options) == json.dumps(value, **options)


def test_a_non_finite_number_from_a_default_hook_fails_loudly():
    with pytest.raises(ValueError, match=whole("Out of range float values are not JSON compliant: "
                                               "nan")):
        json_text({"value": object()}, indent=1, default=lambda o: float("nan"))
