"""The association firmware (C) against the Python model on adversarial lists: empty, full
(the record table full), every candidate in one gate, tracks at and leaving the border."""


import numpy as np

from dptbd.dsp.association import AssociationConfig
from helpers.firmware_runs import KW, recs, run_both


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
