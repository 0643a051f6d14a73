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
from dptbd.hw.dp16kd import DP16KD_MAX_DEPTH
from dptbd.hw.staged_histogram import request_and_read, staged_histogram

__all__ = ["HISTOGRAM_STYLES", "Histogram"]

#: ``Histogram(style=…)`` (and ``DPCore(histogram_style=…)``).
HISTOGRAM_STYLES = ("memory", "dp16kd")


class Histogram(wiring.Component):
    """Histogram memory with a five-stage increment pipeline and a read-and-clear scan.

    One memory of ``2**b`` words of ``bin_count_bits``, one synchronous, non-transparent
    read port and one write port. An increment request is registered first, so the read
    address comes from registers. Every read, an increment's or the scan's, is issued in a
    cycle r, its word registered in r+1 and used in r+2, where its new count is formed and
    registered; the memory is written from those registers in r+3. A bin whose new count
    was formed in r-1, r or r+1 (by an earlier increment or the scan's clearing) and not yet
    written when r read it is taken from the registers that hold the last three counts
    instead (forwarding, decided in r+1 from the registered addresses): no path runs from
    the memory's output into logic, and the memory's write port is driven by registers.

    * **Increment.** ``add_en`` high in cycle c registers bin ``add_bin``, read in c+1; in
      cycle c+3 the count plus one, saturated at ``2**bin_count_bits - 1``, is formed (and
      written to the memory in c+4).
      One per cycle, any sequence of bins (back-to-back increments of one bin see each other
      through the forwarding).
    * **Scan.** ``scan_start`` high in cycle c (with no increment issued from c until
      ``scanning`` falls; one issued in c-1 or earlier is counted) reads bins ``2**b - 1``
      down to 0 in cycles c … c+2**b-1; each count appears on ``scan_count`` with
      ``scan_valid`` two cycles after its read, i.e. in cycles c+2 … c+2**b+1 (``scan_bin``
      says which, ``scan_last`` marks bin 0), and that bin's new count 0 is formed in the
      same cycle. After the scan every counter is 0 (the last clearing reaches the memory a
      cycle after ``scanning`` falls; a read before that takes it from the forwarding). An
      increment issued in c-1, whose read the scan's first read displaces, is held and added
      to its bin's count as the scan passes it.

    The memory's power-up contents are 0; after a reset they are whatever they were, so the
    segmenter runs one scan after every reset to clear them.

    Parameters
    ----------
    cfg : DPConfig
        Bins and count width.
    style : {"memory", "dp16kd"}
        ``"memory"`` (default): an :class:`~amaranth.lib.memory.Memory` (block RAM) and a
        register after its read port. ``"dp16kd"``: ECP5 DP16KDs
        (:func:`~dptbd.hw.dp16kd.dp16kd_memory`) whose output register is that register,
        so the read's word leaves a register instead of the array's 5.8 ns clock-to-out,
        and the pipeline of :func:`~dptbd.hw.staged_histogram.staged_histogram` (the word
        registered again, increments of one bin in consecutive reads added as an amount);
        at most 16384 bins. Same cycles; for ECP5 synthesis only (no simulation model).
        Anything else raises ``ValueError``.
    dp16kd : callable or None
        For ``"dp16kd"``: the DP16KD builder (``cell`` of
        :func:`~dptbd.hw.dp16kd.dp16kd_memory`; tests pass a behavioural model).
    held_apart : bool
        ``False`` (default): the held increment is in ``scan_count`` (+1, saturated).
        ``True`` (the ECP5 build, with ``"dp16kd"``): ``scan_count`` is the count without
        it and ``scan_held`` says that the consumer adds one
        (:class:`~dptbd.hw.threshold.ThresholdSearch` ``held_apart``), so no carry chain
        lies between the memory's word and the scan's output; ``scan_count`` is then one bit
        wider and not saturated: ``scan_count + scan_held`` may exceed
        ``2**bin_count_bits - 1`` (up to ``2**(bin_count_bits + 1) - 1``; with ``"dp16kd"``
        the scan's first count right after an increment of its bin is that increment's sum
        without its saturation, so no LUT follows its carry chain), which the threshold
        search cannot tell from the saturated count: both exceed every n.

    Members
    -------
    add_bin : In(range(2**b)), add_en : In(1)
        Increment request.
    scan_start : In(1)
        Start a scan (ignored while one is under way).
    scan_valid, scan_last : Out(1); scan_bin : Out(range(2**b)); scan_count : Out(bin_count_bits)
        The scanned counts, top bin first (with ``held_apart`` ``bin_count_bits + 1`` wide).
    scan_held : Out(1)
        With ``held_apart``: the held increment belongs to this count (add one).
    scan_first : Out(1)
        With ``held_apart``: ``scan_valid`` and ``scan_bin`` the top bin (a register).
    scanning : Out(1)
        A scan is under way (cycles c+1 … c+2**b+1: reads issued or counts still to come out).
    """

    def __init__(self, cfg: DPConfig, *, style: str = "memory", dp16kd=None,
                 held_apart: bool = False):
        if style not in HISTOGRAM_STYLES:
            raise ValueError(f"style must be one of {HISTOGRAM_STYLES}, got {style!r}")
        if style == "dp16kd" and cfg.n_bins > DP16KD_MAX_DEPTH:
            raise ValueError(f"style 'dp16kd' holds at most {DP16KD_MAX_DEPTH} bins, got "
                             f"{cfg.n_bins} (histogram_bits={cfg.histogram_bits}); use 'memory'")
        self._cfg = cfg
        self._style = style
        self._dp16kd = dp16kd
        self._held_apart = held_apart
        super().__init__({
            "add_bin": In(range(cfg.n_bins)),
            "add_en": In(1),
            "scan_start": In(1),
            "scan_valid": Out(1),
            "scan_bin": Out(range(cfg.n_bins)),
            "scan_count": Out(cfg.bin_count_bits + held_apart),
            "scan_last": Out(1),
            "scanning": Out(1),
            **({"scan_held": Out(1), "scan_first": Out(1)} if held_apart else {}),
        })

    def elaborate(self, platform):
        if self._style == "dp16kd":
            return staged_histogram(self, self._cfg, self._dp16kd, self._held_apart)
        m = Module()
        cfg = self._cfg
        top = cfg.n_bins - 1
        full = (1 << cfg.bin_count_bits) - 1

        # The memory's ports as signals; the word read in r is `word_2` in r+2 (below).
        read = _Port(addr=Signal(range(cfg.n_bins)), en=Signal())
        write = _Port(addr=Signal(range(cfg.n_bins)), en=Signal(),
                      data=Signal(cfg.bin_count_bits))

        add_en, add_bin, scan_active, scan_read, held_en, held_bin = request_and_read(
            m, self, cfg.n_bins, read.addr, read.en)

        # ---- cycle r+1: the word comes out of the memory and is registered ---------------
        scan_1 = Signal()
        add_1 = Signal()
        bin_1 = Signal(range(cfg.n_bins))
        m.d.sync += [scan_1.eq(scan_read), add_1.eq(add_en & ~scan_read),
                     bin_1.eq(read.addr)]
        # The results (counts to write) of the last three cycles: `result` is computed in
        # this cycle and written from the `write` registers in the next, then held in
        # `last` and `prev` while the reads that missed them are under way.
        result = _Port(addr=Signal(range(cfg.n_bins)), en=Signal(),
                       data=Signal(cfg.bin_count_bits))
        last_en = Signal()
        last_bin = Signal(range(cfg.n_bins))
        last_data = Signal(cfg.bin_count_bits)
        prev_en = Signal()
        prev_bin = Signal(range(cfg.n_bins))
        prev_data = Signal(cfg.bin_count_bits)
        m.d.sync += [write.en.eq(result.en), write.addr.eq(result.addr),
                     write.data.eq(result.data),
                     last_en.eq(write.en), last_bin.eq(write.addr), last_data.eq(write.data),
                     prev_en.eq(last_en), prev_bin.eq(last_bin), prev_data.eq(last_data)]
        # which result the read of r missed (those computed in r-1, r, r+1, written in r,
        # r+1, r+2), for use in r+2, newest first
        take_write = Signal()                         # computed in r+1
        take_last = Signal()                          # computed in r
        take_prev = Signal()                          # computed in r-1
        forward = Signal()                            # any of the three
        hit_write = result.en & (result.addr == bin_1)
        hit_last = write.en & (write.addr == bin_1)
        hit_prev = last_en & (last_bin == bin_1)
        m.d.sync += [take_write.eq(hit_write), take_last.eq(hit_last), take_prev.eq(hit_prev),
                     forward.eq(hit_write | hit_last | hit_prev)]
        word_2 = self._memory(m, read, write)
        scan_2 = Signal()
        add_2 = Signal()
        bin_2 = Signal(range(cfg.n_bins))
        held_2 = Signal()                             # the scan's count gets the held one
        m.d.sync += [scan_2.eq(scan_1), add_2.eq(add_1),
                     bin_2.eq(bin_1), held_2.eq(scan_1 & held_en & (bin_1 == held_bin))]

        # ---- cycle r+2: the count (forwarded), its scan output or its increment ----------
        # the forwarded count is chosen among registers beside the memory's read, so the
        # memory's word meets one multiplexer
        forwarded = Signal(cfg.bin_count_bits)
        m.d.comb += forwarded.eq(Mux(take_write, write.data, Mux(take_last, last_data, prev_data)))
        count = Signal(cfg.bin_count_bits)
        m.d.comb += count.eq(Mux(forward, forwarded, word_2))
        incremented = Mux(count == full, full, count + 1)
        m.d.comb += [
            self.scan_valid.eq(scan_2),
            self.scan_bin.eq(bin_2),
            self.scan_count.eq(count if self._held_apart else Mux(held_2, incremented, count)),
            self.scan_last.eq(scan_2 & (bin_2 == 0)),
            self.scanning.eq(scan_active | scan_1 | scan_2),
            result.addr.eq(bin_2),
            result.data.eq(Mux(scan_2, 0, incremented)),
            result.en.eq(scan_2 | add_2),
        ]
        if self._held_apart:
            m.d.comb += self.scan_held.eq(held_2)
            # the scan's top bin out now: a register of its own, from the cycle before
            m.d.sync += self.scan_first.eq(scan_1 & (bin_1 == top))
        return m

    def _memory(self, m, read, write):
        """The counters' memory on the ``read`` / ``write`` port signals; returns the word
        read in cycle r as a register in r+2."""
        cfg = self._cfg
        m.submodules.memory = memory = Memory(
            shape=cfg.bin_count_bits, depth=cfg.n_bins, init=[])
        write_port = memory.write_port(domain="sync")
        read_port = memory.read_port(domain="sync")
        word_2 = Signal(cfg.bin_count_bits)
        m.d.comb += [
            read_port.addr.eq(read.addr), read_port.en.eq(read.en),
            write_port.addr.eq(write.addr), write_port.data.eq(write.data),
            write_port.en.eq(write.en),
        ]
        m.d.sync += word_2.eq(read_port.data)
        return word_2


class _Port:
    """A memory port's signals (``addr``, ``en``, ``data``)."""

    def __init__(self, **signals):
        self.__dict__.update(signals)
