"""The fused compiled kernel (``dptbd.model.fast``) is bit-exact with the readable golden
model (``dptbd.model.fixed``) and refuses bad input with the same errors.

Small frames and short sequences keep this file quick; the JIT compiles once per kernel
(and is cached on disk by numba afterwards).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from dptbd.config import DPConfig, EnergyWidthWarning
from dptbd.weights import plain_weights
from dptbd.model import fast
from dptbd.model.fast import fast_dp_step, fast_segment_start, kernel_path, run_fixed_fast
from dptbd.model.fixed import dp_step, run_fixed, segment_start

H, W = 9, 12


def make_cfg(**kw) -> DPConfig:
    """A config; ``weights="random"`` / ``"plain"`` are expanded. EnergyWidthWarning is
    required exactly when B_E cannot hold K full-scale pixels (and refused otherwise)."""
    kw = dict(kw)
    kw.setdefault("width", W)
    kw.setdefault("height", H)
    radius = kw.get("radius", 1)
    n_moves = (2 * radius + 1) ** 2
    if kw.get("weights") == "random":
        kw["weights"] = np.random.default_rng(radius).random((n_moves + 1, n_moves))
    elif kw.get("weights") == "plain":
        kw["weights"] = plain_weights(radius)
    k = kw.get("segment_frames", 4)
    input_bits, energy_bits = kw.get("input_bits", 8), kw.get("energy_bits", 16)
    full_scale = k * ((1 << input_bits) - 1)
    if full_scale > (1 << energy_bits) - 1:
        warning = (rf"^energy_bits={energy_bits} saturates: K={k} full-scale {input_bits}-bit "
                   rf"pixels sum to {full_scale} > {(1 << energy_bits) - 1}; "
                   rf"energy_bits >= {full_scale.bit_length()} never saturates$")
        with pytest.warns(EnergyWidthWarning, match=warning):
            return DPConfig(**kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error", EnergyWidthWarning)
        return DPConfig(**kw)


def scene(cfg: DPConfig, n_frames: int, lead: tuple = (), seed: int = 0,
          dtype=np.uint16) -> np.ndarray:
    """Random pixels, sparse bright ones on a dim floor (many equal energies: ties)."""
    rng = np.random.default_rng(seed)
    shape = lead + (n_frames, cfg.height, cfg.width)
    top = cfg.pixel_max
    dim = rng.integers(0, max(1, top // 8) + 1, shape)
    bright = rng.integers(0, top + 1, shape)
    frames = np.where(rng.random(shape) < 0.2, bright, dim)
    return frames.astype(dtype)


def assert_same_output(a, b) -> None:
    assert a.energy.dtype == b.energy.dtype == np.uint32
    assert a.direction.dtype == b.direction.dtype == np.uint8
    assert a.energy.shape == b.energy.shape
    np.testing.assert_array_equal(a.end_frames, b.end_frames)
    np.testing.assert_array_equal(a.energy, b.energy)
    np.testing.assert_array_equal(a.direction, b.direction)


# (config, kernel the fast model must pick); the ids say what each one exercises
CONFIGS = [
    (dict(radius=1), "binary"),
    (dict(radius=2, rounding="half_up", segment_frames=3, segment_stride=1), "binary"),
    (dict(radius=1, weights="random", weight_frac_bits=0, rounding="half_up"), "binary"),
    (dict(radius=1, weights="plain", weight_frac_bits=16, segment_frames=5), "binary"),
    (dict(radius=1, weights="random", rounding="half_up"), "general"),
    (dict(radius=2, weights="random", segment_frames=5, segment_stride=2), "general"),
    (dict(radius=1, input_bits=8, energy_bits=9, segment_frames=6), "binary"),
    (dict(radius=2, input_bits=8, energy_bits=8, weights="random"), "general"),
    (dict(radius=1, input_bits=1, energy_bits=2, segment_frames=7, segment_stride=3), "binary"),
    (dict(radius=1, input_bits=16, energy_bits=28), "binary"),
    (dict(radius=2, input_bits=16, energy_bits=27, segment_frames=2), "binary"),
    (dict(radius=2, input_bits=16, energy_bits=28, segment_frames=2), "general"),
    (dict(radius=1, input_bits=16, energy_bits=32), "general"),
    (dict(radius=1, segment_frames=1), "binary"),
    (dict(radius=1, segment_frames=40, segment_stride=7), "binary"),  # > one wavefront group
    (dict(radius=2, width=3, height=3, segment_frames=3), "binary"),  # no interior pixel
    (dict(radius=2, width=4, height=17, weights="random", segment_frames=3), "general"),
]
CONFIG_IDS = [
    "r1-paper-trunc", "r2-halfup-overlap", "r1-F0-randomLUT", "r1-plain-F16",
    "r1-randomLUT-halfup", "r2-randomLUT-overlap", "r1-saturating", "r2-saturating-randomLUT",
    "r1-1bit-ties-saturating", "r1-BE28", "r2-BE27", "r2-BE28-wide", "r1-BE32-wide", "K1",
    "K40-groups", "r2-3x3", "r2-4x17-randomLUT",
]


@pytest.mark.parametrize(("kw", "path"), CONFIGS, ids=CONFIG_IDS)
def test_run_matches_reference(kw, path):
    cfg = make_cfg(**kw)
    assert kernel_path(cfg) == path
    n_frames = cfg.segment_frames + 2 * cfg.segment_stride + 1  # a trailing partial segment
    frames = scene(cfg, n_frames, seed=len(kw))
    assert_same_output(run_fixed(frames, cfg), run_fixed_fast(frames, cfg))


@pytest.mark.parametrize(("kw", "path"), [CONFIGS[1], CONFIGS[4]], ids=["binary", "general"])
def test_batches_and_threads(kw, path):
    cfg = make_cfg(**kw)
    frames = scene(cfg, 2 * cfg.segment_frames + 1, lead=(2, 3), seed=7)
    ref = run_fixed(frames, cfg)
    for threads in (1, 4):
        assert_same_output(ref, run_fixed_fast(frames, cfg, threads=threads))
    # a batch is its trials run one by one
    single = run_fixed_fast(frames[1, 2], cfg, threads=1)
    np.testing.assert_array_equal(single.energy, ref.energy[1, 2])
    np.testing.assert_array_equal(single.direction, ref.direction[1, 2])


def test_empty_batch():
    cfg = make_cfg(radius=1)
    frames = np.zeros((0, 4, H, W), np.uint16)
    assert_same_output(run_fixed(frames, cfg), run_fixed_fast(frames, cfg))


@pytest.mark.parametrize("dtype", [np.uint8, np.int64, np.dtype(">u2"), np.int32])
def test_pixel_dtypes_and_layouts(dtype):
    cfg = make_cfg(radius=1, segment_frames=3)
    frames = scene(cfg, 7, dtype=np.uint16).astype(np.uint8).astype(dtype)
    assert_same_output(run_fixed(frames, cfg), run_fixed_fast(frames, cfg))
    strided = frames[:, ::-1, ::2]  # a non-contiguous view
    strided_cfg = cfg.replace(width=strided.shape[-1])
    assert not strided.flags.c_contiguous
    assert_same_output(run_fixed(strided, strided_cfg), run_fixed_fast(strided, strided_cfg))


def test_constant_scenes_tie_break():
    """All-equal energies: every candidate ties, the lowest valid move index must win."""
    for radius in (1, 2):
        cfg = make_cfg(radius=radius, segment_frames=3)
        for value in (0, 1, 255):
            frames = np.full((3, H, W), value, np.uint16)
            assert_same_output(run_fixed(frames, cfg), run_fixed_fast(frames, cfg))


# ---- single steps ----------------------------------------------------------------------

def random_state(cfg: DPConfig, lead: tuple, seed: int, e_top: int):
    rng = np.random.default_rng(seed)
    shape = lead + (cfg.height, cfg.width)
    energy = rng.integers(0, e_top + 1, shape, dtype=np.int64).astype(np.uint32)
    direction = rng.integers(0, cfg.start_code + 1, shape).astype(np.uint8)
    pixels = rng.integers(0, cfg.pixel_max + 1, shape).astype(np.uint16)
    return energy, direction, pixels


@pytest.mark.parametrize(("kw", "path"), [CONFIGS[0], CONFIGS[1], CONFIGS[4], CONFIGS[5],
                                          CONFIGS[9], CONFIGS[10]],
                         ids=["r1-binary", "r2-binary", "r1-general", "r2-general",
                              "r1-BE28", "r2-BE27"])
@pytest.mark.parametrize("lead", [(), (3,)], ids=["single", "batch"])
def test_step_matches_reference(kw, path, lead):
    cfg = make_cfg(**kw)
    for seed, e_top in enumerate((cfg.e_max, 3, (1 << 32) - 1)):  # the last one: E > E_max
        e, d, x = random_state(cfg, lead, seed, e_top)
        want = dp_step(e, d, x, cfg)
        got = fast_dp_step(e, d, x, cfg)
        for a, b in zip(want, got):
            assert a.dtype == b.dtype and a.shape == b.shape
            np.testing.assert_array_equal(a, b)


def test_step_chain_equals_run():
    cfg = make_cfg(radius=2, segment_frames=4)
    frames = scene(cfg, 4, seed=3)
    e, d = fast_segment_start(frames[0], cfg)
    e_ref, d_ref = segment_start(frames[0], cfg)
    np.testing.assert_array_equal(e, e_ref)
    np.testing.assert_array_equal(d, d_ref)
    assert e.dtype == e_ref.dtype and d.dtype == d_ref.dtype
    for t in range(1, 4):
        e, d = fast_dp_step(e, d, frames[t], cfg)
    out = run_fixed(frames, cfg)
    np.testing.assert_array_equal(e, out.energy[0])
    np.testing.assert_array_equal(d, out.direction[0])


def outcome(fn, *args):
    """The result of ``fn(*args)``, or the type and message of what it raised."""
    try:
        return fn(*args)
    except Exception as exc:  # noqa: BLE001 - compared, not swallowed
        return type(exc), str(exc)


def assert_same_outcome(a, b):
    if isinstance(a, tuple) and isinstance(a[0], type):
        assert b == a
    else:
        for u, v in zip(a, b):
            np.testing.assert_array_equal(u, v)
            assert u.dtype == v.dtype


def test_step_out_of_range_state_behaves_like_reference():
    """States the model never produces go through the reference: same result or error."""
    cfg = make_cfg(radius=1)
    e, d, x = random_state(cfg, (), 0, 100)
    cases = [
        (e.astype(np.int64) - 50, d, x),          # negative energies
        (e, d.astype(np.int64) - 1, x),           # direction -1 (numpy wraps to START)
        (e, np.full_like(d, 10), x),              # direction > M: the START row (§3)
        (e.astype(np.float64), d, x),             # float energy
        (e[:, :-1], d, x),                        # shape mismatch
        (e, d, x.astype(np.float32)),             # float pixels: TypeError
        (e, d, x + 256),                          # pixel out of range: ValueError
    ]
    for args in cases:
        assert_same_outcome(outcome(dp_step, *args, cfg), outcome(fast_dp_step, *args, cfg))


@pytest.mark.parametrize(("kw", "path"), [CONFIGS[0], CONFIGS[4], CONFIGS[5], CONFIGS[10]],
                         ids=["r1-binary", "r1-general", "r2-general", "r2-BE27"])
def test_step_with_direction_above_m_matches_reference(kw, path):
    """Every B_d-bit code, M+1 … 2**B_d − 1 included (a corrupted state): the fast step
    equals the reference, which reads them as START (§3)."""
    cfg = make_cfg(**kw)
    e, d, x = random_state(cfg, (2,), 7, 1000)
    d = np.random.default_rng(8).integers(0, 1 << cfg.direction_bits, d.shape).astype(np.uint8)
    assert (d > cfg.start_code).any()
    got = fast_dp_step(e, d, x, cfg)
    want = dp_step(e, d, x, cfg)
    start = dp_step(e, np.minimum(d, cfg.start_code).astype(np.uint8), x, cfg)
    for a, b, c in zip(got, want, start):
        assert a.dtype == b.dtype and a.shape == b.shape
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(a, c)


# ---- bad input: the same errors as the reference ----------------------------------------

BAD = {
    "too-few-axes": np.ones((H, W), np.uint16),
    "wrong-frame-size": np.ones((4, H, W + 1), np.uint16),
    "too-short": np.ones((3, H, W), np.uint16),
    "float": np.ones((4, H, W), np.float64),
    "bool": np.ones((4, H, W), bool),
    "complex": np.ones((4, H, W), np.complex64),
    "negative": np.full((4, H, W), -1, np.int16),
    "too-large": np.full((4, H, W), 256, np.uint16),
    "list": [[[1.5] * W] * H] * 4,
}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_input_same_errors(name):
    cfg = make_cfg(radius=1)
    frames = BAD[name]
    want = outcome(run_fixed, frames, cfg)
    assert isinstance(want, tuple) and isinstance(want[0], type), "the reference must refuse it"
    assert outcome(run_fixed_fast, frames, cfg) == want
    if np.ndim(frames) == 3 and np.shape(frames)[1:] == (H, W):
        first = np.asarray(frames)[0]
        assert_same_outcome(outcome(segment_start, first, cfg),
                            outcome(fast_segment_start, first, cfg))


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
@pytest.mark.parametrize("frame", [0, 2, 6, 7, 9], ids=lambda t: f"frame{t}")
@pytest.mark.parametrize("kw", [dict(radius=1), dict(radius=2, weights="random")],
                         ids=["binary", "general"])
def test_one_bad_pixel_anywhere(dtype, frame, kw):
    """uint8/uint16 pixels are range-checked inside the kernel: a single bad pixel in a
    segment's first frame, in a step, in the last frame of the last segment or in a
    trailing frame that no segment uses gives the reference's error all the same."""
    cfg = make_cfg(input_bits=4, energy_bits=8, segment_frames=4, segment_stride=3, **kw)
    frames = scene(cfg, 10, dtype=dtype)  # segments cover frames 0 .. 6; 7 .. 9 trail
    frames[frame, H // 2, W - 1] = 16
    want = outcome(run_fixed, frames, cfg)
    assert want[0] is ValueError and "found values in [0, 16]" in want[1]
    assert outcome(run_fixed_fast, frames, cfg) == want


def test_bad_threads():
    cfg = make_cfg(radius=1)
    with pytest.raises(ValueError, match=r"^threads must be an integer in \[1, inf\), got 0$"):
        run_fixed_fast(scene(cfg, 4), cfg, threads=0)


def test_plan_constants():
    """The key layout of the binary kernel: tags below the shift, full = high bits | tag."""
    for radius, shift in ((1, 4), (2, 5)):
        plan = fast._plan(make_cfg(radius=radius))
        assert int(plan.key_shift) == shift
        assert [int(t) for t in plan.tags] == [(1 << shift) - 1 - m for m in range(plan.n_moves)]
        assert min(int(t) for t in plan.tags) > 0  # an in-image key is never 0
        for full, tag in zip(plan.fulls, plan.tags):
            assert int(full) & ((1 << shift) - 1) == int(tag)
            assert int(full) >> shift == (1 << (32 - shift)) - 1
