"""The harness of the AXI4 state store's manager port (:class:`AxiStoreHarness`):
``dptbd_dp --state-store axi`` (:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi`) on a
small build, any subordinate that keeps the AXI4 rules, any pixel stream and consumer."""

from __future__ import annotations

from amaranth.hdl import Assert, Assume, Cover, Mux, Signal

from dptbd.config import AxiStoreConfig, DPConfig
from dptbd.hw.axi_store.bus import BURST_INCR, size_code
from dptbd.hw.axi_store.pipeline import DPPipelineAxi
from dptbd.sim.formal.harness import Harness
from dptbd.sim.formal.harnesses.tiny import tiny_config
from dptbd.sim.formal.properties import axis_manager, axis_subordinate

__all__ = ["tiny_store", "AxiStoreHarness"]


def tiny_store(cfg: DPConfig | None = None) -> AxiStoreConfig:
    """The small store build of the proofs: the tiny 5 x 4 frames with B_E = 10 (16-bit
    slots: 2 per beat), a 32-bit bus, 2-beat bursts (8 bytes), 13 address bits (the region
    can straddle the 4 KB boundary at 4096), 2 bursts in flight per direction."""
    cfg = cfg or tiny_config(energy_bits=10)
    return cfg.axi_store(data_bits=32, burst_beats=2, address_bits=13, outstanding=2)


def _queue(m, name: str, depth: int, width: int, push, value, pop):
    """A shadow FIFO of the harness: (count, head); ``pop`` takes the head, ``push`` puts
    ``value`` behind the rest (both in one cycle allowed); reset with the design."""
    entries = [Signal(width, name=f"{name}_q{i}") for i in range(depth)]
    count = Signal(range(depth + 2), name=f"{name}_count")
    slot = Signal(range(depth + 2), name=f"{name}_slot")
    m.d.comb += slot.eq(count - pop)
    for i, entry in enumerate(entries):
        shifted = Mux(pop, entries[i + 1] if i + 1 < depth else 0, entry)
        m.d.sync += entry.eq(Mux(push & (slot == i), value, shifted))
    m.d.sync += count.eq(count + push - pop)
    return count, entries[0]


class AxiStoreHarness(Harness):
    """:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi` of :func:`tiny_store`; every input
    free (pixels, consumer ``ready``, ``state_base`` and K at any time), no LUT write.

    Assumed (the subordinate keeps AXI4): R and B held until taken with a stable payload;
    a read beat only for an accepted AR burst, ``RLAST`` on exactly its last beat; a write
    response only for a burst whose AW and last W beat were accepted; ID 0; the pixel
    stream's rules. Any ``RRESP`` / ``BRESP`` (errors included), any latency and stalls.
    ``RDATA`` is 0 unless ``free_data``: no handshake, address or length depends on the
    state words read (they only reach ``states`` and ``WDATA``), and a free ``RDATA``
    makes the solver carry the DP datapath's values (several times slower per step).

    Asserted: AR, AW and W valid held until ready with address, length, size, burst
    (and ID, cache) or data, strobe and last stable while held; INCR bursts of full beats,
    ``WSTRB`` all ones; no burst crosses a 4 KB boundary; ``ARLEN`` / ``AWLEN`` below
    ``burst_beats``; every W beat belongs to a burst whose AW was offered (W may run ahead
    of the AW handshake, as AXI4 allows, never of the AW itself) and ``WLAST`` is on exactly
    beat ``AWLEN`` + 1; every read beat (all requested, by the assumptions) taken in the
    cycle it is offered (``docs/gateware.md``: ``RREADY`` drops only for unrequested beats;
    it may be low while no beat is offered and the beat FIFO is full), ``BREADY`` always
    high; at most ``outstanding`` bursts in flight per
    direction; no valid on AR, AW, W or ``states`` in the first cycle after a reset, and
    none on AW, W or ``states`` before a pixel was accepted since the reset; the ``states``
    stream's rules, never more words out than pixels accepted.
    """

    def __init__(self, store: AxiStoreConfig | None = None, *, free_data: bool = False):
        super().__init__()
        self.store = store or tiny_store()
        self.free_data = free_data

    def check(self, m, past):
        store = self.store
        m.submodules.dut = dut = DPPipelineAxi(store)
        self.free_inputs(m, dut, "dut", skip=("lut_addr", "lut_data", "lut_we"))

        def p(name):
            return getattr(dut, f"m_axi_state_{name}")

        src, out = dut.pixels, dut.states
        axis_subordinate(m, past, tvalid=src.valid, tready=src.ready,
                         payload=[src.payload.as_value()], name="pixels")
        axis_manager(m, past, tvalid=out.valid, tready=out.ready,
                     payload=[out.payload.as_value()], name="states")
        # ---- the manager's rules on AR, AW, W -------------------------------------------
        for ch in ("ar", "aw"):
            axis_manager(m, past, tvalid=p(f"{ch}valid"), tready=p(f"{ch}ready"),
                         payload=[p(f"{ch}{n}") for n in ("addr", "len", "size", "burst",
                                                           "id", "cache")], name=ch.upper())
        axis_manager(m, past, tvalid=p("wvalid"), tready=p("wready"),
                     payload=[p("wdata"), p("wstrb"), p("wlast")], name="W")
        # ---- the subordinate's rules on R, B (assumed) -------------------------------------
        axis_subordinate(m, past, tvalid=p("rvalid"), tready=p("rready"),
                         payload=[p("rdata"), p("rresp"), p("rlast"), p("rid")], name="R")
        axis_subordinate(m, past, tvalid=p("bvalid"), tready=p("bready"),
                         payload=[p("bresp"), p("bid")], name="B")
        m.d.comb += [Assume(p("rid") == 0), Assume(p("bid") == 0)]
        if not self.free_data:
            m.d.comb += Assume(p("rdata") == 0)

        ar_hs = p("arvalid") & p("arready")
        aw_hs = p("awvalid") & p("awready")
        w_hs = p("wvalid") & p("wready")
        r_hs = p("rvalid") & p("rready")
        b_hs = p("bvalid") & p("bready")
        depth = store.outstanding + 1
        page = 4096
        for ch in ("ar", "aw"):
            name = ch.upper()
            with m.If(p(f"{ch}valid")):
                m.d.comb += [
                    Assert(p(f"{ch}addr")[:12] + (p(f"{ch}len") + 1) * store.beat_bytes
                           <= page, f"{name}: burst crosses a 4 KB boundary"),
                    Assert(p(f"{ch}len") < store.burst_beats,
                           f"{name}: {name}LEN above burst_beats - 1"),
                    Assert((p(f"{ch}size") == size_code(store.beat_bytes))
                           & (p(f"{ch}burst") == BURST_INCR),
                           f"{name}: not an INCR burst of full beats"),
                    Assert(p(f"{ch}addr")[:(store.beat_bytes - 1).bit_length()] == 0,
                           f"{name}: address not aligned to the beat"),
                ]
        with m.If(p("wvalid")):
            m.d.comb += Assert(p("wstrb") == (1 << store.beat_bytes) - 1,
                               "W: strobe not all ones")

        # ---- reads: the accepted bursts' lengths, RLAST assumed on the last beat ----------
        r_last = r_hs & p("rlast")
        reads, read_len = _queue(m, "reads", depth, 8, ar_hs, p("arlen"), r_last)
        r_beat = Signal(8)
        with m.If(r_hs):
            m.d.sync += r_beat.eq(Mux(p("rlast"), 0, r_beat + 1))
        with m.If(p("rvalid")):
            m.d.comb += [Assume(reads != 0), Assume(p("rlast") == (r_beat == read_len))]
        m.d.comb += Assert(reads <= store.outstanding,
                           f"AR: more than {store.outstanding} reads in flight")

        # ---- writes: AW accepted without their W, W bursts done before their AW -----------
        w_last = w_hs & p("wlast")
        pushed, popped = Signal(), Signal()
        aw_open, open_len = _queue(m, "aw_open", depth, 8, pushed, p("awlen"), popped)
        early = Signal(range(4))                  # W bursts done, their AW not accepted yet
        pending_done = w_last & (aw_open == 0)    # the offered AW's burst done by W first
        m.d.comb += [pushed.eq(aw_hs & (early == 0) & ~pending_done),
                     popped.eq(w_last & (aw_open != 0))]
        m.d.sync += early.eq(early + (pending_done & ~aw_hs) - (aw_hs & (early != 0)))
        w_beat = Signal(8)
        with m.If(w_hs):
            m.d.sync += w_beat.eq(Mux(p("wlast"), 0, w_beat + 1))
        with m.If(p("wvalid") & (aw_open == 0)):
            m.d.comb += Assert(p("awvalid") & (early == 0),
                               "W: a beat of a burst whose AW was not offered")
        burst_len = Mux(aw_open != 0, open_len, p("awlen"))
        with m.If(p("wvalid")):
            m.d.comb += Assert(p("wlast") == (w_beat == burst_len),
                               "W: WLAST not on beat AWLEN + 1")
        complete = Signal(range(2 * depth + 2))  # AW and last W accepted, no B yet
        done_now = (w_last & (aw_open != 0)) | (aw_hs & ((early != 0) | pending_done))
        m.d.sync += complete.eq(complete + done_now - b_hs)
        with m.If(p("bvalid")):
            m.d.comb += Assume(complete != 0)
        writes = Signal(range(2 * depth + 2))    # AW accepted, no B yet
        m.d.sync += writes.eq(writes + aw_hs - b_hs)
        m.d.comb += Assert(writes <= store.outstanding,
                           f"AW: more than {store.outstanding} writes in flight")

        # ---- ready, reset, work -------------------------------------------------------------
        with m.If(p("rvalid")):
            m.d.comb += Assert(p("rready"), "R: a requested beat not taken at once")
        m.d.comb += Assert(p("bready"), "B: BREADY low")
        with m.If(past.rst):
            m.d.comb += Assert(~p("arvalid") & ~p("awvalid") & ~p("wvalid") & ~out.valid,
                               "a valid in the first cycle after reset")
        accepted = src.valid & src.ready
        started = Signal()
        with m.If(accepted):
            m.d.sync += started.eq(1)
        with m.If(~started):
            m.d.comb += Assert(~p("awvalid") & ~p("wvalid") & ~out.valid,
                               "AW, W or states valid before any pixel was accepted")
        taken = out.valid & out.ready
        in_flight = Signal(range(-4, 64))
        m.d.sync += in_flight.eq(in_flight + accepted - taken)
        m.d.comb += Assert(in_flight >= 0, "states: more words out than pixels accepted")

        # ---- covers: every property reached --------------------------------------------
        end = lambda ch: p(f"{ch}addr")[:12] + (p(f"{ch}len") + 1) * store.beat_bytes  # noqa: E731
        m.d.comb += [
            Cover(ar_hs & (p("arlen") == store.burst_beats - 1) & (end("ar") == page)),
            Cover(aw_hs & (p("awlen") == store.burst_beats - 1) & (end("aw") == page)),
            Cover(p("arvalid") & ~p("arready") & started),
            Cover(p("awvalid") & ~p("awready") & (aw_open != 0)),
            Cover(w_hs & p("wlast") & (aw_open == 0)),          # W ahead of its AW handshake
            Cover(p("wvalid") & ~p("wready") & ~p("wlast")),
            Cover(reads == store.outstanding),
            Cover(writes == store.outstanding),
            Cover(dut.read_error),
            Cover(dut.write_error),
            Cover(taken & (in_flight == 1)),
        ]
