"""The segmenter: from the DP pipeline's ``states`` stream to a candidate point list per
segment (paper 001 §2, last paragraph; ``docs/arithmetic.md`` §6, ``docs/gateware.md``
"Segmenter").

Design choice (§6.1): the threshold of segment s comes from the histogram of segment s - 1,
so the records stream out while segment s's accumulated image passes by — no second pass
over the state store, no frame buffer, no stall for K >= 2 — at the price of a threshold one
segment stale (a count near n, not exactly <= n: capped at C) and an empty first list after
reset.
"""

from __future__ import annotations

from amaranth.hdl import C, Cat, Module, Mux, Signal
from amaranth.lib import stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.candidate_emitter import CandidateEmitter
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.histogram import Histogram
from dptbd.hw.layouts import state_layout
from dptbd.hw.threshold import ThresholdSearch

__all__ = ["CONTROL_STYLES", "Segmenter", "scan_cycles", "segmenter_setting_members"]

#: ``Segmenter(control_style=…)`` (and ``DPCore(control_style=…)``, which carries it to every
#: top): the control logic, ``"registered"`` the ECP5 build's (flags and enables from
#: registers of their own; same words, same cycles).
CONTROL_STYLES = ("generic", "registered")


def segmenter_setting_members(cfg: DPConfig) -> dict:
    """The run-time settings K, n, s as input members, reset values the build values."""
    return {
        "segment_frames": In(range(1, cfg.k_max + 1), init=cfg.segment_frames),
        "candidate_count": In(range(cfg.record_capacity + 1), init=cfg.n_candidates),
        "histogram_shift": In(range(cfg.energy_bits), init=cfg.bin_shift),
    }


def scan_cycles(cfg: DPConfig) -> int:
    """Cycles from accepting a list's last pixel (beat) to the next scored one at the earliest:
    2**b bins plus 4, plus log2 P, the merge's registers (``docs/gateware.md`` "Segmenter")."""
    return cfg.n_bins + 4 + (cfg.pixels_per_clock - 1).bit_length()


class Segmenter(wiring.Component):
    """Histogram threshold segmentation of the accumulated images on a ``states`` stream.

    The segmenter counts the words of ``states`` itself: column, row and frame k within the
    segment, from reset, realigned to (0, 0, k = 0) after every word with
    ``end_of_segment``. Frame k = K - 1 is *scored*: each of its pixels is histogrammed
    (bin ``min(E >> s, 2**b - 1)``) and, if its bin is >= the threshold T, emitted as a
    record (at most C per list). The list ends at the counters' last pixel of the scored
    frame, or earlier at an ``end_of_segment`` inside it; then the trailer follows and the
    histogram is scanned for the next list's T and cleared. Words of the next scored frame
    wait for the scan (``states.ready`` low, :func:`scan_cycles` = 2**b + 4 cycles from the
    list's last word); words of other frames pass meanwhile, so with K >= 2 and
    W*H*(K-1) >= 2**b + 4 the segmenter never stalls.

    Run-time settings (``docs/gateware.md``, "Run-time settings"): the inputs
    ``segment_frames`` (K), ``candidate_count`` (n) and ``histogram_shift`` (s) are sampled
    when the first word of a segment is accepted, the first word after reset or after an
    ``end_of_segment``, and hold for that segment: K decides its scored frame, s bins its
    scored frame, and n thresholds its histogram in the scan after its list, i.e. makes the
    *next* list's T. A segment the counters start after a scored frame's last pixel
    without ``end_of_segment`` (misaligned after a resync) keeps the settings it has.

    Parameters
    ----------
    cfg : DPConfig
        Frame size, K, widths and the segmentation parameters (n, C, b, s).
    fifo_depth : int
        Entries of the output FIFO (:class:`~dptbd.hw.candidate_emitter.CandidateEmitter`).
    histogram_style : {"memory", "dp16kd"}
        The histogram's memory (:class:`~dptbd.hw.histogram.Histogram`'s ``style``); same
        cycles.
    control_style : {"generic", "registered"}
        The segmenter's control logic (:data:`CONTROL_STYLES`), same words,
        same cycles. ``"registered"`` (ECP5): the histogram's held increment passed to the
        threshold search apart from its count (both blocks' ``held_apart``), the emitter's
        cap a register (:class:`~dptbd.hw.candidate_emitter.CandidateEmitter`
        ``registered_cap``), the list's end and missed end that set ``busy`` and
        ``missed`` as flat products of registers instead of terms of the shared ``accept``,
        ``states.ready`` from registers computed a cycle ahead (two copies: the port's and
        the segmenter's own accept), the selection bits ORed in pairs before cycle B, and
        the histogram's bin from one shifter per source of the shift (the settings port,
        the register), chosen after them.
    dp16kd : callable or None
        For ``"dp16kd"``: the DP16KD builder (:class:`~dptbd.hw.histogram.Histogram`'s
        ``dp16kd``; tests pass a behavioural model).

    Members
    -------
    states : In(stream.Signature(state_layout(cfg)))
        The DP pipeline's output. ``states.ready`` depends on registers and, at a segment's
        first word, on ``segment_frames_one``.
    segment_frames : In(range(1, K_max + 1), init=K)
    candidate_count : In(range(C + 1), init=n)
    histogram_shift : In(range(B_E), init=s)
        Run-time settings of the segment whose first word (after reset or an
        ``end_of_segment``) is accepted. Taken as they are: a value outside its range
        (K = 0, K > K_max, n > C) is the driver's to clamp, as
        :class:`~dptbd.hw.dp_segmenter_top.DPSegmenter`'s settings registers do.
    segment_frames_one : In(1, init=(K == 1))
        ``segment_frames == 1``, given by the driver with ``segment_frames`` (a register in
        :class:`~dptbd.hw.dp_segmenter_top.DPSegmenter`, computed when the setting is
        latched): it decides whether a segment's first word is scored, so the comparison
        stays off the path to ``states.ready``.
    candidates : Out(stream.Signature(candidate_layout(cfg)))
        Records (raster order) and one trailer per list.
    """

    #: Cycles from accepting a state word to its record being valid on ``candidates``
    #: (no back-pressure): stage B writes the FIFO, which takes 2 cycles to its output.
    RECORD_LATENCY = 3

    def __init__(self, cfg: DPConfig, *, fifo_depth: int = 8, histogram_style: str = "memory",
                 control_style: str = "generic", dp16kd=None):
        if control_style not in CONTROL_STYLES:
            raise ValueError(f"control_style must be one of {CONTROL_STYLES}, "
                             f"got {control_style!r}")
        self._cfg = cfg
        self._histogram_style = histogram_style
        self._registered = control_style == "registered"
        self._dp16kd = dp16kd
        self._emitter = CandidateEmitter(cfg, fifo_depth=fifo_depth,
                                         registered_cap=self._registered,
                                         staged_fifo=self._registered)
        super().__init__({
            "states": In(stream.Signature(state_layout(cfg))),
            "candidates": Out(stream.Signature(candidate_layout(cfg))),
            **segmenter_setting_members(cfg),
            "segment_frames_one": In(1, init=cfg.segment_frames == 1),
        })

    @property
    def config(self) -> DPConfig:
        return self._cfg

    @property
    def scan_cycles(self) -> int:
        """:func:`scan_cycles` of this configuration: 2**b + 4."""
        return scan_cycles(self._cfg)

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        width, height = cfg.width, cfg.height

        ecp5 = self._registered                        # the ECP5 structure (docstring)
        m.submodules.histogram = hist = Histogram(cfg, style=self._histogram_style,
                                                  dp16kd=self._dp16kd, held_apart=ecp5)
        m.submodules.threshold = search = ThresholdSearch(cfg, held_apart=ecp5)
        m.submodules.emitter = emitter = self._emitter
        wiring.connect(m, emitter.candidates, wiring.flipped(self.candidates))
        m.d.comb += [
            search.scan_valid.eq(hist.scan_valid),
            search.scan_bin.eq(hist.scan_bin),
            search.scan_count.eq(hist.scan_count),
            search.scan_last.eq(hist.scan_last),
        ]
        if ecp5:
            m.d.comb += [search.scan_held.eq(hist.scan_held),
                         search.scan_first.eq(hist.scan_first)]

        # ---- position of the next word ---------------------------------------------------
        col = Signal(range(width))
        row = Signal(range(height))
        frame = Signal(range(cfg.k_max))
        # ---- run-time settings: sampled at a segment's first word -----------------------
        k_frames = Signal(range(1, cfg.k_max + 1), init=cfg.segment_frames)
        count = Signal(range(cfg.record_capacity + 1), init=cfg.n_candidates)
        shift = Signal(range(cfg.energy_bits), init=cfg.bin_shift)
        list_count = Signal(range(cfg.record_capacity + 1), init=cfg.n_candidates)
        # Registered flags keep the K comparison off the ready/accept path:
        # `aligned_start` (the next word is a segment's first word that the segmenter knows
        # to be one: the first after reset or an end_of_segment; these are the only starts
        # that take the settings ports, so `taking` is this flag) and `in_scored` (the next
        # word, not taking, is in the scored frame). Taking, K = 1 scores the frame. A start
        # the counters reach alone (misaligned after a resync) keeps the settings.
        # The combinational terms below are signals, each one cell read by all its uses.
        aligned_start = Signal(init=1)           # the last word had end_of_segment / reset
        taking = aligned_start
        in_scored = Signal()
        # The ports are in range: DPSegmenter's settings registers hold clamped values.
        eff_frames = Signal.like(k_frames)
        eff_count = Signal.like(count)
        eff_shift = Signal.like(shift)
        scored = Signal()
        m.d.comb += [eff_frames.eq(Mux(taking, self.segment_frames, k_frames)),
                     eff_count.eq(Mux(taking, self.candidate_count, count)),
                     eff_shift.eq(Mux(taking, self.histogram_shift, shift)),
                     scored.eq(Mux(taking, self.segment_frames_one, in_scored))]
        frame_end = Signal()                     # the next word is a frame's last pixel
        last = Signal()
        m.d.comb += last.eq(scored & frame_end)

        # ---- control: busy from a list end (or reset) until the scan has loaded T -------
        busy = Signal(init=1)           # the histogram is not ready for a scored pixel
        clearing = Signal(init=1)       # the scan under way only clears (after reset)
        scan_request = Signal(init=1)   # start a scan this cycle
        missed = Signal()               # an end_of_segment outside a scored frame

        word = self.states.payload
        if ecp5:
            # the ECP5 build: ready from registers computed a cycle ahead (below), two
            # copies: one drives states.ready (the DP output FIFO's read and its input
            # credit), the other, its registers stored inverted so that synthesis keeps
            # them apart, the segmenter's own accept
            port_ready, load_port = self._ready_from_registers(m, "port", False)
            ready, load_own = self._ready_from_registers(m, "own", True)
            m.d.comb += self.states.ready.eq(port_ready)
        else:
            ready = emitter.space & ~(busy & scored)
            m.d.comb += self.states.ready.eq(ready)
            ready = self.states.ready
        accept = Signal()
        m.d.comb += accept.eq(self.states.valid & ready)
        eos = word.end_of_segment
        ends = Signal()
        m.d.comb += ends.eq(scored & (last | eos))

        # ---- cycle A: histogram read, counters ------------------------------------------
        # min(E >> s, 2**b - 1) without a comparator: any bit of E at or above b + s clamps.
        # The clamp's mask depends on s only, so it is formed beside the barrel shifter
        # (not behind it), keeping the path to the histogram's read address short.
        b = cfg.histogram_bits

        def binned(by, stages=False):
            shifted = Signal(b)
            if stages:
                # the shift as a multiplexer per bit of `by` (no $shr cell, which Yosys's
                # `share` would merge with the other source's into one shifter behind a
                # multiplexer of the two shifts)
                value = word.energy
                for k in range(len(by)):
                    value = Mux(by[k], value >> (1 << k), value)
                m.d.comb += shifted.eq(value)
            else:
                m.d.comb += shifted.eq(word.energy >> by)
            above = Signal(cfg.energy_bits)      # bit i set: E's bit i lies above the bins
            m.d.comb += above.eq(Cat(*[by <= i - b if i >= b else C(0, 1)
                                       for i in range(cfg.energy_bits)]))
            return Mux((word.energy & above).any(), cfg.n_bins - 1, shifted)
        energy_bin = Signal(range(cfg.n_bins))
        if ecp5:
            # the ECP5 build: a shifter per source of s (the settings port, the register),
            # the choice after them, so the port's and `taking`'s paths meet no shifter
            # behind a multiplexer (the port's shifter in stages, so that synthesis does not
            # share the two)
            m.d.comb += energy_bin.eq(Mux(taking, binned(self.histogram_shift, stages=True),
                                          binned(shift)))
        else:
            m.d.comb += energy_bin.eq(binned(eff_shift))
        m.d.comb += [
            hist.add_bin.eq(energy_bin),
            hist.add_en.eq(accept & scored),
            hist.scan_start.eq(scan_request),
            search.load.eq(~clearing),
            search.count.eq(list_count),
        ]
        with m.If(accept & taking):
            m.d.sync += [k_frames.eq(eff_frames), count.eq(eff_count), shift.eq(eff_shift)]
        with m.If(accept & ends):                  # this segment's n thresholds its histogram
            m.d.sync += list_count.eq(eff_count)
        with m.If(accept):
            m.d.sync += [aligned_start.eq(eos), in_scored.eq(scored),
                         frame_end.eq(0)]
            with m.If(eos | last):                 # the segment ends: a new one starts
                m.d.sync += [col.eq(0), row.eq(0), frame.eq(0),
                             in_scored.eq(k_frames == 1)]   # used only if not taking
            with m.Elif(frame_end):                # the end of a frame that was not scored
                m.d.sync += [col.eq(0), row.eq(0), frame.eq(frame + 1),
                             in_scored.eq(frame + 2 == k_frames)]
            with m.Elif(col == width - 1):
                m.d.sync += [col.eq(0), row.eq(row + 1)]
            with m.Else():
                m.d.sync += [col.eq(col + 1),
                             frame_end.eq((col == width - 2) & (row == height - 1))]

        if ecp5:
            # the ECP5 build: the list's end and the missed end as flat products of
            # registers (ready is emitter.space & ~busy for a scored word, emitter.space for
            # another), not behind the shared `accept`
            list_end = Signal()
            missed_end = Signal()
            m.d.comb += [
                list_end.eq(self.states.valid & emitter.space & ~busy & scored
                            & (frame_end | eos)),
                missed_end.eq(self.states.valid & emitter.space & ~scored & eos),
            ]
        else:
            list_end = accept & ends
            missed_end = accept & ~scored & eos
        if ecp5:
            # the next cycle's terms of ready: space & ~busy, space & ~taking & ~in_scored,
            # space & taking (ready = the first | the second | the third & ~one, one the
            # settings port segment_frames_one, a register of the driver): the registers'
            # updates above and below, as values
            eos_or_last = Signal()
            m.d.comb += eos_or_last.eq(eos | last)
            busy_next, taking_next, in_scored_next = Signal(), Signal(), Signal()
            m.d.comb += [
                busy_next.eq(list_end | (busy & ~search.done)),
                taking_next.eq(Mux(accept, eos, aligned_start)),
                in_scored_next.eq(Mux(accept, Mux(eos_or_last, k_frames == 1,
                                                  Mux(frame_end, frame + 2 == k_frames,
                                                      scored)),
                                      in_scored)),
            ]
            space_next = emitter.space_next
            nexts = (space_next & ~busy_next, space_next & ~taking_next & ~in_scored_next,
                     space_next & taking_next)
            m.d.sync += load_port(nexts) + load_own(nexts)
        m.d.sync += scan_request.eq(list_end)
        with m.If(list_end):
            m.d.sync += busy.eq(1)
        with m.Elif(search.done):                            # T is loaded at this edge
            m.d.sync += [busy.eq(0), clearing.eq(0)]
        with m.If(list_end):
            m.d.sync += missed.eq(0)
        with m.Elif(missed_end):
            m.d.sync += missed.eq(1)

        # bin >= T without the bin on the path: for T <= 2**b - 1, min(E >> s, 2**b - 1) >= T
        # is floor(E / 2**s) >= T, i.e. E[s:] >= T, and T = 2**b (bit b) selects nothing.
        # One comparison per shift s, each of the word's E (which may come straight out of
        # the DP output FIFO's RAM) with the register T, ANDed with s's one-hot bit (from
        # registers and the settings port, beside the comparisons) and registered; cycle B
        # ORs the bits. No shifter and no multiplexer lie on the word's path.
        e_bits = cfg.energy_bits
        shift_hot = Signal(e_bits)                # bit s: eff_shift == s, and T < 2**b
        m.d.comb += shift_hot.eq(Cat(*[(eff_shift == s) & ~search.threshold[b]
                                       for s in range(e_bits)]))
        selected = Signal(e_bits)                 # bit s: E[s:] >= T at shift s
        m.d.comb += selected.eq(Cat(*[(word.energy[s:] >= search.threshold[:b]) & shift_hot[s]
                                      for s in range(e_bits)]))

        # ---- cycle B: emit ----------------------------------------------------------------
        valid_b = Signal()
        if ecp5:
            # the ECP5 build: the bits ORed in pairs before the register (each pair one LUT
            # of two comparisons and their shift bits, as one bit alone), so cycle B ORs
            # half as many
            selected = Cat(*[selected[s:s + 2].any() for s in range(0, e_bits, 2)])
        selected_b = Signal(len(selected))
        ends_b = Signal()
        aligned_b = Signal()
        missed_b = Signal()
        m.d.sync += valid_b.eq(accept & scored)
        with m.If(accept):
            m.d.sync += [
                selected_b.eq(selected),
                ends_b.eq(ends),
                aligned_b.eq(last & eos),
                missed_b.eq(missed),
                emitter.record.row.eq(row),
                emitter.record.col.eq(col),
                emitter.record.energy.eq(word.energy),
                emitter.record.direction.eq(word.direction),
            ]
        m.d.comb += [
            emitter.valid.eq(valid_b),
            emitter.selected.eq(selected_b.any()),
            emitter.end_of_list.eq(ends_b),
            emitter.aligned.eq(aligned_b),
            emitter.missed.eq(missed_b),
            emitter.threshold.eq(search.threshold),
            emitter.primed.eq(search.primed),
        ]
        return m

    def _ready_from_registers(self, m, name, inverted):
        """``states.ready`` (registered style) from three registers ``ready_{name}_*``
        (stored inverted if ``inverted``; reset: space low, so ready low), and a function
        giving the statements that load them with their next values (:meth:`elaborate`)."""
        regs = [Signal(init=inverted, name=f"ready_{name}_{t}")
                for t in ("open", "free", "taking")]
        value = [~r if inverted else r for r in regs]
        ready = Signal(name=f"ready_{name}")
        m.d.comb += ready.eq(value[0] | value[1] | (value[2] & ~self.segment_frames_one))
        return ready, lambda nexts: [r.eq(~n if inverted else n) for r, n in zip(regs, nexts)]
