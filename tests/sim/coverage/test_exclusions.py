"""``dptbd.sim.coverage.exclusions`` and how the report applies it: the checked-in list
loads, each refusal names the entry and what is wrong, an excluded point is counted apart,
and an entry that matches no point or a covered point is reported stale."""

from __future__ import annotations

import pytest
from helpers.refusals import whole

from dptbd.sim.coverage.exclusions import EXCLUSIONS, Exclusion, load_exclusions
from dptbd.sim.coverage.report import Entry, summarise


def test_the_checked_in_list_loads_and_every_entry_says_why():
    for entry in load_exclusions(EXCLUSIONS):
        assert entry.reason.strip() and entry.point.startswith("hw/")


GOOD = """
[[exclude]]
design = "segmenter"
point = "hw/segmenter.py:201"
kind = "branch"
what = "else"
reason = "n is at least 1"
"""


def test_load_reads_an_entry(tmp_path):
    path = tmp_path / "x.toml"
    path.write_text(GOOD)
    assert load_exclusions(path) == [Exclusion("segmenter", "hw/segmenter.py:201", "branch",
                                               "else", "n is at least 1")]


@pytest.mark.parametrize("text, message", [
    ("[other]\n", "unknown table(s) other; the file holds [[exclude]] tables only"),
    (GOOD.replace('what = "else"', 'line = 3'),
     "exclusion 1: unknown key(s) line; keys are design, point, kind, what, reason"),
    (GOOD + 'bits = "20-31"\n',
     "exclusion 1: bits is for a toggle exclusion whose what names the register"),
    (GOOD.replace('"branch"', '"toggle"') + 'bits = "31-20"\n',
     "exclusion 1: bits '31-20' is not lo-hi (bit indices, lo <= hi)"),
    (GOOD.replace('reason = "n is at least 1"', ''),
     "exclusion 1: reason missing; every exclusion names its design, point, kind and the "
     "reason it cannot be reached"),
    (GOOD.replace('"segmenter"', '"seg"'),
     "exclusion 1: design 'seg' is not one of dp, core, segmenter, axi"),
    (GOOD.replace('"branch"', '"expr"'),
     "exclusion 1: kind 'expr' is not one of line, branch, toggle"),
    (GOOD.replace('"hw/segmenter.py:201"', '"hw/segmenter.py"'),
     "exclusion 1: point 'hw/segmenter.py' is not file.py:line"),
])
def test_load_refuses(tmp_path, text, message):
    path = tmp_path / "x.toml"
    path.write_text(text)
    with pytest.raises(ValueError, match=whole(f"{path}: {message}")):
        load_exclusions(path)


def entry(src, what, count, kind="branch", build="b1"):
    return Entry("segmenter", build, "dptbd_seg.segmenter", kind, src, what, 10, count)


def test_excluded_points_count_apart_and_stale_entries_are_reported():
    points = [entry("hw/segmenter.py:201", "if", 4), entry("hw/segmenter.py:201", "else", 0),
              entry("hw/segmenter.py:311", "if", 2), entry("hw/segmenter.py:311", "else", 1),
              entry("hw/segmenter.py:400", "if", 0),
              entry("hw/segmenter.py:400", "if", 3, build="b2")]   # covered in another build
    unreachable = Exclusion("segmenter", "hw/segmenter.py:201", "branch", "else", "why")
    gone = Exclusion("segmenter", "hw/segmenter.py:999", "branch", None, "why")
    reached = Exclusion("segmenter", "hw/segmenter.py:311", "branch", None, "why")
    summary = summarise(points, [unreachable, gone, reached])
    assert summary.counts == {("segmenter", "dptbd_seg.segmenter", "branch"): [2, 2, 3]}
    assert summary.figure("segmenter", "branch") == (2, 2)
    assert summary.uncovered == []
    assert summary.stale == [(gone, "no such point (the source changed?)"),
                             (reached, "covered: the point is reached")]
    other = Exclusion("axi", "hw/segmenter.py:999", "branch", None, "why")
    assert summarise(points, [other]).stale == []           # no axi run: no verdict
    bare = summarise(points)
    assert bare.figure("segmenter", "branch") == (4, 5)
    assert [name for name, _ in bare.uncovered] == [
        ("segmenter", "dptbd_seg.segmenter", "branch", "hw/segmenter.py:201", "else")]


def test_a_bit_class_excludes_the_bits_of_its_range_only(tmp_path):
    path = tmp_path / "x.toml"
    path.write_text(GOOD.replace('"branch"', '"toggle"').replace('"else"', '"frames_value"')
                    + 'bits = "20-31"\n')
    (high,) = load_exclusions(path)
    assert high.bits == (20, 31)
    points = [entry("hw/segmenter.py:201", f"frames_value[{k}]", 0, "toggle")
              for k in (0, 19, 20, 31)] + [entry("hw/segmenter.py:201", "frames", 0, "toggle"),
                                           entry("hw/segmenter.py:201", "frames_value2[25]", 0,
                                                 "toggle")]
    summary = summarise(points, [high])
    assert summary.counts == {("segmenter", "dptbd_seg.segmenter", "toggle"): [0, 4, 2]}
    assert [name[4] for name, _ in summary.uncovered] == [
        "frames", "frames_value2[25]", "frames_value[0]", "frames_value[19]"]
