"""The association firmware (C) against the Python model, field by field after every segment,
on the main job's scenes: 40 seeds, other association settings, disjoint confirmation
(``-m slow``: 1000 more scenes)."""


import numpy as np
import pytest

from helpers.firmware_runs import example, run_both


def _scenes(seeds, association=None):
    ex = example()
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
