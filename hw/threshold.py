"""The threshold search: the smallest bin T whose count from the top does not exceed n
(``docs/arithmetic.md`` §6.3), from a histogram scan that delivers the top bin first.
"""

from __future__ import annotations

from amaranth.hdl import C, Cat, Module, Mux, Signal
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.controller import clamped

__all__ = ["ThresholdSearch"]


class ThresholdSearch(wiring.Component):
    """Consume a top-down histogram scan; hold the threshold bin T it yields.

    Equivalent to the model's saturating ``cum = min(cum + h[a], n + 1)`` with ``T = a``
    while ``cum <= n`` (``dptbd.model.segmentation.threshold_bin``), computed as a budget
    ``remaining = n - cum`` that each count h[a] must fit: ``h[a] <= remaining`` is one
    borrow chain, so the loop ``remaining -> remaining - h`` is one carry chain deep. After
    the first count that does not fit, nothing changes until the end of the scan (the
    cumulative count only grows). T = 2**b when already the top bin holds more than n
    pixels.

    The scan inputs are registered first (one cycle), so the block RAM's output does not
    feed the carry chain directly. At the scanned bin 0 (``scan_last``) the result is
    loaded into ``threshold`` if ``load`` is high, and the search restarts.

    The run-time n (``count``, clamped to [0, C]) is sampled when the scan's top bin
    (``scan_valid`` with ``scan_bin = 2**b - 1``) arrives at the inputs, and holds for that
    scan.

    Parameters
    ----------
    cfg : DPConfig
        Bins, n, C.
    held_apart : bool
        ``True`` (the ECP5 build, :class:`~dptbd.hw.histogram.Histogram` ``held_apart``):
        the member ``scan_held`` adds one to ``scan_count`` (the histogram's held
        increment), as the borrow in of the one subtraction ``remaining - count - held``
        (an extra low bit ``0 - held``) whose sign is the fit; ``remaining`` is kept in
        two's complement and set to -1 by the first count that does not fit, so no
        ``stopped`` flag enters the loop (one carry chain and one OR); the scan's start is
        the histogram's register ``scan_first``; the best bin is set and loaded on its
        own, and T at bin 0 is the best so far unless bin 0 fits; the data registers
        (``remaining``, the best bin, the scan's registered bin, count and held) are not
        reset (every scan after a reset sets them before they are read), so a (soft)
        reset reaches only the flags. ``False`` (default): no ``scan_held``, no
        ``scan_first``.

    Members
    -------
    scan_valid, scan_last : In(1); scan_bin : In(range(2**b)); scan_count : In(bin_count_bits)
        (With ``held_apart`` ``bin_count_bits + 1`` wide: an unsaturated count.)
        From :class:`~dptbd.hw.histogram.Histogram`.
    count : In(range(C + 1), init=n)
        Run-time n, sampled with the scan's top bin.
    scan_held : In(1)
        With ``held_apart``: ``scan_count`` plus one.
    scan_first : In(1)
        With ``held_apart``: ``scan_valid`` and ``scan_bin`` the top bin (the histogram's
        register, so no comparison of ``scan_bin`` starts the search).
    load : In(1)
        Sampled in the ``done`` cycle: 1 loads the result into ``threshold`` and sets
        ``primed``; 0 discards it (the clearing scan after reset).
    threshold : Out(b + 1)
        T, a register; 2**b (select nothing) after reset.
    primed : Out(1)
        A threshold has been loaded since reset.
    done : Out(1)
        High in the cycle at whose end ``threshold`` is loaded: one cycle after the
        ``scan_last`` input.
    """

    def __init__(self, cfg: DPConfig, *, held_apart: bool = False):
        self._cfg = cfg
        self._held_apart = held_apart
        super().__init__({
            "scan_valid": In(1),
            "scan_bin": In(range(cfg.n_bins)),
            "scan_count": In(cfg.bin_count_bits + held_apart),
            "scan_last": In(1),
            "count": In(range(cfg.record_capacity + 1), init=cfg.n_candidates),
            "load": In(1),
            "threshold": Out(cfg.threshold_bits, init=cfg.n_bins),
            "primed": Out(1),
            "done": Out(1),
            **({"scan_held": In(1), "scan_first": In(1)} if held_apart else {}),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        n = clamped(self.count, 0, cfg.record_capacity)

        valid = Signal()
        last = Signal()
        # with held_apart the bin and count (read only under `valid`) are not reset
        bin_ = Signal(range(cfg.n_bins), reset_less=self._held_apart)
        count = Signal(cfg.bin_count_bits + self._held_apart, reset_less=self._held_apart)
        m.d.sync += [valid.eq(self.scan_valid), last.eq(self.scan_valid & self.scan_last),
                     bin_.eq(self.scan_bin), count.eq(self.scan_count)]

        if self._held_apart:
            self._search_held_apart(m, n, valid, last, bin_, count)
            return m
        remaining = Signal(range(cfg.record_capacity + 1), init=cfg.n_candidates)  # n - cum
        stopped = Signal()                            # cum has exceeded n
        best = Signal(cfg.threshold_bits, init=cfg.n_bins)
        fits = (count <= remaining) & ~stopped
        best_next = Mux(fits, bin_, best)
        m.d.comb += self.done.eq(valid & last)
        with m.If(valid):
            with m.If(last):
                m.d.sync += [remaining.eq(n), stopped.eq(0), best.eq(cfg.n_bins)]
                with m.If(self.load):
                    m.d.sync += [self.threshold.eq(best_next), self.primed.eq(1)]
            with m.Elif(fits):
                m.d.sync += [remaining.eq(remaining - count), best.eq(bin_)]
            with m.Else():
                m.d.sync += stopped.eq(1)
        with m.If(self.scan_valid & (self.scan_bin == cfg.n_bins - 1)):   # a scan begins
            m.d.sync += [remaining.eq(n), stopped.eq(0), best.eq(cfg.n_bins)]
        return m

    def _search_held_apart(self, m, n, valid, last, bin_, count):
        """The search with ``scan_held`` (``held_apart``): ``remaining`` is a two's-complement
        register, -1 once a count did not fit (no ``stopped`` flag on the loop); each cycle
        remaining - count - held (``held`` the borrow in) is loaded, or -1 where it is
        negative, and its sign bit is the fit."""
        cfg = self._cfg
        held = Signal(reset_less=True)
        m.d.sync += held.eq(self.scan_held)
        # -1 <= remaining <= n <= C < 2**(width - 2) and count + held <= 2**(bin_count_bits
        # + 1) - 1 <= 2**(width - 1) - 1 (count unsaturated, bin_count_bits + 1 wide):
        # remaining - count - held lies in [-2**(width - 1), 2**(width - 1))
        width = max(cfg.record_capacity.bit_length(), cfg.bin_count_bits) + 2
        # remaining and best are set by every scan's start (`scan_first`) before they are
        # read, and every scan after a reset starts so: neither is reset, so the soft
        # reset's restart does not reach them
        remaining = Signal(width, init=cfg.n_candidates, reset_less=True)  # n - cum, or -1
        count_wide = Signal(width)
        difference = Signal(width)
        # one subtraction, held its borrow in through an extra low bit 0 - held (no second
        # adder; a subtraction, whose inversion of the count is the carry chain's own, so
        # no logic between the count and held registers and the chain)
        m.d.comb += [count_wide.eq(count),
                     difference.eq((Cat(C(0, 1), remaining) - Cat(held, count_wide))[1:])]
        fits = ~difference[-1]
        best = Signal(cfg.threshold_bits, init=cfg.n_bins, reset_less=True)
        m.d.comb += self.done.eq(valid & last)
        with m.If(valid):
            with m.If(last):
                m.d.sync += remaining.eq(n)
                with m.If(self.load):
                    # the last count is bin 0's: T is 0 if it fits, else the best so far
                    m.d.sync += [self.threshold.eq(best & (~fits).replicate(len(best))),
                                 self.primed.eq(1)]
            with m.Else():
                m.d.sync += remaining.eq(difference | difference[-1].replicate(width))
        with m.If(self.scan_first):                                        # a scan begins
            m.d.sync += remaining.eq(n)
        # best on its own: set by a scan's start and end, loaded with a fitting bin (`last`
        # is registered with the scan's valid: no `valid` in its set)
        with m.If(self.scan_first | last):
            m.d.sync += best.eq(cfg.n_bins)
        with m.Elif(valid & fits):
            m.d.sync += best.eq(bin_)
