"""``dptbd.evaluation.family.list_swaps``: replaying lists with one property swapped."""

from __future__ import annotations

import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.dsp.association import AssociationConfig, Tracker, make_candidates
from dptbd.errors import DptbdError
from dptbd.evaluation.family import detection as fd
from dptbd.evaluation.family import list_swaps as lsw
from dptbd.evaluation.family.association import job_run
from helpers.refusals import whole

SIZE = 64


def _cands(rows, cols, energy, row0=None, col0=None):
    n = len(rows)
    raw = np.zeros(n, dtype=[("row", np.uint16), ("col", np.uint16), ("energy", np.uint32),
                             ("direction", np.uint8)])
    raw["row"], raw["col"], raw["energy"] = rows, cols, energy
    starts = np.stack([rows if row0 is None else row0, cols if col0 is None else col0], axis=1)
    return make_candidates(raw, np.asarray(starts, dtype=np.int64)[:, None, :])


def _view():
    return DPConfig(width=SIZE, height=SIZE, segment_frames=6)


def _random_lists(seed, n_lists=12, n=30, target=True):
    """Noise candidates, and (``target``) one object moving 3 pixels per list."""
    rng = np.random.default_rng(seed)
    out = []
    for s in range(n_lists):
        rows, cols = rng.integers(2, SIZE - 2, (2, n))
        off = rng.integers(-5, 6, (2, n))
        if target:
            rows[0], cols[0], off[:, 0] = 30, 5 + 3 * s, (0, 3)
        energy = rng.integers(3000, 3300, n)
        energy[0] = 4000 if target else energy[0]
        out.append(_cands(rows, cols, energy, np.clip(rows - off[0], 0, SIZE - 1),
                          np.clip(cols - off[1], 0, SIZE - 1)))
    return lsw.NoiseLists(_view(), AssociationConfig(), tuple(out))


def test_distinct_is_the_association_s_cluster_suppression():
    c = _cands([10, 11, 12, 20, 20, 40], [10, 11, 12, 20, 21, 40], [5, 9, 5, 7, 7, 1])
    # (11, 11) beats both neighbours; of the tie (20, 20)/(20, 21) the earlier stays
    np.testing.assert_array_equal(lsw.distinct(c, 1)["energy"], [9, 7, 1])
    assert len(lsw.distinct(c, 0)) == 6
    for seed in range(3):
        lists = _random_lists(seed, target=False)
        tr = Tracker(lists.assoc, segment_frames=6, segment_stride=6, height=SIZE, width=SIZE)
        for cands in lists.candidates:
            tr.step(cands)
        kept = sum(len(lsw.distinct(c, 1)) for c in lists.candidates)
        assert kept == tr.stats["candidates"] - tr.stats["suppressed"]


def test_pair_counts_and_coverage():
    c = _cands([10, 10, 13, 30], [10, 12, 10, 30], [1, 2, 3, 4])
    # distances: 2, 3, 20, 3, 18, 17
    np.testing.assert_array_equal(lsw.pair_counts(c, 5), [0, 0, 1, 2, 0, 3])
    one = _cands([30], [30], [1])
    # integer points within 3 pixels (Euclidean) of one pixel: 29
    assert lsw.coverage(one, (SIZE, SIZE), 3.0) == 29 / SIZE ** 2
    two = _cands([30, 31], [30, 30], [1, 2])
    assert lsw.coverage(two, (SIZE, SIZE), 3.0) < 2 * 29 / SIZE ** 2
    assert lsw.coverage(one[:0], (SIZE, SIZE), 3.0) == 0.0


def test_uniform_positions():
    pos = lsw.uniform_positions(40, (SIZE, SIZE), np.random.default_rng(0), apart=2)
    assert pos.shape == (40, 2) and pos.min() >= 0 and pos.max() < SIZE
    d = np.max(np.abs(pos[:, None] - pos[None]), axis=2)
    assert d[np.triu_indices(40, 1)].min() >= 2
    with pytest.raises(DptbdError, match=whole("600 positions 2 pixels apart do not fit loosely "
                                               "in 64 x 64")):
        lsw.uniform_positions(600, (SIZE, SIZE), np.random.default_rng(0))


def test_uniform_keeps_the_distinct_candidates_energies_and_headings():
    lists = _random_lists(1)
    out = lsw.swap(lists, "uniform", np.random.default_rng(3))
    for before, after in zip(lists.candidates, out.candidates):
        kept = lsw.distinct(before, 1)
        assert len(after) == len(kept) and len(lsw.distinct(after, 1)) == len(after)
        np.testing.assert_array_equal(after["energy"], kept["energy"])
        off = lambda c: (c["row"].astype(int) - c["row0"], c["col"].astype(int) - c["col0"])  # noqa: E731
        inside = ((after["row0"] > 0) & (after["row0"] < SIZE - 1)
                  & (after["col0"] > 0) & (after["col0"] < SIZE - 1))
        for a, b in zip(off(after), off(kept)):
            np.testing.assert_array_equal(a[inside], b[inside])
        assert not np.array_equal(after["row"], kept["row"])


def test_translated_keeps_the_distances_and_moves_the_list():
    lists = _random_lists(4)
    out = lsw.swap(lists, "translated", np.random.default_rng(1))
    moved = 0
    for before, after in zip(lists.candidates, out.candidates):
        kept = lsw.distinct(before, 1)
        np.testing.assert_array_equal(after["energy"], kept["energy"])
        shift = ((after["row"].astype(int) - kept["row"]) % SIZE,
                 (after["col"].astype(int) - kept["col"]) % SIZE)
        assert len(set(shift[0])) == 1 and len(set(shift[1])) == 1    # one offset per list
        moved += bool(shift[0][0] or shift[1][0])
    assert moved >= len(lists.candidates) - 1


def test_heading_swaps():
    lists = _random_lists(2)
    zero = lsw.swap(lists, "zero-headings")
    for c in zero.candidates:
        np.testing.assert_array_equal(c["row0"], c["row"])
        np.testing.assert_array_equal(c["col0"], c["col"])
    src = _random_lists(5)
    short = lsw.NoiseLists(src.view, src.assoc, tuple(c[:7] for c in src.candidates))
    got = lsw.swap(lists, "headings-of", source=short)
    for c, s, orig in zip(got.candidates, short.candidates, lists.candidates):
        j = np.arange(len(c)) % 7
        np.testing.assert_array_equal(c["row"], orig["row"])
        want = np.clip(c["row"].astype(int) - (s["row"].astype(int) - s["row0"])[j], 0, SIZE - 1)
        np.testing.assert_array_equal(c["row0"], want)
    rand = lsw.swap(lists, "random-headings", np.random.default_rng(0))
    offs = np.concatenate([c["col"].astype(int) - c["col0"] for c in rand.candidates])
    assert offs.min() >= -5 and offs.max() <= 5 and len(np.unique(offs)) == 11


def test_alternate_seed_takes_every_other_list():
    lists, other = _random_lists(0), _random_lists(9)
    got = lsw.swap(lists, "alternate-seed", source=other)
    for s, c in enumerate(got.candidates):
        np.testing.assert_array_equal(c, (other if s % 2 else lists).candidates[s])


def test_energy_ranks_change_nothing_the_association_does():
    for seed in range(3):
        lists = _random_lists(seed)
        ranked = lsw.swap(lists, "energy-ranks")
        assert max(int(c["energy"].max()) for c in ranked.candidates) < 30
        assert lsw.associate(ranked) == lsw.associate(lists)


def test_associate_counts_how_far_tracks_got():
    lists = _random_lists(0)
    got = lsw.associate(lists, levels=12)
    tr = Tracker(lists.assoc, segment_frames=6, segment_stride=6, height=SIZE, width=SIZE)
    for c in lists.candidates:
        tr.step(c)
    assert got.reached[0] == tr.stats["started"]
    assert got.false_tracks == len(tr.confirmed_tracks()) >= 1
    assert got.reached[11] >= 1                   # the moving object: one hit in every list
    assert list(got.reached) == sorted(got.reached, reverse=True)
    # without the object no track gets that far
    assert lsw.associate(_random_lists(0, target=False), levels=12).reached[11] == 0
    total = got + got
    assert total.false_tracks == 2 * got.false_tracks and total.reached[0] == 2 * got.reached[0]
    with pytest.raises(DptbdError, match=whole("seeding counts of 12 and 5 hit levels cannot be "
                                               "added")):
        got + lsw.associate(lists)


def test_noise_lists_replay_as_the_job_runs_them():
    lists = lsw.noise_lists(fd.segments(6), 0, 33)
    run = job_run(fd.segments(6), 0, noise_only=True, count=33)
    got = lsw.associate(lists)
    assert got.false_tracks == run.evaluation.false_tracks
    assert got.reached[0] == run.result.stats["started"]
    assert lsw.associate(lsw.swap(lists, "none")) == got


def test_seed_swaps_replays_every_swap_and_measures_the_geometry():
    out = lsw.seed_swaps(0.7, 0, (33,), (26,))
    assert list(out) == [("seg", 33), ("rec", 26)]
    (seg_row, seg_geo), (rec_row, rec_geo) = out.values()
    assert tuple(rec_row) == lsw.SWAPS and tuple(seg_row) == lsw.SWAPS[:-1]
    lists = lsw.noise_lists(fd.segments(6), 0, 33)
    assert seg_row["none"] == lsw.associate(lists)
    assert seg_row["energy-ranks"] == seg_row["none"]
    ds = [lsw.distinct(c, lists.assoc.merge_radius) for c in lists.candidates]
    made, uniform = seg_geo
    assert made[:2] == (sum(len(d) for d in ds), len(ds)) == uniform[:2]
    np.testing.assert_array_equal(made[2], sum(lsw.pair_counts(d, lsw.PAIR_TOP) for d in ds))
    assert made[3] == sum(lsw.coverage(d, (lists.view.height, lists.view.width),
                                       lists.assoc.seed_gate) for d in ds)
    assert len(rec_geo) == 2


@pytest.mark.parametrize("call, message", [
    (lambda l: lsw.swap(l, "shuffle"),
     "swap must be one of 'none', 'uniform', 'translated', 'zero-headings', 'random-headings', 'headings-of', "
     "'energy-ranks', 'alternate-seed', got 'shuffle'"),
    (lambda l: lsw.swap(l, "alternate-seed"),
     "swap 'alternate-seed' needs a source of 12 lists, got none"),
    (lambda l: lsw.swap(l, "uniform"), "swap 'uniform' needs a random generator (rng)"),
    (lambda l: lsw.swap(l, "translated"), "swap 'translated' needs a random generator (rng)"),
    (lambda l: lsw.swap(l, "random-headings"),
     "swap 'random-headings' needs a random generator (rng)"),
    (lambda l: lsw.swap(l, "headings-of"), "swap 'headings-of' needs a source of 12 lists, got none"),
    (lambda l: lsw.swap(l, "headings-of", source=_random_lists(0, n_lists=3)),
     "swap 'headings-of' needs a source of 12 lists, got 3 lists"),
    (lambda l: lsw.swap(l, "headings-of", source=lsw.NoiseLists(
        l.view, l.assoc, (l.candidates[0][:0],) + l.candidates[1:])),
     "swap 'headings-of': source list 0 is empty"),
    (lambda l: lsw.pair_counts(l.candidates[0], 0), "top must be an integer in [1, inf), got 0"),
    (lambda l: lsw.associate(l, levels=0), "levels must be an integer in [1, inf), got 0"),
])
def test_refusals(call, message):
    with pytest.raises(DptbdError, match=whole(message)):
        call(_random_lists(0))
