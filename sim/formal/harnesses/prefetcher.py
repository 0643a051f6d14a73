"""The harness of the state store's read prefetcher alone (:class:`PrefetcherHarness`) and
the invariants that make its AXI4 read rules k-inductive (:func:`prefetcher_invariants`):
what :class:`~dptbd.hw.axi_store.prefetcher.AxiReadPrefetcher`'s counters, next burst and
beat FIFO mean in terms of the harness's shadow counts of the read channels
(:class:`~dptbd.sim.formal.harnesses.axi_store.ReadCounts`).
"""

from __future__ import annotations

from amaranth.hdl import Assert, Assume, Cover, Mux

from dptbd.config import AxiStoreConfig
from dptbd.sim.formal.harness import Elaborated, Harness
from dptbd.sim.formal.harnesses.axi_store import ReadCounts, read_rules, tiny_store
from dptbd.sim.formal.harnesses.write_behind import fifo_invariants

__all__ = ["PrefetcherHarness", "prefetcher_invariants", "PREFETCHER_INVARIANTS",
           "RING_INVARIANTS"]

#: The invariants' names, each a switch of :class:`PrefetcherHarness` (``drop``): without
#: any one of them the induction step fails (``tests/sim/formal/test_runner.py``).
PREFETCHER_INVARIANTS = ("in_flight", "reserved", "next_burst", "shadow")
#: Those of the ECP5 build's prefetcher (``PrefetcherHarness(style="dp16kd")``): its beat
#: FIFO is the DP16KD ring and the flip-flop queue (``ring``, ``queue``: their counts,
#: pointers and flag registers), its issue tests and restart loads registers (``restart``).
RING_INVARIANTS = PREFETCHER_INVARIANTS + ("ring", "queue", "restart")


def prefetcher_invariants(m, store: AxiStoreConfig, pf: Elaborated, ar, counts: ReadCounts,
                          drop: tuple = ()) -> None:
    """Assert what :class:`~dptbd.hw.axi_store.prefetcher.AxiReadPrefetcher`'s state means
    (``pf``, elaborated; ``ar`` its AR channel):

    - ``in_flight`` (AR accepted, ``RLAST`` not yet) = the harness's reads in flight, which
      with the AR held are at most ``outstanding``;
    - ``reserved`` (beats requested and not popped) = the held AR's beats + the beats of the
      bursts in flight not yet received + the beat FIFO's level + the head beat, at most
      the FIFO's depth; the FIFO's pointers agree with its level;
    - the next burst (``next_beat``, ``length``) lies within one aligned burst and the frame
      and is as long as that allows, except in the cycle after an issue (``issued``), when
      ``next_beat`` is already the next block's start and ``length`` is brought up to date;
    - the harness's own shadow queue: each burst in flight shorter than ``burst_beats``, the
      head's beats received fewer than its length, none with no burst in flight.
    """
    bb, beats = store.burst_beats, store.frame_beats
    ring = "available_next" in pf.component.signature.members     # style="dp16kd"
    head_valid, reserved = pf.signal("head_valid"), pf.signal("reserved")
    if ring:
        buffered, depth = _ring_invariants(m, store, pf, drop), pf.component.fifo_depth
    else:
        fifo = pf.sub("fifo")
        buffered, depth = [fifo.component.level, head_valid], fifo.component.depth
    if "in_flight" not in drop:
        m.d.comb += [Assert(pf.signal("in_flight") == counts.reads,
                            "in_flight != reads in flight"),
                     Assert(counts.reads + ar.arvalid <= store.outstanding,
                            "reads in flight + the AR held above outstanding")]
    if "shadow" not in drop:
        for i, length in enumerate(counts.read_lens[:store.outstanding]):
            with m.If(i < counts.reads):
                m.d.comb += Assert(length < bb, f"read {i} in flight longer than a burst")
        with m.If(counts.reads == 0):
            m.d.comb += Assert(counts.r_beat == 0, "beats received with no read in flight")
        with m.Else():
            m.d.comb += Assert(counts.r_beat <= counts.read_lens[0],
                               "beats received beyond the head burst's length")
    if "reserved" not in drop:
        if not ring:
            fifo_invariants(m, fifo, "fifo")
        pending = sum(Mux(i < counts.reads, length + 1, 0)
                      for i, length in enumerate(counts.read_lens[:store.outstanding]))
        held = Mux(ar.arvalid, ar.arlen + 1, 0)
        total = held + pending - counts.r_beat
        for beats_held in buffered:             # the beats buffered, each count in turn
            total = total + beats_held
        m.d.comb += [
            Assert(reserved == total, "reserved != beats requested and not popped"),
            Assert(reserved <= depth, "reserved above the FIFO's depth"),
        ]
    if "next_burst" not in drop:
        next_beat, length = pf.signal("next_beat"), pf.signal("length")
        room = Mux(beats - next_beat < bb - (next_beat & (bb - 1)), beats - next_beat,
                   bb - (next_beat & (bb - 1)))
        m.d.comb += Assert(next_beat < beats, "next_beat beyond the frame")
        with m.If(pf.signal("issued")):
            m.d.comb += Assert((next_beat & (bb - 1)) == 0, "next_beat not a block's start")
        if ring:
            # a burst issued in a restart's cycle is not `issued` (it is stale), and the
            # restart's loads in the next cycle set next_beat and length anew
            with m.Elif(~pf.signal("restarting")):
                m.d.comb += Assert(length == room, "length != the next burst's beats")
        else:
            with m.Else():
                m.d.comb += Assert(length == room, "length != the next burst's beats")


def _ring_invariants(m, store: AxiStoreConfig, pf: Elaborated, drop: tuple):
    """The ECP5 prefetcher's beat FIFO (:func:`~dptbd.hw.axi_store.beat_queue.dp16kd_beat_queue`)
    and registered issue and restart (:func:`prefetcher_invariants`); returns the counts of
    the beats it buffers (the ring's, the array's read register's, the output register's,
    the queue's).

    - ``ring``: the ring's count within its depth, its write pointer its read pointer plus
      the count, "not empty" and "not full" the count's;
    - ``queue``: the queue's level within its beats, its pointers apart by the level, the
      head beat "level not 0", and the credit plus the beats on their way through the two
      registers plus the level its beats, "credit left" the credit's;
    - ``restart``: ``fresh`` is "no stale beat" but in the cycle of a restart's loads,
      ``length_less`` is ``length`` - 1, and the issue's next beat (a register of the
      cycle before) is that after ``next_beat``'s burst whenever a burst may issue.
    """
    from dptbd.hw.axi_store.beat_queue import SKID_BEATS

    def s(name):
        return pf.signal(name)

    depth = pf.component.fifo_depth
    stored, level = s("stored"), s("level")
    ahead, out = s("ahead_valid"), s("out_valid")
    if "ring" not in drop:
        write_ptr, read_ptr = s("write_ptr"), s("read_ptr")
        wrapped = Mux(read_ptr + stored >= depth, read_ptr + stored - depth, read_ptr + stored)
        m.d.comb += [
            Assert((stored <= depth) & (write_ptr < depth) & (read_ptr < depth)
                   & (write_ptr == wrapped), "ring: pointers disagree with the count"),
            Assert(s("any_stored") == (stored != 0), "ring: not empty != count != 0"),
            Assert(s("not_full") == (stored != depth), "ring: not full != count != depth"),
        ]
    if "queue" not in drop:
        produce, consume = s("produce"), s("consume")
        m.d.comb += [
            Assert((level <= SKID_BEATS) & (produce == (consume + level)[:len(produce)]),
                   "queue: pointers disagree with the level"),
            Assert(s("head_valid") == (level != 0), "queue: head beat != level != 0"),
            Assert(s("credit") + ahead + out + level == SKID_BEATS,
                   "queue: credit + beats on their way + level != its beats"),
            Assert(s("any_credit") == (s("credit") != 0), "queue: credit left != credit != 0"),
        ]
    if "restart" not in drop:
        bb, beats = store.burst_beats, store.frame_beats
        next_beat, length = s("next_beat"), s("length")
        last_block_start = (beats - 1) // bb * bb
        with m.If(~s("restarting")):
            m.d.comb += Assert(s("fresh") == (s("stale") == 0), "fresh != no stale beat")
        m.d.comb += Assert(s("length_less") + 1 == length, "length_less != length - 1")
        with m.If(~s("settling") & ~pf.component.ar.arvalid):
            m.d.comb += Assert(s("following_beat") == Mux(next_beat >= last_block_start, 0,
                                                          next_beat + length),
                               "following_beat != the beat after the next burst")
    return [stored, ahead, out, level]


class PrefetcherHarness(Harness):
    """:class:`~dptbd.hw.axi_store.prefetcher.AxiReadPrefetcher` of
    :func:`~dptbd.sim.formal.harnesses.axi_store.tiny_store` alone: ``written`` free in every
    cycle (any order of the reads after the writes), words taken only while ``available``,
    ``restart`` free (it counts only with ``take``), any ``base`` aligned to the burst size;
    the subordinate as in :class:`~dptbd.sim.formal.harnesses.axi_store.AxiStoreHarness`
    (a read beat only for an accepted AR burst, ``RLAST`` on exactly its last beat, R held
    with a stable payload until taken, any ``RRESP``, any latency).

    Asserted: the AR rules of ``AxiStoreHarness`` (held valid, stable payload, INCR of full
    beats, aligned, no 4 KB crossing, ``ARLEN`` < ``burst_beats``), at most ``outstanding``
    reads in flight, every read beat taken in the cycle it is offered, no AR in the first
    cycle after a reset; and the invariants of :func:`prefetcher_invariants`, less those
    named in ``drop`` (:data:`PREFETCHER_INVARIANTS`). ``style="dp16kd"``: the ECP5
    build's prefetcher, its DP16KDs the behavioural model
    (:class:`~dptbd.sim.dp16kd_model.DP16KDModel`), the invariants :data:`RING_INVARIANTS`;
    also asserted: ``available`` is ``available_next`` of the cycle before, but after a
    restart (a take with ``restart``), when it is low.
    """

    def __init__(self, store: AxiStoreConfig | None = None, drop: tuple = (),
                 style: str = "memory"):
        super().__init__()
        self.store = store or tiny_store()
        self.style = style
        names = RING_INVARIANTS if style == "dp16kd" else PREFETCHER_INVARIANTS
        unknown = sorted(set(drop) - set(names))
        if unknown:
            raise ValueError(f"unknown prefetcher invariant(s) {', '.join(unknown)}; the "
                             f"invariants are {', '.join(names)}")
        self.drop = tuple(drop)

    def check(self, m, past):
        from dptbd.hw.axi_store.prefetcher import AxiReadPrefetcher

        store = self.store
        from dptbd.sim.dp16kd_model import DP16KDModel

        pf = Elaborated(AxiReadPrefetcher(store, style=self.style,
                                          dp16kd=DP16KDModel if self.style == "dp16kd" else None))
        m.submodules.dut = pf.fragment
        dut = pf.component
        self.free_inputs(m, dut, "dut")
        ar, r = dut.ar, dut.r
        m.d.comb += [Assume(dut.base[:(store.burst_bytes - 1).bit_length()] == 0)]
        with m.If(dut.take):
            m.d.comb += Assume(dut.available)
        counts = read_rules(m, past, store, ar, r)
        with m.If(r.rvalid):
            m.d.comb += Assert(r.rready, "R: a requested beat not taken at once")
        with m.If(past.rst):
            m.d.comb += Assert(~ar.arvalid, "a valid in the first cycle after reset")
        if self.style == "dp16kd":
            restarted = past(dut.take & dut.restart, "past_restart")
            predicted = past(dut.available_next, "past_available")
            with m.If(~past.rst):
                m.d.comb += Assert(dut.available == (predicted & ~restarted),
                                   "available != available_next a cycle earlier")
        prefetcher_invariants(m, store, pf, ar, counts, self.drop)
        end = ar.araddr[:12] + (ar.arlen + 1) * store.beat_bytes
        stale = pf.signal("stale")
        m.d.comb += [
            Cover(ar.arvalid & ar.arready & (ar.arlen == store.burst_beats - 1) & (end == 4096)),
            Cover(ar.arvalid & ~ar.arready & (counts.reads != 0)),
            Cover(counts.reads == store.outstanding),
            Cover(dut.error),
            Cover(dut.take & dut.restart & (counts.reads != 0)),
            Cover((stale != 0) & r.rvalid),                         # a stale beat received
            Cover(ar.arvalid & ar.arready & (ar.arlen == 0)),        # the frame's last beat
        ]
