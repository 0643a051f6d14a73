"""Frame and segment controller: where each accepted pixel sits in its frame and segment.

The controller counts accepted pixels in raster order (column, row, frame within the
segment), produces the read-ahead address of the state store in the accepting cycle, and
one cycle later the pixel's position and its start/end flags, which then travel down the
pipeline with the data.

Resynchronisation: the input marks the first pixel of every frame with ``first``. The
counters, not ``first``, define positions; ``first`` is only checked. A pixel with
``first`` set where the counters do not expect a frame start restarts the counters: that
pixel becomes pixel (0, 0) of frame 0 of a new segment (the interrupted frame's pixels
already accepted are processed and output without end flags). A missing ``first`` at an
expected frame start is ignored.

Run-time segment length: the input ``segment_frames`` (K, clamped to [1, K_max]) is sampled
in the cycle a segment's first pixel is accepted (pixel (0, 0) of frame 0, also after a
resync) and holds for that whole segment; a change mid-segment takes effect at the next
segment start (``docs/gateware.md``, "Run-time settings").

Recursive mode (``cfg.recursive``, paper 000's family, ``docs/arithmetic.md`` §8.6): every
frame is a one-frame output segment (``end_of_segment`` with every ``end_of_frame``,
``segment_begin`` on every frame's first pixel, the run-time K ignored), but only the
first frame after reset or after a resynchronisation is a *start* frame
(``segment_start``): every later frame continues the recursion on the stored state.
"""

from __future__ import annotations

from amaranth.hdl import Module, Mux, Signal, unsigned
from amaranth.lib import data, wiring
from amaranth.lib.wiring import In, Out

from dptbd.config import DPConfig
from dptbd.hw.modular import increment_mod
from dptbd.hw.schedule import read_ahead_distance

__all__ = ["position_layout", "clamped", "inside_flags", "Controller"]


def clamped(value, lo: int, hi: int):
    """``value`` limited to ``[lo, hi]`` (a run-time setting outside its range, which the
    register block never writes, is clamped instead of misbehaving)."""
    limited = Mux(value > hi, hi, value) if (1 << len(value)) - 1 > hi else value
    return Mux(value < lo, lo, limited) if lo > 0 else limited


def inside_flags(position: int, size: int, radius: int) -> int:
    """Bit i set when ``position + radius - i`` lies in ``[0, size)``, for i in 0 … 2r: which
    rows (or columns) of a window centred at ``position`` are inside the image."""
    return sum(1 << i for i in range(2 * radius + 1) if 0 <= position + radius - i < size)


def _inside_flags_of(value, size: int, radius: int):
    """:func:`inside_flags` of a counter in gateware: equality with the few positions next to
    the edges (no magnitude comparator)."""
    flags = inside_flags(radius, size, radius)         # an interior position's
    for p in dict.fromkeys([*range(radius), *range(size - radius, size)]):   # in order
        flags = Mux(value == p, inside_flags(p, size, radius), flags)
    return flags


def position_layout(cfg: DPConfig) -> data.StructLayout:
    """Position and flags of one pixel, as output by the controller.

    ``start_of_frame`` marks pixel (0, 0) and ``segment_start`` every pixel of a segment's
    first frame; ``end_of_line`` / ``end_of_frame`` / ``end_of_segment`` as in
    :func:`dptbd.hw.layouts.state_layout`.
    """
    return data.StructLayout({
        "row": unsigned(max(1, (cfg.height - 1).bit_length())),
        "col": unsigned(max(1, (cfg.width - 1).bit_length())),
        "start_of_frame": unsigned(1),
        "segment_start": unsigned(1),
        "end_of_line": unsigned(1),
        "end_of_frame": unsigned(1),
        "end_of_segment": unsigned(1),
    })


class Controller(wiring.Component):
    """Raster, frame-in-segment and read-ahead counters.

    Parameters
    ----------
    cfg : DPConfig
        Frame size W x H, segment length K and radius r.

    Members
    -------
    accept : In(1)
        A pixel is accepted in this cycle (cycle 0).
    first : In(1)
        The accepted pixel's ``first`` (start-of-frame) flag.
    segment_frames : In(range(1, K_max + 1), init=K)
        Run-time K, clamped to [1, K_max], sampled in a segment's first accepting cycle.
    segment_begin : Out(1)
        Cycle 0, combinational: the accepted pixel is the first of a segment (its run-time
        settings are sampled now).
    read_addr : Out(range(W*H))
        Cycle 0, combinational: the state-store address to read for the accepted pixel,
        ``(p + r*(W+1)) mod (W*H)`` for its raster position p.
    next_read_addr : Out(range(W*H))
        Cycle 0, combinational: the address the next pixel will read if it continues the
        raster (``read_addr + 1`` mod W*H: a register holding it, or a constant on
        ``resync``; no adder); what the on-chip store reads ahead
        (:class:`~dptbd.hw.read_ahead_store.ReadAheadStore`).
    resync : Out(1)
        Cycle 0, combinational: the accepted pixel restarts the counters.
    valid : Out(1)
        Cycle 1: a pixel was accepted in cycle 0.
    position : Out(position_layout(cfg))
        Cycle 1: that pixel's position and flags.
    row_inside, col_inside : Out(2r+1), Out(2r+1)
        Cycle 1: :func:`inside_flags` of that pixel's row and column (bit i: row / column
        ``y + r - i`` / ``x + r - i`` is inside the image), for the window's edge flags,
        formed from the counters a cycle ahead so that no comparator follows ``position``.

    With ``registered=True`` (the ECP5 build's, ``control_style="registered"``):
    ``position.end_of_segment`` is a frame's end and the register "the segment's last
    frame", without the case of a segment's first pixel (which never ends a frame: W*H > 1)
    and so without the run-time K on its path; ``next_read_addr``'s choice on ``resync``
    from a copy of the "at (0, 0)" register of its own (stored inverted, so that synthesis
    keeps the two apart), placed for the state store's block RAMs, which that address
    drives. Same outputs, same cycles.
    """

    def __init__(self, cfg: DPConfig, *, registered: bool = False):
        self._cfg = cfg
        self._registered = bool(registered)
        super().__init__({
            "accept": In(1),
            "first": In(1),
            "segment_frames": In(range(1, cfg.k_max + 1), init=cfg.segment_frames),
            "segment_begin": Out(1),
            "read_addr": Out(range(cfg.width * cfg.height)),
            "next_read_addr": Out(range(cfg.width * cfg.height)),
            "resync": Out(1),
            "valid": Out(1),
            "position": Out(position_layout(cfg)),
            "row_inside": Out(2 * cfg.radius + 1),
            "col_inside": Out(2 * cfg.radius + 1),
        })

    def elaborate(self, platform):
        m = Module()
        cfg = self._cfg
        width, height = cfg.width, cfg.height
        pixels = width * height
        ahead_start = read_ahead_distance(cfg) % pixels

        # Registered flags stand for the counters' comparisons (col == W - 1, row == H - 1,
        # the frame's place in its segment), each updated with its counter, so no output
        # or counter waits for an equality on a wide counter (ECP5 timing,
        # docs/synthesis.md). W, H >= 3, so a resynchronised pixel (0, 0) neither ends a
        # line nor a frame: after it col = 1, row = 0 and the segment's first frame goes on.
        col = Signal(range(width))
        row = Signal(range(height))
        col_last = Signal()                         # col == W - 1
        row_last = Signal()                         # row == H - 1
        frame_first = Signal(init=1)                # the frame is its segment's first
        frames_left = Signal(range(cfg.k_max))      # frames of the segment after this one
        frame_last = Signal()                       # frames_left == 0
        ahead = Signal(range(pixels), init=ahead_start)
        # ahead + 1 mod W*H, kept in a register so that no carry chain drives the store's
        # read-ahead address (ECP5 timing, docs/synthesis.md)
        ahead_next = Signal(range(pixels), init=(ahead_start + 1) % pixels)
        at_start = Signal(init=1)                   # the next pixel is expected at (0, 0)

        # Effective position of the pixel accepted now: the counters, or (0, 0) of a new
        # segment on an unexpected `first`.
        m.d.comb += self.resync.eq(self.first & ~at_start)
        eff_col = Mux(self.resync, 0, col)
        eff_row = Mux(self.resync, 0, row)
        eff_ahead = Mux(self.resync, ahead_start, ahead)
        begins = (at_start & frame_first) | self.resync
        m.d.comb += self.segment_begin.eq(self.accept & begins)
        segment_k = clamped(self.segment_frames, 1, cfg.k_max)
        # ---- recursive mode (docs/arithmetic.md §8.6) ----------------------------------
        if cfg.recursive:
            last_frame = 1                      # one-frame output segments
            recursing = Signal()                # a start frame has ended since reset/resync
            start_frame = self.resync | ~recursing
        else:
            last_frame = Mux(begins, segment_k == 1, frame_last)
            start_frame = frame_first | self.resync
        # ---- end of recursive mode ---------------------------------------------------
        last_col = ~self.resync & col_last
        end_of_frame = last_col & row_last
        next_ahead = Mux(self.resync, (ahead_start + 1) % pixels, ahead_next)
        m.d.comb += self.read_addr.eq(eff_ahead)
        if self._registered:
            # ~at_start, a copy of its own for the store's read-ahead address
            away = Signal(name="away_from_start")
            with m.If(self.accept):
                m.d.sync += away.eq(~end_of_frame)
            m.d.comb += self.next_read_addr.eq(
                Mux(self.first & away, (ahead_start + 1) % pixels, ahead_next))
        else:
            m.d.comb += self.next_read_addr.eq(next_ahead)

        with m.If(self.accept):
            # Next values from the registers alone, `resync` (from the input `first`)
            # selecting last: it drives one multiplexer per bit, not the carry chains.
            m.d.sync += [
                col.eq(Mux(self.resync, 1, increment_mod(col, width))),
                col_last.eq(~self.resync & (col == width - 2)),
                ahead.eq(next_ahead),
                ahead_next.eq(Mux(self.resync, (ahead_start + 2) % pixels,
                                  increment_mod(ahead_next, pixels))),
                at_start.eq(end_of_frame),
            ]
            with m.If(self.resync):
                m.d.sync += [row.eq(0), row_last.eq(0)]
            with m.Elif(col_last):
                m.d.sync += [row.eq(increment_mod(row, height)),
                             row_last.eq(row == height - 2)]
            if not cfg.recursive:
                with m.If(end_of_frame):        # never with begins: W * H > 1
                    m.d.sync += [frame_first.eq(frame_last),
                                 frames_left.eq(frames_left - 1),
                                 frame_last.eq(frames_left == 1)]
                with m.Elif(begins):            # the segment's K is sampled here
                    m.d.sync += [frame_first.eq(1),
                                 frames_left.eq(segment_k - 1),
                                 frame_last.eq(segment_k == 1)]
            else:                               # recursive mode (§8.6)
                m.d.sync += recursing.eq(end_of_frame | (recursing & ~self.resync))

        m.d.sync += [
            self.valid.eq(self.accept),
            self.position.row.eq(eff_row),
            self.position.col.eq(eff_col),
            self.position.start_of_frame.eq(at_start | self.resync),
            self.position.segment_start.eq(start_frame),
            self.position.end_of_line.eq(last_col),
            self.position.end_of_frame.eq(end_of_frame),
            self.position.end_of_segment.eq(
                end_of_frame & (frame_last if self._registered and not cfg.recursive
                                 else last_frame)),
            self.row_inside.eq(Mux(self.resync, inside_flags(0, height, cfg.radius),
                                   _inside_flags_of(row, height, cfg.radius))),
            self.col_inside.eq(Mux(self.resync, inside_flags(0, width, cfg.radius),
                                   _inside_flags_of(col, width, cfg.radius))),
        ]
        return m
