"""The ECP5 beat FIFO of :class:`~dptbd.hw.axi_store.prefetcher.AxiReadPrefetcher`
(``style="dp16kd"``): a ring buffer in DP16KDs read at its own pace into a queue of
:data:`SKID_BEATS` flip-flop beats, whose head is the prefetcher's head beat."""

from __future__ import annotations

from amaranth.hdl import Mux, Signal

from dptbd.hw.dp16kd import dp16kd_memory

__all__ = ["SKID_BEATS", "dp16kd_beat_queue"]

#: Flip-flop beats between the DP16KDs and the head beat with ``style="dp16kd"`` (a power
#: of two: the queue's pointers wrap by themselves).
SKID_BEATS = 4


def dp16kd_beat_queue(m, store, depth: int, r, pop, dp16kd=None):
    """Add the beat FIFO of ``depth`` beats of ``store.data_bits`` to ``m``, written from
    the AXI4 R channel ``r`` (it drives ``r.rready``), its head beat leaving when ``pop``;
    ``dp16kd``: the DP16KD builder (:func:`~dptbd.hw.dp16kd.dp16kd_memory`'s ``cell``).
    Returns the head beat, "a head beat" and that flag's next value."""
    # ---- ECP5: a ring buffer in DP16KDs read at its own pace into a queue of
    # SKID_BEATS flip-flop beats, whose head is the head beat. The array reads when a
    # queue beat is free (``credit``: free queue beats less those on their way through
    # the array's read register and the output register, which always loads): the
    # block RAMs' enables follow registers, never ``take``. A beat popped in cycle t
    # frees a credit in t + 1 and is replaced in t + 4, so four queue beats keep one
    # beat a cycle; the first beat reaches the head a cycle later than without it. ----
    write_ptr = Signal(range(depth))
    read_ptr = Signal(range(depth))
    stored = Signal(range(depth + 1))           # beats written and not yet read ahead
    credit = Signal(range(SKID_BEATS + 1), init=SKID_BEATS)
    ahead_valid = Signal()                      # the array's read register holds a beat
    out_valid = Signal()                        # the output register holds a beat
    # "stored != 0", "credit != 0" and "stored != depth" registers, kept with their
    # counts: the DP16KDs' enables and RREADY follow no comparison
    any_stored = Signal()
    any_credit = Signal(init=1)
    not_full = Signal(init=1)
    fetch = any_stored & any_credit             # the array reads read_ptr
    write = r.rvalid & r.rready
    m.d.comb += r.rready.eq(not_full)
    with m.If(write & ~fetch):
        m.d.sync += [any_stored.eq(1), not_full.eq(stored != depth - 1)]
    with m.Elif(fetch & ~write):
        m.d.sync += [any_stored.eq(stored != 1), not_full.eq(1)]
    with m.If(pop & ~fetch):
        m.d.sync += any_credit.eq(1)
    with m.Elif(fetch & ~pop):
        m.d.sync += any_credit.eq(credit != 1)

    def step(ptr):
        return Mux(ptr == depth - 1, 0, ptr + 1)

    with m.If(write):
        m.d.sync += write_ptr.eq(step(write_ptr))
    with m.If(fetch):
        m.d.sync += read_ptr.eq(step(read_ptr))
    m.d.sync += [stored.eq(stored + write - fetch),
                 ahead_valid.eq(fetch), out_valid.eq(ahead_valid),
                 credit.eq(credit - fetch + pop)]
    out = dp16kd_memory(m, "fifo", width=store.data_bits, depth=depth,
                        read_addr=read_ptr, read_en=fetch, out_en=1,
                        write_addr=write_ptr, write_data=r.rdata, write_en=write,
                        cell=dp16kd)
    # the queue: a write enable per beat, the head an AND-OR of the beats
    beats = [Signal(store.data_bits, name=f"skid_{i}") for i in range(SKID_BEATS)]
    produce = Signal(range(SKID_BEATS))
    consume = Signal(range(SKID_BEATS))
    level = Signal(range(SKID_BEATS + 1))
    with m.If(out_valid):
        m.d.sync += produce.eq(produce + 1)
    for i, beat in enumerate(beats):
        with m.If(out_valid & (produce == i)):
            m.d.sync += beat.eq(out)
    with m.If(pop):
        m.d.sync += consume.eq(consume + 1)
    level_next = Signal(range(SKID_BEATS + 1))
    head_valid = Signal()
    head_valid_next = Signal()
    # level_next != 0, with `pop` (the pipeline's handshake) in the last LUT (a pop
    # needs a head beat: level >= 1)
    m.d.comb += [level_next.eq(level + out_valid - pop),
                 head_valid_next.eq(out_valid | (level >= 2) | ((level == 1) & ~pop))]
    m.d.sync += [level.eq(level_next), head_valid.eq(head_valid_next)]
    head = 0
    for i, beat in enumerate(beats):
        head = head | Mux(consume == i, beat, 0)
    return head, head_valid, head_valid_next
