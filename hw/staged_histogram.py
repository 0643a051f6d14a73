"""The ECP5 histogram's read-modify-write (``Histogram(style="dp16kd")``): the DP16KD's word
registered again in the fabric, increments of one bin in consecutive reads accumulated as an
amount, so every carry chain starts at registers beside it and ends one LUT before a
register (``docs/gateware.md``, "Implementation options per FPGA family").

Cycles of a read issued in r (an increment's or the scan's): the DP16KD's output register
holds its word in r+2; in r+2 the count it modifies is chosen and registered as a *base*
with an *amount* (the increments to add: 0 for the scan's clearing); in r+3 the new count
``min(base + amount, 2**bin_count_bits - 1)`` is formed (one carry chain from the two
registers, its carry out the saturation) and registered; the memory is written from that
register in r+4. So the read of r misses the counts formed in r-1 … r+2:

* the one formed in r+2 (the read of r-1, same bin): the base is kept and the amount
  grows by one (a saturating counter), so no count formed in one cycle is needed in the
  next;
* those formed in r-1, r, r+1 (the reads of r-4, r-3, r-2) are in registers in r+2 and
  are forwarded into the base, newest first, decided in r+1 from the registered addresses.

The scan's counts leave in r+2 as in the other style: the forwarded count or the word, or,
for the scan's first read right after an increment of its bin (the read of r-1), that
increment's new count formed in r+2 (``held_apart``: its sum, not saturated).
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal

from dptbd.config import DPConfig
from dptbd.hw.dp16kd import dp16kd_memory

__all__ = ["request_and_read", "staged_histogram"]


def staged_histogram(histogram, cfg: DPConfig, dp16kd, held_apart: bool) -> Module:
    """The module of ``histogram`` (a :class:`~dptbd.hw.histogram.Histogram` of style
    ``"dp16kd"``, same members and cycles) with this module's pipeline."""
    m = Module()
    top = cfg.n_bins - 1
    bits = cfg.bin_count_bits
    addr = range(cfg.n_bins)

    read_addr = Signal(addr)
    read_en = Signal()
    add_en, add_bin, scan_active, scan_read, held_en, held_bin = request_and_read(
        m, histogram, cfg.n_bins, read_addr, read_en, data_reset=False)

    # ---- the stages' registers ----------------------------------------------------------
    # the bins and counts are data, read only under their stage's flag (which the reset
    # clears): no reset of their own, so the soft reset's restart reaches the flags only
    def data(shape, name):
        return Signal(shape, name=name, reset_less=True)
    scan_1, add_1, bin_1 = Signal(), Signal(), data(addr, "bin_1")                   # r+1
    scan_2, add_2, bin_2 = Signal(), Signal(), data(addr, "bin_2")                   # r+2
    en_3, bin_3 = Signal(), data(addr, "bin_3")                                      # r+3
    base_3, amount_3 = data(bits, "base_3"), data(bits, "amount_3")
    # r+4, r+5, r+6: the write register, then the two counts written before it
    write_en, write_addr, write_data = Signal(), data(addr, "write_addr"), data(bits, "write_data")
    last_en, last_bin, last_data = Signal(), data(addr, "last_bin"), data(bits, "last_data")
    prev_en, prev_bin, prev_data = Signal(), data(addr, "prev_bin"), data(bits, "prev_data")

    # ---- cycle r+1: the array's word goes to the DP16KD's output register -----------------
    m.d.sync += [scan_1.eq(scan_read), add_1.eq(add_en & ~scan_read), bin_1.eq(read_addr),
                 scan_2.eq(scan_1), add_2.eq(add_1), bin_2.eq(bin_1)]
    # which later count the read of r missed, for use in r+2, newest first: the read of
    # r-1 (in stage 2 now), of r-2 (stage 3), r-3 (the write register), r-4 (`last`)
    hits = [(scan_2 | add_2) & (bin_2 == bin_1), en_3 & (bin_3 == bin_1),
            write_en & (write_addr == bin_1), last_en & (last_bin == bin_1)]
    same, take_write, take_last, take_prev = (Signal(name=n) for n in (
        "same", "take_write", "take_last", "take_prev"))
    m.d.sync += [same.eq(hits[0]), take_write.eq(hits[1]), take_last.eq(hits[2]),
                 take_prev.eq(hits[3])]
    # each hit a register of one comparison; their ORs are formed from those registers
    forward = Signal()                               # one of the three older counts
    take_word = Signal()                             # an increment of the memory's word
    m.d.comb += [forward.eq(take_write | take_last | take_prev),
                 take_word.eq(add_2 & ~(same | forward))]
    held_2 = Signal()
    m.d.sync += held_2.eq(scan_1 & held_en & (bin_1 == held_bin))
    word_2 = dp16kd_memory(m, "memory", width=bits, depth=cfg.n_bins, read_addr=read_addr,
                           read_en=read_en, out_en=1, write_addr=write_addr,
                           write_data=write_data, write_en=write_en, cell=dp16kd)

    # ---- cycle r+3: the new count of the read of r-1 (its base and amount registered) -----
    total = Signal(bits + 1)
    new_count = Signal(bits)                         # saturated: the carry out in every bit
    m.d.comb += [total.eq(base_3 + amount_3),
                 new_count.eq(total[:bits] | total[bits].replicate(bits))]
    m.d.sync += [write_en.eq(en_3), write_addr.eq(bin_3), write_data.eq(new_count),
                 last_en.eq(write_en), last_bin.eq(write_addr), last_data.eq(write_data),
                 prev_en.eq(last_en), prev_bin.eq(last_bin), prev_data.eq(last_data)]

    # ---- cycle r+2: the base and amount of the read of r ---------------------------------
    forwarded = Signal(bits)
    m.d.comb += forwarded.eq(Mux(take_write, write_data, Mux(take_last, last_data, prev_data)))
    amount_plus = Signal(bits + 1)
    m.d.comb += amount_plus.eq(amount_3 + 1)
    # the memory's word meets one multiplexer; the rest is chosen from registers
    other = Mux(scan_2, 0, Mux(same, base_3, forwarded))
    m.d.sync += [
        en_3.eq(scan_2 | add_2), bin_3.eq(bin_2),
        base_3.eq(Mux(take_word, word_2, other)),
        amount_3.eq(Mux(scan_2, 0, Mux(same, amount_plus[:bits]
                                       | amount_plus[bits].replicate(bits), 1))),
    ]
    # the scan's count: the read of r-1's new count (formed now), a forwarded one, the word;
    # held apart, the new count is the sum itself (unsaturated, a bit wider: the search's
    # fit tells no difference), so its carry chain ends at the choice
    other = Mux(forward, forwarded, word_2)
    count = Signal(bits + held_apart)
    m.d.comb += count.eq(Mux(same, total if held_apart else new_count, other))
    if held_apart:
        scan_count = count
        m.d.comb += histogram.scan_held.eq(held_2)
        m.d.sync += histogram.scan_first.eq(scan_1 & (bin_1 == top))
    else:
        plus_one = Signal(bits + 1)
        m.d.comb += plus_one.eq(count + 1)
        scan_count = Mux(held_2, plus_one[:bits] | plus_one[bits].replicate(bits), count)
    m.d.comb += [
        histogram.scan_valid.eq(scan_2),
        histogram.scan_bin.eq(bin_2),
        histogram.scan_count.eq(scan_count),
        histogram.scan_last.eq(scan_2 & (bin_2 == 0)),
        histogram.scanning.eq(scan_active | scan_1 | scan_2),
    ]
    return m


def request_and_read(m, histogram, n_bins: int, read_addr, read_en, *,
                     data_reset: bool = True):
    """Cycles r-1 and r of both styles of :class:`~dptbd.hw.histogram.Histogram`: the
    increment request registered; the read in r on ``read_addr`` / ``read_en`` (the scan's,
    from the top bin down, or an increment's); the increment whose read the scan's first
    read displaces, held to be added as the scan passes its bin. Returns ``add_en``,
    ``add_bin`` (the registered request), ``scan_active`` (a scan read after the first),
    ``scan_read`` (this cycle's read is the scan's), ``held_en``, ``held_bin``.
    ``data_reset=False``: the bin registers (``add_bin``, the scan's address,
    ``held_bin``), read only under their flags, are not reset."""
    top = n_bins - 1
    # ---- cycle r-1: the increment request, registered ------------------------------------
    add_en = Signal()
    add_bin = Signal(range(n_bins), reset_less=not data_reset)
    m.d.sync += [add_en.eq(histogram.add_en), add_bin.eq(histogram.add_bin)]

    # ---- cycle r: the read (the scan's, from the top bin down, or an increment's) --------
    scan_active = Signal()                           # a scan read after the first
    scan_addr = Signal(range(n_bins), reset_less=not data_reset)
    with m.If(scan_active):
        m.d.sync += scan_addr.eq(scan_addr - 1)
        with m.If(scan_addr == 0):
            m.d.sync += scan_active.eq(0)
    with m.Elif(histogram.scan_start):
        m.d.sync += [scan_active.eq(1), scan_addr.eq(top - 1)]
    scan_read = Signal()                             # this cycle's read is the scan's
    m.d.comb += scan_read.eq(scan_active | histogram.scan_start)
    m.d.comb += [
        read_addr.eq(Mux(scan_active, scan_addr, Mux(histogram.scan_start, top, add_bin))),
        read_en.eq(scan_read | add_en),
    ]
    # the increment issued in the cycle before scan_start: its read is displaced by the
    # scan's first; it is held and added to its bin's count as the scan passes it
    held_en = Signal()
    held_bin = Signal(range(n_bins), reset_less=not data_reset)
    with m.If(histogram.scan_start & ~scan_active):
        m.d.sync += [held_en.eq(add_en), held_bin.eq(add_bin)]
    return add_en, add_bin, scan_active, scan_read, held_en, held_bin
