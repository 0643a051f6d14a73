"""The harness of the state store's write-behind alone (:class:`WriteBehindHarness`) and the
invariants that make its AXI4 write rules k-inductive (:func:`write_behind_invariants`):
what :class:`~dptbd.hw.axi_store.write_behind.AxiWriteBehind`'s counters, run registers and
FIFOs (their levels and what their storage holds) mean in terms of the harness's shadow
counts of the write channels (:class:`~dptbd.sim.formal.harnesses.axi_store.WriteCounts`).
"""

from __future__ import annotations

from amaranth.hdl import Array, Assert, Assume, Cover, Mux, Signal
from amaranth.lib import data
from amaranth.lib.fifo import SyncFIFOBuffered

from dptbd.config import AxiStoreConfig
from dptbd.hw.axi_store.prefetcher import pixel_count_bits
from dptbd.hw.thermometer_fifo import ThermometerFIFO
from dptbd.sim.formal.harness import Elaborated, Harness
from dptbd.sim.formal.harnesses.axi_store import WriteCounts, tiny_store, write_rules

__all__ = ["WriteBehindHarness", "fifo_invariants", "thermometer_fifo_invariants",
           "write_behind_invariants", "INVARIANTS", "STAGED_INVARIANTS"]

#: The invariants' names, each a switch of :class:`WriteBehindHarness` (``drop``). The
#: proof needs every one but ``uptos`` (the B responses' pixel counts, which no write rule
#: reads): without any other, its induction step fails (``tests/sim/formal/test_runner.py``).
INVARIANTS = ("fifos", "in_flight", "lengths", "lengths_rows", "sent", "complete", "uptos",
              "descriptors", "run", "idle")
#: The invariants of the staged write-behind (``WriteBehindHarness(staged=True)``, the ECP5
#: build's): ``sent`` becomes ``current`` (the W burst under way in registers). Each is
#: needed but ``uptos``, as in :data:`INVARIANTS`; the beat stage's registered comparison
#: and the W FIFO's level counted beside it need none (the proof closes without them).
STAGED_INVARIANTS = ("fifos", "in_flight", "lengths", "lengths_rows", "current", "complete",
                     "uptos", "descriptors", "run", "idle")


def _at(rows, index):
    """``rows[index mod len(rows)]`` for ``index`` < 2 * len(rows)."""
    depth = len(rows)
    return Array(rows)[Mux(index >= depth, index - depth, index)]


def fifo_invariants(m, fifo: Elaborated, name: str) -> None:
    """Assert that the pointers of ``fifo`` (an :class:`~amaranth.lib.fifo.SyncFIFO` or
    :class:`~amaranth.lib.fifo.SyncFIFOBuffered`, elaborated) are within its storage and
    agree with its level (the storage's level: without the buffered FIFO's output register)."""
    produce, consume = fifo.signal("produce"), fifo.signal("consume")
    if isinstance(fifo.component, SyncFIFOBuffered):
        level, depth = fifo.signal("inner_level"), fifo.component.depth - 1
    else:
        level, depth = fifo.component.level, fifo.component.depth
    wrapped = Mux(consume + level >= depth, consume + level - depth, consume + level)
    m.d.comb += Assert((produce < depth) & (consume < depth) & (level <= depth)
                       & (produce == wrapped), f"{name}: pointers disagree with the level")


def thermometer_fifo_invariants(m, fifo: Elaborated, name: str):
    """Assert that the level of ``fifo`` (a :class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO`,
    elaborated, not staged) is a thermometer code and that its pointers are within its
    memory and agree with that level; returns the words it holds (the memory's and the
    output register's)."""
    from dptbd.sim.formal.harnesses.flow import _count, _thermometer

    at_least = fifo.sub("level").component.at_least
    _thermometer(m, at_least, name)
    count = _count(at_least)
    words = fifo.component.depth - 1
    produce, consume = fifo.signal("produce"), fifo.signal("consume")
    wrapped = Mux(consume + count >= words, consume + count - words, consume + count)
    m.d.comb += Assert((produce < words) & (consume < words) & (produce == wrapped),
                       f"{name}: pointers disagree with the level")
    return count + fifo.component.r.valid


def write_behind_invariants(m, store: AxiStoreConfig, wb: Elaborated, aw, counts: WriteCounts,
                            started, drop: tuple = ()) -> None:
    """Assert what :class:`~dptbd.hw.axi_store.write_behind.AxiWriteBehind`'s state means
    (``wb``, elaborated; ``aw`` its AW channel, ``started`` "a write since the reset"):

    - ``in_flight`` (bursts issued, no B yet) = the harness's writes in flight + the AW held,
      at most ``outstanding``;
    - every FIFO's pointers agree with its level (:func:`fifo_invariants`);
    - the ``lengths`` FIFO holds the bursts whose W is not done: its level is the shadow
      queue's plus the held AW unless its W is already done (``early``, at most one, only
      while an AW is held and no other W is open), its rows from the read pointer are the shadow queue's ``AWLEN``
      then the held ``AWLEN``;
    - ``sent`` (W beats of the burst under way) = the harness's beat count, 0 while no burst
      is queued, at most the head's length;
    - bursts with AW accepted and no B = those with W done + those with W open;
    - the ``uptos`` FIFO's level = ``in_flight``;
    - every descriptor (each row of the ``bursts`` FIFO, and its head while offered) stays within
      one aligned burst: ``beat mod burst_beats + len < burst_beats``; an open run ends
      before its burst's last beat, on the beat before the expected one;
    - before the first write nothing is queued, issued or packed.

    The staged write-behind (its ``bursts`` a :class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO`;
    :data:`STAGED_INVARIANTS`): the ``lengths`` FIFO holds the bursts queued behind the W
    burst under way (``current``, a burst with W open: the shadow queue's head), whose
    beats ``left`` after the one offered are its length less the beats sent and whose
    ``WLAST`` register is "none left", each row's "single beat" flag its length's; the
    descriptor staged for the ``bursts`` FIFO stays within its burst; that FIFO's level
    (a :class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO`'s) is a thermometer code that
    agrees with its pointers.
    """
    bb = store.burst_beats
    descriptor = data.StructLayout({"beat": range(store.frame_beats), "len": 8,
                                    "upto": pixel_count_bits(store)})
    bursts = wb.sub("bursts")
    staged = isinstance(bursts.component, ThermometerFIFO)
    width = len(bursts.component.r.payload) if staged else bursts.component.width
    assert descriptor.size == width, "the descriptor layout changed"

    def fits(view):
        return (view.len < bb) & ((view.beat & (bb - 1)) + view.len < bb)

    in_flight = wb.signal("in_flight")
    lengths, uptos = wb.sub("lengths"), wb.sub("uptos")
    level = lengths.component.level
    queued = counts.aw_open + (aw.awvalid & (counts.early == 0))
    current = wb.signal("current") if staged else None
    with_w = level + current if staged else level      # bursts with W open in the design
    sent = None if staged else wb.signal("sent")
    checks = {
        "in_flight": lambda: [
            Assert(in_flight == counts.writes + aw.awvalid, "in_flight != writes + AW held"),
            Assert(in_flight <= store.outstanding, "in_flight above outstanding"),
            Assert(counts.early <= (aw.awvalid & (counts.aw_open == 0)),
                   "a W burst done early without an AW held, or behind an open one")],
        "lengths": lambda: [Assert(with_w == queued,
                                   "lengths level != bursts with W open")],
        **({} if staged else {"sent": lambda: [Assert(sent == counts.w_beat,
                                                      "sent != the W beats of the open burst")]}),
        "complete": lambda: [Assert(counts.writes == counts.complete + counts.aw_open,
                                    "writes != complete + AW with W open")],
        "uptos": lambda: [Assert(uptos.component.level == in_flight, "uptos level != in_flight")],
    }
    asserts = [a for name, group in checks.items() if name not in drop for a in group()]
    if "fifos" not in drop:
        for fifo in ("lengths", "uptos") if staged else ("w_fifo", "bursts", "lengths", "uptos"):
            fifo_invariants(m, wb.sub(fifo), fifo)
    if staged:
        held = _staged_invariants(m, store, wb, aw, counts, fits, descriptor, drop)
        bursts_empty = ~held & ~bursts.component.w.valid
    else:
        bursts_empty = bursts.component.level == 0
    if "lengths_rows" not in drop:
        rows = lengths.rows("storage")
        depth = len(rows)
        consume = lengths.signal("consume")
        if staged:
            _staged_rows(m, rows, consume, aw, counts, current)
        else:
            for i, expected in enumerate(counts.open_lens[:depth]):
                with m.If(i < counts.aw_open):
                    m.d.comb += Assert(_at(rows, consume + i) == expected,
                                       f"lengths row {i} != AWLEN of open burst {i}")
            with m.If(aw.awvalid & (counts.early == 0)):
                m.d.comb += Assert(_at(rows, consume + counts.aw_open) == aw.awlen,
                                   "lengths row != the held AWLEN")
    if "sent" not in drop and not staged:
        with m.If(level == 0):
            m.d.comb += Assert(sent == 0, "sent != 0 with no burst queued")
        with m.Else():
            m.d.comb += Assert(sent <= lengths.component.r_data, "sent above the head's length")
    if "descriptors" not in drop:
        for i, row in enumerate(bursts.rows("storage")):
            asserts.append(Assert(fits(data.View(descriptor, row)),
                                  f"bursts row {i} crosses its burst"))
        r_rdy, r_data = ((bursts.component.r.valid, bursts.component.r.payload) if staged
                         else (bursts.component.r_rdy, bursts.component.r_data))
        with m.If(r_rdy):     # the read port's register: loaded with r_rdy
            m.d.comb += Assert(fits(data.View(descriptor, r_data)),
                               "bursts head crosses its burst")
    if "run" not in drop:
        run_start, run_len = wb.signal("run_start"), wb.signal("run_len")
        with m.If(wb.signal("run_open")):
            m.d.comb += [Assert((run_start & (bb - 1)) + run_len < bb - 1,
                                "open run reaches its burst's end"),
                         Assert(run_start + run_len + 1 == wb.signal("expect"),
                                "open run does not end before the expected beat")]
    if "idle" not in drop:
        with m.If(~started):
            m.d.comb += Assert((in_flight == 0) & bursts_empty
                               & ~wb.signal("beat_valid") & ~wb.signal("run_open"),
                               "work queued before the first write")
    m.d.comb += asserts


def _staged_rows(m, rows, consume, aw, counts, current):
    """The staged ``lengths`` FIFO's rows from its read pointer: the bursts queued behind
    the one under way (the shadow queue's from its second, then the held AW's), each
    ``AWLEN`` with its "single beat" flag."""
    for j in range(len(rows)):
        i = j + 1                                   # the shadow queue's burst in row j
        expected = Mux(i < counts.aw_open, counts.open_lens[i] if i < len(counts.open_lens)
                       else 0, aw.awlen)
        queued = (i < counts.aw_open) | ((i == counts.aw_open) & aw.awvalid
                                         & (counts.early == 0))
        with m.If(current & queued):
            got = _at(rows, consume + j)
            m.d.comb += Assert((got[:8] == expected) & (got[8] == (expected == 0)),
                               f"lengths row {j} != the AWLEN behind the burst under way")


def _staged_invariants(m, store, wb, aw, counts, fits, descriptor, drop):
    """The staged write-behind's own registers (:func:`write_behind_invariants`); returns
    the ``bursts`` FIFO's words held (for "nothing queued")."""
    bursts = wb.sub("bursts")
    if "fifos" not in drop:
        held = thermometer_fifo_invariants(m, bursts, "bursts")
    else:
        from dptbd.sim.formal.harnesses.flow import _count
        held = _count(bursts.sub("level").component.at_least) + bursts.component.r.valid
    if "current" not in drop:
        current, left, last = wb.signal("current"), wb.signal("left"), wb.signal("last")
        head = Mux(counts.aw_open != 0, counts.open_lens[0], aw.awlen)
        with m.If(current):
            m.d.comb += [Assert(left + counts.w_beat == head,
                                "left + beats sent != the length of the burst under way"),
                         Assert(last == (left == 0), "WLAST register != no beat left")]
        with m.Else():
            m.d.comb += Assert(counts.w_beat == 0, "beats sent with no burst under way")
    if "descriptors" not in drop:
        with m.If(bursts.component.w.valid):
            m.d.comb += Assert(fits(data.View(descriptor, bursts.component.w.payload)),
                               "staged descriptor crosses its burst")
    return held


class WriteBehindHarness(Harness):
    """:class:`~dptbd.hw.axi_store.write_behind.AxiWriteBehind` of
    :func:`~dptbd.sim.formal.harnesses.axi_store.tiny_store` alone (``in_flight`` as in
    :class:`~dptbd.hw.axi_store.pipeline.DPPipelineAxi` of that build), so that the proof
    reaches many bursts: the pipeline's writes in raster order (the next address, or 0
    after a resynchronisation), each only while ``room`` is high (a subset of the
    pipeline's behaviour, which may still write ``in_flight`` states after ``room`` fell),
    state words of one free bit (bit 0; the rest 0: no handshake depends on the data), any
    ``base`` aligned to the burst size; the subordinate as in
    :class:`~dptbd.sim.formal.harnesses.axi_store.AxiStoreHarness` (B only for a burst
    whose AW and last W beat were accepted, held until taken, any ``BRESP``).

    ``staged``: the ECP5 build's write-behind (``AxiWriteBehind(staged=True)``), the
    invariants :data:`STAGED_INVARIANTS`.

    Asserted: the AW and W rules of ``AxiStoreHarness`` (held valid, stable payload, INCR
    of full beats, aligned, no 4 KB crossing, ``AWLEN`` < ``burst_beats``, W never ahead of
    its AW, ``WLAST`` on beat ``AWLEN`` + 1, full strobes), ``BREADY`` high, at most
    ``outstanding`` writes in flight, no valid in the first cycle after reset or before the
    first write; and the invariants of :func:`write_behind_invariants`, less those named in
    ``drop`` (:data:`INVARIANTS`; for the test that each is needed).
    """

    #: The design under proof (``None``: :class:`~dptbd.hw.axi_store.write_behind.AxiWriteBehind`;
    #: a known-bad harness sets a broken one).
    design = None

    def __init__(self, store: AxiStoreConfig | None = None, drop: tuple = (),
                 staged: bool = False):
        super().__init__()
        self.store = store or tiny_store()
        self.staged = staged
        names = STAGED_INVARIANTS if staged else INVARIANTS
        unknown = sorted(set(drop) - set(names))
        if unknown:
            raise ValueError(f"unknown write-behind invariant(s) {', '.join(unknown)}; the "
                             f"invariants are {', '.join(names)}")
        self.drop = tuple(drop)

    def check(self, m, past):
        from dptbd.hw.axi_store.write_behind import AxiWriteBehind
        from dptbd.hw.schedule import check_supported

        store = self.store
        in_flight = check_supported(store.frame).write_latency + 1
        design = self.design or AxiWriteBehind
        wb = Elaborated(design(store, in_flight=in_flight, staged=self.staged))
        m.submodules.dut = wb.fragment
        dut = wb.component
        self.free_inputs(m, dut, "dut")
        aw, w, b = dut.aw, dut.w, dut.b
        if self.staged:         # room_next: room's register input, for the store's gate
            m.d.comb += Assert((dut.room == past(dut.room_next, "past_room_next")) | past.rst,
                               "room != room_next a cycle earlier")
        pixels = store.frame.width * store.frame.height
        next_addr = Signal(range(pixels))
        with m.If(dut.write_en):
            m.d.sync += next_addr.eq(Mux(dut.write_addr == pixels - 1, 0, dut.write_addr + 1))
        with m.If(dut.write_en):
            m.d.comb += [Assume(dut.room),
                         Assume((dut.write_addr == next_addr) | (dut.write_addr == 0))]
        m.d.comb += [Assume(dut.base[:(store.burst_bytes - 1).bit_length()] == 0),
                     # one data bit free: the W data's stability is still checked, and the
                     # solver need not carry whole words through the FIFO
                     Assume(dut.write_data.as_value()[1:] == 0)]
        counts = write_rules(m, past, store, aw, w, b)
        started = Signal()
        with m.If(dut.write_en):
            m.d.sync += started.eq(1)
        with m.If(past.rst):
            m.d.comb += Assert(~aw.awvalid & ~w.wvalid, "a valid in the first cycle after reset")
        with m.If(~started):
            m.d.comb += Assert(~aw.awvalid & ~w.wvalid, "AW or W valid before any write")
        write_behind_invariants(m, store, wb, aw, counts, started, self.drop)
        page = 4096
        end = aw.awaddr[:12] + (aw.awlen + 1) * store.beat_bytes
        m.d.comb += [
            Cover(aw.awvalid & aw.awready & (aw.awlen == store.burst_beats - 1) & (end == page)),
            Cover(aw.awvalid & ~aw.awready & (counts.aw_open != 0)),
            Cover(w.wvalid & w.wready & w.wlast & (counts.aw_open == 0)),
            Cover(counts.writes == store.outstanding),
            Cover(dut.error),
            Cover(dut.write_en & (dut.write_addr == 0) & (next_addr != 0) & started),
            Cover(aw.awvalid & aw.awready & (aw.awlen == 0)),        # a burst cut short
        ]
