"""Write-behind buffer of the state store in external memory: packs the pipeline's state
writes into beats and sends them as AXI4 INCR bursts, never stalling the pipeline.

The pipeline writes one store word per processed pixel (one state at P = 1, the P states of
a beat at P > 1, each in its own slot: :func:`~dptbd.hw.axi_store.prefetcher.to_slots`), in
raster order, a fixed latency after accepting it, and cannot wait: the write-behind takes
every ``write_en``. It packs ``S / P`` words per beat (position ``addr mod S/P``), queues
full beats in the W FIFO and cuts them into bursts
that end at a burst-aligned boundary or at the frame's last beat. ``room`` tells the input
gate whether the FIFO can take every state of the pixels already in the pipeline plus one
more (``in_flight`` of them at most).

A resynchronisation restarts the write addresses at 0: the open burst is closed where it
stands, and the partial beat of the interrupted frame is dropped (its states are never
read: the frame after a resynchronisation is a segment's start frame, which writes every
address before the next frame reads it). ``written`` counts the pixels whose writes have
their B response, in pixel order (a dropped word counts with the next burst), for
:class:`~dptbd.hw.axi_store.prefetcher.AxiReadPrefetcher`.
"""

from __future__ import annotations

from amaranth.hdl import Cat, Module, Mux, Signal
from amaranth.lib import data, wiring
from amaranth.lib.fifo import SyncFIFO, SyncFIFOBuffered
from amaranth.lib.wiring import In, Out

from dptbd.config import AxiStoreConfig
from dptbd.hw.axi_store.bus import BURST_INCR, CACHE_MODIFIABLE, address_channel, axi4_signature, size_code
from dptbd.hw.axi_store.prefetcher import pixel_count_bits, store_word_layout, to_slots
from dptbd.hw.thermometer_fifo import ThermometerFIFO

__all__ = ["AxiWriteBehind"]


class _BufferedPorts:
    """A :class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO` (added to ``m`` as ``name``)
    under ``SyncFIFOBuffered``'s port names, whose cycles it has."""

    def __init__(self, m: Module, name: str, fifo: ThermometerFIFO):
        m.submodules[name] = fifo
        self.w_data, self.w_en, self.w_rdy = fifo.w.payload, fifo.w.valid, fifo.w.ready
        self.r_data, self.r_rdy, self.r_en = fifo.r.payload, fifo.r.valid, fifo.r.ready


class AxiWriteBehind(wiring.Component):
    """AW / W / B channels of the state store's AXI4 port (see the module doc).

    Parameters
    ----------
    store : AxiStoreConfig
        Frame, packing, burst length and outstanding limit.
    in_flight : int
        The most writes that may still arrive after ``room`` was last high (the pipeline's
        write latency + 1).
    staged : bool
        ``False`` (default): a closed burst's descriptor is written into the descriptor
        FIFO in the cycle its last beat is processed. ``True`` (the ECP5 build's,
        :class:`~dptbd.hw.axi_store.AxiStateStore` ``style="dp16kd"``): a cycle later, from
        registers (the FIFO's LUT-RAM write enable and data follow no logic), so each AW
        goes out one cycle later; the W FIFO and the descriptor FIFO are
        :class:`~dptbd.hw.thermometer_fifo.ThermometerFIFO` (the same cycles, "not empty"
        and "full" registers), the W FIFO's level counted beside it; its depth and margin
        are the same, so with bursts of 4 beats or more ``room`` falls as without
        (tested), with bursts of 2 it may fall earlier (the pipeline's AR side is slower
        there). The W burst under way is registers (``WLAST`` one), the same W in every
        cycle. Adds the member ``room_next``.

    Members
    -------
    aw, w, b : AXI4 write channels.
    base : In(address_bits)
        Byte address of pixel 0's slot.
    write_en, write_addr, write_data : In
        The pipeline's store-word write (:class:`~dptbd.hw.state_store.StateStoreSignature`,
        :class:`~dptbd.hw.wide.state_store.WideStateStoreSignature` at P > 1).
    room : Out(1)
        The W FIFO has room for ``in_flight`` more words (a register: its level in the
        cycle before, with one beat of margin more).
    written : Out(pixel_count_bits(store))
        Pixels whose writes have their B response (modular count since reset).
    error : Out(1)
        Pulse: a write response was ``SLVERR`` or ``DECERR``.
    room_next : Out(1)
        With ``staged``: the value ``room`` takes at the next clock edge (its register's
        input), for a gate that registers ``room`` with other flags.
    """

    def __init__(self, store: AxiStoreConfig, *, in_flight: int, staged: bool = False):
        self._store = store
        self._in_flight = in_flight
        self._staged = staged
        axi = axi4_signature(store)
        extra = {"room_next": Out(1)} if staged else {}
        super().__init__({
            "aw": Out(address_channel("aw", store.address_bits, store.id_bits)),
            "w": Out(axi.members["w"].signature),
            "b": Out(axi.members["b"].signature),
            "base": In(store.address_bits, init=store.base_address),
            "write_en": In(1),
            "write_addr": In(range(store.frame_words)),
            "write_data": In(store_word_layout(store)),
            "room": Out(1),
            "written": Out(pixel_count_bits(store)),
            "error": Out(1),
            **extra,
        })

    @property
    def margin(self) -> int:
        """W FIFO beats kept free for the pipeline: ``in_flight`` words, the packing
        register, the beat stage, and the beat that may enter while ``room`` (a register,
        the level of the cycle before) is stale."""
        per_beat = self._store.words_per_beat
        return -(-(self._in_flight + per_beat - 1) // per_beat) + 3

    @property
    def fifo_depth(self) -> int:
        """Beats of the W FIFO: two full bursts plus :attr:`margin`."""
        return 2 * self._store.burst_beats + self.margin

    def elaborate(self, platform):
        m = Module()
        store = self._store
        per_beat = store.words_per_beat
        beats = store.frame_beats
        count_bits = pixel_count_bits(store)
        depth = self.fifo_depth
        slot_select = (per_beat - 1).bit_length()

        # ---- packing: word into position addr mod S/P; a full beat goes to the beat stage ---
        packing = Signal(store.data_bits)
        count = Signal(count_bits)                   # words written since reset
        beat_valid = Signal()
        beat_index = Signal(range(beats))
        beat_upto = Signal(count_bits)
        slot = self.write_addr[:slot_select]
        with m.If(self.write_en):
            m.d.sync += [
                packing.word_select(slot, store.word_bits).eq(
                    to_slots(store, self.write_data.as_value())),
                count.eq(count + 1)]
        full = self.write_en & (slot == per_beat - 1) if slot_select else self.write_en
        m.d.sync += beat_valid.eq(full)
        # The burst flags of the beat, computed as it enters the beat stage (a cycle ahead of
        # the descriptor write that uses them): whether it ends a burst block or the frame,
        # whether it follows the run (is the beat `expect` will hold when it is processed),
        # and the beat after it.
        new_index = self.write_addr >> slot_select

        expect = Signal(range(beats))                # the beat that continues the run
        beat_next = Signal(range(beats))
        beat_block_end = Signal()
        if self._staged:
            # the comparison in pairs of bits, each pair's against both candidates before
            # `beat_valid` chooses, registered; the beat stage ANDs the pairs' flags
            pairs = range(0, len(beat_next), 2)
            follows_pairs = Signal(len(pairs))
            beat_follows = follows_pairs.all()

            def follows_test(index, valid, after_valid, otherwise):
                return Cat(*[Mux(valid, index[k:k + 2] == after_valid[k:k + 2],
                                 index[k:k + 2] == otherwise[k:k + 2]) for k in pairs])
        else:
            beat_follows = follows_pairs = Signal()

            def follows_test(index, valid, after_valid, otherwise):
                return index == Mux(valid, after_valid, otherwise)
        with m.If(full):
            m.d.sync += [beat_index.eq(new_index),
                         beat_upto.eq(count + 1),
                         beat_next.eq(Mux(new_index == beats - 1, 0, new_index + 1)),
                         beat_block_end.eq(
                             ((new_index & (store.burst_beats - 1)) == store.burst_beats - 1)
                             | (new_index == beats - 1)),
                         follows_pairs.eq(follows_test(new_index, beat_valid, beat_next, expect))]

        # ---- bursts: runs of consecutive beats, closed at a boundary, the frame's end,
        # or a jump (resynchronisation) -----------------------------------------------------
        descriptor = data.StructLayout({"beat": range(beats), "len": 8, "upto": count_bits})
        # the descriptors in block RAM (a registered read, one cycle more from a closed burst
        # to its AW; the W FIFO's margin does not depend on it): a queue read without a clock
        # edge is flip-flops and a read multiplexer on the iCE40
        if self._staged:
            # the same FIFOs' cycles with their "not empty" and "full" registers
            w_fifo = _BufferedPorts(m, "w_fifo", ThermometerFIFO(store.data_bits, depth))
            bursts = _BufferedPorts(m, "bursts", ThermometerFIFO(descriptor.size, depth))
        else:
            m.submodules.w_fifo = w_fifo = SyncFIFOBuffered(width=store.data_bits, depth=depth)
            m.submodules.bursts = bursts = SyncFIFOBuffered(width=descriptor.size, depth=depth)
        m.d.comb += [w_fifo.w_data.eq(packing), w_fifo.w_en.eq(beat_valid)]
        run_open = Signal()
        run_start = Signal(range(beats))
        run_len = Signal(8)                          # beats - 1
        run_upto = Signal(count_bits)
        # staged: the descriptor and its write enable a cycle later, from registers
        closing_en = Signal() if self._staged else bursts.w_en
        closing_data = Signal(descriptor.size) if self._staged else bursts.w_data
        if self._staged:
            m.d.sync += [bursts.w_en.eq(closing_en), bursts.w_data.eq(closing_data)]
        closing = data.View(descriptor, closing_data)
        block_end = beat_block_end
        if self._staged:
            self._close_runs(m, beat_valid, beat_follows, beat_index, beat_upto, block_end,
                             expect, beat_next, (run_open, run_start, run_len, run_upto),
                             closing, closing_en)
        else:
            with m.If(beat_valid):
                m.d.sync += expect.eq(beat_next)
                jump = run_open & ~beat_follows
                starts = ~run_open | jump
                start = Mux(starts, beat_index, run_start)
                length = Mux(starts, 0, run_len + 1)
                with m.If(jump):                         # never also a block end: beat 0
                    m.d.comb += [closing.beat.eq(run_start), closing.len.eq(run_len),
                                 closing.upto.eq(run_upto), closing_en.eq(1)]
                with m.Elif(block_end):
                    m.d.comb += [closing.beat.eq(start), closing.len.eq(length),
                                 closing.upto.eq(beat_upto), closing_en.eq(1)]
                m.d.sync += [run_open.eq(~block_end), run_start.eq(start), run_len.eq(length),
                             run_upto.eq(beat_upto)]
        # registered: the level rises by at most one beat a cycle, which the margin counts
        room = Signal(init=1)
        if self._staged:
            # the W FIFO's level, counted here (SyncFIFOBuffered's `level`)
            # (its steps computed beside it, the handshakes choosing last)
            level = Signal(range(depth + 1))
            up = w_fifo.w_en & w_fifo.w_rdy
            down = w_fifo.r_en & w_fifo.r_rdy
            m.d.sync += level.eq(Mux(up == down, level, Mux(up, level + 1, level - 1)))
            m.d.comb += self.room_next.eq(level <= depth - self.margin)
        else:
            level = w_fifo.level
        m.d.sync += room.eq(level <= depth - self.margin)
        m.d.comb += self.room.eq(room)

        # ---- AW: one burst at a time from the descriptor FIFO ---------------------------
        head = data.View(descriptor, bursts.r_data)
        if self._staged:
            # the lengths with a "single beat" flag: the W burst under way loads its WLAST
            # from it (``_w_in_registers``)
            queued = data.StructLayout({"len": 8, "single": 1})
            m.submodules.lengths = lengths = SyncFIFO(width=queued.size, depth=store.outstanding)
        else:
            m.submodules.lengths = lengths = SyncFIFO(width=8, depth=store.outstanding)
        m.submodules.uptos = uptos = SyncFIFO(width=count_bits, depth=store.outstanding)
        in_flight = Signal(range(store.outstanding + 1))
        issue = Signal()
        m.d.comb += [
            issue.eq(bursts.r_rdy & ~self.aw.awvalid & (in_flight < store.outstanding)),
            bursts.r_en.eq(issue),
            uptos.w_data.eq(head.upto), uptos.w_en.eq(issue),
            self.aw.awid.eq(0),
            self.aw.awsize.eq(size_code(store.beat_bytes)),
            self.aw.awburst.eq(BURST_INCR),
            self.aw.awcache.eq(CACHE_MODIFIABLE),
        ]
        with m.If(self.aw.awvalid & self.aw.awready):
            m.d.sync += self.aw.awvalid.eq(0)
        with m.If(issue):
            m.d.sync += [self.aw.awvalid.eq(1),
                         self.aw.awaddr.eq(self.base + head.beat * store.beat_bytes),
                         self.aw.awlen.eq(head.len)]

        # ---- W: the beats of issued bursts, WLAST from their lengths ---------------------
        m.d.comb += [
            self.w.wdata.eq(w_fifo.r_data),
            self.w.wstrb.eq((1 << (store.data_bits // 8)) - 1),
            w_fifo.r_en.eq(self.w.wvalid & self.w.wready),
        ]
        if self._staged:
            self._w_in_registers(m, lengths, queued, head, issue, w_fifo)
        else:
            sent = Signal(8)
            m.d.comb += [
                lengths.w_data.eq(head.len), lengths.w_en.eq(issue),
                self.w.wvalid.eq(w_fifo.r_rdy & lengths.r_rdy),
                self.w.wlast.eq(sent == lengths.r_data),
                lengths.r_en.eq(self.w.wvalid & self.w.wready & self.w.wlast),
            ]
            with m.If(self.w.wvalid & self.w.wready):
                m.d.sync += sent.eq(Mux(self.w.wlast, 0, sent + 1))

        # ---- B: count the answered pixels, flag errors ----------------------------------
        answered = self.b.bvalid & self.b.bready
        m.d.comb += [
            self.b.bready.eq(1),
            uptos.r_en.eq(answered),
            self.error.eq(answered & self.b.bresp[1]),
        ]
        with m.If(answered):
            m.d.sync += self.written.eq(uptos.r_data)
        m.d.sync += in_flight.eq(in_flight + issue - answered)
        return m

    @staticmethod
    def _close_runs(m, beat_valid, follows, beat_index, beat_upto, block_end, expect,
                    beat_next, run, closing, closing_en):
        # staged: the beat stage with the jump choosing last (its test ANDs the registered
        # pairs): the closing descriptor and the run's next start and length are the
        # jump's or those without one, each computed beside it
        run_open, run_start, run_len, run_upto = run
        with m.If(beat_valid):
            m.d.sync += expect.eq(beat_next)
            jump = run_open & ~follows
            # without a jump: the run continues, or a new one opens at this beat
            start = Mux(run_open, run_start, beat_index)
            length = Mux(run_open, run_len + 1, 0)
            m.d.comb += [closing.beat.eq(Mux(jump, run_start, start)),
                         closing.len.eq(Mux(jump, run_len, length)),
                         closing.upto.eq(Mux(jump, run_upto, beat_upto)),
                         closing_en.eq(jump | block_end)]
            m.d.sync += [run_open.eq(~block_end),
                         run_start.eq(Mux(jump, beat_index, start)),
                         run_len.eq(Mux(jump, 0, length)),
                         run_upto.eq(beat_upto)]

    def _w_in_registers(self, m, lengths, queued, head, issue, w_fifo):
        # staged: the W burst under way in registers (valid, beats left after this one,
        # WLAST), loaded when the burst ends (or none is under way) from the lengths FIFO's
        # head or, that FIFO empty, from the descriptor issued in this cycle (which then
        # skips the FIFO): WVALID is two registers' AND, WLAST a register, and the lengths
        # FIFO's read enable one LUT of registers and WREADY. The same W in every cycle.
        current = Signal()                   # a burst's W is under way
        left = Signal(8)                     # its beats after the one offered
        last = Signal()                      # WLAST: the one offered is its last
        beat = self.w.wvalid & self.w.wready
        done = ~current | (beat & last)      # no burst under way after this cycle
        queue = data.View(queued, lengths.r_data)
        m.d.comb += [
            self.w.wvalid.eq(w_fifo.r_rdy & current),
            self.w.wlast.eq(last),
            lengths.r_en.eq(done),
            lengths.w_data.eq(Cat(head.len, head.len == 0)),
            lengths.w_en.eq(issue & ~(done & ~lengths.r_rdy)),
        ]
        with m.If(done):
            with m.If(lengths.r_rdy):
                m.d.sync += [current.eq(1), left.eq(queue.len), last.eq(queue.single)]
            with m.Elif(issue):
                m.d.sync += [current.eq(1), left.eq(head.len), last.eq(head.len == 0)]
            with m.Else():
                m.d.sync += current.eq(0)
        with m.Elif(beat):
            m.d.sync += [left.eq(left - 1), last.eq(left == 1)]
