"""Brute-force path oracle for the DP of ``docs/arithmetic.md`` (paper 001 eqs (8)-(11)).

On tiny scenes we enumerate EVERY admissible path p_1 .. p_K (each step a move of the
search window, every pixel inside the image) and evaluate it on its own, without any
code of ``dptbd.model``:

* float:  v_1 = x_1(p_1);  v_k = w[prev, m_k] * v_{k-1} + x_k(p_k)
* fixed:  v_1 = x_1(p_1);  v_k = min(round_F(v_{k-1} * c[prev, m_k]) + x_k(p_k), E_max)

where m_k is the move p_{k-1} -> p_k and prev is the path's previous move (START for the
first step). ``round_F`` is written here with Python floor division (truncate:
floor(P / 2^F); half_up: floor(P / 2^F + 1/2)) and the codes with exact fractions,
independently of ``dptbd.model.operators`` and ``DPConfig.weight_codes``.

What is provable, and therefore what is tested:

1. **Predecessor-independent LUTs** (all rows equal: plain DP eq (8) is the all-ones
   case). The step v -> round(v * c) + x, clamped, is non-decreasing in v, so by
   induction E_k(q) is the max of v_k over ALL paths ending at q, and the candidate
   C_m = round(E_{k-1}(q_m) * c_m) is the max over paths whose last move is m of the
   pre-add value round(v_{K-1} * c_m). Hence E = best path value for every end pixel,
   and d = the lowest m whose best-with-last-move-m candidate equals the maximum (the
   spec's local tie-break IS this global statement, because the local candidate of move
   m equals the global best over paths ending in m). Holds in float (IEEE multiply and
   add by a fixed non-negative number are monotone too) and in fixed point, with or
   without saturation.
2. **Predecessor-dependent LUTs** (paper eq (11)). The weight of a step depends on the
   direction d stored at the predecessor, which is ONE local argmax; the DP keeps one
   (E, d) per pixel and is a greedy approximation of the best weighted path. What holds:
   a. every pixel's state is the value of a real path: backtracking along the stored d
      from any pixel gives an admissible path that starts at frame 1 with d = START and
      whose oracle value equals E exactly;
   b. a path-form restatement: keep per pixel and frame the ONE chosen path; at frame k
      extend the chosen paths of all valid predecessors by one move, evaluate each
      extended path from scratch, keep the one with the largest candidate (lowest move
      on ties). Its value and last move equal (E, d) at every frame;
   c. E <= max over all paths of the weighted path value (because of a.);
   d. for the paper LUT: E >= the stay-put sum (the zero move always has weight 1), E is
      <= plain DP's E, and for K = 2 (every predecessor is START) it equals plain DP;
   e. NOT guaranteed: E >= the value of every path whose consecutive moves satisfy
      v1 . v2 >= 0 (i.e. E = the best eq-(11)-admissible path). A hand-made scene shows a
      strict gap, so nobody relies on it.
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.weights import paper_weights, plain_weights
from dptbd.model.fixed import run_fixed
from dptbd.model.reference import run_float


# ---------------------------------------------------------------------------------------
# The oracle: independent of dptbd.model
# ---------------------------------------------------------------------------------------

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


# ---------------------------------------------------------------------------------------
# Scenes
# ---------------------------------------------------------------------------------------

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


# ---------------------------------------------------------------------------------------
# 1. Predecessor-independent LUTs: the DP is the exact max over ALL paths
# ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
@pytest.mark.parametrize("high", [2, 15], ids=["ties", "wide"])
def test_plain_dp_is_max_over_all_paths(scene, fixed, high):
    """Plain DP (all-ones LUT): E = best path sum, d = lowest best last move."""
    height, width, k_frames, radius = scene
    cfg = make_cfg(height, width, k_frames, radius, weights=plain_weights(radius))
    rng = np.random.default_rng(1000 * k_frames + 10 * height + width + high)
    for _ in range(4):
        frames = random_frames(rng, k_frames, height, width, high)
        best, d_oracle = exhaustive_oracle(frames, cfg, fixed)
        energy, direction = run_model(frames, cfg, fixed)
        np.testing.assert_array_equal(energy, best)
        np.testing.assert_array_equal(direction, d_oracle)
        # plain DP: the path value is the plain sum of its pixels
        sums_best = exhaustive_oracle(frames, cfg, fixed=False)[0]
        np.testing.assert_array_equal(energy, sums_best)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
def test_plain_dp_fixed_equals_float(scene):
    """Integer pixels, no saturation, all-ones LUT: fixed and float agree bit for bit."""
    height, width, k_frames, radius = scene
    for rounding in ("truncate", "half_up"):
        cfg = make_cfg(height, width, k_frames, radius, weights=plain_weights(radius),
                       rounding=rounding)
        rng = np.random.default_rng(7)
        for _ in range(3):
            frames = random_frames(rng, k_frames, height, width, 2)
            e_fix, d_fix = run_model(frames, cfg, True)
            e_flt, d_flt = run_model(frames, cfg, False)
            np.testing.assert_array_equal(e_fix, e_flt)
            np.testing.assert_array_equal(d_fix, d_flt)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
@pytest.mark.parametrize("rounding", ["truncate", "half_up"])
@pytest.mark.parametrize("frac_bits", [0, 1, 3, 8])
def test_move_only_weights_fixed_is_max_over_all_paths(scene, rounding, frac_bits):
    """Row-independent LUT with fractional weights: the rounded, clamped step is monotone,
    so the fixed-point DP is the exact max over all paths of the fixed-point path value."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(frac_bits * 31 + k_frames)
    for trial in range(3):
        levels = None if trial == 0 else [0.0, 0.25, 0.5, 0.75, 1.0, 0.3]
        cfg = make_cfg(height, width, k_frames, radius, rounding=rounding,
                       weight_frac_bits=frac_bits, weights=row_independent_lut(rng, radius, levels))
        frames = random_frames(rng, k_frames, height, width, 15)
        best, d_oracle = exhaustive_oracle(frames, cfg, fixed=True)
        energy, direction = run_model(frames, cfg, True)
        np.testing.assert_array_equal(energy, best)
        np.testing.assert_array_equal(direction, d_oracle)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
def test_move_only_weights_float_is_max_over_all_paths(scene):
    """Same in float64: multiplying/adding a fixed non-negative number is monotone in IEEE
    arithmetic, so even non-dyadic weights (0.3, random) give the exact max, bit for bit."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(99 + k_frames)
    for trial in range(4):
        levels = None if trial % 2 == 0 else [0.0, 0.3, 0.5, 0.7, 1.0]
        cfg = make_cfg(height, width, k_frames, radius,
                       weights=row_independent_lut(rng, radius, levels))
        frames = random_frames(rng, k_frames, height, width, 2 if trial < 2 else 15)
        best, d_oracle = exhaustive_oracle(frames, cfg, fixed=False)
        energy, direction = run_model(frames, cfg, False)
        np.testing.assert_array_equal(energy, best)
        np.testing.assert_array_equal(direction, d_oracle)


@pytest.mark.parametrize("rounding", ["truncate", "half_up"])
def test_max_over_paths_with_saturation(rounding):
    """Narrow E (3 bits, pixels up to 7, K = 4): clamping at every step is still monotone,
    so E = max over paths of the clamped path value; d follows the pre-add candidates
    (which tie at E_max only when they are equal, never because the sum saturates)."""
    rng = np.random.default_rng(5)
    for weights in (plain_weights(1), row_independent_lut(rng, 1, [0.5, 0.75, 1.0])):
        with pytest.warns(EnergyWidthWarning):
            cfg = make_cfg(5, 5, 4, 1, input_bits=3, energy_bits=3, weight_frac_bits=2,
                           rounding=rounding, weights=weights)
        for _ in range(4):
            frames = random_frames(rng, 4, 5, 5, 7)
            best, d_oracle = exhaustive_oracle(frames, cfg, fixed=True)
            energy, direction = run_model(frames, cfg, True)
            assert energy.max() <= 7
            np.testing.assert_array_equal(energy, best)
            np.testing.assert_array_equal(direction, d_oracle)


@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
def test_single_frame_segment_is_the_frame(fixed):
    """K = 1: E = x and d = START everywhere (§5)."""
    cfg = make_cfg(5, 5, 1, 1)
    frames = random_frames(np.random.default_rng(3), 1, 5, 5, 15)
    best, d_oracle = exhaustive_oracle(frames, cfg, fixed)
    energy, direction = run_model(frames, cfg, fixed)
    np.testing.assert_array_equal(energy, frames[0])
    np.testing.assert_array_equal(energy, best)
    np.testing.assert_array_equal(direction, np.full((5, 5), 9))
    np.testing.assert_array_equal(direction, d_oracle)


# ---------------------------------------------------------------------------------------
# 2. Predecessor-dependent LUTs (paper eq (11)): the exact statements that hold
# ---------------------------------------------------------------------------------------

def states_per_frame(frames, cfg, fixed):
    """(E, d) after each frame 1..K of one segment, from the model (segment_frames = k)."""
    return [run_model(frames[:k], cfg.replace(segment_frames=k, segment_stride=None), fixed)
            for k in range(1, len(frames) + 1)]


def backtrack(states, y, x, radius):
    """The path obtained by following the stored directions back from (y, x) at frame K."""
    moves = window(radius)
    n_moves = len(moves)
    path = [(y, x)]
    for k in range(len(states) - 1, 0, -1):
        m = int(states[k][1][y, x])
        assert m < n_moves, f"d = START at frame {k + 1} > 1"
        dy, dx = moves[m]
        y, x = y - dy, x - dx
        assert 0 <= y < states[0][0].shape[0] and 0 <= x < states[0][0].shape[1], \
            "stored direction points outside the image"
        path.append((y, x))
    assert int(states[0][1][y, x]) == n_moves, "frame 1 must hold d = START"
    return path[::-1]


def weighted_luts(radius, rng):
    """Predecessor-dependent LUTs: the paper's, a random binary one, a random dyadic one."""
    n_moves = (2 * radius + 1) ** 2
    binary = rng.integers(0, 2, size=(n_moves + 1, n_moves)).astype(float)
    binary[:, n_moves // 2] = 1.0  # keep standing still allowed, like the paper
    dyadic = rng.choice([0.0, 0.25, 0.5, 0.75, 1.0], size=(n_moves + 1, n_moves))
    return {"paper": paper_weights(radius), "binary": binary, "dyadic": dyadic}


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
@pytest.mark.parametrize("lut", ["paper", "binary", "dyadic"])
def test_weighted_backtracked_path_value_is_E(scene, fixed, lut):
    """Statement 2a: every (E, d) is a real path, and the oracle value of that path is E."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(17 + k_frames + radius)
    weights = weighted_luts(radius, rng)[lut]
    for rounding in ("truncate", "half_up") if fixed else ("truncate",):
        cfg = make_cfg(height, width, k_frames, radius, weights=weights, rounding=rounding,
                       weight_frac_bits=2)
        for high in (2, 15):
            frames = random_frames(rng, k_frames, height, width, high)
            states = states_per_frame(frames, cfg, fixed)
            energy = states[-1][0]
            for y in range(height):
                for x in range(width):
                    path = backtrack(states, y, x, radius)
                    value, _ = evaluate_path(frames, path, cfg, fixed)
                    assert value == energy[y, x], (y, x, path)
            # statement 2c: never above the best weighted path over ALL paths
            best, _ = exhaustive_oracle(frames, cfg, fixed)
            assert np.all(energy <= best)


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
@pytest.mark.parametrize("lut", ["paper", "binary", "dyadic"])
def test_weighted_dp_equals_greedy_path_oracle(scene, fixed, lut):
    """Statement 2b: (E, d) at every frame equals the path-form greedy oracle, ties included."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(23 + k_frames)
    weights = weighted_luts(radius, rng)[lut]
    cfg = make_cfg(height, width, k_frames, radius, weights=weights, weight_frac_bits=2,
                   rounding="half_up" if lut == "dyadic" else "truncate")
    for high in (2, 9):
        frames = random_frames(rng, k_frames, height, width, high)
        states = states_per_frame(frames, cfg, fixed)
        history = greedy_path_oracle(frames, cfg, fixed)
        for k, ((e_model, d_model), (e_oracle, d_oracle)) in enumerate(zip(states, history)):
            np.testing.assert_array_equal(e_model, e_oracle, err_msg=f"E, frame {k + 1}")
            np.testing.assert_array_equal(d_model, d_oracle, err_msg=f"d, frame {k + 1}")


@pytest.mark.parametrize("scene", SCENES, ids=SCENE_IDS)
def test_paper_lut_bounds(scene):
    """Statement 2d for the paper LUT, float and fixed (integers: fixed == float here)."""
    height, width, k_frames, radius = scene
    rng = np.random.default_rng(41)
    cfg = make_cfg(height, width, k_frames, radius)  # weights=None: paper eq (11)
    plain = cfg.replace(weights=plain_weights(radius))
    for _ in range(4):
        frames = random_frames(rng, k_frames, height, width, 9)
        e_fix, d_fix = run_model(frames, cfg, True)
        e_flt, d_flt = run_model(frames, cfg, False)
        np.testing.assert_array_equal(e_fix, e_flt)  # 0/1 weights, integers: no rounding
        np.testing.assert_array_equal(d_fix, d_flt)
        stay_put = frames.astype(np.int64).sum(axis=0)
        assert np.all(e_fix >= stay_put)
        e_plain, _ = run_model(frames, plain, True)
        assert np.all(e_fix <= e_plain)
        # K = 2: every predecessor is START (all-ones row), so eq (10) is eq (8) exactly
        two = cfg.replace(segment_frames=2, segment_stride=None)
        np.testing.assert_array_equal(run_model(frames[:2], two, True)[0],
                                      run_model(frames[:2], plain.replace(segment_frames=2, segment_stride=None), True)[0])
        np.testing.assert_array_equal(run_model(frames[:2], two, True)[1],
                                      run_model(frames[:2], plain.replace(segment_frames=2, segment_stride=None), True)[1])


@pytest.mark.parametrize("fixed", [False, True], ids=["float", "fixed"])
def test_paper_lut_is_not_the_best_admissible_path(fixed):
    """Statement 2e: a strict gap between the DP and the best eq-(11)-admissible path.

    Frame 1: A = (2,1) holds 3, B = (2,3) holds 2.  Frame 2: q = (2,2) holds 2.
    At q the DP prefers arriving from A (moving right, candidate 3) over B (moving left,
    candidate 2) and stores d = right. In frame 3 the pixel (2,1) left of q can only get 0
    from q (a U-turn, weight 0), so E(2,1) = 3 (A standing still) although the path
    B -> q -> (2,1) moves left twice (v1 . v2 = 1 >= 0, weight 1) and is worth 2 + 2 = 4.
    """
    cfg = make_cfg(5, 5, 3, 1)
    frames = np.zeros((3, 5, 5), dtype=np.uint16)
    frames[0, 2, 1], frames[0, 2, 3], frames[1, 2, 2] = 3, 2, 2
    energy, direction = run_model(frames, cfg, fixed)
    states = states_per_frame(frames, cfg, fixed)
    assert states[1][1][2, 2] == 5  # q arrived moving (0, +1)
    assert energy[2, 1] == 3
    good_path = [(2, 3), (2, 2), (2, 1)]
    value, _ = evaluate_path(frames, good_path, cfg, fixed)
    assert value == 4
    best, _ = exhaustive_oracle(frames, cfg, fixed)
    assert best[2, 1] == 4 > energy[2, 1]
    assert np.all(energy <= best)
