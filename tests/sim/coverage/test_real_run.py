"""One small real coverage run: the 8 x 6 segmenter's coverage build, a clean run checked
bit-exact against the golden model and a run with one LUT write, merged and reported; exact
facts about the weight LUT's write port (``hw/weight_lut.py``): without a write its
``m.If(write_en)`` is never taken; one write to address 5 takes it and one ``m.Case``, and
the ``m.Default`` (an address beyond the table) stays uncovered."""

from __future__ import annotations

import dataclasses
import inspect
import json
import shutil

import pytest

from dptbd.config import DPConfig
from dptbd.sim import verilator as V
from dptbd.sim.coverage.code import read_dat
from dptbd.sim.coverage.report import entries, summarise, write_report
from dptbd.sim.rtl.check import Stimulus, check_stream
from dptbd.sim.scenarios import make_frames
from dptbd.sim.stimulus import pixel_words

try:
    V.check_tools()
    HAVE_TOOLS = shutil.which("verilator_coverage") is not None
except V.ToolMissingError:
    HAVE_TOOLS = False

pytestmark = pytest.mark.skipif(not HAVE_TOOLS,
                                reason="needs Verilator, verilator_coverage and a C++ compiler")

CFG = DPConfig(width=8, height=6, segment_frames=2, candidate_count=2, histogram_bits=4)


def _lines():
    """The lines of WeightLUT's write decode: m.If(write_en), m.Case, m.Default's body."""
    from dptbd.hw import weight_lut

    lines, start = inspect.getsourcelines(weight_lut)
    text = [line.strip() for line in lines]
    if_line = text.index("with m.If(self.write_en):") + 1
    case_line = text.index("with m.Case(address):", if_line) + 1
    default_body = text.index("with m.Default():  # address beyond the table: ignored",
                              case_line) + 2
    return if_line, case_line, default_body


def test_a_real_coverage_run_names_the_weight_lut_write_port(tmp_path):
    sim = V.build(CFG, "segmenter", coverage=True)
    assert sim.coverage and sim.directory.name.split("-")[-2] == "cov"
    words = pixel_words(CFG, make_frames("mixed", CFG, 8, seed=1))
    clean = tmp_path / "runs" / "clean.dat"
    clean.parent.mkdir()
    result = check_stream(sim, words, Stimulus(valid_gap=0.2, ready_pause=0.2), coverage=clean)
    assert result.passed, result.report               # the coverage build is bit-exact
    assert result.report == "bit-exact: 4 lists, 4 records, 8 words"
    if_line, case_line, default_body = _lines()
    module = "dptbd_seg.dp.core.weight_lut"

    def state(found):
        names = {}
        for e in found:
            if e.module == module and e.src in (f"hw/weight_lut.py:{if_line}",
                                                f"hw/weight_lut.py:{case_line}",
                                                f"hw/weight_lut.py:{default_body}"):
                key = (e.kind, int(e.src.rpartition(":")[2]), e.what)
                names[key] = names.get(key, False) or e.count > 0
        return names

    text = (sim.directory / "dptbd_seg.v").read_text()
    first = state(entries("segmenter", sim.directory.name, text, read_dat(clean)))
    assert first[("branch", if_line, "if")] is False
    assert first[("branch", if_line, "else")] is True
    assert first[("line", case_line, "case")] is False
    assert first[("line", default_body, "case")] is False

    one = tmp_path / "runs" / "one-write.dat"
    raw = V.run(sim, words[:96], lut_writes=[(0, 5, 3)], coverage=one)
    assert raw.status == "done" and raw.counters["lut_writes"] == 1
    second = state(entries("segmenter", sim.directory.name, text, read_dat(one)))
    assert second[("branch", if_line, "if")] is True
    assert second[("line", case_line, "case")] is True
    assert second[("line", default_body, "case")] is False

    # merged and reported: the Default's body is listed with its Amaranth line
    out = tmp_path / "report"
    builds = {sim.directory.name: ("segmenter", sim, [clean, one])}
    summary = write_report(out, builds)
    default = ("segmenter", module, "line", f"hw/weight_lut.py:{default_body}", "case")
    assert default in [name for name, _ in summary.uncovered]
    report = (out / "report.md").read_text()
    assert f"- `hw/weight_lut.py:{default_body}` line `case` in `{module}`" in report
    data = json.loads((out / "coverage.json").read_text())
    assert {"design": "segmenter", "module": module, "kind": "line",
            "covered": summary.figure("segmenter", "line", module)[0],
            "total": summary.figure("segmenter", "line", module)[1],
            "excluded": 0} in data["modules"]
    assert (out / "merged" / f"{sim.directory.name}.dat").is_file()
    assert (out / "verilog" / sim.directory.name / "dptbd_seg.v").is_file()
    annotated = (out / "annotated" / "amaranth" / "segmenter" / "hw" / "weight_lut.py")
    rows = annotated.read_text().splitlines()
    assert rows[default_body - 1].startswith("!!  0/")      # never reached
    assert list((out / "annotated" / "verilog" / sim.directory.name).iterdir())
    # the report's own figures beside summarise's: CFG's B_E = 16 with K = 2 has headroom
    # (E reaches 9 bits), so no build of reachable width; no proof asked
    assert (summary.reachable, summary.proofs) == ({"segmenter": [0, 0, 0, 1]}, {})
    assert dataclasses.replace(summary, reachable={}) == summarise(
        entries("segmenter", sim.directory.name, text,
                read_dat(out / "merged" / f"{sim.directory.name}.dat")))


def test_run_coverage_runs_campaign_cases_on_the_execution_layer_and_merges_as_it_goes(tmp_path):
    from dptbd.sim.campaign import Case
    from dptbd.sim.coverage.report import run_coverage

    case = Case("tiny-cov", dict(width=8, height=6, segment_frames=2, candidate_count=2,
                                 histogram_bits=4), "segmenter", 6, 2, ())
    seen = []
    outcomes, builds = run_coverage(tmp_path, [case], workers=1, on_outcome=seen.append)
    sim = V.build(case.cfg, "segmenter", coverage=True)
    merged = tmp_path / "merged" / f"{sim.directory.name}.dat"
    assert [(o.case, o.seed, o.passed) for o in outcomes] == [("tiny-cov", 0, True),
                                                            ("tiny-cov", 1, True)]
    assert seen == outcomes
    assert [(n, d, b.directory, f) for n, (d, b, f) in builds.items()] == [
        (sim.directory.name, "segmenter", sim.directory, [merged])]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["merged"]   # run files merged, gone
    assert sorted(p.name for p in merged.parent.iterdir()) == [merged.name]
    summary = write_report(tmp_path, builds)       # the merged file is reported as it is
    assert summary.figure("segmenter", "line")[0] > 0
