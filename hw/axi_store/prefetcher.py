"""Read prefetcher of the state store in external memory: AXI4 INCR bursts in raster order,
kept in flight ahead of the pipeline, unpacked into one store word per taken pixel.

A *store word* is what the pipeline's store port reads and writes at a time: one state at
P = 1 pixel per clock, the P states of a beat at P = 2 or 4
(:class:`~dptbd.hw.wide.state_store.WideStateStoreSignature`); "pixel" below means one
accepted input beat, "word" one store word (P consecutive state slots in memory, the same
byte layout at every P). The pipeline reads the state store in raster order,
``read_ahead_distance`` words ahead of the accepted pixel (of the beat configuration at
P > 1), wrapping at the frame's end (:class:`~dptbd.hw.controller.Controller`); the
prefetcher reads that same sequence ahead of time. It issues a burst when

* the beat FIFO has room for all its beats (counting the beats of bursts in flight), so
  ``RREADY`` only drops if the memory sends beats it was not asked for;
* fewer than ``outstanding`` bursts are in flight;
* every word of the burst has been written by the previous frame and that write answered
  (``written``, the count of pixels whose write bursts have their B response, from
  :class:`~dptbd.hw.axi_store.write_behind.AxiWriteBehind`): the pixel taking read word ``i``
  needs the state written by pixel ``i + D - W*H/P``, ``D`` the read-ahead. AXI4 does not
  order reads after writes, so the prefetcher waits for the write's response.

Bursts start at the next beat and end at a burst-aligned boundary or at the frame's last
beat, so with a burst-aligned base address they never cross a 4 KB boundary.

Restart: a resynchronisation (``restart`` with ``take``) moves the pipeline's read address
back to the start of a frame. The prefetcher drops every beat requested so far (those in
flight are received and discarded) and starts again at word ``D + 1``. Pixels of the frame
that follows a resynchronisation ignore their predecessors (a segment's start frame), so
the words they take in the meantime do not matter; only the order rule above does.
"""

from __future__ import annotations

from amaranth.hdl import Cat, Const, Module, Mux, Signal, Value
from amaranth.lib import wiring
from amaranth.lib.fifo import SyncFIFOBuffered
from amaranth.lib.wiring import In, Out

from dptbd.config import AxiStoreConfig, DPConfig
from dptbd.hw.axi_store.beat_queue import SKID_BEATS, dp16kd_beat_queue
from dptbd.hw.axi_store.bus import BURST_INCR, CACHE_MODIFIABLE, address_channel, axi4_signature, size_code
from dptbd.hw.layouts import state_word_layout
from dptbd.hw.schedule import read_ahead_distance

__all__ = ["PREFETCH_FIFO_STYLES", "SKID_BEATS", "pixel_count_bits", "store_word_layout",
           "to_slots", "AxiReadPrefetcher"]

#: ``AxiReadPrefetcher(style=…)``: the beat FIFO as an Amaranth FIFO, or ECP5 DP16KDs read
#: through their output register.
PREFETCH_FIFO_STYLES = ("memory", "dp16kd")


def store_word_layout(store: AxiStoreConfig):
    """The store port's word: one state (:func:`~dptbd.hw.layouts.state_word_layout`) at
    P = 1, the P states of a beat (:func:`~dptbd.hw.wide.layouts.beat_word_layout`) at
    P > 1."""
    if store.word_states == 1:
        return state_word_layout(store.frame)
    from dptbd.hw.wide.layouts import beat_word_layout
    return beat_word_layout(store.frame)


def to_slots(store: AxiStoreConfig, word: Value) -> Value:
    """A store word's bits as laid out in memory: each state zero-extended to its slot
    (``store.word_bits`` bits; at P = 1 the word itself, extended where it is assigned)."""
    if store.word_states == 1:
        return word
    bits, pad = store.frame.state_bits, store.slot_bits - store.frame.state_bits
    return Cat(*[Cat(word[k * bits:(k + 1) * bits], Const(0, pad))
                 for k in range(store.word_states)])


def from_slots(store: AxiStoreConfig, chunk: Value) -> Value:
    """The inverse of :func:`to_slots`: the store word in a ``word_bits`` chunk of a beat."""
    bits = store.frame.state_bits
    if store.word_states == 1:
        return chunk[:bits]
    return Cat(*[chunk.word_select(k, store.slot_bits)[:bits]
                 for k in range(store.word_states)])


def pixel_count_bits(store: AxiStoreConfig) -> int:
    """Width of the modular pixel counters that order reads after writes: room for four
    frames plus every buffered word, so the signed difference of two of them never wraps."""
    frame = store.frame
    span = 4 * frame.width * frame.height + 4 * store.outstanding * store.burst_states
    return span.bit_length() + 1


class AxiReadPrefetcher(wiring.Component):
    """AR / R channels of the state store's AXI4 port (see the module doc).

    Parameters
    ----------
    store : AxiStoreConfig
        Frame, packing, burst length and outstanding limit.
    style : {"memory", "dp16kd"}
        The beat FIFO: ``"memory"`` (default) a ``SyncFIFOBuffered`` whose block RAM read is
        registered into the head beat; ``"dp16kd"`` (ECP5) a ring buffer in DP16KDs
        (:func:`~dptbd.hw.dp16kd.dp16kd_memory`) read through their output register at
        their own pace into :data:`SKID_BEATS` flip-flop beats, whose head is the head
        beat: no block-RAM clock-to-out before a register, and the DP16KDs' enables follow
        registers, not ``take``. Same words in the same order; the first word is available
        a cycle later (the first pixel of a zero-latency memory enters in cycle 6 instead
        of 5), then one per cycle; a restart's loads come in the cycle after it, where
        ``available`` is low (at P = 1 the pixel after a resynchronisation enters a cycle
        later). ``"dp16kd"`` adds the member ``available_next``.
        Anything else raises ``ValueError``.
    dp16kd : callable or None
        With ``style="dp16kd"``: builds one DP16KD (``cell`` of
        :func:`~dptbd.hw.dp16kd.dp16kd_memory`; ``None``: the ``Instance``). Tests pass a
        behavioural model.

    Members
    -------
    ar : Out(address_channel("ar", …))
        AXI4 read address channel.
    r : Out(…)
        AXI4 read data channel (``rready`` out).
    base : In(address_bits)
        Byte address of pixel 0's slot (a multiple of the burst size).
    written : In(pixel_count_bits(store))
        Pixels whose state writes have been answered (modular count since reset).
    available : Out(1)
        A word is ready: ``word`` holds it.
    word : Out(store_word_layout(store))
        The next store word in raster read-ahead order.
    take : In(1)
        The word is consumed in this cycle (only with ``available``).
    restart : In(1)
        With ``take``: the pixel taking the word resynchronised (see the module doc).
    error : Out(1)
        Pulse: a read beat came back with ``SLVERR`` or ``DECERR``.
    available_next : Out(1)
        With ``style="dp16kd"``: the value ``available`` takes at the next clock edge, for
        a gate that registers it (:class:`~dptbd.hw.axi_store.AxiStateStore`), except after
        a restart (``take`` with ``restart``), where it is low.
    """

    def __init__(self, store: AxiStoreConfig, *, style: str = "memory", dp16kd=None):
        if style not in PREFETCH_FIFO_STYLES:
            raise ValueError(f"style must be one of {PREFETCH_FIFO_STYLES}, got {style!r}")
        self._store = store
        self._style = style
        self._dp16kd = dp16kd
        axi = axi4_signature(store)
        extra = {"available_next": Out(1)} if style == "dp16kd" else {}
        super().__init__({
            **extra,
            "ar": Out(address_channel("ar", store.address_bits, store.id_bits)),
            "r": Out(axi.members["r"].signature),
            "base": In(store.address_bits, init=store.base_address),
            "written": In(pixel_count_bits(store)),
            "available": Out(1),
            "word": Out(store_word_layout(store)),
            "take": In(1),
            "restart": In(1),
            "error": Out(1),
        })

    @property
    def fifo_depth(self) -> int:
        """Beats the R FIFO holds: ``outstanding`` full bursts."""
        return self._store.outstanding * self._store.burst_beats

    def elaborate(self, platform):
        m = Module()
        store = self._store
        cfg: DPConfig = store.frame
        pixels = store.frame_words                   # store words (beats of pixels at P > 1)
        per_beat = store.words_per_beat
        beats = store.frame_beats
        ahead = read_ahead_distance(cfg.beat_config())
        first_word = ahead % pixels                  # what the controller reads first
        restart_word = (ahead + 1) % pixels          # and after a resync pixel
        count_bits = pixel_count_bits(store)
        depth = self.fifo_depth

        if self._style == "memory":
            m.submodules.fifo = fifo = SyncFIFOBuffered(width=store.data_bits, depth=depth)
            m.d.comb += [
                fifo.w_data.eq(self.r.rdata),
                fifo.w_en.eq(self.r.rvalid),
                self.r.rready.eq(fifo.w_rdy),
                self.error.eq(self.r.rvalid & self.r.rready & self.r.rresp[1]),
            ]
        else:
            m.d.comb += self.error.eq(self.r.rvalid & self.r.rready & self.r.rresp[1])

        # ---- issue side: next beat, its burst's length, the write count it needs -----------
        # ``need``: the written count the burst at ``next_beat`` waits for (the word taking its
        # last word, index i, needs the writes of words up to i + D - W*H/P answered). It and
        # ``length`` are registers, brought up to date in the cycle after an issue and set
        # outright by a restart. The two tests on them are registers too, of the cycle before:
        # ``ordered`` (``written`` only grows, so an old one errs on the safe side) and
        # ``fits`` (``reserved`` grows only by an issue). So after an issue in cycle t, ARVALID
        # blocks t + 1, ``settling`` blocks t + 2 (the tests of t + 1 saw the old ``need`` /
        # ``length``), and after a restart ``settling`` blocks the next cycle: a burst issues
        # every third cycle at most, and every issue test is a register.
        def burst_length(beat: int) -> int:
            return min(store.burst_beats - beat % store.burst_beats, beats - beat)

        modulus = 1 << count_bits
        first_beat, first_skip = first_word // per_beat, first_word % per_beat
        restart_beat, restart_skip = restart_word // per_beat, restart_word % per_beat
        first_need = (burst_length(first_beat) * per_beat - first_skip + ahead - pixels) % modulus
        next_beat = Signal(range(beats), init=first_beat)
        length = Signal(range(store.burst_beats + 1), init=burst_length(first_beat))
        need = Signal(count_bits, init=first_need)
        issued = Signal()                            # a burst issued in the previous cycle
        settling = Signal()                          # the tests below are of stale values
        # dp16kd: a restart's loads a cycle later, from this register (the pipeline's
        # handshake drives one flip-flop), while `ready` is low; `settling` covers the cycle
        # after them
        restarting = Signal()
        reserved = Signal(range(depth + 1))          # beats requested and not popped
        in_flight = Signal(range(store.outstanding + 1))
        # reset values: the tests on the reset values (written = 0, nothing reserved)
        ordered = Signal(init=(-first_need) % modulus < modulus // 2)
        fits = Signal(init=burst_length(first_beat) <= depth)
        m.d.sync += [ordered.eq((self.written - need)[:count_bits].as_signed() >= 0),
                     fits.eq(reserved + length <= depth)]

        rlast_seen = self.r.rvalid & self.r.rready & self.r.rlast
        issue = Signal()
        # not gated by ``restart`` (that comes from the pipeline's input handshake): a burst
        # issued in a restart's cycle belongs to the old sequence and is dropped as stale
        m.d.comb += issue.eq(~self.ar.arvalid & ~settling & ordered & fits
                             & (in_flight < store.outstanding))
        m.d.comb += [
            self.ar.arid.eq(0),
            self.ar.arsize.eq(size_code(store.beat_bytes)),
            self.ar.arburst.eq(BURST_INCR),
            self.ar.arcache.eq(CACHE_MODIFIABLE),
        ]
        with m.If(self.ar.arvalid & self.ar.arready):
            m.d.sync += self.ar.arvalid.eq(0)
        m.d.sync += [issued.eq(issue & ~(self.take & self.restart)),   # a restart sets both
                     settling.eq(issued | (self.take & self.restart)
                                 | (restarting if self._style == "dp16kd" else 0))]
        if self._style == "dp16kd":
            # the beat after the burst, a register of the cycle before: `next_beat` and
            # `length` never change in the cycle before an issue (ARVALID and `settling`
            # block the two cycles after one, `settling` the cycle after a restart), so the
            # issue loads it without the addition. A burst from the frame's last block
            # (and only one) ends the frame: that test is beside the addition
            after_first = first_beat + burst_length(first_beat)
            following_beat = Signal(range(beats), init=0 if after_first == beats else after_first)
            last_block_start = (beats - 1) // store.burst_beats * store.burst_beats
            m.d.sync += following_beat.eq(
                Mux(next_beat >= last_block_start, 0, next_beat + length))
        else:
            following_beat = Mux(next_beat + length == beats, 0, next_beat + length)
        with m.If(issue):
            m.d.sync += [
                self.ar.arvalid.eq(1),
                self.ar.araddr.eq(self.base + next_beat * store.beat_bytes),
                self.ar.arlen.eq(length - 1),
                next_beat.eq(following_beat),
            ]
        with m.If(issued):
            # the next burst: a burst ends at a boundary or the frame's end, so next_beat is
            # aligned here and the burst is a full one unless it is the frame's last block
            last_block = (beats - 1) // store.burst_beats * store.burst_beats
            following = Mux(next_beat == last_block, beats - last_block, store.burst_beats)
            m.d.sync += [length.eq(following),
                         need.eq(need + following * per_beat)]
        if self._style == "dp16kd":
            # `length` - 1 beside it, for `reserved`'s sums
            length_less = Signal(range(store.burst_beats), init=burst_length(first_beat) - 1)
            with m.If(issued):
                m.d.sync += length_less.eq(Mux(next_beat == last_block, beats - last_block - 1,
                                               store.burst_beats - 1))
        m.d.sync += in_flight.eq(in_flight + (self.ar.arvalid & self.ar.arready) - rlast_seen)

        if self._style == "memory":
            # ---- the head beat: a register after the FIFO's block RAM (whose read is slow
            # to come out), refilled in the cycle it is popped -------------------------------
            head = Signal(store.data_bits)
            head_valid = Signal()
            pop = Signal()                           # the head beat leaves
            refill = ~head_valid | pop
            m.d.comb += fifo.r_en.eq(refill)
            with m.If(refill):
                m.d.sync += [head.eq(fifo.r_data), head_valid.eq(fifo.r_rdy)]
        else:
            pop = Signal()                           # the head beat leaves
            head, head_valid, head_valid_next = dp16kd_beat_queue(m, store, depth, self.r, pop,
                                                                  self._dp16kd)

        # ---- take side: unpack the head beat, drop stale beats --------------------------
        # one word per beat: offset stays 0 (one bit, not a zero-width vector)
        offset = Signal(range(max(per_beat, 2)), init=first_skip)
        stale = Signal(range(depth + 1))             # beats to drop after a restart
        # stale == 0, a register kept with it: the gate's `available` (and through it the
        # pipeline's input handshake) follows no comparison
        fresh = Signal(init=1)
        taken = Signal(count_bits)                   # words taken since reset
        m.d.comb += [
            self.available.eq(head_valid & fresh),
            self.word.as_value().eq(
                from_slots(store, head.word_select(offset, store.word_bits))),
        ]
        with m.If(self.take):
            m.d.sync += taken.eq(taken + 1)
        restart_need = (burst_length(restart_beat) * per_beat - restart_skip + ahead - pixels)
        if self._style == "dp16kd":
            # the restart's loads in the cycle after it (no take there: `ready` is low; no
            # issue: `settling`), the restart's word and any burst issued with it counted
            # in `taken` and `reserved` by then; the issue chooses last in `reserved`
            m.d.sync += restarting.eq(self.take & self.restart)
            restart_load = restarting
            dropped, none_dropped = reserved, reserved == 0
            # the burst at restart_beat: words taken (the restart's counted) … on
            need_after = taken + restart_need % modulus
        else:
            restart_load = self.take & self.restart
            requested = reserved + Mux(issue, length, 0)
            dropped = requested                      # a burst issued now is stale
            none_dropped = dropped == 0
            # the burst at restart_beat: words taken + 1 … on, from the restart's skip
            need_after = taken + (1 + restart_need) % modulus
        with m.If(restart_load):
            m.d.sync += [
                stale.eq(dropped),
                fresh.eq(none_dropped),
                offset.eq(restart_skip),
                next_beat.eq(restart_beat),
                length.eq(burst_length(restart_beat)),
                need.eq(need_after),
            ]
        with m.Elif(~fresh):
            m.d.comb += pop.eq(head_valid)
            with m.If(pop):
                m.d.sync += [stale.eq(stale - 1), fresh.eq(stale == 1)]
        with m.Elif(self.take):
            last = offset == per_beat - 1
            m.d.comb += pop.eq(last)
            m.d.sync += offset.eq(Mux(last, 0, offset + 1))
        if self._style == "dp16kd":
            # the four sums from registers, the issue and the pop choosing last
            with m.If(restart_load):
                m.d.sync += length_less.eq(burst_length(restart_beat) - 1)
            m.d.sync += reserved.eq(Mux(issue, Mux(pop, reserved + length_less, reserved + length),
                                        Mux(pop, reserved - 1, reserved)))
        else:
            m.d.sync += reserved.eq(requested - pop)
        if self._style == "dp16kd":
            # no word until the restart's loads are done
            with m.If(self.take & self.restart):
                m.d.sync += fresh.eq(0)
            # `available`'s next value for the gate's `ready` register (the updates of
            # `head_valid` and `fresh` above), low in the cycle after a restart (its loads
            # come then)
            fresh_next = Mux(restarting, none_dropped,
                             ~(self.take & self.restart) & (fresh | (head_valid & (stale == 1))))
            m.d.comb += self.available_next.eq(head_valid_next & fresh_next)
        return m
