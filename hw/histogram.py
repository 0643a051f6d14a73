"""The segmentation histogram: 2**b saturating counters in one memory (``docs/arithmetic.md``
§6.2), one increment per clock, and a read-and-clear scan from the top bin down (§6.3).

The counters are ``bin_count_bits`` = bitlen(C + 1) wide and saturate at all ones, which is
at least C + 1 >= n + 1 for every run-time n: the threshold scan only tells cumulative
counts <= n from > n, so saturation never changes the threshold (and the memory stays one
iCE40 block RAM wide for any C < 2**16).
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.memory import Memory
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig

__all__ = ["Histogram"]


class Histogram(wiring.Component):
    """Histogram memory with a four-stage increment pipeline and a read-and-clear scan.

    One memory of ``2**b`` words of ``bin_count_bits``, one synchronous, non-transparent
    read port and one write port. An increment request is registered first, so the read
    address comes from registers. Every read, an increment's or the scan's, is issued in a
    cycle r, its word registered in r+1 and used in r+2, where a bin written in r or r+1 (by
    an earlier increment or the scan's clearing) is taken from the two registers that hold
    the last two writes instead (forwarding, decided in r+1 from the registered address):
    no path runs from the memory's output into logic, and the write data come from
    registers through one multiplexer and the increment.

    * **Increment.** ``add_en`` high in cycle c registers bin ``add_bin``, read in c+1; in
      cycle c+3 the count plus one, saturated at ``2**bin_count_bits - 1``, is written back.
      One per cycle, any sequence of bins (back-to-back increments of one bin see each other
      through the forwarding).
    * **Scan.** ``scan_start`` high in cycle c (with no increment issued from c until
      ``scanning`` falls; one issued in c-1 or earlier is counted) reads bins ``2**b - 1``
      down to 0 in cycles c … c+2**b-1; each count appears on ``scan_count`` with
      ``scan_valid`` two cycles after its read, i.e. in cycles c+2 … c+2**b+1 (``scan_bin``
      says which, ``scan_last`` marks bin 0), and that bin is written to 0 in the same cycle.
      After the scan every counter is 0. An increment issued in c-1, whose read the scan's
      first read displaces, is held and added to its bin's count as the scan passes it.

    The memory's power-up contents are 0; after a reset they are whatever they were, so the
    segmenter runs one scan after every reset to clear them.

    Members
    -------
    add_bin : In(range(2**b)), add_en : In(1)
        Increment request.
    scan_start : In(1)
        Start a scan (ignored while one is under way).
    scan_valid, scan_last : Out(1); scan_bin : Out(range(2**b)); scan_count : Out(bin_count_bits)
        The scanned counts, top bin first.
    scanning : Out(1)
        A scan is under way (cycles c+1 … c+2**b+1: reads issued or counts still to come out).
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "add_bin": In(range(cfg.n_bins)),
            "add_en": In(1),
            "scan_start": In(1),
            "scan_valid": Out(1),
            "scan_bin": Out(range(cfg.n_bins)),
            "scan_count": Out(cfg.bin_count_bits),
            "scan_last": Out(1),
            "scanning": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        top = cfg.n_bins - 1
        full = (1 << cfg.bin_count_bits) - 1

        m.submodules.memory = memory = Memory(
            shape=cfg.bin_count_bits, depth=cfg.n_bins, init=[])
        write = memory.write_port(domain="sync")
        read = memory.read_port(domain="sync")

        # ---- cycle r-1: the increment request, registered --------------------------------
        add_en = Signal()
        add_bin = Signal(range(cfg.n_bins))
        m.d.sync += [add_en.eq(self.add_en), add_bin.eq(self.add_bin)]

        # ---- cycle r: the read (the scan's, from the top bin down, or an increment's) ----
        scan_active = Signal()                       # a scan read after the first
        scan_addr = Signal(range(cfg.n_bins))
        with m.If(scan_active):
            m.d.sync += scan_addr.eq(scan_addr - 1)
            with m.If(scan_addr == 0):
                m.d.sync += scan_active.eq(0)
        with m.Elif(self.scan_start):
            m.d.sync += [scan_active.eq(1), scan_addr.eq(top - 1)]
        scan_read = Signal()                          # this cycle's read is the scan's
        m.d.comb += scan_read.eq(scan_active | self.scan_start)
        m.d.comb += [
            read.addr.eq(Mux(scan_active, scan_addr, Mux(self.scan_start, top, add_bin))),
            read.en.eq(scan_read | add_en),
        ]
        # the increment issued in the cycle before scan_start: its read is displaced by the
        # scan's first; it is held and added to its bin's count as the scan passes it
        held_en = Signal()
        held_bin = Signal(range(cfg.n_bins))
        with m.If(self.scan_start & ~scan_active):
            m.d.sync += [held_en.eq(add_en), held_bin.eq(add_bin)]

        # ---- cycle r+1: the word comes out of the memory and is registered ---------------
        scan_1 = Signal()
        add_1 = Signal()
        bin_1 = Signal(range(cfg.n_bins))
        m.d.sync += [scan_1.eq(scan_read), add_1.eq(add_en & ~scan_read),
                     bin_1.eq(read.addr)]
        # the last two writes: the one of this cycle is `last` from the next cycle on
        last_en = Signal()
        last_bin = Signal(range(cfg.n_bins))
        last_data = Signal(cfg.bin_count_bits)
        prev_en = Signal()
        prev_bin = Signal(range(cfg.n_bins))
        prev_data = Signal(cfg.bin_count_bits)
        m.d.sync += [last_en.eq(write.en), last_bin.eq(write.addr), last_data.eq(write.data),
                     prev_en.eq(last_en), prev_bin.eq(last_bin), prev_data.eq(last_data)]
        # which write the read of r missed (r's own or r+1's), for use in r+2
        take_last = Signal()                          # the write of cycle r+1
        take_prev = Signal()                          # the write of cycle r
        m.d.sync += [take_last.eq(write.en & (write.addr == bin_1)),
                     take_prev.eq(last_en & (last_bin == bin_1))]
        word_2 = Signal(cfg.bin_count_bits)
        scan_2 = Signal()
        add_2 = Signal()
        bin_2 = Signal(range(cfg.n_bins))
        held_2 = Signal()                             # the scan's count gets the held one
        m.d.sync += [word_2.eq(read.data), scan_2.eq(scan_1), add_2.eq(add_1),
                     bin_2.eq(bin_1), held_2.eq(scan_1 & held_en & (bin_1 == held_bin))]

        # ---- cycle r+2: the count (forwarded), its scan output or its increment ----------
        count = Signal(cfg.bin_count_bits)
        m.d.comb += count.eq(Mux(take_last, last_data, Mux(take_prev, prev_data, word_2)))
        incremented = Mux(count == full, full, count + 1)
        m.d.comb += [
            self.scan_valid.eq(scan_2),
            self.scan_bin.eq(bin_2),
            self.scan_count.eq(Mux(held_2, incremented, count)),
            self.scan_last.eq(scan_2 & (bin_2 == 0)),
            self.scanning.eq(scan_active | scan_1 | scan_2),
            write.addr.eq(bin_2),
            write.data.eq(Mux(scan_2, 0, incremented)),
            write.en.eq(scan_2 | add_2),
        ]
        return m
