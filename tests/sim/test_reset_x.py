"""4-state (Icarus) runs of each top level around reset (:mod:`dptbd.sim.reset_x`): a pixel
offered in every cycle, in reset and in the first cycle after it; ``ready`` 0 during reset
and in that cycle, no X on any output, no deadlock, every word after the reset bit-exact;
the AXI top level from power-up with no register written, over three segments.

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
from dptbd.sim.reset_x import run_reset_x_check

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
