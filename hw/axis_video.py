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
  segment, ``tlast`` = end of line.
"""

from __future__ import annotations

from amaranth.hdl import Module, Signal
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import candidate_layout
from dptbd.hw.layouts import pixel_layout, state_layout, state_word_layout

__all__ = ["byte_padded", "axis_signature", "video_in_signature", "video_tdata_layout", "candidate_out_signature",
           "state_out_signature", "STATE_TUSER", "AxisToPixels", "CandidatesToAxis",
           "StatesToAxis"]

#: ``m_axis_state_tuser`` bits.
STATE_TUSER = {"start_of_frame": 0, "end_of_frame": 1, "end_of_segment": 2}


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
    """``m_axis_state``: one pixel's (E, d) per beat, three ``tuser`` bits."""
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
    """The core's ``candidates`` stream to ``m_axis_cand``.

    Members
    -------
    candidates : In(stream.Signature(candidate_layout(cfg)))
    cand : Out(candidate_out_signature(cfg))
    stalled : Out(1)
        ``tvalid`` high and ``tready`` low in this cycle (back-pressure).
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "candidates": In(stream.Signature(candidate_layout(cfg))),
            "cand": Out(candidate_out_signature(cfg)),
            "stalled": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        src, out = self.candidates, self.cand
        list_start = Signal(init=1)            # the next word is the first of a list
        m.d.comb += [
            out.tdata.eq(src.payload.as_value()),
            out.tuser[0].eq(list_start),
            out.tlast.eq(src.payload.end_of_list),
            out.tvalid.eq(src.valid),
            src.ready.eq(out.tready),
            self.stalled.eq(src.valid & ~out.tready),
        ]
        with m.If(src.valid & out.tready):
            m.d.sync += list_start.eq(src.payload.end_of_list)
        return m


class StatesToAxis(wiring.Component):
    """The DP pipeline's ``states`` stream to ``m_axis_state`` (see the module doc).

    Members
    -------
    states : In(stream.Signature(state_layout(cfg)))
    state : Out(state_out_signature(cfg))
    stalled : Out(1)
        ``tvalid`` high and ``tready`` low in this cycle (back-pressure).
    """

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "states": In(stream.Signature(state_layout(cfg))),
            "state": Out(state_out_signature(cfg)),
            "stalled": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        src, out = self.states, self.state
        frame_start = Signal(init=1)           # the next word is pixel (0, 0) of a frame
        word = Signal(state_word_layout(self._cfg))
        m.d.comb += [
            word.energy.eq(src.payload.energy),
            word.direction.eq(src.payload.direction),
            out.tdata.eq(word.as_value()),
            out.tuser[STATE_TUSER["start_of_frame"]].eq(frame_start),
            out.tuser[STATE_TUSER["end_of_frame"]].eq(src.payload.end_of_frame),
            out.tuser[STATE_TUSER["end_of_segment"]].eq(src.payload.end_of_segment),
            out.tlast.eq(src.payload.end_of_line),
            out.tvalid.eq(src.valid),
            src.ready.eq(out.tready),
            self.stalled.eq(src.valid & ~out.tready),
        ]
        with m.If(src.valid & out.tready):
            m.d.sync += frame_start.eq(src.payload.end_of_frame)
        return m
