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
T. The *selection stage* holds one accepted scored beat with its lanes' comparisons with
T; the *record funnel* takes it from there and hands its selected lanes, in raster order,
one per cycle, to the P = 1 :class:`~dptbd.hw.candidate_emitter.CandidateEmitter`,
followed (on a list's last beat) by lane P-1 with ``end_of_list``; the list's trailer
fields (threshold, primed, aligned, missed) are held with the beat.
"""

from __future__ import annotations

from amaranth.hdl import C, Cat, Module, Mux, Signal, unsigned
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.banked_histogram import BankedHistogram
from dptbd.hw.candidate_emitter import CandidateEmitter
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.segmenter import CONTROL_STYLES, scan_cycles, segmenter_setting_members
from dptbd.hw.threshold import ThresholdSearch
from dptbd.hw.wide.layouts import beat_word_layout, wide_state_layout

__all__ = ["SegmenterWide", "held_beat_layout", "segmenter"]


def held_beat_layout(cfg: DPConfig) -> data.StructLayout:
    """A scored beat as :class:`SegmenterWide`'s selection stage and record funnel hold it:
    its P states (state 0 first), its position (``row``, ``col`` in beats) and its list's
    trailer fields (``threshold``, ``primed``, ``aligned``, ``missed``; ``end``: the beat
    ends its list)."""
    return data.StructLayout({
        "states": beat_word_layout(cfg),
        "row": range(cfg.height),
        "col": range(cfg.row_beats),
        "threshold": unsigned(cfg.threshold_bits),
        "primed": unsigned(1),
        "aligned": unsigned(1),
        "missed": unsigned(1),
        "end": unsigned(1),
    })


class SegmenterWide(wiring.Component):
    """:class:`~dptbd.hw.segmenter.Segmenter` on beats of P states (P = 2 or 4).

    Lists, trailers and the run-time settings' semantics are the P = 1 segmenter's, bit for
    bit, on the same states (``docs/gateware.md``, "Segmenter"). Timing
    (``docs/gateware.md``, "P pixels per clock"):

    * A beat of a frame that is not scored is accepted in any cycle. A beat of the scored
      frame is accepted once the threshold scan after the last list is done, while the
      selection stage is free: empty, or its beat moving to the funnel this cycle. The
      stage's beat moves, at the earliest in the cycle after its acceptance, when the
      funnel is free: empty, or handing out its last lane this cycle and that lane not a
      list's end. The funnel hands out one lane per cycle, from the cycle after it took
      the beat, while the emitter has ``space``; so scored beats with at most one selected
      pixel pass one per cycle, one with j > 1 holds the beat behind it j - 1 cycles more,
      and a list's last beat one more.
    * A record is valid on ``candidates`` 2 cycles after its lane's hand-out, the first of
      a beat :attr:`RECORD_LATENCY` = 4 cycles after the beat's acceptance (no stalls; one
      more than at P = 1: the selection stage); the trailer 3 cycles after the end lane's
      hand-out.
    * The scan starts in the cycle after a list's last beat is accepted and takes
      :func:`~dptbd.hw.segmenter.scan_cycles` cycles to the next scored beat: 2**b + 5
      at P = 2, one more than at P = 1 (the banked histogram registers the banks' counts
      before their sum), 2**b + 6 at P = 4 (and the pairs' sums); beats of other frames
      pass meanwhile.

    ``histogram_style`` is each histogram bank's (:class:`Segmenter`'s option: ``"dp16kd"``
    on ECP5), ``dp16kd`` its DP16KD builder (tests pass a behavioural model);
    ``control_style="registered"`` (ECP5) passes the banks' held increments apart from
    their counts (:class:`~dptbd.hw.banked_histogram.BankedHistogram` and
    :class:`~dptbd.hw.threshold.ThresholdSearch` ``held_apart``) and builds the emitter's
    cap and FIFO as :class:`Segmenter`'s ECP5 build does
    (:class:`~dptbd.hw.candidate_emitter.CandidateEmitter` ``registered_cap``,
    ``staged_fifo``). Same words, same cycles.

    Members as :class:`Segmenter`'s, ``states`` with the beats' layout
    (:func:`~dptbd.hw.wide.layouts.wide_state_layout`, state 0 in the low bits); as there,
    ``segment_frames_one`` (``segment_frames == 1``, a register of the driver latched with
    K) decides whether a segment's first beat is scored, so no comparison lies on the path
    to ``states.ready``.
    """

    #: Cycles from a beat's acceptance to its first record valid on ``candidates`` (no
    #: stalls): the selection stage, the funnel, the FIFO's 2.
    RECORD_LATENCY = 4

    def __init__(self, cfg: DPConfig, *, fifo_depth: int = 8, histogram_style: str = "memory",
                 control_style: str = "generic", dp16kd=None):
        if cfg.pixels_per_clock == 1:
            raise ValueError("SegmenterWide takes pixels_per_clock 2 or 4; at 1 use "
                             "dptbd.hw.segmenter.Segmenter (dptbd.hw.wide.segmenter.segmenter "
                             "picks by P)")
        cfg.require_paper001_datapath("the segmenter at P pixels per clock "
                                      "(dptbd.hw.wide.segmenter)")
        if control_style not in CONTROL_STYLES:
            raise ValueError(f"control_style must be one of {CONTROL_STYLES}, "
                             f"got {control_style!r}")
        self._cfg = cfg
        self._registered = control_style == "registered"
        self._histogram = BankedHistogram(cfg, style=histogram_style, dp16kd=dp16kd,
                                          held_apart=self._registered)
        self._emitter = CandidateEmitter(cfg, fifo_depth=fifo_depth,
                                         registered_cap=self._registered,
                                         staged_fifo=self._registered)
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
        """:func:`~dptbd.hw.segmenter.scan_cycles` of this configuration: 2**b + 5 at
        P = 2, 2**b + 6 at P = 4."""
        return scan_cycles(self._cfg)

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        lanes = cfg.pixels_per_clock
        lane_bits = (lanes - 1).bit_length()
        beats, height = cfg.row_beats, cfg.height

        m.submodules.histogram = hist = self._histogram
        m.submodules.threshold = search = ThresholdSearch(cfg, held_apart=self._registered)
        m.submodules.emitter = emitter = self._emitter
        wiring.connect(m, emitter.candidates, wiring.flipped(self.candidates))
        m.d.comb += [
            search.scan_valid.eq(hist.scan_valid),
            search.scan_bin.eq(hist.scan_bin),
            search.scan_count.eq(hist.scan_count),
            search.scan_last.eq(hist.scan_last),
        ]
        if self._registered:
            m.d.comb += [search.scan_held.eq(hist.scan_held),
                         search.scan_first.eq(hist.scan_first)]

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
        stage_free = Signal()                # the selection stage can take a beat this cycle
        ready = Signal()
        m.d.comb += [ready.eq(~scored | (stage_free & ~busy)), self.states.ready.eq(ready)]
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

        def bits_above(by, name):
            """Bit i set: a lane's E's bit i lies above the bins at shift ``by``."""
            above = Signal(e_bits, name=name)
            m.d.comb += above.eq(Cat(*[by <= i - b if i >= b else C(0, 1)
                                       for i in range(e_bits)]))
            return above

        def binned(energy, by, above, stages=False):
            """min(E >> by, 2**b - 1); ``stages``: the shift as a multiplexer per bit of
            ``by`` (no $shr cell, which Yosys's `share` would merge with another)."""
            if stages:
                value = energy
                for i in range(len(by)):
                    value = Mux(by[i], value >> (1 << i), value)
            else:
                value = energy >> by
            return Mux((energy & above).any(), cfg.n_bins - 1, value[:b])

        if self._registered:
            # the ECP5 build, as Segmenter's: a shifter per source of s (the settings port,
            # the register), the choice after them
            above_port = bits_above(self.histogram_shift, "above_port")
            above_reg = bits_above(shift, "above_register")
        else:
            above = bits_above(eff_shift, "above")
        # bin >= T as Segmenter computes it: E[s:] >= T at the shift s in use (equal for
        # T <= 2**b - 1; T = 2**b selects nothing), one comparison of each lane's E with the
        # register T per shift, ANDed with s's one-hot bit and ORed in pairs (each pair one
        # LUT of two comparisons and their shift bits), registered with the beat in the
        # selection stage; the funnel ORs the pairs when it takes the beat. No shifter, no
        # multiplexer and no OR tree between a lane's E, or `taking`, and a register.
        shift_hot = Signal(e_bits)                # bit s: eff_shift == s, and T < 2**b
        m.d.comb += shift_hot.eq(Cat(*[(eff_shift == s) & ~search.threshold[b]
                                       for s in range(e_bits)]))
        selected_pairs = []
        for k in range(lanes):
            energy = getattr(beat, f"energy_{k}")
            energy_bin = Signal(range(cfg.n_bins), name=f"energy_bin_{k}")
            if self._registered:
                m.d.comb += energy_bin.eq(Mux(
                    taking, binned(energy, self.histogram_shift, above_port, stages=True),
                    binned(energy, shift, above_reg)))
            else:
                m.d.comb += energy_bin.eq(binned(energy, eff_shift, above))
            m.d.comb += hist.add_bin[k].eq(energy_bin)
            at_shift = [(energy[s:] >= search.threshold[:b]) & shift_hot[s]
                        for s in range(e_bits)]
            pairs = Signal((e_bits + 1) // 2, name=f"selected_pairs_{k}")
            m.d.comb += pairs.eq(Cat(*[Cat(*at_shift[s:s + 2]).any()
                                       for s in range(0, e_bits, 2)]))
            selected_pairs.append(pairs)
        m.d.comb += hist.add_en.eq(Mux(accept & scored, (1 << lanes) - 1, 0))

        # ---- the selection stage and the record funnel ------------------------------------
        # The stage holds one accepted scored beat with its comparisons; the funnel takes it
        # when free and hands its selected lanes out one per cycle (lane P-1 too on a list
        # end). Both hold the beat's fields and its list's trailer fields.
        stage = Signal(held_beat_layout(cfg), name="stage")
        funnel = Signal(held_beat_layout(cfg), name="funnel")
        stage_valid = Signal()
        stage_pairs = Signal(data.ArrayLayout(len(selected_pairs[0]), lanes),
                             name="stage_pairs")
        pending = Signal(lanes)          # lanes still to hand out (lane P-1 on a list end)
        chosen = Signal(lanes)           # of those, the selected ones

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
        free = Signal()                  # the funnel can take the stage's beat this cycle
        m.d.comb += free.eq(~pending.any() | (hand_out & ~rest.any() & ~funnel.end))
        moving = Signal()
        m.d.comb += [moving.eq(stage_valid & free), stage_free.eq(~stage_valid | free)]
        with m.If(hand_out):
            m.d.sync += pending.eq(rest)
        with m.If(moving):
            selected = Cat(*[stage_pairs[k].any() for k in range(lanes)])
            m.d.sync += [
                stage_valid.eq(0),
                pending.eq(selected | Mux(stage.end, 1 << (lanes - 1), 0)),
                chosen.eq(selected),
                funnel.eq(stage),
            ]
        with m.If(accept & scored):
            m.d.sync += [
                stage_valid.eq(1),
                stage_pairs.eq(Cat(*selected_pairs)),
                stage.row.eq(row),
                stage.col.eq(col),
                stage.threshold.eq(search.threshold),
                stage.primed.eq(search.primed),
                stage.aligned.eq(last & eos),
                stage.missed.eq(missed),
                stage.end.eq(ends),
                *[stage.states[k].energy.eq(getattr(beat, f"energy_{k}")) for k in range(lanes)],
                *[stage.states[k].direction.eq(getattr(beat, f"direction_{k}"))
                  for k in range(lanes)],
            ]
        energy_out = Signal(e_bits)
        direction_out = Signal(cfg.direction_bits)
        # lane k's fields (a shift, not a case: Yosys writes a P-way case on a one-hot
        # select whose patterns Verilator's lint reports as overlapping)
        m.d.comb += [
            energy_out.eq(Cat(*[funnel.states[k].energy for k in range(lanes)])
                          .word_select(lane, e_bits)),
            direction_out.eq(Cat(*[funnel.states[k].direction for k in range(lanes)])
                             .word_select(lane, cfg.direction_bits)),
        ]
        m.d.comb += [
            emitter.valid.eq(hand_out),
            emitter.selected.eq((chosen & lowest).any()),
            emitter.end_of_list.eq(funnel.end & ~rest.any()),
            emitter.aligned.eq(funnel.aligned),
            emitter.missed.eq(funnel.missed),
            emitter.threshold.eq(funnel.threshold),
            emitter.primed.eq(funnel.primed),
            emitter.record.row.eq(funnel.row),
            emitter.record.col.eq(Cat(lane[:lane_bits], funnel.col)),
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
