"""The cocotbext-axi side of the ``dptbd_axi`` benches (:mod:`dptbd.sim.benches.axi`,
:mod:`dptbd.sim.benches.axi_store`): :class:`AxiBench` (clock, reset, the video source, the
candidate sink and the AXI4-Lite manager of one run, register reads and checked writes, the
watchers of stalls, accepted beats and ``irq``) and :func:`line_frames` (beats as
AXI-Stream frames, one per line).

Never imported outside a simulator.
"""

from __future__ import annotations

import cocotb
from cocotb.clock import Clock
from cocotb.simtime import get_sim_time
from cocotb.triggers import RisingEdge
from cocotbext.axi import (AxiLiteBus, AxiLiteMaster, AxiStreamBus, AxiStreamFrame,
                           AxiStreamSink, AxiStreamSource)

from dptbd.hw.register_map import constants_namespace
from dptbd.sim.axi.stimulus import Beats
from dptbd.sim.benches.dp import PERIOD_NS
from dptbd.sim.benches.drivers import Cycles, pause_generator

__all__ = ["AxiBench", "line_frames", "high", "OKAY", "SLVERR"]

#: AXI response codes the benches expect.
OKAY, SLVERR = 0, 2


def high(handle) -> bool:
    value = handle.value
    return value.is_resolvable and bool(int(value))


def line_frames(beats: Beats, start: int, stop: int) -> list[AxiStreamFrame]:
    """Beats ``[start, stop)`` as AXI-Stream frames, each ending at a beat with ``last``."""
    frames, lo = [], start
    for i in range(start, stop):
        if beats.last[i] or i == stop - 1:
            frames.append(AxiStreamFrame(tdata=[int(p) for p in beats.pixel[lo:i + 1]],
                                         tuser=[int(f) for f in beats.first[lo:i + 1]]))
            lo = i + 1
    return frames


class AxiBench:
    """Clock, reset, the three cocotbext-axi drivers and the watchers of one run."""

    def __init__(self, dut, job: dict, cfg):
        self.dut, self.job, self.cfg = dut, job, cfg
        self.regs = constants_namespace(cfg)
        self.period = int(job.get("period_ns", PERIOD_NS))
        self.log = cocotb.log
        self.problems: list[str] = []
        self.irq_edges: list[tuple[int, int]] = []
        self.accept_cycles: list[int] = []
        self.stalls = {"input": 0, "output": 0}      # seen on the buses, after reset
        self.cycles = Cycles(1)
        clk, rst = dut.aclk, dut.aresetn
        self.source = AxiStreamSource(AxiStreamBus.from_prefix(dut, "s_axis_video"), clk, rst,
                                      reset_active_level=False, byte_lanes=1)
        self.sink = AxiStreamSink(AxiStreamBus.from_prefix(dut, "m_axis_cand"), clk, rst,
                                  reset_active_level=False, byte_lanes=1)
        self.axil = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axil"), clk, rst,
                                  reset_active_level=False)
        self.state_sink = None
        if job.get("state_output"):
            self.state_sink = AxiStreamSink(AxiStreamBus.from_prefix(dut, "m_axis_state"), clk,
                                            rst, reset_active_level=False, byte_lanes=1)
            self.state_sink.set_pause_generator(pause_generator(job.get("state_pause")))
        self.source.set_pause_generator(pause_generator(job.get("valid_pause")))
        self.sink.set_pause_generator(pause_generator(job.get("ready_pause")))

    async def start(self) -> None:
        Clock(self.dut.aclk, self.period, unit="ns").start(start_high=False)
        self.dut.aresetn.value = 0
        await RisingEdge(self.dut.aclk)
        t0 = get_sim_time("step")
        await RisingEdge(self.dut.aclk)
        self.cycles.period_steps = int(get_sim_time("step") - t0)
        for _ in range(3):
            await RisingEdge(self.dut.aclk)
        self.dut.aresetn.value = 1
        cocotb.start_soon(self._watch())

    async def _watch(self) -> None:
        dut, edge, irq = self.dut, RisingEdge(self.dut.aclk), 0
        while True:
            await edge
            now = self.cycles.now()
            if high(dut.s_axis_video_tvalid):
                if high(dut.s_axis_video_tready):
                    self.accept_cycles.append(now)
                else:
                    self.stalls["input"] += 1
            if (high(dut.m_axis_cand_tvalid) and not high(dut.m_axis_cand_tready)) or (
                    self.state_sink is not None and high(dut.m_axis_state_tvalid)
                    and not high(dut.m_axis_state_tready)):
                self.stalls["output"] += 1
            level = int(dut.irq.value) if dut.irq.value.is_resolvable else 0
            if level != irq:
                self.irq_edges.append((now, level))
                irq = level

    async def read(self, name: str) -> int:
        resp = await self.axil.read(getattr(self.regs, f"REG_{name}"), 4)
        if int(resp.resp) != OKAY:
            self.problems.append(f"read {name}: response {int(resp.resp)}")
        return int.from_bytes(resp.data, "little")

    async def write(self, address: int, value: int, want: int, what: str) -> None:
        resp = await self.axil.write(address, int(value).to_bytes(4, "little"))
        if int(resp.resp) != want:
            self.problems.append(f"write {what} = {value}: response {int(resp.resp)}, "
                                 f"expected {want}")

    async def write_register(self, name: str, value: int) -> None:
        lo = getattr(self.regs, f"{name}_{name}_MIN", None)
        hi = getattr(self.regs, f"{name}_{name}_MAX", None)
        taken = lo is None or lo <= value <= hi
        before = await self.read(name) if lo is not None else None
        await self.write(getattr(self.regs, f"REG_{name}"), value, OKAY if taken else SLVERR,
                         name)
        if lo is not None:
            after = await self.read(name)
            want = value if taken else before
            if after != want:
                self.problems.append(f"{name} reads {after} after writing {value}, "
                                     f"expected {want}")

    async def check(self, expected: dict, when: str) -> None:
        for name, want in expected.items():
            got = await self.read(name)
            if got != want:
                self.problems.append(f"{when}: {name} = {got}, expected {want}")

    async def settle(self, cycles: int) -> None:
        for _ in range(cycles):
            await RisingEdge(self.dut.aclk)
