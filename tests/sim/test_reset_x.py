"""4-state (Icarus) runs of each top level around reset (:mod:`dptbd.sim.reset_x`): a pixel
offered in every cycle, in reset and in the first cycle after it; ``ready`` 0 during reset
and in that cycle, no X on any output, no deadlock, every word after the reset bit-exact;
the AXI top level from power-up with no register written, over three segments. The ECP5
builds (the family's options, the line buffer in DP16KDs too) on the 4-state DP16KD model
(``sim/dp16kd.v``: every word X until written, every output register X until loaded).

The self-check keeps the failure reproducible: with Amaranth's own Verilog conversion
(``always @*`` blocks, :mod:`dptbd.hw.flow.to_verilog`), ``pixels.ready`` is X from the
first clock edge of a reset held from power-up.
"""

from __future__ import annotations

import shutil

import pytest
from amaranth.back import verilog

from dptbd.config import DPConfig
from dptbd.hw.flow import verilog as flow_verilog
from dptbd.hw.flow.family import ECP5
from dptbd.sim import reset_x
from dptbd.sim.cell_models import cell_instances, model_path
from dptbd.sim.reset_x import TOPS, run_reset_x_check

pytestmark = pytest.mark.skipif(shutil.which("iverilog") is None, reason="needs Icarus Verilog")

#: Reset from power-up (4 cycles, 1 cycle), and asserted in cycles 1, 2, 5 after a start
#: without reset: (first reset cycle, reset cycles).
RESETS = [(0, 4), (0, 1), (1, 1), (2, 3), (5, 2)]

#: 37 x 23 (the size of the report), K = 2: three segments in six frames; n = 12.
CFG = DPConfig(width=37, height=23, segment_frames=2, candidate_count=12)


@pytest.mark.parametrize("top", ["dp", "seg", "axi"])
def test_reset_sweep_ready_low_no_x_no_deadlock_model_exact(top):
    cfg = CFG.build_config() if top == "axi" else CFG
    results = run_reset_x_check(cfg, 6, top=top, resets=RESETS)
    assert [r.ok for r in results] == [True] * len(RESETS), \
        "\n".join(r.report for r in results)
    words = {r.words for r in results}
    assert len(words) == 1                        # the same words whatever the reset
    if top == "dp":
        assert words == {6 * cfg.width * cfg.height}
    else:   # 3 lists (the first unprimed: its trailer only), records in the later ones
        assert words.pop() > 3


def test_the_check_sees_x_with_amaranth_conversion(monkeypatch):
    """Self-check: Amaranth's ``always @*`` Verilog fails the power-up reset run."""
    monkeypatch.setattr(flow_verilog, "to_verilog",
                        lambda top, name: verilog.convert(top, name=name, emit_src=False))
    cfg = DPConfig(width=37, height=23, segment_frames=3)
    (result,) = run_reset_x_check(cfg, 3, top="dp", resets=[(0, 4)])
    assert not result.ok
    lines = result.report.splitlines()
    # ready X from the first clock edge to the first cycle after the reset (cycle 4) ...
    assert [line for line in lines if line.startswith("READY_FAULT")] == [
        "READY_FAULT cycle=1 rst=1 ready=x valid=x", "READY_FAULT cycle=2 rst=1 ready=x valid=0",
        "READY_FAULT cycle=3 rst=1 ready=x valid=0", "READY_FAULT cycle=4 rst=0 ready=x valid=0"]
    # ... so the pixel offered there poisons the store: every word of frames 1 and 2 is X
    assert "2553/2553 pixels taken, 2553 words, 1706 cycles with X/Z on an output" in lines[0]
    assert [line for line in lines if line.startswith("word ")][0] == "word 851: X/Z in 0xxxxx"


def ecp5_options(cfg: DPConfig) -> dict:
    """The ECP5 family's options (on-chip store and histogram in DP16KDs) with the line
    buffer in DP16KDs too (the family's choice from 512 wide): every DP16KD of a top."""
    return {**ECP5.options_for(cfg), "line_buffer_style": "dp16kd"}


#: 16 x 12, K = 2, n = 4 (1024 bins: the histogram one DP16KD of 18 x 1024): two segments
#: in four frames, the second list with records.
ECP5_CFG = DPConfig(width=16, height=12, segment_frames=2, candidate_count=4)


def check_ecp5(tmp_path, cfg, top, frames, options, resets, seed=1) -> list:
    """:func:`run_reset_x_check` of the ECP5 build: every run passes, the same words after
    each reset; the DP16KD instances per module of the Verilog and the words."""
    results = run_reset_x_check(cfg, frames, top=top, resets=resets, core_options=options,
                                seed=seed, directory=tmp_path)
    assert [r.ok for r in results] == [True] * len(resets), \
        "\n".join(r.report for r in results)
    words = {r.words for r in results}
    assert len(words) == 1
    text = (tmp_path / f"{TOPS[top]['module']}.v").read_text()
    return cell_instances(text, "DP16KD"), words.pop()


@pytest.mark.parametrize("top, cells", [
    ("dp", {"dptbd_dp.core.line_buffer": 3, "dptbd_dp.state_store": 2}),
    ("axi", {"dptbd_axi.core.dp.core.line_buffer": 2, "dptbd_axi.core.dp.state_store": 1,
             "dptbd_axi.core.segmenter.histogram": 1}),
])
def test_the_ecp5_builds_on_the_dp16kd_model(tmp_path, top, cells):
    """Every DP16KD use (line buffer, on-chip store, ``dptbd_axi``'s histogram) from
    power-up and after later resets: no X on any output, ``ready`` low where promised,
    every word after the reset the model's (lists with records)."""
    cfg = ECP5_CFG.build_config() if top == "axi" else ECP5_CFG
    found, words = check_ecp5(tmp_path, cfg, top, 4, ecp5_options(cfg),
                              [(0, 4), (1, 1), (5, 2)])
    assert found == cells
    assert words == (4 * cfg.width * cfg.height if top == "dp" else 1 + 8)   # list 2: 7 records


def test_the_check_sees_the_dp16kd_model_x(tmp_path, monkeypatch):
    """Self-check: with a DP16KD model whose writes never land (every word X), the ECP5
    build's outputs carry X."""
    broken = tmp_path / "broken.v"
    text = model_path("DP16KD").read_text()
    write = "      mem[word_a] <= write_word(mem[word_a], byte_en, dia[W-1:0]);"
    assert text.count(write) == 1
    broken.write_text(text.replace(write, "      ;"))
    monkeypatch.setattr(reset_x, "model_sources", lambda verilog: [broken])
    (result,) = run_reset_x_check(ECP5_CFG, 2, top="dp", resets=[(0, 4)],
                                  core_options=ecp5_options(ECP5_CFG), directory=tmp_path)
    assert not result.ok
    # frame 0 starts a segment (no store read); frame 1's first word reads the store
    assert [line for line in result.report.splitlines() if line.startswith("word ")][0] \
        == "word 192: X/Z in 0xxxxx", result.report


@pytest.mark.slow
@pytest.mark.parametrize("top, width, height", [("axi", 128, 128), ("dp", 512, 8)])
def test_the_ecp5_family_builds_at_their_sizes(tmp_path, top, width, height):
    """The family's own choice (``Family.options_for``): ``dptbd_axi`` at 128 x 128 (store
    and histogram in DP16KDs, line buffer in LUT RAM), ``dptbd_dp`` at 512 wide (line
    buffer in DP16KDs too)."""
    cfg = DPConfig(width=width, height=height, segment_frames=2)
    cfg = cfg.build_config() if top == "axi" else cfg
    options = ECP5.options_for(cfg)
    assert options["line_buffer_style"] == ("dp16kd" if width >= 512 else "lutram")
    found, words = check_ecp5(tmp_path, cfg, top, 4, options, [(0, 4), (5, 2)])
    assert sum(found.values()) > 0 and words > 2
