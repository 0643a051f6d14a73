"""Beat streams for the AXI top level's video input, with frame-sync faults injected, and
the frame monitor's fault rule as a reference.

Plain numpy (no simulator import): the cocotb bench :mod:`dptbd.sim.benches.axi`, its pytest
driver and the monitor's unit test use it. A stream is three arrays over beats: the pixel,
``first`` (``tuser[0]``, start of frame) and ``last`` (``tlast``, end of line).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from dptbd.config import DPConfig
from dptbd.hw.register_map import FAULTS, register_map
from dptbd.model.segmentation import CandidateList, segment_stream
from dptbd.model.settings import SegmentSettings
from dptbd.sim.stream_model import expected_stream, saturated_events

__all__ = ["FAULT_KINDS", "SETTINGS", "Beats", "clean_beats", "with_fault", "fault_stretches",
           "fault_pulses",
           "fault_counts", "Piece", "Expected", "CutList", "stream_pieces", "expected_outputs"]

#: What :func:`with_fault` can inject, each raising exactly one pulse of its class.
FAULT_KINDS = FAULTS

#: The setting registers, in the order of :class:`~dptbd.model.settings.SegmentSettings`.
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


def fault_stretches(cfg: DPConfig, frames: np.ndarray) -> tuple[Beats, list[int]]:
    """Frames ``(4 + 2 * len(FAULT_KINDS), H, W)`` as beats: four clean frames, then two
    frames with each frame-sync fault in turn (:func:`with_fault`); and the beat where each
    fault's stretch starts."""
    beats, starts = clean_beats(frames[:4]), []
    for i, kind in enumerate(FAULT_KINDS):
        starts.append(len(beats))
        beats = beats + with_fault(cfg, frames[4 + 2 * i:6 + 2 * i], kind)
    return beats, starts


def _prefix(beats: Beats, n: int) -> Beats:
    return Beats(beats.pixel[:n].copy(), beats.first[:n].copy(), beats.last[:n].copy())


def fault_pulses(cfg: DPConfig, first, last, *, no_sof: bool = False) -> list[dict[str, int]]:
    """The frame monitor's fault pulses for every beat (``docs/integration.md``): the
    core's counting rule for frames (an unexpected start of frame restarts the counters, a
    missing one is ignored, and is no fault with ``no_sof``), and one ``line_length`` per
    line (beats up to ``tlast``, a start of frame begins a new one) whose length is not W."""
    width, height = cfg.width, cfg.height
    col = row = 0
    run = 0                             # beats of the current line so far
    at_start = True
    out = []
    for f, lst in zip(first, last):
        restart = bool(f) and not at_start
        pulses = {"sof_unexpected": restart and col != 0, "frame_short": restart and col == 0,
                  "frame_long": at_start and not f and not no_sof}
        if restart:
            col = row = 0
        index = 0 if f else run
        pulses["line_length"] = (bool(lst) and index < width - 1) or index == width
        run = 0 if lst else index + 1
        out.append({k: int(v) for k, v in pulses.items()})
        at_start = col == width - 1 and row == height - 1
        if col == width - 1:
            col, row = 0, (0 if row == height - 1 else row + 1)
        else:
            col += 1
    return out


def fault_counts(cfg: DPConfig, beats: Beats, *, no_sof: bool = False) -> dict[str, int]:
    """Total pulses per fault class of a stream (what the FAULT_* counters must read)."""
    pulses = fault_pulses(cfg, beats.first, beats.last, no_sof=no_sof)
    return {k: sum(p[k] for p in pulses) for k in FAULTS}


@dataclasses.dataclass(frozen=True)
class Piece:
    """Beats ``[start, stop)`` that the core processes from reset, with LUT writes
    (``lut_changes``) and run-time settings written (``settings_changes``) just before the
    beats at their absolute indices."""

    start: int
    stop: int
    lut_changes: dict
    settings_changes: dict


@dataclasses.dataclass(frozen=True)
class Expected:
    """What the golden model says the whole stream gives: the candidate lists, the counts
    the FRAMES, SEGMENTS, LISTS and SATURATED registers must read, and the ``states`` stream
    (``m_axis_state``): packed words, their (frame, row, column) and whether each starts a
    frame (``tuser[0]``: the first word after a reset or soft reset, or the word after an
    end of frame)."""

    lists: list
    frames: int
    segments: int
    saturated: int
    state_words: np.ndarray = None
    state_positions: np.ndarray = None
    state_first: np.ndarray = None
    list_starts: tuple = ()      # per list: the first beat of the piece it belongs to
    open_records: tuple = ()     # packed records of a list the stream's end leaves open

    def counters(self) -> dict[str, int]:
        return {"FRAMES": self.frames, "SEGMENTS": self.segments,
                "LISTS": sum(not isinstance(lst, CutList) for lst in self.lists),
                "SATURATED": self.saturated}


def stream_pieces(cfg: DPConfig, steps: list[dict]) -> list[Piece]:
    """Cut a bench's steps (:mod:`dptbd.sim.benches.axi`) into pieces at every ``soft_reset`` and
    ``aresetn``.

    A step's writes to a setting register (``SEGMENT_FRAMES``, ``CANDIDATE_COUNT``,
    ``HISTOGRAM_SHIFT``) that the register block takes (refused values are ignored, as the
    gateware ignores them), its ``lut_codes`` and its taken ``lut_writes`` (``[p, m, code,
    wstrb]``: ``wstrb`` = 0xF and the code in [0, 2**F]) apply from the step's first beat on. A soft
    reset keeps the registers (the settings are sampled again at the next segment start)
    and the LUT (a memory); ``aresetn`` (held low before the step's writes) returns the
    settings to the build values and keeps the LUT.
    """
    limits = {name: register_map(cfg)[name].fields[0].limits for name in SETTINGS}
    current = dataclasses.astuple(SegmentSettings.defaults(cfg))
    pieces, lo, start, lut = [], 0, 0, None
    luts, settings = {}, {}
    for step in steps:
        if (step.get("soft_reset") or step.get("aresetn")) and start > lo:
            pieces.append(Piece(lo, start, luts, settings))
            lo = start
            luts = {start: lut} if lut is not None else {}
            settings = {start: SegmentSettings(*current)}
        if step.get("aresetn"):             # the registers return to the build values
            current = dataclasses.astuple(SegmentSettings.defaults(cfg))
            settings[start] = SegmentSettings(*current)
        values = dict(zip(SETTINGS, current))
        for name, value in step.get("writes", []):
            if name in SETTINGS and limits[name][0] <= value <= limits[name][1]:
                values[name] = int(value)
        if tuple(values.values()) != current:
            current = tuple(values.values())
            settings[start] = SegmentSettings(*current)
        if step.get("lut_codes") is not None:
            lut = step["lut_codes"]
            luts[start] = lut
        taken = [(p, m, code) for p, m, code, strobe in step.get("lut_writes", [])
                 if strobe == 0xF and 0 <= code <= 1 << cfg.weight_frac_bits]
        if taken:                       # single entries over the table in force
            lut = np.array(cfg.weight_codes if lut is None else lut, dtype=np.int64)
            for p, m, code in taken:
                lut[p, m] = code
            lut = lut.tolist()
            luts[start] = lut
        start = step["stop"]
    pieces.append(Piece(lo, start, luts, settings))
    return pieces


@dataclasses.dataclass(frozen=True)
class CutList(CandidateList):
    """A list closed by a soft reset (``docs/integration.md``): the records sent before it,
    then the cut trailer (``cut`` = 1, ``count``, every other field 0). ``drained``: the
    soft reset waited for the outputs of every beat before it (then exactly these records
    are sent); else words in flight are lost and a prefix of them is sent."""

    cut: int = 1
    drained: bool = True
    closed: bool = True          # False: abandoned by aresetn, no trailer

    @property
    def trailer(self) -> dict[str, int]:
        return {**{name: 0 for name in super().trailer}, "count": int(self.count)}


def _cut_list(cfg: DPConfig, piece: Piece, beats: Beats, expect, lists: list,
              drained: bool = True, closed: bool = True):
    """The list the segmenter has open after the piece's words, as a :class:`CutList` of
    the records sent so far; ``None`` if no list is open or it has no record yet.

    The segmenter's own counters decide (they may differ from the DP input's after a
    fault): one more word with ``end_of_segment`` ends an open list there, and the model's
    list then holds the records so far, and the extra word's own record if its bin reached
    T. That one is told apart by a second extra word of other E and d."""
    if not len(expect.fields):
        return None

    def ended_by(energy: int, direction: int):
        fields = np.vstack([expect.fields, [[energy, direction, 0, 0, 1]]])
        settings = (None if expect.settings is None
                    else np.vstack([expect.settings, expect.settings[-1:]]))
        more = segment_stream(fields, cfg, settings)
        return more[len(lists)] if len(more) > len(lists) else None

    last = ended_by(0, 0)
    if last is None or not len(last.records):
        return None
    kept = last.records
    if int(kept[-1]["energy"]) == 0 and int(kept[-1]["direction"]) == 0:
        other = ended_by(cfg.e_max, 1).records
        if tuple(other[-1]) != tuple(kept[-1]):          # the extra word's own record
            kept = kept[:-1]
    if not len(kept):
        return None
    return CutList(**{**{f.name: getattr(last, f.name) for f in
                         dataclasses.fields(CandidateList)}, "records": kept,
                      "count": len(kept), "drained": drained, "closed": closed})


def expected_outputs(cfg: DPConfig, beats: Beats, steps: list[dict], *,
                     cut_lists: bool = False) -> Expected:
    """The golden model of the whole stream, piece by piece (:func:`stream_pieces`):
    :func:`~dptbd.sim.stream_model.expected_stream` for the states and
    :func:`~dptbd.model.segmentation.segment_stream` for the lists, with the settings
    sampled as the gateware samples them. With ``cut_lists`` a soft reset's pipeline is taken
    as drained (the soft reset waits for the last beat's outputs) and the list it cuts, if
    one is open, follows the piece's lists (:class:`CutList`; ``drained`` False for a
    ``soft_reset`` of ``"now"`` and an ``aresetn`` with ``aresetn_wait``, which lose the
    words in flight); without, soft resets are
    taken to land where no list is open. With ``cut_lists``, ``open_records`` are the records
    of the list the stream's end leaves open (sent, never closed)."""
    lists, frames, segments, saturated = [], 0, 0, 0
    words, positions, first = [], [], []
    pieces = stream_pieces(cfg, steps)
    now, hard, lost, start = set(), set(), set(), 0
    for step in steps:
        now |= {start} if step.get("soft_reset") == "now" else set()
        hard |= {start} if step.get("aresetn") else set()
        lost |= {start} if step.get("aresetn") and "aresetn_wait" in step else set()
        start = step["stop"]
    list_starts, open_records = [], ()
    for n, piece in enumerate(pieces):
        a, b = piece.start, piece.stop
        expect = expected_stream(cfg, beats.pixel[a:b], beats.first[a:b],
                                 {i - a: codes for i, codes in piece.lut_changes.items()},
                                 {i - a: st for i, st in piece.settings_changes.items()})
        piece_lists = segment_stream(expect.fields, cfg, expect.settings)
        lists += piece_lists
        if cut_lists and n < len(pieces) - 1:
            cut = _cut_list(cfg, piece, beats, expect, piece_lists,
                            piece.stop not in lost and (piece.stop not in now
                                                        or piece.stop in hard),
                            piece.stop not in hard)
            lists += [cut] if cut is not None else []
        elif cut_lists:                 # the stream ends inside a list: its records so far
            from dptbd.sim.candidate_scoreboard import list_words
            cut = _cut_list(cfg, piece, beats, expect, piece_lists)
            open_records = () if cut is None else tuple(list_words(cfg, [cut])[0][:-1])
        list_starts += [piece.start] * (len(lists) - len(list_starts))
        frames += sum(run.complete for run in expect.runs)
        segments += sum(run.complete and run.frame == run.segment_frames - 1
                        for run in expect.runs)
        saturated += saturated_events(cfg, expect.saturated)
        starts = np.ones(len(expect.words), dtype=bool)
        starts[1:] = expect.fields[:-1, 3] == 1
        offset = positions[-1][-1, 0] + 1 if positions and len(positions[-1]) else 0
        words.append(expect.words)
        positions.append(expect.positions + np.array([offset, 0, 0]))
        first.append(starts)
    return Expected(lists, frames, segments, saturated, np.concatenate(words),
                    np.concatenate(positions), np.concatenate(first), tuple(list_starts),
                    open_records)
