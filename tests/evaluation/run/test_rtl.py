"""dptbd.evaluation.run.rtl: the lines that say what the RTL check covered, and its refusals."""

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.evaluation.run.rtl import RtlCheck, RtlError, rtl_line, rtl_summary, run_rtl


def test_rtl_summary_names_frames_words_and_cycles():
    assert rtl_summary(24, 24, "dptbd_seg", "verilator", 50, 24594) == (
        "RTL (dptbd_seg on Verilator) checked frames 0-23 of 24: bit-exact, 50 candidate-list "
        "words compared, 24594 cycles")
    assert rtl_summary(12, 24, "dptbd_dp", design="dp", words=7) == (
        "RTL (dptbd_dp) checked frames 0-11 of 24: bit-exact, 7 (E, d) words compared; frames "
        "12-23 come from the golden model only (--rtl-frames 0 checks all)")


def test_rtl_line_says_which_frames_and_the_speed():
    rtl = {"report": "bit-exact", "module": "dptbd_seg", "simulator": "icarus",
           "design": "segmenter", "frames": 12, "words_compared": 21, "cycles": 12306,
           "cycles_per_second": 900, "seconds": 3.25}
    assert rtl_line(rtl, 24) == (
        "  RTL: bit-exact — the generated Verilog (dptbd_seg on Icarus) matches the golden "
        "model on the first 12 of 24 frames: 21 candidate-list words compared, 12306 cycles, "
        "900 cycles/s (3.2 s in all); the model's output is used for the rest")
    rtl.update(frames=24, cycles_per_second=2_500_000, simulator="verilator")
    assert rtl_line(rtl, 24).endswith("on all 24 frames: 21 candidate-list words compared, "
                                      "12306 cycles, 2.50 M cycles/s (3.2 s in all)")


def test_rtl_check_defaults():
    assert RtlCheck() == RtlCheck("verilator", 0, None)


def test_run_rtl_refusals(monkeypatch):
    from dptbd.sim import sim_job

    frames = np.zeros((12, 8, 8), np.uint8)
    cfg = DPConfig(width=8, height=8, segment_frames=6, input_bits=8)
    monkeypatch.setattr(sim_job, "simulator_tools_missing", lambda sim, option: None)
    with pytest.raises(ValueError, match=r"^--rtl-frames must be an integer in \[0, inf\), got -1$"):
        run_rtl(frames, cfg, -1, None)
    monkeypatch.setattr(sim_job, "simulator_tools_missing", lambda sim, option: f"no {sim}")
    with pytest.raises(RtlError, match=r"^no icarus$"):
        run_rtl(frames, cfg, 0, None, simulator="icarus")
