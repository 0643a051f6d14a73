"""AXI4-Stream video adapters between the AXI top level's ports and the core's streams.

AXI4-Stream video convention (Xilinx UG934): ``tuser[0]`` = start of frame, ``tlast`` = end
of line; ``tdata`` is a whole number of bytes. Here:

- input ``s_axis_video``: ``tdata`` = ``8 * ceil(B_in / 8)`` bits, the pixel in the low
  B_in bits (higher bits ignored), ``tuser[0]`` = start of frame (the pixel layout's
  ``first``), ``tlast`` = end of line (checked by :mod:`dptbd.hw.frame_monitor`, not
  needed by the core);
- output ``m_axis_cand``: ``tdata`` = the candidate word
  (:func:`~dptbd.hw.candidate_layout.candidate_layout`) zero-extended to whole bytes,
  ``tuser[0]`` = first word of a list, ``tlast`` = the trailer (end of list = end of
  segment). A list with no record is one word with both set;
- output ``m_axis_state`` (AXI top level built with ``state_output=True``): one pixel's
  (E, d) per beat in raster order, ``tdata`` = E in bits [B_E-1:0], d in the next B_d bits
  (:func:`~dptbd.hw.layouts.state_word_layout`), zero-extended to whole bytes; ``tuser[0]``
  = start of frame (pixel (0, 0)), ``tuser[1]`` = end of frame, ``tuser[2]`` = end of
  segment, ``tuser[3]`` = cut (a filler word closing a line cut by a soft reset: E = 0,
  d = 0, no other flag), ``tlast`` = end of line (every line W words).
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.layouts import pixel_layout, state_layout, state_word_layout

__all__ = ["byte_padded", "axis_signature", "video_in_signature", "video_tdata_layout", "candidate_out_signature",
           "state_out_signature", "STATE_TUSER", "AxisToPixels", "CandidatesToAxis",
           "StatesToAxis"]

#: ``m_axis_state_tuser`` bits.
STATE_TUSER = {"start_of_frame": 0, "end_of_frame": 1, "end_of_segment": 2, "cut": 3}


def byte_padded(bits: int) -> int:
    """``bits`` rounded up to whole bytes (AXI4-Stream ``tdata`` widths)."""
    return 8 * -(-bits // 8)


def axis_signature(data_bits: int, user_bits: int = 1) -> wiring.Signature:
    """AXI4-Stream as the transmitter sees it: ``tdata``, ``tvalid``, ``tready``, ``tuser``,
    ``tlast``."""
    return wiring.Signature({
        "tdata": Out(data_bits),
        "tvalid": Out(1),
        "tready": In(1),
        "tuser": Out(user_bits),
        "tlast": Out(1),
    })


def video_in_signature(cfg: DPConfig) -> wiring.Signature:
    """``s_axis_video``: one pixel per beat."""
    return axis_signature(byte_padded(cfg.input_bits))


def video_tdata_layout(cfg: DPConfig) -> data.StructLayout:
    """The bits of ``s_axis_video_tdata`` the core reads: the pixel in the low B_in bits
    (start of frame is ``tuser[0]``, not a ``tdata`` bit; the bits above B_in are ignored)."""
    return data.StructLayout({"pixel": cfg.input_bits})


def candidate_out_signature(cfg: DPConfig) -> wiring.Signature:
    """``m_axis_cand``: one record or trailer per beat."""
    return axis_signature(byte_padded(data.Layout.cast(candidate_layout(cfg)).size))


def state_out_signature(cfg: DPConfig) -> wiring.Signature:
    """``m_axis_state``: one pixel's (E, d) per beat, the ``tuser`` bits of
    :data:`STATE_TUSER`."""
    return axis_signature(byte_padded(data.Layout.cast(state_word_layout(cfg)).size),
                          len(STATE_TUSER))


class AxisToPixels(wiring.Component):
    """``s_axis_video`` to the core's ``pixels`` stream (combinational).

    Members
    -------
    video : In(video_in_signature(cfg))
    pixels : Out(stream.Signature(pixel_layout(cfg)))
    accepted : Out(1)
        A beat is transferred in this cycle.
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "video": In(video_in_signature(cfg)),
            "pixels": Out(stream.Signature(pixel_layout(cfg))),
            "accepted": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        video, pixels = self.video, self.pixels
        m.d.comb += [
            pixels.payload.pixel.eq(video.tdata[:self._cfg.input_bits]),
            pixels.payload.first.eq(video.tuser[0]),
            pixels.valid.eq(video.tvalid),
            video.tready.eq(pixels.ready),
            self.accepted.eq(video.tvalid & pixels.ready),
        ]
        return m


class CandidatesToAxis(wiring.Component):
    """The core's ``candidates`` stream to ``m_axis_cand``, and the soft reset's close of an
    open list.

    Without a soft reset the port is the stream itself (combinational), ``tuser[0]`` on a
    list's first word. ``soft_reset`` (a one-cycle request) is served without breaking
    AXI4-Stream, in this order:

    1. a word already offered and not yet taken (``tvalid`` high, ``tready`` low in the
       cycle before) stays offered, unchanged, until it is taken; no new word is offered;
    2. if a list is then open (words of it were sent, not its trailer), the *cut trailer*
       (:func:`~dptbd.hw.candidate_layout.pack_cut_trailer`: ``cut`` = 1, ``count`` = the
       records sent, every other field 0, ``tlast``) is offered until it is taken;
    3. ``restart`` pulses, registered: the caller resets the core (and everything after
       it) in that cycle. It comes in the cycle after the one the list is closed in: the
       request's own cycle when no word is offered and no list is open, the cycle the cut
       trailer is taken, or the cycle after the word of 1. is taken if that word was a
       trailer; never after a cycle with ``hold`` high (another output is not closed yet:
       ``m_axis_state``'s :class:`StatesToAxis`), so it comes after the later of the two.
       In the ``restart`` cycle no word is offered and none is taken from ``candidates``.

    ``busy`` is high from the request to ``restart`` included: the caller holds the input.

    Members
    -------
    candidates : In(stream.Signature(candidate_layout(cfg)))
    cand : Out(candidate_out_signature(cfg))
    soft_reset, hold : In(1)
    busy, restart : Out(1)
    stalled : Out(1)
        ``tvalid`` high and ``tready`` low in this cycle (back-pressure).
    soft_reset_ahead : In(1)
        Only with ``busy_ahead=True``: ``soft_reset`` of the next cycle (the register
        block's ``soft_reset_ahead``); the request (``soft_reset``, or one waiting) is then
        a register loaded from it, so ``soft_reset`` itself is not read (low in the cycle
        after a reset, as the register block's). The core's ``ready`` reads a copy of
        that register of its own (``request_open_core``, inverted), not the one the
        port's pins read.
    busy_next : Out(1)
        Only with ``busy_ahead=True``: ``busy`` of the next cycle (``soft_reset_ahead`` or
        a request now: the request is then still waiting or restarts), so that the caller
        can hold the input from registers of its own.
    """

    def __init__(self, cfg: DPConfig, *, busy_ahead: bool = False):
        self._cfg = cfg
        self._ahead = bool(busy_ahead)
        super().__init__({
            "candidates": In(stream.Signature(candidate_layout(cfg))),
            "cand": Out(candidate_out_signature(cfg)),
            "soft_reset": In(1),
            "hold": In(1),
            "busy": Out(1),
            "restart": Out(1),
            "stalled": Out(1),
            **({"soft_reset_ahead": In(1), "busy_next": Out(1)} if self._ahead else {}),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        src, out = self.candidates, self.cand
        list_start = Signal(init=1)            # the next word is the first of a list
        records = Signal(range(cfg.record_capacity + 1))     # records sent in the open list
        closing = Signal()                     # a soft reset waits for the list's close
        held = Signal()                        # a core word was offered, not taken, last cycle
        if self._ahead:
            # soft_reset | closing from a register of its own, computed a cycle ahead
            # (below): no logic between the register block's pulse and the close
            request = Signal(name="request")
        else:
            request = self.soft_reset | closing
        passing = ~request | held              # the core's word may be offered
        if self._ahead:
            # the request's copy for the core's ready (the FIFO's output register it
            # enables), which the placer can put apart from the port's pins; stored
            # inverted, so that synthesis keeps the two apart
            open_core = Signal(init=1, name="request_open_core")
            passing_core = open_core | held
        else:
            passing_core = passing
        cut = request & ~held & ~list_start    # offer the cut trailer
        # the list is closed: restart in the next cycle (registered, its reset fans out to
        # the core); in that cycle nothing is offered or taken
        close = Signal()
        m.d.comb += close.eq(request & ~held & ~self.hold & (list_start | (cut & out.tready)))
        m.d.sync += self.restart.eq(close)
        offering = ~self.restart
        cut_word = Signal(candidate_layout(cfg))
        m.d.comb += [
            cut_word.body.trailer.count.eq(records),
            cut_word.body.trailer.cut.eq(1),
            cut_word.end_of_list.eq(1),
        ]
        # tdata and tlast are 0 while no word is offered (the FIFO's output register holds X
        # until its first word)
        payload = src.payload.as_value() & src.valid.replicate(len(src.payload.as_value()))
        m.d.comb += [
            out.tdata.eq(Mux(cut, cut_word.as_value(), payload)),
            out.tlast.eq(cut | (src.valid & src.payload.end_of_list)),
            out.tvalid.eq(offering & (cut | (src.valid & passing))),
            out.tuser[0].eq(list_start),
            src.ready.eq(offering & out.tready & passing_core),
            self.stalled.eq(out.tvalid & ~out.tready),
            self.busy.eq(request | self.restart),
        ]
        if self._ahead:
            # closing' | restart' = request: a request not closed now waits, one closed
            # now restarts
            m.d.comb += self.busy_next.eq(self.soft_reset_ahead | request)
            m.d.sync += [request.eq(self.soft_reset_ahead | (request & ~close)),
                         open_core.eq(~(self.soft_reset_ahead | (request & ~close)))]
        m.d.sync += held.eq(offering & src.valid & passing & ~out.tready)
        with m.If(close):
            m.d.sync += [closing.eq(0), list_start.eq(1), records.eq(0)]
        with m.Else():
            m.d.sync += closing.eq(request)
            with m.If(out.tvalid & out.tready):
                m.d.sync += [list_start.eq(out.tlast),
                             records.eq(Mux(out.tlast, 0, records + 1))]
        return m


class StatesToAxis(wiring.Component):
    """The DP pipeline's ``states`` stream to ``m_axis_state`` (see the module doc), and the
    soft reset's close of an open line.

    Without ``closing`` the port is the stream itself (combinational). While ``closing`` is
    high (the caller's soft reset, held until the caller resets this adapter):

    1. a word already offered and not yet taken (``tvalid`` high, ``tready`` low in the
       cycle before) stays offered, unchanged, until it is taken; no new word is offered;
    2. if a line is then open (words of it were sent, not its ``tlast``), it is completed
       to W words by *filler* words: ``tdata`` = 0 (E = 0, d = 0), ``tuser`` = only
       ``tuser[3]`` (cut), ``tlast`` on the line's W-th word; each is offered until taken;
    3. ``closed`` is high (combinationally) when nothing is left to send after this cycle:
       no word is held and no line is open, or the word taken in this cycle has ``tlast``.

    The adapter counts the words since the last ``tlast`` (or reset) modulo W, and the
    fillers complete them to a multiple of W: one line, but after a resync at the input
    (whose interrupted line has no ``tlast``). A line is open whenever a word without
    ``tlast`` was sent since the last ``tlast``, also when that count is a multiple of W
    (then W fillers close it).

    Members
    -------
    states : In(stream.Signature(state_layout(cfg)))
    state : Out(state_out_signature(cfg))
    closing : In(1)
    closed : Out(1)
    stalled : Out(1)
        ``tvalid`` high and ``tready`` low in this cycle (back-pressure).
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "states": In(stream.Signature(state_layout(cfg))),
            "state": Out(state_out_signature(cfg)),
            "closing": In(1),
            "closed": Out(1),
            "stalled": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        width = self._cfg.width
        src, out = self.states, self.state
        frame_start = Signal(init=1)           # the next word is pixel (0, 0) of a frame
        column = Signal(range(width))          # words sent in the open line (modulo W)
        line_open = Signal()                   # a word without tlast sent since the last tlast
        held = Signal()                        # a core word was offered, not taken, last cycle
        passing = ~self.closing | held         # the core's word may be offered
        offer = src.valid & passing
        fill = self.closing & ~held & line_open               # offer a filler word
        word = Signal(state_word_layout(self._cfg))
        user = Signal(len(STATE_TUSER))
        m.d.comb += [
            word.energy.eq(src.payload.energy),
            word.direction.eq(src.payload.direction),
            user[STATE_TUSER["start_of_frame"]].eq(frame_start),
            user[STATE_TUSER["end_of_frame"]].eq(src.payload.end_of_frame),
            user[STATE_TUSER["end_of_segment"]].eq(src.payload.end_of_segment),
        ]
        # Mux: tdata, tuser and tlast are 0 while no word is offered; a filler is all 0 but
        # its cut bit and (on the line's last word) tlast
        m.d.comb += [
            out.tdata.eq(Mux(offer, word.as_value(), 0)),
            out.tuser.eq(Mux(offer, user, Mux(fill, 1 << STATE_TUSER["cut"], 0))),
            out.tlast.eq(Mux(offer, src.payload.end_of_line, fill & (column == width - 1))),
            out.tvalid.eq(offer | fill),
            src.ready.eq(out.tready & passing),
            self.stalled.eq(out.tvalid & ~out.tready),
            self.closed.eq((~held & ~line_open) | (out.tvalid & out.tready & out.tlast)),
        ]
        m.d.sync += held.eq(offer & ~out.tready)
        with m.If(out.tvalid & out.tready):
            m.d.sync += [column.eq(Mux(out.tlast | (column == width - 1), 0, column + 1)),
                         line_open.eq(~out.tlast)]
        with m.If(offer & out.tready):
            m.d.sync += frame_start.eq(src.payload.end_of_frame)
        return m
