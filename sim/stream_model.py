"""What the pipeline outputs for an *arbitrary* accepted input stream, from the golden model.

:func:`dptbd.sim.scoreboard.expected_words` models a clean scene: whole frames, a start-of-
frame marker on each, segments counted from frame 0. Real streams are not always clean:
a reset in the middle of a frame, a start-of-frame marker in the middle of a frame, a frame
shorter or longer than W·H, a weight LUT rewritten between frames. This module applies the
gateware's counter rule (``docs/gateware.md``, "Reset and resynchronisation";
``hw/controller.py``) to a stream of accepted words and asks the golden model for every
output:

* positions come from counters started at reset: raster order, W·H pixels a frame, K frames
  a segment; a missing ``first`` at an expected frame start is ignored;
* a ``first`` where the counters do not expect a frame start restarts them: that pixel is
  (0, 0) of frame 0 of a new segment. The interrupted frame's pixels come out as the model
  computes them (a prefix of that frame), with ``end_of_line`` but without
  ``end_of_frame`` / ``end_of_segment``;
* a frame's state is ``segment_start`` in a segment's first frame and ``dp_step`` on the
  previous *complete* frame otherwise (a partial frame is always followed by a restart, so
  it is never a predecessor);
* a LUT write applies to every pixel accepted after it (``docs/gateware.md``, "Weight LUT
  write protocol").

The per-frame model is the reference :mod:`dptbd.model.fixed` (``segment_start``,
``dp_step``), the same the cocotb scoreboard uses.
"""

from __future__ import annotations

import dataclasses
from typing import Mapping

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.layouts import pack_states, pixel_layout, unpack_array
from dptbd.model.fixed import dp_step, segment_start

__all__ = ["FrameRun", "StreamExpectation", "frame_runs", "expected_stream", "split_words"]


def split_words(cfg: DPConfig, words: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(pixel, first)`` of packed ``pixels`` payloads (:func:`dptbd.hw.layouts.pixel_layout`)."""
    fields = unpack_array(pixel_layout(cfg), words)
    return fields["pixel"].astype(np.int64), fields["first"].astype(bool)


@dataclasses.dataclass(frozen=True)
class FrameRun:
    """Consecutive accepted words that the counters place in one frame."""

    start: int        # index of its first word in the stream
    stop: int         # one past its last word
    frame: int        # frame within its segment (0 = segment start)
    complete: bool    # all W·H pixels (ends with end_of_frame)


def frame_runs(cfg: DPConfig, first: np.ndarray) -> list[FrameRun]:
    """Split a stream (its ``first`` flags) into frames by the gateware's counter rule."""
    first = np.asarray(first, dtype=bool)
    n = len(first)
    size = cfg.width * cfg.height
    marks = np.flatnonzero(first)
    runs: list[FrameRun] = []
    i, k = 0, 0
    while i < n:
        nxt = np.searchsorted(marks, i, side="right")     # the next `first` after word i
        stop = min(i + size, n, int(marks[nxt]) if nxt < len(marks) else n)
        complete = stop - i == size
        runs.append(FrameRun(i, stop, k, complete))
        k = (k + 1) % cfg.segment_frames if complete else 0   # a partial frame: restart
        i = stop
    return runs


@dataclasses.dataclass(frozen=True)
class StreamExpectation:
    """The model's output for every accepted word, in stream order."""

    words: np.ndarray      # uint64 packed ``states`` payloads
    fields: np.ndarray     # (N, 5) int64: energy, direction, end_of_line, end_of_frame, end_of_segment
    positions: np.ndarray  # (N, 3) int64: frame (counted from the stream's start), row, col
    runs: tuple[FrameRun, ...]


def _lut_pieces(cfg: DPConfig, changes: list[tuple[int, DPConfig]], start: int, stop: int):
    """(lo, hi, cfg) pieces of [start, stop) by the LUT in force at each word."""
    pieces = []
    current = cfg
    cuts = []
    for index, cfg_i in changes:
        if index <= start:
            current = cfg_i
        elif index < stop:
            cuts.append((index, cfg_i))
    lo = start
    for index, cfg_i in cuts:
        pieces.append((lo, index, current))
        lo, current = index, cfg_i
    pieces.append((lo, stop, current))
    return pieces


def expected_stream(cfg: DPConfig, pixels: np.ndarray, first: np.ndarray,
                    lut_changes: Mapping[int, np.ndarray] | None = None) -> StreamExpectation:
    """The golden model's ``states`` output for a stream of accepted words after reset.

    Parameters
    ----------
    cfg : DPConfig
        The configuration; its LUT is the one in force at the stream's start.
    pixels, first : array
        The accepted words' fields, in acceptance order (:func:`split_words`).
    lut_changes : mapping, optional
        ``{word index: (M+1) x M codes}``: a LUT written just before that word was accepted.

    Returns
    -------
    StreamExpectation
    """
    pixels = np.asarray(pixels, dtype=np.int64)
    first = np.asarray(first, dtype=bool)
    if pixels.shape != first.shape or pixels.ndim != 1:
        raise ValueError(f"pixels and first must be 1-D of one length, got {pixels.shape} "
                         f"and {first.shape}")
    h, w, size = cfg.height, cfg.width, cfg.width * cfg.height
    changes = sorted((int(i), cfg.with_weight_codes(codes))
                     for i, codes in (lut_changes or {}).items())
    runs = frame_runs(cfg, first)
    n = len(pixels)
    fields = np.zeros((n, 5), dtype=np.int64)
    positions = np.zeros((n, 3), dtype=np.int64)
    prev = None
    for index, run in enumerate(runs):
        length = run.stop - run.start
        frame = np.zeros(size, dtype=np.uint16)
        frame[:length] = pixels[run.start:run.stop]
        frame = frame.reshape(h, w)
        energy = np.empty(size, dtype=np.int64)
        direction = np.empty(size, dtype=np.int64)
        for lo, hi, cfg_p in _lut_pieces(cfg, changes, run.start, run.stop):
            if run.frame == 0:
                e, d = segment_start(frame, cfg_p)
            else:
                e, d = dp_step(prev[0], prev[1], frame, cfg_p)
            a, b = lo - run.start, hi - run.start
            energy[a:b] = e.reshape(-1)[a:b]
            direction[a:b] = d.reshape(-1)[a:b]
        sl = slice(run.start, run.stop)
        p = np.arange(length)
        fields[sl, 0] = energy[:length]
        fields[sl, 1] = direction[:length]
        fields[sl, 2] = (p % w) == w - 1
        if run.complete:
            fields[run.stop - 1, 3] = 1
            fields[run.stop - 1, 4] = int(run.frame == cfg.segment_frames - 1)
            prev = (energy.reshape(h, w), direction.reshape(h, w))
        positions[sl, 0] = index
        positions[sl, 1] = p // w
        positions[sl, 2] = p % w
    words = pack_states(cfg, energy=fields[:, 0], direction=fields[:, 1],
                        end_of_line=fields[:, 2], end_of_frame=fields[:, 3],
                        end_of_segment=fields[:, 4])
    return StreamExpectation(words, fields, positions, tuple(runs))
