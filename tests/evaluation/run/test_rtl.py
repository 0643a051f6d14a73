"""dptbd.evaluation.run.rtl: the lines that say what the RTL check covered, and its refusals."""

import re

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.evaluation.run.rtl import (RtlCheck, RtlError, block_ram_bits, needs_axi_store,
                                      resolve_state_store, rtl_line, rtl_summary, run_rtl)


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
    assert RtlCheck() == RtlCheck("verilator", 0, None, "auto")


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


def test_block_ram_bits_is_the_largest_device_of_the_families():
    from dptbd.hw.flow.family import ECP5

    count, bits = ECP5.block_rams["85k"]
    assert block_ram_bits() == (count * bits, "ecp5 85k") == (3833856, "ecp5 85k")


@pytest.mark.parametrize("size, store", [((128, 128), "chip"), ((256, 256), "chip"),
                                         ((512, 512), "axi"), ((640, 512), "axi"),
                                         ((4096, 256), "axi")])
def test_auto_takes_the_axi_store_when_the_state_exceeds_the_block_ram(size, store):
    width, height = size
    cfg = DPConfig(width=width, height=height)
    # 20-bit states: 256 x 256 is 1.3 Mbit, 512 x 512 5.2 Mbit, the ECP5-85F 3.8 Mbit
    assert cfg.state_bits == 20
    assert needs_axi_store(cfg) is (store == "axi")
    assert resolve_state_store(cfg, "auto") == store
    assert resolve_state_store(cfg, "chip") == "chip"
    assert resolve_state_store(cfg, "axi") == "axi"
    assert resolve_state_store(cfg, "chip", "icarus") == "chip"


def test_resolve_state_store_refusals():
    big, small = DPConfig(width=640, height=512), DPConfig(width=32, height=32)
    msg = ("the state of a 640x512 frame (6553600 bits) exceeds the block RAM of the largest "
           "device (ecp5 85k: 3833856 bits), so --rtl keeps it in external memory (AXI4), "
           "which only the Verilator harness models; use --rtl-simulator verilator, or "
           "--rtl-state-store chip")
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        resolve_state_store(big, "auto", "icarus")
    msg = ("--rtl-state-store axi: only the Verilator harness models the AXI4 memory; use "
           "--rtl-simulator verilator")
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        resolve_state_store(small, "axi", "icarus")
    msg = "--rtl-state-store must be one of auto, chip, axi, got 'dram'"
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        resolve_state_store(small, "dram")


def test_run_rtl_refuses_the_axi_store_on_icarus_before_any_work(monkeypatch):
    from dptbd.sim import sim_job

    monkeypatch.setattr(sim_job, "simulator_tools_missing", lambda sim, option: None)
    frames = np.zeros((12, 8, 8), np.uint8)
    cfg = DPConfig(width=8, height=8, segment_frames=6, input_bits=8)
    msg = ("--rtl-state-store axi: only the Verilator harness models the AXI4 memory; use "
           "--rtl-simulator verilator")
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        run_rtl(frames, cfg, 0, None, simulator="icarus", state_store="axi")


def test_rtl_line_names_the_store_and_the_rate():
    rtl = {"report": "bit-exact", "module": "dptbd_axi", "simulator": "verilator",
           "design": "axi", "frames": 8, "words_compared": 70, "cycles": 2621500,
           "cycles_per_second": 0, "seconds": 9.0, "state_store": "axi",
           "cycles_per_pixel": 1.0, "memory_latency": 0}
    assert rtl_line(rtl, 8) == (
        "  RTL: bit-exact — the generated Verilog (dptbd_axi --state-store axi on Verilator) "
        "matches the golden model on all 8 frames: 70 candidate-list words compared, "
        "2621500 cycles (9.0 s in all); 1.000 cycles per pixel with the AXI4 store at "
        "latency 0")
