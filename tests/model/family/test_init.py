"""The family's golden model (``dptbd.model.family``): defaults, properties, schedule (§8)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from dptbd.weights import paper_weights, plain_weights
from dptbd.model.family import family_start, family_step, run_family_fixed
from dptbd.model.fixed import run_fixed
from helpers.family_strategies import family_configs, family_frames
from helpers.model_strategies import SETTINGS, frames_for, make_cfg, shapes

pytestmark = pytest.mark.filterwarnings("ignore::dptbd.config.EnergyWidthWarning")


@SETTINGS
@given(data=st.data(), rounding=st.sampled_from(["truncate", "half_up"]),
       frac=st.integers(0, 8), bits=st.integers(8, 12), paper=st.booleans())
def test_defaults_equal_the_001_model_bit_for_bit(data, rounding, frac, bits, paper):
    shape = data.draw(shapes())
    cfg = make_cfg(**shape, input_bits=8, energy_bits=bits, rounding=rounding,
                   weight_frac_bits=frac,
                   weights=(paper_weights if paper else plain_weights)(shape["radius"]))
    assert cfg.is_paper001_datapath
    frames = frames_for(data.draw, shape, 255, n_frames=shape["segment_frames"] + 2)
    want, got = run_fixed(frames, cfg), run_family_fixed(frames, cfg)
    np.testing.assert_array_equal(got.energy, want.energy)
    np.testing.assert_array_equal(got.direction, want.direction)
    np.testing.assert_array_equal(got.end_frames, want.end_frames)
    assert got.energy.dtype == want.energy.dtype and got.direction.dtype == want.direction.dtype


@SETTINGS
@given(data=st.data())
def test_alpha_one_and_zero_penalty_reduce_to_the_001_dp_even_with_explicit_fields(data):
    shape = data.draw(shapes())
    base = make_cfg(**shape, energy_bits=9)
    var = base.replace(merit_codes=np.arange(256), penalty_codes=np.zeros((base.n_moves + 1, base.n_moves), int),
                       forgetting=1.0, forgetting_bits=data.draw(st.integers(0, 16)))
    frames = frames_for(data.draw, shape, 255)
    assert var.is_paper001_datapath and var.family_fields_in_use == []
    want = run_fixed(frames, base).energy
    np.testing.assert_array_equal(run_family_fixed(frames, var).energy, want)
    np.testing.assert_array_equal(run_fixed(frames, var).energy, want)  # accepted by the 001 model


@SETTINGS
@given(data=st.data())
def test_state_is_within_the_clamp_and_directions_are_moves(data):
    cfg = data.draw(family_configs())
    frames = family_frames(data.draw, cfg)
    out = run_family_fixed(frames, cfg)
    assert out.energy.min(initial=0) >= 0 and out.energy.max(initial=0) <= cfg.e_max
    if cfg.recursive or cfg.segment_frames > 1:
        last = out.direction[..., -1, :, :] if len(frames) > 1 else None
        if last is not None:
            assert last.max() < cfg.n_moves


@SETTINGS
@given(data=st.data())
def test_monotone_in_the_pixel_when_the_merit_lut_is(data):
    """A non-decreasing merit LUT: raising one pixel never lowers any E (row-independent
    tables; with direction-dependent tables the greedy d can change, so it is not claimed)."""
    cfg = data.draw(family_configs(row_independent=True))
    cfg = cfg.replace(merit_codes=np.sort(cfg.merit_code_array))
    frames = family_frames(data.draw, cfg)
    t, y, x = (data.draw(st.integers(0, s - 1)) for s in frames.shape)
    assume(frames[t, y, x] < cfg.pixel_max)
    higher = frames.copy()
    higher[t, y, x] = data.draw(st.integers(frames[t, y, x] + 1, cfg.pixel_max))
    assert np.all(run_family_fixed(higher, cfg).energy >= run_family_fixed(frames, cfg).energy)


@SETTINGS
@given(data=st.data())
def test_recursive_maps_are_a_segment_from_frame_zero(data):
    """The recursive map of frame t equals a (t+1)-frame segment starting at frame 0."""
    cfg = data.draw(family_configs(recursive=True))
    frames = family_frames(data.draw, cfg, n_frames=data.draw(st.integers(1, 5)))
    rec = run_family_fixed(frames, cfg)
    np.testing.assert_array_equal(rec.end_frames, np.arange(len(frames)))
    for t in range(len(frames)):
        seg = run_family_fixed(frames[:t + 1], cfg.replace(recursive=False, segment_frames=t + 1))
        np.testing.assert_array_equal(rec.energy[t], seg.energy[0])
        np.testing.assert_array_equal(rec.direction[t], seg.direction[0])


def test_start_frame_is_the_clamped_merit():
    cfg = make_cfg(width=3, height=3, input_bits=2, energy_bits=4, merit_codes=[-5, 0, 9, 15],
                   merit_bits=5)
    e, d = family_start(np.array([[0, 1, 2], [3, 3, 0], [2, 1, 0]]), cfg)
    np.testing.assert_array_equal(e, [[0, 0, 9], [15, 15, 0], [9, 0, 0]])
    assert np.all(d == cfg.start_code)


def test_one_step_by_hand():
    """3 x 3, r = 1, plain weights, penalty 2 on every move but the centre's, alpha = 3/4
    (G = 2, truncate), merit[1] = -1 everywhere."""
    pen = np.full((10, 9), 2)
    pen[:, 4] = 0
    cfg = make_cfg(width=3, height=3, input_bits=2, energy_bits=6, weights=plain_weights(1),
                   merit_codes=[0, -1, 1, 2], penalty_codes=pen, forgetting=0.75, forgetting_bits=2)
    energy = np.array([[1, 0, 0], [0, 3, 0], [0, 0, 8]], dtype=np.uint32)
    direction = np.full((3, 3), cfg.start_code, dtype=np.uint8)
    e, d = family_step(energy, direction, np.ones((3, 3), dtype=np.int64), cfg)
    # centre: candidates V = E(q) - 2 for 8 neighbours, 3 - 0 for the centre; best 8 - 2 = 6
    # from q = (2, 2) = (y - dy, x - dx) with (dy, dx) = (-1, -1), move 0; floor(6 * 3 / 4) = 4;
    # 4 - 1 = 3
    assert (int(e[1, 1]), int(d[1, 1])) == (3, 0)
    # corner (0, 0): valid q are (0,0) m4: 1, (0,1) m3: -2, (1,0) m1: -2, (1,1) m0: 3 - 2 = 1;
    # max 1, lowest index m0; floor(3/4) = 0; 0 - 1 -> clamped to 0
    assert (int(e[0, 0]), int(d[0, 0])) == (0, 0)


def test_negative_best_is_floored_towards_minus_infinity():
    pen = np.full((10, 9), 3)
    cfg = make_cfg(width=3, height=3, input_bits=2, energy_bits=6, weights=plain_weights(1),
                   merit_codes=[0, 1, 2, 3], penalty_codes=pen, forgetting=0.5, forgetting_bits=1)
    zero = np.zeros((3, 3), dtype=np.uint32)
    e, _ = family_step(zero, np.full((3, 3), 9, dtype=np.uint8), np.full((3, 3), 3), cfg)
    assert np.all(e == 1)  # V = -3, floor(-3/2) = -2, -2 + 3 = 1
    e, _ = family_step(zero, np.full((3, 3), 9, dtype=np.uint8), np.full((3, 3), 3),
                       cfg.replace(rounding="half_up"))
    assert np.all(e == 2)  # floor(-3/2 + 1/2) = -1, -1 + 3 = 2


def test_bad_frames_are_refused_like_the_001_model():
    cfg = make_cfg(width=3, height=3, recursive=True)
    with pytest.raises(ValueError, match=r"^pixels must be in \[0, 255\] for input_bits=8, "
                                         r"found values in \[256, 256\]$"):
        run_family_fixed(np.full((2, 3, 3), 256), cfg)
    with pytest.raises(ValueError, match=r"^frames are 4x3 \(H x W\) but the configuration is "
                                         r"height=3, width=3$"):
        run_family_fixed(np.zeros((2, 4, 3), dtype=np.int64), cfg)


@pytest.mark.parametrize("kwargs, fields", [
    (dict(forgetting=0.5), "forgetting"),
    (dict(recursive=True), "recursive"),
    (dict(input_bits=2, merit_codes=[0, 1, 2, 3], penalty_codes=np.ones((10, 9), int)),
     "penalty_codes"),
    (dict(input_bits=2, merit_codes=[0, 1, 3, 2], forgetting=0.5, recursive=True),
     "merit_codes, forgetting, recursive"),
])
def test_the_001_models_refuse_a_family_configuration(kwargs, fields):
    """``fixed``, ``fast`` and ``reference`` implement §4-§5 only: a §8 field that changes
    the arithmetic is refused, never ignored."""
    from dptbd.model.fast import fast_segment_start, run_fixed_fast
    from dptbd.model.reference import run_float
    cfg = make_cfg(width=3, height=3, segment_frames=2, **kwargs)
    frames = np.zeros((2, 3, 3), dtype=np.int64)
    for run, where in ((run_fixed, "fixed"), (run_fixed_fast, "fast"), (run_float, "reference"),
                       (lambda f, c: fast_segment_start(f[0], c), "fast")):
        with pytest.raises(ValueError, match=(
                rf"^dptbd\.model\.{where} implements paper 001's datapath only "
                rf"\(docs/arithmetic\.md §4-§5\), but this configuration sets paper 000's family "
                rf"field\(s\) {fields} \(§8\): use dptbd\.model\.family\.run_family_fixed$")):
            run(frames, cfg)
