"""The segmenter at P = 2 or 4 pixels per clock (``docs/gateware.md``, "P pixels per clock"
and "Segmenter"): ``states`` beats of P states in, the same candidate lists as the P = 1
:class:`~dptbd.hw.segmenter.Segmenter` out.

Three parts. The *beat control* counts beats as :class:`Segmenter` counts words (column
in beats, row, frame k within the segment; settings sampled at a segment's first beat; the
scored frame; busy from a list end until the threshold scan has loaded T): a beat of a row
never straddles two rows and the end flags sit on its last pixel, so every decision of the
P = 1 segmenter falls on a beat's last pixel. The *histogram* is a
:class:`~dptbd.hw.banked_histogram.BankedHistogram` (lane k increments bank k), scanned
into the P = 1 :class:`~dptbd.hw.threshold.ThresholdSearch`: the same counts, so the same
T. The *record funnel* holds one accepted scored beat and hands its selected lanes, in
raster order, one per cycle, to the P = 1 :class:`~dptbd.hw.candidate_emitter.CandidateEmitter`,
followed (on a list's last beat) by lane P-1 with ``end_of_list``; the list's trailer
fields (threshold, primed, aligned, missed) are held with the beat.
"""

from __future__ import annotations

from amaranth.hdl import C, Cat, Module, Mux, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.banked_histogram import BankedHistogram
from dptbd.hw.candidate_emitter import CandidateEmitter
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.segmenter import scan_cycles, segmenter_setting_members
from dptbd.hw.threshold import ThresholdSearch
from dptbd.hw.wide.layouts import wide_state_layout

__all__ = ["SegmenterWide", "segmenter"]


class SegmenterWide(wiring.Component):
    """:class:`~dptbd.hw.segmenter.Segmenter` on beats of P states (P = 2 or 4).

    Lists, trailers and the run-time settings' semantics are the P = 1 segmenter's, bit for
    bit, on the same states (``docs/gateware.md``, "Segmenter"). Timing
    (``docs/gateware.md``, "P pixels per clock"):

    * A beat of a frame that is not scored is accepted in any cycle. A beat of the scored
      frame is accepted once the threshold scan after the last list is done, while the
      funnel is free: empty, or handing out its last lane this cycle and that lane not a
      list's end. The funnel hands out one lane per cycle
      while the emitter has ``space``; so a scored beat with at most one selected pixel
      passes in one cycle, one with j > 1 holds the input for j - 1 more, and a list's
      last beat for one more.
    * Each record is valid on ``candidates`` :attr:`RECORD_LATENCY` = 3 cycles after the
      cycle its lane was handed out (its beat's acceptance for the first lane, no
      back-pressure); the trailer one cycle after the list's last record or end lane.
    * The scan starts in the cycle after a list's last beat is accepted and takes
      :func:`~dptbd.hw.segmenter.scan_cycles` = 2**b + 5 cycles to the next scored
      beat, one more than at P = 1: the banked histogram registers the banks' counts
      before their sum (beats of other frames pass meanwhile).

    ``histogram_style`` is each histogram bank's (:class:`Segmenter`'s option: ``"dp16kd"``
    on ECP5), ``dp16kd`` its DP16KD builder (tests pass a behavioural model); same words,
    same cycles.

    Members as :class:`Segmenter`'s, ``states`` with the beats' layout
    (:func:`~dptbd.hw.wide.layouts.wide_state_layout`, state 0 in the low bits); as there,
    ``segment_frames_one`` (``segment_frames == 1``, a register of the driver latched with
    K) decides whether a segment's first beat is scored, so no comparison lies on the path
    to ``states.ready``.
    """

    #: Cycles from a lane's hand-out (for the first record of a beat: the beat's
    #: acceptance) to its record valid on ``candidates``: the funnel register, the FIFO's 2.
    RECORD_LATENCY = 3

    def __init__(self, cfg: DPConfig, *, fifo_depth: int = 8, histogram_style: str = "memory",
                 dp16kd=None):
        if cfg.pixels_per_clock == 1:
            raise ValueError("SegmenterWide takes pixels_per_clock 2 or 4; at 1 use "
                             "dptbd.hw.segmenter.Segmenter (dptbd.hw.wide.segmenter.segmenter "
                             "picks by P)")
        cfg.require_paper001_datapath("the segmenter at P pixels per clock "
                                      "(dptbd.hw.wide.segmenter)")
        self._cfg = cfg
        self._histogram = BankedHistogram(cfg, style=histogram_style, dp16kd=dp16kd)
        self._emitter = CandidateEmitter(cfg, fifo_depth=fifo_depth)
        super().__init__({
            "states": In(stream.Signature(wide_state_layout(cfg))),
            "candidates": Out(stream.Signature(candidate_layout(cfg))),
            **segmenter_setting_members(cfg),
            "segment_frames_one": In(1, init=cfg.segment_frames == 1),
        })

    @property
    def config(self) -> DPConfig:
        return self._cfg

    @property
    def scan_cycles(self) -> int:
        """:func:`~dptbd.hw.segmenter.scan_cycles` of this configuration: 2**b + 5."""
        return scan_cycles(self._cfg)

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        lanes = cfg.pixels_per_clock
        lane_bits = (lanes - 1).bit_length()
        beats, height = cfg.row_beats, cfg.height

        m.submodules.histogram = hist = self._histogram
        m.submodules.threshold = search = ThresholdSearch(cfg)
        m.submodules.emitter = emitter = self._emitter
        wiring.connect(m, emitter.candidates, wiring.flipped(self.candidates))
        m.d.comb += [
            search.scan_valid.eq(hist.scan_valid),
            search.scan_bin.eq(hist.scan_bin),
            search.scan_count.eq(hist.scan_count),
            search.scan_last.eq(hist.scan_last),
        ]

        # ---- beat control: Segmenter.elaborate's word control, counting beats ------------
        col = Signal(range(beats))
        row = Signal(range(height))
        frame = Signal(range(cfg.k_max))
        k_frames = Signal(range(1, cfg.k_max + 1), init=cfg.segment_frames)
        count = Signal(range(cfg.record_capacity + 1), init=cfg.n_candidates)
        shift = Signal(range(cfg.energy_bits), init=cfg.bin_shift)
        list_count = Signal(range(cfg.record_capacity + 1), init=cfg.n_candidates)
        taking = Signal(init=1)              # the next beat is a segment's aligned first beat
        in_scored = Signal()                 # the next beat, not taking, is in the scored frame
        eff_frames = Signal.like(k_frames)
        eff_count = Signal.like(count)
        eff_shift = Signal.like(shift)
        scored = Signal()
        m.d.comb += [eff_frames.eq(Mux(taking, self.segment_frames, k_frames)),
                     eff_count.eq(Mux(taking, self.candidate_count, count)),
                     eff_shift.eq(Mux(taking, self.histogram_shift, shift)),
                     scored.eq(Mux(taking, self.segment_frames_one, in_scored))]
        frame_end = Signal()                 # the next beat is a frame's last
        last = Signal()
        m.d.comb += last.eq(scored & frame_end)
        busy = Signal(init=1)
        clearing = Signal(init=1)
        scan_request = Signal(init=1)
        missed = Signal()

        beat = self.states.payload
        eos = beat.end_of_segment
        free = Signal()                      # the funnel can take a beat this cycle
        ready = Signal()
        m.d.comb += [ready.eq(~scored | (free & ~busy)), self.states.ready.eq(ready)]
        accept = Signal()
        m.d.comb += accept.eq(self.states.valid & ready)
        ends = Signal()
        m.d.comb += ends.eq(scored & (last | eos))

        with m.If(accept & taking):
            m.d.sync += [k_frames.eq(eff_frames), count.eq(eff_count), shift.eq(eff_shift)]
        with m.If(accept & ends):
            m.d.sync += list_count.eq(eff_count)
        with m.If(accept):
            m.d.sync += [taking.eq(eos), in_scored.eq(scored), frame_end.eq(0)]
            with m.If(eos | last):
                m.d.sync += [col.eq(0), row.eq(0), frame.eq(0), in_scored.eq(k_frames == 1)]
            with m.Elif(frame_end):
                m.d.sync += [col.eq(0), row.eq(0), frame.eq(frame + 1),
                             in_scored.eq(frame + 2 == k_frames)]
            with m.Elif(col == beats - 1):
                m.d.sync += [col.eq(0), row.eq(row + 1)]
            with m.Else():
                m.d.sync += [col.eq(col + 1),
                             frame_end.eq((col == beats - 2) & (row == height - 1))]
        m.d.sync += scan_request.eq(accept & ends)
        with m.If(accept & ends):
            m.d.sync += busy.eq(1)
        with m.Elif(search.done):
            m.d.sync += [busy.eq(0), clearing.eq(0)]
        with m.If(accept & ends):
            m.d.sync += missed.eq(0)
        with m.Elif(accept & ~scored & eos):
            m.d.sync += missed.eq(1)
        m.d.comb += [hist.scan_start.eq(scan_request), search.load.eq(~clearing),
                     search.count.eq(list_count)]

        # ---- per lane: the bin (Segmenter's clamp without a comparator) and selection ----
        b = cfg.histogram_bits
        e_bits = cfg.energy_bits
        above = Signal(e_bits)
        m.d.comb += above.eq(Cat(*[eff_shift <= i - b if i >= b else C(0, 1)
                                   for i in range(e_bits)]))
        # bin >= T as Segmenter computes it: E[s:] >= T at the shift s in use (equal for
        # T <= 2**b - 1; T = 2**b selects nothing), one comparison of each lane's E with the
        # register T per shift, ANDed with s's one-hot bit: no shifter and no multiplexer
        # between a lane's E, or `taking`, and the funnel's `pending`
        shift_hot = Signal(e_bits)                # bit s: eff_shift == s, and T < 2**b
        m.d.comb += shift_hot.eq(Cat(*[(eff_shift == s) & ~search.threshold[b]
                                       for s in range(e_bits)]))
        selected = Signal(lanes)
        for k in range(lanes):
            energy = getattr(beat, f"energy_{k}")
            shifted = Signal(b, name=f"shifted_{k}")
            energy_bin = Signal(range(cfg.n_bins), name=f"energy_bin_{k}")
            m.d.comb += [
                shifted.eq(energy >> eff_shift),
                energy_bin.eq(Mux((energy & above).any(), cfg.n_bins - 1, shifted)),
                hist.add_bin[k].eq(energy_bin),
                selected[k].eq(Cat(*[(energy[s:] >= search.threshold[:b]) & shift_hot[s]
                                     for s in range(e_bits)]).any()),
            ]
        m.d.comb += hist.add_en.eq(Mux(accept & scored, (1 << lanes) - 1, 0))

        # ---- the record funnel: one scored beat, its lanes handed out one per cycle ------
        pending = Signal(lanes)          # lanes still to hand out (lane P-1 on a list end)
        chosen = Signal(lanes)           # of those, the selected ones
        list_end = Signal()              # the beat ends its list
        f_row = Signal.like(row)
        f_col = Signal.like(col)
        energies = [Signal(cfg.energy_bits, name=f"funnel_energy_{k}") for k in range(lanes)]
        directions = [Signal(cfg.direction_bits, name=f"funnel_direction_{k}")
                      for k in range(lanes)]
        f_threshold = Signal(cfg.threshold_bits)
        f_primed = Signal()
        f_aligned = Signal()
        f_missed = Signal()

        lowest = Signal(lanes)           # the lane handed out now: pending's lowest bit
        m.d.comb += lowest.eq(Cat(*[pending[k] & ~pending[:k].any() if k else pending[0]
                                    for k in range(lanes)]))
        lane = Signal(range(lanes))
        for k in reversed(range(lanes)):
            with m.If(lowest[k]):
                m.d.comb += lane.eq(k)
        rest = Signal(lanes)             # pending after this hand-out
        m.d.comb += rest.eq(pending & ~lowest)
        hand_out = Signal()
        m.d.comb += hand_out.eq(pending.any() & emitter.space)
        m.d.comb += free.eq(~pending.any() | (hand_out & ~rest.any() & ~list_end))
        with m.If(hand_out):
            m.d.sync += pending.eq(rest)
        with m.If(accept & scored):
            m.d.sync += [
                pending.eq(selected | Mux(ends, 1 << (lanes - 1), 0)),
                chosen.eq(selected),
                list_end.eq(ends),
                f_row.eq(row),
                f_col.eq(col),
                f_threshold.eq(search.threshold),
                f_primed.eq(search.primed),
                f_aligned.eq(last & eos),
                f_missed.eq(missed),
                *[energies[k].eq(getattr(beat, f"energy_{k}")) for k in range(lanes)],
                *[directions[k].eq(getattr(beat, f"direction_{k}")) for k in range(lanes)],
            ]
        energy_out = Signal(cfg.energy_bits)
        direction_out = Signal(cfg.direction_bits)
        # lane k's fields (a shift, not a case: Yosys writes a P-way case on a one-hot
        # select whose patterns Verilator's lint reports as overlapping)
        m.d.comb += [
            energy_out.eq(Cat(*energies).word_select(lane, cfg.energy_bits)),
            direction_out.eq(Cat(*directions).word_select(lane, cfg.direction_bits)),
        ]
        m.d.comb += [
            emitter.valid.eq(hand_out),
            emitter.selected.eq((chosen & lowest).any()),
            emitter.end_of_list.eq(list_end & ~rest.any()),
            emitter.aligned.eq(f_aligned),
            emitter.missed.eq(f_missed),
            emitter.threshold.eq(f_threshold),
            emitter.primed.eq(f_primed),
            emitter.record.row.eq(f_row),
            emitter.record.col.eq(Cat(lane[:lane_bits], f_col)),
            emitter.record.energy.eq(energy_out),
            emitter.record.direction.eq(direction_out),
        ]
        return m


def segmenter(cfg: DPConfig, **options):
    """The segmenter for ``cfg``: :class:`~dptbd.hw.segmenter.Segmenter` at P = 1,
    :class:`SegmenterWide` at P = 2 or 4; ``options`` are passed on."""
    if cfg.pixels_per_clock == 1:
        from dptbd.hw.segmenter import Segmenter
        return Segmenter(cfg, **options)
    return SegmenterWide(cfg, **options)
