"""Brute-force path oracle for paper 000's DP family (``docs/arithmetic.md`` §8.9).

On tiny scenes every admissible path p_1 … p_T is enumerated and evaluated on its own with
Python integers, without any code of ``dptbd.model``:

    v_1 = clamp(P[x_1(p_1)]);  v_k = clamp(round_G(a * (round_F(v_{k-1} c[prev, m_k]) - Qc[prev, m_k]))
                                          + P[x_k(p_k)])

(clamp to [0, E_max], round_* by floor division). With predecessor-independent tables each
step is non-decreasing in v, so E = the best path value and d = the lowest last move m whose
best candidate V (before forgetting and clamp, which can merge values) is the largest; with direction-dependent tables, the path backtracked along the stored d from
any pixel is worth exactly E (the greedy datapath form).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from dptbd.model.family import run_family_fixed
from helpers.family_strategies import family_configs, family_frames
from helpers.model_strategies import SETTINGS

pytestmark = pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")


def _window(radius):
    side = 2 * radius + 1
    return [(m // side - radius, m % side - radius) for m in range(side * side)]


def _round(value, bits, mode):
    if bits == 0:
        return value
    if mode == "truncate":
        return value // (1 << bits)
    return (value + (1 << (bits - 1))) // (1 << bits)


def _oracle_tables(cfg):
    scale = 1 << cfg.weight_frac_bits
    codes = [[int(np.floor(w * scale + 0.5)) for w in row] for row in cfg.weight_array]
    return dict(merit=[int(v) for v in cfg.merit_code_array], codes=codes,
                pen=[[int(v) for v in row] for row in cfg.penalty_code_array],
                a=round(cfg.forgetting * (1 << cfg.forgetting_bits)), g=cfg.forgetting_bits,
                f=cfg.weight_frac_bits, mode=cfg.rounding, e_max=cfg.e_max, start=cfg.n_moves)


def path_value(frames, path, moves, t):
    """Value of one path (cells ``path``, move indices ``moves``) on its own, and the
    penalised candidate V of its last step (before forgetting; None for one frame)."""
    clamp = lambda v: min(max(v, 0), t["e_max"])  # noqa: E731
    v = clamp(t["merit"][int(frames[0][path[0]])])
    prev, cand = t["start"], None
    for k in range(1, len(path)):
        m = moves[k - 1]
        cand = _round(v * t["codes"][prev][m], t["f"], t["mode"]) - t["pen"][prev][m]
        v = clamp(_round(t["a"] * cand, t["g"], t["mode"]) + t["merit"][int(frames[k][path[k]])])
        prev = m
    return v, cand


def all_paths(height, width, n_frames, radius):
    """Every admissible (cells, moves) path of ``n_frames`` frames."""
    window = _window(radius)
    for start in itertools.product(range(height), range(width)):
        for moves in itertools.product(range(len(window)), repeat=n_frames - 1):
            cells = [start]
            for m in moves:
                y, x = cells[-1][0] + window[m][0], cells[-1][1] + window[m][1]
                if not (0 <= y < height and 0 <= x < width):
                    break
                cells.append((y, x))
            else:
                yield cells, moves


@SETTINGS
@given(data=st.data())
def test_row_independent_tables_give_the_best_path(data):
    cfg = data.draw(family_configs(max_k=3, row_independent=True, recursive=False))
    frames = family_frames(data.draw, cfg)
    t = _oracle_tables(cfg)
    out = run_family_fixed(frames, cfg)
    best, best_cand = {}, {}
    for cells, moves in all_paths(cfg.height, cfg.width, cfg.segment_frames, cfg.radius):
        v, cand = path_value(frames, cells, moves, t)
        best[cells[-1]] = max(best.get(cells[-1], v), v)
        if moves:  # d is the lowest move whose best candidate V is the largest (§8.4)
            key = (cells[-1], moves[-1])
            best_cand[key] = max(best_cand.get(key, cand), cand)
    for (y, x), v in best.items():
        assert int(out.energy[0, y, x]) == v
        if cfg.segment_frames > 1:
            per_move = {m: c for (cell, m), c in best_cand.items() if cell == (y, x)}
            top = max(per_move.values())
            assert int(out.direction[0, y, x]) == min(m for m, c in per_move.items() if c == top)


@SETTINGS
@given(data=st.data())
def test_every_state_is_the_value_of_its_backtracked_path(data):
    cfg = data.draw(family_configs(max_k=4))
    frames = family_frames(data.draw, cfg)
    n_t = len(frames)
    window = _window(cfg.radius)
    t = _oracle_tables(cfg)
    # the direction history: the state after every frame (recursive maps, or K prefixes)
    history = [run_family_fixed(frames[:k + 1], cfg.replace(recursive=True)).direction[k]
               for k in range(n_t)]
    last = run_family_fixed(frames, cfg.replace(recursive=True))
    for y in range(cfg.height):
        for x in range(cfg.width):
            cells, moves = [(y, x)], []
            for k in range(n_t - 1, 0, -1):
                m = int(history[k][cells[0]])
                moves.insert(0, m)
                cells.insert(0, (cells[0][0] - window[m][0], cells[0][1] - window[m][1]))
            assert int(last.energy[-1, y, x]) == path_value(frames, cells, moves, t)[0]
