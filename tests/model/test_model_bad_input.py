"""Bad input to the models is refused with a message naming what is wrong and the allowed
range (``docs/arithmetic.md`` §1: never clipped, never wrapped)."""

from __future__ import annotations


import numpy as np
import pytest

from dptbd.config import DPConfig
from dptbd.model.fixed import dp_step, run_fixed, segment_start
from dptbd.model.operators import check_pixels
from dptbd.model.reference import run_float
from helpers.refusals import whole

CFG = DPConfig(width=6, height=5, segment_frames=3, input_bits=8, energy_bits=12)
MODELS = [run_fixed, run_float]
MODEL_IDS = ["fixed", "float"]


def good(n_frames=3, dtype=np.uint16, lead=()):
    return np.ones(lead + (n_frames, 5, 6), dtype=dtype)


@pytest.mark.parametrize("run", MODELS, ids=MODEL_IDS)
def test_good_input_runs(run):
    out = run(good(), CFG)
    assert out.energy.shape == (1, 5, 6)
    out = run(good(lead=(2, 3)), CFG)  # leading batch axes are fine
    assert out.energy.shape == (2, 3, 1, 5, 6)


@pytest.mark.parametrize("run", MODELS, ids=MODEL_IDS)
@pytest.mark.parametrize("shape", [(), (6,), (5, 6)])
def test_too_few_axes(run, shape):
    with pytest.raises(ValueError, match=whole(f"frames must have shape (..., T, H, W) with at least 3 "
                                               f"axes, got shape {shape}")):
        run(np.ones(shape, dtype=np.uint16), CFG)


@pytest.mark.parametrize("run", MODELS, ids=MODEL_IDS)
@pytest.mark.parametrize("hw", [(6, 5), (5, 5), (5, 7), (1, 1)])
def test_frame_size_mismatch(run, hw):
    frames = np.ones((3,) + hw, dtype=np.uint16)
    with pytest.raises(ValueError, match=rf"^frames are {hw[0]}x{hw[1]} \(H x W\) but the configuration "
                                         r"is height=5, width=6$"):
        run(frames, CFG)


@pytest.mark.parametrize("run", MODELS, ids=MODEL_IDS)
@pytest.mark.parametrize("n_frames", [0, 1, 2])
def test_sequence_shorter_than_one_segment(run, n_frames):
    with pytest.raises(ValueError, match=rf"^a sequence of {n_frames} frames is shorter than one "
                                         r"segment \(segment_frames=3\)$"):
        run(good(n_frames), CFG)


@pytest.mark.parametrize("dtype", [np.float32, np.float64, bool, np.complex64])
def test_non_integer_dtype_to_fixed_model(dtype):
    frames = good(dtype=dtype)
    refusal = (rf"^pixels must be an integer array of 8-bit unsigned values, got dtype "
               rf"{np.dtype(dtype)}; quantise float scenes with dptbd\.scenes\.synthetic\.quantise$")
    with pytest.raises(TypeError, match=refusal):
        run_fixed(frames, CFG)
    # integral float values are not silently accepted either, nor in the step functions
    with pytest.raises(TypeError, match=refusal):
        segment_start(frames[0], CFG)
    with pytest.raises(TypeError, match=refusal):
        dp_step(np.zeros((5, 6), np.uint32), np.zeros((5, 6), np.uint8), frames[1], CFG)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_to_float_model(bad):
    frames = good(dtype=np.float64)
    frames[1, 2, 3] = bad
    with pytest.raises(ValueError, match=r"^pixels must be finite; found NaN or inf$"):
        run_float(frames, CFG)


def test_non_numeric_to_float_model():
    frames = np.full((3, 5, 6), "x")
    with pytest.raises(TypeError, match=r"^pixels must be a real numeric array, got dtype <U1$"):
        run_float(frames, CFG)


@pytest.mark.parametrize("dtype", [np.int8, np.int16, np.int64])
@pytest.mark.parametrize("value", [-1, -128])
def test_negative_pixels(dtype, value):
    frames = good(dtype=dtype)
    frames[2, 4, 5] = value
    with pytest.raises(ValueError, match=rf"^pixels must be in \[0, 255\] for input_bits=8, "
                                         rf"found values in \[{value}, 1\]$"):
        run_fixed(frames, CFG)


@pytest.mark.parametrize("input_bits, value", [(8, 256), (8, 65535), (1, 2), (4, 16), (12, 4096)])
def test_pixels_too_wide(input_bits, value):
    cfg = CFG.replace(input_bits=input_bits, energy_bits=input_bits + 2)  # K = 3: no warning
    top = 2**input_bits - 1
    frames = good(dtype=np.int64)
    frames[0, 0, 0] = value
    with pytest.raises(ValueError, match=rf"^pixels must be in \[0, {top}\] for "
                                         rf"input_bits={input_bits}, found values in \[1, {value}\]$"):
        run_fixed(frames, cfg)
    frames[0, 0, 0] = top  # the largest legal pixel is fine
    run_fixed(frames, cfg)


def test_pixels_too_wide_are_refused_in_every_frame_and_every_segment():
    """A bad pixel in a frame that is not the segment's first, or in a later segment, or in
    trailing frames that form no segment, is still refused (never clipped or wrapped)."""
    cfg = CFG.replace(segment_frames=2, segment_stride=2)
    for t in range(5):
        frames = good(5, dtype=np.int64)
        frames[t, 1, 1] = 256
        with pytest.raises(ValueError, match=(r"^pixels must be in \[0, 255\] for "
                                              r"input_bits=8, found values in \[1, 256\]$")):
            run_fixed(frames, cfg)


def test_huge_unsigned_pixels_do_not_wrap_through_int64():
    frames = good(dtype=np.uint64)
    frames[0, 0, 0] = np.uint64(2**64 - 1)
    with pytest.raises(ValueError, match=(r"^pixels must be in \[0, 255\] for input_bits=8, "
                                          r"found values in \[1, 18446744073709551615\]$")):
        run_fixed(frames, CFG)


def test_check_pixels_operator():
    assert check_pixels(np.array([0, 255], np.uint8), 8).dtype == np.int64
    with pytest.raises(ValueError, match=(r"^pixels must be in \[0, 1\] for input_bits=1, "
                                          r"found values in \[0, 2\]$")):
        check_pixels(np.array([0, 2]), 1)
    check_pixels(np.zeros((0, 3), np.int16), 8)  # an empty array has no bad pixel
