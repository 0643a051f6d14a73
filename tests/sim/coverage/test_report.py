"""``dptbd.sim.coverage.report``: points added up by name across builds (a toggle bit by
register and index), the terminal table against the goals, the report's text."""

from __future__ import annotations

import shutil

import pytest
from helpers.refusals import whole

from dptbd.sim.coverage.code import read_dat
from dptbd.sim.coverage.report import Entry, RunMerger, _markdown, format_table, summarise


def e(kind, src, what, count, build="b1", design="segmenter", module="dptbd_seg.segmenter"):
    return Entry(design, build, module, kind, src, what, 7, count)


def test_points_add_up_by_name_across_builds():
    points = [e("line", "hw/a.py:3", "if", 0), e("line", "hw/a.py:3", "if", 2, build="b2"),
              e("branch", "hw/a.py:5", "else", 0),
              e("toggle", "hw/a.py:1", "q[0]", 1), e("toggle", "hw/a.py:1", "q[0]", 0, "b2"),
              e("toggle", "hw/a.py:1", "q[9]", 0, "b2"),
              e("line", "hw/b.py:9", "case", 1, design="axi", module="dptbd_axi.regs")]
    s = summarise(points)
    assert s.counts == {("segmenter", "dptbd_seg.segmenter", "line"): [1, 1, 0],
                        ("segmenter", "dptbd_seg.segmenter", "branch"): [0, 1, 0],
                        ("segmenter", "dptbd_seg.segmenter", "toggle"): [1, 2, 0],
                        ("axi", "dptbd_axi.regs", "line"): [1, 1, 0]}
    assert [n for n, _ in s.uncovered] == [
        ("segmenter", "dptbd_seg.segmenter", "branch", "hw/a.py:5", "else"),
        ("segmenter", "dptbd_seg.segmenter", "toggle", "", "q[9]")]
    assert s.percent("segmenter", "toggle") == 50.0 and s.percent("dp", "line") is None
    table = format_table(s).splitlines()
    assert table[0] == ("design                   line (covered/total) branch (covered/total)"
                        " toggle (covered/total)")
    assert table[1] == ("dptbd_axi              100.00 %      1/1      ok        -      0/0"
                        "             -      0/0")                # no point: no verdict
    assert table[2] == ("dptbd_seg              100.00 %      1/1      ok   0.00 %      0/1"
                        "      <goal  50.00 %      1/2      <goal")
    assert table[3].startswith("goals (dptbd_axi, dptbd_seg): line 100 %, branch 100 %, "
                               "toggle 95 %, outside the exclusions; 2 uncovered")
    text = _markdown(s)
    assert ("- `hw/a.py:5` branch `else` in `dptbd_seg.segmenter` (Verilog line 7 of "
            "`verilog/b1/`)") in text
    assert "- `hw/a.py:1` `dptbd_seg.segmenter` `q[9]` (Verilog line 7 of `verilog/b2/`)" in text
    assert "| `dptbd_seg.segmenter` | 100.00 % (1/1) | 0.00 % (0/1) | 50.00 % (1/2) | 0 |" in text


def _dat(count: int) -> str:
    key = "".join(f"\x01{k}\x02{v}" for k, v in
                  dict(f="top.v", l=12, n=5, page="v_branch/top", o="if", h="TOP.top").items())
    return f"# SystemC::Coverage-3\nC '{key}' {count}\n"


@pytest.mark.skipif(shutil.which("verilator_coverage") is None,
                    reason="needs verilator_coverage")
def test_runs_merge_as_they_finish_and_their_files_go(tmp_path):
    target = tmp_path / "merged" / "b1.dat"
    target.parent.mkdir()
    merger = RunMerger(target)
    for i, count in enumerate((3, 4)):
        run = tmp_path / f"r{i}.dat"
        run.write_text(_dat(count))
        merger.add(run)
        assert not run.exists()                           # merged, then deleted
    assert [p.count for p in read_dat(target)] == [7]     # 3 + 4
    assert sorted(p.name for p in target.parent.iterdir()) == ["b1.dat"]  # no .part left
    kept = tmp_path / "kept.dat"
    kept.write_text(_dat(1))
    RunMerger(target, keep=True).add(kept)
    assert kept.exists() and [p.count for p in read_dat(target)] == [8]
    with pytest.raises(RuntimeError, match=whole(
            f"coverage run wrote no coverage file {tmp_path / 'none.dat'}")):
        merger.add(tmp_path / "none.dat")


def test_the_toggle_figure_on_the_builds_of_reachable_width():
    """b16: B_E = 16 with K = 2 (E reaches 9 bits: headroom); b9: B_E = 9 (saturates: every
    bit reachable). The figure counts b9's points only: a bit that exists in b16 only (the
    headroom energy[12]) is not counted, and one b16 toggled but b9 did not (energy[8]) is
    uncovered."""
    import warnings

    from dptbd.config import DPConfig, EnergyWidthWarning
    from dptbd.sim.coverage.report import Summary, reachable_toggle, reachable_width

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EnergyWidthWarning)
        configs = {"b16": DPConfig(segment_frames=2),
                   "b9": DPConfig(segment_frames=6, energy_bits=9)}
    assert not reachable_width(configs["b16"]) and reachable_width(configs["b9"])
    points = [e("toggle", "hw/a.py:1", "energy[3]", 1, "b16"),
              e("toggle", "hw/a.py:1", "energy[3]", 1, "b9"),
              e("toggle", "hw/a.py:1", "energy[8]", 1, "b16"),
              e("toggle", "hw/a.py:1", "energy[8]", 0, "b9"),
              e("toggle", "hw/a.py:1", "energy[12]", 0, "b16"),
              e("line", "hw/a.py:3", "if", 0, "b9"),
              e("toggle", "hw/a.py:1", "q[0]", 0, "b1", design="axi", module="dptbd_axi.regs")]
    reach = reachable_toggle(points, (), set(), {**configs, "b1": configs["b16"]})
    assert reach == {"segmenter": [1, 2, 1, 2], "axi": [0, 0, 0, 1]}
    s = Summary({}, [], [], reachable=reach)
    assert format_table(s).splitlines()[1:3] == [
        "dptbd_axi: toggle on the builds of reachable width (0 of 1): - 0/0",
        "dptbd_seg: toggle on the builds of reachable width (1 of 2): 50.00 % 1/2 <goal"]
