"""What the ``candidates`` stream must carry, and the comparison that names the first
mismatching segment, record and field.

Plain numpy and Python (no cocotb import), used by the cocotb test
(:mod:`dptbd.sim.benches.segmenter`) and the Amaranth-simulator tests alike. Words are packed
with :mod:`dptbd.hw.candidate_layout`, never with hand-written bit positions.
:class:`CandidateScoreboard` is the ``candidates`` stream's
:class:`~dptbd.sim.checker.InOrderChecker`.

The expectation comes from the golden models: :func:`dptbd.sim.scoreboard.model_frames`
(the DP, frame by frame from reset) and :func:`dptbd.model.segmentation.segment_sequence`
(the segmenter, ``docs/arithmetic.md`` §6) on the accumulated image of every whole segment.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from amaranth.lib import data

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import (
    RECORD_FIELDS,
    TRAILER_FIELDS,
    candidate_layout,
    pack_record,
    pack_trailer,
    unpack_candidate,
)
from dptbd.model.segmentation import CandidateList, segment_sequence, segment_stream
from dptbd.sim.checker import InOrderChecker, describe_field_mismatch, differing_fields
from dptbd.sim.scoreboard import model_frames

__all__ = [
    "segment_images",
    "expected_lists",
    "state_stream",
    "list_words",
    "CandidateMismatch",
    "CandidateScoreboard",
    "stream_lists",
]


def segment_images(cfg: DPConfig, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Accumulated images and direction maps ``(S, H, W)`` of the whole segments of
    ``frames`` (segments of K from frame 0, as the gateware counts them from reset)."""
    k = cfg.segment_frames
    energy, direction = [], []
    for t, (e, d) in enumerate(model_frames(cfg, np.asarray(frames))):
        if t % k == k - 1:
            energy.append(e)
            direction.append(d)
    shape = (0, cfg.height, cfg.width)
    return (np.array(energy, dtype=np.int64).reshape(-1, cfg.height, cfg.width) if energy
            else np.zeros(shape, np.int64),
            np.array(direction, dtype=np.int64).reshape(-1, cfg.height, cfg.width) if direction
            else np.zeros(shape, np.int64))


def expected_lists(cfg: DPConfig, frames: np.ndarray) -> list[CandidateList]:
    """The segmenter's list for every whole segment of ``frames``, from reset."""
    energy, direction = segment_images(cfg, frames)
    return segment_sequence(energy, direction, cfg)


def state_stream(cfg: DPConfig, frames: np.ndarray) -> np.ndarray:
    """Every ``states`` word of ``frames`` as ``(T*H*W, 5)`` int64 rows
    (E, d, end_of_line, end_of_frame, end_of_segment), in stream order."""
    frames = np.asarray(frames)
    n_frames = len(frames)
    h, w, k = cfg.height, cfg.width, cfg.segment_frames
    out = np.zeros((n_frames, h, w, 5), dtype=np.int64)
    for t, (e, d) in enumerate(model_frames(cfg, frames)):
        out[t, ..., 0] = e
        out[t, ..., 1] = d
        out[t, :, -1, 2] = 1
        out[t, -1, -1, 3] = 1
        out[t, -1, -1, 4] = int(t % k == k - 1)
    return out.reshape(-1, 5)


def list_words(cfg: DPConfig, lists: list[CandidateList]) -> list[list[int]]:
    """The packed ``candidates`` payloads of each list: its records, then its trailer
    (``cut`` = 0, but for a list cut by a soft reset: :class:`dptbd.sim.axi.stimulus.CutList`)."""
    out = []
    for lst in lists:
        words = [pack_record(cfg, *(int(r[f]) for f in RECORD_FIELDS)) for r in lst.records]
        if getattr(lst, "closed", True):        # a list abandoned by aresetn has none
            words.append(pack_trailer(cfg, **lst.trailer, cut=int(getattr(lst, "cut", 0))))
        out.append(words)
    return out


@dataclasses.dataclass(frozen=True)
class CandidateMismatch:
    """The first ``candidates`` word that differs from the model."""

    index: int                 # position in the output stream (0 = first word after reset)
    segment: int               # list number (0 = first list after reset)
    position: int              # word within the list (records 0 … count-1, then the trailer)
    expected_kind: str         # "record" or "trailer"
    got_kind: str
    fields: tuple[str, ...]    # differing fields (layout order), or ("kind",)
    got: dict
    expected: dict

    def __str__(self) -> str:
        where = (f"segment {self.segment}, "
                 + (f"record {self.position}" if self.expected_kind == "record"
                    else f"trailer (after {self.position} records)"))
        if self.fields == ("kind",):
            return (f"first mismatch at output word {self.index}: {where}: expected a "
                    f"{self.expected_kind} {self.expected}, got a {self.got_kind} {self.got}")
        return (f"first mismatch at output word {self.index}: {where}, "
                + describe_field_mismatch(self.fields, self.got, self.expected))


class CandidateScoreboard(InOrderChecker):
    """Compares the ``candidates`` stream word by word with the model's lists; stops at the
    first mismatch and reports the segment, the record and the field
    (:class:`CandidateMismatch`).

    Parameters
    ----------
    cfg : DPConfig
    lists : list of CandidateList
        The expected lists (:func:`expected_lists`).

    Attributes
    ----------
    segments_done : int
        Lists received whole (trailer included) and bit-exact.
    """

    def __init__(self, cfg: DPConfig, lists: list[CandidateList]):
        self.cfg = cfg
        self.lists = list(lists)
        words, self._positions, trailer = [], [], []
        for segment, list_of_words in enumerate(list_words(cfg, self.lists)):
            for position, word in enumerate(list_of_words):
                words.append(word)
                self._positions.append((segment, position))
                trailer.append(position == len(list_of_words) - 1)
        wide = data.Layout.cast(candidate_layout(cfg)).size > 64
        super().__init__(np.array(words, dtype=object if wide else np.uint64))
        self._trailer = np.array(trailer, dtype=bool)
        self.segments_done = 0

    def corrupt_word(self, index: int, xor: int) -> None:
        """Flip bits of expected word ``index`` (the checker's self-check: it must fail)."""
        word = int(self._expected[index]) ^ int(xor)
        self._expected[index] = word
        self._trailer[index] = unpack_candidate(self.cfg, word)[0] == "trailer"

    @property
    def records_expected(self) -> int:
        return sum(lst.count for lst in self.lists)

    def compare(self, index: int, got: int, want: int) -> CandidateMismatch:
        segment, position = self._positions[index]
        want_kind, want_f = unpack_candidate(self.cfg, want)
        got_kind, got_f = unpack_candidate(self.cfg, got)
        if got_kind != want_kind:
            fields: tuple[str, ...] = ("kind",)
        else:
            names = RECORD_FIELDS if want_kind == "record" else TRAILER_FIELDS
            fields = differing_fields(names, got, want, got_f, want_f)
        return CandidateMismatch(index, segment, position, want_kind, got_kind, fields,
                                 got_f, want_f)

    def matched(self, start: int, stop: int) -> None:
        self.segments_done += int(np.count_nonzero(self._trailer[start:stop]))

    def expected_summary(self) -> str:
        return f"{len(self.lists)} lists"

    def received_summary(self) -> str:
        return f" ({self.segments_done} of {len(self.lists)} lists)"

    def exact_summary(self) -> str:
        return (f"{len(self.lists)} lists, {self.records_expected} records, "
                f"{self.count} words")


def stream_lists(cfg: DPConfig, states: np.ndarray) -> list[CandidateList]:
    """The lists for an arbitrary ``states`` stream ``(N, 5)`` (e.g. a truncated one):
    :func:`dptbd.model.segmentation.segment_stream`."""
    return segment_stream(states, cfg)
