"""Property tests (hypothesis) of the segment schedule (``docs/arithmetic.md`` §5,
:mod:`dptbd.model.segments`) and the batch axes of the golden model."""

from __future__ import annotations


import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from dptbd.model.fixed import run_fixed, segment_start
from dptbd.model.reference import run_float

from helpers.model_strategies import SETTINGS, frames_for, make_cfg, shapes




# ---------------------------------------------------------------------------------------
# segments (§5) and batch axes
# ---------------------------------------------------------------------------------------

@SETTINGS
@given(data=st.data(), k_frames=st.integers(1, 4), n_frames=st.integers(1, 10))
def test_segments_are_independent_runs(data, k_frames, n_frames):
    stride = data.draw(st.integers(1, k_frames))
    cfg = make_cfg(width=4, height=3, segment_frames=k_frames, segment_stride=stride)
    frames = data.draw(arrays(np.int64, (n_frames, 3, 4), elements=st.integers(0, 255)))
    n_seg = 0 if n_frames < k_frames else (n_frames - k_frames) // stride + 1
    assert cfg.n_segments(n_frames) == n_seg
    if n_seg == 0:
        with pytest.raises(ValueError, match=rf"^a sequence of {n_frames} frames is shorter than one "
                                             rf"segment \(segment_frames={k_frames}\)$"):
            run_fixed(frames, cfg)
        return
    out = run_fixed(frames, cfg)
    assert out.energy.shape == (n_seg, 3, 4) and out.direction.shape == (n_seg, 3, 4)
    single = cfg.replace(segment_stride=k_frames)
    for s in range(n_seg):
        first = s * stride
        assert out.end_frames[s] == first + k_frames - 1
        ref = run_fixed(frames[first:first + k_frames], single)
        np.testing.assert_array_equal(out.energy[s], ref.energy[0])
        np.testing.assert_array_equal(out.direction[s], ref.direction[0])
    # the segment start ignores the previous state entirely: E = x, d = START
    e0, d0 = segment_start(frames[0], cfg)
    np.testing.assert_array_equal(e0, frames[0])
    np.testing.assert_array_equal(d0, cfg.start_code)


@SETTINGS
@given(data=st.data(), shape=shapes(), batch=st.integers(1, 3))
def test_batch_axes_are_independent_trials(data, shape, batch):
    cfg = make_cfg(**shape)
    frames = np.stack([frames_for(data.draw, shape, 255) for _ in range(batch)])
    for run in (run_fixed, run_float):
        out = run(frames, cfg)
        for b in range(batch):
            ref = run(frames[b], cfg)
            np.testing.assert_array_equal(out.energy[b], ref.energy)
            np.testing.assert_array_equal(out.direction[b], ref.direction)
