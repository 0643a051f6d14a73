"""Bit layouts of the segmenter's output stream ``candidates``, pack/unpack helpers, and the
bits-per-segment figure (``docs/arithmetic.md`` §6.6, ``docs/gateware.md`` "Segmenter").

The segmenter hands the DSP, per segment, a list of candidate records followed by one
trailer word. Both share one stream payload (:func:`candidate_layout`): a ``body`` that is
either a record or a trailer, and the ``end_of_list`` bit that marks the trailer. Like
:mod:`dptbd.hw.layouts`, these are the only definitions: the gateware builds its port from
them and the testbenches (Amaranth and cocotb) pack and unpack with the same functions.
"""

from __future__ import annotations

import dataclasses
import functools

from amaranth.hdl import Shape, unsigned
from amaranth.lib import data

from dptbd.config import DPConfig
from dptbd.hw.layouts import field_offsets, pack, state_word_layout, unpack

__all__ = [
    "RECORD_FIELDS",
    "TRAILER_FIELDS",
    "record_layout",
    "trailer_layout",
    "candidate_layout",
    "candidate_field_offsets",
    "pack_record",
    "pack_trailer",
    "pack_cut_trailer",
    "unpack_candidate",
    "SegmentBits",
    "bits_per_segment",
]

#: Fields of a candidate record, in layout order.
RECORD_FIELDS = ("row", "col", "energy", "direction")
#: Fields of a trailer, in layout order: those of ``dptbd.model.segmentation`` (same names),
#: then ``cut``, which only ``dptbd_axi`` sets (a list closed by a soft reset).
TRAILER_FIELDS = ("count", "threshold", "overflow", "primed", "aligned", "missed", "cut")


def _width(value_range: range) -> int:
    return Shape.cast(value_range).width


@functools.lru_cache(maxsize=64)    # one layout per configuration: packing a word is hot
def record_layout(cfg: DPConfig) -> data.StructLayout:
    """One candidate point, (row, col, E, d).

    ========= ================ ====================================================
    field     width            meaning
    ========= ================ ====================================================
    row       ceil(log2 H)     y, 0 … H-1
    col       ceil(log2 W)     x, 0 … W-1
    energy    B_E              accumulated energy E of the pixel
    direction B_d              its arrival move d (0 … M-1, START = M)
    ========= ================ ====================================================
    """
    return data.StructLayout({
        "row": unsigned(_width(range(cfg.height))),
        "col": unsigned(_width(range(cfg.width))),
        "energy": unsigned(cfg.energy_bits),
        "direction": unsigned(cfg.direction_bits),
    })


@functools.lru_cache(maxsize=64)    # one layout per configuration: packing a word is hot
def trailer_layout(cfg: DPConfig) -> data.StructLayout:
    """The last word of every list.

    ========= ================ ==========================================================
    field     width            meaning
    ========= ================ ==========================================================
    count     ceil(log2(C+1))  records in this list, 0 … C
    threshold b + 1            threshold bin T used: records have min(E >> s, 2^b-1) >= T
    overflow  1                more than C pixels reached T; those after the C-th dropped
    primed    1                T came from a histogram (0: first list after reset, empty)
    aligned   1                the frame ended with end_of_segment where expected
    missed    1                a segment end was seen outside a scored frame since the
                               previous list (a list was lost to a resynchronisation)
    cut       1                the list was cut by ``CONTROL.soft_reset`` of ``dptbd_axi``:
                               ``count`` = the records sent before it, every other field 0
                               (always 0 from the segmenter itself)
    ========= ================ ==========================================================
    """
    return data.StructLayout({
        "count": unsigned(_width(range(cfg.record_capacity + 1))),
        "threshold": unsigned(cfg.threshold_bits),
        "overflow": unsigned(1),
        "primed": unsigned(1),
        "aligned": unsigned(1),
        "missed": unsigned(1),
        "cut": unsigned(1),
    })


@functools.lru_cache(maxsize=64)    # one layout per configuration: packing a word is hot
def candidate_layout(cfg: DPConfig) -> data.StructLayout:
    """Payload of the output stream ``candidates``: ``body`` (a record or a trailer, both
    from bit 0) and ``end_of_list`` (1: the body is the list's trailer) above it."""
    return data.StructLayout({
        "body": data.UnionLayout({"record": record_layout(cfg), "trailer": trailer_layout(cfg)}),
        "end_of_list": unsigned(1),
    })


def candidate_field_offsets(cfg: DPConfig) -> dict[str, dict]:
    """``{"record": {...}, "trailer": {...}, "end_of_list": {...}}`` bit fields of a payload
    (offsets from bit 0 of the payload), for manifests and HDL testbenches."""
    body = candidate_layout(cfg)["body"]
    return {
        "record": field_offsets(record_layout(cfg)),
        "trailer": field_offsets(trailer_layout(cfg)),
        "end_of_list": {"offset": body.width, "width": 1},
    }


@functools.lru_cache(maxsize=64)
def _body_width(cfg: DPConfig) -> int:
    return candidate_layout(cfg)["body"].width


def pack_record(cfg: DPConfig, row: int, col: int, energy: int, direction: int) -> int:
    """The ``candidates`` payload of a record (``end_of_list`` = 0)."""
    return pack(record_layout(cfg), {"row": row, "col": col, "energy": energy,
                                     "direction": direction}, "record")


def pack_trailer(cfg: DPConfig, **fields: int) -> int:
    """The ``candidates`` payload of a trailer (``end_of_list`` = 1); every field of
    :func:`trailer_layout` must be given (a model list's ``trailer`` with ``cut=0``)."""
    return pack(trailer_layout(cfg), fields, "trailer") | (1 << _body_width(cfg))


def pack_cut_trailer(cfg: DPConfig, count: int) -> int:
    """The trailer ``dptbd_axi`` sends to close a list cut by a soft reset after ``count``
    records: ``cut`` = 1, ``count``, every other field 0."""
    return pack_trailer(cfg, **{**{name: 0 for name in TRAILER_FIELDS}, "count": count,
                                "cut": 1})


def unpack_candidate(cfg: DPConfig, word: int) -> tuple[str, dict[str, int]]:
    """``("record", {row, col, energy, direction})`` or ``("trailer", {count, …})``."""
    body_width = candidate_layout(cfg)["body"].width
    if (int(word) >> body_width) & 1:
        return "trailer", unpack(trailer_layout(cfg), word)
    return "record", unpack(record_layout(cfg), word)


@dataclasses.dataclass(frozen=True)
class SegmentBits:
    """Bits per segment: the whole accumulated image against the candidate list.

    Attributes
    ----------
    image : int
        W*H*(B_E + B_d): every (E, d) of the segment's accumulated image.
    record, trailer : int
        Bits of the record and trailer fields.
    word : int
        Width of one ``candidates`` payload (body + ``end_of_list``).
    nominal : int
        (n + 1) words: n records and the trailer.
    worst : int
        (C + 1) words: a full list.
    """

    image: int
    record: int
    trailer: int
    word: int
    nominal: int
    worst: int

    @property
    def reduction(self) -> float:
        """``image / nominal``."""
        return self.image / self.nominal

    @property
    def worst_reduction(self) -> float:
        """``image / worst``."""
        return self.image / self.worst

    def for_count(self, records: float) -> float:
        """Bits of a list of ``records`` records (may be a mean): ``(records + 1) * word``."""
        return (records + 1) * self.word


def bits_per_segment(cfg: DPConfig) -> SegmentBits:
    """Bits the FPGA sends the DSP per segment, from the layouts (§6.6).

    For the defaults (128 x 128, B_E = 16, r = 1, n = 33, C = 66): the image is
    16384 * 20 = 327 680 bits; a record is 34 bits, a payload word 35; a list of n records
    and its trailer is 34 * 35 = 1190 bits (275x fewer), a full list 67 * 35 = 2345 bits
    (140x fewer).
    """
    image = cfg.width * cfg.height * data.Layout.cast(state_word_layout(cfg)).size
    word = data.Layout.cast(candidate_layout(cfg)).size
    return SegmentBits(
        image=image,
        record=record_layout(cfg).size,
        trailer=trailer_layout(cfg).size,
        word=word,
        nominal=(cfg.n_candidates + 1) * word,
        worst=(cfg.record_capacity + 1) * word,
    )
