"""The AXI4-Stream video input at P = 2 or 4 pixels per beat (``docs/integration.md``,
``docs/gateware.md`` "P pixels per clock"): the common multi-pixel convention, pixel 0 in
the low bits, each pixel in a lane of whole bytes (``8 * ceil(B_in / 8)`` bits, the value in
its low B_in bits, the bits above ignored, as at P = 1); ``tuser[0]`` on a frame's first
beat, ``tlast`` on a row's last beat."""

from __future__ import annotations

from amaranth.hdl import Module
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.axis_video import axis_signature, byte_padded
from dptbd.hw.wide.layouts import wide_pixel_layout

__all__ = ["lane_bits", "video_in_signature_wide", "video_tdata_layout_wide", "AxisToBeats"]


def lane_bits(cfg: DPConfig) -> int:
    """Bits of one pixel's lane of ``tdata``: B_in rounded up to whole bytes."""
    return byte_padded(cfg.input_bits)


def video_in_signature_wide(cfg: DPConfig) -> wiring.Signature:
    """``s_axis_video`` at P pixels per beat: ``tdata`` of P lanes."""
    return axis_signature(cfg.pixels_per_clock * lane_bits(cfg))


def video_tdata_layout_wide(cfg: DPConfig) -> data.StructLayout:
    """The bits of ``tdata`` the core reads: pixel k in the low B_in bits of lane k."""
    fields = {}
    for k in range(cfg.pixels_per_clock):
        fields[f"pixel_{k}"] = cfg.input_bits
        pad = lane_bits(cfg) - cfg.input_bits
        if pad and k < cfg.pixels_per_clock - 1:
            fields[f"pad_{k}"] = pad
    return data.StructLayout(fields)


class AxisToBeats(wiring.Component):
    """``s_axis_video`` (P pixels per beat) to the core's ``pixels`` beats (combinational);
    members as :class:`~dptbd.hw.axis_video.AxisToPixels`'."""

    def __init__(self, cfg: DPConfig):
        self._cfg = cfg
        super().__init__({
            "video": In(video_in_signature_wide(cfg)),
            "pixels": Out(stream.Signature(wide_pixel_layout(cfg))),
            "accepted": Out(1),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        video, pixels = self.video, self.pixels
        lane = lane_bits(cfg)
        for k in range(cfg.pixels_per_clock):
            m.d.comb += getattr(pixels.payload, f"pixel_{k}").eq(
                video.tdata[k * lane:k * lane + cfg.input_bits])
        m.d.comb += [
            pixels.payload.first.eq(video.tuser[0]),
            pixels.valid.eq(video.tvalid),
            video.tready.eq(pixels.ready),
            self.accepted.eq(video.tvalid & pixels.ready),
        ]
        return m
