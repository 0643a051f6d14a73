"""The ``candidates`` payload layout, its pack/unpack helpers and the bits-per-segment figure
(docs/arithmetic.md §6.6)."""

import numpy as np
import pytest
from amaranth.lib import data

from dptbd.config import DPConfig
from dptbd.hw.candidate_layout import (
    RECORD_FIELDS,
    TRAILER_FIELDS,
    bits_per_segment,
    candidate_field_offsets,
    candidate_layout,
    pack_record,
    pack_cut_trailer,
    pack_trailer,
    record_layout,
    trailer_layout,
    unpack_candidate,
)
from dptbd.model.segmentation import TRAILER_FIELDS as MODEL_TRAILER_FIELDS


def test_default_widths():
    cfg = DPConfig()
    assert {n: f.width for n, f in record_layout(cfg)} == {
        "row": 7, "col": 7, "energy": 16, "direction": 4}
    assert {n: f.width for n, f in trailer_layout(cfg)} == {
        "count": 7, "threshold": 11, "overflow": 1, "primed": 1, "aligned": 1, "missed": 1,
        "cut": 1}
    assert data.Layout.cast(candidate_layout(cfg)).size == 35
    assert tuple(n for n, _ in record_layout(cfg)) == RECORD_FIELDS
    # the model's trailer fields, then cut (only dptbd_axi sets it: a soft reset's close)
    assert tuple(n for n, _ in trailer_layout(cfg)) == TRAILER_FIELDS == (*MODEL_TRAILER_FIELDS,
                                                                            "cut")
    offsets = candidate_field_offsets(cfg)
    assert offsets["end_of_list"] == {"offset": 34, "width": 1}
    assert offsets["record"]["direction"] == {"offset": 30, "width": 4}


def test_bits_per_segment_128x128_paper_count():
    """001's 128 x 128 at 0.2 % (n = 33): 275x fewer bits than the whole image per segment
    (140x for a full list of C = 66)."""
    bits = bits_per_segment(DPConfig())
    assert bits.image == 128 * 128 * (16 + 4) == 327_680
    assert (bits.record, bits.trailer, bits.word) == (34, 23, 35)
    assert bits.nominal == 34 * 35 == 1190
    assert bits.worst == 67 * 35 == 2345
    assert round(bits.reduction, 1) == 275.4
    assert round(bits.worst_reduction, 1) == 139.7
    assert bits.for_count(19.0) == 700.0


def test_bits_per_segment_other_sizes():
    bits = bits_per_segment(DPConfig(width=256, height=256, radius=2, segment_frames=6))
    # 131 points (0.2 % of 65536), C = 262: row/col 8 bits, d 5 bits, count 9, T 11
    assert (bits.record, bits.trailer, bits.word) == (37, 25, 38)
    assert bits.image == 65536 * 21
    assert bits.nominal == 132 * 38


def test_pack_unpack_round_trip():
    cfg = DPConfig(width=13, height=7, candidate_count=5, histogram_bits=6)
    rng = np.random.default_rng(0)
    for _ in range(50):
        rec = dict(row=int(rng.integers(7)), col=int(rng.integers(13)),
                   energy=int(rng.integers(cfg.e_max + 1)), direction=int(rng.integers(10)))
        assert unpack_candidate(cfg, pack_record(cfg, **rec)) == ("record", rec)
        trl = dict(count=int(rng.integers(11)), threshold=int(rng.integers(65)),
                   overflow=int(rng.integers(2)), primed=int(rng.integers(2)),
                   aligned=int(rng.integers(2)), missed=int(rng.integers(2)),
                   cut=int(rng.integers(2)))
        assert unpack_candidate(cfg, pack_trailer(cfg, **trl)) == ("trailer", trl)


def test_pack_refuses_bad_values():
    cfg = DPConfig(width=8, height=8)
    with pytest.raises(ValueError, match=r"^row=8 does not fit 3 unsigned bits$"):
        pack_record(cfg, 8, 0, 0, 0)
    with pytest.raises(ValueError, match=r"^trailer fields missing \['cut', 'missed'\], unknown "
                                         r"\[\]; the layout has \['count', 'threshold', "
                                         r"'overflow', 'primed', 'aligned', 'missed', 'cut'\]$"):
        pack_trailer(cfg, count=0, threshold=0, overflow=0, primed=0, aligned=0)


def test_cut_trailer():
    """The trailer dptbd_axi closes a cut list with: cut = 1, the records sent, zeros."""
    cfg = DPConfig(width=13, height=7, candidate_count=5, histogram_bits=6)
    kind, fields = unpack_candidate(cfg, pack_cut_trailer(cfg, 3))
    assert kind == "trailer"
    assert fields == {"count": 3, "threshold": 0, "overflow": 0, "primed": 0, "aligned": 0,
                      "missed": 0, "cut": 1}
