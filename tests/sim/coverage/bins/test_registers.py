"""The register accesses of an AXI run (:mod:`dptbd.sim.coverage.bins.registers`): the word
a strobed write makes, why an access is refused, the accesses the steps make in order."""

from __future__ import annotations

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.register_map import register_map
from dptbd.sim.coverage.bins.registers import (aligned_registers, bus_operations, bus_reason,
                                               merged_write, ranged_registers)

CFG = DPConfig(width=4, height=3, segment_frames=2, candidate_count=2)


def test_a_strobed_write_keeps_the_bytes_it_does_not_strobe():
    assert merged_write(0x12345678, 0b0001, 0xAABBCCDD) == 0xAABBCC78
    assert merged_write(0x12345678, 0b1010, 0xAABBCCDD) == 0x12BB56DD
    assert merged_write(0x12345678, 0b0000, 0xAABBCCDD) == 0xAABBCCDD
    assert merged_write(0x12345678, 0b1111, 0xAABBCCDD) == 0x12345678


def test_each_refusal_has_its_reason():
    regs = register_map(CFG)
    at = {r.name: r.address for r in regs.registers}
    lut = regs.window("LUT").base
    top = max(at.values()) + 4
    held = {r.address: r.reset for r in regs.registers if r.kind == "setting"}
    unity = 1 << CFG.weight_frac_bits
    cases = [(("r", at["ID"], 0, 0), None), (("w", at["SEGMENT_FRAMES"], 1, 0xF), None),
             (("w", at["SEGMENT_FRAMES"], 0, 0xF), "SEGMENT_FRAMES value out of range"),
             (("w", at["SEGMENT_FRAMES"], 0, 0x0), None),       # no strobe: the held K
             (("w", lut, unity, 0xF), None),
             (("w", lut, unity + 1, 0xF), "LUT value out of range"),
             (("w", lut, 0, 0x7), "LUT write without wstrb = 1111"),
             (("r", lut, 0, 0), "LUT read"),
             (("w", at["ID"], 0, 0xF), "write to a constant register"),
             (("w", at["FRAMES"], 0, 0xF), "write to a counter"),
             (("w", at["STATUS"], 0, 0xF), "write to the status register"),
             (("w", 2, 0, 0xF), "unaligned write"), (("r", 1, 0, 0), "unaligned read"),
             (("w", top, 0, 0xF), "unmapped write"), (("r", top, 0, 0), "unmapped read")]
    assert [bus_reason(regs, *op, held) for op, _ in cases] == [why for _, why in cases]
    assert ranged_registers(CFG) == [r.name for r in regs.registers if r.kind == "setting"] + \
        ["LUT"]


def test_the_store_builds_map_judges_state_base():
    """With the state store (``--state-store axi``) STATE_BASE is a setting of its map:
    a base in range that is not a multiple of the burst size is refused as not aligned, one
    above the highest as out of range; without the store its address is unmapped."""
    store = CFG.axi_store(data_bits=32, burst_beats=2, outstanding=2)
    assert store.burst_bytes == 8
    regs = register_map(CFG, store)
    base = regs["STATE_BASE"]
    hi = base.fields[0].limits[1]
    held = {r.address: r.reset for r in regs.registers if r.kind == "setting"}
    cases = [(("w", base.address, 32, 0xF), None),
             (("w", base.address, 36, 0xF), "STATE_BASE value not aligned"),
             (("w", base.address, 0x5510, 0x1), None),        # the strobed byte: 16
             (("w", base.address, 0x550C, 0x1), "STATE_BASE value not aligned"),
             (("w", base.address, hi + 8, 0xF), "STATE_BASE value out of range"),
             (("w", base.address, 2**32 - 1, 0xF), "STATE_BASE value out of range"),
             (("r", regs["STATE_BASE_ACTIVE"].address, 0, 0), None),
             (("w", regs["STATE_READ_ERRORS"].address, 0, 0xF), "write to a counter"),
             (("w", regs["BUILD_STATE_BYTES"].address, 0, 0xF),
              "write to a constant register")]
    assert [bus_reason(regs, *op, held) for op, _ in cases] == [why for _, why in cases]
    assert bus_reason(register_map(CFG), "w", base.address, 32, 0xF, {}) == "unmapped write"
    assert aligned_registers(CFG) == [] and aligned_registers(CFG, store) == ["STATE_BASE"]
    assert "STATE_BASE" in ranged_registers(CFG, store)
    assert "STATE_BASE" not in ranged_registers(CFG)


def test_the_steps_accesses_come_in_the_order_they_are_made():
    regs = register_map(CFG)
    lut = regs.window("LUT").base
    codes = np.arange((CFG.n_moves + 1) * CFG.n_moves).reshape(CFG.n_moves + 1, CFG.n_moves)
    steps = [{"stop": 4, "writes": [("SEGMENT_FRAMES", 1)], "lut_writes": [[1, 0, 5, 0x3]],
              "bus": [["r", 8], ["w", 12, 7, 0x1]]},
             {"stop": 8, "lut_codes": codes}]
    ops = bus_operations(CFG, steps)
    assert ops[:4] == [(0, ("w", regs["SEGMENT_FRAMES"].address, 1, 0xF)),
                       (0, ("w", lut + 4 * CFG.lut_address(1, 0), 5, 0x3)),
                       (0, ("r", 8, 0, 0)), (0, ("w", 12, 7, 0x1))]
    assert ops[4:] == [(1, ("w", lut + 4 * CFG.lut_address(p, m), int(codes[p, m]), 0xF))
                       for p in range(CFG.n_moves + 1) for m in range(CFG.n_moves)]
