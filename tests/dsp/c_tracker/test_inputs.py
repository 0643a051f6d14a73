"""What the association firmware does to its input before associating: the path starts
backtracked in C (corrupt maps refused per candidate) and the input trimmed, against the
model."""


import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.dsp.association import CANDIDATE_DTYPE
from dptbd.dsp.backtrack import backtrack
from dptbd.dsp import association
from dptbd.dsp.c_tracker import backtrack_starts, trim_to_count
from helpers.firmware_runs import example, recs


@pytest.mark.parametrize("seed", [0, 5])
def test_backtracking_in_c_matches_the_model(seed):
    cfg, assoc, res = example().scene_pipeline(seed)
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


def test_trim_in_c_matches_the_model_on_gateware_lists():
    from dptbd.model.segmentation import segment_sequence
    cfg, assoc, res = example().scene_pipeline(2)
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
