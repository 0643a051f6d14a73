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
  write protocol");
* run-time settings (K, n, s) written before a word are sampled at the next segment start
  (a segment's first accepted pixel, also after a restart): K sets that segment's length,
  and n, s travel with the segment to the segmenter (``docs/gateware.md``, "Run-time
  settings"). :attr:`StreamExpectation.settings` holds them per word for
  :func:`dptbd.model.segmentation.segment_stream`;
* the accumulator's ``saturated`` flag of every word, for the ``saturated`` event counter.

The per-frame model is the reference :mod:`dptbd.model.fixed` (``segment_start``,
``dp_step``), the same the cocotb scoreboard uses.
"""

from __future__ import annotations

import dataclasses
from typing import Mapping

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.layouts import pack_states, pixel_layout, unpack_array
from dptbd.model.fixed import dp_step_saturated, segment_start
from dptbd.model.settings import SegmentSettings

__all__ = ["FrameRun", "StreamExpectation", "frame_runs", "port_settings", "expected_stream",
           "split_words"]


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
    segment_frames: int = dataclasses.field(default=0, compare=False)   # K of its segment


def frame_runs(cfg: DPConfig, first: np.ndarray, port_k: np.ndarray | None = None
               ) -> list[FrameRun]:
    """Split a stream (its ``first`` flags) into frames by the gateware's counter rule.

    ``port_k``: the run-time K on the port when each word is accepted (default: the build
    K); a segment takes the value at its first word.
    """
    first = np.asarray(first, dtype=bool)
    n = len(first)
    size = cfg.width * cfg.height
    marks = np.flatnonzero(first)
    runs: list[FrameRun] = []
    i, k, frames = 0, 0, cfg.segment_frames
    while i < n:
        if k == 0 and port_k is not None:
            frames = int(port_k[i])
        nxt = np.searchsorted(marks, i, side="right")     # the next `first` after word i
        stop = min(i + size, n, int(marks[nxt]) if nxt < len(marks) else n)
        complete = stop - i == size
        runs.append(FrameRun(i, stop, k, complete, frames))
        k = (k + 1) % frames if complete else 0            # a partial frame: restart
        i = stop
    return runs


@dataclasses.dataclass(frozen=True)
class StreamExpectation:
    """The model's output for every accepted word, in stream order."""

    words: np.ndarray      # uint64 packed ``states`` payloads
    fields: np.ndarray     # (N, 5) int64: energy, direction, end_of_line, end_of_frame, end_of_segment
    positions: np.ndarray  # (N, 3) int64: frame (counted from the stream's start), row, col
    runs: tuple[FrameRun, ...]
    saturated: np.ndarray = None  # (N,) bool: the accumulator clipped this word's E
    settings: np.ndarray = None   # (N, 3) int64: K, n, s of the word's segment

    def saturation_counts(self) -> np.ndarray:
        """Saturated words per run (frame or partial frame), in stream order."""
        return np.array([int(self.saturated[r.start:r.stop].sum()) for r in self.runs],
                        dtype=np.int64)


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


def port_settings(cfg: DPConfig, n: int,
                  changes: Mapping[int, SegmentSettings] | None = None) -> np.ndarray:
    """``(n, 3)`` int64: the run-time (K, n, s) on the ports when each of ``n`` words is
    accepted, from ``{word index: SegmentSettings}`` written just before that word (the
    build values before the first; each checked against ``cfg``)."""
    out = np.empty((n, 3), dtype=np.int64)
    out[:] = dataclasses.astuple(SegmentSettings.defaults(cfg))
    for index, entry in sorted((changes or {}).items()):
        if not isinstance(entry, SegmentSettings):
            raise ValueError(f"settings change before word {index} must be a SegmentSettings, "
                             f"got {type(entry).__name__}")
        out[max(int(index), 0):] = dataclasses.astuple(entry.checked(cfg))
    return out


def expected_stream(cfg: DPConfig, pixels: np.ndarray, first: np.ndarray,
                    lut_changes: Mapping[int, np.ndarray] | None = None,
                    settings_changes: Mapping[int, SegmentSettings] | None = None
                    ) -> StreamExpectation:
    """The golden model's ``states`` output for a stream of accepted words after reset.

    Parameters
    ----------
    cfg : DPConfig
        The configuration; its LUT is the one in force at the stream's start.
    pixels, first : array
        The accepted words' fields, in acceptance order (:func:`split_words`).
    lut_changes : mapping, optional
        ``{word index: (M+1) x M codes}``: a LUT written just before that word was accepted.
    settings_changes : mapping, optional
        ``{word index: SegmentSettings}``: run-time settings written just before that word
        was accepted (sampled at the next segment start).

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
    n = len(pixels)
    ports = port_settings(cfg, n, settings_changes)
    runs = frame_runs(cfg, first, ports[:, 0])
    fields = np.zeros((n, 5), dtype=np.int64)
    positions = np.zeros((n, 3), dtype=np.int64)
    saturated = np.zeros(n, dtype=bool)
    settings = np.zeros((n, 3), dtype=np.int64)
    segment_settings = ports[0] if n else None
    prev = None
    for index, run in enumerate(runs):
        length = run.stop - run.start
        frame = np.zeros(size, dtype=np.uint16)
        frame[:length] = pixels[run.start:run.stop]
        frame = frame.reshape(h, w)
        energy = np.empty(size, dtype=np.int64)
        direction = np.empty(size, dtype=np.int64)
        clipped = np.zeros(size, dtype=bool)
        for lo, hi, cfg_p in _lut_pieces(cfg, changes, run.start, run.stop):
            if run.frame == 0:
                e, d = segment_start(frame, cfg_p)
                c = np.zeros(e.shape, dtype=bool)
            else:
                e, d, c = dp_step_saturated(prev[0], prev[1], frame, cfg_p)
            a, b = lo - run.start, hi - run.start
            energy[a:b] = e.reshape(-1)[a:b]
            direction[a:b] = d.reshape(-1)[a:b]
            clipped[a:b] = c.reshape(-1)[a:b]
        if run.frame == 0:
            segment_settings = ports[run.start]
        sl = slice(run.start, run.stop)
        saturated[sl] = clipped[:length]
        settings[sl] = segment_settings
        p = np.arange(length)
        fields[sl, 0] = energy[:length]
        fields[sl, 1] = direction[:length]
        fields[sl, 2] = (p % w) == w - 1
        if run.complete:
            fields[run.stop - 1, 3] = 1
            fields[run.stop - 1, 4] = int(run.frame == run.segment_frames - 1)
            prev = (energy.reshape(h, w), direction.reshape(h, w))
        positions[sl, 0] = index
        positions[sl, 1] = p // w
        positions[sl, 2] = p % w
    words = pack_states(cfg, energy=fields[:, 0], direction=fields[:, 1],
                        end_of_line=fields[:, 2], end_of_frame=fields[:, 3],
                        end_of_segment=fields[:, 4])
    return StreamExpectation(words, fields, positions, tuple(runs), saturated, settings)


def saturated_events(cfg: DPConfig, saturated) -> int:
    """The ``saturated`` event pulses of a stream whose words' clipped flags are
    ``saturated`` (a run from a beat boundary): one per clipped word at P = 1, one per beat
    with a clipped pixel at P > 1 (the lanes' flags ORed, ``docs/gateware.md`` "P pixels
    per clock")."""
    p = cfg.pixels_per_clock
    flags = np.asarray(saturated, dtype=bool)
    if p == 1:
        return int(flags.sum())
    flags = np.concatenate([flags, np.zeros(-len(flags) % p, dtype=bool)])
    return int(flags.reshape(-1, p).any(axis=1).sum())
