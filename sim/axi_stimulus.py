"""Beat streams for the AXI top level's video input, with frame-sync faults injected, and
the frame monitor's fault rule as a reference.

Plain numpy (no simulator import): the cocotb bench :mod:`dptbd.sim.tb_axi`, its pytest
driver and the monitor's unit test use it. A stream is three arrays over beats: the pixel,
``first`` (``tuser[0]``, start of frame) and ``last`` (``tlast``, end of line).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.register_map import FAULTS, register_map
from dptbd.sim.candidate_scoreboard import stream_lists
from dptbd.sim.stream_model import expected_stream

__all__ = ["FAULT_KINDS", "SETTINGS", "Beats", "clean_beats", "with_fault", "fault_pulses",
           "fault_counts", "Piece", "stream_pieces", "expected_lists"]

#: What :func:`with_fault` can inject, each raising exactly one pulse of its class.
FAULT_KINDS = FAULTS

#: Setting registers -> the DPConfig field the model takes them as.
SETTINGS = {"SEGMENT_FRAMES": "segment_frames", "CANDIDATE_COUNT": "candidate_count",
            "HISTOGRAM_SHIFT": "histogram_shift"}


@dataclasses.dataclass(frozen=True)
class Beats:
    """One video input stream: per-beat ``pixel``, ``first`` and ``last``."""

    pixel: np.ndarray
    first: np.ndarray
    last: np.ndarray

    def __len__(self) -> int:
        return len(self.pixel)

    def __add__(self, other: "Beats") -> "Beats":
        return Beats(*(np.concatenate([a, b]) for a, b in
                       zip(dataclasses.astuple(self), dataclasses.astuple(other))))

    def to_json(self) -> dict:
        return {name: np.asarray(v, dtype=np.int64).tolist()
                for name, v in dataclasses.asdict(self).items()}

    @classmethod
    def from_json(cls, values: dict) -> "Beats":
        return cls(np.asarray(values["pixel"], dtype=np.int64),
                   np.asarray(values["first"], dtype=bool), np.asarray(values["last"], dtype=bool))


def clean_beats(frames: np.ndarray) -> Beats:
    """Frames ``(T, H, W)`` as beats: ``first`` on pixel (0, 0), ``last`` on column W-1."""
    frames = np.asarray(frames)
    first = np.zeros(frames.shape, dtype=bool)
    first[:, 0, 0] = True
    last = np.zeros(frames.shape, dtype=bool)
    last[:, :, -1] = True
    return Beats(frames.astype(np.int64).ravel(), first.ravel(), last.ravel())


def with_fault(cfg: DPConfig, frames: np.ndarray, kind: str) -> Beats:
    """``frames`` as beats with one fault of class ``kind`` in frame 0 (the frames after it
    clean; at least two frames):

    - ``sof_unexpected``: frame 0 is cut after 1.5 lines (no ``tlast`` on the cut line);
    - ``frame_short``: frame 0 has its first H-1 lines only;
    - ``frame_long``: frame 1 comes without its start of frame;
    - ``line_length``: line 0 of frame 0 has no ``tlast``.
    """
    if kind not in FAULT_KINDS:
        raise ValueError(f"fault kind must be one of {FAULT_KINDS}, got {kind!r}")
    if len(frames) < 2:
        raise ValueError(f"a fault needs at least 2 frames, got {len(frames)}")
    w = cfg.width
    head, tail = clean_beats(frames[:1]), clean_beats(frames[1:])
    if kind == "sof_unexpected":
        head = _prefix(head, w + w // 2)
    elif kind == "frame_short":
        head = _prefix(head, w * (cfg.height - 1))
    elif kind == "frame_long":
        tail.first[0] = False
    else:
        head.last[w - 1] = False
    return head + tail


def _prefix(beats: Beats, n: int) -> Beats:
    return Beats(beats.pixel[:n].copy(), beats.first[:n].copy(), beats.last[:n].copy())


def fault_pulses(cfg: DPConfig, first, last) -> list[dict[str, int]]:
    """The frame monitor's fault pulses for every beat (``docs/integration.md``): the
    core's counting rule (an unexpected start of frame restarts the counters, a missing one
    is ignored) and the four classes."""
    width, height = cfg.width, cfg.height
    col = row = 0
    at_start = True
    out = []
    for f, lst in zip(first, last):
        restart = bool(f) and not at_start
        pulses = {"sof_unexpected": restart and col != 0, "frame_short": restart and col == 0,
                  "frame_long": at_start and not f}
        if restart:
            col = row = 0
        pulses["line_length"] = bool(lst) != (col == width - 1)
        out.append({k: int(v) for k, v in pulses.items()})
        at_start = col == width - 1 and row == height - 1
        if col == width - 1:
            col, row = 0, (0 if row == height - 1 else row + 1)
        else:
            col += 1
    return out


def fault_counts(cfg: DPConfig, beats: Beats) -> dict[str, int]:
    """Total pulses per fault class of a stream (what the FAULT_* counters must read)."""
    pulses = fault_pulses(cfg, beats.first, beats.last)
    return {k: sum(p[k] for p in pulses) for k in FAULTS}


@dataclasses.dataclass(frozen=True)
class Piece:
    """Beats ``[start, stop)`` that the core processes from reset with one set of settings
    (``cfg``) and LUT writes at ``lut_changes`` (absolute beat index -> codes)."""

    start: int
    stop: int
    cfg: DPConfig
    lut_changes: dict


def stream_pieces(cfg: DPConfig, steps: list[dict]) -> list[Piece]:
    """Cut a bench's steps (:mod:`dptbd.sim.tb_axi`) into pieces at every ``soft_reset``.

    A step's valid writes to a setting register (``SEGMENT_FRAMES``, ``CANDIDATE_COUNT``,
    ``HISTOGRAM_SHIFT``; refused values are ignored as the gateware ignores them) change the
    model's configuration. The golden model here takes one configuration per piece, so a
    setting may change only before a piece's first beat (the stream's start or a
    ``soft_reset`` step); elsewhere ``ValueError``. The LUT is a memory: it keeps its codes
    across a soft reset.
    """
    limits = {name: (getattr(f, "limits")) for name in SETTINGS
              for f in register_map(cfg)[name].fields}
    pieces, lo, start, current, changes, lut = [], 0, 0, cfg, {}, None
    for index, step in enumerate(steps):
        if step.get("soft_reset") and start > lo:
            pieces.append(Piece(lo, start, current, changes))
            lo, changes = start, ({start: lut} if lut is not None else {})
        for name, value in step.get("writes", []):
            if name in SETTINGS and limits[name][0] <= value <= limits[name][1]:
                if start > lo:
                    raise ValueError(f"step {index}: {name} changes after beat {lo} of a "
                                     f"piece; the model takes settings per piece (write them "
                                     f"before the first beat or with a soft_reset step)")
                current = current.replace(**{SETTINGS[name]: int(value)})
        if step.get("lut_codes") is not None:
            lut = step["lut_codes"]
            changes[start] = lut
        start = step["stop"]
    pieces.append(Piece(lo, start, current, changes))
    return pieces


def expected_lists(cfg: DPConfig, beats: Beats, steps: list[dict]):
    """The candidate lists the golden model makes of the whole stream, and its frame runs:
    :func:`~dptbd.sim.stream_model.expected_stream` and
    :func:`~dptbd.sim.candidate_scoreboard.stream_lists` per :func:`stream_pieces` piece."""
    lists, runs = [], []
    for piece in stream_pieces(cfg, steps):
        a, b = piece.start, piece.stop
        expect = expected_stream(piece.cfg, beats.pixel[a:b], beats.first[a:b],
                                 {i - a: codes for i, codes in piece.lut_changes.items()})
        lists += stream_lists(piece.cfg, expect.fields)
        runs += [(run, piece.cfg.segment_frames) for run in expect.runs]
    return lists, runs
