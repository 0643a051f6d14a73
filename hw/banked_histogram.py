"""The segmentation histogram at P pixels per clock: P banks, one increment per bank per
clock, merged at the scan (``docs/gateware.md``, "P pixels per clock").

Each bank is a :class:`~dptbd.hw.histogram.Histogram` (one memory, one increment per clock,
the read-and-clear scan); lane k of a beat increments bank k. The scan reads the P banks in
lockstep, registers their counts, and outputs, per bin, the sum of those registers clamped
at all ones (``2**bin_count_bits - 1``): one cycle later than one bank's scan, so that no
path runs from a bank's read-modify-write through the adders; at P = 4 the two pairs' sums
are registered too, two cycles later (the segmenter's
:func:`~dptbd.hw.segmenter.scan_cycles` is one more at P = 2, two at P = 4). That is
exactly the count one histogram of every increment gives (§6.2): if no bank saturated the
sum is the true count, clamped exactly when the true count reaches all ones; if one did,
both are all ones.
So the threshold scan (§6.3) sees the same counts at every P.
"""

from __future__ import annotations

from amaranth.hdl import Module, Signal, unsigned
from amaranth.lib import wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.adder_tree import adder_tree
from dptbd.hw.histogram import Histogram

__all__ = ["BankedHistogram"]


class BankedHistogram(wiring.Component):
    """P histogram banks, merged at the scan.

    Parameters
    ----------
    cfg : DPConfig
        Bins, counter width and P (``pixels_per_clock``; 1 builds one bank, no adder).
    style : {"memory", "dp16kd"}
        Each bank's :class:`~dptbd.hw.histogram.Histogram` ``style`` (``"dp16kd"``: the
        ECP5 build, the word out of the DP16KD's output register); same counts, same cycles.
    dp16kd : callable or None
        For ``"dp16kd"``: the DP16KD builder (tests pass a behavioural model).
    held_apart : bool
        ``True`` (the ECP5 build): the banks' ``held_apart`` (no carry chain between a
        bank's word and its scan count), their held increments added in the merge's adders
        as carries in (no adder more), but one: that one leaves as ``scan_held`` for the
        threshold search (:class:`~dptbd.hw.threshold.ThresholdSearch` ``held_apart``), with
        ``scan_first`` (a register); ``scan_count`` is then one bit wider, its top bit 0
        (the sum clamped at all ones of ``bin_count_bits``, so ``scan_count + scan_held``
        is at most ``2**bin_count_bits``, above every n as all ones is). ``False``
        (default): the held increments in the counts.

    Members
    -------
    add_bin : In(range(2**b)).array(P), add_en : In(P)
        Lane k's increment request (bit k of ``add_en``); any lanes in any cycle.
    scan_start : In(1)
        Start a scan of every bank (ignored while one is under way), as
        :class:`~dptbd.hw.histogram.Histogram`'s: no increment in flight or issued until
        ``scanning`` falls.
    scan_valid, scan_last : Out(1); scan_bin : Out(range(2**b)); scan_count : Out(bin_count_bits)
        The merged counts, top bin first, one cycle after :class:`Histogram`'s: each bank's
        count is registered, and the sum of the registers is combinational; at P = 4 two
        cycles after, the pairs' sums registered and their sum combinational. (With P = 1,
        the one bank's outputs, with :class:`Histogram`'s timing.)
    scan_held, scan_first : Out(1)
        With ``held_apart``: one held increment to add to ``scan_count``; ``scan_valid``
        and ``scan_bin`` the top bin (a register).
    scanning : Out(1)
        A scan is under way, or its last count still to come out.
    """

    def __init__(self, cfg: DPConfig, *, style: str = "memory", dp16kd=None,
                 held_apart: bool = False):
        self._cfg = cfg
        self._held_apart = held_apart
        self._banks = [Histogram(cfg, style=style, dp16kd=dp16kd, held_apart=held_apart)
                       for _ in range(cfg.pixels_per_clock)]
        lanes = cfg.pixels_per_clock
        super().__init__({
            "add_bin": In(range(cfg.n_bins)).array(lanes),
            "add_en": In(lanes),
            "scan_start": In(1),
            "scan_valid": Out(1),
            "scan_bin": Out(range(cfg.n_bins)),
            "scan_count": Out(cfg.bin_count_bits + held_apart),
            "scan_last": Out(1),
            "scanning": Out(1),
            **({"scan_held": Out(1), "scan_first": Out(1)} if held_apart else {}),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        lanes = cfg.pixels_per_clock
        banks = self._banks
        for lane, bank in enumerate(banks):
            m.submodules[f"bank_{lane}"] = bank
            m.d.comb += [
                bank.add_bin.eq(self.add_bin[lane]),
                bank.add_en.eq(self.add_en[lane]),
                bank.scan_start.eq(self.scan_start),
            ]
        # every bank scans in lockstep: bank 0's scan outputs stand for all of them
        held_apart = self._held_apart
        if lanes == 1:
            m.d.comb += [
                self.scan_valid.eq(banks[0].scan_valid),
                self.scan_bin.eq(banks[0].scan_bin),
                self.scan_last.eq(banks[0].scan_last),
                self.scanning.eq(banks[0].scanning),
                self.scan_count.eq(banks[0].scan_count),
            ]
            if held_apart:
                m.d.comb += [self.scan_held.eq(banks[0].scan_held),
                             self.scan_first.eq(banks[0].scan_first)]
            return m
        # the banks' outputs registered: the merge's adders start from registers
        bits = cfg.bin_count_bits
        valid = Signal()
        last = Signal()
        bin_ = Signal(range(cfg.n_bins))
        counts = [Signal(bits + held_apart, name=f"count_{lane}") for lane in range(lanes)]
        m.d.sync += [valid.eq(banks[0].scan_valid), last.eq(banks[0].scan_last),
                     bin_.eq(banks[0].scan_bin),
                     *[count.eq(bank.scan_count) for count, bank in zip(counts, banks)]]
        helds = ()
        if held_apart:
            helds = [Signal(name=f"held_{lane}") for lane in range(lanes)]
            m.d.sync += [held.eq(bank.scan_held) for held, bank in zip(helds, banks)]
        scanning = banks[0].scanning | valid
        first = banks[0].scan_first if held_apart else None
        if lanes == 4:
            # a second register level at P = 4: the two pairs' sums (banks 0 + 1 and 2 + 3,
            # each with its first held increment as carry in), so that one adder, not two
            # in series, lies between registers; the scan a cycle longer again
            pairs = [Signal(bits + held_apart + 1, name=f"pair_{i}") for i in range(2)]
            m.d.sync += [pair.eq(adder_tree(counts[2 * i:2 * i + 2],
                                            carries=tuple(helds[i:i + 1])))
                         for i, pair in enumerate(pairs)]
            valid_pairs = Signal()
            last_pairs = Signal()
            bin_pairs = Signal.like(bin_)
            m.d.sync += [valid_pairs.eq(valid), last_pairs.eq(last), bin_pairs.eq(bin_)]
            scanning = scanning | valid_pairs
            valid, last, bin_, counts = valid_pairs, last_pairs, bin_pairs, pairs
            if held_apart:
                later = [Signal(name=f"held_{lane}_pairs") for lane in (2, 3)]
                m.d.sync += [held.eq(early) for held, early in zip(later, helds[2:])]
                helds = later
                first_pairs = Signal()
                m.d.sync += first_pairs.eq(first)
                first = first_pairs
        if held_apart:
            m.d.sync += self.scan_first.eq(first)
            m.d.comb += self.scan_held.eq(helds[-1])
        total = Signal(unsigned(bits + held_apart + (lanes - 1).bit_length()))
        # with held_apart every held increment but the last is an adder's carry in
        m.d.comb += total.eq(adder_tree(counts, carries=tuple(helds[:-1])))
        # clamped at all ones: above all ones exactly when a bit above them is set (an OR
        # of those bits, not a comparison with a constant, which Yosys maps to a carry chain
        # on ECP5 after the adders' own)
        over = total[bits:].any()
        m.d.comb += [
            self.scan_valid.eq(valid),
            self.scan_bin.eq(bin_),
            self.scan_last.eq(last),
            self.scanning.eq(scanning),
            self.scan_count.eq(total[:bits] | over.replicate(bits)),
        ]
        return m
