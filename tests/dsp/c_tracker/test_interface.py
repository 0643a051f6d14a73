"""The association firmware's interface: the tracker class, the model's refusals, clipped
lists and dropped coordinates counted, bad contexts refused, the context's memory, the
128-bit paths and the integer helpers against Python."""

import ctypes
import math

import numpy as np
import pytest

from dptbd.dsp.association import AssociationConfig, AssociationError, Tracker
from dptbd.dsp.c_tracker import (CTracker, FirmwareError, _Candidate, _Params, load_firmware,
                                 params_codes, tracker_class)
from helpers.firmware_runs import KW, assert_same, assert_same_costs, probe, recs, run_both


def test_tracker_class():
    assert tracker_class("python") is Tracker
    assert tracker_class("c") is CTracker
    with pytest.raises(ValueError, match=r"^dsp must be one of python, c, got 'dsp'$"):
        tracker_class("dsp")


def test_refusals_are_the_models():
    c = CTracker(AssociationConfig(max_candidates=2), **KW)
    with pytest.raises(AssociationError, match=r"^3 candidates in one segment but the input "
                                               r"buffer holds max_candidates=2$"):
        c.step(recs([(1, 1, 1, 0, 1, 1, 1)] * 3))
    with pytest.raises(AssociationError, match=r"^candidates must be CANDIDATE_DTYPE records "
                                               r"\(make_candidates\), got dtype int64$"):
        c.step(np.zeros(2, dtype=np.int64))
    with pytest.raises(AssociationError, match=r"^the C firmware needs segment_stride in "
                                               r"\[1, 1024\], got 2000$"):
        CTracker(AssociationConfig(), **{**KW, "segment_stride": 2000})


def test_list_longer_than_capacity_is_clipped_with_a_counter():
    assoc = AssociationConfig(max_candidates=4)
    items = recs([(10 * i, 10 * i, 100 + i, 4, 10 * i, 10 * i, 1) for i in range(6)])
    py, c = Tracker(assoc, **KW), CTracker(assoc, **KW)
    assert c.step_raw(items) == 1                     # DPTBD_W_CLIPPED
    py.step(items[:4])
    assert_same(py, c, "clipped")
    assert c.input_counters == {"clipped_candidates": 2, "rejected_candidates": 0}


def test_coordinates_outside_the_frame_are_dropped_with_a_counter():
    kw = {**KW, "height": 50, "width": 60}
    items = recs([(10, 10, 100, 4, 10, 10, 1), (50, 5, 100, 4, 50, 5, 1), (5, 60, 100, 4, 5, 5, 1),
                  (5, 5, 100, 4, 70, 5, 1), (20, 20, 100, 4, 70, 70, 0)])
    py, c = Tracker(AssociationConfig(), **kw), CTracker(AssociationConfig(), **kw)
    assert c.step_raw(items) == 2                     # DPTBD_W_REJECTED
    py.step(items[[0, 4]])
    assert_same(py, c, "rejected")
    assert c.input_counters == {"clipped_candidates": 0, "rejected_candidates": 3}


def test_null_and_uninitialised_contexts_are_refused():
    lib = load_firmware()
    one = (_Candidate * 1)()
    assert lib.dptbd_track_step(None, one, 1, None) == -1
    assert lib.dptbd_track_init(None, None) == -1
    c = CTracker(AssociationConfig(), **KW)
    assert lib.dptbd_track_step(ctypes.byref(c._ctx), None, 1, None) == -1
    blank = type(c._ctx)()                            # zeroed: never initialised
    assert lib.dptbd_track_step(ctypes.byref(blank), one, 1, None) == -3
    bad = _Params(**{**params_codes(c, 1), "confirm_hits": 1, "predict_hits": 2})
    assert lib.dptbd_track_init(ctypes.byref(blank), ctypes.byref(bad)) == -2
    for wrong in ({"confirm_gap": 0}, {"wake_radius": 17}, {"wake_points": 0}):
        bad = _Params(**{**params_codes(c, 1), **wrong})
        assert lib.dptbd_track_init(ctypes.byref(blank), ctypes.byref(bad)) == -2, wrong
    c._ctx.segment = 2 ** 31 - 1
    with pytest.raises(FirmwareError, match=r"^dptbd_track_step returned DPTBD_E_SEGMENTS$"):
        c.step(recs([]))


def test_context_memory_of_the_default_capacities():
    lib = load_firmware()
    # records 64 x 72 B, histories 64 x 64 x 20 B, the same for the archive, input buffer
    # and scratch: docs/dsp_firmware.md quotes this figure
    assert lib.dptbd_track_context_bytes() == 177344


def test_extreme_headings_use_the_128_bit_paths():
    """|v|^2 |h|^2 beyond 2^64 (the integer square root) and heading_weight * (|v||h| - v.h)
    beyond 2^64 (the long division): the C's 128-bit helpers against Python's integers."""
    kw = dict(segment_frames=2, segment_stride=1024, height=65536, width=65536, radius=1)
    assoc = AssociationConfig(heading_weight=100.0, seed_gate=1000.0, gate_base=1000.0,
                              gate_max=1000.0, merge_radius=0, duplicate_radius=0)
    lists = [recs([(1000, 1000, 900, 4, 968, 968, 1)]),      # heading 32 px x 1024 per segment
             recs([(33768, 33768, 900, 4, 65535, 65535, 1),  # reversed, very long path
                   (33760, 33770, 900, 4, 0, 65535, 1),
                   (33775, 33768, 900, 4, 2, 3, 1)])]
    py, c = run_both(assoc, kw, lists[:1])
    v = (int(py.tracks["v_row"][0]), int(py.tracks["v_col"][0]))
    h = ((33768 - 65535) * 16 * 1024, (33768 - 65535) * 16 * 1024)
    v2h2 = (v[0] ** 2 + v[1] ** 2) * (h[0] ** 2 + h[1] ** 2)
    norm = math.isqrt(v2h2)
    assert v2h2 >= 2 ** 64 and py.heading_weight * (norm - (v[0] * h[0] + v[1] * h[1])) >= 2 ** 64
    for cands in lists[1:]:
        py.step(cands)
        c.step(cands)
        assert_same(py, c, "extreme")
        assert_same_costs(py, c, "extreme")
    assert c.stats["matched"] == 1


def test_integer_helpers_match_python():
    lib = probe()
    rng = np.random.default_rng(0)
    values = [0, 1, 2, 3, 4, 2 ** 64 - 1, 2 ** 64, 2 ** 126, 2 ** 128 - 1]
    values += [r * r + d for r in (2 ** 32 - 1, 2 ** 32, 2 ** 63, 2 ** 64 - 1) for d in (-1, 0, 1)]
    values += [int(rng.integers(0, 2 ** 62)) * int(rng.integers(0, 2 ** 62)) for _ in range(300)]
    for a in values:
        a = min(max(a, 0), 2 ** 128 - 1)
        assert lib.probe_isqrt(a >> 64, a & (2 ** 64 - 1)) == math.isqrt(a), a
    for _ in range(300):
        c = int(rng.integers(1, 2 ** 62))
        a, b = int(rng.integers(0, 2 ** 15)), int(rng.integers(0, 2 * c + 1))
        assert lib.probe_mul_div(a, b, c) == a * b // c
    for a in (-7, -6, -5, -1, 0, 1, 5, 6, 7, -(2 ** 40) - 1, 2 ** 40 + 3):
        for b in (1, 2, 3, 5, 2 ** 20):
            assert lib.probe_div_round(a, b) == (2 * a + b) // (2 * b)
