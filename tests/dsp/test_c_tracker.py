"""The association firmware (C) against the Python model, field by field after every segment.

The Python :class:`~dptbd.dsp.association.Tracker` is the reference; :class:`CTracker` runs
each segment in ``dptbd_track.c`` and copies the whole C context (records, histories,
archive, input buffer, scratch, counters) into the same arrays, so every field is compared.
Default suite: 40 seeds of the main job's scenes, other association settings, adversarial
and random lists; ``-m slow``: 1000 more scenes and 500 more random runs.
"""

import ctypes
import functools
import importlib.util
import math
import pathlib

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.dsp.association import (CANDIDATE_DTYPE, AssociationConfig, AssociationError, Tracker)
from dptbd.dsp.backtrack import backtrack
from dptbd.dsp import association
from dptbd.dsp.c_tracker import (CTracker, FirmwareError, _Candidate, _Params, backtrack_starts,
                                 load_firmware, params_codes, tracker_class, trim_to_count)
from dptbd.dsp.firmware import build_shared_library, capacity_defines

ROOT = pathlib.Path(__file__).resolve().parents[2]
STATE = ("tracks", "history", "archive", "archive_history", "inbuf", "_head_row", "_head_col",
         "_keep", "_claimed", "_match", "_class", "_order_tracks")
SCALARS = ("segment", "next_id", "n_archived", "n_in", "stats")


def _example():
    spec = importlib.util.spec_from_file_location(
        "write_candidates", ROOT / "examples" / "dsp_tracker" / "write_candidates.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def assert_same(py, c, where):
    for name in SCALARS:
        assert getattr(py, name) == getattr(c, name), f"{where}: {name}"
    for name in STATE:
        a, b = getattr(py, name), getattr(c, name)
        if a.dtype.names:
            for field in a.dtype.names:
                assert np.array_equal(a[field], b[field]), f"{where}: {name}.{field}"
        else:
            assert np.array_equal(a, b), f"{where}: {name}"
    assert py.active() == c.active()


@functools.lru_cache(maxsize=None)
def probe(capacity=64, max_candidates=128, max_points=64, output_capacity=64):
    """The firmware's internals (tests/dsp/firmware/probe.c) for these capacities."""
    lib = ctypes.CDLL(str(build_shared_library(
        capacity_defines(capacity, max_candidates, max_points, output_capacity),
        sources=[pathlib.Path(__file__).parent / "firmware" / "probe.c"])))
    u64, i64 = ctypes.c_uint64, ctypes.c_int64
    for name, res, args in (("probe_isqrt", u64, [u64, u64]),
                            ("probe_mul_div", u64, [u64, u64, u64]),
                            ("probe_div_round", i64, [i64, i64]),
                            ("probe_cost", i64, [ctypes.c_void_p, ctypes.c_int, ctypes.c_uint32])):
        getattr(lib, name).restype, getattr(lib, name).argtypes = res, args
    return lib


def assert_same_costs(py, c, where):
    """Tracker._cost against the firmware's cost_of for every live track and candidate."""
    cfg = py.cfg
    lib = probe(cfg.capacity, cfg.max_candidates, cfg.max_points, cfg.output_capacity)
    for i in np.flatnonzero(py.tracks["state"] != 0):
        for j in range(py.n_in):
            assert py._cost(int(i), j) == lib.probe_cost(ctypes.byref(c._ctx), int(i), j), \
                f"{where}: cost of candidate {j} for track {i}"


def run_both(assoc, kwargs, lists, where="", costs=False):
    """Both trackers over ``lists``; compared after every segment (and every match cost
    if ``costs``); returns them."""
    py, c = Tracker(assoc, **kwargs), CTracker(assoc, **kwargs)
    for s, cands in enumerate(lists):
        py.step(cands)
        c.step(cands)
        assert_same(py, c, f"{where} segment {s}")
        if costs:
            assert_same_costs(py, c, f"{where} segment {s}")
    assert py.confirmed_tracks() == [] or all(
        a.id == b.id and a.alive == b.alive and np.array_equal(a.points, b.points)
        for a, b in zip(py.confirmed_tracks(), c.confirmed_tracks(), strict=True))
    return py, c


# ---- the main job's scenes ------------------------------------------------------------

def _scenes(seeds, association=None):
    ex = _example()
    for seed in seeds:
        cfg, assoc, kwargs, lists = ex.scene_lists(seed, association)
        yield seed, assoc, kwargs, lists


@pytest.mark.parametrize("first", [0, 10, 20, 30])
def test_bit_exact_on_main_job_scenes(first):
    confirmed = 0
    for seed, assoc, kwargs, lists in _scenes(range(first, first + 10)):
        py, _ = run_both(assoc, kwargs, lists, f"seed {seed}", costs=seed == first)
        confirmed += len(py.confirmed_tracks())
    assert confirmed > 0


@pytest.mark.slow
@pytest.mark.parametrize("first", range(40, 1040, 100))
def test_bit_exact_on_main_job_scenes_slow(first):
    for seed, assoc, kwargs, lists in _scenes(range(first, first + 100)):
        run_both(assoc, kwargs, lists, f"seed {seed}")


@pytest.mark.parametrize("changes", [
    {"reject_reversed": True, "link_gate": 2.0},
    {"confirm_hits": 1, "predict_hits": 1, "merge_radius": 0, "duplicate_radius": 0},
    {"max_points": 3, "output_capacity": 1, "capacity": 16, "heading_weight": 3.5,
     "gate_max": 12.0, "max_misses": 0},
    {"wake_radius": 2, "wake_points": 2},
    {"wake_radius": 3, "wake_points": 70, "max_points": 3},
])
def test_bit_exact_with_other_settings(changes):
    for seed, assoc, kwargs, lists in _scenes(range(3)):
        run_both(assoc.replace(**changes), kwargs, lists, f"seed {seed} {changes}")


@pytest.mark.parametrize("stride, confirm_hits", [(3, 3), (2, 2), (4, 4)])
def test_bit_exact_with_disjoint_confirmation(stride, confirm_hits):
    """confirm_disjoint with overlapping segments (the scenes' K = 6 lists read as ending
    every ``stride`` frames: a hit counts only every ceil(6 / stride) segments)."""
    counted = 0
    for seed, assoc, kwargs, lists in _scenes(range(3)):
        py, c = run_both(assoc.replace(confirm_disjoint=True, confirm_hits=confirm_hits),
                         {**kwargs, "segment_stride": stride}, lists, f"seed {seed} S {stride}")
        assert py.confirm_gap == -(-6 // stride) > 1
        counted += int(np.count_nonzero(py.tracks["counted"] < py.tracks["hits"]))
    assert counted > 0          # some live track had hits that did not count


# ---- adversarial lists -----------------------------------------------------------------

KW = dict(segment_frames=6, segment_stride=6, height=128, width=128, radius=1)


def recs(items):
    return np.array(items, dtype=CANDIDATE_DTYPE)


def test_empty_lists():
    lists = [recs([])] * 5 + [recs([(10, 10, 500, 4, 10, 10, 1)])] + [recs([])] * 10
    py, c = run_both(AssociationConfig(), KW, lists)
    assert c.stats["segments"] == 16 and c.stats["started"] == 1 and c.active() == 0


def test_full_lists_and_record_table_full():
    rng = np.random.default_rng(5)
    assoc = AssociationConfig(capacity=8, max_candidates=32, max_points=4, output_capacity=2,
                              confirm_hits=2, predict_hits=1, max_misses=6, delete_ratio=0.1,
                              predict_ratio=0.1, confirm_ratio=0.3)
    lists = []
    for s in range(30):
        items = [(20 + s, 20 + s, 5000, 8, 20 + s, 20 + s - 1, 1), (90 - s, 30 + s, 5000, 0,
                                                                   91 - s, 29 + s, 1)]
        while len(items) < 32:
            r, col = (int(v) for v in rng.integers(0, 128, 2))
            items.append((r, col, int(rng.integers(100, 300)), int(rng.integers(0, 10)), r, col,
                          int(rng.integers(0, 2))))
        lists.append(recs(items))
    py, c = run_both(assoc, KW, lists)
    for name in ("dropped_candidates", "history_wrapped", "dropped_outputs"):
        assert c.stats[name] > 0, name
    assert c.stats["peak_active"] == 8


def test_all_candidates_in_one_gate():
    lists = []
    for s in range(12):
        r, col = 30 + 3 * s, 40 + 2 * s
        lists.append(recs([(r + dr, col + dc, 1000 + 7 * ((dr + dc) % 3), (dr + 1) * 3 + dc + 1,
                            r + dr - 3, col + dc - 2, 1)
                           for dr in (-1, 0, 1) for dc in (-1, 0, 1)]))
    for merge in (0, 1):
        run_both(AssociationConfig(merge_radius=merge, duplicate_radius=0), KW, lists)


def test_tracks_at_the_border_and_leaving_the_image():
    lists = []
    for s in range(20):
        lists.append(recs([(0, min(127, 4 * s), 900, 5, 0, max(0, 4 * s - 4), 1),
                           (127, max(0, 127 - 5 * s), 900, 3, 127, min(127, 132 - 5 * s), 1),
                           (min(127, 100 + 3 * s), 127, 950, 7, min(127, 97 + 3 * s), 127, 1),
                           (s % 128, 0, 800, 4, 0, 0, 0)]
                          + ([(64, 60 + 10 * s, 990, 5, 64, 52 + 10 * s, 1),     # runs out
                              (70 + 10 * s, 3, 980, 7, 62 + 10 * s, 3, 1)] if s <= 5 else [])))
    py, c = run_both(AssociationConfig(), KW, lists)
    assert c.stats["left_image"] > 0


# ---- random streams --------------------------------------------------------------------

def random_run(seed):
    """Random parameters, geometry and candidate stream: moving targets (sometimes fast,
    with paths from anywhere), clutter, tied energies, codes beyond the moves."""
    rng = np.random.default_rng(seed)
    big = seed % 4 == 3                                     # 65536 x 65536, huge headings
    k = int(rng.integers(1, 9))
    kwargs = dict(segment_frames=k, segment_stride=int(rng.integers(1, k + 1)) if not big else 1024,
                  height=65536 if big else int(rng.integers(8, 200)),
                  width=65536 if big else int(rng.integers(8, 200)),
                  radius=int(rng.integers(1 if big else 0, 4)))
    caps = [(64, 128, 64, 64), (4, 16, 3, 1), (1, 1, 1, 0)][seed % 3]
    ratios = np.sort(rng.uniform(0, 1, 3))
    assoc = AssociationConfig(
        capacity=caps[0], max_candidates=caps[1], max_points=caps[2], output_capacity=caps[3],
        merge_radius=int(rng.integers(0, 3)), duplicate_radius=int(rng.integers(0, 4)),
        seed_gate=float(rng.uniform(0, 8)), gate_base=float(rng.uniform(0, 8)),
        gate_growth=float(rng.uniform(0, 2)), gate_growth_segments=int(rng.integers(0, 12)),
        gate_miss=float(rng.uniform(0, 3)),
        gate_max=None if rng.random() < 0.5 or big else float(rng.uniform(0, 20)),
        manoeuvre=float(rng.uniform(0, 6)), link_gate=float(rng.choice([0.0, rng.uniform(0, 5)])),
        heading_weight=float(rng.uniform(0, 4)), reject_reversed=bool(rng.random() < 0.5),
        heading_min=float(rng.uniform(0, 2)), max_speed=float(rng.uniform(1, 64)) if big else 1.0,
        delete_ratio=float(ratios[0]),
        predict_ratio=float(ratios[1]), confirm_ratio=float(ratios[2]),
        predict_hits=int(rng.integers(1, 4)), max_misses=int(rng.integers(0, 6)))
    assoc = assoc.replace(confirm_hits=int(rng.integers(assoc.predict_hits, 6)))
    h, w = kwargs["height"], kwargs["width"]
    side = 2 * kwargs["radius"] + 1
    if big:   # one move of d per segment is 1024 px: tracks start from d, then paths of any length
        moves = [(int(rng.integers(-1, 2)), int(rng.integers(-1, 2))) for _ in range(4)]
        targets = [(32768 + rng.uniform(-9000, 9000), 32768 + rng.uniform(-9000, 9000),
                    1024 * dy, 1024 * dx, (dy + kwargs["radius"]) * side + dx + kwargs["radius"])
                   for dy, dx in moves]
    else:
        targets = [(rng.uniform(0, h), rng.uniform(0, w), rng.normal(0, 3), rng.normal(0, 3),
                    None) for _ in range(int(rng.integers(1, 5)))]
    lists = []
    for s in range(int(rng.integers(5, 40))):
        items = []
        for (r0, c0, vr, vc, d) in targets:
            if rng.random() < 0.75:
                r, col = int(r0 + vr * s) + int(rng.integers(-1, 2)), int(c0 + vc * s)
                if 0 <= r < h and 0 <= col < w:
                    pr = int(rng.integers(0, h)) if big else int(np.clip(r - vr, 0, h - 1))
                    pc = int(rng.integers(0, w)) if big else int(np.clip(col - vc, 0, w - 1))
                    path = int(s > 3 and rng.random() < 0.7) if big else int(rng.integers(0, 2))
                    items.append((r, col, int(rng.integers(500, 520)),
                                  d if d is not None else int(rng.integers(0, 12)), pr, pc, path))
        for _ in range(int(rng.integers(0, max(1, caps[1] + 1 - len(items))))):
            r, col = int(rng.integers(0, h)), int(rng.integers(0, w))
            items.append((r, col, int(rng.integers(0, 512)), int(rng.integers(0, 256)),
                          int(rng.integers(0, h)), int(rng.integers(0, w)), int(rng.integers(0, 3))))
        lists.append(recs(items[:caps[1]]))
    # drawn last: the streams as before these settings
    assoc = assoc.replace(confirm_disjoint=bool(rng.random() < 0.5),
                          wake_radius=int(rng.choice([0, 0, 1, 2, 16])),
                          wake_points=int(rng.integers(1, 5)))
    return assoc, kwargs, lists


@pytest.mark.parametrize("seed", range(24))
def test_bit_exact_on_random_streams(seed):
    run_both(*random_run(seed), f"random seed {seed}", costs=True)


@pytest.mark.slow
@pytest.mark.parametrize("first", range(24, 524, 50))
def test_bit_exact_on_random_streams_slow(first):
    for seed in range(first, first + 50):
        run_both(*random_run(seed), f"random seed {seed}")


# ---- interface, refusals and bad input ------------------------------------------------

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


# ---- backtracking ----------------------------------------------------------------------

@pytest.mark.parametrize("seed", [0, 5])
def test_backtracking_in_c_matches_the_model(seed):
    cfg, assoc, res = _example().scene_pipeline(seed)
    for s, cands in enumerate(res.candidates):
        got, failed = backtrack_starts(cands, res.maps[s], cfg.radius)
        assert failed == 0
        for name in CANDIDATE_DTYPE.names:
            assert np.array_equal(got[name], cands[name]), f"segment {s} {name}"


def test_backtracking_corrupt_maps_is_refused_per_candidate():
    maps = np.full((4, 10, 12), 4, dtype=np.uint8)        # d = 4: no move (r = 1)
    maps[0] = 9                                            # START in frame 0
    maps[3, 2, 2] = 0                                      # move (-1, -1): from (3, 3)
    maps[2, 3, 3] = 9                                      # START inside the segment
    maps[3, 0, 5] = 7                                      # move (1, 0): from row -1
    cands = recs([(2, 2, 9, 0, 0, 0, 0), (0, 5, 9, 1, 0, 0, 0), (7, 7, 9, 4, 0, 0, 0)])
    got, failed = backtrack_starts(cands, maps, 1)
    assert failed == 2
    assert got[["row0", "col0", "path"]].tolist() == [(2, 2, 0), (0, 5, 0), (7, 7, 1)]
    with pytest.raises(ValueError, match=r"^direction START at frame 2 of a segment"):
        backtrack(maps, 2, 2, DPConfig(width=12, height=10, segment_frames=4))


# ---- the input trim --------------------------------------------------------------------

def test_trim_in_c_matches_the_model_on_gateware_lists():
    from dptbd.model.segmentation import segment_sequence
    cfg, assoc, res = _example().scene_pipeline(2)
    lists = segment_sequence(res.segments.energy, res.segments.direction, res.cfg)
    trimmed = 0
    for s, out in enumerate(lists):
        raw = association.make_candidates(out.records)
        want = association.trim_to_count(raw, res.count)
        assert trim_to_count(raw, res.count).tolist() == want.tolist(), f"segment {s}"
        trimmed += len(raw) - len(want)
    assert trimmed > 0


@pytest.mark.parametrize("seed", range(5))
def test_trim_in_c_matches_the_model_with_ties(seed):
    rng = np.random.default_rng(seed)
    for _ in range(60):
        n = int(rng.integers(0, 40))
        raw = recs([(int(rng.integers(0, 128)), int(rng.integers(0, 128)),
                     int(rng.integers(0, 6 if seed % 2 else 2 ** 32)), 0, 0, 0, 0)
                    for _ in range(n)])
        for count in (0, 1, n // 2, max(n - 1, 0), n, n + 3):
            assert trim_to_count(raw, count).tolist() == \
                association.trim_to_count(raw, count).tolist(), (n, count)
