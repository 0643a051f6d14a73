"""Brute-force path oracle for the DP of ``docs/arithmetic.md`` (paper 001 eqs (8)-(11)), and
the tiny scenes the tests of ``tests/model/oracle/`` run it on.

On tiny scenes we enumerate EVERY admissible path p_1 .. p_K (each step a move of the
search window, every pixel inside the image) and evaluate it on its own, without any
code of ``dptbd.model``:

* float:  v_1 = x_1(p_1);  v_k = w[prev, m_k] * v_{k-1} + x_k(p_k)
* fixed:  v_1 = x_1(p_1);  v_k = min(round_F(v_{k-1} * c[prev, m_k]) + x_k(p_k), E_max)

where m_k is the move p_{k-1} -> p_k and prev is the path's previous move (START for the
first step). ``round_F`` is written here with Python floor division (truncate:
floor(P / 2^F); half_up: floor(P / 2^F + 1/2)) and the codes with exact fractions,
independently of ``dptbd.model.operators`` and ``DPConfig.weight_codes``. :func:`run_model`
is the model's side, for the comparisons."""

from __future__ import annotations

import functools
import math
from fractions import Fraction

import numpy as np

from dptbd.config import DPConfig
from dptbd.model.fixed import run_fixed
from dptbd.model.reference import run_float


def window(radius: int) -> list[tuple[int, int]]:
    """(dy, dx) per move index, from the spec's formula m = (dy + r)(2r + 1) + (dx + r)."""
    side = 2 * radius + 1
    out: list = [None] * side * side
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            out[(dy + radius) * side + (dx + radius)] = (dy, dx)
    return out


def exact_codes(weights: np.ndarray, frac_bits: int) -> np.ndarray:
    """c = floor(w * 2^F + 1/2) in exact rational arithmetic (docs §3)."""
    scale = 1 << frac_bits
    return np.array([[math.floor(Fraction(float(w)) * scale + Fraction(1, 2)) for w in row]
                     for row in np.asarray(weights, dtype=np.float64)], dtype=np.int64)


def round_f(product, frac_bits: int, mode: str):
    """round_F(P) by floor division: truncate floor(P/2^F), half_up floor(P/2^F + 1/2).

    Works on Python ints and on int64 arrays (numpy's // is floor division too); the
    values of these tiny scenes stay far below 2^62.
    """
    if mode == "truncate":
        return product // (1 << frac_bits)
    return (2 * product + (1 << frac_bits)) // (1 << (frac_bits + 1))


def enumerate_paths(height: int, width: int, n_frames: int, radius: int):
    """Every admissible path: ys, xs of shape (N, K) and move indices of shape (N, K-1)."""
    ys = np.repeat(np.arange(height), width)[:, None]
    xs = np.tile(np.arange(width), height)[:, None]
    moves = np.zeros((height * width, 0), dtype=np.int64)
    for _ in range(1, n_frames):
        parts_y, parts_x, parts_m = [], [], []
        for m, (dy, dx) in enumerate(window(radius)):
            ny, nx = ys[:, -1] + dy, xs[:, -1] + dx
            ok = (ny >= 0) & (ny < height) & (nx >= 0) & (nx < width)
            parts_y.append(np.concatenate([ys[ok], ny[ok, None]], axis=1))
            parts_x.append(np.concatenate([xs[ok], nx[ok, None]], axis=1))
            parts_m.append(np.concatenate([moves[ok], np.full((ok.sum(), 1), m)], axis=1))
        ys, xs, moves = (np.concatenate(p) for p in (parts_y, parts_x, parts_m))
    return ys, xs, moves


def path_values(frames, ys, xs, moves, *, weights, start, fixed=None):
    """Value of each path and its pre-add candidate of the last step (None for K = 1).

    ``fixed`` is None for float, else a dict(codes=, frac_bits=, mode=, e_max=).
    """
    frames = np.asarray(frames)
    n, k_frames = ys.shape
    prev = np.full(n, start)
    if fixed is None:
        v = frames[0][ys[:, 0], xs[:, 0]].astype(np.float64)
    else:
        v = np.minimum(frames[0][ys[:, 0], xs[:, 0]].astype(np.int64), fixed["e_max"])
    cand = None
    for k in range(1, k_frames):
        m = moves[:, k - 1]
        pix = frames[k][ys[:, k], xs[:, k]]
        if fixed is None:
            cand = np.asarray(weights)[prev, m] * v
            v = cand + pix.astype(np.float64)
        else:
            product = v * fixed["codes"][prev, m]
            assert product.max(initial=0) < 2**60
            cand = round_f(product, fixed["frac_bits"], fixed["mode"])
            v = np.minimum(cand + pix.astype(np.int64), fixed["e_max"])
        prev = m
    return v, cand


@functools.lru_cache(maxsize=None)
def fixed_params(cfg: DPConfig) -> dict:
    """Codes (exact), F, rounding and E_max of ``cfg``; cached (DPConfig is frozen, hashable)."""
    return dict(codes=exact_codes(cfg.weight_array, cfg.weight_frac_bits),
                frac_bits=cfg.weight_frac_bits, mode=cfg.rounding,
                e_max=(1 << cfg.energy_bits) - 1)


def exhaustive_oracle(frames, cfg: DPConfig, fixed: bool):
    """Best path value per end pixel; and per end pixel and last move, the best candidate.

    Returns (best (H, W), d_oracle (H, W)) where d_oracle is the lowest move m whose best
    pre-add candidate over paths ending with move m equals the max over m (START if K = 1).
    """
    height, width = cfg.height, cfg.width
    n_moves = (2 * cfg.radius + 1) ** 2
    k_frames = len(frames)
    ys, xs, moves = enumerate_paths(height, width, k_frames, cfg.radius)
    v, cand = path_values(frames, ys, xs, moves, weights=cfg.weight_array, start=n_moves,
                          fixed=fixed_params(cfg) if fixed else None)
    end = ys[:, -1] * width + xs[:, -1]
    best = np.full(height * width, -np.inf)
    np.maximum.at(best, end, v.astype(np.float64))
    if k_frames == 1:
        return best.reshape(height, width), np.full((height, width), n_moves)
    per_move = np.full((height * width, n_moves), -np.inf)
    np.maximum.at(per_move, (end, moves[:, -1]), cand.astype(np.float64))
    top = per_move.max(axis=1, keepdims=True)
    d = np.argmax(per_move == top, axis=1)  # first (lowest) move attaining the max
    return best.reshape(height, width), d.reshape(height, width)


def evaluate_path(frames, pixels, cfg: DPConfig, fixed: bool):
    """Oracle value and last pre-add candidate (None for one pixel) of one explicit path
    [(y, x), ...] through frames 1..len(pixels), in plain Python scalars."""
    index = {mv: m for m, mv in enumerate(window(cfg.radius))}
    prev = (2 * cfg.radius + 1) ** 2  # START
    weights = cfg.weights  # nested tuples of floats
    if fixed:
        params = fixed_params(cfg)
        codes = params["codes"]
    y, x = pixels[0]
    value = int(frames[0][y, x]) if fixed else float(frames[0][y, x])
    if fixed:
        value = min(value, params["e_max"])
    cand = None
    for k in range(1, len(pixels)):
        (y0, x0), (y, x) = pixels[k - 1], pixels[k]
        m = index[(y - y0, x - x0)]
        if fixed:
            cand = round_f(value * int(codes[prev, m]), params["frac_bits"], params["mode"])
            value = min(cand + int(frames[k][y, x]), params["e_max"])
        else:
            cand = weights[prev][m] * value
            value = cand + float(frames[k][y, x])
        prev = m
    return value, cand


def greedy_path_oracle(frames, cfg: DPConfig, fixed: bool):
    """Path-form restatement of the direction-weighted DP (statement 2b of the module doc).

    Returns per frame k the (E, d) maps obtained by keeping one chosen path per pixel and
    evaluating every extended path from scratch with :func:`evaluate_path`.
    """
    height, width, n_moves = cfg.height, cfg.width, (2 * cfg.radius + 1) ** 2
    chosen = {(y, x): [(y, x)] for y in range(height) for x in range(width)}
    e0 = np.array([[evaluate_path(frames[:1], chosen[(y, x)], cfg, fixed)[0]
                    for x in range(width)] for y in range(height)])
    history = [(e0, np.full((height, width), n_moves))]
    for k in range(1, len(frames)):
        new, e_k, d_k = {}, np.zeros((height, width)), np.zeros((height, width), dtype=int)
        for y in range(height):
            for x in range(width):
                best = None
                for m, (dy, dx) in enumerate(window(cfg.radius)):
                    q = (y - dy, x - dx)
                    if not (0 <= q[0] < height and 0 <= q[1] < width):
                        continue
                    path = chosen[q] + [(y, x)]
                    value, cand = evaluate_path(frames[:k + 1], path, cfg, fixed)
                    if best is None or cand > best[0]:  # strict: the lowest move keeps a tie
                        best = (cand, value, m, path)
                new[(y, x)] = best[3]
                e_k[y, x], d_k[y, x] = best[1], best[2]
        chosen = new
        history.append((e_k, d_k))
    return history


#: (height, width, K, radius): the tiny scenes of the brief.
SCENES = [(5, 5, 4, 1), (4, 6, 4, 1), (6, 4, 3, 1), (5, 5, 3, 2)]


SCENE_IDS = [f"{h}x{w}-K{k}-r{r}" for h, w, k, r in SCENES]


def make_cfg(height, width, k_frames, radius, **kw) -> DPConfig:
    kw.setdefault("input_bits", 4)
    kw.setdefault("energy_bits", 12)
    return DPConfig(width=width, height=height, segment_frames=k_frames, radius=radius, **kw)


def random_frames(rng, k_frames, height, width, high):
    """Pixels in 0..high; a tiny range gives plenty of ties."""
    return rng.integers(0, high + 1, size=(k_frames, height, width)).astype(np.uint16)


def row_independent_lut(rng, radius, levels=None) -> np.ndarray:
    """A LUT whose weight depends on the move only (every row equal, START row too)."""
    n_moves = (2 * radius + 1) ** 2
    if levels is None:
        row = rng.uniform(0.0, 1.0, n_moves)
    else:
        row = rng.choice(levels, n_moves)
    return np.tile(row, (n_moves + 1, 1))


def run_model(frames, cfg, fixed: bool):
    out = (run_fixed if fixed else run_float)(np.asarray(frames), cfg)
    return out.energy[0], out.direction[0]
