"""The association firmware (C) against the Python model on random candidate streams, every
match cost compared too (``-m slow``: 500 more runs)."""


import numpy as np
import pytest

from dptbd.dsp.association import AssociationConfig
from helpers.firmware_runs import recs, run_both


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
