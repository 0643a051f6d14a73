"""The known-bad harnesses: deliberately broken components under the checks of a good one;
their proofs must FAIL, which shows the checks detect the violation they are written for."""

from __future__ import annotations

from amaranth.hdl import Module, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.axi_lite import axi_lite_signature
from dptbd.hw.axis_video import candidate_out_signature
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.sim.formal.harness import Harness
from dptbd.hw.axi_store.write_behind import AxiWriteBehind
from dptbd.sim.formal.harnesses.streams import CandidatesHarness
from dptbd.sim.formal.harnesses.write_behind import STAGED_INVARIANTS, WriteBehindHarness
from dptbd.sim.formal.properties import axil_subordinate

__all__ = ["DroppingCandidatesToAxis", "DroppingCandidatesHarness", "EagerAXILite",
           "EagerAXILiteHarness", "DoubleQueuedWriteBehind", "DoubleQueuedWriteBehindHarness"]


class DroppingCandidatesToAxis(wiring.Component):
    """A deliberately broken ``m_axis_cand`` adapter (known-bad harness): the soft reset
    resets the core at once, dropping a word that is offered and not taken — the violation
    the outside testbench found before :class:`~dptbd.hw.axis_video.CandidatesToAxis`
    served the soft reset. It does not cut a list (a request while a list is open, or in a
    cycle a word is taken, is ignored), so only the dropped word breaks a rule."""

    def __init__(self, cfg: DPConfig):
        super().__init__({
            "candidates": In(stream.Signature(candidate_layout(cfg))),
            "cand": Out(candidate_out_signature(cfg)),
            "soft_reset": In(1), "hold": In(1), "restart": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        src, out = self.candidates, self.cand
        list_start = Signal(init=1)
        m.d.comb += [
            out.tdata.eq(src.payload.as_value()), out.tvalid.eq(src.valid),
            out.tlast.eq(src.payload.end_of_list), out.tuser[0].eq(list_start),
            src.ready.eq(out.tready),
            self.restart.eq(self.soft_reset & list_start & ~(src.valid & out.tready)),
        ]
        with m.If(self.restart):
            m.d.sync += list_start.eq(1)
        with m.Elif(out.tvalid & out.tready):
            m.d.sync += list_start.eq(out.tlast)
        return m


class DroppingCandidatesHarness(CandidatesHarness):
    """:class:`CandidatesHarness` on :class:`DroppingCandidatesToAxis`: must FAIL."""

    adapter = DroppingCandidatesToAxis

    def invariants(self, m, dut, opened):
        pass


class EagerAXILite(wiring.Component):
    """A deliberately broken AXI4-Lite subordinate (known-bad harness): it answers a write
    as soon as its address is accepted, without waiting for the data (W)."""

    def __init__(self):
        super().__init__({"axil": In(axi_lite_signature(4))})

    def elaborate(self, platform):
        m = Module()
        aw, w, b = self.axil.aw, self.axil.w, self.axil.b
        m.d.comb += [aw.awready.eq(~b.bvalid), w.wready.eq(1)]
        with m.If(aw.awvalid & aw.awready):
            m.d.sync += b.bvalid.eq(1)
        with m.Elif(b.bready):
            m.d.sync += b.bvalid.eq(0)
        return m


class EagerAXILiteHarness(Harness):
    """The AXI4-Lite subordinate checks on :class:`EagerAXILite`: must FAIL."""

    def check(self, m, past):
        m.submodules.dut = dut = EagerAXILite()
        self.free_inputs(m, dut, "dut")
        axil_subordinate(m, past, dut.axil)


class DoubleQueuedWriteBehind(AxiWriteBehind):
    """A deliberately broken staged write-behind (known-bad harness): a burst issued while
    no W burst is under way and the lengths FIFO is empty is loaded into the W registers
    at once and, wrongly, also queued in the lengths FIFO, so its W beats are sent twice."""

    def _w_in_registers(self, m, lengths, queued, head, issue, w_fifo):
        super()._w_in_registers(m, lengths, queued, head, issue, w_fifo)
        m.d.comb += lengths.w_en.eq(issue)      # the last assignment wins: no skip


class DoubleQueuedWriteBehindHarness(WriteBehindHarness):
    """The staged write-behind's AW / W / B checks on :class:`DoubleQueuedWriteBehind`,
    without the invariants (the violation is reached from reset): must FAIL."""

    design = DoubleQueuedWriteBehind

    def __init__(self):
        super().__init__(staged=True, drop=STAGED_INVARIANTS)
