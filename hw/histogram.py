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
    """Histogram memory with an increment pipeline and a read-and-clear scan.

    One memory of ``2**b`` words of ``bin_count_bits``, one synchronous read port
    (transparent for the write port, so back-to-back increments of one bin see each other)
    and one write port.

    * **Increment.** ``add_en`` high in cycle c reads bin ``add_bin``; in cycle c+1 the count
      plus one, saturated at ``2**bin_count_bits - 1``, is written back. One per cycle, any
      sequence of bins.
    * **Scan.** ``scan_start`` high in cycle c (with no increment in flight and none issued
      until ``scanning`` falls) reads bins ``2**b - 1`` down to 0 in cycles c+1 … c+2**b;
      each count appears on ``scan_count`` with ``scan_valid`` one cycle after its read
      (``scan_bin`` says which, ``scan_last`` marks bin 0), and that bin is written to 0 in
      the same cycle. After the scan every counter is 0.

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
        A scan is under way (reads issued or counts still to come out).
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
        read = memory.read_port(domain="sync", transparent_for=(write,))

        # ---- scan: one read per cycle from the top bin down ---------------------------
        scan_active = Signal()                       # a read is issued this cycle
        scan_addr = Signal(range(cfg.n_bins))
        with m.If(scan_active):
            m.d.sync += scan_addr.eq(scan_addr - 1)
            with m.If(scan_addr == 0):
                m.d.sync += scan_active.eq(0)
        with m.Elif(self.scan_start):
            m.d.sync += [scan_active.eq(1), scan_addr.eq(top)]
        scan_valid = Signal()
        scan_bin = Signal(range(cfg.n_bins))
        m.d.sync += [scan_valid.eq(scan_active), scan_bin.eq(scan_addr)]
        m.d.comb += [
            self.scan_valid.eq(scan_valid),
            self.scan_bin.eq(scan_bin),
            self.scan_count.eq(read.data),
            self.scan_last.eq(scan_valid & (scan_bin == 0)),
            self.scanning.eq(scan_active | scan_valid),
        ]

        # ---- increment: read in cycle c, write back in c+1 ----------------------------
        add_valid = Signal()
        add_bin = Signal(range(cfg.n_bins))
        m.d.sync += [add_valid.eq(self.add_en), add_bin.eq(self.add_bin)]
        incremented = Mux(read.data == full, full, read.data + 1)

        m.d.comb += [
            read.addr.eq(Mux(scan_active, scan_addr, self.add_bin)),
            read.en.eq(scan_active | self.add_en),
            write.addr.eq(Mux(scan_valid, scan_bin, add_bin)),
            write.data.eq(Mux(scan_valid, 0, incremented)),
            write.en.eq(scan_valid | add_valid),
        ]
        return m
