"""The harness of the AXI4 state store's manager port (:class:`AxiStoreHarness`):
``dptbd_dp --state-store axi`` (:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi`) on a
small build, any subordinate that keeps the AXI4 rules, any pixel stream and consumer."""

from __future__ import annotations

import dataclasses

from amaranth.hdl import Assert, Assume, Cover, Mux, Signal

from dptbd.config import AxiStoreConfig, DPConfig
from dptbd.hw.axi_store.bus import BURST_INCR, size_code
from dptbd.hw.axi_store.pipeline import DPPipelineAxi
from dptbd.sim.formal.harness import Elaborated, Harness
from dptbd.sim.formal.harnesses.tiny import tiny_config
from dptbd.sim.formal.properties import axis_manager, axis_subordinate

__all__ = ["STORE_INVARIANTS", "tiny_store", "read_rules", "ReadCounts", "write_rules", "WriteCounts",
           "AxiStoreHarness"]


#: The invariant groups of :class:`AxiStoreHarness` (``drop``), each needed by its proof:
#: the DP core's flow control (:func:`~dptbd.sim.formal.harnesses.flow.dp_core_invariants`),
#: the prefetcher's (:func:`~dptbd.sim.formal.harnesses.prefetcher.prefetcher_invariants`),
#: the write-behind's (:func:`~dptbd.sim.formal.harnesses.write_behind.write_behind_invariants`).
STORE_INVARIANTS = ("core", "reader", "writer")


def tiny_store(cfg: DPConfig | None = None) -> AxiStoreConfig:
    """The small store build of the proofs: the tiny 5 x 4 frames with B_E = 10 (16-bit
    slots: 2 per beat), a 32-bit bus, 2-beat bursts (8 bytes), 13 address bits (the region
    can straddle the 4 KB boundary at 4096), 2 bursts in flight per direction."""
    cfg = cfg or tiny_config(energy_bits=10)
    return cfg.axi_store(data_bits=32, burst_beats=2, address_bits=13, outstanding=2)


@dataclasses.dataclass(frozen=True)
class WriteCounts:
    """The write channels' shadow state in :func:`write_rules`: ``aw_open`` bursts whose
    AW was accepted and whose W is not done (their ``AWLEN`` in ``open_lens``, head
    first), ``early`` W bursts done before their AW handshake, ``w_beat`` beats of the W
    burst under way, ``complete`` bursts with AW and last W accepted and no B yet,
    ``writes`` AW accepted and no B yet."""

    aw_open: Signal
    open_lens: list
    early: Signal
    w_beat: Signal
    complete: Signal
    writes: Signal


def _queue(m, name: str, depth: int, width: int, push, value, pop):
    """A shadow FIFO of the harness: (count, entries, head first); ``pop`` takes the head,
    ``push`` puts ``value`` behind the rest (both in one cycle allowed); reset with the
    design."""
    entries = [Signal(width, name=f"{name}_q{i}") for i in range(depth)]
    count = Signal(range(depth + 2), name=f"{name}_count")
    slot = Signal(range(depth + 2), name=f"{name}_slot")
    m.d.comb += slot.eq(count - pop)
    for i, entry in enumerate(entries):
        shifted = Mux(pop, entries[i + 1] if i + 1 < depth else 0, entry)
        m.d.sync += entry.eq(Mux(push & (slot == i), value, shifted))
    m.d.sync += count.eq(count + push - pop)
    return count, entries


def _address_rules(m, past, store: AxiStoreConfig, ch, prefix: str) -> None:
    """The manager's rules of address channel ``ch`` (``"ar"`` or ``"aw"``): valid held until
    ready with a stable payload, INCR bursts of full beats at aligned addresses, no 4 KB
    crossing, length below ``burst_beats``."""
    name = prefix.upper()

    def s(n):
        return getattr(ch, f"{prefix}{n}")

    axis_manager(m, past, tvalid=s("valid"), tready=s("ready"),
                 payload=[s(n) for n in ("addr", "len", "size", "burst", "id", "cache")],
                 name=name)
    with m.If(s("valid")):
        m.d.comb += [
            Assert(s("addr")[:12] + (s("len") + 1) * store.beat_bytes <= 4096,
                   f"{name}: burst crosses a 4 KB boundary"),
            Assert(s("len") < store.burst_beats, f"{name}: {name}LEN above burst_beats - 1"),
            Assert((s("size") == size_code(store.beat_bytes)) & (s("burst") == BURST_INCR),
                   f"{name}: not an INCR burst of full beats"),
            Assert(s("addr")[:(store.beat_bytes - 1).bit_length()] == 0,
                   f"{name}: address not aligned to the beat"),
        ]


@dataclasses.dataclass(frozen=True)
class ReadCounts:
    """The read channels' shadow state in :func:`read_rules`: ``reads`` bursts whose AR
    was accepted and whose ``RLAST`` was not (their ``ARLEN`` in ``read_lens``, head first),
    ``r_beat`` beats of the head burst received."""

    reads: Signal
    read_lens: list
    r_beat: Signal


def read_rules(m, past, store: AxiStoreConfig, ar, r) -> ReadCounts:
    """The read channels: the AR rules (``_address_rules``), at most ``outstanding``
    reads in flight; assumed of the subordinate: R held with a stable payload, a beat only
    for an accepted AR burst, ``RLAST`` on exactly its last beat, ID 0."""
    _address_rules(m, past, store, ar, "ar")
    axis_subordinate(m, past, tvalid=r.rvalid, tready=r.rready,
                     payload=[r.rdata, r.rresp, r.rlast, r.rid], name="R")
    m.d.comb += Assume(r.rid == 0)
    ar_hs = ar.arvalid & ar.arready
    r_hs = r.rvalid & r.rready
    # the accepted bursts' lengths, RLAST assumed on the last beat
    r_last = r_hs & r.rlast
    reads, read_lens = _queue(m, "reads", store.outstanding + 1, 8, ar_hs, ar.arlen, r_last)
    r_beat = Signal(8)
    with m.If(r_hs):
        m.d.sync += r_beat.eq(Mux(r.rlast, 0, r_beat + 1))
    with m.If(r.rvalid):
        m.d.comb += [Assume(reads != 0), Assume(r.rlast == (r_beat == read_lens[0]))]
    m.d.comb += Assert(reads <= store.outstanding,
                       f"AR: more than {store.outstanding} reads in flight")
    return ReadCounts(reads, read_lens, r_beat)


def write_rules(m, past, store: AxiStoreConfig, aw, w, b):
    """The write channels: the AW rules (``_address_rules``), W held with stable data,
    strobe and last, full strobes, every W beat of a burst whose AW was offered, ``WLAST``
    on beat ``AWLEN`` + 1, ``BREADY`` high, at most ``outstanding`` writes in flight;
    assumed of the subordinate: B held with a stable payload, only for a burst whose AW and
    last W beat were accepted, ID 0. Returns the harness's shadow counts
    (:class:`WriteCounts`) for cover statements and induction invariants."""
    _address_rules(m, past, store, aw, "aw")
    axis_manager(m, past, tvalid=w.wvalid, tready=w.wready,
                 payload=[w.wdata, w.wstrb, w.wlast], name="W")
    axis_subordinate(m, past, tvalid=b.bvalid, tready=b.bready, payload=[b.bresp, b.bid],
                     name="B")
    m.d.comb += Assume(b.bid == 0)
    with m.If(w.wvalid):
        m.d.comb += Assert(w.wstrb == (1 << store.beat_bytes) - 1, "W: strobe not all ones")
    m.d.comb += Assert(b.bready, "B: BREADY low")
    aw_hs = aw.awvalid & aw.awready
    w_hs = w.wvalid & w.wready
    b_hs = b.bvalid & b.bready
    depth = store.outstanding + 1
    # ---- writes: AW accepted without their W, W bursts done before their AW -----------
    w_last = w_hs & w.wlast
    pushed, popped = Signal(), Signal()
    aw_open, open_lens = _queue(m, "aw_open", depth, 8, pushed, aw.awlen, popped)
    open_len = open_lens[0]
    early = Signal(range(4))                  # W bursts done, their AW not accepted yet
    pending_done = w_last & (aw_open == 0)    # the offered AW's burst done by W first
    m.d.comb += [pushed.eq(aw_hs & (early == 0) & ~pending_done),
                 popped.eq(w_last & (aw_open != 0))]
    m.d.sync += early.eq(early + (pending_done & ~aw_hs) - (aw_hs & (early != 0)))
    w_beat = Signal(8)
    with m.If(w_hs):
        m.d.sync += w_beat.eq(Mux(w.wlast, 0, w_beat + 1))
    with m.If(w.wvalid & (aw_open == 0)):
        m.d.comb += Assert(aw.awvalid & (early == 0),
                           "W: a beat of a burst whose AW was not offered")
    burst_len = Mux(aw_open != 0, open_len, aw.awlen)
    with m.If(w.wvalid):
        m.d.comb += Assert(w.wlast == (w_beat == burst_len),
                           "W: WLAST not on beat AWLEN + 1")
    complete = Signal(range(2 * depth + 2))  # AW and last W accepted, no B yet
    done_now = (w_last & (aw_open != 0)) | (aw_hs & ((early != 0) | pending_done))
    m.d.sync += complete.eq(complete + done_now - b_hs)
    with m.If(b.bvalid):
        m.d.comb += Assume(complete != 0)
    writes = Signal(range(2 * depth + 2))    # AW accepted, no B yet
    m.d.sync += writes.eq(writes + aw_hs - b_hs)
    m.d.comb += Assert(writes <= store.outstanding,
                       f"AW: more than {store.outstanding} writes in flight")
    return WriteCounts(aw_open, open_lens, early, w_beat, complete, writes)



class AxiStoreHarness(Harness):
    """:class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi` of :func:`tiny_store`; every input
    free (pixels, consumer ``ready``, ``state_base`` and K at any time), no LUT write.

    Assumed (the subordinate keeps AXI4): R and B held until taken with a stable payload;
    a read beat only for an accepted AR burst, ``RLAST`` on exactly its last beat; a write
    response only for a burst whose AW and last W beat were accepted; ID 0; the pixel
    stream's rules. Any ``RRESP`` / ``BRESP`` (errors included), any latency and stalls.

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

    ``core_options``: the pipeline's implementation options
    (:data:`~dptbd.hw.dp_core.CORE_OPTIONS`); with ``state_store_style="dp16kd"`` (the
    ECP5 build's store: the staged write-behind, the DP16KD prefetcher, the registered
    gate) the DP16KDs are the behavioural model
    (:func:`~dptbd.sim.dp16kd_model.modelled_dp16kd`).
    """

    def __init__(self, store: AxiStoreConfig | None = None, drop: tuple = (),
                 core_options: dict | None = None):
        super().__init__()
        self.store = store or tiny_store()
        self.core_options = dict(core_options or {})
        unknown = sorted(set(drop) - set(STORE_INVARIANTS))
        if unknown:
            raise ValueError(f"unknown invariant group(s) {', '.join(unknown)}; the groups "
                             f"are {', '.join(STORE_INVARIANTS)}")
        self.drop = tuple(drop)

    def check(self, m, past):
        from dptbd.sim.dp16kd_model import modelled_dp16kd

        store = self.store
        with modelled_dp16kd():             # the ECP5 store's DP16KDs: the behavioural model
            top = Elaborated(DPPipelineAxi(store, **self.core_options))
        m.submodules.dut = top.fragment
        dut = top.component
        self.free_inputs(m, dut, "dut", skip=("lut_addr", "lut_data", "lut_we"))

        def p(name):
            return getattr(dut, f"m_axi_state_{name}")

        src, out = dut.pixels, dut.states
        axis_subordinate(m, past, tvalid=src.valid, tready=src.ready,
                         payload=[src.payload.as_value()], name="pixels")
        axis_manager(m, past, tvalid=out.valid, tready=out.ready,
                     payload=[out.payload.as_value()], name="states")
        # ---- the read channels: AR asserted, R assumed ------------------------------------
        read_counts = read_rules(m, past, store, dut.channel("ar"), dut.channel("r"))
        reads = read_counts.reads
        ar_hs = p("arvalid") & p("arready")
        aw_hs = p("awvalid") & p("awready")
        w_hs = p("wvalid") & p("wready")
        page = 4096

        # ---- writes (also the write-behind's harness) --------------------------------------
        counts = write_rules(m, past, store, dut.channel("aw"), dut.channel("w"),
                              dut.channel("b"))
        aw_open, writes = counts.aw_open, counts.writes

        # ---- ready, reset, work -------------------------------------------------------------
        with m.If(p("rvalid")):
            m.d.comb += Assert(p("rready"), "R: a requested beat not taken at once")
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

        self._invariants(m, past, top, read_counts, counts, in_flight, started)

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

    def _invariants(self, m, past, top, read_counts, write_counts, in_flight, started):
        from dptbd.sim.formal.harnesses.flow import dp_core_invariants
        from dptbd.sim.formal.harnesses.prefetcher import prefetcher_invariants
        from dptbd.sim.formal.harnesses.write_behind import write_behind_invariants

        store = top.sub("state_store")
        reader, writer = store.sub("reader"), store.sub("writer")
        wrote = Signal()                                    # a state write since the reset
        with m.If(writer.component.write_en):
            m.d.sync += wrote.eq(1)
        if "core" not in self.drop:
            dp_core_invariants(m, past, top.sub("core"), in_flight, started)
            with m.If(~started):
                m.d.comb += Assert(~wrote, "a state written before the first pixel")
        if "reader" not in self.drop:
            prefetcher_invariants(m, self.store, reader, reader.component.ar, read_counts)
        if "writer" not in self.drop:
            write_behind_invariants(m, self.store, writer, writer.component.aw, write_counts,
                                    wrote)
