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

__all__ = ["PrefetcherHarness", "prefetcher_invariants", "PREFETCHER_INVARIANTS"]

#: The invariants' names, each a switch of :class:`PrefetcherHarness` (``drop``): without
#: any one of them the induction step fails (``tests/sim/formal/test_runner.py``).
PREFETCHER_INVARIANTS = ("in_flight", "reserved", "next_burst", "shadow")


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
    fifo = pf.sub("fifo")
    head_valid, reserved = pf.signal("head_valid"), pf.signal("reserved")
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
        fifo_invariants(m, fifo, "fifo")
        pending = sum(Mux(i < counts.reads, length + 1, 0)
                      for i, length in enumerate(counts.read_lens[:store.outstanding]))
        held = Mux(ar.arvalid, ar.arlen + 1, 0)
        m.d.comb += [
            Assert(reserved == held + pending - counts.r_beat + fifo.component.level
                   + head_valid, "reserved != beats requested and not popped"),
            Assert(reserved <= fifo.component.depth, "reserved above the FIFO's depth"),
        ]
    if "next_burst" not in drop:
        next_beat, length = pf.signal("next_beat"), pf.signal("length")
        room = Mux(beats - next_beat < bb - (next_beat & (bb - 1)), beats - next_beat,
                   bb - (next_beat & (bb - 1)))
        m.d.comb += Assert(next_beat < beats, "next_beat beyond the frame")
        with m.If(pf.signal("issued")):
            m.d.comb += Assert((next_beat & (bb - 1)) == 0, "next_beat not a block's start")
        with m.Else():
            m.d.comb += Assert(length == room, "length != the next burst's beats")


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
    named in ``drop`` (:data:`PREFETCHER_INVARIANTS`).
    """

    def __init__(self, store: AxiStoreConfig | None = None, drop: tuple = ()):
        super().__init__()
        self.store = store or tiny_store()
        unknown = sorted(set(drop) - set(PREFETCHER_INVARIANTS))
        if unknown:
            raise ValueError(f"unknown prefetcher invariant(s) {', '.join(unknown)}; the "
                             f"invariants are {', '.join(PREFETCHER_INVARIANTS)}")
        self.drop = tuple(drop)

    def check(self, m, past):
        from dptbd.hw.axi_store.prefetcher import AxiReadPrefetcher

        store = self.store
        pf = Elaborated(AxiReadPrefetcher(store))
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
